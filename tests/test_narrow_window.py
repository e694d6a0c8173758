"""Exact projections under a narrow window (inside the data range) against the float64 reference.

The display shortcuts of the cell walk (amip_loop, amip_loop_blocks with the
hooks amip_max_hooks / amip_min_hooks) start the running value at a bound
where the transfer functions stop changing (MIP: the floor; MinIP: the
ceiling) and stop at the other.  VTK draws colour and opacity from tables
that interpolate between texels, so a value left *at* a bound is not drawn
in the constant colour beyond it: with a window a few texels wide every ray
whose answer lies beyond the bound came out tinted (analytic MinIP on
vessels, window 0.032-0.041: every pixel off, by up to 15 grey levels).
The walk now hands such rays to the tables' ends (normalised 0 / 1).
"""
import numpy as np
import pytest

from mipcast.data_fixtures import make_fixture
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView

SIZE = (96, 80)


@pytest.fixture(scope="module")
def vessels48():
    return make_fixture("vessels", size=48)


@pytest.mark.parametrize("name, window, beyond", [
    ("analytic_minip", (0.032, 0.041), 255),  # most minima above the ceiling: white
    ("analytic", (0.6, 0.609), 0),            # most maxima below the floor: black
])
def test_narrow_window_beyond_a_bound_draws_the_constant_colour(vessels48, name, window, beyond):
    image = vessels48
    low, high = image.GetPointData().GetScalars().GetRange(0)
    assert low < window[0] and window[1] < high  # narrow, inside the data range
    scene = OffscreenView(image, name, size=SIZE, window=window)
    picture = scene.screenshot()[..., 0].astype(float)
    exact = METHODS[name].reference(image, scene.camera, scene.size)
    hits = np.isfinite(exact)
    assert hits.mean() > 0.3
    expected = np.round(255 * np.clip((exact - window[0]) / (window[1] - window[0]), 0, 1))
    # the test must see rays on both sides: most beyond the bound, some not
    assert 0.5 < np.mean(expected[hits] == beyond) < 1.0
    assert picture.max() == 255 and picture[hits].min() < 255
    error = np.abs(picture - expected)[hits]
    # (what stays: VTK's table interpolation for answers inside the window, as stock draws them)
    assert np.mean(error <= 1) >= 0.98, (np.mean(error <= 1), error.max())
    assert np.all(np.abs(picture - expected)[hits & (expected == beyond)] <= 1)


@pytest.mark.parametrize("name, window", [
    ("minip", None),             # its default window on the vessels: 3 % of the data range
    ("analytic_minip", None),
    ("mip", (0.3, 0.34)),
    ("analytic", (0.3, 0.34)),
    ("average", (0.12, 0.16)),
    ("analytic_average", (0.12, 0.16)),
])
def test_the_picture_is_the_reference_through_the_window(name, window):
    """Every hit pixel within 1 grey of the float64 reference mapped through the window's grey ramp, with no
    bias. VTK tabulates a transfer function at i / (n - 1) of its range and reads texel i at (i + 0.5) / n,
    so a value looked up at itself is read half a table step off; mipcast's colour pieces read where the
    table holds the value (mcAtTable, shaders/mip_globals.glsl). Until 2026-12-04 they read as VTK does (as
    stock VTK still draws): MinIP at its default window on the vessels 24³ up to 4 grey dark on 233 of 1440
    pixels (mean -3.7 grey), MIP under a window 3 % of the range wide -1.6 grey on average."""
    image = make_fixture("vessels", size=24)
    scene = OffscreenView(image, name, size=(40, 36), view="front", window=window)
    picture = scene.screenshot()[..., 0].astype(float)
    method = METHODS[name]
    settings = {} if method.walks_cells else {"sample_distance": scene.sample_distance}
    exact = method.reference(image, scene.camera, scene.size, window=scene.window, **settings)
    low, high = scene.window
    span = image.GetPointData().GetScalars().GetRange(0)
    assert (high - low) < 0.1 * (span[1] - span[0])  # a narrow window: a few dozen table steps
    inside = np.isfinite(exact) & (exact > low) & (exact < high)
    assert inside.sum() > 5
    expected = np.where(np.isfinite(exact), np.round(255 * np.clip((exact - low) / (high - low), 0, 1)), 0.0)
    error = picture - expected
    assert np.abs(error).max() <= 1, np.abs(error).max()
    assert abs(error[inside].mean()) < 0.35, error[inside].mean()


@pytest.mark.parametrize("where", ["inside", "top", "bottom"])
@pytest.mark.parametrize("dtype", [np.uint8, np.int8])
@pytest.mark.parametrize("name", ["mip", "analytic", "minip", "analytic_minip", "average", "analytic_average"])
def test_8_bit_data_is_drawn_at_its_value_not_256_255_of_it(name, dtype, where):
    """8-bit data: VTK's normalised scalar is that of the value times 256/255 (128/127 signed), so its colour
    and opacity lookups read the tables 0.4 % of the value too high (stock VTK draws so); the float readout
    undid the factor (float_readout.texture_scale), the colour pieces did not until 2026-12-05: under a
    window 20 units wide every pixel inside it 2.5 to 9 grey too bright (uint8 analytic, a window 177-250 of
    8-250: +3 grey). Now u_mc_tableScale takes the scalar to the value's place in the tables
    (float_readout.table_coordinate). A ramp along x seen from the front: every ray's maximum, minimum and
    mean are the ramp's value at its x; it saturates at both ends (8-bit data often does), and the window
    lies inside the range, or ends at its top or bottom: the projections' shortcuts hand a value beyond a
    window end to the tables' ends (mcTableEnd), which must draw the saturated values white or black."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    ramp = np.clip(4.0 * np.arange(64), 80.0, 172.0) - (0.0 if dtype == np.uint8 else 120.0)  # x 20 to 43
    image = vtkImageData()
    image.SetDimensions(64, 4, 4)
    image.GetPointData().SetScalars(numpy_to_vtk(np.tile(ramp, 16).astype(dtype), deep=True))
    low = {"inside": ramp[30], "top": ramp.max() - 20.0, "bottom": ramp.min()}[where]
    low, high = float(low), float(low) + 20.0  # 20 units of the range
    scene = OffscreenView(image, name, size=(128, 16), view="front", window=(low, high))
    camera = scene.camera
    camera.SetParallelScale(2.0)  # x 15.6 to 47.6, a pixel a quarter of a point: the ramp's values at
    camera.SetFocalPoint(31.625, 1.5, 1.5)  # the pixels are whole numbers (llvmpipe filters 8-bit
    camera.SetPosition(31.625, 1.5, 40.0)   # textures to 8 bits: a half-way value would round up)
    scene.renderer.ResetCameraClippingRange()
    picture = scene.screenshot()[..., 0].astype(float)
    method = METHODS[name]
    settings = {} if method.walks_cells else {"sample_distance": scene.sample_distance}
    exact = method.reference(image, camera, scene.size, window=(low, high), **settings)
    inside = np.isfinite(exact) & (exact > low) & (exact < high)
    assert inside.sum() > 100
    if where != "inside":  # the saturated end drawn, and its pixels are the window's end
        assert np.sum(exact == (ramp.max() if where == "top" else ramp.min())) > 100
    expected = np.where(np.isfinite(exact), np.round(255 * np.clip((exact - low) / (high - low), 0, 1)), 0.0)
    error = picture - expected
    assert abs(error[inside].mean()) < 0.35, error[inside].mean()
    # within 1 grey, but where the value lies within one table step (1/1023 of the range) of a window end
    # inside the data's range: there VTK's table interpolates across the ramp's corner (at the range's own
    # ends the table ends: nothing to interpolate across)
    step = np.ptp(ramp) / 1023.0
    corner = np.zeros(exact.shape, bool)
    for end in (low, high):
        if ramp.min() < end < ramp.max():
            corner |= np.abs(exact - end) <= step
    assert np.abs(error)[~corner].max() <= 1, np.abs(error)[~corner].max()
