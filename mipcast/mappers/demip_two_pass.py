"""Two-pass DEMIP: the paper's comparison version (Table 2), a MIP pass then a depth pass.

Díaz & Vázquez (paper §4.1) compare their one-shader DEMIP with a version
split into two fragment shaders: a MIP ray cast that stores per pixel what
the second needs in a 2D texture, then a second ray cast that reads it,
marches to the depth where the maximum's material is first reached and
composes the colour.  :class:`DEMIPTwoPassVolumeMapper` is that version,
on the GPU, inside VTK, so that its frame time can be compared with the
one-pass :class:`~mipcast.mappers.demip.DEMIPVolumeMapper` in one process.
See docs/methods.md, section Two-pass DEMIP.
"""
from __future__ import annotations

from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import vtkVolume

from mipcast.core import parameter_tables
from mipcast.mappers.demip import DEMIPVolumeMapper
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.core.object_state import object_state
from mipcast.mappers import clip_uniforms
from mipcast.mappers.private_draw import GL_BLEND, GL_DEPTH_TEST, GL_SCISSOR_TEST, follow_volume, rendering_renderer
from mipcast.mappers.stereo import draw_for

#: Sample indices are packed as ``start * INDEX_BASE + max`` into one float32
#: (exact below 2**24): rays of at most this many samples hand pass 2 the
#: start of its march; longer rays hand only the maximum's index (pass 2 then
#: marches from the ray start: same picture, more samples).
INDEX_BASE = 4096

#: GL_BLEND, GL_DEPTH_TEST, GL_SCISSOR_TEST: restored after pass 1 (its buffer changes them).
_GL_CAPS = (GL_BLEND, GL_DEPTH_TEST, GL_SCISSOR_TEST)


class DEMIPFirstPassMapper(MIPVolumeMapper):
    """Pass 1 of :class:`DEMIPTwoPassVolumeMapper`: MIP that writes sample indices, not a picture.

    Marches exactly like the one-pass DEMIP's first march
    (``shaders/demip_two_pass_first_hooks.glsl``) and writes, per pixel, the index
    of the ray's maximum and the start of the second march into its float
    render-to-image "depth" image (``shaders/demip_two_pass_store.glsl``;
    encoding in ``shaders/demip_two_pass_globals.glsl``).  Its colour image
    (the MIP picture) is not used.  Created, configured and drawn by the
    two-pass mapper; not meant to be used on its own.
    """

    BRICKS = None
    PIECES = ("mip_globals", "demip_two_pass_globals", "image_terminate", "demip_helpers",
              "sampled_loop", "demip_two_pass_first_hooks", "no_stock_sample", "mip_color",
              "demip_two_pass_store")

    def __init__(self) -> None:
        super().__init__()
        self.SetAutoAdjustSampleDistances(False)
        self.RenderToImageOn()
        self.SetDepthImageScalarTypeToFloat()

    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES` (never a readout), plus the jitter fix while jittering is on."""
        jitter = ("demip_two_pass_first_jitter",) if self.GetUseJittering() else ()
        return tuple(self.PIECES) + jitter


class DEMIPTwoPassVolumeMapper(DEMIPVolumeMapper):
    """Depth-enhanced MIP in two GPU passes, the paper's Table 2 comparison.

    Same picture and settings as :class:`~mipcast.mappers.demip.DEMIPVolumeMapper`
    (depth weight, material threshold, all four depth modes, colour sphere,
    pseudo-chromadepth, depth of the maximum, float and depth readouts); the
    work is split as in the paper: a private first pass marches each ray and
    stores, per pixel, the index of its maximum and where the second march may
    start in a float texture; this mapper's own pass reads it, marches to the
    first sample of the maximum's material and composes the colour.  Drop-in:
    :meth:`Attach` it to a volume (in a renderer); nothing else has to be
    added to the scene.

    Rules: ``AutoAdjustSampleDistances`` is off at construction and rendering
    with it on is refused (use ``SetSampleDistance``); projection ``"mip"``
    only (:meth:`SetProjection` refuses LMIP, attenuated MIP and MIDA); zero
    weights still run both passes; the first pass holds its own copy of the 3D
    texture (twice the GPU memory of one pass).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from mipcast.data_fixtures import make_fixture
    >>> mapper = DEMIPTwoPassVolumeMapper()
    >>> mapper.SetInputData(make_fixture("frontback", size=32))
    >>> mapper.SetDepthMode("eye_distance")
    >>> mapper.Attach(vtkVolume())
    >>> mapper.GetDepthMode(), mapper.GetAutoAdjustSampleDistances()
    ('eye_distance', 0)

    See docs/methods.md, section Two-pass DEMIP (what each pass does, pixel
    alignment, opaque geometry, what is copied to the first pass):
    ``docs/methods.md#two-pass-demip``.
    """

    PIECES = ("mip_globals", "demip_two_pass_globals", "demip_two_pass_fetch", "demip_helpers",
              "sampled_loop", "demip_two_pass_second_hooks", "no_stock_sample", "demip_color")
    PARAMETERS = parameter_tables.DEMIP_SETTINGS

    #: The one projection the two passes implement.
    PROJECTIONS = ("mip",)

    def __init__(self) -> None:
        super().__init__()
        self.SetAutoAdjustSampleDistances(False)
        # after MIPVolumeMapper's own check (priority 0): pass 1 draws only if it passed
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _draw_first_pass, -1.0)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, _release_first_pass, -1.0)

    def SetProjection(self, projection: str) -> None:
        """Only ``"mip"``: the other projections of the one-pass mapper are not split in two passes."""
        if projection not in self.PROJECTIONS:
            raise ValueError(
                f"projection {projection!r} is not available in two passes; valid: 'mip' "
                "(for 'lmip', 'attenuated' or 'mida' use the one-pass DEMIPVolumeMapper)")
        super().SetProjection(projection)

    def GetFirstPassMapper(self):
        """The private pass-1 mapper (``None`` before the first render)."""
        entry = object_state(self).get("first_pass")
        return None if entry is None else entry["mapper"]

    def GetTextureBytes(self) -> int:
        """GPU texture bytes: the volume twice (pass 1's mapper uploads its own copy) plus pass 1's images.

        Pass 1 renders to an image of the window's size: an RGBA8 colour
        buffer and a float32 "depth" image (4 + 4 bytes a pixel), counted once
        it has rendered (before: the two volume textures only).

        Examples
        --------
        >>> from mipcast.data_fixtures import make_fixture
        >>> mapper = DEMIPTwoPassVolumeMapper()
        >>> mapper.SetInputData(make_fixture("spheres", size=16))
        >>> mapper.GetTextureBytes() == 2 * 16 ** 3 * 4
        True
        """
        total = 2 * super().GetTextureBytes()
        entry = object_state(self).get("first_pass")
        volume = self.GetAttachedVolume()
        renderer = rendering_renderer(self, volume) if entry is not None and volume is not None else None
        if renderer is not None:
            width, height = renderer.GetSize()
            total += int(width) * int(height) * 8
        return total

    def GetRenderProblem(self):
        """As :meth:`DEMIPVolumeMapper.GetRenderProblem`, plus: no auto-adjusted sample distance."""
        problem = super().GetRenderProblem()
        if problem is None and self.GetAutoAdjustSampleDistances():
            problem = ("two-pass DEMIP needs the same samples in both passes: "
                       "AutoAdjustSampleDistances would adjust each pass's step on its own; "
                       "call SetAutoAdjustSampleDistances(False) and SetSampleDistance(d)")
        return problem

    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES`, plus DEMIP's readout piece while a float readout renders."""
        readout = ("demip_readout",) if object_state(self).get("exact_readout") else ()
        return self._with_missing(tuple(self.PIECES) + readout)

    def _push_uniforms(self, uniforms) -> None:
        super()._push_uniforms(uniforms)
        uniforms.SetUniformi("u_mc_indexBase", INDEX_BASE)
        uniforms.SetUniformf("u_mc_toImage", 1.0 if self.GetRenderToImage() else 0.0)


# -- per-frame work (observers: module functions, no reference cycles) ------------
def _draw_first_pass(mapper, event) -> None:
    """Draw pass 1 into its float image and bind that image as pass 2's ``in_depthSampler``."""
    state = object_state(mapper)
    if object_state(mapper).get("render_problem") is not None:  # MIPVolumeMapper's observer reported it
        _bind(state, state.get("shared_texture"))  # VTK still sets the sampler: keep it valid
        return
    if state.get("brick_own_draw") is not None:  # drawn in bricks (mipcast.mappers.bricked_demip): no pass 1
        return
    volume = mapper.GetAttachedVolume()
    uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
    renderer = rendering_renderer(mapper, volume)
    if renderer is None:  # drawn outside any renderer's prop list: nowhere to draw pass 1 from
        vtkOutputWindow.GetInstance().DisplayErrorText(
            f"{type(mapper).__name__}: its volume is in no renderer, so pass 1 cannot be drawn "
            "and nothing is drawn: add the volume to a renderer (renderer.AddVolume(volume))\n")
        mapper.InvokeEvent(vtkCommand.ErrorEvent)
        uniforms.SetUniformf("u_mc_refused", 1.0)
        _bind(state, state.get("shared_texture"))
        return
    entry = state.get("first_pass")
    if entry is None:
        first = DEMIPFirstPassMapper()
        first_volume = vtkVolume()
        first.Attach(first_volume)
        entry = state["first_pass"] = {"mapper": first, "volume": first_volume, "matrix": vtkMatrix4x4()}
    _copy_settings(mapper, volume, entry)
    draw_for(entry["mapper"], renderer.GetActiveCamera(), renderer)  # its eye, in stereo
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    first_uniforms = entry["volume"].GetShaderProperty().GetFragmentCustomUniforms()
    mapper._push_uniforms(first_uniforms)
    # pass 2 draws straight into the window (not into a buffer of its own) only at
    # image sample distance 1 without render-to-image (shaders/demip_two_pass_first_jitter.glsl)
    in_window = mapper.GetImageSampleDistance() == 1.0 and not mapper.GetRenderToImage()
    first_uniforms.SetUniform2f("u_mc_pass2Offset", [float(x0[0]), float(y0[0])] if in_window else [0.0, 0.0])
    # pass 1's render-to-image buffer sets the viewport to (0, 0, w, h) and turns
    # blending and the scissor test off: put back what the renderer had set
    gl_state = renderer.GetRenderWindow().GetState()
    enabled = {cap: gl_state.GetEnumState(cap) for cap in _GL_CAPS}
    entry["volume"].RenderVolumetricGeometry(renderer)
    gl_state.vtkglViewport(x0[0], y0[0], width[0], height[0])
    for cap, on in enabled.items():
        gl_state.SetEnumState(cap, on)
    texture = entry["mapper"].GetDepthTexture()
    if texture is None:  # pass 1 drew nothing (it reported why): neither does pass 2
        uniforms.SetUniformf("u_mc_refused", 1.0)
        _bind(state, state.get("shared_texture"))
        return
    mapper.SetSharedDepthTexture(texture)  # no-op when it is the same texture as last frame
    state["shared_texture"] = texture
    _bind(state, texture)


def _bind(state, texture) -> None:
    """Activate ``texture`` (a texture unit for pass 2's in_depthSampler) until the render ends."""
    if texture is not None:
        texture.Activate()
        state["bound_texture"] = texture


def _release_first_pass(mapper, event) -> None:
    texture = object_state(mapper).pop("bound_texture", None)
    if texture is not None:
        texture.Deactivate()


def _copy_settings(mapper, volume, entry) -> None:
    """Give pass 1 what decides its samples; setters only where values differ (no shader rebuilds)."""
    first, first_volume, matrix = entry["mapper"], entry["volume"], entry["matrix"]
    image = mapper.GetInput()
    if first.GetInput() is not image:
        first.SetInputData(image)
    if first.GetComponent() != mapper.GetComponent():
        first.SetComponent(mapper.GetComponent())
    if first.GetMaskInput() is not mapper.GetMaskInput():
        first.SetMaskInput(mapper.GetMaskInput())
    first.SetSampleDistance(mapper.GetSampleDistance())  # VTK's setters ignore equal values
    first.SetImageSampleDistance(mapper.GetImageSampleDistance())
    first.SetLockSampleDistanceToInputSpacing(mapper.GetLockSampleDistanceToInputSpacing())
    follow_volume(mapper, volume, first, first_volume, matrix)
    clip_uniforms.copy_clipping(mapper, first)
