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
- **Half cells** (:func:`halved_cells`): a block of one cell shrinks to the
  box around its half cells above the floor (exact maxima of the
  trilinear interpolant), where the view magnifies the cells.
- **Splat** (:func:`splat_texels`): each box's 8 corners are projected;
  every texel whose cell meets their bounding rectangle is marked.

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
    projection = matrix_array(camera.GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0))
    return projection @ world @ np.linalg.inv(to_index)


def splat_texels(boxes: np.ndarray, ndc_from_index: np.ndarray, grid, texels: np.ndarray) -> np.ndarray:
    """Texels of ``grid`` (top row first) among ``texels`` whose cell meets a box's projected rectangle.

    Parameters
    ----------
    boxes : numpy.ndarray, shape (boxes, 2, 3)
        :func:`blocks_above` (or :func:`halved_cells`).
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
    if not texels.any():
        return np.zeros(np.shape(texels), bool)
    return splat_ranges(texel_ranges(boxes, ndc_from_index, grid), grid, texels)


def splat_ranges(ranges, grid, texels: np.ndarray) -> np.ndarray:
    """:func:`splat_texels` from the boxes' :func:`texel_ranges` (which depend on the view, not on ``texels``:
    a caller whose view stands still while the texels that matter move, e.g. with the gaze, keeps them).

    Examples
    --------
    >>> to_ndc = np.diag([0.25, 0.25, 0.25, 1.0]); to_ndc[:3, 3] = -1.0
    >>> ranges = texel_ranges(np.array([[[3.0, 3.0, 0.0], [4.0, 4.0, 8.0]]]), to_ndc, (8, 8))
    >>> near = np.zeros((8, 8), bool); near[5, :] = True          # only row 5 matters
    >>> np.argwhere(splat_ranges(ranges, (8, 8), near)).tolist()
    [[5, 3], [5, 4]]
    """
    columns, rows = int(grid[0]), int(grid[1])
    hit = np.zeros((rows, columns), bool)
    if not texels.any():
        return hit
    if ranges is None:  # a corner behind the eye: its projection is unbounded
        return texels.copy()
    if len(ranges[0]) == 0:
        return hit
    keep = _meeting(ranges, texels)
    first_row, end_row, first_column, end_column = (part[keep] for part in ranges)
    # a difference array: +1 at each rectangle's first corner, -1 past its ends, summed along both axes
    width = columns + 1
    corners = np.concatenate([first_row * width + first_column, end_row * width + end_column,
                              first_row * width + end_column, end_row * width + first_column])
    signs = np.repeat(np.array([1, 1, -1, -1]), len(first_row))
    counts = np.bincount(corners, weights=signs, minlength=(rows + 1) * width).reshape(rows + 1, width)
    return (counts.cumsum(axis=0).cumsum(axis=1)[:rows, :columns] > 0.5) & texels


def texel_ranges(boxes: np.ndarray, ndc_from_index: np.ndarray, grid):
    """Per box, the texel rows ``[first, end)`` (top row first) and columns ``[first, end)`` its projected
    rectangle meets: 4 int arrays; None when a box corner lies behind the eye.

    Examples
    --------
    >>> to_ndc = np.diag([0.25, 0.25, 0.25, 1.0]); to_ndc[:3, 3] = -1.0   # index [0, 8] -> NDC [-1, 1]
    >>> [int(part[0]) for part in texel_ranges(np.array([[[3.0, 3.0, 0.0], [4.0, 4.0, 8.0]]]), to_ndc, (8, 8))]
    [4, 6, 3, 5]
    """
    columns, rows = int(grid[0]), int(grid[1])
    if len(boxes) == 0:
        return (np.zeros(0, np.int64),) * 4
    low, high = _rectangles(boxes, ndc_from_index)
    if low is None:
        return None

    def index(values, scale, shift):
        return np.clip(np.floor(values * scale + shift), 0, scale).astype(np.int64)

    return (index(-high[1], rows, rows), index(-low[1], rows, rows + 1),
            index(low[0], columns, 0.0), index(high[0], columns, 1.0))


def _meeting(ranges, texels: np.ndarray) -> np.ndarray:
    """Which boxes' :func:`texel_ranges` meet the bounding rectangle of ``texels`` (a cheap, generous filter)."""
    rows_of, columns_of = np.nonzero(texels)
    if rows_of.size == 0:
        return np.zeros(len(ranges[0]), bool)
    first_row, end_row, first_column, end_column = ranges
    return ((end_column > columns_of.min()) & (first_column <= columns_of.max())
            & (end_row > rows_of.min()) & (first_row <= rows_of.max()))


def halved_cells(values: np.ndarray, boxes: np.ndarray, floor: float) -> np.ndarray:
    """Each one-cell box shrunk to the box around its half cells whose trilinear maximum exceeds ``floor``.

    The trilinear interpolant is linear along each axis, so its values at a
    cell's edge, face and body midpoints are averages of the corners', and
    its maximum over each of the cell's 8 half cells (halved along each
    axis) is the largest of that half cell's 8 corner values: exact, not a
    bound.  The box around the half cells above the floor is a tighter
    bound than the cell where a view magnifies the cells (a cell spans
    several texels), for no more boxes to project.

    Parameters
    ----------
    values : numpy.ndarray, shape (nz, ny, nx)
        The point values (missing below every finite value).
    boxes : numpy.ndarray, shape (boxes, 2, 3)
        :func:`blocks_above` with blocks of one cell.
    floor : float

    Returns
    -------
    numpy.ndarray, shape (boxes, 2, 3)
        (A box without a half cell above the floor keeps its whole cell.)

    Examples
    --------
    >>> values = np.zeros((2, 2, 2)); values[0, 0, 0] = 1.0    # one cell, its value 1 at the corner (0, 0, 0)
    >>> halved_cells(values, np.array([[[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]]]), 0.5).tolist()   # only there
    [[[0.0, 0.0, 0.0], [0.5, 0.5, 0.5]]]
    """
    nz, ny, nx = values.shape
    x, y, z = boxes[:, 0].astype(np.int64).T
    fine = np.empty((3, 3, 3, len(boxes)))   # (z, y, x) at the cell's corners and midpoints, per cell
    for c in (0, 1):
        for b in (0, 1):
            for a in (0, 1):
                fine[2 * c, 2 * b, 2 * a] = values[np.minimum(z + c, nz - 1), np.minimum(y + b, ny - 1),
                                                   np.minimum(x + a, nx - 1)]
    fine[1, ::2, ::2] = (fine[0, ::2, ::2] + fine[2, ::2, ::2]) / 2.0
    fine[:, 1, ::2] = (fine[:, 0, ::2] + fine[:, 2, ::2]) / 2.0
    fine[:, :, 1] = (fine[:, :, 0] + fine[:, :, 2]) / 2.0
    low = np.full((len(boxes), 3), np.inf)
    high = np.full((len(boxes), 3), -np.inf)
    for c in (0, 1):
        for b in (0, 1):
            for a in (0, 1):
                above = fine[c:c + 2, b:b + 2, a:a + 2].max(axis=(0, 1, 2)) > floor
                half = np.array([0.5 * a, 0.5 * b, 0.5 * c])
                low[above] = np.minimum(low[above], half)
                high[above] = np.maximum(high[above], half + 0.5)
    none = ~np.isfinite(low[:, 0])
    low[none], high[none] = 0.0, 1.0
    lower = boxes[:, 0] + low
    return np.stack([lower, np.minimum(boxes[:, 0] + high, boxes[:, 1])], axis=1)


def _rectangles(boxes: np.ndarray, ndc_from_index: np.ndarray) -> tuple:
    """(low, high): x and y rows (2, boxes), 0..1 over the viewport (y up), of each box's projected bounding
    rectangle; (None, None) when a corner lies behind the eye.  An affine projection (orthographic) moves every
    box's corners by the same offsets from its first corner (those of the largest box, which hold a smaller box's),
    so one point a box is projected; a perspective one projects all 8.  Element-wise arithmetic, not matrix
    products: a BLAS library's threads would stay busy after the call and take the cores a software rasteriser
    draws the frame with."""
    offsets = np.array([[a, b, c] for a in (0, 1) for b in (0, 1) for c in (0, 1)], np.float64)
    lower, sizes = boxes[:, 0], boxes[:, 1] - boxes[:, 0]
    m = ndc_from_index
    if np.allclose(m[3], [0.0, 0.0, 0.0, m[3, 3]]) and m[3, 3] > 0:  # affine: the largest box's offsets
        spread = offsets * sizes.max(axis=0)   # (8, 3)
        spread = np.array([[sum(row[k] * m[axis, k] for k in range(3)) for row in spread] for axis in (0, 1)])
        low, high = [], []
        for axis in (0, 1):
            first = (lower[:, 0] * m[axis, 0] + lower[:, 1] * m[axis, 1] + lower[:, 2] * m[axis, 2]
                     + m[axis, 3]) / m[3, 3]
            low.append((first + spread[axis].min() / m[3, 3] + 1.0) / 2.0)
            high.append((first + spread[axis].max() / m[3, 3] + 1.0) / 2.0)
        return np.array(low), np.array(high)
    corners = (lower[:, None] + offsets[None] * sizes[:, None]).reshape(-1, 3)
    clip = [corners[:, 0] * m[row, 0] + corners[:, 1] * m[row, 1] + corners[:, 2] * m[row, 2] + m[row, 3]
            for row in (0, 1, 3)]
    if np.any(clip[2] <= 1e-12):
        return None, None
    xy = [((clip[axis] / clip[2] + 1.0) / 2.0).reshape(-1, 8) for axis in (0, 1)]
    return np.array([v.min(axis=1) for v in xy]), np.array([v.max(axis=1) for v in xy])
