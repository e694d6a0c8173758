"""Foveation overheads removed (issue 17): level 0's scissor box when the band misses the view; the refine pass."""
import numpy as np

from mipcast.bench.foveation_bench import framed_view
from mipcast.bench.benchmark import apply_settings
from mipcast.core import foveation
from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture


def test_band_reaches_view_is_exact_against_the_band_on_the_pixels():
    """Where band_reaches_view says no, no pixel of any level-0 grid is in the silhouette band."""
    rng = np.random.default_rng(7)
    said_no = said_yes = 0
    for _ in range(200):
        aspect = float(rng.uniform(0.5, 2.0))
        centre = rng.uniform(-0.5, 1.5, 2)
        points = centre + rng.uniform(-2.5, 2.5, (8, 2))
        edges = foveation.silhouette_edges(points, aspect)
        if edges is None:
            continue
        height = 48
        width = max(1, round(height * aspect))
        plan = foveation.plan_frame((0, 0, width, height), tuple(rng.uniform(0, 1, 2)), 0.1, 0.2)
        silhouette = (edges, 1.0 / height)
        band = foveation.silhouette_band(plan, silhouette, (width, height))
        if not foveation.band_reaches_view(silhouette, plan.aspect):
            said_no += 1
            assert not band.any()
        else:
            said_yes += 1
    assert said_no > 10 and said_yes > 10  # both answers exercised


def test_a_filled_view_keeps_level_0_in_its_box_and_gpu_masks_use_the_refine_pass():
    view = framed_view(make_fixture("vessels", size=32), "foveated", 96, "fill", (0.25, 1.0))
    apply_settings(view.mapper, (("Method", "mip"), ("ContentTolerance", 2.0), ("GazePoint", (0.5, 0.5))))
    picture = view.screenshot()
    assert picture.max() > 100, "something drawn"
    state = object_state(view.mapper)
    frame = state["frame"]
    assert frame["silhouette"] is not None
    assert not foveation.band_reaches_view(frame["silhouette"], frame["plan"].aspect)
    assert state.get("refine_passes", 0) >= 1
    view.render_window.Finalize()


def test_reduced_gpu_masked_levels_in_their_box_keep_no_rays_of_earlier_frames():
    """The GPU-masked reduced levels draw in the plan's scissor box (VTK clears its reduced buffer under
    that box only): after the gaze moves, the picture equals a fresh view's at the new gaze."""
    image = make_fixture("vessels", size=32)
    settings = (("Method", "mip"), ("ContentTolerance", 2.0))

    def view_at(gaze):
        view = framed_view(image, "foveated", 96, "fill", (0.25, 1.0))
        apply_settings(view.mapper, settings + (("GazePoint", gaze),))
        return view

    moving = view_at((0.85, 0.85))
    moving.screenshot()
    for gaze in ((0.15, 0.2), (0.8, 0.25), (0.5, 0.5)):
        moving.mapper.SetGazePoint(*gaze)
        picture = moving.screenshot()
        fresh = view_at(gaze)
        assert np.array_equal(picture, fresh.screenshot()), gaze
        assert picture.max() > 100, "something drawn"
        frame = object_state(moving.mapper)["frame"]
        boxed = [layer for layer in frame["plan"].layers[1:]
                 if layer.image_sample_distance != 1.0 and layer.scissor is not None]
        assert boxed, "a reduced GPU-masked level drawn in a scissor box"
        fresh.render_window.Finalize()
    assert object_state(moving.mapper).get("refine_passes", 0) >= 1
    moving.render_window.Finalize()


def test_a_viewport_away_from_the_window_corner_keeps_no_rays_of_earlier_frames():
    """A subplot (a renderer's viewport not at the window's lower left corner): VTK clears a reduced
    level's buffer under the renderer's box, which starts at the viewport's corner, while the buffer's
    texels count from its own corner; the coarsest level (no box of its own) left the last frame's rays
    below and left of it, stretched into the picture after a gaze move (255 grey off). Now its box
    starts at the window's origin: the picture equals a fresh view's at the new gaze."""
    from mipcast.offscreen import OffscreenView

    image = make_fixture("vessels", size=32)
    for tolerance in (0.0, 2.0):
        def view_at(gaze):
            view = OffscreenView(image, "foveated", size=(120, 64))
            view.renderer.SetViewport(0.4, 0.2, 1.0, 1.0)
            apply_settings(view.mapper, (("ContentTolerance", tolerance), ("GazePoint", gaze)))
            return view

        moving = view_at((0.3, 0.6))
        moving.screenshot()
        moving.mapper.SetGazePoint(0.7, 0.4)
        picture = moving.screenshot()
        assert picture.max() > 100 and np.array_equal(picture, view_at((0.7, 0.4)).screenshot()), tolerance


def test_a_pixel_read_mid_frame_leaves_the_scissor_box_to_the_draws_after_it():
    """VTK's pixel reads turn the scissor test off and leave it off; mipcast's mid-frame reads (the CPU masks'
    picture, a bricked frame's depth) keep it: every level of a CPU-masked content-adaptive frame draws in its
    box (before, every level after the read covered the whole view: level 0 drew 4x its box's pixels, a 1024²
    frame of the vessels 308 -> 224 ms)."""
    from vtkmodules.vtkCommonCore import vtkCommand, vtkUnsignedCharArray

    from mipcast.mappers.private_draw import GL_SCISSOR_BOX, GL_SCISSOR_TEST, scissor_kept

    view = framed_view(make_fixture("vessels", size=32), "foveated", 96, "fill", (0.25, 1.0))
    apply_settings(view.mapper, (("Method", "mip"), ("ContentTolerance", 2.0), ("GazePoint", (0.5, 0.5))))
    object_state(view.mapper)["masks_on_cpu"] = True
    window = view.render_window
    window.Render()
    gl_state = window.GetState()
    seen = []

    def note(mapper, event):
        box = [0, 0, 0, 0]
        gl_state.vtkglGetIntegerv(GL_SCISSOR_BOX, box)
        seen.append((mapper.GetImageSampleDistance(), bool(gl_state.GetEnumState(GL_SCISSOR_TEST)), box))

    for entry in object_state(view.mapper)["levels_drawn"].values():
        entry["mapper"].AddObserver(vtkCommand.VolumeMapperRenderStartEvent, note, 10.0)
    assert view.screenshot().max() > 100, "something drawn"
    assert len(seen) >= 4 and all(enabled for _, enabled, _ in seen), seen
    level_0_boxes = [box for isd, _, box in seen if isd == 1.0]
    assert level_0_boxes and all(box[2] < 96 and box[3] < 96 for box in level_0_boxes), seen
    # the helper itself: VTK's read turns the test off, scissor_kept brings it and the box back
    gl_state.vtkglEnable(GL_SCISSOR_TEST)
    gl_state.vtkglScissor(3, 4, 20, 30)
    window.GetRGBACharPixelData(0, 0, 9, 9, 0, vtkUnsignedCharArray())
    assert not gl_state.GetEnumState(GL_SCISSOR_TEST)
    gl_state.vtkglEnable(GL_SCISSOR_TEST)
    with scissor_kept(window):
        window.GetRGBACharPixelData(0, 0, 9, 9, 0, vtkUnsignedCharArray())
    box = [0, 0, 0, 0]
    gl_state.vtkglGetIntegerv(GL_SCISSOR_BOX, box)
    assert gl_state.GetEnumState(GL_SCISSOR_TEST) and box == [3, 4, 20, 30]
    window.Finalize()
