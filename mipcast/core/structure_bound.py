"""Where a full-quality ray may meet a value above the transfer function's floor: a bound from the data.

Content-adaptive density (:mod:`mipcast.core.content_adaptive`) casts the
fovea's full-density rays where a coarser level's picture shows structure.
A structure smaller than that level's ray spacing which none of its rays met
above the floor -- a one-voxel speck, the tip of a vessel that barely
clears the window -- would be left out of the fovea (``mipcast bench
--stability``, "specks just above the window floor": a third of them shown
without this bound).  This module says, from the volume itself, which texels
of the deciding level's grid have a full-quality ray anywhere in their cell
that *may* meet a value above the floor; the structure test adds them.

- **Blocks above the floor** (:func:`blocks_above`): a block of
  ``block``^3 cells whose block maximum
  (:func:`mipcast.mappers.max_blocks.block_maxima`, which bounds the
  trilinear interpolant everywhere in the block: every sample of a sampled
  ray and the exact maximum of analytic MIP) exceeds the floor
  (:func:`mipcast.core.transfer_bounds.constant_ends`: at or below it the
  premultiplied colour is the one the data's minimum gets).
- **Splat** (:func:`splat_texels`): each such block's 8 corners are
  projected; every texel whose cell meets their bounding rectangle is
  marked.

Why no structure is missed: a ray that meets a value above the floor does so
inside a block above the floor, so its pixel centre lies in that block's
projection (the convex hull of its projected corners when they all lie in
front of the eye; otherwise every texel is marked), hence in the rectangle;
the pixel's nearest deciding texel is the one whose cell holds the centre,
and that cell meets the rectangle.  Cropping and clipping planes only
remove samples, so the bound holds with them too.
"""
from __future__ import annotations

import math
import numpy as np

from mipcast.core.camera_rays import index_space, matrix_array

#: Blocks along a volume's longest axis at most (coarser blocks beyond it): the splat stays small.
FLAG_CELLS = 128


def block_size(dims) -> int:
    """Cells per block edge: at most :data:`FLAG_CELLS` blocks along any axis.

    Examples
    --------
    >>> block_size((128, 128, 128)), block_size((256, 256, 108)), block_size((512, 512, 400))
    (1, 2, 4)
    """
    return max(1, math.ceil((max(dims) - 1) / FLAG_CELLS))


def blocks_above(maxima: np.ndarray, floor: float, block: int, dims) -> np.ndarray:
    """Index-space boxes ``(lower, upper)`` of the blocks whose maximum exceeds ``floor``.

    Parameters
    ----------
    maxima : numpy.ndarray, shape (bz, by, bx)
        :func:`mipcast.mappers.max_blocks.block_maxima` of the values the
        method draws (missing values below every finite one), ``block``
        cells a block.
    floor : float
        Values at or below it look like the data's minimum.
    block : int
        Cells per block edge.
    dims : (nx, ny, nz)
        The volume's points per axis.

    Returns
    -------
    numpy.ndarray, shape (blocks, 2, 3)
        Per block its lowest and highest point, (x, y, z) index coordinates.

    Examples
    --------
    >>> maxima = np.array([[[0.0, 0.2, 1.0]]])   # 6 x 2 x 2 points in blocks of 2 cells: the last block above
    >>> blocks_above(maxima, 0.5, 2, (6, 2, 2)).tolist()
    [[[4.0, 0.0, 0.0], [5.0, 1.0, 1.0]]]
    """
    found = np.argwhere(maxima > floor)[:, ::-1].astype(np.float64)  # (x, y, z) blocks
    lower = found * block
    upper = np.minimum(lower + block, np.asarray(dims, np.float64) - 1.0)
    return np.stack([lower, upper], axis=1)


def ndc_from_index(image, camera, aspect: float, volume_matrix=None) -> np.ndarray:
    """The map from ``image``'s index space (as :func:`blocks_above` counts it) to the camera's NDC.

    Parameters
    ----------
    image : vtkImageData
    camera : vtkCamera
    aspect : float
        The viewport's width / height.
    volume_matrix : vtkMatrix4x4, optional
        The vtkVolume's matrix (identity if omitted).

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> image = vtkImageData(); image.SetDimensions(3, 3, 3)
    >>> camera = vtkCamera(); camera.ParallelProjectionOn(); camera.SetParallelScale(1.0)
    >>> camera.SetPosition(1.0, 1.0, 10.0); camera.SetFocalPoint(1.0, 1.0, 0.0)
    >>> point = ndc_from_index(image, camera, 1.0) @ [2.0, 1.0, 1.0, 1.0]
    >>> [round(float(v), 6) for v in point[:2] / point[3]]   # one to the right of the centre: the right edge
    [1.0, 0.0]
    """
    to_index, _ = index_space(image)
    world = np.eye(4) if volume_matrix is None else matrix_array(volume_matrix)
    return matrix_array(camera.GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0)) @ world @ np.linalg.inv(to_index)


def splat_texels(boxes: np.ndarray, ndc_from_index: np.ndarray, grid, texels: np.ndarray) -> np.ndarray:
    """Texels of ``grid`` (top row first) among ``texels`` whose cell meets a box's projected rectangle.

    Parameters
    ----------
    boxes : numpy.ndarray, shape (blocks, 2, 3)
        :func:`blocks_above`.
    ndc_from_index : numpy.ndarray, shape (4, 4)
        The volume's index space -> NDC.
    grid : (columns, rows)
    texels : numpy.ndarray, bool, shape (rows, columns)
        The texels that matter (the others are False).

    Returns
    -------
    numpy.ndarray, bool, shape (rows, columns)
        Every texel of ``texels`` when a corner lies behind the eye.

    Examples
    --------
    >>> to_ndc = np.diag([0.25, 0.25, 0.25, 1.0]); to_ndc[:3, 3] = -1.0   # index [0, 8] -> NDC [-1, 1]
    >>> box = np.array([[[3.0, 3.0, 0.0], [4.0, 4.0, 8.0]]])               # one cell across, seen end on
    >>> hit = splat_texels(box, to_ndc, (8, 8), np.ones((8, 8), bool))
    >>> np.argwhere(hit).tolist()                                          # its cell and the cells its edges touch
    [[4, 3], [4, 4], [5, 3], [5, 4]]
    """
    columns, rows = int(grid[0]), int(grid[1])
    hit = np.zeros((rows, columns), bool)
    if len(boxes) == 0 or not texels.any():
        return hit
    low, high = _rectangles(boxes, ndc_from_index)
    if low is None:  # a corner behind the eye: its projection is unbounded
        return texels.copy()
    first_column = np.clip(np.floor(low[:, 0] * columns), 0, columns).astype(np.int64)
    end_column = np.clip(np.floor(high[:, 0] * columns) + 1, 0, columns).astype(np.int64)
    first_row = np.clip(np.floor((1.0 - high[:, 1]) * rows), 0, rows).astype(np.int64)   # top row first
    end_row = np.clip(np.floor((1.0 - low[:, 1]) * rows) + 1, 0, rows).astype(np.int64)
    rows_of, columns_of = np.nonzero(texels)
    keep = ((end_column > columns_of.min()) & (first_column <= columns_of.max())
            & (end_row > rows_of.min()) & (first_row <= rows_of.max()))
    # a difference array: +1 at each rectangle's first corner, -1 past its ends, summed along both axes
    width = columns + 1
    corners = np.concatenate([first_row[keep] * width + first_column[keep], end_row[keep] * width + end_column[keep],
                              first_row[keep] * width + end_column[keep], end_row[keep] * width + first_column[keep]])
    signs = np.repeat(np.array([1, 1, -1, -1]), keep.sum())
    counts = np.bincount(corners, weights=signs, minlength=(rows + 1) * width).reshape(rows + 1, width)
    return (counts.cumsum(axis=0).cumsum(axis=1)[:rows, :columns] > 0.5) & texels


def _rectangles(boxes: np.ndarray, ndc_from_index: np.ndarray) -> tuple:
    """(low, high) corners, 0..1 over the viewport (y up), of each box's projected bounding rectangle; (None, None)
    when a corner lies behind the eye.  An affine projection (orthographic) moves every box's corners by the same
    offsets from its first corner (those of the largest box, which hold a smaller box's), so one point a box is
    projected; a perspective one projects all 8.  Element-wise arithmetic, not matrix products: a BLAS library's
    threads would stay busy after the call and take the cores a software rasteriser draws the frame with."""
    offsets = np.array([[a, b, c] for a in (0, 1) for b in (0, 1) for c in (0, 1)], np.float64)
    sizes = boxes[:, 1] - boxes[:, 0]
    affine = np.allclose(ndc_from_index[3], [0.0, 0.0, 0.0, ndc_from_index[3, 3]]) and ndc_from_index[3, 3] > 0
    if affine:  # the largest box's offsets: a box clipped at the volume's far faces gets a rectangle too big
        spread = _apply(ndc_from_index, offsets * sizes.max(axis=0), translate=False)[:, :2] / ndc_from_index[3, 3]
        origin = _apply(ndc_from_index, boxes[:, 0])[:, :2] / ndc_from_index[3, 3]
        return (origin + spread.min(axis=0) + 1.0) / 2.0, (origin + spread.max(axis=0) + 1.0) / 2.0
    corners = (boxes[:, None, 0] + offsets[None] * sizes[:, None]).reshape(-1, 3)
    clip = _apply(ndc_from_index, corners)
    if np.any(clip[:, 3] <= 1e-12):
        return None, None
    xy = ((clip[:, :2] / clip[:, 3:] + 1.0) / 2.0).reshape(-1, 8, 2)
    return xy.min(axis=1), xy.max(axis=1)


def _apply(matrix: np.ndarray, points: np.ndarray, translate: bool = True) -> np.ndarray:
    """``matrix @ (x, y, z, 1)`` (or ``(x, y, z, 0)``) for each point, element-wise: (points, 4)."""
    out = np.empty((len(points), 4))
    for row in range(4):
        out[:, row] = (points[:, 0] * matrix[row, 0] + points[:, 1] * matrix[row, 1] + points[:, 2] * matrix[row, 2]
                       + (matrix[row, 3] if translate else 0.0))
    return out
