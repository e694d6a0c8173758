"""Progressive refinement: still frames converge to full quality (bit for bit / float rounding); a change resets."""
import numpy as np
import pytest

from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

SIZE = (80, 64)


@pytest.fixture(scope="module")
def vessels():
    return make_fixture("vessels", size=32)


def _pair(image, method, frames=3):
    full = OffscreenView(image, method, size=SIZE)
    fov = OffscreenView(image, "foveated", size=SIZE)
    fov.mapper.SetMethod(method)
    fov.mapper.SetGazePoint(0.3, 0.6)
    fov.mapper.SetRefinementFrames(frames)
    fov.mapper.SetProgressive(True)
    return full, fov


def _grab(view):
    """The last rendered picture, without rendering again."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkUnsignedCharArray

    pixels = vtkUnsignedCharArray()
    width, height = SIZE
    view.render_window.GetRGBACharPixelData(0, 0, width - 1, height - 1, 0, pixels)
    return vtk_to_numpy(pixels).reshape(height, width, 4)[::-1, :, :3]


def test_still_frames_refine_until_the_picture_is_full_quality_bit_for_bit(vessels):
    full, fov = _pair(vessels, "mip", frames=3)
    full.render_window.Render()
    reference = _grab(full)
    errors, layers = [], []
    for _ in range(4):
        fov.render_window.Render()
        errors.append(int(np.abs(_grab(fov).astype(int) - reference).max()))
        layers.append(len(fov.mapper.GetLastPlan().layers))
    # foveated, then refining (here the second frame's wider fovea and the silhouette band, which
    # level 0 casts, already leave no difference: its plan still has the coarser levels)
    assert errors[0] > 20 and errors[1] <= errors[0] and layers[1] > 1, (errors, layers)
    assert errors[3] == 0 and np.array_equal(_grab(fov), reference)  # frame 3 of 3: full quality
    assert fov.mapper.GetRefinementStep() == 3 and not fov.mapper.NeedsRefinement()
    fov.camera.Azimuth(5.0)  # any change drops back to the foveated frame
    full.camera.Azimuth(5.0)
    fov.render_window.Render()
    full.render_window.Render()
    assert fov.mapper.GetRefinementStep() == 0 and fov.mapper.NeedsRefinement()
    assert np.abs(_grab(fov).astype(int) - _grab(full)).max() > 20
    fov.mapper.SetGazePoint(0.6, 0.6)  # so does a gaze move
    fov.render_window.Render()
    fov.render_window.Render()
    assert fov.mapper.GetRefinementStep() == 1
    # the refinement's property stamp reads the user's property and creates nothing on it (it once
    # made a gradient-opacity function, which every later packed exact draw then had: OpenGL errors)
    assert not fov.volume.GetProperty().HasGradientOpacity(0)


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_a_discretizable_colour_map_refines_from_the_second_frame(vessels, method):
    # ParaView's colour maps rebuild their table at the first lookup after a change, which moves their
    # MTime; the skipping floor looks colours up during the frame, so the next frame saw a changed
    # property and started over once (the ParaView GUI took 5 frames to converge, not 4)
    from vtkmodules.vtkRenderingCore import vtkDiscretizableColorTransferFunction

    _, fov = _pair(vessels, method, frames=3)
    grey = fov.volume.GetProperty().GetRGBTransferFunction(0)
    colours = vtkDiscretizableColorTransferFunction()
    colours.DeepCopy(grey)
    fov.volume.GetProperty().SetColor(colours)
    steps = []
    for _ in range(4):
        fov.render_window.Render()
        steps.append(fov.mapper.GetRefinementStep())
    assert steps == [0, 1, 2, 3], steps


def test_converged_analytic_readout_is_full_quality_within_float_rounding(vessels):
    full, fov = _pair(vessels, "analytic", frames=2)
    reference = full.float_image()
    for _ in range(3):
        fov.render_window.Render()
    values = fov.float_image()
    assert fov.mapper.GetRefinementStep() == 2
    hit = ~np.isnan(reference)
    assert hit.mean() > 0.3 and np.array_equal(hit, ~np.isnan(values))
    assert np.allclose(values[hit], reference[hit], rtol=1e-6, atol=1e-7)


def test_progressive_off_never_asks_for_frames(vessels):
    view = OffscreenView(vessels, "foveated", size=SIZE)
    view.render_window.Render()
    view.render_window.Render()
    assert not view.mapper.NeedsRefinement() and view.mapper.GetRefinementStep() == 0


TIMER_SCRIPT = '''
import time
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkRenderingCore import vtkRenderWindowInteractor
from mipcast.data_fixtures import make_fixture
from mipcast.mappers.refinement import drive_refinement
from mipcast.offscreen import OffscreenView

view = OffscreenView(make_fixture("vessels", size=24), "foveated", size=(64, 48))
view.render_window.SetOffScreenRendering(False)
view.mapper.SetRefinementFrames(3)
view.mapper.SetProgressive(True)
interactor = vtkRenderWindowInteractor()
interactor.SetRenderWindow(view.render_window)
interactor.Initialize()
handle = drive_refinement(interactor, lambda: [view.mapper], interval_ms=20)
renders = []
view.render_window.AddObserver(vtkCommand.EndEvent, lambda *a: renders.append(view.mapper.GetRefinementStep()))
started = time.perf_counter()
def stop(caller, event):
    if not view.mapper.NeedsRefinement() or time.perf_counter() - started > 20:
        caller.TerminateApp()
interactor.AddObserver(vtkCommand.TimerEvent, stop)
view.render_window.Render()
interactor.Start()
print("steps", renders)
assert renders[-1] == 3 and not view.mapper.NeedsRefinement(), renders
n = len(renders)
time.sleep(0.2)  # converged: the timer renders nothing more
print("timer ok")
'''


def test_a_timer_renders_the_refining_frames_under_xvfb(tmp_path):
    import shutil
    import sys

    if shutil.which("xvfb-run") is None:
        pytest.skip("needs xvfb-run")
    sys.path.insert(0, str(__import__("pathlib").Path(__file__).parent))
    from installed import plain_env
    from xvfb import run_under_xvfb

    script = tmp_path / "timer_check.py"
    script.write_text(TIMER_SCRIPT)
    result = run_under_xvfb([sys.executable, str(script)], cwd=tmp_path, env=plain_env(), timeout=120)
    assert result.returncode == 0 and "timer ok" in result.stdout, result.stdout + result.stderr


def test_both_eyes_of_a_stereo_frame_draw_the_same_still_frame(vessels):
    """A stereo window draws the volume twice a frame; the refinement counts frames, not eye draws
    (before: the right eye was one still frame ahead of the left, and each frame took two steps)."""
    from mipcast.core.object_state import object_state

    full, fov = _pair(vessels, "mip", frames=3)
    for view in (full, fov):
        view.render_window.SetStereoTypeToAnaglyph()
        view.render_window.StereoRenderOn()
    drawn = []
    fov.mapper.AddObserver("VolumeMapperRenderStartEvent",
                           lambda *_: drawn.append(object_state(fov.mapper)["refine_step"]), -2.0)  # after the draw
    per_frame = []
    for _ in range(5):
        drawn.clear()
        fov.render_window.Render()
        per_frame.append(tuple(drawn))
    assert per_frame == [(0, 0), (1, 1), (2, 2), (3, 3), (3, 3)], per_frame
    full.render_window.Render()
    assert np.array_equal(_grab(fov), _grab(full))  # the converged pair: both eyes at full quality
