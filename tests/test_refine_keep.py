"""Progressive refinement keeps what it has: still frames cast level 0 only outside the last frame's exact disc.

Every picture is compared with the method at full quality in its own view,
pixel for pixel and alpha too; the rays come from ``GetLastFrameCost``.
"""
import numpy as np
import pytest
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture
from mipcast.mappers import refine_keep
from mipcast.offscreen import OffscreenView
from test_progressive import SIZE, _pair

FRAMES = 3


@pytest.fixture(scope="module")
def vessels():
    return make_fixture("vessels", size=32)


def _grab(view):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkUnsignedCharArray

    pixels = vtkUnsignedCharArray()
    width, height = view.render_window.GetSize()
    view.render_window.GetRGBACharPixelData(0, 0, width - 1, height - 1, 0, pixels)
    return vtk_to_numpy(pixels).reshape(height, width, 4)[::-1].astype(int)


def _views(image, method, multisamples=0, tolerance=0.0):
    full, fov = _pair(image, method, FRAMES)
    fov.mapper.SetContentTolerance(tolerance)
    for view in (full, fov):
        view.render_window.SetMultiSamples(multisamples)
    return full, fov


def _frames(fov, count):
    """(step, rays, the radius of the last frame's disc kept: -inf for none) of ``count`` renders."""
    out = []
    for _ in range(count):
        fov.render_window.Render()
        kept = object_state(fov.mapper)["frame"]["kept"]
        out.append((fov.mapper.GetRefinementStep(), fov.mapper.GetLastFrameCost()["rays"],
                    -np.inf if kept is None else kept.radius))
    return out


def _sphere(view, image, position=(0.0, 0.0, 0.0)):
    source = vtkSphereSource()
    source.SetRadius(4.0)
    source.SetCenter(image.GetCenter())
    mapper = vtkPolyDataMapper()
    mapper.SetInputConnection(source.GetOutputPort())
    actor = vtkActor()
    actor.SetMapper(mapper)
    actor.SetPosition(*position)
    view.renderer.AddActor(actor)
    return actor


@pytest.mark.parametrize("method", ["mip", "analytic", "demip"])
def test_still_frames_cast_only_what_is_not_yet_full_quality(vessels, method, monkeypatch):
    full, fov = _views(vessels, method)
    full.render_window.Render()
    reference = _grab(full)
    frames = _frames(fov, FRAMES + 3)
    full_rays = fov.mapper.GetLastFrameCost()["full_rays"]
    steps, rays, skips = zip(*frames)
    assert steps == (0, 1, 2, 3, 3, 3), frames
    assert skips[0] == -np.inf and all(b > a for a, b in zip(skips[1:4], skips[2:4])), frames  # a wider disc kept
    assert np.array_equal(_grab(fov), reference)  # bit for bit, alpha too
    # the same frames casting every ray again (as before): each still frame cast more, the last one
    # and every later still frame all of full quality's rays; kept, the converged view casts none
    monkeypatch.setattr(refine_keep, "kept_disc", lambda *args: None)
    _, again = _views(vessels, method)
    steps_again, rays_again, _ = zip(*_frames(again, FRAMES + 3))
    assert steps_again == steps and np.array_equal(_grab(again), reference)
    assert all(r < r_again for r, r_again in zip(rays[1:], rays_again[1:])), (rays, rays_again)
    assert rays_again[3:] == (full_rays,) * 3 and rays[4:] == (0, 0), (rays, rays_again, full_rays)


def test_the_kept_disc_is_full_quality_at_every_step(vessels):
    """Each still frame's picture inside the disc it keeps for the next equals full quality."""
    full, fov = _views(vessels, "mip")
    full.render_window.Render()
    reference = _grab(full)
    for _ in range(FRAMES):
        fov.render_window.Render()
        plan = fov.mapper.GetLastPlan()
        radius = refine_keep.exact_radius(plan)
        ys, xs = np.mgrid[0:SIZE[1], 0:SIZE[0]]
        at_x, at_y = (xs + 0.5) / SIZE[0], (SIZE[1] - 1 - ys + 0.5) / SIZE[1]
        inside = np.hypot((at_x - plan.gaze[0]) * plan.aspect, at_y - plan.gaze[1]) < radius - 1e-3
        assert inside.sum() > 50 and np.array_equal(_grab(fov)[inside], reference[inside]), radius


def test_multisampling_and_an_opaque_object_moved_after_convergence(vessels):
    """With 8x MSAA and a sphere in the volume: converged bit for bit; moving the sphere (nothing the
    refinement signature sees) is not answered with the kept picture."""
    full, fov = _views(vessels, "mip", multisamples=8)
    actors = [_sphere(view, vessels) for view in (full, fov)]
    full.render_window.Render()
    frames = _frames(fov, FRAMES + 2)
    assert np.array_equal(_grab(fov), _grab(full)) and frames[-1][1] == 0, frames
    for actor in actors:
        actor.SetPosition(6.0, 0.0, 0.0)
    full.render_window.Render()
    step, rays, skip = _frames(fov, 1)[0]
    assert np.array_equal(_grab(fov), _grab(full)) and rays > 0 and skip == -np.inf, (step, rays, skip)
    assert _frames(fov, 1)[0][1] == 0 and np.array_equal(_grab(fov), _grab(full))  # then kept again


def test_content_adaptive_frame_then_acuity_only_still_frames(vessels):
    """The foveated frame keeps its content-adaptive mask; the still frames cast acuity-only levels,
    whose fovea is full quality for the next frame to keep."""
    full, fov = _views(vessels, "mip", tolerance=2.0)
    full.render_window.Render()
    frames = _frames(fov, 1)
    passes = object_state(fov.mapper).get("refine_passes", 0)
    frames += _frames(fov, FRAMES + 1)
    assert passes > 0 and object_state(fov.mapper)["refine_passes"] == passes  # only the foveated frame built masks
    assert frames[2][2] > 0 and frames[-1][1] == 0 and np.array_equal(_grab(fov), _grab(full)), frames


@pytest.mark.parametrize("stereo", ["Anaglyph", "SplitViewportHorizontal"])
def test_each_eye_of_a_stereo_pair_keeps_its_own_picture(vessels, stereo):
    full, fov = _views(vessels, "mip")
    for view in (full, fov):
        getattr(view.render_window, f"SetStereoTypeTo{stereo}")()
        view.render_window.StereoRenderOn()
    full.render_window.Render()
    rays = []  # each eye's rays (the cost of its draw, read right after it)
    fov.mapper.AddObserver("VolumeMapperRenderEndEvent",
                           lambda *_: rays.append(fov.mapper.GetLastFrameCost()["rays"]), -2.0)
    for _ in range(FRAMES + 2):
        rays.clear()
        fov.render_window.Render()
    assert np.array_equal(_grab(fov), _grab(full)) and rays == [0, 0], rays  # both eyes kept, bit for bit
    kept = object_state(fov.mapper)["kept_pictures"]
    assert sorted(kept) == [0, 1] and kept[0]["texture"] is not kept[1]["texture"]


def test_a_clipping_plane_or_mapper_setting_changed_after_convergence_is_drawn(vessels):
    """Neither a moved clipping plane nor VTK's sample distance is part of the refinement signature:
    the still frame after either casts its rays again instead of keeping the old picture."""
    from vtkmodules.vtkCommonDataModel import vtkPlane

    full, fov = _views(vessels, "mip")
    planes = []
    for view in (full, fov):
        plane = vtkPlane()
        plane.SetOrigin(vessels.GetCenter())
        plane.SetNormal(1.0, 0.3, 0.0)
        view.mapper.AddClippingPlane(plane)
        planes.append(plane)
    full.render_window.Render()
    assert _frames(fov, FRAMES + 2)[-1][1] == 0 and np.array_equal(_grab(fov), _grab(full))
    for plane in planes:
        plane.SetOrigin(vessels.GetCenter()[0] + 5.0, *vessels.GetCenter()[1:])
    full.render_window.Render()
    step, rays, _ = _frames(fov, 1)[0]
    assert step == FRAMES and rays > 0 and np.array_equal(_grab(fov), _grab(full))
    for view in (full, fov):
        view.mapper.SetSampleDistance(view.mapper.GetSampleDistance() * 2.0)
    full.render_window.Render()
    step, rays, _ = _frames(fov, 1)[0]
    assert step == FRAMES and rays > 0 and np.array_equal(_grab(fov), _grab(full))
    assert _frames(fov, 1)[0][1] == 0 and np.array_equal(_grab(fov), _grab(full))  # then kept again


def test_a_gaze_moved_within_the_fovea_keeps_the_overlap_of_the_two_full_quality_discs(vessels):
    """A pursuit-like move keeps the pixels both frames draw at full quality: the picture is the one
    a fresh view at the new gaze draws, bit for bit, with fewer rays; a jump past the fovea keeps none."""
    fov = OffscreenView(vessels, "foveated", size=(96, 96))
    fov.mapper.SetFovealRadius(0.3)
    fov.mapper.SetGazePoint(0.45, 0.5)
    fov.render_window.Render()
    for gaze, overlaps in (((0.5, 0.52), True), ((0.95, 0.05), False)):
        fov.mapper.SetGazePoint(*gaze)
        fov.render_window.Render()
        fresh = OffscreenView(vessels, "foveated", size=(96, 96))
        fresh.mapper.SetFovealRadius(0.3)
        fresh.mapper.SetGazePoint(*gaze)
        fresh.render_window.Render()
        rays, fresh_rays = fov.mapper.GetLastFrameCost()["rays"], fresh.mapper.GetLastFrameCost()["rays"]
        kept = object_state(fov.mapper)["frame"]["kept"]
        assert np.array_equal(_grab(fov), _grab(fresh)), gaze
        assert (kept is not None and rays < 0.8 * fresh_rays) if overlaps else (kept is None and rays == fresh_rays), (
            gaze, kept, rays, fresh_rays)


def test_a_subplot_converges_bit_for_bit(vessels):
    """A renderer whose viewport is not at the window's corner, beside another renderer: the copy, the
    skip and the keep pass work in its viewport (this once kept the stale rays of a reduced level,
    test_foveation_overhead), and the other renderer's pixels are untouched."""
    from vtkmodules.vtkRenderingCore import vtkRenderer

    full, fov = _views(vessels, "mip")
    for view in (full, fov):
        view.renderer.SetViewport(0.4, 0.2, 1.0, 1.0)
        other = vtkRenderer()
        other.SetViewport(0.0, 0.0, 0.4, 1.0)
        other.SetBackground(0.2, 0.3, 0.4)
        view.render_window.AddRenderer(other)
    full.render_window.Render()
    frames = _frames(fov, FRAMES + 2)
    assert frames[-1][1] == 0 and frames[2][2] > 0, frames
    assert np.array_equal(_grab(fov), _grab(full))


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_multisampling_in_a_view_grazing_a_face_converges_bit_for_bit(vessels, method):
    """A face met at a grazing angle (3 degrees above the box's top face: a sine of 0.005) with 8x MSAA: the
    window's draw keeps the starts VTK puts in front of the box (silhouette pixels), and so do the levels'
    private draws, which take the window's multisampling (mipcast.mappers.stereo.draw_for); moving theirs
    left mip's converged picture 4 pixels up to 8 levels off full quality."""
    from test_bricked_mapper import _grazing

    full, fov = _views(vessels, method, multisamples=8)
    for view in (full, fov):
        _grazing(view.renderer, vessels)
    assert 0.0 < fov.mapper._entry_moves(fov.volume) < 2.0  # a face near edge-on, MSAA: only starts behind
    full.render_window.Render()
    frames = _frames(fov, FRAMES + 2)
    assert frames[-1][0] == FRAMES and np.array_equal(_grab(fov), _grab(full)), frames
