"""Slabs, clipping planes and cropping boxes as planes, and the ray interval they leave.

Every mipcast method clips the same way: each ray's interval inside the
volume's box is intersected with the half-spaces of a list of planes (the
mapper's clipping planes, the six faces of its cropping box and the two
faces of its slab).  A plane is ``origin`` and ``normal``; the kept side is
the one the normal points to (``normal . (x - origin) >= 0``), as in VTK's
``AddClippingPlane``.  The GPU mappers hand these planes to the shader as
uniforms (:mod:`mipcast.mappers.clip_uniforms`), the float64 references
take them as arrays (:func:`mipcast.reference.render`'s ``clip_planes``).

Only numpy: no VTK rendering, usable by the references and the mappers.

Examples
--------
>>> origins, normals = slab_planes(10.0, (0, 0, 0), (0, 0, 1))
>>> origins.tolist(), normals.tolist()
([[0.0, 0.0, -5.0], [0.0, 0.0, 5.0]], [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])
>>> lo, hi = ray_interval(np.zeros((1, 3)), np.array([[0.0, 0.0, 1.0]]), 0.0, 20.0,
...                       plane_rows(*slab_planes(4.0, (0, 0, 10), (0, 0, 1))))
>>> float(lo[0]), float(hi[0])
(8.0, 12.0)
"""
from __future__ import annotations

from typing import Optional, Sequence, Tuple

import numpy as np

#: Most planes one mapper clips with: VTK's six clipping planes, the six faces
#: of the cropping box and the slab's two faces.
MAX_PLANES = 14

#: A sample within this many steps outside a plane is kept (sampled methods): a sample ON a plane is kept
#: whatever float rounding makes of it. Orthographic views along an axis put every ray's samples on the
#: voxel planes, and a slab centred on one with a whole number of spacings has both faces there (a clinical
#: thick slab): without it the near face's slice was dropped and the far one's kept, as rounding fell
#: (the shader's ``1.0e-3`` in ``shaders/sampled_loop.glsl``; the references and the CPU's outline rays).
SAMPLE_ON_PLANE = 1.0e-3


def _vector(name: str, value, size: int = 3) -> np.ndarray:
    array = np.asarray(value, dtype=np.float64).reshape(-1)
    if array.shape != (size,) or not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be {size} finite numbers, got {value!r}")
    return array


def slab_planes(thickness: float, centre: Sequence[float], normal: Sequence[float]) -> Tuple[np.ndarray, np.ndarray]:
    """The two planes bounding a slab ``thickness`` thick around ``centre``, normal to ``normal``.

    Returns ``(origins, normals)``, each (2, 3), normals pointing into the slab.

    Examples
    --------
    >>> slab_planes(2.0, (1, 2, 3), (2, 0, 0))[0].tolist()
    [[0.0, 2.0, 3.0], [2.0, 2.0, 3.0]]
    """
    thickness = float(thickness)
    if not np.isfinite(thickness) or thickness <= 0:
        raise ValueError(f"slab thickness must be > 0 (0 means no slab), got {thickness!r}")
    centre = _vector("slab centre", centre)
    normal = _vector("slab normal", normal)
    size = np.linalg.norm(normal)
    if size == 0:
        raise ValueError("slab normal must not be the zero vector")
    normal = normal / size
    half = 0.5 * thickness * normal
    return np.array([centre - half, centre + half]), np.array([normal, 0.0 - normal])


def box_planes(bounds: Sequence[float]) -> Tuple[np.ndarray, np.ndarray]:
    """The six planes of the box ``(x0, x1, y0, y1, z0, z1)``, normals pointing inside.

    An empty box (``x0 > x1`` on some axis) keeps nothing.

    Examples
    --------
    >>> origins, normals = box_planes((0, 1, 0, 2, 0, 3))
    >>> normals[:2].tolist(), origins[1].tolist()
    ([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]], [1.0, 2.0, 3.0])
    """
    b = _vector("box bounds", bounds, 6)
    low, high = b[0::2], b[1::2]
    origins, normals = [], []
    for axis in range(3):
        unit = np.eye(3)[axis]
        origins += [low, high]
        normals += [unit, 0.0 - unit]
    return np.array(origins), np.array(normals)


def plane_rows(origins, normals, transform: Optional[np.ndarray] = None) -> np.ndarray:
    """Planes as rows ``(a, b, c, d)``: a point ``p`` is kept where ``a p_x + b p_y + c p_z + d >= 0``.

    With ``transform`` (4x4, from the planes' space to another: world ->
    index, say), the rows are those of the same planes in the other space.

    Examples
    --------
    >>> plane_rows([[0, 0, 2]], [[0, 0, 1]]).tolist()
    [[0.0, 0.0, 1.0, -2.0]]
    >>> scale = np.diag([1.0, 1.0, 0.5, 1.0])   # z -> z / 2
    >>> plane_rows([[0, 0, 2]], [[0, 0, 1]], scale).tolist()
    [[0.0, 0.0, 2.0, -2.0]]
    """
    origins = np.asarray(origins, dtype=np.float64).reshape(-1, 3)
    normals = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    if origins.shape != normals.shape:
        raise ValueError(f"need as many plane origins as normals, got {len(origins)} and {len(normals)}")
    if not (np.all(np.isfinite(origins)) and np.all(np.isfinite(normals))):
        raise ValueError("plane origins and normals must be finite")
    rows = np.concatenate([normals, -np.sum(normals * origins, axis=1, keepdims=True)], axis=1)
    if transform is not None:
        # p_other = T p  =>  row . p = (row T^-1) . p_other
        rows = rows @ np.linalg.inv(np.asarray(transform, dtype=np.float64))
    return rows


def ray_interval(origin: np.ndarray, direction: np.ndarray, t_low, t_high, rows: np.ndarray) -> tuple:
    """Narrow the ray intervals ``[t_low, t_high]`` of ``origin + t direction`` to the planes' kept side.

    ``origin``/``direction`` are (N, 3) in the planes' space, ``rows`` from
    :func:`plane_rows`.  Returns ``(lo, hi)`` (N,); ``lo > hi`` where nothing
    is kept.  A ray parallel to a plane is kept whole on the kept side and
    dropped on the other.

    Examples
    --------
    >>> rows = plane_rows([[0, 0, 3]], [[0, 0, -1]])     # keep z <= 3
    >>> [float(v[0]) for v in ray_interval(np.zeros((1, 3)), np.array([[0, 0, 1.0]]), 0.0, 10.0, rows)]
    [0.0, 3.0]
    """
    origin = np.asarray(origin, dtype=np.float64)
    direction = np.asarray(direction, dtype=np.float64)
    lo = np.broadcast_to(np.asarray(t_low, dtype=np.float64), origin.shape[:1]).copy()
    hi = np.broadcast_to(np.asarray(t_high, dtype=np.float64), origin.shape[:1]).copy()
    for row in np.asarray(rows, dtype=np.float64).reshape(-1, 4):
        at0 = origin @ row[:3] + row[3]
        rate = direction @ row[:3]
        with np.errstate(divide="ignore", invalid="ignore"):
            cross = -at0 / rate
        lo = np.where(rate > 0, np.maximum(lo, cross), lo)
        hi = np.where(rate < 0, np.minimum(hi, cross), hi)
        hi = np.where((rate == 0) & (at0 < 0), -np.inf, hi)
    return lo, hi


def region_extent(rows: np.ndarray, upper: Sequence[float], to_eye: np.ndarray) -> Optional[Tuple[float, float, float, float]]:
    """View depths and eye distances spanned by the box ``[0, upper]`` cut by the planes ``rows``.

    The box and ``rows`` (:func:`plane_rows`, kept side ``>= 0``) are in one
    space (index space, say); ``to_eye`` (4x4) maps it to eye coordinates
    (camera at the origin looking down -z).  The kept region is a convex
    polytope; returns ``(near, far, nearest, farthest)``: the least and
    greatest view distance ``-z`` over it and the least and greatest
    distance from the eye point, or ``None`` if nothing of the box is kept.
    DEMIP normalises its depth over this region (docs/methods.md, "Slabs,
    clipping and cropping").

    Examples
    --------
    >>> rows = plane_rows(*slab_planes(2.0, (5, 5, 5), (0, 0, 1)))
    >>> to_eye = np.eye(4); to_eye[2, 3] = -20.0          # eye at z = 20 looking down -z
    >>> [round(v, 6) for v in region_extent(rows, (10, 10, 10), to_eye)]
    [14.0, 16.0, 14.0, 21.354157]
    """
    upper = np.asarray(upper, dtype=np.float64).reshape(3)
    box = plane_rows(*box_planes((0.0, upper[0], 0.0, upper[1], 0.0, upper[2])))
    rows = np.concatenate([box, np.asarray(rows, dtype=np.float64).reshape(-1, 4)])
    rows = rows @ np.linalg.inv(np.asarray(to_eye, dtype=np.float64))  # the planes in eye space
    scale = np.linalg.norm(rows[:, :3], axis=1)
    rows = rows[scale > 0] / scale[scale > 0, None]
    tolerance = 1e-9 * max(1.0, float(np.abs(rows[:, 3]).max(initial=1.0)))

    def inside(points: np.ndarray) -> np.ndarray:
        return np.all(points @ rows[:, :3].T + rows[:, 3] >= -tolerance, axis=1)

    count = len(rows)
    vertices = []
    for i in range(count):
        for j in range(i + 1, count):
            for k in range(j + 1, count):
                a = rows[[i, j, k], :3]
                if abs(np.linalg.det(a)) > 1e-12:
                    vertices.append(np.linalg.solve(a, -rows[[i, j, k], 3]))
    vertices = np.array(vertices).reshape(-1, 3)
    vertices = vertices[inside(vertices)]
    if not len(vertices):
        return None
    # the nearest point to the eye (the origin): the origin itself, or its
    # projection on a face or an edge of the region, or a vertex
    candidates = [np.zeros((1, 3)), vertices]
    normals, offsets = rows[:, :3], rows[:, 3]
    candidates.append(-offsets[:, None] * normals)
    for i in range(count):
        for j in range(i + 1, count):
            a = normals[[i, j]]
            gram = a @ a.T
            if abs(np.linalg.det(gram)) > 1e-12:
                candidates.append((a.T @ np.linalg.solve(gram, -offsets[[i, j]]))[None])
    candidates = np.concatenate(candidates)
    candidates = candidates[inside(candidates)]
    distance = -vertices[:, 2]
    return (float(distance.min()), float(distance.max()),
            float(np.linalg.norm(candidates, axis=1).min()), float(np.linalg.norm(vertices, axis=1).max()))


# -- cropping regions ---------------------------------------------------------------
#: VTK's ``GetCroppingRegionFlags()`` of the sub-volume (``SetCroppingRegionFlagsToSubVolume``):
#: bit 13, the centre region.  mipcast crops to it with the box's six planes (:func:`box_planes`).
SUBVOLUME_FLAGS = 0x2000
#: Every one of the 27 regions (no region hidden).
ALL_REGIONS = (1 << 27) - 1


def crop_box(bounds: Sequence[float], transform: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """The cropping planes ``(x0, x1, y0, y1, z0, z1)`` (data coordinates) in another space.

    ``transform`` (4x4, data -> index or texture coordinates) maps the
    corners ``(x0, y0, z0)`` and ``(x1, y1, z1)``; returns their images
    ``(low, high)`` (3,) each: the planes are ``p_a = low_a`` and
    ``p_a = high_a`` on axis ``a`` there.

    Examples
    --------
    >>> low, high = crop_box((1, 3, 0, 2, 4, 5), np.diag([2.0, 1.0, 1.0, 1.0]))
    >>> low.tolist(), high.tolist()
    ([2.0, 0.0, 4.0], [6.0, 2.0, 5.0])
    """
    b = _vector("cropping region planes", bounds, 6)
    transform = np.asarray(transform, dtype=np.float64)
    corners = np.array([[b[0], b[2], b[4], 1.0], [b[1], b[3], b[5], 1.0]]) @ transform.T
    corners = corners[:, :3] / corners[:, 3:]
    return corners[0], corners[1]


def crop_region(points: np.ndarray, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    """VTK's cropping region number (bit index, 0..26) of each point (N, 3).

    Per axis ``a``: 0 below ``low_a``, 1 from ``low_a`` up to (not including)
    ``high_a``, 2 from ``high_a`` on (VTK's GPU ray caster's rule); the
    region is ``i + 3 j + 9 k``, the bit of ``GetCroppingRegionFlags()``
    that makes it visible.

    Examples
    --------
    >>> crop_region(np.array([[0.5, 0.5, 0.5], [2.0, 0.5, 0.5], [-1, -1, 9]]), np.zeros(3), np.ones(3)).tolist()
    [13, 14, 18]
    """
    points = np.asarray(points, dtype=np.float64)
    code = (points >= low).astype(np.int64) + (points >= high)
    return code[..., 0] + 3 * code[..., 1] + 9 * code[..., 2]


def sample_kept(at: np.ndarray, low: np.ndarray, high: np.ndarray, step: float = 1.0) -> np.ndarray:
    """Whether samples at ``at`` (ray parameter, broadcast) lie in the kept interval ``[low, high]`` of a ray
    stepping by ``step`` (the same units): a sample on an end is kept, within :data:`SAMPLE_ON_PLANE` steps.

    Examples
    --------
    >>> sample_kept(np.array([1.9999999, 2.0, 5.0, 5.01]), 2.0, 5.0).tolist()
    [True, True, True, False]
    """
    tie = SAMPLE_ON_PLANE * step
    return (at + tie >= low) & (at - tie <= high)


def sample_visible(points: np.ndarray, step: np.ndarray, low: np.ndarray, high: np.ndarray, flags: int) -> np.ndarray:
    """Whether each sample (N, 3) of a ray stepping by ``step`` (broadcast) counts under cropping regions.

    A sample on a region's boundary counts when the region on either side of
    it along the ray is visible (within :data:`SAMPLE_ON_PLANE` steps, as a
    sample on a clipping plane is kept): float rounding no longer decides. The
    shader's test is the same (``mcCropSampleVisible``, shaders/clip_regions.glsl).

    Examples
    --------
    >>> sample_visible(np.array([[1.0, 0.5, 0.5]]), np.array([1.0, 0.0, 0.0]), np.zeros(3), np.ones(3),
    ...                0x2000).tolist()   # on the plane x = 1 between the visible centre and a hidden region
    [True]
    """
    offset = SAMPLE_ON_PLANE * np.asarray(step, dtype=np.float64)
    return crop_visible(points - offset, low, high, flags) | crop_visible(points + offset, low, high, flags)


def crop_visible(points: np.ndarray, low: np.ndarray, high: np.ndarray, flags: int) -> np.ndarray:
    """Whether each point (N, 3) lies in a region whose bit is set in ``flags``.

    Examples
    --------
    >>> crop_visible(np.array([[0.5, 0.5, 0.5], [2.0, 0.5, 0.5]]), np.zeros(3), np.ones(3), 0x2000).tolist()
    [True, False]
    """
    return ((int(flags) >> crop_region(points, low, high)) & 1).astype(bool)
