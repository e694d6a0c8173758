"""Split a volume larger than one 3D texture into bricks that share a layer of points.

A volume beyond the GPU's 3D texture limit is split into bricks of at most
``limit`` points per axis that **share one layer of points** with their
neighbours (:func:`brick_ranges`), so every cell of the volume lies in
exactly one brick, whole; each brick is a copy of its points placed in world
space (:func:`extract_brick`: origin moved along the direction matrix, same
spacing and direction).  The mappers draw such a volume brick by brick inside
the user's render and combine the bricks exactly:
:mod:`mipcast.mappers.bricked_draw`.
"""
from __future__ import annotations

from typing import List, Sequence, Tuple

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes, vtkImageData

from mipcast.core.prepare import VALID_POINT_MASK

#: Point arrays that hide points (missing data: :func:`mipcast.core.prepare.hidden_points`), carried into bricks.
HIDING_ARRAYS = (vtkDataSetAttributes.GhostArrayName(), VALID_POINT_MASK)


def brick_ranges(points: int, limit: int) -> List[Tuple[int, int]]:
    """Split ``points`` along one axis into inclusive ranges of <= ``limit`` points sharing an end point.

    Consecutive ranges share one point (``(a, b), (b, c)``), so every cell
    ``[i, i + 1]`` lies in exactly one range.  The ranges are as even as
    possible.

    Examples
    --------
    >>> brick_ranges(40, 16)
    [(0, 13), (13, 26), (26, 39)]
    >>> brick_ranges(10, 16)
    [(0, 9)]
    """
    if limit < 2:
        raise ValueError(f"a brick needs at least 2 points per axis, the limit is {limit}")
    cells = points - 1
    count = max(1, -(-cells // (limit - 1)))
    edges = [round(i * cells / count) for i in range(count + 1)]
    return [(edges[i], edges[i + 1]) for i in range(count)]


def brick_extents(dims: Sequence[int], limit: int) -> List[Tuple[int, int, int, int, int, int]]:
    """Inclusive point-index extents ``(x0, x1, y0, y1, z0, z1)`` of the bricks of a ``dims`` volume.

    Examples
    --------
    >>> len(brick_extents((40, 40, 40), 16)), brick_extents((40, 10, 10), 16)[1]
    (27, (13, 26, 0, 9, 0, 9))
    """
    xs, ys, zs = (brick_ranges(int(n), int(limit)) for n in dims)
    return [(x0, x1, y0, y1, z0, z1) for (z0, z1) in zs for (y0, y1) in ys for (x0, x1) in xs]


def extract_brick(image: vtkImageData, extent: Sequence[int]) -> vtkImageData:
    """A copy of ``image``'s points in ``extent`` as its own image, placed where they were in world space.

    The copy's extent starts at 0; its origin is the original origin moved by
    the direction matrix times ``(x0, y0, z0) * spacing``; spacing, direction
    and the scalars' type and name are kept, and so are the arrays that hide
    points (:data:`HIDING_ARRAYS`: they are missing data in the brick too).
    ``image`` is not modified.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=8)
    >>> brick = extract_brick(image, (4, 7, 0, 7, 0, 7))
    >>> brick.GetDimensions(), brick.GetBounds()[:2] == image.GetBounds()[:2]
    ((4, 8, 8), False)
    """
    x0, x1, y0, y1, z0, z1 = (int(v) for v in extent)
    dims = image.GetDimensions()
    first = image.GetExtent()[::2]
    scalars = image.GetPointData().GetScalars()
    components = scalars.GetNumberOfComponents()
    values = vtk_to_numpy(scalars).reshape(dims[2], dims[1], dims[0], components)
    block = np.ascontiguousarray(values[z0:z1 + 1, y0:y1 + 1, x0:x1 + 1])
    brick = vtkImageData()
    brick.SetDimensions(x1 - x0 + 1, y1 - y0 + 1, z1 - z0 + 1)
    brick.SetSpacing(image.GetSpacing())
    direction = np.array([image.GetDirectionMatrix().GetElement(r, c) for r in range(3) for c in range(3)]).reshape(3, 3)
    offset = (np.array([x0, y0, z0]) + np.array(first)) * np.array(image.GetSpacing())
    brick.SetOrigin(*(np.array(image.GetOrigin()) + direction @ offset))
    brick.SetDirectionMatrix(image.GetDirectionMatrix())
    array = numpy_to_vtk(block.reshape(-1, components) if components > 1 else block.ravel(), deep=True,
                         array_type=scalars.GetDataType())
    array.SetName(scalars.GetName() or "scalars")
    brick.GetPointData().SetScalars(array)
    for name in HIDING_ARRAYS:  # hidden points stay hidden (missing data) in the brick
        hiding = image.GetPointData().GetArray(name)
        if hiding is not None and hiding.GetNumberOfComponents() == 1:
            part = vtk_to_numpy(hiding).reshape(dims[2], dims[1], dims[0])[z0:z1 + 1, y0:y1 + 1, x0:x1 + 1]
            copy = numpy_to_vtk(np.ascontiguousarray(part).ravel(), deep=True, array_type=hiding.GetDataType())
            copy.SetName(name)
            brick.GetPointData().AddArray(copy)
    return brick
