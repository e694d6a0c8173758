"""Block maxima (and minima) of a volume: the coarse level the MIP (and MinIP) rays skip work with.

Block ``b`` along an axis covers the cells between points ``B*b`` and
``B*b + B`` (both included, clipped to the volume), so it bounds the
trilinear interpolant everywhere inside those cells: from above with its
maximum, from below with its minimum.

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
    return _block_reduce(values, block, margin, np.maximum)


def block_minima(values: np.ndarray, block: int, margin: int = 0) -> np.ndarray:
    """Minimum of ``values`` over each block, as :func:`block_maxima` takes the maximum.

    Examples
    --------
    >>> block_minima(np.arange(5.0).reshape(1, 1, 5) * np.ones((2, 2, 1)), 2, margin=1)[0, 0]
    array([0., 1.])
    """
    return _block_reduce(values, block, margin, np.minimum)


def _block_reduce(values: np.ndarray, block: int, margin: int, extreme) -> np.ndarray:
    result = np.asarray(values)
    for axis in range(3):
        result = _axis_reduce(result, block, axis, margin, extreme)
    return result


def _axis_reduce(values: np.ndarray, block: int, axis: int, margin: int, extreme) -> np.ndarray:
    # no padded copy of the volume: the full blocks' points [B*b, B*b + B) are a reshaped view,
    # the last, short block (if any) runs to the volume's end; then each block adds the point
    # B*b + B it shares with the next one (where that point exists)
    moved = np.moveaxis(values, axis, 0)
    cells = moved.shape[0] - 1
    full = cells // block
    parts = [extreme.reduce(moved[:full * block].reshape((full, block) + moved.shape[1:]), axis=1)] if full else []
    if full * block < cells:
        parts.append(extreme.reduce(moved[full * block:], axis=0, keepdims=True))
    windows = np.concatenate(parts) if len(parts) > 1 else parts[0]
    if full:
        extreme(windows[:full], moved[block::block][:full], out=windows[:full])
    blocks = windows.shape[0]
    for k in range(1, margin + 1):  # block b also covers points B*b - k and B*b + B + k, where they exist
        below = moved[block - k::block][:blocks - 1]
        extreme(windows[1:1 + len(below)], below, out=windows[1:1 + len(below)])
        above = moved[block + k::block][:blocks]
        extreme(windows[:len(above)], above, out=windows[:len(above)])
    return np.moveaxis(windows, 0, axis)


def block_level_image(values: np.ndarray, block: int, low: float, high: float, margin: int = 0,
                      extreme: str = "max") -> vtkImageData:
    """:func:`block_maxima` (``extreme`` "max") or :func:`block_minima` ("min") as a float32
    vtkImageData, normalised like VTK's scalars.

    The value stored is ``(max - low) / (high - low)``, the same normalised
    scale VTK's ray caster uses for the volume's scalars, so the shader
    compares it with its running maximum (minimum) directly.

    Examples
    --------
    >>> image = block_level_image(np.arange(27.0).reshape(3, 3, 3), 2, 0.0, 26.0)
    >>> image.GetDimensions(), image.GetPointData().GetScalars().GetValue(0)
    ((1, 1, 1), 1.0)
    >>> block_level_image(np.arange(27.0).reshape(3, 3, 3), 2, 0.0, 26.0, extreme="min").GetPointData().GetScalars().GetValue(0)
    0.0
    """
    reduce = {"max": block_maxima, "min": block_minima}[extreme]
    level = reduce(values, block, margin).astype(np.float64)
    normalised = ((level - low) / (high - low if high > low else 1.0)).astype(np.float32)
    image = vtkImageData()
    image.SetDimensions(normalised.shape[2], normalised.shape[1], normalised.shape[0])
    array = numpy_to_vtk(normalised.ravel(), deep=True)
    array.SetName(f"block_{extreme}")
    image.GetPointData().SetScalars(array)
    return image


def block_bytes(dims, block: int) -> int:
    """Bytes of the float32 block level (maxima or minima) of a volume with ``dims`` points.

    Examples
    --------
    >>> block_bytes((129, 129, 65), 8)   # 16 x 16 x 8 blocks, float32
    8192
    """
    count = 1
    for n in dims:
        count *= max(1, -(-(max(n, 2) - 1) // block))
    return 4 * count
