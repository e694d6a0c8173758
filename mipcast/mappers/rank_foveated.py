"""The foveated method composited exactly over the ranks of one parallel render view.

A foveated frame (:mod:`mipcast.mappers.foveated`) casts several levels
(ray grids, each on a pyramid volume level) and blends them.  Across ranks
the principle is that of :mod:`mipcast.mappers.bricked_foveated` beyond the
texture limit: each level's rays are composited over the pieces FIRST, by
the maximum (exact for the ``mip`` and ``analytic`` layers: the maximum
over disjoint sample or cell sets is the maximum over their union), and
only then blended.  Blending each rank's own foveated picture and
compositing those is what goes wrong (a maximum of blends is no blend of
maxima; ordered alpha blending of MIP pictures loses the far pieces).

Per frame, on every rank, in the renderer's StartEvent
(plugin/representation/mipcast_representation.py, as
:mod:`mipcast.mappers.rank_composite`):

1. the shape, the scalar range, the whole volume and the plan's sizes are
   reduced first (a rank without data learns them and takes part);
2. the coarse pyramid levels of the WHOLE volume: each rank max-reduces its
   piece onto the whole coarse grid (:func:`partial_pyramid`; a coarse
   point takes the maximum of the fine points in its window, a window cut by
   a piece border gets the part on this piece), reduced with MAX over the
   ranks, so every rank holds the whole volume's exact coarse levels (1/8,
   1/64 ... of the voxels: the price of exactness);
3. each level of the plan is read out privately (float, the level's grid,
   the WHOLE volume's rays, cast range and silhouette band:
   :func:`mipcast.mappers.bricked_foveated.source_class`): level volume 0 from
   this rank's piece, coarser ones from the whole coarse level; reduced with
   MAX over the ranks;
4. the reduced levels are coloured with the volume's transfer functions
   (:func:`mipcast.mappers.bricked_draw.colour`) and blended on the CPU as
   the GPU blends them (:func:`blend_levels`): every rank draws the same
   picture (:func:`mipcast.mappers.rank_composite.draw`).

Refused across ranks, with a message (every rank alike): DEMIP layers (two
phases per level), content-adaptive density (``content_tolerance`` > 0),
progressive refinement, volumes with missing (NaN) values.

Examples
--------
>>> import numpy as np
>>> from mipcast.mappers.rank_foveated import partial_max_reduce_axis
>>> whole = np.array([0, 0, 0, 9, 0, 0, 0.0])
>>> first, part = partial_max_reduce_axis(whole[:4], 0, 0, 7)       # a piece of points 0..3
>>> second, rest = partial_max_reduce_axis(whole[3:], 0, 3, 7)      # and 3..6 (one point shared)
>>> full = np.full(4, -np.inf); full[first:first + len(part)] = part
>>> full[second:second + len(rest)] = np.maximum(full[second:second + len(rest)], rest); full.tolist()
[0.0, 9.0, 9.0, 0.0]
"""
from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Callable, Optional, Sequence, Tuple

import numpy as np

from mipcast.core import content_adaptive, foveation
from mipcast.core.camera_rays import first_point
from mipcast.core.object_state import object_state
from mipcast.core.prepare import missing_fill, prepare_scalars
from mipcast.core.parameter_tables import FOVEATION_LAYERS
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.mappers.clip_uniforms import cuts
from mipcast.mappers.stereo import draw_for

Reduce = Callable[[np.ndarray, str], np.ndarray]

_LOW, _HIGH = -1.0e300, 1.0e300
#: A missing voxel in the pieces' shares of the coarse levels: above "no rank covered it" (_LOW), below every value.
_MISSING = -1.0e299
#: The layer methods' ``BRICKS`` composited over the ranks: the maximum (MIP, analytic MIP) and DEMIP's two phases.
_LAYERS = ("max", "demip")
#: Most pyramid levels / plan layers the fixed-size head carries.
_MAX_LEVELS = 12
#: Why content-adaptive density with missing values is refused over ranks.
MISSING_ADAPTIVE = ("foveated content-adaptive density (content_tolerance > 0) over MPI ranks is not supported on "
                    "data with missing (NaN/Inf) values: a fovea ray that meets missing data only paints what lies "
                    "beneath on one process (shaders/foveated_paint_beneath.glsl), which the ranks' blend does not "
                    "reproduce yet; use content_tolerance 0 (acuity-only foveation) or fill the missing values")

#: Why content-adaptive density with cropping, clipping planes or a slab is refused over ranks.
CUT_ADAPTIVE = ("foveated content-adaptive density (content_tolerance > 0) over MPI ranks is not supported with "
                "cropping, clipping planes or a slab: a fovea ray they cut away entirely paints what lies beneath on "
                "one process (shaders/foveated_paint_beneath.glsl), which the ranks' blend cannot tell from a ray "
                "outside the volume in the values it reduces; use content_tolerance 0 (acuity-only foveation), or "
                "render on one rank")


def partial_max_reduce_axis(values: np.ndarray, axis: int, start: int, whole: int) -> Tuple[int, np.ndarray]:
    """A piece's share of one 2:1 max reduction of the whole axis (:func:`volume_pyramid.max_reduce_axis`).

    ``values`` hold whole indices ``start .. start + len - 1`` along ``axis``
    of an axis of ``whole`` points.  Returns (first coarse index, values) for
    the coarse points whose window holds a point of the piece: the maximum of
    those of its points; the maximum over pieces that cover the axis is the
    whole's reduction exactly.
    """
    from mipcast.mappers.volume_pyramid import coarse_axis

    m = coarse_axis(whole)
    if m == whole:
        return start, values
    ratio = (whole - 1) / (m - 1)
    stop = start + values.shape[axis] - 1
    first = max(0, math.ceil((start - 0.5 * ratio - 1e-9) / ratio))
    last = min(m - 1, math.floor((stop + 0.5 * ratio + 1e-9) / ratio))
    parts = []
    for c in range(first, last + 1):
        centre = c * ratio
        lo = max(start, math.ceil(centre - 0.5 * ratio - 1e-9))
        hi = min(stop, math.floor(centre + 0.5 * ratio + 1e-9))
        if hi < lo:  # the window holds no point of this piece (cannot happen between first and last)
            shape = list(values.shape)
            shape[axis] = 1
            parts.append(np.full(shape, -np.inf))
            continue
        taken = np.take(values, np.arange(lo - start, hi - start + 1), axis=axis)
        parts.append(taken.max(axis=axis, keepdims=True))
    return first, np.concatenate(parts, axis=axis)


def whole_coarse_dims(dims: Sequence[int], levels: int) -> list:
    """The (nx, ny, nz) of the whole volume's coarse levels 1 .. (as :func:`volume_pyramid.build_max_pyramid`)."""
    from mipcast.mappers.volume_pyramid import coarse_axis

    out, current = [], list(dims)
    for _ in range(1, max(int(levels), 1)):
        nxt = [coarse_axis(n) for n in current]
        if nxt == current:
            break
        out.append(tuple(nxt))
        current = nxt
    return out


def partial_pyramid(values: np.ndarray, offset: Sequence[int], whole_dims: Sequence[int], levels: int) -> list:
    """This piece's share of every coarse level: [(offset (x, y, z) in the coarse grid, values (z, y, x))]."""
    out = []
    array, start, dims = np.asarray(values, dtype=np.float64), [int(o) for o in offset], list(whole_dims)
    for coarse in whole_coarse_dims(whole_dims, levels):
        for axis in range(3):  # numpy axis 0 is z
            index = 2 - axis
            start[index], array = partial_max_reduce_axis(array, axis, start[index], dims[index])
        dims = list(coarse)
        out.append((tuple(start), array))
    return out


class _WholeBox:
    """What the plan's helpers ask of a vtkVolume (bounds, centre, matrix), of the WHOLE volume."""

    def __init__(self, volume, whole_image):
        self._matrix = volume.GetMatrix()
        b = whole_image.GetBounds()
        corners = np.array([[x, y, z, 1.0] for x in b[0:2] for y in b[2:4] for z in b[4:6]])
        m = np.array([[self._matrix.GetElement(r, c) for c in range(4)] for r in range(4)])
        world = corners @ m.T
        world = world[:, :3] / world[:, 3:]
        low, high = world.min(axis=0), world.max(axis=0)
        self._bounds = (low[0], high[0], low[1], high[1], low[2], high[2])
        self._centre = tuple(0.5 * (low + high))

    def GetBounds(self):
        return self._bounds

    def GetCenter(self):
        return self._centre

    def GetMatrix(self):
        return self._matrix


def spill_bounds(bounds: Sequence[float], camera, height: int, texel_pixels: float) -> Tuple[float, ...]:
    """World ``bounds`` enlarged so that their projection covers ``texel_pixels`` more pixels on every side.

    A coarse level's rays stretched over the viewport (linear filtering)
    reach up to one coarse texel (``texel_pixels``, its image sample distance
    in pixels) beyond the volume's outline.  IceT keeps each rank's pixels
    only inside the projection of the bounds of the props it shows
    (``vtkIceTCompositePass``: ``ComputeVisiblePropBounds`` ->
    ``icetBoundingBoxd``), so the representation shows a prop of these
    bounds: each axis grows by the pixels times the world length of a pixel
    at the box's farthest corner (the largest, so no corner moves fewer
    pixels), which moves the projected outline out by at least that many
    pixels (the enlarged box holds a ball of that radius round every point).

    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> camera = vtkCamera(); camera.ParallelProjectionOn(); camera.SetParallelScale(10.0)
    >>> [round(v, 2) for v in spill_bounds((0, 1, 0, 1, 0, 1), camera, 100, 4)]   # 0.2 world per pixel
    [-0.8, 1.8, -0.8, 1.8, -0.8, 1.8]
    """
    low, high = np.array(bounds[0::2], dtype=np.float64), np.array(bounds[1::2], dtype=np.float64)
    height = max(int(height), 1)
    if camera.GetParallelProjection():
        world = 2.0 * camera.GetParallelScale() / height
    else:
        corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1])
                            for z in (low[2], high[2])])
        depth = (corners - np.array(camera.GetPosition())) @ np.array(camera.GetDirectionOfProjection())
        world = 2.0 * max(float(depth.max()), 0.0) * math.tan(math.radians(camera.GetViewAngle()) / 2.0) / height
    margin = world * float(texel_pixels)
    return tuple(float(v) for pair in zip(low - margin, high + margin) for v in pair)


def refusal(mapper, renderer=None) -> Optional[str]:
    """Why ``mapper``'s settings cannot be composited exactly over the ranks (in ``renderer``), or None.

    >>> from mipcast.mappers.foveated import FoveatedVolumeMapper
    >>> refusal(FoveatedVolumeMapper()) is None
    True
    >>> mapper = FoveatedVolumeMapper(); mapper.SetMethod("demip"); refusal(mapper) is None   # every layer today
    True
    """
    params = mapper._parameters()
    method = params["method"]
    if getattr(FOVEATION_LAYERS[method].factory, "BRICKS", None) not in _LAYERS:
        able = ", ".join(n for n, e in FOVEATION_LAYERS.items() if getattr(e.factory, "BRICKS", None) in _LAYERS)
        return (f"foveated with {method!r} levels cannot be composited exactly over the ranks (a level's ray "
                f"value over several pieces is not the pieces' maximum): use foveation layers {able}, or the "
                f"{method!r} method itself unfoveated")
    if float(params["content_tolerance"]) > 0.0 and renderer is not None and _background(renderer) is None:
        return ("foveated content-adaptive density (content_tolerance > 0) over the ranks needs a single-colour "
                "background (its masks compare the coarse levels' pictures with what lay beneath them, which the "
                "ranks know only as the background colour): use a single-colour background, or content_tolerance "
                "0, or render on one rank")
    if float(params["content_tolerance"]) > 0.0 and cuts(mapper, renderer.GetActiveCamera() if renderer else None):
        return CUT_ADAPTIVE
    return None


def _is_demip(method: str) -> bool:
    """Whether the layer ``method`` draws DEMIP levels (two phases, reduced with MAX and MIN)."""
    return getattr(FOVEATION_LAYERS[method].factory, "BRICKS", None) == "demip"


def _background(renderer) -> Optional[tuple]:
    """The renderer's background as the 8-bit framebuffer holds it (RGB, 0 .. 255); None when it is no single
    colour (a gradient, a texture, a skybox: not known to the ranks' CPU blend)."""
    for flag in ("GetGradientBackground", "GetTexturedBackground"):
        if getattr(renderer, flag, lambda: False)():
            return None
    return tuple(float(np.floor(np.clip(c, 0.0, 1.0) * 255.0 + 0.5)) for c in renderer.GetBackground())


def _piece_values(piece, component) -> Tuple[np.ndarray, float, float, bool]:
    """(values (z, y, x) with missing voxels NaN, finite low, finite high, missing) of this rank's piece.

    The drawn component (:func:`mipcast.core.prepare.prepare_scalars`), not
    filled: the pieces agree on the fill once the whole range is reduced.  A
    piece of missing values only: low > high (nothing to the range).
    """
    prepared = prepare_scalars(piece, component, whole_range=(0.0, 1.0))  # any range: the finite one is low, high
    values = np.asarray(prepared.values)
    if not prepared.missing:
        return values, prepared.low, prepared.high, False
    if prepared.missing == values.size:
        return np.full(values.shape, np.nan), _HIGH, _LOW, True
    # filled below the piece's own finite range: everything under its threshold was missing
    own = prepare_scalars(piece, component, whole_range=(prepared.low, prepared.high))
    return (np.where(np.asarray(own.values) < own.missing_below, np.nan, own.values), prepared.low, prepared.high,
            True)


def _texture_range(image) -> Tuple[float, float]:
    """The scalar range of ``image``'s texture as a level mapper prepares it (missing values: from the fill)."""
    prepared = prepare_scalars(image)
    return (prepared.fill if prepared.missing else prepared.low), prepared.high


def _source_entry(state, key, kind, image, extent, whole, distance) -> dict:
    """A private brick mapper of the layer method casting only a level's rays, cached per key."""
    from mipcast.mappers.brick_rays import brick_entry
    from mipcast.mappers.bricked_foveated import source_class

    cache = state.setdefault("rank_foveated_sources", {})
    cached = cache.get(key[0])
    if cached is not None and cached[0] == key:
        return cached[1]
    entry = brick_entry(source_class(kind), image, extent, whole, image.GetSpacing(), distance)
    object_state(entry["mapper"])["global_cells"] = False  # cells lie whole in a piece
    cache[key[0]] = (key, entry)
    return entry


def _image_of(values: np.ndarray, origin, spacing, direction, dtype, name: str):
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    nz, ny, nx = values.shape
    image = vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetOrigin(origin)
    image.SetSpacing(spacing)
    image.SetDirectionMatrix(direction)
    array = numpy_to_vtk(np.ascontiguousarray(values.astype(dtype)).ravel(), deep=True)
    array.SetName(name)
    image.GetPointData().SetScalars(array)
    return image


def compose(mapper, volume, renderer, piece, whole_stub, reduce: Reduce) -> Tuple[Optional[np.ndarray], Optional[str]]:
    """This frame's final premultiplied RGBA (top row first), the same on every rank; or (None, why).

    As :func:`mipcast.mappers.rank_composite.compose` (the same arguments,
    rule ``"foveated"``); ``mapper`` a :class:`~mipcast.mappers.foveated.FoveatedVolumeMapper`.
    Every rank enters the same reductions whatever happens locally: a rank
    that fails notes why (``rank.problem``) and goes on to the end.  The
    steps: :func:`_plan_locally` (0: progressive refinement's step, agreed),
    :func:`_agree_head` (1: the frame's shape, range and plan, agreed),
    :func:`_reduce_coarse_levels` (2: the whole volume's coarse levels),
    :func:`_read_levels` (3: each level's rays, and the structure bound),
    :func:`_finish` (the DEMIP levels' second phase, then 4: the blend).
    """
    rank = _plan_locally(mapper, volume, renderer, piece, whole_stub, reduce)
    failure = _agree_head(rank, reduce)
    if failure is not None:
        return None, failure
    _reduce_coarse_levels(rank, reduce)
    failure = _read_levels(rank, volume, renderer, reduce)
    if failure is not None:
        return None, failure
    return _finish(rank, volume, renderer, reduce)


def _plan_locally(mapper, volume, renderer, piece, whole_stub, reduce: Reduce) -> SimpleNamespace:
    """This rank's frame: its piece's values, the gaze, progressive refinement's step (0: the fewest still
    frames over the ranks, a change on any rank making it 0), the plan and each layer's sampling."""
    from mipcast.mappers import foveated, foveated_levels, volume_pyramid
    from mipcast.mappers.brick_rays import whole_geometry

    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    shape = (max(height[0], 1), max(width[0], 1))
    rank = SimpleNamespace(
        mapper=mapper, piece=piece, whole_stub=whole_stub, shape=shape, viewport=(x0[0], y0[0], shape[1], shape[0]),
        camera=renderer.GetActiveCamera(), problem=None, plan=None, values0=None, sampling=[], whole_image=None,
        params=None, low=_HIGH, high=_LOW, missing=False, tolerance=0.0, box=None,
        state=object_state(mapper) if mapper is not None else {})
    if mapper is not None:
        rank.state.pop("rank_foveated_bounds", None)
    rank.usable = (mapper is not None and piece is not None and piece.GetNumberOfPoints() > 0
                   and whole_stub is not None and piece.GetPointData().GetScalars() is not None)
    step = gaze = radius = None
    if rank.usable:
        try:
            rank.problem = refusal(mapper, renderer)
            rank.params = mapper._parameters()
            stamp = (piece.GetAddressAsString("vtkObjectBase"), piece.GetMTime(), mapper.GetComponent())
            cached = rank.state.get("rank_foveated_piece_values")
            if cached is None or cached[0] != stamp:  # prepared once per piece, not every frame
                cached = (stamp, _piece_values(piece, mapper.GetComponent()))
                rank.state["rank_foveated_piece_values"] = cached
            rank.values0, rank.low, rank.high, rank.missing = cached[1]
            rank.whole_image = whole_geometry(whole_stub)
            rank.box = _WholeBox(volume, rank.whole_image)
            gaze, radius = foveated._current_gaze(rank.state, renderer, rank.camera, rank.viewport)
            if rank.params["progressive"]:
                step = foveated.refine_step(rank.state, rank.params, piece, volume, rank.camera, rank.viewport, gaze,
                                            foveated.counts_frame(renderer, rank.camera))
        except Exception as error:  # noqa: BLE001  (reported; the collectives still run)
            rank.problem, rank.params = repr(error), None
    # 0: progressive refinement's still frames, the same on every rank: the fewest (a change on any rank: 0)
    agreed = float(reduce(np.array([-float(step) if step is not None else _LOW]), "max")[0])
    if not rank.usable or rank.params is None:
        return rank
    params, viewport = rank.params, rank.viewport
    try:
        foveate = params["foveation"]
        if agreed > 0.5 * _LOW:
            rank.state["refine_step"] = int(round(-agreed))
            radius, foveate = foveated.refined_radius(params, viewport, gaze, radius, rank.state["refine_step"])
        base_isd = float(mapper.GetImageSampleDistance())
        base_distance = float(mapper.GetSampleDistance())
        cap = foveated_levels.level_cap(rank.whole_image, rank.box, rank.camera, viewport)
        plan = foveation.plan_frame(viewport, gaze, radius, params["falloff"], params["number_of_levels"],
                                    foveate, cap, base_isd)
        rank.tolerance = float(params["content_tolerance"])
        if rank.tolerance > 0 and len(plan.layers) > 1:  # content-adaptive: a coarser content level cast everywhere
            plan = content_adaptive.adaptive_plan(plan, cap)
        cells = foveated_levels.walks_cells(params["method"])
        spacings = volume_pyramid.pyramid_voxel_sizes(rank.whole_image, params["number_of_levels"])
        world_per_pixel = foveated_levels.world_per_pixel(rank.camera, rank.box, viewport)
        for layer in plan.layers:
            footprint = world_per_pixel * viewport[3] / max(layer.grid[1], 1)
            rank.sampling.append(volume_pyramid.level_sampling(layer.level, footprint, base_distance, spacings,
                                                               cells, params["peripheral_sampling"]))
        rank.plan = plan
    except Exception as error:  # noqa: BLE001  (reported; the collectives still run)
        rank.problem = repr(error)
    return rank


def _agree_head(rank, reduce: Reduce) -> Optional[str]:
    """1: the head, reduced with MAX: shape, finite range, whole dims, the plan's layers (grid, volume level),
    a failure flag, missing values, DEMIP, the structure bound's layer.  Sets the agreed figures on ``rank``;
    returns why the frame cannot be drawn (the same on every rank), or None."""
    plan, params = rank.plan, rank.params
    head = np.full(8 + 3 + 1 + 3 * _MAX_LEVELS + 3, _LOW)
    finite = rank.usable and rank.high >= rank.low
    head[:6] = [rank.shape[0], rank.shape[1], -rank.shape[0], -rank.shape[1], -rank.low if finite else _LOW,
                rank.high if finite else _LOW]
    if rank.whole_image is not None:
        head[6:9] = rank.whole_image.GetDimensions()
    if plan is not None and len(plan.layers) <= _MAX_LEVELS:
        head[11] = len(plan.layers)
        for index, (layer, (volume_level, _)) in enumerate(zip(plan.layers, rank.sampling)):
            head[12 + 3 * index: 15 + 3 * index] = (layer.grid[0], layer.grid[1], volume_level)
    head[9] = 1.0 if rank.problem else 0.0
    head[10] = float(params["number_of_levels"]) if params is not None else _LOW
    head[-1] = 1.0 if rank.missing else 0.0
    head[-2] = 1.0 if params is not None and _is_demip(params["method"]) else 0.0
    if plan is not None and rank.tolerance > 0 and len(plan.layers) > 1:  # the layer the structure bound joins
        source = content_adaptive.structure_source(plan)
        head[-3] = float(source) if source is not None else _LOW
    head = reduce(head, "max")
    if head[0] != -head[2] or head[1] != -head[3]:
        return f"the ranks' viewports differ ({int(head[0])}x{int(head[1])} vs {int(-head[2])}x{int(-head[3])})"
    if head[9] > 0.0:
        return rank.problem or "a rank refused or failed to plan the foveated frame"
    if head[11] <= 0.5 * _LOW:
        return "no rank has data"
    rank.low_global, rank.high_global, rank.missing = float(-head[4]), float(head[5]), bool(head[-1] > 0.0)
    if not rank.high_global >= rank.low_global:
        return "no rank has finite data"
    if rank.missing and head[-3] > 0.5 * _LOW:  # (every rank returns here: the same head)
        return MISSING_ADAPTIVE
    rank.whole_dims = tuple(int(v) for v in head[6:9])
    rank.layers = [tuple(int(v) for v in head[12 + 3 * i: 15 + 3 * i]) for i in range(int(head[11]))]
    rank.number_of_levels = int(head[10])
    rank.demip = bool(head[-2] > 0.0)
    rank.bound_source = int(head[-3]) if head[-3] > 0.5 * _LOW else None
    return None


def _reduce_coarse_levels(rank, reduce: Reduce) -> None:
    """2: the whole volume's coarse levels the layers read (``rank.coarse_levels``): this piece's share of each
    (:func:`partial_pyramid`) reduced with MAX over the ranks."""
    rank.coarse_levels = {}
    coarse_dims = whole_coarse_dims(rank.whole_dims, rank.number_of_levels)
    needed = max([v for _, _, v in rank.layers] + [0])
    if needed <= 0:
        return
    share = []
    if rank.usable and rank.values0 is not None and rank.problem is None:
        try:
            extent, whole = rank.piece.GetExtent(), rank.whole_stub[0]
            offset = (extent[0] - whole[0], extent[2] - whole[2], extent[4] - whole[4])
            # a missing voxel loses to every finite one (the fill lies below them all): a coarse point of
            # missing voxels only stays missing, as the one process's pyramid has it
            share = partial_pyramid(np.where(np.isnan(rank.values0), _MISSING, rank.values0.astype(np.float64)),
                                    offset, rank.whole_dims, needed + 1)
        except Exception as error:  # noqa: BLE001  (reported; the collectives still run)
            rank.problem, share = repr(error), []
    buffers = []
    for level in range(1, needed + 1):
        nx, ny, nz = coarse_dims[level - 1]
        full = np.full((nz, ny, nx), _LOW)
        if len(share) >= level:
            (ox, oy, oz), part = share[level - 1]
            z, y, x = part.shape
            full[oz:oz + z, oy:oy + y, ox:ox + x] = np.where(np.isfinite(part), part, _LOW)
        buffers.append(full.ravel())
    reduced = reduce(np.concatenate(buffers), "max")
    if not rank.usable or rank.problem is not None:
        return
    try:
        whole_image = rank.whole_image
        spacing, dims = list(whole_image.GetSpacing()), list(rank.whole_dims)
        name = rank.piece.GetPointData().GetScalars().GetName() or "scalars"
        at = 0
        for level in range(1, needed + 1):
            nx, ny, nz = coarse_dims[level - 1]
            values = reduced[at:at + nx * ny * nz].reshape(nz, ny, nx)
            # a coarse point no rank covered (pieces that do not cover the whole): the lowest value;
            # one of missing voxels only: missing (its level's mapper fills it, as on one process)
            values = np.where(values <= 0.5 * _LOW, rank.low_global,
                              np.where(values <= 0.5 * _MISSING, np.nan, values))
            at += nx * ny * nz
            spacing = [s * ((f - 1) / (n - 1) if n > 1 else 1.0) for s, f, n in zip(spacing, dims, (nx, ny, nz))]
            dims = [nx, ny, nz]
            rank.coarse_levels[level] = _image_of(values, first_point(whole_image), spacing,
                                                  whole_image.GetDirectionMatrix(), rank.values0.dtype, name)
    except Exception as error:  # noqa: BLE001
        rank.problem = repr(error)


def _level_entry(rank, volume, index: int, volume_level: int, kind) -> tuple:
    """(entry, rays): layer ``index``'s private brick mapper of ``kind`` on this rank's share of its volume (the
    piece, or the whole coarse level), set up, and the rays' geometry."""
    from mipcast.mappers import foveated_levels
    from mipcast.mappers.brick_rays import placed
    from mipcast.mappers.bricks import extract_brick

    layer, distance, piece, state = rank.plan.layers[index], rank.sampling[index][1], rank.piece, rank.state
    if volume_level == 0:
        dims = piece.GetDimensions()
        stamp = (piece.GetAddressAsString("vtkObjectBase"), piece.GetMTime())
        cached = state.get("rank_foveated_piece")
        if cached is None or cached[0] != stamp:
            cached = (stamp, extract_brick(piece, (0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)))
            state["rank_foveated_piece"] = cached
        image, extent, whole, rays = cached[1], tuple(piece.GetExtent()), rank.whole_stub[0], rank.whole_image
        component = rank.mapper.GetComponent()
    else:
        image = rank.coarse_levels[volume_level]
        extent = whole = tuple(image.GetExtent())
        rays, component, stamp = image, -1, image.GetAddressAsString("vtkObjectBase")
    rays = placed(rays, volume.GetMatrix())  # the rays where the volume's matrix puts the level
    key = ((index, kind), stamp, extent, tuple(whole), kind, volume_level)
    entry = _source_entry(state, key, kind, image, extent, whole, distance)
    brick_mapper, brick_volume = entry["mapper"], entry["volume"]
    if brick_mapper.GetComponent() != component:
        brick_mapper.SetComponent(component)
    foveated_levels.copy_settings(rank.mapper, volume, brick_mapper, brick_volume, entry["matrix"], distance,
                                  layer.image_sample_distance)
    # this rank's piece fills its missing values as the whole volume (a coarse level is whole)
    brick_mapper.GetInputPreparer().SetWholeRange((rank.low_global, rank.high_global)
                                                  if rank.missing and volume_level == 0 else None)
    foveated_levels.set_uniforms(brick_volume, rank.plan, layer)
    foveated_levels.set_silhouette(brick_volume, rank.silhouette if len(rank.plan.layers) > 1 else None,
                                   layer.level)
    return entry, rays


def _read_levels(rank, volume, renderer, reduce: Reduce) -> Optional[str]:
    """3: each level's readout of this rank's share of its rays and the texels where this rank's piece may put
    structure above the floor that the coarse rays missed, reduced with MAX (``rank.values``, ``rank.bound``,
    ``rank.entries``); why the frame cannot be drawn (the same on every rank), or None."""
    from mipcast.mappers import foveated_levels, foveated_masks
    from mipcast.mappers.brick_rays import box_in_view
    from mipcast.mappers.rank_composite import _clear_depth

    rank.silhouette, rank.entries = None, {}
    if rank.usable and rank.problem is None:
        try:
            rank.silhouette = foveated_levels.silhouette(rank.whole_image, volume, rank.camera, rank.viewport,
                                                         float(rank.mapper.GetImageSampleDistance()))
            _clear_depth(renderer)  # the rays end at the depth they find: the last frame's, before this one
        except Exception as error:  # noqa: BLE001
            rank.problem = repr(error)
    size = (rank.shape[1], rank.shape[0])
    layer_values = []
    for index, (columns, rows, volume_level) in enumerate(rank.layers):
        local = np.full((rows, columns), np.nan)
        if rank.usable and rank.problem is None:
            try:  # DEMIP: its phase 1
                kind = MIPVolumeMapper if rank.demip else FOVEATION_LAYERS[rank.params["method"]].factory
                entry, rays = _level_entry(rank, volume, index, volume_level, kind)
                if box_in_view(entry["volume"], renderer, (rows, columns)):
                    rank.entries[index] = entry
                    local = _readout(renderer, entry, rays, rank.camera, (rows, columns), size)
            except Exception as error:  # noqa: BLE001
                rank.problem = repr(error)
        layer_values.append(np.where(np.isnan(local), _LOW, local).ravel())
    bound_part = []
    if rank.bound_source is not None:
        columns, rows, _ = rank.layers[rank.bound_source]
        local = np.zeros((rows, columns))
        if rank.usable and rank.problem is None:
            try:
                above = foveated_masks.above_floor_boxes(rank.state, rank.piece, volume, rank.values0,
                                                         (rank.low_global, rank.high_global), rank.whole_dims)
                local = foveated_masks.structure_texels(rank.state, rank.plan, rank.bound_source, rank.piece, volume,
                                                        rank.camera, rank.viewport, above) * 1.0
            except Exception as error:  # noqa: BLE001
                rank.problem = repr(error)
        bound_part = [local.ravel()]
    flag = np.array([1.0 if rank.problem else 0.0])
    reduced = reduce(np.concatenate(layer_values + bound_part + [flag]), "max") if rank.layers else flag
    if reduced[-1] > 0.0:
        return rank.problem or "a rank failed to render its piece"
    rank.values, at = {}, 0
    for index, (columns, rows, _) in enumerate(rank.layers):
        level_values = reduced[at:at + rows * columns].reshape(rows, columns)
        at += rows * columns
        rank.values[index] = np.where(level_values <= 0.5 * _LOW, np.nan, level_values)
    rank.bound = None
    if rank.bound_source is not None:
        columns, rows, _ = rank.layers[rank.bound_source]
        rank.bound = (rank.bound_source, reduced[at:at + rows * columns].reshape(rows, columns) > 0.5)
    return None


def _finish(rank, volume, renderer, reduce: Reduce) -> Tuple[Optional[np.ndarray], Optional[str]]:
    """The DEMIP levels' second phase (every rank enters), then 4: the levels blended after compositing, as
    the GPU draws them (coarsest first, "over", weights, upscale)."""
    # the level volumes' scalar ranges (VTK's transfer-function textures span them): the whole volume's, the
    # reduced coarse levels' (with missing values: from the fill up, as their mappers prepare them)
    dtype = rank.values0.dtype if rank.values0 is not None else np.float64
    low_global, high_global = rank.low_global, rank.high_global
    whole_range = (missing_fill(low_global, high_global, "below", dtype)[0] if rank.missing else low_global,
                   high_global)
    ranges = [whole_range] * len(rank.layers)
    try:  # (a failure here must not keep this rank from the DEMIP levels' reduction)
        ranges = [_texture_range(rank.coarse_levels[v]) if v and rank.usable and rank.problem is None
                  else whole_range for _, _, v in rank.layers]
    except Exception as error:  # noqa: BLE001
        rank.problem = repr(error)
    colours, problem = None, rank.problem
    if rank.demip:  # phase 2 of each DEMIP level, then its colours (as bricked_foveated's DEMIP levels)
        colours, problem = _demip_levels(
            renderer, rank.layers, rank.values, rank.entries,
            lambda index, volume_level, kind: _level_entry(rank, volume, index, volume_level, kind),
            rank.camera, rank.shape, reduce, problem, ranges, rank.coarse_levels, volume, rank.sampling,
            rank.whole_image if rank.usable else None)
    if problem is not None:  # (after the last collective: this rank alone draws nothing, and says why)
        return None, problem
    if not rank.usable:
        return None, None  # a rank without data: it took part, it draws nothing
    plan, layers = rank.plan, rank.layers
    values = {layer.level: rank.values[index] for index, layer in enumerate(plan.layers)}
    if colours is not None:
        colours = {layer.level: colours[index] for index, layer in enumerate(plan.layers)}
    # 4: blended after compositing, as the GPU draws the levels (coarsest first, "over", weights, upscale)
    rank.state["rank_foveated_values"] = (plan, values, [volume_level for _, _, volume_level in layers])
    # the bounds whose projection covers the coarse levels' stretch beyond the outline (spill_bounds):
    # twice the coarsest texel, for the margin
    rank.state["rank_foveated_bounds"] = spill_bounds(
        rank.box.GetBounds(), rank.camera, rank.shape[0],
        2.0 * max(layer.image_sample_distance for layer in plan.layers))
    band = rank.silhouette if len(plan.layers) > 1 else None
    ranges = {layer.level: ranges[index] for index, layer in enumerate(plan.layers)}
    adaptive = ((rank.tolerance, _background(renderer), rank.bound)
                if rank.tolerance > 0 and len(plan.layers) > 1 else None)
    return blend_levels(plan, values, volume.GetProperty(), band, ranges, adaptive, colours), None


def _demip_levels(renderer, layers, values, entries, level_entry, camera, shape, reduce, problem, ranges,
                  coarse_levels, volume, sampling, whole_image):
    """DEMIP levels over the ranks: ({layer index: premultiplied RGBA}, None) or (None, why); every rank enters.

    ``values``: each layer's phase-1 maximum, reduced (MAX); ``ranges``: each
    layer's level texture's scalar range (its material window's span, as a
    DEMIP level mapper's on one process: the fill included).  Phase 2 on
    each level's grid: the whole-ray index of the first sample of that
    maximum's material on this rank's share (:class:`~mipcast.mappers.demip_brick.DEMIPBrickDepthMapper`,
    casting only the level's rays), reduced with MIN over the ranks and the
    levels at once; then depth, Eq. 1 and the colour sphere on the CPU
    (:func:`mipcast.mappers.demip_composite.demip_composite`, the level
    volume's box and sample distance, the viewport's aspect), as
    :func:`mipcast.mappers.bricked_demip.compose` composites a level beyond
    the texture limit.  DEMIP's settings are a DEMIP mapper's defaults (the
    foveated mapper passes none to its levels).
    """
    from mipcast.mappers.demip_brick import DEMIPBrickDepthMapper, bind_maximum, match_index
    from mipcast.mappers.demip_composite import demip_composite

    found = []
    for index, (columns, rows, volume_level) in enumerate(layers):
        local = np.full((rows, columns), np.inf)
        if index in entries and problem is None:
            try:
                entry, rays = level_entry(index, volume_level, DEMIPBrickDepthMapper)
                bind_maximum(renderer.GetRenderWindow(), entry["mapper"], values[index], ranges[index])
                local = match_index(_readout(renderer, entry, rays, camera, (rows, columns), (shape[1], shape[0]),
                                             raw=True))
            except Exception as error:  # noqa: BLE001  (reported; the collective still runs)
                problem = repr(error)
        found.append(np.where(np.isfinite(local), local, _HIGH).ravel())
    reduced = reduce(np.concatenate(found + [[-1.0 if problem else 0.0]]), "min")
    if reduced[-1] < 0.0:
        return None, problem or "a rank failed to render its piece"
    if whole_image is None:
        return None, None
    from mipcast.core.parameter_tables import DEMIP_SETTINGS

    params = {p.name: getattr(DEMIPBrickDepthMapper(), p.getter)() for p in DEMIP_SETTINGS}  # a DEMIP mapper's defaults
    colours, at = {}, 0
    for index, (columns, rows, volume_level) in enumerate(layers):
        index_values = reduced[at:at + rows * columns].reshape(rows, columns)
        at += rows * columns
        index_values = np.where(index_values >= 0.5 * _HIGH, np.inf, index_values)
        level = values[index].astype(np.float32).astype(np.float64)  # as the float readout carries the value
        geometry = whole_image if volume_level == 0 else coarse_levels[volume_level]
        base, alpha = gpu_lookup(level, volume.GetProperty(), ranges[index])  # the level's tables, as its GPU's
        _, rgb = demip_composite(geometry, camera, sampling[index][1], level, index_values, params,
                                 volume.GetProperty(), aspect=shape[1] / shape[0], base_rgb=base)  # no slab
        colours[index] = np.concatenate([rgb * alpha[..., None], alpha[..., None]], axis=-1)
    return colours, None


def _stretch(texels: np.ndarray, size) -> np.ndarray:
    """A level's 8-bit premultiplied RGBA grid (0 .. 255, top row first) over the viewport, as the GPU
    stretches VTK's image-sample framebuffer (GL linear filtering, clamped edges): texel coordinates in
    fixed point with 8 fraction bits, the lerps along x then y each rounded to 8 bits (llvmpipe's
    filtering of 8-bit textures; rays without a value are transparent)."""
    width, height = int(size[0]), int(size[1])
    rows, columns = texels.shape[:2]
    if (rows, columns) == (height, width):
        return texels
    grid = np.asarray(texels[::-1], dtype=np.int64)  # bottom row first, like GL

    def coordinates(n, m):
        fixed = np.floor(((np.arange(n) + 0.5) * m / n - 0.5) * 256.0).astype(np.int64)
        return fixed >> 8, fixed & 255

    x0, fx = coordinates(width, columns)
    y0, fy = coordinates(height, rows)

    def texel(y, x):
        return grid[np.clip(y, 0, rows - 1)][:, np.clip(x, 0, columns - 1)]

    def lerp(a, b, weight):
        return a + (((b - a) * weight + 128) >> 8)

    below = lerp(texel(y0, x0), texel(y0, x0 + 1), fx[None, :, None])
    above = lerp(texel(y0 + 1, x0), texel(y0 + 1, x0 + 1), fx[None, :, None])
    return lerp(below, above, fy[:, None, None])[::-1].astype(np.float64)


def blend_levels(plan, values: dict, volume_property, silhouette=None, ranges: Optional[dict] = None,
                 adaptive: Optional[tuple] = None, colours: Optional[dict] = None) -> np.ndarray:
    """The foveated picture (premultiplied RGBA, top row first) from each level's composited values.

    What the GPU draws (shaders/foveated_weight.glsl): coarsest level first,
    each ray's premultiplied colour times its level weight (1 in level 0's
    silhouette band), the level's grid stretched over the viewport (VTK's
    image-sample quad) and drawn "over" the levels before.  The GPU's arithmetic
    is mirrored: the colours looked up in VTK's transfer-function textures
    (:func:`gpu_colour`, over ``ranges[level]``, the level volume's scalar
    range; default the colour function's range), the rays written to an
    8-bit target (VTK's image-sample framebuffer for a reduced level, then
    stretched with 8-bit linear filtering: :func:`_stretch`) and blended in
    8 bits, as the window's framebuffer blends.  On one rank this is the
    GPU's picture bit for bit (tests/test_rank_foveated.py).

    ``adaptive``: (content tolerance, background RGB 0 .. 255[, (layer index,
    the data's structure bound of that layer's texels)]) of a
    content-adaptive frame (``plan`` from :func:`mipcast.core.content_adaptive.adaptive_plan`):
    each finer level keeps only the rays its refinement mask casts
    (:func:`mipcast.core.content_adaptive.refinement_mask` of the deciding
    level's picture over the background, and the background: the
    definition the GPU's refine pass evaluates), and level 0 its
    silhouette band, as ``shaders/foveated_skip_coarse.glsl`` casts them.
    ``colours``: {level: premultiplied float RGBA} of levels whose colour is
    not their value's (DEMIP's), drawn instead of :func:`gpu_colour`.

    >>> plan = foveation.plan_frame((0, 0, 8, 8), (0.5, 0.5), 10.0, 0.2)   # one level: the fovea covers all
    >>> from mipcast.offscreen import grey_property
    >>> rgba = blend_levels(plan, {0: np.full((8, 8), 1.0)}, grey_property((0.0, 1.0)))
    >>> rgba.shape, float(rgba[4, 4, 0])
    ((8, 8, 4), 1.0)
    """
    _, _, width, height = plan.viewport
    out = np.zeros((height, width, 4))
    masks, tests = {}, {}
    for index, layer in enumerate(plan.layers):  # coarsest first
        if adaptive is not None and index >= 1:  # the mask from the deciding level's picture
            source = content_adaptive.decided_by(plan, index)
            if source == index - 1:  # just drawn: its refinement test
                tolerance, background, bound = (tuple(adaptive) + (None,))[:3]
                below = np.broadcast_to(np.asarray(background, dtype=np.float64), (height, width, 3))
                after = np.minimum(out[..., :3] + _times_8bit(below, 255.0 - out[..., 3:4]), 255.0)
                grid = plan.layers[source].grid
                edge, structure = content_adaptive.refinement_test(content_adaptive.coarse_texels(after, grid),
                                                                   content_adaptive.coarse_texels(below, grid),
                                                                   tolerance)
                if bound is not None and bound[0] == source:  # the data's bound on structure the rays missed
                    structure = structure | bound[1]
                tests[source] = edge, structure
            masks[layer.level] = content_adaptive.refinement_mask(*tests[source], plan, layer)
        level_values = values.get(layer.level)
        if level_values is None:
            continue
        if layer.level in masks:  # the rays not cast show the coarser levels through
            cast = masks[layer.level]
            if silhouette is not None and layer.level == 0:
                cast = cast | foveation.silhouette_band(plan, silhouette, layer.grid)
            level_values = np.where(cast, level_values, np.nan)
        if colours is not None and layer.level in colours:
            rgba = np.where(np.isfinite(level_values)[..., None], colours[layer.level], 0.0)
        else:
            rgba = gpu_colour(level_values, volume_property, (ranges or {}).get(layer.level))
        lam = foveation.desired_level(foveation.eccentricity(layer.grid, plan.gaze, plan.aspect), plan)
        weight = foveation.layer_weight(layer.level, lam, plan)
        if silhouette is not None and layer.level == 0:
            weight = np.where(foveation.silhouette_band(plan, silhouette, layer.grid), 1.0, weight)
        rgba = rgba * weight[..., None]
        if layer.level in masks:  # a cast ray is drawn over the background, not the coarser levels
            below = np.asarray(adaptive[1], dtype=np.float64) / 255.0  # (shaders/foveated_paint_beneath.glsl)
            painted = np.concatenate([rgba[..., :3] + (weight - rgba[..., 3])[..., None] * below,
                                      weight[..., None]], axis=-1)
            rgba = np.where(np.isfinite(level_values)[..., None], painted, rgba)
        # the level's rays are written to an 8-bit target: VTK's image-sample framebuffer for a reduced
        # grid (then stretched over the viewport), else the window's; blended "over" in 8 bits
        drawn = _stretch(_to_8bit(rgba), (width, height))
        out = np.minimum(drawn + _times_8bit(out, 255.0 - drawn[..., 3:4]), 255.0)
    cover = (content_adaptive.outline_cover(plan, silhouette)
             if adaptive is not None and silhouette is not None else None)
    # the background over the deciding levels' stretch past the outline (foveated_masks.outline_cover)
    if cover is not None:
        (x0, y0, columns, rows), weight = cover
        patch = content_adaptive.cover_patch(weight, np.asarray(adaptive[1], dtype=np.float64))
        part = out[height - y0 - rows:height - y0, x0:x0 + columns]
        part[...] = np.minimum(patch + _times_8bit(part, 255.0 - patch[..., 3:4]), 255.0)
    return (out / 255.0).astype(np.float32)


def _times_8bit(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The product of 8-bit normalised values (0 .. 255), rounded as an 8-bit target blends."""
    return np.floor(a * b / 255.0 + 0.5)


def _to_8bit(rgba: np.ndarray) -> np.ndarray:
    """A float colour written to an 8-bit target: clamped, rounded to the nearest of 0 .. 255."""
    return np.floor(np.clip(rgba, 0.0, 1.0) * 255.0 + 0.5)


#: VTK's transfer-function textures: at least this many texels (vtkOpenGLVolumeLookupTable), at most this.
_TABLE_MIN, _TABLE_MAX = 1024, 16384


def _table_width(function, low: float, high: float) -> int:
    return int(min(max(_TABLE_MIN, function.EstimateMinNumberOfSamples(low, high)), _TABLE_MAX))


def gpu_colour(values: np.ndarray, volume_property, value_range=None) -> np.ndarray:
    """Data values -> premultiplied RGBA as mipcast's colour pieces look them up in VTK's tables; NaN: transparent.

    VTK tabulates component 0's colour and scalar-opacity functions at
    ``width`` points ``low + i (high - low) / (width - 1)`` (``GetTable``;
    ``width`` at least 1024) into float textures; mipcast's pieces read them,
    linearly filtered, where the table holds ``u = (value - low) / (high -
    low)``: at texel ``u (width - 1)`` (``mcAtTable``, shaders/mip_globals.glsl;
    VTK's own lookups read at texel ``u width - 1/2``, up to half a table step
    off), which this reproduces. ``value_range``: (low, high), the level
    volume's scalar range; default the colour function's range.

    >>> from mipcast.offscreen import grey_property
    >>> gpu_colour(np.array([[0.0, 0.5, np.nan]]), grey_property((0.0, 1.0)))[0, :, 0].round(3).tolist()
    [0.0, 0.5, 0.0]
    """
    rgb, alpha = gpu_lookup(values, volume_property, value_range)
    out = np.zeros(np.shape(values) + (4,))
    out[..., :3] = rgb * alpha[..., None]
    out[..., 3] = alpha
    return out


def gpu_lookup(values: np.ndarray, volume_property, value_range=None) -> Tuple[np.ndarray, np.ndarray]:
    """(straight RGB, opacity) at ``values`` as VTK's transfer-function textures give them (:func:`gpu_colour`);
    0 where NaN.

    >>> from mipcast.offscreen import grey_property
    >>> rgb, alpha = gpu_lookup(np.array([0.5, np.nan]), grey_property((0.0, 1.0)))
    >>> rgb[:, 0].round(3).tolist(), alpha.round(3).tolist()
    ([0.5, 0.0], [1.0, 0.0])
    """
    values = np.asarray(values, dtype=np.float64)
    hit = np.isfinite(values)
    rgb_out, alpha_out = np.zeros(values.shape + (3,)), np.zeros(values.shape)
    if not hit.any():
        return rgb_out, alpha_out
    rgb_function = volume_property.GetRGBTransferFunction(0)
    opacity_function = volume_property.GetScalarOpacity(0)
    low, high = (float(v) for v in (value_range if value_range is not None else rgb_function.GetRange()))
    if not high > low:
        high = low + 1.0

    def lookup(table, texels):
        t = np.clip((values[hit] - low) / (high - low) * (texels - 1.0), 0.0, texels - 1.0)
        i = np.minimum(np.floor(t).astype(int), max(texels - 2, 0))
        f = (t - i)[:, None]
        return table[i] * (1.0 - f) + table[np.minimum(i + 1, texels - 1)] * f

    texels = _table_width(rgb_function, low, high)
    rgb_table = np.zeros(texels * 3)
    rgb_function.GetTable(low, high, texels, rgb_table)
    rgb = lookup(rgb_table.reshape(texels, 3), texels)
    texels = _table_width(opacity_function, low, high)
    opacity_table = np.zeros(texels)
    opacity_function.GetTable(low, high, texels, opacity_table)
    rgb_out[hit] = rgb
    alpha_out[hit] = lookup(opacity_table[:, None], texels)[:, 0]
    return rgb_out, alpha_out


def _readout(renderer, entry, rays, camera, shape, size, raw: bool = False) -> np.ndarray:
    """One float readout (data units, NaN: none; ``raw``: as written) of a level's brick on ``shape``'s grid,
    the whole's rays."""
    from mipcast.mappers import bricked_draw
    from mipcast.mappers.brick_rays import push_whole_rays

    brick_mapper, brick_volume = entry["mapper"], entry["volume"]
    draw_for(brick_mapper, camera, renderer)
    push_whole_rays(brick_volume, brick_mapper.GetSampleDistance(), rays, camera, size)
    object_state(brick_mapper)["exact_readout"] = True
    brick_mapper.RenderToImageOn()
    brick_mapper.SetDepthImageScalarTypeToFloat()
    gl = renderer.GetRenderWindow().GetState()
    gl.Push()
    try:
        brick_volume.RenderVolumetricGeometry(renderer)
        return bricked_draw.brick_readout(brick_mapper, shape, raw=raw)
    finally:
        gl.Pop()
        object_state(brick_mapper).pop("exact_readout", None)
        brick_mapper.RenderToImageOff()
