"""Private mappers drawn inside a mipcast mapper's render (foveation levels, DEMIP's first pass).

A mapper that draws other mappers of its own needs two things: the renderer
drawing it right now (a volume can be in several), and its private volumes
seeing what the user's volume sees (property, matrix, cropping, clipping,
jittering).  Setters are called only where values differ, so no shader is
rebuilt and no texture re-uploaded from frame to frame.
"""
from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator, Optional

import numpy as np
from vtkmodules.vtkCommonCore import vtkCommand, vtkWeakReference
from vtkmodules.vtkRenderingCore import vtkRenderer

from mipcast.core.object_state import object_state


def rendering_renderer(mapper, volume) -> Optional[vtkRenderer]:
    """The renderer drawing ``volume`` now: its only consumer, or the one whose render started last.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> rendering_renderer(None, vtkVolume()) is None
    True
    """
    renderers = [volume.GetConsumer(i) for i in range(volume.GetNumberOfConsumers())]
    renderers = [r for r in renderers if isinstance(r, vtkRenderer)]
    if len(renderers) <= 1:
        return renderers[0] if renderers else None
    state = object_state(mapper)
    hooked = state.setdefault("hooked_renderers", set())
    link = vtkWeakReference()
    link.Set(mapper)
    for renderer in renderers:
        key = renderer.GetAddressAsString("vtkObjectBase")
        if key not in hooked:
            renderer.AddObserver(vtkCommand.StartEvent, _make_start_hook(link))
            hooked.add(key)
    current = state.get("current_renderer")
    current = current.Get() if current is not None else None
    return current if any(current is r for r in renderers) else renderers[0]


def _make_start_hook(mapper_link):
    def started(renderer, event):
        mapper = mapper_link.Get()
        if mapper is not None:
            link = vtkWeakReference()
            link.Set(renderer)
            object_state(mapper)["current_renderer"] = link
    return started


def follow_volume(mapper, volume, private_mapper, private_volume, matrix) -> None:
    """Give a private mapper/volume the user's jittering, cropping, clipping, property and matrix.

    ``matrix`` is a vtkMatrix4x4 owned by the caller for this private
    volume: the user's volume matrix is copied into it only when it changed.

    Examples
    --------
    >>> from vtkmodules.vtkCommonMath import vtkMatrix4x4
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper
    >>> user, own = vtkVolume(), vtkVolume()
    >>> user.SetPosition(1.0, 2.0, 3.0)
    >>> matrix = vtkMatrix4x4()
    >>> follow_volume(vtkOpenGLGPUVolumeRayCastMapper(), user, vtkOpenGLGPUVolumeRayCastMapper(), own, matrix)
    >>> own.GetMatrix().GetElement(1, 3), own.GetProperty() is user.GetProperty()
    (2.0, True)
    """
    private_mapper.SetUseJittering(mapper.GetUseJittering())  # VTK's setters ignore equal values
    private_mapper.SetCropping(mapper.GetCropping())
    private_mapper.SetCroppingRegionPlanes(mapper.GetCroppingRegionPlanes())
    private_mapper.SetCroppingRegionFlags(mapper.GetCroppingRegionFlags())
    if private_mapper.GetClippingPlanes() is not mapper.GetClippingPlanes():
        private_mapper.SetClippingPlanes(mapper.GetClippingPlanes())
    if private_volume.GetProperty() is not volume.GetProperty():
        private_volume.SetProperty(volume.GetProperty())
    current = volume.GetMatrix()
    if any(matrix.GetElement(r, c) != current.GetElement(r, c) for r in range(4) for c in range(4)):
        matrix.DeepCopy(current)
        private_volume.SetUserMatrix(matrix)
    elif private_volume.GetUserMatrix() is not matrix:
        private_volume.SetUserMatrix(matrix)


#: OpenGL enums the private draws set state with (vtkOpenGLState takes plain numbers).
GL_BLEND, GL_DEPTH_TEST, GL_SCISSOR_TEST = 0x0BE2, 0x0B71, 0x0C11
GL_ONE, GL_ONE_MINUS_SRC_ALPHA = 1, 0x0303
GL_READ_FRAMEBUFFER, GL_DRAW_FRAMEBUFFER, GL_COLOR_BUFFER_BIT, GL_NEAREST = 0x8CA8, 0x8CA9, 0x4000, 0x2600
GL_SCISSOR_BOX = 0x0C10


def scissor_from_origin(window) -> Optional[list]:
    """Widen an enabled scissor box that leaves out the window's origin to one from it; return the box replaced.

    VTK's ray caster at an image sample distance above 1 draws into a
    reduced buffer whose texels count from the buffer's corner, and clears
    it under the current scissor box, in window pixels.  A renderer whose
    viewport is not at the window's lower left corner (a subplot) sets a box
    starting at its corner, so the buffer's texels below and left of it kept
    the last frame's rays, stretched into the picture after the camera or
    the gaze moved (255 grey off a fresh view).  A box holding the origin
    and the old box holds both; drawing stays within the viewport (the
    reduced buffer is stretched over the viewport only).  None: the box
    already held the origin, or the scissor test is off.
    """
    gl_state = window.GetState()
    if not gl_state.GetEnumState(GL_SCISSOR_TEST):
        return None
    box = [0, 0, 0, 0]
    gl_state.vtkglGetIntegerv(GL_SCISSOR_BOX, box)
    if box[0] <= 0 and box[1] <= 0:
        return None
    gl_state.vtkglScissor(0, 0, box[0] + box[2], box[1] + box[3])
    return box


@contextmanager
def scissor_kept(window) -> Iterator[None]:
    """Within: the window's scissor test and box come back as they were.

    VTK's pixel reads (``vtkOpenGLRenderWindow.ReadPixels`` under
    ``GetRGBACharPixelData``, ``GetZbufferData``) turn the scissor test off
    and leave it off: a read in the middle of a frame let every later draw
    of it cover the whole viewport instead of its box (content-adaptive
    levels on the CPU path: level 0 at 1024² drew 4 times the pixels of
    its box).
    """
    gl_state = window.GetState()
    enabled = gl_state.GetEnumState(GL_SCISSOR_TEST)
    box = [0, 0, 0, 0]
    gl_state.vtkglGetIntegerv(GL_SCISSOR_BOX, box)
    try:
        yield
    finally:
        if enabled:
            gl_state.vtkglEnable(GL_SCISSOR_TEST)
        else:
            gl_state.vtkglDisable(GL_SCISSOR_TEST)
        gl_state.vtkglScissor(*box)


def read_depth(window, viewport) -> np.ndarray:
    """The window's depth buffer over ``viewport`` (x0, y0, width, height): (height, width) float32, bottom
    row first; the scissor test and box kept (:func:`scissor_kept`), so the draws after it keep their boxes.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.offscreen import OffscreenView
    >>> view = OffscreenView(make_fixture("spheres", size=8), "mip", size=(16, 12))
    >>> view.render_window.Render()
    >>> read_depth(view.render_window, (0, 0, 16, 12)).shape
    (12, 16)
    """
    x0, y0, width, height = viewport
    depth = np.empty(width * height, dtype=np.float32)
    with scissor_kept(window):
        window.GetZbufferData(x0, y0, x0 + width - 1, y0 + height - 1, depth)
    return depth.reshape(height, width)


def read_rgba(window, viewport) -> np.ndarray:
    """The window's picture over ``viewport`` (x0, y0, width, height): (height, width, 4) uint8, bottom row
    first; the scissor test and box kept (:func:`scissor_kept`).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.offscreen import OffscreenView
    >>> view = OffscreenView(make_fixture("spheres", size=8), "mip", size=(16, 12))
    >>> view.render_window.Render()
    >>> read_rgba(view.render_window, (0, 0, 16, 12)).shape
    (12, 16, 4)
    """
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkUnsignedCharArray

    x0, y0, width, height = viewport
    pixels = vtkUnsignedCharArray()
    with scissor_kept(window):
        window.GetRGBACharPixelData(x0, y0, x0 + width - 1, y0 + height - 1, 0, pixels)
    return vtk_to_numpy(pixels).reshape(height, width, 4)


def pixel_texture(window):
    """A new 2D ``vtkTextureObject`` on ``window`` read texel for texel: nearest filtering, clamped edges.

    For the pictures and masks the private draws hand to a shader or draw
    over a viewport (one texel per pixel or per ray).
    """
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject

    texture = vtkTextureObject()
    texture.SetContext(window)
    texture.SetMinificationFilter(vtkTextureObject.Nearest)
    texture.SetMagnificationFilter(vtkTextureObject.Nearest)
    texture.SetWrapS(vtkTextureObject.ClampToEdge)
    texture.SetWrapT(vtkTextureObject.ClampToEdge)
    return texture


def kept_texture(store: dict, key, window):
    """``store[key]``: a :func:`pixel_texture` on ``window``, made anew when missing or of another window.

    Kept between frames, so VTK's copy program for it compiles once.
    """
    texture = store.get(key)
    if texture is None or texture.GetContext() is not window:
        texture = pixel_texture(window)
        store[key] = texture
    return texture


def texture_target(window, width: int, height: int) -> tuple:
    """(texture, framebuffer): a new RGBA8 :func:`pixel_texture` of ``width`` x ``height`` and a framebuffer drawing into it.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> window = vtkRenderWindow(); window.SetOffScreenRendering(True); window.AddRenderer(vtkRenderer())
    >>> window.SetSize(8, 8); window.Render()
    >>> texture, framebuffer = texture_target(window, 6, 4)
    >>> texture.GetWidth(), texture.GetHeight(), framebuffer.GetNumberOfColorAttachments()
    (6, 4, 1)
    """
    from vtkmodules.vtkCommonCore import VTK_UNSIGNED_CHAR
    from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLFramebufferObject

    texture = pixel_texture(window)
    texture.Allocate2D(int(width), int(height), 4, VTK_UNSIGNED_CHAR)
    framebuffer = vtkOpenGLFramebufferObject()
    framebuffer.SetContext(window)
    gl_state = window.GetState()
    gl_state.PushFramebufferBindings()
    try:
        framebuffer.Bind()  # creates it: attachments go only to an existing framebuffer
        framebuffer.AddColorAttachment(0, texture)
    finally:
        gl_state.PopFramebufferBindings()
    return texture, framebuffer


def copy_drawn(renderer, viewport, framebuffer) -> None:
    """Copy the viewport of the framebuffer being drawn into ``framebuffer`` (a :func:`texture_target`) on the GPU.

    A framebuffer blit (resolving a multisampled framebuffer as
    ``glReadPixels`` does), the scissor test off while it runs; no readback.
    """
    from vtkmodules.vtkCommonCore import reference

    window = renderer.GetRenderWindow()
    gl_state = window.GetState()
    binding, buffer = reference(0), reference(0)
    gl_state.GetCurrentDrawFramebufferState(binding, buffer)
    with scissor_kept(window):
        gl_state.PushFramebufferBindings()
        try:
            gl_state.vtkglBindFramebuffer(GL_READ_FRAMEBUFFER, int(binding))
            gl_state.vtkglReadBuffer(int(buffer))
            framebuffer.Bind(GL_DRAW_FRAMEBUFFER)
            framebuffer.ActivateDrawBuffer(0)
            gl_state.vtkglDisable(GL_SCISSOR_TEST)
            x0, y0, width, height = viewport
            gl_state.vtkglBlitFramebuffer(x0, y0, x0 + width, y0 + height, 0, 0, width, height,
                                          GL_COLOR_BUFFER_BIT, GL_NEAREST)
        finally:
            gl_state.PopFramebufferBindings()


def draw_over(window, texture, viewport, quads=None, depth: bool = False, depth_test: bool = False) -> None:
    """Draw ``texture`` over ``viewport`` (x, y, width, height) with premultiplied "over" blending.

    ``quads``: (texture coordinates, NDC vertices) pairs as
    ``vtkTextureObject.CopyToFrameBuffer`` takes them, or None for the whole
    viewport.  ``depth``: depth-test and write the quad's depth (window depth
    0.5); ``depth_test``: depth-test the quads' own depth (their vertices' NDC
    z) without writing it; else neither.  The GL state is restored afterwards.
    """
    x, y, width, height = viewport
    gl = window.GetState()
    gl.Push()
    try:
        gl.vtkglViewport(x, y, width, height)
        gl.vtkglScissor(x, y, width, height)
        gl.vtkglEnable(GL_BLEND)
        gl.vtkglBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA)
        if depth or depth_test:
            gl.vtkglEnable(GL_DEPTH_TEST)
        else:
            gl.vtkglDisable(GL_DEPTH_TEST)
        gl.vtkglDepthMask(depth)
        if quads is None:
            texture.CopyToFrameBuffer(None, None)
        else:
            for tcoords, verts in quads:
                texture.CopyToFrameBuffer(tcoords, verts, None, None)
    finally:
        gl.Pop()


def auto_sample_distance(image, volume) -> float:
    """VTK's auto-adjusted sample distance at full time: the smallest world spacing of ``image`` drawn by ``volume``.

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> image = vtkImageData()
    >>> image.SetSpacing(2.0, 0.5, 1.0)
    >>> volume = vtkVolume()
    >>> volume.SetScale(1.0, 3.0, 1.0)
    >>> auto_sample_distance(image, volume)
    1.0
    """
    import numpy as np

    from mipcast.core.camera_rays import matrix_array

    matrix = matrix_array(volume.GetMatrix())[:3, :3]
    direction = matrix_array(image.GetDirectionMatrix())
    columns = matrix @ direction
    return min(abs(s) * float(np.linalg.norm(columns[:, i])) for i, s in enumerate(image.GetSpacing()))
