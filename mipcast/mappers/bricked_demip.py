"""DEMIP of a volume beyond the 3D texture limit, drawn in bricks inside the user's render.

:mod:`mipcast.mappers.bricked_draw` draws MIP and MinIP beyond the limit by
the maximum / minimum of the bricks' readouts.  DEMIP (``demip``,
``demip_two_pass``: ``BRICKS = "demip"``) needs more than a maximum: the
depth of the first sample of the maximum's material along the WHOLE ray.
It is composited here exactly as :mod:`mipcast.distributed` composites it
over MPI ranks, with every brick local:

1. phase 1: every brick (same extents as :mod:`mipcast.mappers.bricked_draw`,
   the whole volume's samples through the ``global_phase`` piece) renders
   its sampled MIP into a float readout; their MAX is the whole ray's maximum;
2. phase 2: that maximum goes back to every brick as a float texture, and
   :class:`mipcast.mappers.demip_brick.DEMIPBrickDepthMapper` reads out the
   whole-ray index of the brick's first sample of the maximum's material;
   their MIN is the whole ray's first same-material sample;
3. depth (over the whole box, the mapper's depth mode), Eq. 1, the colour
   sphere and chromadepth on the CPU
   (:func:`mipcast.mappers.demip_composite.demip_composite`), and the
   premultiplied picture is drawn over the renderer's viewport as
   :mod:`mipcast.mappers.bricked_draw` draws its own.

A slab (``slab_thickness`` > 0) clips every brick's part of the whole ray
to the same global slab (the clipping uniforms of each brick's own texture
space, :func:`mipcast.mappers.clip_uniforms.copy_clipping`), and the depth
is normalised over the box's part inside the slab on the CPU
(:func:`mipcast.mappers.demip_composite.demip_composite`'s ``slab``).

The projections that depend on the order along the ray draw their bricks
front to back (:func:`mipcast.mappers.brick_rays.visibility_order`), each
brick continuing the single texture's scan from a per-pixel state the
bricks in front left, handed to it as a float texture
(:mod:`mipcast.mappers.demip_ordered_bricks`): LMIP (the running maximum;
its phase 2 is MIP's), attenuated MIP (the crossed material; no phase 2)
and MIDA (running material and opacity; its picture only, its float
readout is the MAX of phase 1).  That texture's alpha is the scene depth,
so their rays end at opaque geometry where the whole volume's ray ends
(``whole_ray_end``).  Missing values: every brick fills them as the whole
volume (:func:`mipcast.mappers.input_preparer.piece_range`); attenuated
MIP's and MIDA's bricks have no missing test of their own, the whole ray's
is applied here (the attenuated value; MIDA's sampled maximum, phase 1's
MAX).  :func:`problem` names what cannot be
drawn in bricks (nothing of DEMIP's now; kept for the callers).  During a
float readout the mapper's ``GetDepthImage`` returns the bricked value
(readout ``"value"``) or depth (``"depth"``).

Examples
--------
>>> from mipcast.mappers.demip import DEMIPVolumeMapper
>>> problem(DEMIPVolumeMapper(), 20) is None
True
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.object_state import object_state
from mipcast.core.parameter_tables import DEMIP_SETTINGS
from mipcast.mappers import clip_uniforms, float_readout
from mipcast.mappers.brick_rays import (box_in_view, brick_entry, cached_bricks, nearest_interpolation, placed,
                                       push_rays, whole_of)
from mipcast.mappers.bricked_draw import seen
from mipcast.mappers.demip_brick import DEMIPBrickDepthMapper, bind_maximum, match_index
from mipcast.mappers.demip_composite import demip_composite, demip_premultiplied
from mipcast.mappers.input_preparer import piece_range
from mipcast.mappers.outline_rays import scene_depth
from mipcast.mappers.private_draw import auto_sample_distance, follow_volume
from mipcast.mappers.stereo import draw_for


#: The projections DEMIP composites in bricks: "mip" (MAX of the bricks), "lmip" (the bricks front to back,
#: :mod:`mipcast.mappers.demip_ordered_bricks`).
PROJECTIONS = ("mip", "lmip", "attenuated", "mida")


def problem(mapper, limit: int) -> Optional[str]:
    """Why ``mapper``'s DEMIP settings cannot be drawn in bricks of ``limit`` points, or None.

    Examples
    --------
    >>> from mipcast.mappers.demip import DEMIPVolumeMapper
    >>> mapper = DEMIPVolumeMapper()
    >>> mapper.SetProjection("mida"); mapper.SetSlabThickness(5.0)
    >>> problem(mapper, 20) is None   # every projection, with or without a slab
    True
    """
    projection = mapper.GetProjection()
    if projection not in PROJECTIONS:
        return (f"the volume exceeds this GPU's 3D texture limit of {limit} points per axis, and DEMIP in "
                f"bricks composites projection 'mip' only, got {projection!r} (LMIP, attenuated MIP and MIDA "
                "depend on the order along the whole ray): set projection 'mip', or resample the volume to "
                f"at most {limit} points per axis (e.g. vtkImageResample)")
    return None


def _whole(image, volume) -> vtkImageData:
    """A scalar-less image with the whole volume's geometry as ``volume``'s matrix places it (rays, depth box)."""
    return whole_of(image, volume.GetMatrix())


def bricks_of(mapper, limit: int, kinds=None) -> list:
    """Per brick: a phase-1 MIP entry and a phase-2 depth entry (mapper, volume, matrix, extent).

    ``kinds``: a function of a brick mapper class giving the class the
    bricks use instead (a foveated level's bricks cast only its rays,
    :func:`mipcast.mappers.bricked_foveated.source_class`); the mapper's
    state keeps one set of bricks, so one mapper always passes the same.
    """
    from mipcast.mappers.mip import MIPVolumeMapper

    adapt = kinds or (lambda kind: kind)

    def make(piece, extent, whole):
        return tuple(brick_entry(adapt(kind), piece, extent, whole, piece.GetSpacing(), mapper.GetSampleDistance())
                     for kind in (MIPVolumeMapper, DEMIPBrickDepthMapper))
    return cached_bricks(mapper, limit, "demip_bricks", make)


#: The ordered projections' brick mappers (:mod:`mipcast.mappers.demip_ordered_bricks`) and the
#: uniforms besides ``u_mc_brickChannel`` (0) they start with.
_ORDERED_BRICKS = {"lmip": ("LMIPBrickMapper", {"u_mc_brickLocal": 1.0e30}),
                   "attenuated": ("AttenuatedBrickMapper", {"u_mc_brickWindow": [0.0, 1.0, 0.0, 0.0]}),
                   "mida": ("MIDABrickMapper", {"u_mc_brickWindow": [0.0, 1.0, 0.0, 0.0]})}


def ordered_bricks_of(mapper, limit: int, projection: str) -> list:
    """Per brick: the entry of ``projection``'s brick mapper ("lmip", "attenuated" or "mida"), drawn front to back."""
    def make(piece, extent, whole):
        return ordered_brick_entry(projection, piece, extent, whole, mapper.GetSampleDistance())
    return cached_bricks(mapper, limit, f"demip_{projection}_bricks", make)


def ordered_brick_entry(projection: str, piece, extent, whole, sample_distance: float) -> dict:
    """A brick entry (:func:`mipcast.mappers.brick_rays.brick_entry`) of ``projection``'s brick mapper.

    ``projection``: "lmip", "attenuated" or "mida"; ``piece`` the brick's
    image (extent from 0), ``extent`` its place in the ``whole`` extent.
    Also a rank's piece in :mod:`mipcast.mappers.rank_ordered`.
    """
    from mipcast.mappers import demip_ordered_bricks

    name, start = _ORDERED_BRICKS[projection]
    entry = brick_entry(getattr(demip_ordered_bricks, name), piece, extent, whole, piece.GetSpacing(),
                        sample_distance)
    uniforms = entry["volume"].GetShaderProperty().GetFragmentCustomUniforms()
    uniforms.SetUniformf("u_mc_brickChannel", 0.0)
    for uniform, value in start.items():
        if isinstance(value, list):
            uniforms.SetUniform4f(uniform, value)
        else:
            uniforms.SetUniformf(uniform, value)
    return entry


def follow_demip_brick(mapper, volume, entry, distance: float, demip: bool,
                       image_sample_distance: float = 1.0) -> None:
    """The brick's mapper as the user's: DEMIP's settings (phase 2), sampling, cropping, clipping, matrix.

    ``image_sample_distance``: the brick's rays (1: one per pixel; a foveated level's coarser grid).
    """
    brick_mapper = entry["mapper"]
    if demip:
        for parameter in DEMIP_SETTINGS:
            value = getattr(mapper, parameter.getter)()
            if getattr(brick_mapper, parameter.getter)() != value:
                getattr(brick_mapper, parameter.setter)(value)
    if brick_mapper.GetComponent() != mapper.GetComponent():
        brick_mapper.SetComponent(mapper.GetComponent())
    brick_mapper.GetInputPreparer().SetWholeRange(piece_range(mapper.GetInputPreparer()))  # the whole's fill
    brick_mapper.SetAutoAdjustSampleDistances(False)
    brick_mapper.SetUseJittering(False)
    if brick_mapper.GetSampleDistance() != distance:
        brick_mapper.SetSampleDistance(distance)
    if brick_mapper.GetImageSampleDistance() != image_sample_distance:
        brick_mapper.SetImageSampleDistance(image_sample_distance)
    follow_volume(mapper, volume, brick_mapper, entry["volume"], entry["matrix"])
    clip_uniforms.copy_clipping(mapper, brick_mapper)


def _render(renderer, entry, mapper, camera, shape, raw: bool = False, size=None) -> np.ndarray:
    """One brick's float readout (normalised as the shader wrote it, NaN: none), top row first.

    ``raw``: the readout's float32 values as written (1.0, the clear value, where no ray was cast).
    ``size``: the viewport's (width, height) when ``shape`` is a coarser ray grid (its aspect).
    """

    brick_mapper, brick_volume = entry["mapper"], entry["volume"]
    draw_for(brick_mapper, camera, renderer)
    push_rays(mapper, entry, camera, shape, size)
    object_state(brick_mapper)["exact_readout"] = True
    brick_mapper.RenderToImageOn()
    brick_mapper.SetDepthImageScalarTypeToFloat()
    try:
        brick_volume.RenderVolumetricGeometry(renderer)
        image = vtkImageData()
        brick_mapper.GetDepthImage(image)
    finally:
        object_state(brick_mapper).pop("exact_readout", None)
        brick_mapper.RenderToImageOff()
    from vtkmodules.util.numpy_support import vtk_to_numpy

    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        return np.full(shape, np.nan)
    columns, rows, _ = image.GetDimensions()
    found = vtk_to_numpy(scalars).reshape(rows, columns)[::-1]
    found = np.array(found, dtype=np.float32) if raw else float_readout.decode(found)
    if found.shape != shape:
        raise RuntimeError(f"a brick's readout is {found.shape}, the viewport {shape}")
    return found


def _front_to_back(mapper, volume, limit, camera, shape, entries, in_view, ordered, size=None) -> list:
    """The ``ordered`` entries (one per brick, as ``entries``) of the bricks in view, front to back."""
    from mipcast.mappers.brick_rays import ray_uniforms, visibility_order

    seen = {id(first) for first, _ in in_view}
    visible = [i for i, (first, _) in enumerate(entries) if id(first) in seen]
    rays = ray_uniforms(_whole(mapper.GetInput(), volume), camera, (shape[1], shape[0]) if size is None else size)
    return [ordered[visible[p]] for p in visibility_order([ordered[i]["extent"] for i in visible], rays)]


def _attenuated_scan(mapper, volume, renderer, limit, camera, shape, distance, entries, in_view, data_range,
                     isd: float = 1.0, size=None, scene=None):
    """Attenuated MIP over the bricks in view front to back (data units, NaN: miss).

    ``scene``: the scene depth per ray (:func:`mipcast.mappers.outline_rays.scene_depth`) the bricks' rays end
    at, in their state texture's alpha (None: the far plane); the same for the other scans.
    """
    from mipcast.mappers.demip_ordered_bricks import attenuated_value, bind_crossed

    crossed = np.zeros(shape, dtype=np.float32)
    best = np.full(shape, np.nan)
    window = renderer.GetRenderWindow()
    for entry in _front_to_back(mapper, volume, limit, camera, shape, entries, in_view,
                                ordered_bricks_of(mapper, limit, "attenuated"), size):
        follow_demip_brick(mapper, volume, entry, distance, demip=True, image_sample_distance=isd)
        bind_crossed(window, entry["mapper"], crossed, data_range, scene)
        uniforms = entry["volume"].GetShaderProperty().GetFragmentCustomUniforms()
        found = _render(renderer, entry, mapper, camera, shape, raw=True, size=size)
        uniforms.SetUniformf("u_mc_brickChannel", 1.0)
        try:
            after = _render(renderer, entry, mapper, camera, shape, raw=True, size=size)
        finally:
            uniforms.SetUniformf("u_mc_brickChannel", 0.0)
        best = np.fmax(best, np.where(found == 1.0, np.nan, -found.astype(np.float64)))
        crossed = np.where(after == 1.0, crossed, -after).astype(np.float32)
    return attenuated_value(best, volume.GetProperty(), data_range)


def _mida_scan(mapper, volume, renderer, limit, camera, shape, distance, entries, in_view, data_range,
               isd: float = 1.0, size=None, scene=None):
    """MIDA's picture over the bricks in view front to back: premultiplied float RGBA (``scene``: as
    :func:`_attenuated_scan`'s)."""
    from mipcast.mappers.demip_ordered_bricks import MIDA_CHANNELS, bind_mida, mida_scan

    colour, opacity, material = np.zeros(shape + (3,)), np.zeros(shape), np.zeros(shape)
    window = renderer.GetRenderWindow()
    for entry in _front_to_back(mapper, volume, limit, camera, shape, entries, in_view,
                                ordered_bricks_of(mapper, limit, "mida"), size):
        follow_demip_brick(mapper, volume, entry, distance, demip=True, image_sample_distance=isd)
        bind_mida(window, entry["mapper"], material, opacity, data_range, scene)
        uniforms = entry["volume"].GetShaderProperty().GetFragmentCustomUniforms()
        readouts = {}
        try:
            for channel, name in enumerate(MIDA_CHANNELS):
                uniforms.SetUniformf("u_mc_brickChannel", float(channel))
                readouts[name] = _render(renderer, entry, mapper, camera, shape, raw=True, size=size)
        finally:
            uniforms.SetUniformf("u_mc_brickChannel", 0.0)
        mida_scan(colour, opacity, material, readouts)
    rgba = np.zeros(shape + (4,))
    rgba[..., :3] = np.clip(colour, 0.0, 1.0)
    rgba[..., 3] = np.clip(opacity, 0.0, 1.0)
    return rgba


def _lmip_scan(mapper, volume, renderer, limit, camera, shape, distance, entries, in_view, data_range,
               isd: float = 1.0, size=None, scene=None):
    """LMIP's phase 1: the bricks in view front to back, each continuing the scan (data units, NaN: miss;
    ``scene``: as :func:`_attenuated_scan`'s)."""
    from mipcast.mappers.demip_ordered_bricks import bind_running, local_threshold, scan

    local = local_threshold(volume.GetProperty(), data_range, mapper.GetLocalThreshold())
    running, ended = np.full(shape, np.nan), np.zeros(shape, dtype=bool)
    window = renderer.GetRenderWindow()
    for entry in _front_to_back(mapper, volume, limit, camera, shape, entries, in_view,
                                ordered_bricks_of(mapper, limit, "lmip"), size):
        follow_demip_brick(mapper, volume, entry, distance, demip=True, image_sample_distance=isd)
        bind_running(window, entry["mapper"], running, local, scene)
        uniforms = entry["volume"].GetShaderProperty().GetFragmentCustomUniforms()
        scalars = entry["mapper"].GetRenderedInput().GetPointData().GetScalars()
        found = _render(renderer, entry, mapper, camera, shape, size=size)
        brick_max = float_readout.to_data_units(np.where(np.abs(found) > 1.0e3, np.nan, found), scalars)
        uniforms.SetUniformf("u_mc_brickChannel", 1.0)
        try:
            brick_ended = _render(renderer, entry, mapper, camera, shape, size=size)
        finally:
            uniforms.SetUniformf("u_mc_brickChannel", 0.0)
        scan(running, ended, brick_max, brick_ended)
    return running


def _above_floor(values: np.ndarray, volume_property, data_range) -> np.ndarray:
    """Where the maximum (data units) is above the material window's floor: the rays with a DEMIP term.

    Phase 2's test on the maximum (``shaders/demip_brick_hooks.glsl``: above the
    floor by the floor tolerance of the window; none with constant transfer functions).
    """
    from mipcast.core.shading import FLOOR_TOLERANCE
    from mipcast.core.transfer_bounds import constant_ends

    floor, ceiling = constant_ends(volume_property, *data_range)
    if not ceiling > floor:
        return np.zeros(values.shape, dtype=bool)
    return np.nan_to_num(values, nan=-np.inf) > floor + FLOOR_TOLERANCE * (ceiling - floor)


def compose(mapper, volume, renderer, limit: int, image_sample_distance: float = 1.0, grid=None,
            kinds=None) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Both phases over every brick in view, then the CPU composite.

    ``image_sample_distance`` and ``grid`` (columns, rows): rays on a coarser
    grid than the viewport's pixels (VTK's reduced framebuffer of that image
    sample distance, the camera keeping the viewport's aspect; a foveated
    level, :mod:`mipcast.mappers.bricked_foveated`): the results then have
    ``grid``'s shape.  ``kinds``: the bricks' classes (:func:`bricks_of`).

    Returns
    -------
    values : numpy.ndarray, (height, width) of the viewport (or ``grid``'s rows, columns)
        The whole-ray maximum in data units (NaN: miss), top row first.
    depth : numpy.ndarray
        DEMIP's depth in [0, 1] (NaN: no DEMIP term).
    rgba : numpy.ndarray, (height, width, 4)
        The premultiplied picture, float.
    """

    reason = problem(mapper, limit)
    if reason is not None:
        raise ValueError(reason)
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    shape = (max(height[0], 1), max(width[0], 1))
    size = (shape[1], shape[0])  # the viewport's: the camera's aspect
    if grid is not None:
        shape = (int(grid[1]), int(grid[0]))
    isd = float(image_sample_distance)
    camera = renderer.GetActiveCamera()
    distance = mapper.GetSampleDistance()
    if mapper.GetAutoAdjustSampleDistances():
        distance = auto_sample_distance(mapper.GetInput(), volume)
    entries = bricks_of(mapper, limit, kinds)
    missing = bool(mapper.GetRenderedInput() is not None and mapper.GetInputPreparer().GetPrepared().missing)
    in_view = []
    values = np.full(shape, np.nan)
    empty = np.zeros(shape, dtype=bool)  # rays a brick drew without a sample (mipcast.mappers.outline_rays)
    drawn_any = np.zeros(shape, dtype=bool)  # rays a brick drew a fragment for
    for first, second in entries:  # phase 1: MAX of the bricks' sampled MIP
        follow_demip_brick(mapper, volume, first, distance, demip=False, image_sample_distance=isd)
        if not box_in_view(first["volume"], renderer, shape):
            continue
        in_view.append((first, second))
        if mapper.GetProjection() in ("lmip", "attenuated"):
            continue  # phase 1 of LMIP, attenuated MIP: the bricks front to back (below)
        if mapper.GetProjection() == "mida" and not object_state(mapper).get("exact_readout") and not missing:
            continue  # MIDA's picture needs no maximum (its compositing, below) unless rays may see no finite data
        found = _render(renderer, first, mapper, camera, shape, size=size)
        empty |= np.abs(np.nan_to_num(found)) > 1.0e3
        drawn_any |= ~np.isnan(found)
        scalars = first["mapper"].GetRenderedInput().GetPointData().GetScalars()
        brick = float_readout.to_data_units(np.where(np.abs(found) > 1.0e3, np.nan, found), scalars)
        values = np.fmax(values, brick)
    data_range = mapper.GetRenderedInput().GetPointData().GetScalars().GetRange(0)  # as the single texture's window
    completed = np.zeros(shape, dtype=bool)
    if mapper.GetProjection() == "mip" and in_view:  # the outline rays no brick could sample: one sample each
        from mipcast.mappers import outline_rays

        before = np.isnan(values)
        image = placed(mapper.GetRenderedInput(), volume.GetMatrix())  # the volume's matrix folded in
        values = seen(mapper, outline_rays.complete(values, empty, image, camera, size, distance,
                                                    undrawn=outline_rays.undrawn(mapper, renderer, drawn_any),
                                                    nearest=nearest_interpolation(volume)))
        completed = before & ~np.isnan(values)
    # the ordered projections' rays end at opaque geometry: the scene depth in their state texture's alpha
    scan = {"isd": isd, "size": size, "scene": scene_depth(renderer, shape) if mapper.GetProjection() != "mip" else None}
    if mapper.GetProjection() == "lmip":
        values = _lmip_scan(mapper, volume, renderer, limit, camera, shape, distance, entries, in_view, data_range,
                            **scan)
    elif mapper.GetProjection() == "attenuated":
        values = seen(mapper, _attenuated_scan(mapper, volume, renderer, limit, camera, shape, distance, entries,
                                               in_view, data_range, **scan))  # one texture's missing test
    values = values.astype(np.float32).astype(np.float64)  # as the float readout / MPI reduction carry it
    index = np.full(shape, np.inf)
    window = renderer.GetRenderWindow()
    for _, second in in_view if mapper.GetProjection() in ("mip", "lmip") else ():  # phase 2: MIN of the whole-ray index of the first same-material sample
        follow_demip_brick(mapper, volume, second, distance, demip=True, image_sample_distance=isd)
        bind_maximum(window, second["mapper"], values, data_range)
        index = np.minimum(index, match_index(_render(renderer, second, mapper, camera, shape, size=size)))
    if completed.any():  # their one sample is the maximum: the first of its material, if it has a DEMIP term
        index[completed & _above_floor(values, volume.GetProperty(), data_range)] = 0.0
    object_state(mapper)["bricks_drawn"] = len(in_view)
    params = {p.name: getattr(mapper, p.getter)() for p in DEMIP_SETTINGS}
    depth, rgb = demip_composite(_whole(mapper.GetInput(), volume), camera, distance, values, index, params,
                                 volume.GetProperty(), slab=clip_uniforms.slab_of(mapper, camera),
                                 aspect=size[0] / size[1])
    if mapper.GetProjection() == "mida":  # the picture: the bricks' compositing front to back
        if object_state(mapper).get("exact_readout"):
            return values, depth, None  # a float readout: MIDA's value is the sampled maximum (MAX above)
        rgba = _mida_scan(mapper, volume, renderer, limit, camera, shape, distance, entries, in_view, data_range,
                          **scan)
        # missing values: a ray whose maximum (the MAX above) saw no finite data draws nothing, as one texture's
        return values, depth, np.where(np.isnan(values)[..., None], 0.0, rgba) if missing else rgba
    return values, depth, demip_premultiplied(values, rgb, volume.GetProperty())


def face_picture(mapper, volume, renderer, rgba: np.ndarray, face, pixels: np.ndarray) -> np.ndarray:
    """DEMIP's premultiplied picture ``rgba`` with the ``pixels``' as the single texture's fragment of the box
    face ``face`` draws them (multisampling).

    The face's rays (:func:`mipcast.mappers.outline_rays.face_samples`: from
    where the pixel centre's ray crosses the face's plane, ended at opaque
    geometry, clipped) and their samples' projection as the float64
    reference finds it: the maximum (LMIP: of the samples up to the first
    fall below a running maximum above the local threshold) and its first
    same-material sample, then depth measured from the ray's start, Eq. 1
    and the sphere as for the composited rays
    (:func:`mipcast.mappers.demip_composite.demip_composite`); attenuated
    MIP's attenuated maximum; MIDA's composite of the transfer functions'
    colour and opacity (:func:`mipcast.mappers.demip_composite.mida_composite`).
    """
    from mipcast.core.transfer_bounds import constant_ends
    from mipcast.mappers import outline_rays
    from mipcast.mappers.demip_composite import mida_composite
    from mipcast.mappers.demip_ordered_bricks import local_threshold
    from mipcast.reference.demip import attenuated_maximum, local_maxima, same_material

    out = rgba.copy()
    if not pixels.any():
        return out
    distance = mapper.GetSampleDistance()
    if mapper.GetAutoAdjustSampleDistances():
        distance = auto_sample_distance(mapper.GetInput(), volume)
    camera, projection = renderer.GetActiveCamera(), mapper.GetProjection()
    image = placed(mapper.GetRenderedInput(), volume.GetMatrix())  # the volume's matrix folded in
    rows, columns, start, step, samples = outline_rays.face_samples(mapper, renderer, image, rgba.shape[:2], distance,
                                                                    face, pixels)
    data_range = mapper.GetRenderedInput().GetPointData().GetScalars().GetRange(0)  # as the single texture's window
    floor, ceiling = constant_ends(volume.GetProperty(), *data_range)
    window = ceiling > floor  # else no material anywhere: no DEMIP term, no attenuation, no MIDA fading
    params = {p.name: getattr(mapper, p.getter)() for p in DEMIP_SETTINGS}
    valid = np.isfinite(samples)
    if projection == "mida":  # a ray that saw no finite data (its maximum below the missing threshold): nothing
        shown = np.isfinite(seen(mapper, np.fmax.reduce(samples, axis=1)))[:, None]
        out[rows, columns] = np.where(shown, mida_composite(samples, valid, volume.GetProperty(), floor,
                                                            ceiling if window else np.inf), 0.0)
        return out
    if projection == "lmip":
        valid = local_maxima(samples, valid, local_threshold(volume.GetProperty(), data_range, mapper.GetLocalThreshold()))
    values, first = np.fmax.reduce(np.where(valid, samples, np.nan), axis=1), np.full(len(rows), -1)
    if projection == "attenuated" and window:
        decay = mapper.GetAttenuation() * distance / min(abs(v) for v in mapper.GetInput().GetSpacing())
        values = np.where(valid.any(axis=1), attenuated_maximum(samples, valid, floor, ceiling, decay), np.nan)
    elif window and projection != "attenuated":
        eps = params["material_threshold"] if params["depth_of"] == "same_material" else 0.0
        first = same_material(samples, valid, floor, ceiling, eps)[1]
    values = seen(mapper, values).astype(np.float32).astype(np.float64)  # as the GPU carries the value
    _, rgb = demip_composite(_whole(mapper.GetInput(), volume), camera, distance, values[None],
                             np.where(first >= 0, first, np.inf)[None], params, volume.GetProperty(),
                             slab=clip_uniforms.slab_of(mapper, camera),
                             aspect=rgba.shape[1] / rgba.shape[0], rays=(start[None], step[None]))
    out[rows, columns] = demip_premultiplied(values[None], rgb, volume.GetProperty())[0]
    return out
