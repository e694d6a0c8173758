"""Block maxima of a volume: the coarse level analytic MIP uses to skip work.

Block ``b`` along an axis covers the cells between points ``B*b`` and
``B*b + B`` (both included, clipped to the volume), so it bounds the
trilinear interpolant everywhere inside those cells.

See docs/methods.md, section Skipping (``docs/methods.md#skipping``).
"""
from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData


def block_maxima(values: np.ndarray, block: int) -> np.ndarray:
    """Maximum of ``values`` over each block of ``block``^3 cells.

    Parameters
    ----------
    values : ndarray, shape (nz, ny, nx)
        Point values, every axis of length >= 2.
    block : int
        Cells per block edge (>= 1).

    Returns
    -------
    ndarray, shape (ceil((nz-1)/block), ceil((ny-1)/block), ceil((nx-1)/block))

    Examples
    --------
    >>> block_maxima(np.arange(5.0).reshape(1, 1, 5) * np.ones((2, 2, 1)), 2)[0, 0]
    array([2., 4.])
    """
    result = np.asarray(values)
    for axis in range(3):
        result = _axis_maxima(result, block, axis)
    return result


def _axis_maxima(values: np.ndarray, block: int, axis: int) -> np.ndarray:
    # no padded copy of the volume: the full blocks' points [B*b, B*b + B) are a reshaped view,
    # the last, short block (if any) runs to the volume's end; then each block adds the point
    # B*b + B it shares with the next one (where that point exists)
    moved = np.moveaxis(values, axis, 0)
    cells = moved.shape[0] - 1
    full = cells // block
    parts = [moved[:full * block].reshape((full, block) + moved.shape[1:]).max(axis=1)] if full else []
    if full * block < cells:
        parts.append(moved[full * block:].max(axis=0, keepdims=True))
    windows = np.concatenate(parts) if len(parts) > 1 else parts[0]
    if full:
        np.maximum(windows[:full], moved[block::block][:full], out=windows[:full])
    return np.moveaxis(windows, 0, axis)


def block_maxima_image(values: np.ndarray, block: int, low: float, high: float) -> vtkImageData:
    """:func:`block_maxima` as a float32 vtkImageData, normalised like VTK's scalars.

    The value stored is ``(max - low) / (high - low)``, the same normalised
    scale VTK's ray caster uses for the volume's scalars, so the shader
    compares it with its running maximum directly.

    Examples
    --------
    >>> image = block_maxima_image(np.arange(27.0).reshape(3, 3, 3), 2, 0.0, 26.0)
    >>> image.GetDimensions(), image.GetPointData().GetScalars().GetValue(0)
    ((1, 1, 1), 1.0)
    """
    maxima = block_maxima(values, block).astype(np.float64)
    normalised = ((maxima - low) / (high - low if high > low else 1.0)).astype(np.float32)
    image = vtkImageData()
    image.SetDimensions(normalised.shape[2], normalised.shape[1], normalised.shape[0])
    array = numpy_to_vtk(normalised.ravel(), deep=True)
    array.SetName("block_max")
    image.GetPointData().SetScalars(array)
    return image
