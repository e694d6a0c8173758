"""The private level mappers of a foveated frame: their classes, settings, uniforms and draws.

A :class:`mipcast.mappers.foveated.FoveatedVolumeMapper` draws each level of
its plan (:func:`mipcast.core.foveation.plan_frame`) with a private mapper of
the layer method plus the foveation pieces (:func:`level_class`): this module
makes those mappers (:func:`new_level`), copies the user's settings to them
(:func:`copy_settings`), sets their foveation and silhouette-band uniforms
(:func:`set_uniforms`, :func:`set_silhouette`), draws a level whose mask the
GPU builds (:func:`render_coarse_level`) or whose rays were composited over
bricks (:func:`composite_level`), and measures what a level needs from the
view (:func:`level_cap`, :func:`world_per_pixel`, :func:`silhouette`).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Optional

import numpy as np
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_OBJECT, reference, vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import vtkVolume
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.core import foveation
from mipcast.core.camera_rays import matrix_array
from mipcast.core.object_state import object_state
from mipcast.core.parameter_tables import FOVEATION_LAYERS
from mipcast.mappers import bricked_draw, bricked_foveated, clip_uniforms, float_readout, refine_keep, volume_pyramid
from mipcast.mappers.private_draw import GL_SCISSOR_BOX, GL_SCISSOR_TEST, follow_volume, scissor_kept
from mipcast.mappers.stereo import draw_for

if TYPE_CHECKING:
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject

#: Stand-in for an unbounded eccentricity in the shader's uniforms.
FAR = 1.0e30

#: Pieces every level adds to its method's own.
LEVEL_PIECES = ("foveated_band_dec", "foveated_skip", "foveated_weight")
#: Pieces of the finer levels with content-adaptive ray density (ContentTolerance > 0).
#: A cast ray of theirs is drawn over the picture beneath the volume, not over the coarser levels.
MASKED_LEVEL_PIECES = ("foveated_band_dec", "foveated_skip_masked", "foveated_mask_dec", "foveated_weight",
                       "foveated_paint_beneath")
#: The same with the refinement mask built on the GPU from the deciding level's picture (no readback).
COARSE_LEVEL_PIECES = ("foveated_band_dec", "foveated_skip_coarse", "foveated_coarse_dec", "foveated_weight",
                       "foveated_paint_beneath")


def capture_depth(state, renderer) -> Optional[vtkTextureObject]:
    """Copy the depth buffer once for all levels; the bound texture they share, or None.

    Each VTK volume mapper copies the whole window's depth buffer before it
    draws (so rays stop at opaque geometry): about 4 ms at 512^2 on llvmpipe,
    as much as a coarse level's rays.  A private mapper with a 2x2x2 input,
    cropped to nothing, does that copy once per frame; the levels read its
    texture (``SetSharedDepthTexture``), bound while they draw.
    """
    entry = state.get("depth_capture")
    if entry is None:
        dummy = vtkImageData()
        dummy.SetDimensions(2, 2, 2)
        dummy.SetSpacing(1e-3, 1e-3, 1e-3)
        dummy.AllocateScalars(10, 1)  # VTK_FLOAT
        dummy.GetPointData().GetScalars().Fill(0.0)
        capture = vtkOpenGLGPUVolumeRayCastMapper()  # VTK's own: no mipcast checks per frame
        capture.SetBlendModeToMaximumIntensity()
        capture.SetInputData(dummy)
        capture.SetCropping(True)
        capture.SetCroppingRegionPlanes(0.0, 1e-3, 0.0, 1e-3, 0.0, 1e-3)
        capture.SetCroppingRegionFlags(0)  # every fragment is cropped away: it draws nothing
        capture_volume = vtkVolume()
        capture_volume.SetMapper(capture)
        entry = state["depth_capture"] = {"mapper": capture, "volume": capture_volume}
    entry["volume"].RenderVolumetricGeometry(renderer)
    depth = entry["mapper"].GetDepthTexture()
    if depth is not None:
        depth.Activate()
    return depth


def new_level(method: str, kind: Optional[str] = None, bricks: bool = False) -> dict:
    """A private level mapper and volume; ``kind``: None, ``"masked"`` (CPU mask) or ``"coarse"`` (GPU mask).

    ``bricks``: a level drawn from its rays' values composited over bricks
    (:mod:`mipcast.mappers.bricked_foveated`), whatever the layer method.
    """
    base = value_class(bricked_foveated.is_demip(method)) if bricks else FOVEATION_LAYERS[method].factory
    level_mapper = level_class(base, kind)()
    level_volume = vtkVolume()
    level_mapper.Attach(level_volume)
    if bricks:
        level_mapper.AddObserver(vtkCommand.UpdateShaderEvent, bricked_foveated.bind_values_sampler)
    if kind == "masked":
        level_mapper.AddObserver(vtkCommand.UpdateShaderEvent, bind_mask_sampler)
    elif kind == "coarse":
        level_mapper.AddObserver(vtkCommand.UpdateShaderEvent, bind_coarse_samplers)
    return {"mapper": level_mapper, "volume": level_volume, "matrix": vtkMatrix4x4()}


@calldata_type(VTK_OBJECT)
def bind_coarse_samplers(level_mapper, event, program) -> None:
    """Point a GPU-masked level's samplers (the refine pass's texture, fovea spans, the picture beneath) at their
    textures' units."""
    level_state = object_state(level_mapper)
    units = level_state.get("coarse_units")
    if program is not None and units is not None and min(units) >= 0:
        for name, unit in zip(("u_mc_fovRefine", "u_mc_fovFovea", "u_mc_fovBeneath"), units):
            program.SetUniformi(name, int(unit))
        level_state["samplers_set"] = True


_VALUE_CLASSES: dict = {}


def value_class(colours: bool = False) -> type:
    """The mapper class of a level drawn from composited values (``shaders/foveated_brick_hooks.glsl``).

    ``colours``: a DEMIP level's, drawing the composited colours too
    (``shaders/foveated_brick_color.glsl``).
    """
    if colours not in _VALUE_CLASSES:
        from mipcast.mappers.mip import sampled_projection_mapper

        _VALUE_CLASSES[colours] = (sampled_projection_mapper(bricked_foveated.HOOKS, bricked_foveated.COLOUR)
                                   if colours else sampled_projection_mapper(bricked_foveated.HOOKS))
    return _VALUE_CLASSES[colours]


def level_bricks(source, limit) -> list:
    """A level source's brick entries (one per brick; a DEMIP layer's phase-1 and phase-2 entries both)."""
    if bricked_foveated.is_demip(source["method"]):
        return [entry for pair in bricked_foveated.demip_bricks(source, limit) for entry in pair]
    return bricked_draw.bricks_of(source["mapper"], limit)


def composite_level(mapper, state, volume, renderer, level, volume_level, level_input, component, distance, plan,
                     layer, silhouette) -> tuple:
    """A level beyond the texture limit: its rays composited over its bricks, uploaded for its draw.

    Returns (the 2 x 2 x 2 box the level draws, the values' texture, a DEMIP
    layer's colours' texture or None); see :mod:`mipcast.mappers.bricked_foveated`.
    """
    source = bricked_foveated.level_source(state, volume_level, mapper._parameters()["method"])
    source_mapper = source["mapper"]
    if source_mapper.GetInput() is not level_input:
        source_mapper.SetInputData(level_input)
    if source_mapper.GetComponent() != component:
        source_mapper.SetComponent(component)
    copy_settings(mapper, volume, source_mapper, source["volume"], source["matrix"], distance,
                   layer.image_sample_distance)
    draw_for(source_mapper, renderer.GetActiveCamera(), renderer)
    limit = bricked_foveated.level_limit(mapper, level_input)
    for brick in level_bricks(source, limit):  # they cast only the level's rays
        set_uniforms(brick["volume"], plan, layer)
        set_silhouette(brick["volume"], silhouette, layer.level)
    colours = None
    if bricked_foveated.is_demip(source["method"]):
        values, rgba = bricked_foveated.composite_demip(source, volume, renderer, limit, layer.image_sample_distance,
                                                        layer.grid)
        colours = bricked_foveated.level_texture(state, renderer, level, rgba, "colours")
    else:
        values = bricked_foveated.composite(source, volume, renderer, limit, layer.image_sample_distance,
                                            layer.grid)
    rendered = source_mapper.GetRenderedInput()
    boxes = state.setdefault("value_boxes", {})
    stamp = (rendered.GetAddressAsString("vtkObjectBase"), rendered.GetMTime())
    if boxes.get(volume_level, (None,))[0] != stamp:
        boxes[volume_level] = (stamp, bricked_foveated.value_box(rendered))
    normalised = bricked_foveated.normalised_values(values, rendered)
    return boxes[volume_level][1], bricked_foveated.level_texture(state, renderer, level, normalised, "values"), colours


def render_coarse_level(level_mapper, level_volume, renderer, plan, layer, kept=None) -> None:
    """Draw a GPU-masked level, its samplers pointing at the coarse pictures.

    VTK invokes UpdateShaderEvent (where :func:`bind_coarse_samplers` sets
    the samplers) on every draw except one that (re)builds the shader, whose
    samplers would all read unit 0.  So when the level may need a build (its
    first draw, or anything VTK's rebuild test watches changed since the last
    draw that set the samplers: :func:`shader_stamp`), it is first drawn with every ray discarded
    (:func:`_probe`), which builds the shader; the real draw then sets them.
    ``kept``: the :class:`refine_keep.Disc` level 0 casts no ray in (:func:`set_uniforms`).
    """
    level_state = object_state(level_mapper)
    stamp = shader_stamp(level_mapper, level_volume, renderer)
    if level_state.get("sampler_stamp") != stamp:
        level_state["sampler_probes"] = level_state.get("sampler_probes", 0) + 1
        _probe(level_volume, renderer, plan, layer, kept)
    level_state["samplers_set"] = False
    level_volume.RenderVolumetricGeometry(renderer)
    if level_state["samplers_set"]:
        level_state["sampler_stamp"] = stamp
    else:  # built again by the real draw: this frame's masks read the wrong textures; probe next frame
        level_state.pop("sampler_stamp", None)
        level_state["sampler_misses"] = level_state.get("sampler_misses", 0) + 1


def shader_stamp(level_mapper, level_volume, renderer) -> tuple:
    """What VTK's test for rebuilding a volume mapper's shader reads (besides render passes and picking):
    the mapper's, the shader property's and the volume property's modification times, the lights' (the light
    collection's and each light's: a headlight moves with the camera, so VTK rebuilds the shader, from its
    cache, at every frame whose camera moved), and the window."""
    lights = renderer.GetLights()
    light_time = lights.GetMTime()
    lights.InitTraversal()
    light = lights.GetNextItem()
    while light is not None:
        light_time = max(light_time, light.GetMTime())
        light = lights.GetNextItem()
    return (level_mapper.GetMTime(), level_volume.GetShaderProperty().GetShaderMTime(),
            level_volume.GetProperty().GetMTime(), light_time,
            renderer.GetRenderWindow().GetAddressAsString("vtkObjectBase"))


def _probe(level_volume, renderer, plan, layer, kept) -> None:
    """Draw the level with every ray discarded, which (re)builds its shader: the cast range emptied and the
    silhouette band off (level 0 casts it whatever the mask, and a level drawn from bricks reads the samplers
    there too: drawn by the probe it was blended over the real draw's, a frame that probed 93 % of the pixels
    within 1 grey, up to 35 off along the box's outline), in a scissor box of one pixel (it draws nothing: VTK's
    fixed cost of a pass, not a fragment per pixel of the level's box)."""
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    uniforms.SetUniformf("u_mc_fovCastFrom", FAR)
    uniforms.SetUniformf("u_mc_fovCastTo", FAR)
    band = reference(0.0)
    uniforms.GetUniformf("u_mc_fovSilOn", band)
    uniforms.SetUniformf("u_mc_fovSilOn", 0.0)
    window = renderer.GetRenderWindow()
    gl_state = window.GetState()
    box = [0, 0, 0, 0]
    gl_state.vtkglGetIntegerv(GL_SCISSOR_BOX, box)
    try:
        with scissor_kept(window):
            gl_state.vtkglEnable(GL_SCISSOR_TEST)
            gl_state.vtkglScissor(box[0], box[1], 1, 1)
            level_volume.RenderVolumetricGeometry(renderer)
    finally:
        set_uniforms(level_volume, plan, layer, kept)
        uniforms.SetUniformf("u_mc_fovSilOn", float(band))


def bind_coarse(level_mapper, level_volume, textures) -> None:
    """Activate the refine pass's texture and the fovea spans for a GPU-masked level; note their units.

    :func:`bind_coarse_samplers` points the samplers at these units on
    every draw (see :func:`render_coarse_level` for the draw that builds
    the shader).
    """
    for texture in textures:
        texture.Activate()
    object_state(level_mapper)["coarse_units"] = tuple(texture.GetTextureUnit() for texture in textures)


def set_coarse_uniforms(level_volume, coarser, layer) -> None:
    """The grids ``foveated_coarse_dec``'s mask lookup needs: the level drawn before (``coarser``) and this one."""
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    for name, value in (("u_mc_fovCoarseW", coarser.grid[0]), ("u_mc_fovCoarseH", coarser.grid[1]),
                        ("u_mc_fovLevelW", layer.grid[0]), ("u_mc_fovLevelH", layer.grid[1])):
        uniforms.SetUniformi(name, int(value))


@calldata_type(VTK_OBJECT)
def bind_mask_sampler(level_mapper, event, program) -> None:
    """Point the masked level's ``u_mc_fovMask`` and ``u_mc_fovBeneath`` at their textures' units.

    VTK invokes UpdateShaderEvent when it builds the shader, not every frame;
    :mod:`mipcast.mappers.foveated` re-installs the pieces (a rebuild) should the unit change.
    """
    units = object_state(level_mapper).get("mask_unit")
    if program is not None and units is not None and min(units) >= 0:
        program.SetUniformi("u_mc_fovMask", int(units[0]))
        program.SetUniformi("u_mc_fovBeneath", int(units[1]))  # (the mask's own unit when nothing is beneath)
        object_state(level_mapper)["mask_unit_built"] = units


_LEVEL_CLASSES: dict = {}


def level_class(base, kind: Optional[str] = None) -> type:
    """``base`` (a mipcast mapper class) plus the foveation pieces.

    ``kind``: None, ``"masked"`` (refinement mask uploaded from the CPU) or
    ``"coarse"`` (mask built in the shader from the coarse picture).
    """
    cls = _LEVEL_CLASSES.get((base, kind))
    if cls is None:
        extra = {None: LEVEL_PIECES, "masked": MASKED_LEVEL_PIECES,
                 "coarse": COARSE_LEVEL_PIECES}[kind]

        def GetShaderPieces(self):
            return tuple(base.GetShaderPieces(self)) + extra

        name = f"Foveated{base.__name__}{(kind or '').capitalize()}Level"
        members = {"__doc__": f"One pyramid level of a FoveatedVolumeMapper rendering with {base.__name__}.",
                   "GetShaderPieces": GetShaderPieces}
        if kind is not None and base.MISSING_PIECE == "missing_exit":  # coarser levels lie beneath: paint, not skip
            members["MISSING_PIECE"] = "foveated_missing_flag"
        cls = type(name, (base,), members)
        _LEVEL_CLASSES[(base, kind)] = cls
    return cls


def copy_settings(mapper, volume, level_mapper, level_volume, matrix, distance, image_distance) -> None:
    level_mapper.SetAutoAdjustSampleDistances(False)
    if level_mapper.GetSampleDistance() != distance:
        level_mapper.SetSampleDistance(distance)
    if level_mapper.GetImageSampleDistance() != image_distance:
        level_mapper.SetImageSampleDistance(image_distance)
    follow_volume(mapper, volume, level_mapper, level_volume, matrix)
    clip_uniforms.copy_clipping(mapper, level_mapper)


def set_uniforms(level_volume, plan, layer, kept=None) -> None:
    """The level's foveation uniforms; ``kept``: the :class:`refine_keep.Disc` level 0 casts no ray in."""
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    refine_keep.set_skip_uniforms(uniforms, kept if layer.level == 0 else None)
    uniforms.SetUniform2f("u_mc_fovGaze", [float(plan.gaze[0]), float(plan.gaze[1])])
    uniforms.SetUniformf("u_mc_fovAspect", float(plan.aspect))
    uniforms.SetUniformf("u_mc_fovCastFrom", max(layer.cast_from, -FAR))
    uniforms.SetUniformf("u_mc_fovCastTo", min(layer.cast_to, FAR))
    uniforms.SetUniformf("u_mc_fovStart", float(plan.start))
    uniforms.SetUniformf("u_mc_fovGain", float(plan.gain))
    uniforms.SetUniformf("u_mc_fovTop", float(plan.top))
    uniforms.SetUniformf("u_mc_fovLevel", float(layer.level))


def silhouette(image, volume, camera, viewport, base_isd) -> Optional[tuple]:
    """The volume box's projected outline for the silhouette band: (edges (6, 3), unit), or None.

    ``unit`` is one level-0 ray spacing in viewport heights.  None when a
    corner lies behind the camera or the outline is degenerate.  The edges
    are kept for the last projected corners: a frame whose view stands
    still (the gaze moving) projects them alone.
    """
    if image is None or image.GetNumberOfPoints() == 0:
        return None
    extent = image.GetExtent()  # VTK's structured indices: a piece's extent may start anywhere
    corners = []
    for i in extent[0:2]:
        for j in extent[2:4]:
            for k in extent[4:6]:
                point = [0.0, 0.0, 0.0]
                image.TransformIndexToPhysicalPoint(i, j, k, point)
                corners.append(point + [1.0])
    aspect = viewport[2] / viewport[3]
    world = matrix_array(volume.GetMatrix()) @ np.array(corners).T
    clip = matrix_array(camera.GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0)) @ world
    if np.any(clip[3] <= 1e-12):
        return None
    points = ((clip[:2] / clip[3]).T + 1.0) / 2.0
    key = (points.tobytes(), aspect)
    if _EDGES.get("key") != key:
        edges = foveation.silhouette_edges(points, aspect)
        if edges is not None:
            edges.setflags(write=False)  # shared by the frames that keep it
        _EDGES.update(key=key, edges=edges)
    edges = _EDGES["edges"]
    return None if edges is None else (edges, float(base_isd) / viewport[3])


#: The last outline :func:`silhouette` found, and the projected corners and aspect it was found for.
_EDGES: dict = {}


def set_silhouette(level_volume, silhouette, level: int) -> bool:
    """Upload the silhouette band's uniforms (shaders/foveated_skip.glsl); True when level 0 casts the band."""
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    edges, unit = silhouette if silhouette is not None else (np.tile([0.0, 0.0, FAR], (6, 1)), 0.0)
    uniforms.SetUniformf("u_mc_fovSilOn", 1.0 if silhouette is not None and level == 0 else 0.0)
    uniforms.SetUniformf("u_mc_fovSilUnit", float(unit))
    for index, edge in enumerate(edges):
        uniforms.SetUniform3f(f"u_mc_fovSil{index}", [float(v) for v in edge])
    return silhouette is not None and level == 0


def level_values(level_mapper, grid) -> np.ndarray:
    """A level's float readout in data units, (rows, columns) top row first, NaN = no ray."""
    image = vtkImageData()
    level_mapper.GetDepthImage(image)
    scalars = image.GetPointData().GetScalars()
    columns, rows = grid
    if scalars is None:
        return np.full((rows, columns), np.nan)
    columns, rows, _ = image.GetDimensions()
    normalised = float_readout.decode(vtk_to_numpy(scalars).reshape(rows, columns)[::-1])
    return float_readout.to_data_units(normalised, level_mapper.GetRenderedInput().GetPointData().GetScalars())


def level_cap(image, volume, camera, viewport) -> int:
    """Coarsest image level whose texels still fit MIN_TEXELS times into the volume's projection."""
    x0, y0, width, height = viewport
    bounds = volume.GetBounds()
    matrix = matrix_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
    corners = np.array([[x, y, z, 1.0] for x in bounds[0:2] for y in bounds[2:4] for z in bounds[4:6]])
    points = corners @ matrix.T
    if np.any(points[:, 3] <= 0):
        return 99  # the camera is inside or behind: the volume covers the view
    ndc = points[:, :2] / points[:, 3:]
    low, high = np.clip(ndc.min(axis=0), -1, 1), np.clip(ndc.max(axis=0), -1, 1)
    extent = min(0.5 * (high[0] - low[0]) * width, 0.5 * (high[1] - low[1]) * height)
    level = 0
    while 2 ** (level + 1) * foveation.MIN_TEXELS <= extent:
        level += 1
    return level


def world_per_pixel(camera, volume, viewport) -> float:
    """Model-space length one pixel spans at the volume's centre."""
    height = viewport[3]
    if camera.GetParallelProjection():
        world = 2.0 * camera.GetParallelScale() / height
    else:
        centre = np.array(volume.GetCenter())
        direction = np.array(camera.GetDirectionOfProjection())
        depth = abs(float(np.dot(centre - np.array(camera.GetPosition()), direction)))
        world = 2.0 * depth * math.tan(math.radians(camera.GetViewAngle()) / 2.0) / height
    matrix = matrix_array(volume.GetMatrix())[:3, :3]
    scale = float(np.cbrt(abs(np.linalg.det(matrix)))) or 1.0
    return world / scale


def walks_cells(method: str) -> bool:
    return FOVEATION_LAYERS[method].walks_cells


def pyramid(state, image) -> list:
    params = state["parameters"]
    component = state["preparer"].GetComponent() if "preparer" in state else -1
    stamp = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime(), params["number_of_levels"], component)
    cached = state.get("pyramid")
    if cached is None or cached[0] != stamp:
        cached = (stamp, volume_pyramid.build_max_pyramid(image, params["number_of_levels"], component))
        state["pyramid"] = cached
    return cached[1]
