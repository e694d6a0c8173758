"""A foveated frame keeps what the last one left at full quality instead of casting it again.

Where a frame drew level 0 alone -- eccentricity below every coarser
level's cast range, :func:`exact_radius` -- its picture is full quality
pixel for pixel (level 0's weight is 1 there and nothing lies beneath it
but the scene).  The next frame of the same scene (:func:`scene_key`, and
the foveated mapper's signature of everything but the gaze) keeps those
pixels wherever it is full quality itself: inside its own exact disc.  For
a still frame of progressive refinement
(:meth:`mipcast.mappers.foveated.FoveatedVolumeMapper.SetProgressive`),
whose disc only widens, that is the whole last disc; for a gaze that moved
(a pursuit, a small saccade) it is where the last frame's disc and this
frame's overlap (:class:`Disc`).  Level 0 skips those pixels
(``u_mc_fovSkip*`` in ``shaders/foveated_skip*.glsl``), and after the
levels a small pass (``shaders/foveated_keep_pass.glsl``,
:func:`draw_kept`) writes the last frame's picture there, blending and the
depth test off.  It writes a region :data:`MARGIN` wider than level 0
skipped, so every pixel is either cast or kept whatever float32 rounding
does at the border.  A converged frame keeps the whole view: drawing a
still, refined view again casts no ray.

The last picture (:func:`keep_picture`, a GPU copy of the viewport) is used
only under the same scene key, window and clipping range, with every other
prop of the window unchanged (:func:`scene_key`); each eye of a stereo
pair keeps its own.  A content-adaptive frame leaves nothing to keep (its
fovea interpolates where the mask says so); progressive refinement's still
frames therefore cast acuity-only levels.  The foveated mapper keeps
nothing (every ray cast, as before) for a tile of a bigger picture, a
float readout, levels drawn from bricks, a reduced level 0 (image sample
distance above 1) and on several ranks.
"""
from __future__ import annotations

import math
from typing import NamedTuple, Optional, Sequence

import numpy as np

from mipcast.core.foveation import REACH_TEXELS, eccentricity
from mipcast.mappers.private_draw import GL_BLEND, GL_DEPTH_TEST, copy_drawn, texture_target
from mipcast.mappers.shader_pieces import load_piece

#: Viewport heights between the disc level 0 skips and the wider disc the pass writes, and between that
#: and the last frame's exact radius (float32 eccentricities agree to ~1e-7 of the height).
MARGIN = 1.0e-4
#: The pass's one statement (a constant: the piece holds the code).
_IMPL = "gl_FragData[0] = mcFovKeepPass(texCoord);"
#: Stand-in for an unbounded radius in the pass's uniform.
_FAR = 1.0e30


def exact_radius(plan) -> float:
    """Eccentricity below which a frame of ``plan`` drew level 0 alone: its picture is full quality there.

    The smallest cast range start of the coarser levels, less how far each
    level's bilinear stretch reaches inward from its outermost cast texel
    (:data:`mipcast.core.foveation.REACH_TEXELS` of its texels): the foveal
    radius of the plan, or less where a coarse level's texels are large.
    Infinite for a one-level plan (foveation off, or the last still frame).

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> round(exact_radius(plan_frame((0, 0, 512, 512), (0.5, 0.5), 0.1, 0.1)), 9)  # the foveal radius
    0.1
    >>> exact_radius(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1, foveation=False))
    inf
    """
    return min((layer.cast_from - REACH_TEXELS * max(1.0 / layer.grid[1], plan.aspect / layer.grid[0])
                for layer in plan.layers if layer.level != 0), default=math.inf)


#: VTK settings of a volume mapper a picture depends on (``Get<name>``; those a VTK lacks are skipped).
MAPPER_SETTINGS = ("SampleDistance", "ImageSampleDistance", "AutoAdjustSampleDistances",
                   "LockSampleDistanceToInputSpacing", "UseJittering", "BlendMode", "Cropping",
                   "CroppingRegionPlanes", "CroppingRegionFlags", "ScalarMode", "ArrayAccessMode", "ArrayId",
                   "ArrayName", "MaskInput", "MaskType", "MaskBlendFactor", "ColorRangeType",
                   "ScalarOpacityRangeType", "GradientOpacityRangeType", "ComputeNormalFromOpacity",
                   "GlobalIlluminationReach", "VolumetricScatteringBlending", "Transfer2DYAxisArray",
                   "ClampDepthToBackface", "FinalColorWindow", "FinalColorLevel")


def _value(value):
    """A setting as a comparable value (a VTK object by its address and modification time)."""
    if hasattr(value, "GetAddressAsString"):
        return (value.GetAddressAsString("vtkObjectBase"), value.GetMTime())
    return tuple(value) if isinstance(value, (list, tuple)) else value


def scene_key(renderer, volume, mapper=None) -> tuple:
    """What besides the refinement signature a kept picture depends on: window, clipping range, the rest of the scene.

    The window with its multisampling (a screenshot may render without it);
    ``mapper``'s clipping planes and VTK settings (:data:`MAPPER_SETTINGS`;
    mipcast's own are in the foveated mapper's signature);
    every renderer of the window with its background, layer and lights and,
    for each of its props but ``volume``, the prop's visibility and redraw
    time (which covers its mapper, input and property).  Not a renderer's
    own modification time: ParaView's view moves it every frame.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkActor, vtkRenderWindow, vtkRenderer, vtkVolume
    >>> window, renderer, actor = vtkRenderWindow(), vtkRenderer(), vtkActor()
    >>> window.AddRenderer(renderer); renderer.AddActor(actor)
    >>> key = scene_key(renderer, vtkVolume())
    >>> actor.GetProperty().SetColor(1.0, 0.0, 0.0)
    >>> scene_key(renderer, vtkVolume()) == key
    False
    """
    window = renderer.GetRenderWindow()
    renderers = window.GetRenderers()
    planes = mapper.GetClippingPlanes() if mapper is not None else None
    parts = [window.GetAddressAsString("vtkObjectBase"), window.GetMultiSamples(),
             renderer.GetAddressAsString("vtkObjectBase"), tuple(renderer.GetActiveCamera().GetClippingRange()),
             None if planes is None else tuple(planes.GetItem(i).GetMTime() for i in range(planes.GetNumberOfItems())),
             None if mapper is None else tuple(_value(getattr(mapper, f"Get{name}")()) for name in MAPPER_SETTINGS
                                               if hasattr(mapper, f"Get{name}"))]
    for other in (renderers.GetItemAsObject(i) for i in range(renderers.GetNumberOfItems())):
        props, lights = other.GetViewProps(), other.GetLights()
        background = (other.GetBackground(), other.GetBackground2(), other.GetBackgroundAlpha(),
                      other.GetGradientBackground(), other.GetTexturedBackground(), other.GetErase(),
                      other.GetDraw(), other.GetLayer(), tuple(other.GetViewport()))
        parts.append((other.GetAddressAsString("vtkObjectBase"), background,
                      tuple(lights.GetItemAsObject(i).GetMTime() for i in range(lights.GetNumberOfItems())),
                      tuple((prop.GetAddressAsString("vtkObjectBase"), prop.GetVisibility(), prop.GetRedrawMTime())
                            for prop in (props.GetItemAsObject(i) for i in range(props.GetNumberOfItems()))
                            if prop is not volume)))
    return tuple(parts)


class Disc(NamedTuple):
    """Where a frame keeps the last picture: within ``radius`` of the last frame's gaze ``gaze`` and
    within ``bound`` of this frame's (viewport heights; both the full-quality discs of their frames)."""
    gaze: tuple
    radius: float
    bound: float


def kept_disc(state: dict, key, window, eye: int, plan) -> Optional[Disc]:
    """The :class:`Disc` a frame of ``plan`` (acuity-only: before content-adaptive density widens its
    coarsest level) keeps from the last frame, if that was kept under ``key`` on ``window``; else None.

    ``eye``: 0 (one picture, or a stereo pair's left eye) or 1 (the right
    eye): each eye keeps its own picture.  None too when the discs do not
    overlap, and when the window released the copy's texture since
    (ParaView does when it captures a screenshot).

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.3, 0.1)
    >>> kept_disc({}, "scene", None, 0, plan) is None   # nothing kept yet
    True
    """
    kept = state.get("kept_pictures", {}).get(eye)
    if kept is None or kept["key"] != key or not _usable(kept, window):
        return None
    disc = Disc(kept["gaze"], kept["radius"], exact_radius(plan))
    gap = float(np.hypot((plan.gaze[0] - disc.gaze[0]) * plan.aspect, plan.gaze[1] - disc.gaze[1]))
    if min(disc.radius, disc.bound) <= 2 * MARGIN or gap >= disc.radius + disc.bound - 4 * MARGIN:
        return None
    return disc


def _usable(target: dict, window) -> bool:
    texture = target["texture"]
    return target["window"] is window and texture.GetContext() is window and texture.GetHandle() != 0


def keeps_all(disc: Optional[Disc]) -> bool:
    """Whether ``disc`` covers the whole view (a converged still frame): level 0 need not be drawn."""
    return disc is not None and disc.radius == math.inf and disc.bound == math.inf


def set_skip_uniforms(uniforms, disc: Optional[Disc]) -> None:
    """Level 0's ``u_mc_fovSkip*`` uniforms (``shaders/foveated_skip*.glsl``): no ray where ``disc`` is
    kept, less :data:`MARGIN` (none for None)."""
    if disc is None:
        gaze, radius, bound = (0.0, 0.0), -_FAR, -_FAR
    else:
        gaze, radius, bound = disc.gaze, disc.radius - 2 * MARGIN, disc.bound - 2 * MARGIN
    uniforms.SetUniform2f("u_mc_fovSkipGaze", [float(gaze[0]), float(gaze[1])])
    uniforms.SetUniformf("u_mc_fovSkip", float(min(radius, _FAR)))
    uniforms.SetUniformf("u_mc_fovSkipBound", float(min(bound, _FAR)))


def skipped(disc: Optional[Disc], grid: Sequence[int], plan) -> np.ndarray:
    """Whether level 0 skipped each ray of ``grid`` (top row first) for ``disc`` (float64, as the shader's test).

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = plan_frame((0, 0, 8, 8), (0.5, 0.5), 0.3, 0.1)
    >>> int(skipped(Disc((0.5, 0.5), 0.2, 0.3), (8, 8), plan).sum()), int(skipped(None, (8, 8), plan).sum())
    (12, 0)
    """
    if disc is None:
        return np.zeros((int(grid[1]), int(grid[0])), bool)
    return ((eccentricity(grid, disc.gaze, plan.aspect) < disc.radius - 2 * MARGIN)
            & (eccentricity(grid, plan.gaze, plan.aspect) < disc.bound - 2 * MARGIN))


def keep_picture(state: dict, renderer, viewport, plan, key, kept: Optional[Disc], eye: int = 0) -> None:
    """Copy the viewport's picture after the levels (on the GPU) for the next frame, with its gaze and exact radius.

    ``kept``: the :class:`Disc` this frame kept from the last (None: none);
    when it is concentric, the pixels it wrote are full quality too.
    """
    window = renderer.GetRenderWindow()
    pictures = state.setdefault("kept_pictures", {})
    target = pictures.get(eye)
    size = (int(viewport[2]), int(viewport[3]))
    if target is None or target["size"] != size or not _usable(target, window):
        texture, framebuffer = texture_target(window, *size)
        target = {"window": window, "size": size, "texture": texture, "framebuffer": framebuffer}
    copy_drawn(renderer, viewport, target["framebuffer"])
    radius = exact_radius(plan)
    if kept is not None and tuple(kept.gaze) == tuple(plan.gaze):
        radius = max(radius, min(kept.radius, kept.bound) - MARGIN)
    target.update(key=key, radius=radius, gaze=tuple(plan.gaze))
    pictures[eye] = target


def forget(state: dict) -> None:
    """Drop the kept pictures (the next frame casts every ray)."""
    for kept in state.pop("kept_pictures", {}).values():
        if "quad" in kept:
            kept["quad"].ReleaseGraphicsResources(kept["window"])


def draw_kept(state: dict, renderer, viewport, plan, disc: Disc, eye: int = 0) -> None:
    """Write the kept picture inside ``disc`` less :data:`MARGIN` (blending, depth test off)."""
    from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLQuadHelper, vtkOpenGLRenderUtilities

    target = state["kept_pictures"][eye]
    window = renderer.GetRenderWindow()
    if "quad" not in target:
        fragment = vtkOpenGLRenderUtilities.GetFullScreenQuadFragmentShaderTemplate()
        fragment = fragment.replace("//VTK::FSQ::Decl", load_piece("foveated_keep_pass").text)
        fragment = fragment.replace("//VTK::FSQ::Impl", _IMPL)
        target["sources"] = (vtkOpenGLRenderUtilities.GetFullScreenQuadVertexShader(), fragment)
        target["quad"] = vtkOpenGLQuadHelper(window, *target["sources"], "")
    gl_state = window.GetState()
    gl_state.Push()
    try:
        x0, y0, width, height = viewport
        gl_state.vtkglViewport(x0, y0, width, height)
        gl_state.vtkglDisable(GL_BLEND)
        gl_state.vtkglDisable(GL_DEPTH_TEST)
        target["texture"].Activate()
        program = window.GetShaderCache().ReadyShaderProgram(*target["sources"], "")
        program.SetUniformi("u_mc_fovKept", target["texture"].GetTextureUnit())
        program.SetUniform2f("u_mc_fovGaze", [float(plan.gaze[0]), float(plan.gaze[1])])
        program.SetUniform2f("u_mc_fovKeptGaze", [float(disc.gaze[0]), float(disc.gaze[1])])
        program.SetUniformf("u_mc_fovAspect", float(plan.aspect))
        program.SetUniformf("u_mc_fovKeep", float(min(disc.radius - MARGIN, _FAR)))
        program.SetUniformf("u_mc_fovKeepBound", float(min(disc.bound - MARGIN, _FAR)))
        program.SetUniform2f("u_mc_fovSize", [float(width), float(height)])
        target["quad"].Render()
    finally:
        target["texture"].Deactivate()
        gl_state.Pop()
