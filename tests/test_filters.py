"""pyvista wrappers: offscreen render and Plotter integration."""
import numpy as np
import pytest
import pyvista as pv

from mipcast.data_fixtures import make_fixture
from mipcast.filters import add_volume, render
from mipcast.core.metrics import grey_diff


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


def _two_arrays(grid):
    """``grid`` with a second point array, ``flipped`` (the vessels upside down), active scalars unchanged."""
    both = grid.copy()
    values = np.asarray(grid.point_data.active_scalars)
    both.point_data["flipped"] = values.reshape(grid.dimensions[::-1])[::-1].ravel().copy()
    both.point_data.active_scalars_name = grid.point_data.active_scalars_name
    return both


def test_scalars_chooses_the_array_without_modifying_the_grid(grid):
    both = _two_arrays(grid)
    active = both.point_data.active_scalars_name
    only_flipped = pv.ImageData(dimensions=grid.dimensions, spacing=grid.spacing, origin=grid.origin)
    only_flipped.point_data["flipped"] = both.point_data["flipped"]
    chosen = render(both, "analytic", scalars="flipped", size=(48, 48), as_float=True)
    expected = render(only_flipped, "analytic", size=(48, 48), as_float=True)
    default = render(both, "analytic", size=(48, 48), as_float=True)
    assert np.array_equal(np.isnan(chosen), np.isnan(expected))
    assert np.nanmax(np.abs(chosen - expected)) < 1e-6
    assert np.nanmax(np.abs(chosen - default)) > 0.1  # a different picture from the active array
    assert both.point_data.active_scalars_name == active
    plotter = pv.Plotter(off_screen=True, window_size=(48, 48))
    volume = plotter.mip.add_volume(both, "mip", scalars="flipped")
    assert volume.mapper.GetInput().GetPointData().GetScalars().GetName() == "flipped"
    assert both.point_data.active_scalars_name == active
    plotter.close()


def test_scalars_that_are_not_an_array_are_refused_cell_arrays_drawn(grid):
    both = _two_arrays(grid)
    both.cell_data["cells"] = np.zeros(both.n_cells)
    with pytest.raises(ValueError, match=r"'nope' is not a numeric point array.*flipped"):
        render(both, scalars="nope")
    plotter = pv.Plotter(off_screen=True, window_size=(32, 32))
    # a cell array is drawn, on the image of the cell centres (mipcast.core.prepare.cell_centres)
    active = both.point_data.active_scalars_name
    drawn = add_volume(plotter, both, scalars="cells").mapper.GetInput()
    assert drawn.GetPointData().GetScalars().GetName() == "cells"
    assert drawn.GetDimensions() == tuple(n - 1 for n in both.dimensions)
    assert both.point_data.active_scalars_name == active and "cells" not in both.point_data
    plotter.close()


def test_add_volume_behaves_like_pyvistas(grid):
    plotter = pv.Plotter(off_screen=True, window_size=(64, 64))
    plotter.camera_position = [(120.0, 40.0, 30.0), (16.0, 16.0, 16.0), (0.0, 0.0, 1.0)]
    before = plotter.camera_position
    first = add_volume(plotter, grid, "mip", name="vessels")
    assert isinstance(first, pv.Volume) and first.mapper is first.GetMapper()
    assert plotter.camera_position == before  # a camera the user set is kept
    second = add_volume(plotter, grid, "analytic", name="vessels")  # same name: replaces
    assert plotter.renderer.GetVolumes().GetNumberOfItems() == 1
    assert plotter.renderer.GetVolumes().GetItemAsObject(0) is second
    assert plotter.screenshot().std() > 5
    plotter.remove_actor("vessels")
    assert plotter.renderer.GetVolumes().GetNumberOfItems() == 0
    # the plotter component forgets (and detaches) what pyvista removed
    third = plotter.mip.add_volume(grid, "mip", name="again")
    replacing = plotter.mip.add_volume(grid, "analytic", name="again")
    assert plotter.mip.volumes == (replacing,) and not third.mapper.IsAttached()
    plotter.remove_actor("again")
    assert plotter.mip.volumes == () and not replacing.mapper.IsAttached()
    other = pv.Plotter(off_screen=True, window_size=(64, 64))
    add_volume(other, grid, "mip")  # no camera set: reset to the volume, as pyvista does
    assert np.allclose(other.camera.focal_point, grid.center)
    plotter.close()
    other.close()
