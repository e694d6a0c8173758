"""A max-filtered 3D pyramid of a volume, for peripheral rays of foveated MIP.

Each level halves the number of points along every axis that has more than
2 (the paper's "hyperpyramid", 1/8 of the voxels per level), keeping the
bounds of the volume exactly: ``n' = ceil((n - 1) / 2) + 1`` points spread
over the same extent.  A coarse point takes the **maximum** of the fine
points within half a coarse spacing of it (a 2-3 tap window per axis, every
fine point in at least one window).

Why a max filter and not the paper's box filter: a MIP pixel *is* a
maximum, and the maximum of maxima is the maximum, whereas a box filter
averages a thin bright vessel with its background and lowers its peak by
up to 7/8 per level, so vessels fade out of the periphery.  With the max
filter no peak is lost: every fine point's value is reached at a coarse
point within one coarse voxel, so a coarse ray passing there finds it.  The
price is width: structures grow by up to one coarse voxel, which is why the
foveated mapper reads level ``j`` only where its voxels are no wider than
the spacing of the peripheral rays (see :func:`level_sampling`) -- there
the widening is about what those rays resolve anyway, and it is what stops
thin vessels from flickering or breaking into dashes between peripheral
rays (aliasing).  When the view is zoomed in (voxels larger than the
peripheral ray spacing) no coarse level is read at all.
"""
from __future__ import annotations

import math
from typing import List, Sequence

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.foveation import SAMPLING_POLICIES
from mipcast.core.prepare import prepare_scalars


def coarse_axis(n: int) -> int:
    """Points along an axis of ``n`` points at the next level.

    Examples
    --------
    >>> [coarse_axis(n) for n in (2, 3, 4, 5, 64, 65)]
    [2, 2, 3, 3, 33, 33]
    """
    return max(2, math.ceil((n - 1) / 2) + 1) if n > 2 else n


def max_reduce_axis(values: np.ndarray, axis: int) -> np.ndarray:
    """One 2:1 max reduction along ``axis`` (bounds kept, see the module docstring).

    Examples
    --------
    >>> max_reduce_axis(np.array([0, 0, 0, 9, 0, 0, 0]), 0)
    array([0, 9, 9, 0])
    >>> max_reduce_axis(np.array([5, 0, 0, 0]), 0)
    array([5, 0, 0])
    """
    n = values.shape[axis]
    m = coarse_axis(n)
    if m == n:
        return values
    ratio = (n - 1) / (m - 1)
    centres = np.arange(m) * ratio
    nearest = np.rint(centres).astype(int)  # always inside its own window
    result = np.take(values, nearest, axis=axis)
    shape = [1] * values.ndim
    shape[axis] = m
    for offset in (-2, -1, 1, 2):
        index = nearest + offset
        inside = (index >= 0) & (index < n) & (np.abs(index - centres) <= 0.5 * ratio + 1e-9)
        taken = np.take(values, np.clip(index, 0, n - 1), axis=axis)
        result = np.where(inside.reshape(shape), np.maximum(result, taken), result)
    return result.astype(values.dtype, copy=False)


def build_max_pyramid(image: vtkImageData, levels: int, component=None) -> List[vtkImageData]:
    """Level 0 (``image`` itself) and up to ``levels - 1`` max-reduced levels.

    Stops early when no axis can shrink (every axis has 2 points).  Coarse
    levels keep the origin, direction matrix, bounds, scalar type and the
    scalars' name; their spacing is ``(n - 1) / (n' - 1)`` times larger.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> pyramid = build_max_pyramid(make_fixture("spheres", size=16), 3)
    >>> [p.GetDimensions() for p in pyramid]
    [(16, 16, 16), (9, 9, 9), (5, 5, 5)]
    >>> pyramid[2].GetBounds() == pyramid[0].GetBounds()
    True
    """
    prepared = prepare_scalars(image, component)  # one component, missing values filled
    pyramid = [image]
    array = np.asarray(prepared.values)
    name = image.GetPointData().GetScalars().GetName() or "scalars"
    for _ in range(1, max(int(levels), 1)):
        coarse = array
        for axis in range(3):
            coarse = max_reduce_axis(coarse, axis)
        if coarse.shape == array.shape:
            break
        # a coarse point of missing voxels only is missing again (NaN): its level's mapper fills it
        level = np.where(coarse < prepared.missing_below, np.nan, coarse) if prepared.missing else coarse
        pyramid.append(_wrap(level, image, array.shape, pyramid[-1], name))
        array = coarse
    return pyramid


def _wrap(values: np.ndarray, original: vtkImageData, fine_shape, fine: vtkImageData,
          name: str) -> vtkImageData:
    nz, ny, nx = values.shape
    fz, fy, fx = fine_shape
    spacing = [s * ((f - 1) / (n - 1) if n > 1 else 1.0)
               for s, f, n in zip(fine.GetSpacing(), (fx, fy, fz), (nx, ny, nz))]
    out = vtkImageData()
    out.SetDimensions(nx, ny, nz)
    out.SetSpacing(spacing)
    out.SetOrigin(original.GetPoint(0))  # the first point of the extent
    out.SetDirectionMatrix(original.GetDirectionMatrix())
    array = numpy_to_vtk(np.ascontiguousarray(values).ravel(), deep=True)
    array.SetName(name)
    out.GetPointData().SetScalars(array)
    return out


def pyramid_voxel_sizes(image: vtkImageData, levels: int) -> List[float]:
    """The largest spacing of each level :func:`build_max_pyramid` would build, without building it.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> pyramid_voxel_sizes(make_fixture("spheres", size=16), 4)
    [1.0, 1.875, 3.75, 7.5]
    """
    dims = list(image.GetDimensions())
    spacing = [abs(s) for s in image.GetSpacing()]
    sizes = [max(spacing)]
    current = list(dims)
    for _ in range(1, max(int(levels), 1)):
        coarse = [coarse_axis(n) for n in current]
        if coarse == current:
            break
        current = coarse
        sizes.append(max(s * ((n0 - 1) / (n - 1) if n > 1 else 1.0)
                         for s, n0, n in zip(spacing, dims, current)))
    return sizes


#: How peripheral levels sample along their rays (see :func:`level_sampling`).


def level_sampling(level: int, footprint: float, base_distance: float, voxel_sizes: Sequence[float],
                   walks_cells: bool = False, policy: str = "footprint") -> tuple:
    """(pyramid level, sample distance) for image level ``level``.

    Parameters
    ----------
    level : int
        Image pyramid level (rays every ``2**level`` pixels); level 0 always
        reads the full volume at ``base_distance``.
    footprint : float
        Spacing of this level's rays at the volume, model units.
    base_distance : float
        Full-quality sample distance, model units.
    voxel_sizes : sequence of float
        :func:`pyramid_voxel_sizes` of the volume.
    walks_cells : bool, default: False
        The method visits cells instead of taking samples (analytic MIP):
        only the pyramid level matters.
    policy : {"footprint", "level", "rays"}, default: "footprint"
        ``"footprint"``: samples along the ray no farther apart than the
        rays themselves (isotropic 3D sampling, as the paper intends when a
        pixel is about a voxel) and at most ``2**level`` times the base
        distance, snapped to one sample per voxel of the coarsest pyramid
        level that fits -- no depth aliasing, and widening by the max filter
        stays below the ray spacing.  ``"level"``: the paper's fixed
        schedule, ``2**level`` times the base distance, reading pyramid level
        ``level`` (widens thin structures when zoomed in).  ``"rays"``:
        ``2**level`` times the base distance on the full volume (aliases
        along the ray on thin structures).

    Examples
    --------
    >>> sizes = [1.0, 2.0, 4.0]
    >>> level_sampling(2, 0.5, 1.0, sizes)   # zoomed in: rays closer than voxels
    (0, 1.0)
    >>> level_sampling(2, 8.0, 1.0, sizes), level_sampling(1, 8.0, 0.5, sizes)
    ((2, 4.0), (1, 1.0))
    >>> level_sampling(2, 0.5, 1.0, sizes, policy="level"), level_sampling(2, 0.5, 1.0, sizes, policy="rays")
    ((2, 4.0), (0, 4.0))
    >>> level_sampling(2, 2.5, 1.0, sizes, walks_cells=True)  # the distance is unused there
    (1, 2.0)
    """
    if policy not in SAMPLING_POLICIES:
        raise ValueError(f"unknown policy {policy!r}; valid: {', '.join(map(repr, SAMPLING_POLICIES))}")
    if level <= 0:
        return 0, base_distance
    schedule = base_distance * 2 ** level
    if policy == "rays":
        return 0, schedule
    if policy == "level":
        chosen = min(level, len(voxel_sizes) - 1)
        return chosen, schedule
    reach = footprint if walks_cells else min(footprint, voxel_sizes[0] * 2 ** level)
    chosen = choose_level(reach, voxel_sizes)
    return chosen, base_distance * voxel_sizes[chosen] / voxel_sizes[0]


def choose_level(footprint: float, voxel_sizes: Sequence[float]) -> int:
    """The coarsest level whose voxels are no wider than ``footprint``.

    ``footprint`` is the smaller of the spacing between a level's rays and
    between its samples, in the same units as ``voxel_sizes``; level 0 when
    even that is below the full-resolution voxel.

    Examples
    --------
    >>> choose_level(4.0, [1.0, 2.0, 4.0])
    2
    >>> choose_level(3.9, [1.0, 2.0, 4.0]), choose_level(0.5, [1.0, 2.0])
    (1, 0)
    """
    chosen = 0
    for index, size in enumerate(voxel_sizes):
        if size <= footprint * (1.0 + 1e-9):
            chosen = index
    return chosen
