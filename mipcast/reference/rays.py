"""Rays and trilinear interpolation shared by the float64 references.

Rays come from :func:`mipcast.core.camera_rays.camera_rays` (VTK's own
pixel-centre rays, in index space); the volume is interpolated trilinearly
between point values, as the GPU's clamp-to-edge 3D texture does.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.lib.stride_tricks import as_strided
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.camera_rays import camera_rays, index_space, matrix_array
from mipcast.core.clipping import SUBVOLUME_FLAGS, box_planes, crop_box, plane_rows, ray_interval

#: Rays per chunk of the sampled reference.
RAY_CHUNK = 65536
#: Samples or segments held in memory at once.
BUDGET = 1 << 20


def hit_rays(image: vtkImageData, camera: Any, size: tuple) -> tuple:
    """The pixels' rays that meet the volume, in index space.

    Returns ``hit`` (bool, H*W, row-major, top row first) and, per hit ray,
    its ``entry`` point (N, 3), ``direction`` (N, 3, per unit length) and
    ``length`` (N,) inside the box, in world units, or for an image placed
    by a volume's matrix that scales (:func:`mipcast.mappers.brick_rays.placed`:
    its direction matrix is not orthonormal) in the volume's own units, where
    VTK measures the sample distance.
    """
    rays = camera_rays(image, camera, size)
    hit = rays.hit.ravel()
    t_enter = rays.t_enter.ravel()[hit]
    length = rays.t_exit.ravel()[hit] - t_enter
    direction = rays.direction.reshape(-1, 3)[hit]
    entry = rays.origin.reshape(-1, 3)[hit] + t_enter[:, None] * direction
    axes = matrix_array(image.GetDirectionMatrix())
    if not np.allclose(axes.T @ axes, np.eye(3), rtol=0.0, atol=1e-12):  # a scaling volume matrix folded in
        own = np.linalg.norm(direction * np.abs(np.array(image.GetSpacing())), axis=1)  # own length per world length
        direction, length = direction / own[:, None], length * own
    return hit, entry, direction, length


def scatter(found: np.ndarray, hit: np.ndarray, height: int, width: int) -> np.ndarray:
    """Per-hit-ray results (N, ...) as an (H, W, ...) image, NaN where the ray misses."""
    out = np.full((width * height,) + found.shape[1:], np.nan)
    out[hit] = found
    return out.reshape((height, width) + found.shape[1:])


def gather(values: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """Corner values (M, 8) of cells ``cell`` (M, 3); column b = dx + 2 dy + 4 dz."""
    nz, ny, nx = values.shape
    flat = values.ravel()
    step = flat.strides[0]
    # item n of this view is the 2x2x2 block of points whose first corner is point n
    blocks = as_strided(flat, shape=(flat.size - nx * ny - nx - 1, 2, 2, 2),
                        strides=(step, nx * ny * step, nx * step, step), writeable=False)
    return blocks[cell[:, 0] + nx * (cell[:, 1] + ny * cell[:, 2])].reshape(-1, 8)


def cells(values: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Index (M, 3) of the cell holding each position, clipped to the grid."""
    top = np.array(values.shape[::-1]) - 2
    return np.clip(np.floor(position), 0, top).astype(np.int64)


def nearest(values: np.ndarray, position: np.ndarray) -> np.ndarray:
    """The value of the point nearest each index position (M, 3), clamped to the grid: a 3D texture's
    nearest-neighbour lookup (``SetInterpolationTypeToNearest``; half-way rounds up, as ``floor(u * N)``).

    Examples
    --------
    >>> nearest(np.arange(8.0).reshape(2, 2, 2), np.array([[0.4, 0.6, 0.0], [1.5, 0.2, 3.0]])).tolist()
    [2.0, 5.0]
    """
    top = np.array(values.shape[::-1]) - 1
    index = np.clip(np.floor(position + 0.5), 0, top).astype(np.int64)
    return values[index[:, 2], index[:, 1], index[:, 0]]


def trilinear(values: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Clamp-to-edge trilinear interpolation at index positions (M, 3)."""
    position = np.clip(position, 0, np.array(values.shape[::-1]) - 1.0)
    cell = cells(values, position)
    corner = gather(values, cell)
    weight = position - cell
    for axis in range(3):
        w = weight[:, axis, None]
        corner = corner[:, 0::2] + w * (corner[:, 1::2] - corner[:, 0::2])
    return corner[:, 0]


def clip_interval(image, entry: np.ndarray, direction: np.ndarray, length: np.ndarray,
                  clip_planes=None, within_box: bool = True) -> tuple:
    """Per hit ray, the part ``[lo, hi]`` (world distance from its box entry) that ``clip_planes`` keep.

    ``clip_planes`` is ``(origins, normals)`` in world coordinates (see
    :func:`mipcast.reference.render`); without planes the whole ray,
    ``[0, length]``.  ``within_box=False``: the planes' interval alone (the
    sampled references filter the box ray's own samples with it: a ray
    shorter than one step keeps its one sample unless a plane drops it).

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> image = vtkImageData()
    >>> image.SetDimensions(5, 5, 5)
    >>> lo, hi = clip_interval(image, np.array([[2.0, 2.0, 0.0]]), np.array([[0.0, 0.0, 1.0]]),
    ...                        np.array([4.0]), ([[0, 0, 1.5]], [[0, 0, 1]]))
    >>> float(lo[0]), float(hi[0])
    (1.5, 4.0)
    """
    low, high = (0.0, length) if within_box else (-np.inf, np.inf)
    if clip_planes is None:
        return (np.broadcast_to(np.asarray(low, dtype=np.float64), np.shape(length)).copy(),
                np.broadcast_to(np.asarray(high, dtype=np.float64), np.shape(length)).copy())
    origins, normals = clip_planes
    to_index, _ = index_space(image)
    rows = plane_rows(origins, normals, to_index)
    return ray_interval(entry, direction, low, high, rows)


def cropping_setup(image, cropping, clip_planes, matrix=None) -> tuple:
    """VTK's cropping for the references: ``(clip_planes, crop)``.

    ``cropping`` is ``(bounds, flags)``: ``SetCroppingRegionPlanes`` (six
    numbers, data coordinates) and ``GetCroppingRegionFlags()``, or ``None``.
    The sub-volume (flags ``0x2000``) is the box's six planes, appended to
    ``clip_planes`` (as the mappers clip with it); other flags give ``crop =
    (low, high, flags)``, the planes in index space for
    :func:`mipcast.core.clipping.crop_visible` (``None``: no cropping).
    ``matrix`` (4x4 array or vtkMatrix4x4): the volume's matrix when ``image``
    is placed by it (:func:`mipcast.mappers.brick_rays.placed`): the data
    coordinates are then the volume's own, ``matrix`` maps them to the world.

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> image = vtkImageData()
    >>> image.SetDimensions(5, 5, 5)
    >>> image.SetSpacing(2.0, 1.0, 1.0)
    >>> planes, crop = cropping_setup(image, ((1, 3, 1, 3, 1, 3), 0x1), None)
    >>> planes is None, crop[0].tolist(), crop[1].tolist(), crop[2]
    (True, [0.5, 1.0, 1.0], [1.5, 3.0, 3.0], 1)
    >>> planes, crop = cropping_setup(image, ((1, 3, 1, 3, 1, 3), 0x2000), None)
    >>> len(planes[0]), crop
    (6, None)
    """
    if cropping is None:
        return clip_planes, None
    try:
        bounds, flags = cropping
        flags = int(flags)
    except (TypeError, ValueError):
        raise TypeError(f"cropping must be (six region planes, region flags), got {cropping!r}") from None
    if not 0 <= flags < (1 << 27):
        raise ValueError(f"cropping region flags must be in 0 .. 0x7ffffff (27 regions), got {flags:#x}")
    to_world = np.eye(4) if matrix is None else matrix if isinstance(matrix, np.ndarray) else matrix_array(matrix)
    if flags == SUBVOLUME_FLAGS:
        origins, normals = box_planes(bounds)
        origins = origins @ to_world[:3, :3].T + to_world[:3, 3]
        normals = normals @ np.linalg.inv(to_world[:3, :3])  # a plane's normal: the inverse transpose
        if clip_planes is not None:
            origins = np.concatenate([np.asarray(clip_planes[0], float).reshape(-1, 3), origins])
            normals = np.concatenate([np.asarray(clip_planes[1], float).reshape(-1, 3), normals])
        return (origins, normals), None
    to_index, _ = index_space(image)
    low, high = crop_box(bounds, to_index @ to_world)
    return clip_planes, (low, high, flags)
