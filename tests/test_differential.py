"""Random combinations of input and settings (tests/differential_check.py), each against its float64 reference.

The first 24 cases of the differential run: every method with a float readout and a reference, drawn with a
random scalar type, NaN holes, a mask, vectors, anisotropic spacing, a rotated direction, an extent not from
0, a slab, a clipping plane, cropping regions, bricks and view. Each must agree with the reference within the
method's tolerance (docs/reliability.md, "Ties", lists the cases further on that do not, and why).
Cases drawn with nearest-neighbour interpolation; and cases drawn by a scene that drew another case first
and was then changed (``--after 5000``: input, in place for odd cases, window, view, size, sampling, matrix
and every mapper setting), as a viewer is.
"""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy

from mipcast.data_fixtures import make_fixture
from differential_check import run_case


@pytest.fixture(scope="module")
def base():
    return vtk_to_numpy(make_fixture("vessels", size=24).GetPointData().GetScalars()).astype(np.float64).reshape(
        24, 24, 24)


@pytest.mark.parametrize("number", range(24))
def test_a_random_combination_agrees_with_the_reference(base, number):
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", list(range(12)) + [125])
def test_a_scene_changed_from_another_case_agrees_with_the_reference(base, number):
    """Case 125 (demip_two_pass in bricks, its image given another spacing in place) found the bricks' box
    placed at the old spacing's first point (tests/test_bricked_mapper.py, the new time step)."""
    case, problem = run_case(number, base, after=number + 5000)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [24, 60, 99, 126, 176, 280, 322, 2942])
def test_nearest_interpolation_cases_agree_with_the_reference(base, number):
    """Cases drawn with nearest-neighbour interpolation (mip, minip, average): the front views' half-way ties
    (either point accepted) and, in bricks, the CPU's one sample of a grazing outline ray (176, 322: linear
    until 2026-12-05; tests/test_interpolation.py); 2942, the average on a long perspective ray through a
    scaled volume, a sample 1e-5 to 3e-5 point-index units from half-way (the tie's width, TIE)."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [19, 20, 87, 115, 132, 133, 197, 207, 241, 255, 310])
def test_the_eye_inside_the_volume_agrees_with_the_reference(base, number):
    """Cases whose perspective eye is inside the volume (``camera_case`` "inside"): VTK starts those rays at
    its near-plane cap, which until 2026-12-05 the float64 reference did not (it started them on the near
    plane: 19 of 27 such cases off, mip up to 6 % of the range, each of these among them), and which in a
    volume placed by a scaling matrix lies the offset in the volume's own units away (mipcast's bricks and
    the reference took world units: 133 and 310 off until then)."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [109, 148, 231, 234, 274, 275, 396, 543])
def test_rays_from_an_eye_inside_the_volume_aim_through_the_pixel_centre(base, number):
    """Eye-inside cases off until 2026-12-05 by 1.6e-4 to 5.1e-4 of the range (148: 0.03, a sample whose value
    crossed the missing-data floor of the mask's edge, counted in the average): VTK aimed each ray from the
    eye at its fragment on the near-plane cap, 0.001 of the clipping range away, both in float32. Now the
    perspective_ray_direction piece aims it along the pixel's line through the frustum (1.3e-6 to 8e-6)."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [521, 568])
def test_8_bit_data_under_a_narrow_window_is_coloured_at_its_value(base, number):
    """analytic on 8-bit data under a window 30 % of the range wide (0.7-1.0): until 2026-12-05 the picture
    was 3 grey brighter than the float readout and the reference (tests/test_narrow_window.py, the 8-bit
    ramp)."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [39, 54, 125, 177, 531])
def test_demip_with_nearest_interpolation_agrees_with_the_reference(base, number):
    """DEMIP drawn with nearest-neighbour interpolation, against its reference's (``interpolation="nearest"``,
    since 2026-12-05). Case 531 (LMIP in bricks, int16 with a mask) found the scan ending at a brick's first
    sample: the same point's value read from the brick in front and from this one differed by float32
    rounding (2.2e-6 of the range), and a sample equal to the carried maximum counted as a fall (9 pixels, up
    to 0.6 of the range off; shaders/demip_brick_lmip_hooks.glsl). Case 177 (an odd picture's front view)
    needs the ties bounded per axis (differential_check.CORNERS)."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


def test_lmip_in_bricks_through_a_brick_of_hidden_points_agrees_with_the_reference(base):
    """Case 1483 (DEMIP's LMIP in bricks with a mask, perspective): a brick all hidden points is a constant
    texture, which VTK normalises over a range 1e-6 wide; until 2026-12-05 the readouts took it as 0 and 1 and
    the running maximum carried through such a brick came back as its fill value (161 of 557 pixels up to
    1.57 of the range off)."""
    case, problem = run_case(1483, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [486, 1468, 2443])
def test_nearest_ties_of_values_not_monotone_in_the_picks_agree_with_the_reference(base, number):
    """Nearest interpolation, samples half-way between points: DEMIP's attenuated value (486) and LMIP (1468),
    and the average with a mask (2443), whose lowest picks may give the higher value; the GPU's value lies in
    the span of the plain reference and the two whole-ray picks (run_case; 1468: the lowest picks' exactly)."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [143, 225, 233, 410, 441, 484, 549, 612])
def test_demip_depth_and_picture_agree_with_the_reference(base, number):
    """DEMIP's depth (the readout "depth") and picture against the float64 reference's, with a random depth
    mode, depth weight, colour sphere and chromadepth (differential_check.demip_problem; since 2026-12-05):
    slabs, cropping, clipping, bricks, masks, vectors, cell scalars, volume matrices, an off-centre window and
    the eye inside the volume. 549 (8-bit data in bricks) has rays whose maximum lies at the window's floor
    within the texture unit's 8-bit filtering: a tie at the floor."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)


@pytest.mark.parametrize("number", [55, 71, 82, 86, 103, 138, 145, 180, 205, 240, 252, 461, 2440])
def test_pictures_under_a_users_colour_map_and_opacity_agree_with_the_reference(base, number):
    """The grey methods under a random colour map and opacity (a V, its middle transparent; a step; a
    sigmoid), as pyvista's ``cmap`` and ``opacity`` give them (differential_check.transfer_case; since
    2026-12-05): the picture is the reference's value through those functions, premultiplied, over black,
    in bricks (composited on the CPU) as in one texture. 461 and 2440 draw with MSAA: 461 (analytic MinIP in
    bricks, perspective, a volume matrix) was 130 pixels up to 166 levels off until the CPU's colour table
    stopped spanning a face's extrapolated values (tests/test_bricked_mapper.py). 82, 138 and 180 are DEMIP
    (its base colour through the colour map, ``reference.render(..., colour=)``, then its terms, then the
    opacity)."""
    case, problem = run_case(number, base)
    assert problem is None, (case, problem)
