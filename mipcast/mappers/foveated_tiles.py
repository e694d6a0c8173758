"""A foveated level drawn at reduced resolution in one tile of a bigger picture, seamlessly.

VTK renders a picture bigger than its window (``vtkWindowToImageFilter``
with a scale, ParaView's ``SaveScreenshot`` beyond the view's size) in
tiles: the window's ``TileScale`` and ``TileViewport``, the camera's view
angle narrowed and its window centre moved for each tile.  A foveated level
drawn with ``ImageSampleDistance = s > 1`` is VTK's reduced-resolution
render of the viewport (one ray per ``s x s`` pixels), magnified linearly
over it.  Untiled, a pixel within ``s / 2`` of a tile's inner edge blends
the last ray of its tile with the first of the next; in the tile alone
the magnification clamps to the tile's own edge rays (up to 39 greys off
next to the seams of a 2 x 2 vessel screenshot, tests/test_foveated_tiles.py).

:func:`draw_extended` draws such a level over the tile extended by one
coarse ray spacing beyond each inner edge (the whole picture's edges stay:
untiled, they clamp too), into a float framebuffer of its own, and then
draws the tile's part of it over the tile with VTK's premultiplied "over"
blending, so the rays next to the seam are those of the untiled picture.
The extension is made with VTK's own tiling: the window's tile viewport set
to the extended box (its origin is then 0), the camera's view angle (or
parallel scale) and window centre widened to match, and the level's
eccentricity uniforms rescaled to the extended box's normalised coordinates.
"""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

from vtkmodules.vtkCommonCore import VTK_FLOAT
from vtkmodules.vtkRenderingCore import vtkCamera

from mipcast.core.object_state import object_state
from mipcast.mappers.private_draw import GL_SCISSOR_TEST, draw_over, kept_texture, pixel_texture, read_depth, scissor_kept

_FAR = 1.0e30
_GL_COLOR_BUFFER_BIT, _GL_DEPTH_BUFFER_BIT = 0x4000, 0x0100
_GL_DRAW_FRAMEBUFFER = 0x8CA9


def tile_margins(renderer, viewport, spacing: float) -> Optional[tuple]:
    """(left, bottom, right, top) pixels to draw beyond the tile for a level of ray ``spacing``, or None.

    One coarse ray spacing (rounded to pixels) beyond each edge of the tile
    that lies inside the renderer's whole viewport; 0 at the whole
    picture's edges.  None when the window renders no tiles, the level is
    drawn at full resolution, or the camera is one the widening does not
    handle (an off-axis or explicit projection).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
    >>> window, renderer = vtkRenderWindow(), vtkRenderer()
    >>> window.AddRenderer(renderer)
    >>> tile_margins(renderer, (0, 0, 80, 64), 4.0) is None  # no tiles
    True
    """
    window = renderer.GetRenderWindow()
    if window is None or tuple(window.GetTileScale()) == (1, 1) or spacing <= 1.0:
        return None
    camera = renderer.GetActiveCamera()
    if camera.GetUseOffAxisProjection() or camera.GetUseExplicitProjectionTransformMatrix():
        return None
    columns, rows = window.GetSize()  # the whole picture
    tile = window.GetTileViewport()
    port = renderer.GetViewport()
    x0, y0, width, height = viewport
    left, bottom = tile[0] * columns + x0, tile[1] * rows + y0
    margin = int(round(spacing))
    margins = (margin if left > port[0] * columns + 0.5 else 0,
               margin if bottom > port[1] * rows + 0.5 else 0,
               margin if left + width < port[2] * columns - 0.5 else 0,
               margin if bottom + height < port[3] * rows - 0.5 else 0)
    return margins if any(margins) else None


def band_layer(plan, whole_plan, base_sample_distance: float = 1.0):
    """``plan`` (a tile's) with a level-0 layer casting only the silhouette band, where the whole
    picture's plan draws level 0 with the band (more than one layer) and the tile's plan left
    level 0 out (the fovea's cast range does not reach the tile); else ``plan`` itself.

    Level 0 casts the volume's silhouette band whatever the eccentricity
    (``shaders/foveated_band_dec.glsl``): untiled, it is drawn in every
    corner of the picture the band crosses.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> whole = plan_frame((0, 0, 192, 144), (0.3, 0.6), 0.1, 0.1)
    >>> tile = plan_frame((0, 0, 96, 72), (-0.4, 1.2), 0.2, 0.2)
    >>> [layer.level for layer in tile.layers], [layer.level for layer in band_layer(tile, whole).layers]
    ([2], [2, 0])
    """
    from mipcast.core.foveation import Layer, level_grid

    if len(whole_plan.layers) < 2 or whole_plan.layers[-1].level != 0 or plan.layers[-1].level == 0:
        return plan
    width, height = plan.viewport[2:]
    band = Layer(0, float(base_sample_distance), level_grid(width, height, 0, base_sample_distance), _FAR, _FAR,
                 None)
    return plan._replace(layers=tuple(plan.layers) + (band,))


def draw_extended(state: dict, renderer, viewport, margins, level_volume, plan, layer, shared_depth, draw) -> None:
    """Call ``draw()`` (one level's ``RenderVolumetricGeometry``) over the tile extended by ``margins``.

    The level is drawn into this function's float framebuffer (cleared to
    transparent black) with the tile viewport, camera and the level's
    eccentricity uniforms of the extended box, then the tile's part is
    drawn over the tile's viewport of the framebuffer bound before, blended
    as VTK blends a volume (premultiplied "over").  The level's uniforms
    are left rescaled: the caller sets them again before its next draw.
    """
    from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLFramebufferObject

    window = renderer.GetRenderWindow()
    camera = renderer.GetActiveCamera()
    left, bottom, right, top = margins
    x0, y0, width, height = viewport
    wide, high = width + left + right, height + bottom + top
    columns, rows = window.GetSize()
    tile = tuple(window.GetTileViewport())
    ex0, ey0 = tile[0] * columns + x0 - left, tile[1] * rows + y0 - bottom
    targets = state.setdefault("tile_targets", {})  # one per level size (they alternate every tile)
    entry = targets.get((wide, high))
    if entry is None or entry["window"] is not window:
        texture = pixel_texture(window)
        texture.Allocate2D(wide, high, 4, VTK_FLOAT)
        target = vtkOpenGLFramebufferObject()
        target.SetContext(window)
        window.GetState().PushFramebufferBindings()
        try:
            target.Bind()
            target.AddColorAttachment(0, texture)
            target.AddDepthAttachment()
        finally:
            window.GetState().PopFramebufferBindings()
        entry = targets[(wide, high)] = {"window": window, "texture": texture, "framebuffer": target}
    depth = _extended_depth(state, window, viewport, margins)
    level_mapper = level_volume.GetMapper()
    saved = (camera.GetWindowCenter(), camera.GetViewAngle(), camera.GetParallelScale())
    kx, ky = wide / width, high / height
    centre = saved[0]
    gl = window.GetState()
    # the extended box is cleared and drawn with the scissor test off; the test and box come back after
    with scissor_kept(window):
        gl.PushFramebufferBindings()
        try:
            # the draw framebuffer only: the level reads the scene depth from the texture given here
            entry["framebuffer"].Bind(_GL_DRAW_FRAMEBUFFER)
            entry["framebuffer"].ActivateDrawBuffer(0)
            gl.vtkglDisable(GL_SCISSOR_TEST)
            gl.vtkglViewport(0, 0, wide, high)
            gl.vtkglScissor(0, 0, wide, high)
            gl.vtkglClearColor(0.0, 0.0, 0.0, 0.0)
            gl.vtkglClearDepth(1.0)
            gl.vtkglDepthMask(True)
            gl.vtkglClear(_GL_COLOR_BUFFER_BIT | _GL_DEPTH_BUFFER_BIT)
            window.SetTileViewport(ex0 / columns, ey0 / rows, (ex0 + wide) / columns, (ey0 + high) / rows)
            camera.SetWindowCenter((centre[0] + (right - left) / width) / kx,
                                   (centre[1] + (top - bottom) / height) / ky)
            if camera.GetParallelProjection():
                camera.SetParallelScale(saved[2] * ky)
            else:
                along = kx if camera.GetUseHorizontalViewAngle() else ky
                half = math.tan(math.radians(saved[1]) / 2.0) * along
                camera.SetViewAngle(math.degrees(2.0 * math.atan(half)))
            _rescale_uniforms(level_volume, viewport, margins, plan, layer)
            level_mapper.SetSharedDepthTexture(depth)
            depth.Activate()  # a shared texture is bound by its owner while the level draws
            draw()
            depth.Deactivate()
        finally:
            level_mapper.SetSharedDepthTexture(shared_depth)
            window.SetTileViewport(*tile)
            camera.SetWindowCenter(*saved[0])
            camera.SetViewAngle(saved[1])
            camera.SetParallelScale(saved[2])
            gl.PopFramebufferBindings()
            gl.vtkglViewport(x0, y0, width, height)
    _draw_part(window, entry["texture"], viewport, margins, (wide, high))
    object_state(level_volume)["tile_margins"] = tuple(margins)


def _extended_depth(state: dict, window, viewport, margins):
    """The scene depth over the extended box as a depth texture: the tile's (read back from
    the window), far (1) in the margins, whose depth lies in other tiles."""
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject

    left, bottom, right, top = margins
    x0, y0, width, height = viewport
    wide, high = width + left + right, height + bottom + top
    depth = np.ones((high, wide), dtype=np.float32)
    depth[bottom:bottom + height, left:left + width] = read_depth(window, viewport)
    texture = kept_texture(state, "tile_depth", window)
    texture.CreateDepthFromRaw(wide, high, vtkTextureObject.Float32, VTK_FLOAT, np.ascontiguousarray(depth))
    texture.Deactivate()
    return texture


def _rescale_uniforms(level_volume, viewport, margins, plan, layer) -> None:
    """The level's gaze, aspect and eccentricity uniforms
    (:func:`mipcast.mappers.foveated_levels.set_uniforms`) in the extended box's normalised coordinates.

    An eccentricity is a distance in viewport heights: the extended box's
    are ``height / extended height`` times the tile's.
    """
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    left, bottom, right, top = margins
    x0, y0, width, height = viewport
    wide, high = width + left + right, height + bottom + top
    shrink = height / high
    gaze = plan.gaze
    uniforms.SetUniform2f("u_mc_fovGaze", [(float(gaze[0]) * width + left) / wide,
                                           (float(gaze[1]) * height + bottom) / high])
    uniforms.SetUniformf("u_mc_fovAspect", wide / high)
    uniforms.SetUniformf("u_mc_fovCastFrom", max(layer.cast_from * shrink, -_FAR))
    uniforms.SetUniformf("u_mc_fovCastTo", min(layer.cast_to * shrink, _FAR))
    uniforms.SetUniformf("u_mc_fovStart", float(plan.start) * shrink)
    uniforms.SetUniformf("u_mc_fovGain", float(plan.gain) / shrink)


def _draw_part(window, texture, viewport, margins, size) -> None:
    """Draw the tile's part of the extended level's picture over the tile's viewport, premultiplied "over"."""
    left, bottom, right, top = margins
    x0, y0, width, height = viewport
    wide, high = size
    s0, s1 = left / wide, (left + width) / wide
    t0, t1 = bottom / high, (bottom + height) / high
    tcoords = [s0, t0, s1, t0, s1, t1, s0, t1]
    verts = [-1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0]
    draw_over(window, texture, viewport, [(tcoords, verts)])


def whole_viewport(renderer, viewport):
    """(whole, to_tile, scale): the renderer's viewport in the whole picture's pixels, a function
    taking a gaze in its normalised coordinates to this tile's, and the whole viewport's height
    in tile viewport heights.  Without tiles (a window's TileScale of 1): ``viewport``, the
    identity and 1.

    A tile's pixels are the whole picture's pixels (VTK's tiles: TileScale, TileViewport), so
    eccentricities measured in the tile's viewport heights are ``scale`` times the whole
    picture's, across and up alike (the tile's aspect ratio is its own).
    """
    window = renderer.GetRenderWindow()
    sx, sy = window.GetTileScale()
    if (sx, sy) == (1, 1):
        return viewport, (lambda gaze: gaze), 1.0
    columns, rows = window.GetSize()  # the whole picture (the window's size times the tile scale)
    tile = window.GetTileViewport()
    vp = renderer.GetViewport()
    rx0, ry0 = vp[0] * columns, vp[1] * rows
    rw, rh = max((vp[2] - vp[0]) * columns, 1.0), max((vp[3] - vp[1]) * rows, 1.0)
    tx0, ty0 = tile[0] * columns, tile[1] * rows
    x0, y0, width, height = viewport

    def to_tile(gaze):
        return ((gaze[0] * rw + rx0 - tx0 - x0) / width, (gaze[1] * rh + ry0 - ty0 - y0) / height)

    whole = (int(round(rx0)), int(round(ry0)), int(round(rw)), int(round(rh)))
    return whole, to_tile, rh / height


def whole_camera(camera, renderer):
    """The camera of the whole picture while a tile renders: vtkWindowToImageFilter narrows the
    view angle (``2 atan(tan(a / 2) / scale)``) or the parallel scale by the tile scale and moves
    the window centre for each tile; undone here (the whole picture's window centre taken as
    the middle)."""
    scale = float(renderer.GetRenderWindow().GetTileScale()[1])
    whole = vtkCamera()
    whole.DeepCopy(camera)
    whole.SetWindowCenter(0.0, 0.0)
    if camera.GetParallelProjection():
        whole.SetParallelScale(camera.GetParallelScale() * scale)
    else:
        half = math.tan(math.radians(camera.GetViewAngle()) / 2.0) * scale
        whole.SetViewAngle(math.degrees(2.0 * math.atan(half)))
    return whole
