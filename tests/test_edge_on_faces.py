"""A volume turned about the view axis and seen head-on: its side faces are edge-on to every ray.

VTK starts each ray at its fragment's rasterised position on the volume's box. A face seen edge-on
rasterises, after float rounding, as a sliver a pixel wide, whose interpolated position lands anywhere
along the pixel's line (in front of the box, behind the eye) or is NaN, with VTK's step and termination
(llvmpipe). Until 2026-12-05 such a pixel was drawn from there: analytic MIP 56 times the data range off
(a cell walk from far outside the box), sampled MIP 0.7 of it, analytic MinIP in bricks 0.21 (differential
case 704: an 8-bit volume, a direction matrix turning it 0.5 rad about z, a front view; case 821, the
analytic average on the same ray, 0.013). While a face is that near edge-on, every method installs
shaders/ray_mend.glsl, which sets such a ray up again along its pixel's line; every pixel is then within
1e-4 of the range of the float64 reference on the same rays (docs/reliability.md, "A face seen edge-on").
"""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy

from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture
from mipcast.methods import METHODS
from differential_check import run_case
from edge_on_check import tilted_scene, turned


# (turn, window size, the view tilted by degrees): scenes of a sweep over 30 turns whose slivers llvmpipe drew
# off, head-on and tilted (a face 1e-3 degree off edge-on: 0.026 of the range off until then)
@pytest.mark.parametrize("angle, size, tilt", [(0.65, (41, 37), 0.0), (1.2, (64, 64), 0.0),
                                               (0.65, (41, 37), 0.001)])
@pytest.mark.parametrize("name", ["analytic", "analytic_minip", "mip", "average"])
def test_a_volume_turned_about_the_view_axis_agrees_with_the_reference(name, angle, size, tilt):
    image = turned(24, angle)
    scene = tilted_scene(image, name, size, tilt)
    got = scene.float_image()
    assert "ray_mend" in object_state(scene.mapper)["installed"]
    sampling = {} if METHODS[name].walks_cells else {"sample_distance": scene.sample_distance}
    expected = METHODS[name].reference(image, scene.camera, size, window=scene.window, **sampling)
    hits = np.isfinite(got) & np.isfinite(expected)
    assert hits.sum() > 150  # (the box covers 12-14 % of the picture)
    assert (np.isnan(got) != np.isnan(expected)).sum() <= 3  # pixel centres on the outline: rasterisation
    error = np.abs(got[hits] - expected[hits]) / 250.0
    assert error.max() <= 1e-4, (name, float(error.max()), int((error > 1e-4).sum()))


# (method, turn, window size, the view tilted by degrees): scenes of the sweep 0.01 to 0.5 degree off head-on
# (faces' sines 8.7e-6 to 6.1e-3, the piece not installed) where VTK's start lay inside the box past where
# the pixel's line enters it; and the last three where it lay in front of the box
@pytest.mark.parametrize("name, angle, size, tilt", [
    ("analytic", 0.65, (41, 37), 0.01), ("mip", 0.65, (41, 37), 0.01), ("analytic_minip", 0.65, (41, 37), 0.01),
    ("average", 0.65, (41, 37), 0.01), ("analytic", 0.15, (64, 64), 0.1), ("mip", 0.15, (64, 64), 0.1),
    ("analytic_average", 0.15, (64, 64), 0.1), ("demip", 0.15, (64, 64), 0.1),
    ("mip", 1.4, (41, 37), 0.1), ("minip", 1.4, (41, 37), 0.1), ("mip", 1.1, (64, 64), 0.5)])
def test_a_view_just_off_head_on_starts_its_rays_where_they_enter_the_box(name, angle, size, tilt):
    """A face met at a grazing angle rasterises with its fragments' positions on the pixel's line but up to a
    tenth of the box inside it (the ray skipped the box's first part), or in front of it: until 2026-12-05
    these scenes were 3.3e-3 to 0.055 of the range off at 1 or 2 pixels. The ray loops now move such a start
    to the line's entry (mip_globals: mcEntryShift); what is left is at most one pixel between 1e-4 and 7.6e-4 (a
    ray grazing the face: where it crosses it is ill-conditioned in float32, a tie)."""
    image = turned(24, angle)
    scene = tilted_scene(image, name, size, tilt)
    got = scene.float_image()
    assert "ray_mend" not in object_state(scene.mapper)["installed"]
    sampling = {} if METHODS[name].walks_cells else {"sample_distance": scene.sample_distance}
    expected = METHODS[name].reference(image, scene.camera, size, window=scene.window, **sampling)
    hits = np.isfinite(got) & np.isfinite(expected)
    assert hits.sum() > 150 and (np.isnan(got) != np.isnan(expected)).sum() <= 3
    error = np.abs(got[hits] - expected[hits]) / 250.0
    assert error.max() <= 1e-3 and (error > 1e-4).sum() <= 1, (name, float(error.max()), int((error > 1e-4).sum()))


def test_the_starts_move_unless_vtk_caps_the_box():
    """u_mc_entryMoves: 2 (starts behind and in front of the entry move) while a face is met at a sine below
    ENTRY_MOVES (0.1), 1 while the window draws with MSAA (VTK starts a silhouette pixel in front of the box on purpose: only starts behind move; the bricked
    and refinement MSAA tests fail with 2), 0 while the near plane cuts the box (the cap's starts lie inside
    it: 17 eye-inside tests fail with 1)."""
    scene = tilted_scene(turned(24, 0.5), "mip", (32, 32), 0.1)
    scene.float_image()
    assert scene.mapper._entry_moves(scene.volume) == 2.0
    scene.render_window.SetMultiSamples(4)
    assert scene.mapper._entry_moves(scene.volume) == 1.0
    scene.render_window.SetMultiSamples(0)
    scene.camera.Elevation(20.0)  # no face near edge-on (a sine of 0.16): no start moves, no test in the loops
    assert scene.mapper._entry_moves(scene.volume) == 0.0
    centre = np.array(scene.volume.GetCenter())
    scene.camera.SetFocalPoint(*centre)
    scene.camera.SetPosition(*(centre - 3.0 * np.array(scene.camera.GetDirectionOfProjection())))  # inside
    scene.camera.SetClippingRange(0.1, 100.0)
    assert scene.mapper._entry_moves(scene.volume) == 0.0


@pytest.mark.parametrize("view, tilt, installed", [("front", 0.0, True), ("front", 0.002, True),
                                                   ("front", 0.1, False), ("oblique", 0.0, False)])
def test_the_mending_piece_is_installed_only_near_edge_on(view, tilt, installed):
    """ray_mend costs llvmpipe 5-12 % of a frame (it runs a branch's body on every lane) and a program switch
    when it comes or goes: installed while a face is within EDGE_ON (a sine of 1e-4) of edge-on (0 and 1.7e-5
    here), not for the views further off (8.4e-4, the oblique view's 0.071)."""
    scene = tilted_scene(turned(24, 0.5), "mip", (32, 32), tilt, view)
    scene.float_image()
    assert ("ray_mend" in object_state(scene.mapper)["installed"]) == installed


@pytest.mark.parametrize("number", [704, 821])
def test_the_differential_cases_seen_edge_on_agree_with_the_reference(number):
    base = vtk_to_numpy(make_fixture("vessels", size=24).GetPointData().GetScalars()).astype(np.float64)
    case, problem = run_case(number, base.reshape(24, 24, 24))
    assert problem is None, (case, problem)
