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
