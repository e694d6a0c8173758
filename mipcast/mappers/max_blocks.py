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


def block_maxima(values: np.ndarray, block: int, margin: int = 0) -> np.ndarray:
    """Maximum of ``values`` over each block of ``block``^3 cells (and ``margin`` points around it).

    Parameters
    ----------
    values : ndarray, shape (nz, ny, nx)
        Point values, every axis of length >= 2.
    block : int
        Cells per block edge (>= 1).
    margin : int
        Points beyond the block's own on each side that its maximum covers
        too (0: the block's cells only).  Sampled rays use 1: a sample on a
        block's face may be read from the neighbouring cell.

    Returns
    -------
    ndarray, shape (ceil((nz-1)/block), ceil((ny-1)/block), ceil((nx-1)/block))

    Examples
    --------
    >>> block_maxima(np.arange(5.0).reshape(1, 1, 5) * np.ones((2, 2, 1)), 2)[0, 0]
    array([2., 4.])
    >>> block_maxima(np.arange(5.0)[::-1].reshape(1, 1, 5) * np.ones((2, 2, 1)), 2, margin=1)[0, 0]
    array([4., 3.])
    """
    result = np.asarray(values)
    for axis in range(3):
        result = _axis_maxima(result, block, axis, margin)
    return result


def _axis_maxima(values: np.ndarray, block: int, axis: int, margin: int = 0) -> np.ndarray:
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
    blocks = windows.shape[0]
    for k in range(1, margin + 1):  # block b also covers points B*b - k and B*b + B + k, where they exist
        below = moved[block - k::block][:blocks - 1]
        np.maximum(windows[1:1 + len(below)], below, out=windows[1:1 + len(below)])
        above = moved[block + k::block][:blocks]
        np.maximum(windows[:len(above)], above, out=windows[:len(above)])
    return np.moveaxis(windows, 0, axis)


def block_maxima_image(values: np.ndarray, block: int, low: float, high: float, margin: int = 0) -> vtkImageData:
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
    maxima = block_maxima(values, block, margin).astype(np.float64)
    normalised = ((maxima - low) / (high - low if high > low else 1.0)).astype(np.float32)
    image = vtkImageData()
    image.SetDimensions(normalised.shape[2], normalised.shape[1], normalised.shape[0])
    array = numpy_to_vtk(normalised.ravel(), deep=True)
    array.SetName("block_max")
    image.GetPointData().SetScalars(array)
    return image


def block_bytes(dims, block: int) -> int:
    """Bytes of the float32 block-maximum level of a volume with ``dims`` points.

    Examples
    --------
    >>> block_bytes((129, 129, 65), 8)   # 16 x 16 x 8 blocks, float32
    8192
    """
    count = 1
    for n in dims:
        count *= max(1, -(-(max(n, 2) - 1) // block))
    return 4 * count
