"""Content-adaptive foveation: the refinement test once per coarse texel, in its own small GPU pass.

The finer levels of a GPU-masked foveated frame (``ContentTolerance > 0``)
cast a ray only where :func:`mipcast.core.content_adaptive.refinement_mask`
asks for one.  That rule depends on the picture the coarser levels left, in
the 3 x 3 neighbourhood of the ray's nearest texel of the level drawn just
before (and, for structure, on whether the ray lies in the fovea).  Before
each finer level this pass evaluates it once per texel of the level drawn
before (:func:`mipcast.core.content_adaptive.refinement_test`; at most 1/4
of the finer level's fragments) into a texture of that grid
(``shaders/foveated_refine_pass.glsl``: red = the grey span exceeds the
tolerance, green = structure above the floor, in the picture or where the
data says a full-quality ray may meet it, :mod:`mipcast.core.structure_bound`,
a texture the CPU uploads); the finer level's fragments
read one texel (``shaders/foveated_coarse_dec.glsl``) instead of the 18
texel fetches of the neighbourhood each.  The decisions, and so the
pictures, are the CPU definition's bit for bit
(``tests/test_content_adaptive_gpu.py``).
"""
from __future__ import annotations

import math

from mipcast.mappers.private_draw import texture_target
from mipcast.mappers.shader_pieces import load_piece

#: OpenGL enums the pass saves and restores.
_GL_BLEND, _GL_DEPTH_TEST, _GL_SCISSOR_TEST, _GL_VIEWPORT = 0x0BE2, 0x0B71, 0x0C11, 0x0BA2
#: Refine targets kept (twice the deciding levels of a content-adaptive frame: a frame's own, and the last size's).
KEPT_TARGETS = 4
#: The pass's one statement (a constant: the piece holds the code).
_IMPL = "gl_FragData[0] = mcFovRefinePass(texCoord);"


def _sources() -> tuple:
    """(vertex, fragment) source of the pass: VTK's full-screen quad with the piece's code."""
    from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLRenderUtilities

    fragment = vtkOpenGLRenderUtilities.GetFullScreenQuadFragmentShaderTemplate()
    fragment = fragment.replace("//VTK::FSQ::Decl", load_piece("foveated_refine_pass").text)
    fragment = fragment.replace("//VTK::FSQ::Impl", _IMPL)
    return vtkOpenGLRenderUtilities.GetFullScreenQuadVertexShader(), fragment


def refine_target(state: dict, window, grid) -> dict:
    """The pass's output for one coarser grid (an RGBA8 texture of ``grid``, its framebuffer, the quad).

    Cached in ``state``, one per grid (a frame's deciding levels have one
    each), the :data:`KEPT_TARGETS` used last (a resized window makes new
    grids); made again for another window.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> window = vtkRenderWindow(); window.SetOffScreenRendering(True); window.AddRenderer(vtkRenderer())
    >>> window.SetSize(8, 8); window.Render()
    >>> state = {}
    >>> target = refine_target(state, window, (4, 2))
    >>> target["texture"].GetWidth(), target["texture"].GetHeight()
    (4, 2)
    >>> refine_target(state, window, (2, 1)) is not target, refine_target(state, window, (4, 2)) is target
    (True, True)
    >>> for columns in range(3, 9):   # a window resized again and again keeps the last few
    ...     _ = refine_target(state, window, (columns, 1))
    >>> len(state["refine_targets"]) == KEPT_TARGETS and (8, 1) in state["refine_targets"]
    True
    """
    from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLQuadHelper

    targets = state.setdefault("refine_targets", {})
    address = window.GetAddressAsString("vtkObjectBase")
    for stale in [key for key, entry in targets.items() if entry["key"][0] != address]:
        old = targets.pop(stale)
        old["quad"].ReleaseGraphicsResources(old["window"])
    entry = targets.pop(tuple(grid), None)
    if entry is not None:
        targets[tuple(grid)] = entry  # the most recently used last
        return entry
    while len(targets) >= KEPT_TARGETS:
        old = targets.pop(next(iter(targets)))
        old["quad"].ReleaseGraphicsResources(old["window"])
    texture, target = texture_target(window, int(grid[0]), int(grid[1]))
    vertex, fragment = _sources()
    quad = vtkOpenGLQuadHelper(window, vertex, fragment, "")
    entry = targets[tuple(grid)] = {"key": (address, tuple(grid)), "window": window, "texture": texture,
                                    "framebuffer": target, "quad": quad, "sources": (vertex, fragment)}
    return entry


def run_refine_pass(state: dict, window, coarse: dict, viewport, grid, tolerance: float, whole_fovea: bool = False):
    """Evaluate the refinement test of every coarse texel into :func:`refine_target`'s texture; return it.

    ``coarse``: the viewport's picture after the level drawn before the
    finer one and before the frame's first level (``coarse["after"]``,
    ``coarse["before"]``, viewport-sized RGBA8 textures), and
    ``coarse["bound"]``, a texture of ``grid`` whose texels count as
    structure whatever the picture says
    (:mod:`mipcast.core.structure_bound`, all zero where none); ``grid``: that
    coarser level's (columns, rows).  ``whole_fovea``: every texel counts
    as structure (a content level deciding acuity's coarsest level, which
    casts the whole fovea: :func:`mipcast.core.content_adaptive.refinement_mask`). The GL state
    it touches (framebuffer, viewport, blending, depth and scissor tests)
    is restored.
    """
    target = refine_target(state, window, grid)
    gl_state = window.GetState()
    saved_viewport = [0, 0, 0, 0]
    gl_state.vtkglGetIntegerv(_GL_VIEWPORT, saved_viewport)
    enabled = {flag: gl_state.GetEnumState(flag) for flag in (_GL_BLEND, _GL_DEPTH_TEST, _GL_SCISSOR_TEST)}
    gl_state.PushFramebufferBindings()
    try:
        target["framebuffer"].Bind()
        target["framebuffer"].ActivateDrawBuffer(0)
        for flag in enabled:
            gl_state.vtkglDisable(flag)
        gl_state.vtkglViewport(0, 0, int(grid[0]), int(grid[1]))
        for texture in (coarse["after"], coarse["before"], coarse["bound"]):
            texture.Activate()
        program = window.GetShaderCache().ReadyShaderProgram(*target["sources"], "")
        program.SetUniformi("u_mc_fovAfter", coarse["after"].GetTextureUnit())
        program.SetUniformi("u_mc_fovBefore", coarse["before"].GetTextureUnit())
        program.SetUniformi("u_mc_fovBound", coarse["bound"].GetTextureUnit())
        for name, value in (("u_mc_fovCoarseW", grid[0]), ("u_mc_fovCoarseH", grid[1]),
                            ("u_mc_fovViewW", viewport[2]), ("u_mc_fovViewH", viewport[3])):
            program.SetUniformi(name, int(value))
        # grey ranges are integers: range > tolerance  <=>  range >= floor(tolerance) + 1 (exact in float32)
        program.SetUniformf("u_mc_fovEdgeMin", float(math.floor(tolerance) + 1))
        program.SetUniformf("u_mc_fovWholeFovea", 1.0 if whole_fovea else 0.0)
        target["quad"].Render()
    finally:
        for texture in (coarse["after"], coarse["before"], coarse["bound"]):
            texture.Deactivate()
        gl_state.PopFramebufferBindings()
        gl_state.vtkglViewport(*saved_viewport)
        for flag, on in enabled.items():
            if on:
                gl_state.vtkglEnable(flag)
    state["refine_passes"] = state.get("refine_passes", 0) + 1
    return target["texture"]
