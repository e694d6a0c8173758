"""Progressive refinement keeps what it has: a still frame casts level 0 only where the last was not yet full quality.

Still frame ``k`` of progressive refinement
(:meth:`mipcast.mappers.foveated.FoveatedVolumeMapper.SetProgressive`) widens
the fovea until the picture is full quality.  Where a frame drew level 0
alone -- eccentricity below every coarser level's cast range,
:func:`exact_radius` -- its picture is full quality pixel for pixel (level 0's
weight is 1 there and nothing lies beneath it but the scene).  The next still
frame of the same scene keeps those pixels instead of casting them again:
level 0 skips the disc (``u_mc_fovSkip`` in ``shaders/foveated_skip.glsl``),
and after the levels a small pass (``shaders/foveated_keep_pass.glsl``,
:func:`draw_kept`) writes the last frame's picture there, blending and the
depth test off.  It writes a disc :data:`MARGIN` wider than level 0 skipped,
so every pixel is either cast or kept whatever float32 rounding does at the
border.  A converged frame keeps the whole view: drawing a still, refined view
again casts no ray.

The last picture is kept (:func:`keep_picture`) only where it can be used
again: the same refinement signature (camera, volume, property, input,
settings, viewport, gaze), the same window and clipping range, and every other
prop of the window unchanged (:func:`scene_key`); each eye of a stereo pair
keeps its own.  The foveated mapper keeps nothing (every ray cast, as
before) for a tile of a bigger picture, a float readout, levels drawn from bricks, a reduced level 0 (image
sample distance above 1) and content-adaptive frames (their fovea is not
full quality where the mask interpolates); its still frames cast acuity-only
levels so that the next can keep them.
"""
from __future__ import annotations

import math
from typing import Optional

from mipcast.core.foveation import REACH_TEXELS
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


def scene_key(renderer, volume, mapper=None) -> tuple:
    """What besides the refinement signature a kept picture depends on: window, clipping range, the rest of the scene.

    The window with its multisampling (a screenshot may render without it);
    ``mapper``'s clipping planes (a plane's change does not move the
    mapper's modification time, which the foveated mapper compares itself);
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
             None if planes is None else tuple(planes.GetItem(i).GetMTime() for i in range(planes.GetNumberOfItems()))]
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


def kept_radius(state: dict, key, window, eye: int = 0) -> Optional[float]:
    """Radius of the disc the last frame left at full quality, if it was kept under ``key`` on ``window``; else None.

    ``eye``: 0 (one picture, or a stereo pair's left eye) or 1 (the right
    eye): each eye keeps its own picture.  None too when the window
    released the copy's texture since (ParaView does when it captures a
    screenshot).
    """
    kept = state.get("kept_pictures", {}).get(eye)
    if kept is None or kept["key"] != key or kept["radius"] <= 2 * MARGIN or not _usable(kept, window):
        return None
    return kept["radius"]


def _usable(target: dict, window) -> bool:
    texture = target["texture"]
    return target["window"] is window and texture.GetContext() is window and texture.GetHandle() != 0


def skip_radius(radius: Optional[float]) -> float:
    """The disc level 0 skips in a frame that keeps ``radius`` (-inf: none)."""
    return -math.inf if radius is None else radius - 2 * MARGIN


def keep_picture(state: dict, renderer, viewport, plan, key, kept: Optional[float], eye: int = 0) -> None:
    """Copy the viewport's picture after the levels (on the GPU) for the next still frame, with its exact radius.

    ``kept``: the radius this frame kept from the last (None: none); the
    pixels it wrote are full quality too.
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
    if kept is not None:
        radius = max(radius, kept - MARGIN)
    target.update(key=key, radius=radius)
    pictures[eye] = target


def forget(state: dict) -> None:
    """Drop the kept pictures (the next frame casts every ray)."""
    for kept in state.pop("kept_pictures", {}).values():
        if "quad" in kept:
            kept["quad"].ReleaseGraphicsResources(kept["window"])


def draw_kept(state: dict, renderer, viewport, plan, radius: float, eye: int = 0) -> None:
    """Write the kept picture inside the disc of ``radius - MARGIN`` around the gaze (blending, depth test off)."""
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
        program.SetUniformf("u_mc_fovAspect", float(plan.aspect))
        program.SetUniformf("u_mc_fovKeep", float(min(radius - MARGIN, _FAR)))
        program.SetUniform2f("u_mc_fovSize", [float(width), float(height)])
        target["quad"].Render()
    finally:
        target["texture"].Deactivate()
        gl_state.Pop()
