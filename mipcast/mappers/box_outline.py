"""The volume's box as the camera sees it, for drawing a composed picture with the box's own coverage.

A volume's own draw rasterises its box, so with multisampling (pyvista's
default 8x MSAA) the pixels on the box's silhouette are blended by the share
of their samples the box covers.  A picture composed elsewhere (the bricks of
:mod:`mipcast.mappers.bricked_draw`) drawn as one viewport quad would cover
every sample of those pixels instead.  :func:`outline_ndc` gives the box's
silhouette in normalised device coordinates (the convex hull of its 8
projected corners) and :func:`outline_quads` the quads that tile it, so the
picture can be drawn through the same outline and get the same coverage.

Examples
--------
>>> outline_quads([(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.5, 1.5), (0.0, 1.0)])[1]
((0.0, 0.0), (0.5, 1.5), (0.0, 1.0), (0.0, 1.0))
"""
from __future__ import annotations

from typing import List, Optional, Sequence, Tuple

import numpy as np

Point = Tuple[float, float]


def box_corners(image, volume) -> np.ndarray:
    """The 8 world-space corners of ``image``'s point box as ``volume`` places it, shape (8, 3).

    Through the image's direction matrix and the volume's matrix (position,
    orientation, scale, user matrix), as VTK places the volume's box.

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> image = vtkImageData()
    >>> image.SetDimensions(3, 2, 2)
    >>> image.SetSpacing(2.0, 1.0, 1.0)
    >>> box_corners(image, vtkVolume()).max(axis=0).tolist()
    [4.0, 1.0, 1.0]
    """
    extent = image.GetExtent()
    index = np.array([[i, j, k] for i in extent[0:2] for j in extent[2:4] for k in extent[4:6]], dtype=float)
    direction = np.array([[image.GetDirectionMatrix().GetElement(r, c) for c in range(3)] for r in range(3)])
    points = np.asarray(image.GetOrigin()) + (index * np.asarray(image.GetSpacing())) @ direction.T
    matrix = volume.GetMatrix()
    model = np.array([[matrix.GetElement(r, c) for c in range(4)] for r in range(4)])
    world = np.c_[points, np.ones(8)] @ model.T
    return world[:, :3] / world[:, 3:]


def outline_ndc(corners: np.ndarray, renderer) -> Optional[List[Point]]:
    """The box's silhouette in the renderer's normalised device coordinates, counter-clockwise; None if unknown.

    None when a corner lies at or behind the camera's near plane (the
    projection of the box is then no longer the hull of its corners) or when
    the window renders tiles (the camera's projection then depends on the
    tile); the caller draws over the whole viewport then.
    """
    ndc = _projected(corners, renderer)
    return None if ndc is None else _hull([(float(x), float(y)) for x, y, _ in ndc])


def _face_ring(axis: int, side: int) -> Tuple[int, int, int, int]:
    """The corners (rows of :func:`box_corners`: row 4 i + 2 j + k) of a face, around it."""
    u, v = [b for b in range(3) if b != axis]
    return tuple((side << (2 - axis)) + (du << (2 - u)) + (dv << (2 - v))
                 for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)))


#: The box's six faces: (axis, side) (side 0 the low index) and their corners around them.
FACES = tuple(((axis, side), _face_ring(axis, side)) for axis in range(3) for side in (0, 1))


def front_faces(corners: np.ndarray, renderer) -> Optional[List[Tuple[Tuple[int, int], List[Tuple[float, ...]]]]]:
    """The box's faces turned to the camera: ``((axis, side), corners in NDC (x, y, z) counter-clockwise)``; None
    as for :func:`outline_ndc`.

    The faces the volume's own draw rasterises (VTK culls the back faces):
    a face is turned to the camera when its corners, in the order whose
    right-hand normal points out of the box, project counter-clockwise.
    Together they tile :func:`outline_ndc`'s polygon.

    Examples
    --------
    >>> FACES[0], FACES[5]
    (((0, 0), (0, 2, 3, 1)), ((2, 1), (1, 5, 7, 3)))
    """
    ndc = _projected(corners, renderer)
    if ndc is None:
        return None
    centre = corners.mean(axis=0)
    faces = []
    for face, ring in FACES:
        quad = [(float(ndc[i, 0]), float(ndc[i, 1]), float(ndc[i, 2])) for i in ring]
        area = sum(x0 * y1 - x1 * y0 for (x0, y0, _), (x1, y1, _) in zip(quad, quad[1:] + quad[:1]))
        p = corners[list(ring)]
        outward = float(np.dot(np.cross(p[1] - p[0], p[3] - p[0]), p.mean(axis=0) - centre))
        if area * outward > 0.0:
            faces.append((face, quad if area > 0.0 else quad[::-1]))
    return faces


def _projected(corners: np.ndarray, renderer) -> Optional[np.ndarray]:
    """The corners in the renderer's NDC (x, y, z), shape (n, 3); None as for :func:`outline_ndc`."""
    window = renderer.GetRenderWindow()
    if window is not None and (tuple(window.GetTileScale()) != (1, 1)
                               or tuple(window.GetTileViewport()) != (0.0, 0.0, 1.0, 1.0)):
        return None
    camera = renderer.GetActiveCamera()
    matrix = camera.GetCompositeProjectionTransformMatrix(renderer.GetTiledAspectRatio(), -1.0, 1.0)
    projection = np.array([[matrix.GetElement(r, c) for c in range(4)] for r in range(4)])
    clip = np.c_[corners, np.ones(len(corners))] @ projection.T
    if np.any(clip[:, 3] <= 0.0) or np.any(clip[:, 2] < -clip[:, 3]):
        return None
    return clip[:, :3] / clip[:, 3:]


def outline_quads(polygon: Sequence[Point]) -> List[Tuple[Point, Point, Point, Point]]:
    """Quads ``(p0, a, b, c)`` that tile a convex polygon as a fan from its first point.

    Each quad is drawn as the triangles (p0, a, b) and (p0, b, c)
    (``vtkOpenGLRenderUtilities::RenderQuad``), so a polygon of n points gives
    n - 2 fan triangles, the last one doubled (zero area, covering nothing)
    when n is odd; neighbouring triangles share an edge, which the rasteriser
    covers once.
    """
    points = list(polygon)
    quads = []
    for i in range(1, len(points) - 1, 2):
        a, b = points[i], points[i + 1]
        c = points[i + 2] if i + 2 < len(points) else b
        quads.append((points[0], a, b, c))
    return quads


def _hull(points: List[Point]) -> List[Point]:
    """Convex hull, counter-clockwise (Andrew's monotone chain); collinear points dropped."""
    points = sorted(set(points))
    if len(points) < 3:
        return points

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in points:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0.0:
            lower.pop()
        lower.append(p)
    for p in reversed(points):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0.0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]
