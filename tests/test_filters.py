"""pyvista wrappers: offscreen render and Plotter integration."""
import numpy as np
import pytest
import pyvista as pv

from mipcast.data_fixtures import make_fixture
from mipcast.filters import add_volume, render
from mipcast.metrics import grey_diff


@pytest.fixture(scope="module")
def grid():
    return pv.wrap(make_fixture("vessels", size=32))


def test_render_rgb_and_float(grid):
    rgb = render(grid, size=(64, 48))
    values = render(grid, size=(64, 48), as_float=True)
    assert rgb.shape == (48, 64, 3) and rgb.dtype == np.uint8 and rgb.max() > 100
    assert values.shape == (48, 64) and values.dtype == np.float32
    hit = ~np.isnan(values)
    assert 0.2 < hit.mean() < 0.9
    # where the float value is high the picture is bright, and vice versa
    assert np.corrcoef(values[hit], rgb[..., 0][hit])[0, 1] > 0.99


def test_plotter_mip_equals_stock_in_the_same_plotter_setup(grid):
    shots = []
    for method in ("stock", "mip"):
        plotter = pv.Plotter(off_screen=True, window_size=(96, 96))
        add_volume(plotter, grid, method=method, cmap="viridis", clim=(0.1, 0.9))
        plotter.camera.azimuth = 30
        shots.append(plotter.screenshot())
        plotter.close()
    assert shots[1].std() > 10, "picture is flat"
    assert grey_diff(shots[0], shots[1])["within_1"] >= 0.999


def test_plotter_bad_parameters(grid):
    plotter = pv.Plotter(off_screen=True, window_size=(32, 32))
    with pytest.raises(ValueError, match="clim"):
        add_volume(plotter, grid, clim=(1.0, 0.0))
    with pytest.raises(ValueError, match="opacity"):
        add_volume(plotter, grid, opacity=2.0)
    with pytest.raises(ValueError, match="unknown method"):
        add_volume(plotter, grid, method="best")
    plotter.close()
