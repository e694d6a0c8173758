"""pyvista extension API: grid.mip accessor, plotter.mip component, method parameters as keywords."""
import subprocess
import sys

import numpy as np
import pytest
import pyvista as pv

import mipcast
import mipcast.filters
from mipcast import METHODS, create_mapper
from mipcast.data_fixtures import make_fixture
from mipcast.filters import add_volume, method_parameters, render, set_parameters
from mipcast.offscreen import OffscreenView
from mipcast.mappers.shader_pieces import installed_tags
from installed import OUTSIDE

SIZE = (48, 40)


@pytest.fixture(scope="module")
def grid():
    return pv.wrap(make_fixture("vessels", size=24))


def test_import_mipcast_does_not_import_pyvista():
    code = "import sys, mipcast; assert 'pyvista' not in sys.modules, 'pyvista imported'; print('ok')"
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60,
                            cwd=OUTSIDE)
    assert result.returncode == 0 and "ok" in result.stdout, result.stderr


def test_extensions_are_registered_on_import():
    accessors = {(r.name, r.target) for r in pv.registered_accessors()}
    assert ("mip", pv.ImageData) in accessors
    assert "mip" in {r.name for r in pv.registered_plotter_components()}
    assert isinstance(pv.ImageData(dimensions=(2, 2, 2)).mip, mipcast.filters.MipAccessor)


@pytest.mark.parametrize("method", list(METHODS))
def test_accessor_renders_like_the_function(grid, method):
    shot = grid.mip.render(method, size=SIZE)
    assert shot.shape == (SIZE[1], SIZE[0], 3) and shot.dtype == np.uint8
    assert shot.max() > 100, f"{method} picture is dark"
    np.testing.assert_array_equal(shot, render(grid, method, size=SIZE))


def test_accessor_float_readout(grid):
    values = grid.mip.render("analytic", size=SIZE, as_float=True)
    low, high = grid.get_data_range()
    hit = ~np.isnan(values)
    assert values.dtype == np.float32 and 0.2 < hit.mean() < 0.95
    assert low <= values[hit].min() and values[hit].max() <= high + 1e-6 * (high - low)


@pytest.mark.parametrize("method", list(METHODS))
def test_unknown_parameter_is_a_type_error_naming_it(grid, method):
    with pytest.raises(TypeError, match="'no_such_weight'.*method parameters are: ") as error:
        grid.mip.render(method, size=SIZE, no_such_weight=0.2)
    for name in method_parameters(create_mapper(method)):
        assert name in str(error.value)


def test_parameters_reach_the_mapper_setters():
    mapper = create_mapper("mip")
    set_parameters(mapper, image_sample_distance=2.0, cropping_region_planes=(0, 1, 0, 2, 0, 3))
    assert mapper.GetImageSampleDistance() == 2.0
    assert mapper.GetCroppingRegionPlanes() == (0.0, 1.0, 0.0, 2.0, 0.0, 3.0)
    with pytest.raises(TypeError, match="image_sample_distance='far'"):
        set_parameters(mapper, image_sample_distance="far")


def test_method_parameters_are_the_methods_table_not_its_setters():
    assert method_parameters(create_mapper("stock")) == ()
    analytic = method_parameters(create_mapper("analytic"))
    assert "partitions" not in analytic  # overrides a VTK setter
    assert "corner_packer" not in analytic  # an internal setter is no user parameter
    assert "readout" not in method_parameters(create_mapper("demip"))
    for name, method in METHODS.items():
        assert method_parameters(method.create()) == tuple(sorted(p.name for p in method.parameters)), name

    class Weighted(mipcast.MIPVolumeMapper):
        def SetDepthWeight(self, value):
            pass

    # a setter is not a parameter until the table says so (MIP's table: skipping and the shared slab)
    assert method_parameters(Weighted()) == ("skipping", "slab_centre", "slab_normal", "slab_thickness")
    with pytest.raises(AttributeError, match="AverageVolumeMapper has no parameter 'skipping'"):
        create_mapper("average").SetSkipping(False)  # inherited from MIP's accessors, not in the average's table
    create_mapper("minip").SetSkipping(False)  # MinIP's own table has it (block minima)


@pytest.mark.skipif("demip" not in METHODS, reason="DEMIP is not registered yet")
def test_demip_parameters_as_keywords(grid):
    assert {"depth_weight", "sphere_weight", "depth_mode"} <= set(method_parameters(create_mapper("demip")))
    plain = grid.mip.render("mip", size=SIZE)
    np.testing.assert_array_equal(grid.mip.render("demip", size=SIZE, depth_weight=0.0), plain)
    assert np.abs(grid.mip.render("demip", size=SIZE, depth_weight=0.5).astype(int) - plain).max() > 20


def test_plotter_component_adds_like_the_function(grid):
    shots = []
    for use_component in (True, False):
        plotter = pv.Plotter(off_screen=True, window_size=SIZE)
        if use_component:
            volume = plotter.mip.add_volume(grid, "analytic", cmap="viridis", clim=(0.1, 0.9))
            assert plotter.mip.volumes == (volume,)
            assert isinstance(volume.GetMapper(), mipcast.AnalyticMIPVolumeMapper)
        else:
            add_volume(plotter, grid, "analytic", cmap="viridis", clim=(0.1, 0.9))
        shots.append(plotter.screenshot())
        plotter.close()
    assert shots[0].std() > 10
    np.testing.assert_array_equal(shots[0], shots[1])


def test_plotter_close_removes_and_detaches(grid):
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    renderer = plotter.renderer
    volumes = [plotter.mip.add_volume(grid, method) for method in METHODS]
    plotter.screenshot()
    assert renderer.GetVolumes().GetNumberOfItems() == len(METHODS)
    plotter.close()
    assert plotter.mip.volumes == ()
    assert renderer.GetVolumes().GetNumberOfItems() == 0
    for volume in volumes:
        assert installed_tags(volume.GetShaderProperty()) == []
        assert not getattr(volume.GetMapper(), "IsAttached", lambda: False)()


def test_bad_arguments_add_nothing(grid):
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    with pytest.raises(TypeError, match="no_such_weight"):
        plotter.mip.add_volume(grid, "mip", no_such_weight=1.0)
    with pytest.raises(ValueError, match="clim"):
        plotter.mip.add_volume(grid, clim=(1.0, 0.0))
    with pytest.raises(ValueError, match="unknown method"):
        plotter.mip.add_volume(grid, "best")
    assert plotter.mip.volumes == () and plotter.renderer.GetVolumes().GetNumberOfItems() == 0
    other = pv.Plotter(off_screen=True, window_size=SIZE)
    with pytest.raises(ValueError, match="not added by plotter.mip"):
        plotter.mip.remove_volume(other.mip.add_volume(grid))
    other.close()
    plotter.close()


def test_accessor_plot_shows_what_add_volume_shows(grid):
    shown = grid.mip.plot("demip", off_screen=True, window_size=SIZE, screenshot=True,
                          cmap="bone", depth_weight=0.5)
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    add_volume(plotter, grid, "demip", cmap="bone", depth_weight=0.5)
    expected = plotter.screenshot()
    plotter.close()
    assert shown.shape == expected.shape and shown.std() > 5
    assert np.array_equal(shown, expected)
    with pytest.raises(TypeError, match="depth_wieght"):
        grid.mip.plot("demip", off_screen=True, window_size=SIZE, depth_wieght=0.5)


def test_render_takes_clim_as_pyvista_spells_the_window(grid):
    """``render(clim=)`` / ``grid.mip.render(clim=)`` is ``window=`` (add_volume's and plot's name for it); both, or a
    colour map the grey render cannot draw, are refused with the fix."""
    narrow = render(grid, "mip", size=SIZE, window=(0.5, 0.9))
    assert np.array_equal(render(grid, "mip", size=SIZE, clim=(0.5, 0.9)), narrow)
    assert np.array_equal(grid.mip.render("mip", size=SIZE, clim=(0.5, 0.9)), narrow)
    assert not np.array_equal(render(grid, "mip", size=SIZE), narrow)  # clim is not ignored
    with pytest.raises(TypeError, match="window or clim"):
        render(grid, "mip", size=SIZE, window=(0.5, 0.9), clim=(0.5, 0.9))
    with pytest.raises(TypeError, match="add_volume"):
        grid.mip.render("mip", size=SIZE, cmap="bone")


def _against_reference(data, method, camera_from):
    """``render(data, method, as_float=True)`` beside the float64 reference of the equivalent right-handed image data,
    both on ``camera_from``'s camera (the filters place their own)."""
    from mipcast import reference
    from mipcast.io import as_image_data
    from mipcast.offscreen import OffscreenView

    image = as_image_data(data)
    view = OffscreenView(image, method, size=SIZE, window=(0.25, 1.0))
    view.camera.DeepCopy(camera_from.camera)
    view.renderer.ResetCameraClippingRange()
    found = view.float_image()
    extra = {"sample_distance": view.sample_distance} if method == "mip" else {}
    exact = reference.render(image, view.camera, SIZE, method=method, **extra)
    hits = ~np.isnan(found) & ~np.isnan(exact)
    return found, exact, hits


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_a_mirrored_volume_is_drawn_right_handed(grid, method):
    """pyvista image data with a reflection in its direction matrix (an odd number of flipped axes): VTK's GPU ray
    caster drew it nearly blank (stock too: rays entered through the far faces; analytic 0.88 of the range off its
    float64 reference); the filters draw its right-handed copy (mipcast.io.right_handed), the user's grid unchanged."""
    from mipcast.io import right_handed
    from mipcast.offscreen import OffscreenView

    nx, ny, nz = grid.dimensions
    mirrored = pv.ImageData(dimensions=grid.dimensions, spacing=(0.5, 0.7, 1.1), origin=(3.0, 12.0, 5.0))
    mirrored.direction_matrix = np.diag([1.0, -1.0, 1.0])
    mirrored.point_data["v"] = np.asarray(grid.active_scalars).reshape(nz, ny, nx)[:, ::-1, :].ravel()
    before = np.asarray(mirrored.point_data["v"]).copy()
    fixed = right_handed(mirrored)
    assert np.linalg.det(np.asarray(pv.wrap(fixed).direction_matrix)) > 0 and fixed.GetBounds() == mirrored.bounds
    picture = render(mirrored, method, size=SIZE, window=(0.25, 1.0))
    assert np.array_equal(picture, render(pv.wrap(fixed), method, size=SIZE, window=(0.25, 1.0)))
    assert (picture.max(axis=-1) > 40).mean() > 0.1  # the vessels, not the nearly blank picture
    found, exact, hits = _against_reference(mirrored, method, OffscreenView(fixed, method, size=SIZE))
    assert hits.sum() > 200 and np.mean(np.isnan(found) == np.isnan(exact)) > 0.99
    assert np.abs(found[hits] - exact[hits]).max() < 1e-4
    assert np.array_equal(np.asarray(mirrored.point_data["v"]), before)
    assert np.linalg.det(np.asarray(mirrored.direction_matrix)) < 0


def test_an_evenly_spaced_rectilinear_grid_is_drawn_as_image_data(grid):
    """A RectilinearGrid (netCDF / xarray latitudes, longitudes, levels) with even steps: ``grid.mip`` and the
    filters draw it as the image data it is (a decreasing axis too: latitudes from north to south); uneven steps
    raise TypeError naming the axis and the fix."""
    from mipcast.io import as_image_data

    nx, ny, nz = grid.dimensions
    x, y, z = 3.0 + 0.5 * np.arange(nx), -2.0 + 0.7 * np.arange(ny), 5.0 + 1.1 * np.arange(nz)
    values = np.asarray(grid.active_scalars)
    image = pv.ImageData(dimensions=grid.dimensions, spacing=(0.5, 0.7, 1.1), origin=(3.0, -2.0, 5.0))
    image.point_data["v"] = values
    even = pv.RectilinearGrid(x, y, z)
    even.point_data["v"] = values
    assert np.array_equal(even.mip.render("mip", size=SIZE, window=(0.25, 1.0)),
                          image.mip.render("mip", size=SIZE, window=(0.25, 1.0)))
    south = pv.RectilinearGrid(x, y[::-1], z)  # decreasing y: a reflection, drawn right-handed
    south.point_data["v"] = values.reshape(nz, ny, nx)[:, ::-1, :].ravel()
    drawn = as_image_data(south)
    assert np.allclose(drawn.GetBounds(), image.bounds, atol=1e-9)
    found, exact, hits = _against_reference(south, "analytic", OffscreenView(drawn, "analytic", size=SIZE))
    assert hits.sum() > 200 and np.abs(found[hits] - exact[hits]).max() < 1e-4
    latitudes = (np.arange(ny) * 0.1 + 60.0).astype(np.float32)  # float32 coordinates: steps spread by rounding
    stored = pv.RectilinearGrid(x, latitudes, z)
    stored.point_data["v"] = values
    spread = np.ptp(np.diff(latitudes.astype(np.float64))) / 0.1
    assert spread > 1e-5 and stored.mip.render("mip", size=SIZE).max() > 0  # beyond EVEN_STEPS: the rounding allowance
    uneven = pv.RectilinearGrid(x ** 1.5, y, z)
    uneven.point_data["v"] = values
    with pytest.raises(TypeError, match="x coordinates are not evenly spaced.*resample"):
        uneven.mip.render("mip", size=SIZE)


def test_a_multiblock_holding_one_volume_is_drawn_as_that_volume(grid):
    """pyvista's MultiBlock (pv.read of a .vtm, a reader's output): ``mb.mip``, ``render`` and ``add_volume`` draw
    the one volume it holds (nested, beside empty blocks), or its image pieces joined (pyvista's
    extract_subset, which rebases each piece's origin); blocks that are not one volume raise TypeError naming
    the fix. Until 2026-12-04 a MultiBlock had no ``mip`` and the filters raised "expected vtkImageData"."""
    nz = grid.dimensions[2]
    image = grid.copy()
    image.origin, image.spacing = (3.0, -2.0, 7.5), (0.5, 0.7, 1.1)
    expected = image.mip.render("analytic", size=SIZE)
    assert (expected.max(axis=-1) > 40).mean() > 0.1  # the vessels
    one = pv.MultiBlock({"empty": pv.MultiBlock(), "inner": pv.MultiBlock([None, image])})
    halves = pv.MultiBlock([image.extract_subset((0, 23, 0, 23, 0, nz // 2)),
                            image.extract_subset((0, 23, 0, 23, nz // 2, nz - 1))])
    assert halves[1].origin[2] != image.origin[2]  # rebased: the second piece's origin is its first point
    before = [(piece.origin, piece.extent, piece.active_scalars.copy()) for piece in halves]
    for blocks in (one, halves):
        assert np.array_equal(blocks.mip.render("analytic", size=SIZE), expected)
        assert np.array_equal(render(blocks, "analytic", size=SIZE), expected)
        plotter = pv.Plotter(off_screen=True, window_size=SIZE)
        try:
            volume = plotter.mip.add_volume(blocks, "analytic")
            assert volume.mapper.GetInput().GetDimensions() == image.dimensions
        finally:
            plotter.close()
    apart = pv.MultiBlock([image, image.translate((100.0, 0.0, 0.0))])
    with pytest.raises(TypeError, match="holds 2 data sets.*draw one of them: pyvista mb\\[0\\]"):
        apart.mip.render(size=SIZE)
    for piece, (origin, extent, values) in zip(halves, before):  # the user's blocks are left as they were
        assert piece.origin == origin and piece.extent == extent and np.array_equal(piece.active_scalars, values)


def _transfer_functions(volume, values):
    """RGB and opacity of ``volume``'s property at ``values``."""
    prop = volume.GetProperty()
    colour, opacity = prop.GetRGBTransferFunction(), prop.GetScalarOpacity()
    return (np.array([colour.GetColor(v) for v in values]), np.array([opacity.GetValue(v) for v in values]))


@pytest.mark.parametrize("kwargs", [
    dict(cmap=["black", "red", "white"], opacity=1.0),
    dict(cmap="viridis", flip_scalars=True, opacity="sigmoid"),
    dict(cmap="bone", opacity=[0.0, 0.3, 1.0]),
    dict(cmap="hot", opacity=np.linspace(1.0, 0.2, 7)),
    dict(cmap="viridis", n_colors=5, opacity="linear_r"),
    dict(colormap="plasma", rng=(0.2, 0.7), opacity=0.5),  # pyvista's aliases
], ids=["colour list", "flipped", "opacity list", "opacity array", "5 colours", "aliases"])
def test_colour_and_opacity_keywords_map_as_pyvista_maps_them(grid, kwargs):
    """cmap (a name, a list of colours), opacity (a number, a name, values spread over clim), n_colors, flip_scalars
    and pyvista's aliases give the transfer functions pyvista's own add_volume builds (its lookup table stores
    colours and opacities in 8 bits and clips opacity at 0.998); before, lists and arrays raised TypeError."""
    kwargs = dict(kwargs)
    clim = kwargs.pop("rng", (0.1, 0.9))
    aliases = {"colormap": kwargs.pop("colormap")} if "colormap" in kwargs else {}
    values = np.linspace(clim[0], clim[1], 97)
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    theirs = plotter.add_volume(grid, clim=clim, blending="maximum", show_scalar_bar=False,
                                **{**kwargs, "cmap": aliases.get("colormap", kwargs.get("cmap"))})
    if aliases:
        ours = plotter.mip.add_volume(grid, "mip", rng=clim, **aliases, **kwargs)
    else:
        ours = plotter.mip.add_volume(grid, "mip", clim=clim, **kwargs)
    (their_rgb, their_alpha), (our_rgb, our_alpha) = (_transfer_functions(v, values) for v in (theirs, ours))
    assert np.abs(our_rgb - their_rgb).max() <= 1.0 / 255 + 1e-6
    assert np.abs(our_alpha - their_alpha).max() <= 2.0 / 255 + 1e-6
    assert np.ptp(our_rgb) > 0.2
    plotter.close()


def test_an_opacity_per_colour_is_used_as_it_is(grid):
    """opacity= n_colors values in [0, 1] are the opacities (pyvista's documented meaning; pyvista 0.49's own
    lookup table stores them in 8 bits unscaled, i.e. as 0)."""
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    alphas = np.linspace(1.0, 0.2, 64)
    volume = plotter.mip.add_volume(grid, "mip", clim=(0.1, 0.9), opacity=alphas, n_colors=64)
    _, found = _transfer_functions(volume, np.linspace(0.1, 0.9, 64))
    assert np.abs(found - alphas).max() < 1e-6
    plotter.close()


def test_log_scale_spreads_the_colour_map_over_the_logarithm(grid):
    """log_scale=True: the colour at v is the map at (log v - log low) / (log high - log low); clim at or below 0
    is refused with the fix."""
    from matplotlib import colormaps

    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    volume = plotter.mip.add_volume(grid, "analytic", cmap="viridis", clim=(0.01, 1.0), log_scale=True)
    values = np.geomspace(0.01, 1.0, 40)
    rgb, _ = _transfer_functions(volume, values)
    expected = colormaps["viridis"](np.log(values / 0.01) / np.log(100.0))[:, :3]
    assert np.abs(rgb - expected).max() < 0.01
    with pytest.raises(ValueError, match="log_scale needs clim above 0.*positive low"):
        plotter.mip.add_volume(grid, "mip", clim=(0.0, 1.0), log_scale=True)
    plotter.close()


def test_scalars_given_as_values_draw_as_the_named_array(grid):
    """scalars= an array (per point in point order, or per cell) as pyvista's add_volume takes it: the same picture
    as the array added by name, the grid unchanged; a wrong length names the two that fit and the fix."""
    doubled = 2.0 * np.asarray(grid.active_scalars)
    named = grid.copy()
    named.point_data["doubled"] = doubled
    expected = render(named, "analytic", size=SIZE, scalars="doubled", window=(0.2, 1.8))
    assert (expected.max(axis=-1) > 40).mean() > 0.1
    arrays_before = grid.array_names
    assert np.array_equal(render(grid, "analytic", size=SIZE, scalars=doubled, window=(0.2, 1.8)), expected)
    assert np.array_equal(grid.mip.render("analytic", size=SIZE, scalars=doubled, window=(0.2, 1.8)), expected)
    assert grid.array_names == arrays_before
    per_cell = grid.point_data_to_cell_data()
    cells = np.asarray(per_cell.active_scalars)
    by_name = render(per_cell, "mip", size=SIZE, scalars=per_cell.active_scalars_name, window=(0.2, 0.9))
    assert np.array_equal(render(grid, "mip", size=SIZE, scalars=cells, window=(0.2, 0.9)), by_name)
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    with pytest.raises(ValueError, match=rf"{grid.n_points}.*{grid.n_cells}.*ravel\(order='F'\)"):
        plotter.mip.add_volume(grid, scalars=doubled[:-1])
    with pytest.raises(TypeError, match="numbers"):
        plotter.mip.add_volume(grid, scalars=np.array(["a"] * grid.n_points))
    assert plotter.renderer.GetVolumes().GetNumberOfItems() == 0
    plotter.close()


def test_a_numpy_volume_and_one_number_clim_as_in_pyvista(grid):
    """A 3-D numpy array indexed [x, y, z] is drawn as pyvista.wrap makes it (resolution= its spacing), and
    clim=c is (-c, c), as pyvista's add_volume takes them."""
    nx, ny, nz = grid.dimensions
    array = np.asarray(grid.active_scalars).reshape(nz, ny, nx).transpose(2, 1, 0)  # [x, y, z]
    spaced = grid.copy()
    spaced.spacing = (1.0, 2.0, 0.5)
    expected = render(spaced, "mip", size=SIZE, window=(-0.9, 0.9))
    assert (expected.max(axis=-1) > 40).mean() > 0.1
    assert np.array_equal(render(array, "mip", size=SIZE, resolution=(1.0, 2.0, 0.5), clim=0.9), expected)
    shots = []
    for volume in (spaced, array):
        plotter = pv.Plotter(off_screen=True, window_size=SIZE)
        plotter.mip.add_volume(volume, "analytic", clim=0.9, resolution=None if volume is spaced else (1, 2, 0.5))
        shots.append(plotter.screenshot())
        plotter.close()
    assert np.array_equal(shots[0], shots[1]) and shots[0].std() > 5
    with pytest.raises(TypeError, match="resolution= is the spacing of a numpy array"):
        render(grid, resolution=(1, 1, 1))
    with pytest.raises(TypeError, match="3-D array"):
        render(np.zeros((4, 4)))


def test_user_matrix_places_the_volume_against_the_float64_reference(grid):
    """user_matrix= (pyvista's placement of the prop): the float readout equals the reference of the volume so placed."""
    from mipcast import reference
    from mipcast.mappers.float_readout import render_float

    matrix = np.array([[0.0, -1.0, 0.0, 5.0], [1.0, 0.0, 0.0, -3.0], [0.0, 0.0, 1.5, 2.0], [0.0, 0.0, 0.0, 1.0]])
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    volume = plotter.mip.add_volume(grid, "analytic", clim=(0.2, 0.9), user_matrix=matrix)
    plotter.camera_position = "iso"
    plotter.render()
    assert np.allclose(volume.user_matrix, matrix)
    found = render_float(plotter.render_window, volume.GetMapper())
    exact = reference.render(grid, plotter.renderer.GetActiveCamera(), SIZE, method="analytic",
                             matrix=volume.GetMatrix())
    hits = ~np.isnan(found) & ~np.isnan(exact)
    assert hits.mean() > 0.1 and np.mean(np.isnan(found) == np.isnan(exact)) > 0.99
    assert np.abs(found[hits] - exact[hits]).max() < 1e-4
    plotter.close()


def test_scalar_bar_and_its_annotations(grid):
    """show_scalar_bar=True adds a bar of the colour map over clim (title: the array's name; scalar_bar_args and
    annotations as in pyvista); by default there is none."""
    plotter = pv.Plotter(off_screen=True, window_size=(128, 128))
    plotter.mip.add_volume(grid, "mip", cmap="hot", clim=(0.1, 0.9))
    assert list(plotter.scalar_bars.keys()) == []
    plotter.mip.add_volume(grid, "mip", cmap="hot", clim=(0.1, 0.9), show_scalar_bar=True, name="barred",
                           annotations={0.5: "half"})
    name = grid.active_scalars_name
    assert list(plotter.scalar_bars.keys()) == [name]
    bar = plotter.scalar_bars[name]
    assert bar.GetLookupTable().GetRange() == (0.1, 0.9) and bar.GetLookupTable().GetAnnotation(0) == "half"
    plotter.mip.add_volume(grid, "mip", show_scalar_bar=True, scalar_bar_args={"title": "HU"}, name="titled")
    assert "HU" in plotter.scalar_bars.keys()
    plotter.close()


@pytest.mark.parametrize("keyword, value, words", [
    ("mapper", "gpu", "the method is the mapper"),  # before: "got multiple values for argument 'mapper'"
    ("shade", True, "not shaded"),
    ("specular", 0.5, "not shaded"),
    ("opacity_unit_distance", 2.0, "does not accumulate opacity"),
    ("categories", True, "not categories"),
    ("blending", "composite", "projects by 'maximum'.*'composite' and 'additive' are not projections"),
    ("blending", "minimum", "'minimum': method .*'minip'"),
    ("cmap", pv.LookupTable(), "LookupTable is not taken"),
    ("n_colors", 1, "n_colors"),
    ("opacity", [0.0, 1.5], r"opacity must be within \[0, 1\]"),
])
def test_pyvista_keywords_without_a_meaning_here_say_why(grid, keyword, value, words):
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    with pytest.raises((TypeError, ValueError), match=words):
        plotter.mip.add_volume(grid, "mip", **{keyword: value})
    assert plotter.renderer.GetVolumes().GetNumberOfItems() == 0
    if keyword == "mapper":
        with pytest.raises(TypeError, match="the method is the mapper"):
            render(grid, "mip", size=SIZE, mapper="gpu")
    plotter.close()


def test_the_method_s_own_blending_is_accepted(grid):
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    for method, blending in (("analytic", "maximum"), ("analytic_minip", "minimum"), ("average", "average")):
        volume = plotter.mip.add_volume(grid, method, blending=blending)
        assert type(volume.GetMapper()) is type(create_mapper(method))
    plotter.close()


@pytest.mark.parametrize("method", ["average", "analytic_average", "minip", "mip"])
def test_every_projection_draws_its_colour_map(grid, method):
    """cmap="hot" colours every mipcast projection (the averages drew VTK's grey before 2026-12-04)."""
    plotter = pv.Plotter(off_screen=True, window_size=SIZE)
    plotter.background_color = "black"
    plotter.mip.add_volume(grid, method, cmap="hot", clim=(0.0, 0.5) if method != "minip" else (0.0, 0.2))
    shot = plotter.screenshot().astype(int)
    plotter.close()
    assert (shot.max(axis=-1) - shot.min(axis=-1)).max() > 100, "no colour: the colour map was not applied"


def test_stock_average_says_it_ignores_the_window_and_colour_map(grid):
    """VTK's AVERAGE_INTENSITY blend draws its own grey whatever window or colours it is given: the pyvista
    filters say so (as the CLI does), and the averages that honour them do not warn."""
    import warnings

    with pytest.warns(mipcast.InputWarning, match="stock_average draws VTK's own grey.*ignores window.*'average'"):
        windowed = render(grid, "stock_average", size=(32, 32), window=(0.3, 0.6))
    assert np.array_equal(windowed, render(grid, "stock_average", size=(32, 32)))  # the window changed nothing
    plotter = pv.Plotter(off_screen=True, window_size=(32, 32))
    with pytest.warns(mipcast.InputWarning, match="ignores clim and cmap"):
        add_volume(plotter, grid, "stock_average", clim=(0.2, 0.8), cmap="viridis")
    plotter.close()
    with warnings.catch_warnings():
        warnings.simplefilter("error", mipcast.InputWarning)
        render(grid, "average", size=(32, 32), window=(0.3, 0.6))
        plotter = pv.Plotter(off_screen=True, window_size=(32, 32))
        add_volume(plotter, grid, "analytic_average", clim=(0.2, 0.8), cmap="viridis")
        plotter.close()


def test_half_precision_and_long_double_arrays_are_drawn_as_their_float_values(grid):
    """VTK has no float16 nor long double: a numpy volume or scalars= values of either were a TypeError from
    VTK's numpy bridge ("Could not find a suitable VTK type for float16"); they are drawn as float32/float64."""
    values = np.asarray(grid.point_data.active_scalars).reshape(grid.dimensions, order="F")
    expected = render(values.astype(np.float32), size=(32, 32))
    assert expected.max() > 100
    assert np.array_equal(render(values.astype(np.float16).astype(np.float32), size=(32, 32)),
                          render(values.astype(np.float16), size=(32, 32)))
    assert np.array_equal(render(values.astype(np.longdouble), size=(32, 32)), render(values, size=(32, 32)))
    flat = values.ravel(order="F").astype(np.float16)
    assert np.array_equal(render(grid, scalars=flat, size=(32, 32)),
                          render(grid, scalars=flat.astype(np.float32), size=(32, 32)))


@pytest.mark.parametrize("dtype", [np.float32, np.int16, np.float64])
def test_masked_array_entries_are_missing_data_not_the_fill_value(grid, dtype):
    """netCDF4 (and readers built on it) return numpy masked arrays where a variable has a fill value; np.asarray
    drops the mask, so the fill value (9.97e36, or -32768 for int16) was drawn as data and took the whole window.
    Masked entries are missing data now: the picture and the float readout are the NaN twin's; nothing the user
    gave is modified."""
    values = (np.asarray(grid.point_data.active_scalars).reshape(grid.dimensions, order="F") * 1000).astype(dtype)
    mask = np.zeros(values.shape, bool)
    mask[:, :, :10] = True
    fill = np.float32(9.96921e36) if np.dtype(dtype).kind == "f" else np.iinfo(dtype).min
    masked = np.ma.masked_array(np.where(mask, fill, values).astype(dtype), mask=mask)
    before = masked.data.copy()
    twin = np.where(mask, np.nan, values).astype(np.float64 if dtype == np.float64 else np.float32)
    for method in ("mip", "analytic", "average"):
        expected = render(twin, method, size=(32, 32), as_float=True)
        assert np.nanmax(expected) < 1001
        got = render(masked, method, size=(32, 32), as_float=True)
        assert np.allclose(got, expected, rtol=1e-6, equal_nan=True), method
        assert np.array_equal(render(masked, method, size=(32, 32)), render(twin, method, size=(32, 32)))
    flat = masked.ravel(order="F")
    assert np.array_equal(render(grid, "mip", scalars=flat, size=(32, 32)),
                          render(twin, "mip", size=(32, 32)))
    assert np.array_equal(masked.data, before) and masked.mask.sum() == mask.sum()
    unmasked = np.ma.masked_array(values, mask=False)  # a mask with nothing masked: the values as they are
    assert np.array_equal(render(unmasked, size=(32, 32)), render(values, size=(32, 32)))


def test_big_endian_arrays_are_drawn_and_left_as_they_were(grid):
    """astropy reads FITS cubes (radio astronomy's peak-intensity maps are MIPs) as big-endian arrays.
    pyvista.wrap byte-swaps such an array in place: mipcast's render handed it the user's array, which then
    held garbage (3.4e38 when used again). Now a native copy is drawn and the user's array stays as it was."""
    values = np.asarray(grid.point_data.active_scalars).reshape(grid.dimensions, order="F")
    expected = render(values.astype(np.float32), size=(32, 32))
    assert expected.max() > 100
    for dtype in (">f4", ">i2", ">f8"):
        native = (values * 1000).astype(dtype[1:] if dtype[1] == "f" else np.int16)
        swapped = native.astype(dtype)
        before = swapped.tobytes()
        assert np.array_equal(render(swapped, size=(32, 32)), render(native, size=(32, 32))), dtype
        assert np.array_equal(render(grid, scalars=swapped.ravel(order="F"), size=(32, 32)),
                              render(grid, scalars=native.ravel(order="F"), size=(32, 32))), dtype
        assert swapped.tobytes() == before and swapped.dtype == np.dtype(dtype), dtype


def test_numpy_vector_and_complex_volumes_draw_their_magnitude_or_a_component(grid):
    """A numpy volume [x, y, z, component] (a simulation's velocity) and a complex one (an MR reconstruction)
    were refused ("must be a 3-D array") or, for complex scalars= values, a TypeError; they are drawn as the
    same components in image data are: the magnitude by default, component= one of them (complex: 0 the real
    part, 1 the imaginary part), missing where any component is NaN or masked."""
    values = np.asarray(grid.point_data.active_scalars).reshape(grid.dimensions, order="F").astype(np.float32)
    vector = np.stack([values, 0.5 * values[::-1], 0.25 * values[:, ::-1]], axis=-1)
    magnitude = np.sqrt((vector.astype(np.float64) ** 2).sum(axis=-1)).astype(np.float32)
    for method in ("mip", "analytic"):
        expected = render(magnitude, method, size=(32, 32), as_float=True)
        assert np.allclose(render(vector, method, size=(32, 32), as_float=True), expected, rtol=1e-5, equal_nan=True)
        for k in range(3):
            assert np.array_equal(render(vector, method, size=(32, 32), component=k),
                                  render(np.ascontiguousarray(vector[..., k]), method, size=(32, 32))), (method, k)
    complex_values = (vector[..., 0] + 1j * vector[..., 1]).astype(np.complex64)
    assert np.allclose(render(complex_values, size=(32, 32), as_float=True),
                       render(np.abs(complex_values), size=(32, 32), as_float=True), rtol=1e-5, equal_nan=True)
    assert np.array_equal(render(complex_values, size=(32, 32), component=1),
                          render(np.ascontiguousarray(vector[..., 1]), size=(32, 32)))
    flat = complex_values.ravel(order="F")
    assert np.array_equal(render(grid, scalars=flat, size=(32, 32)), render(complex_values, size=(32, 32)))
    holed = np.ma.masked_array(complex_values, mask=np.zeros(complex_values.shape, bool))
    holed[:, :, :10] = np.ma.masked
    twin = np.abs(complex_values)
    twin[:, :, :10] = np.nan
    assert np.array_equal(render(holed, size=(32, 32)), render(twin, size=(32, 32)))
    with pytest.raises(TypeError, match="must hold numbers.*astype"):
        render(values.astype(object), size=(32, 32))
    with pytest.raises(TypeError, match="3-D array.*4-D"):
        render(values[..., 0], size=(32, 32))


def test_array_like_volumes_are_read_as_numpy(grid):
    """xarray's DataArray, h5py's and zarr's datasets and dask arrays are volumes users have: any object with
    __array__ and 3 or 4 dimensions is drawn as np.asarray of it (it was "expected vtkImageData ... got ...")."""

    class Dataset:  # what h5py.Dataset, zarr.Array and xarray.DataArray share for this purpose
        def __init__(self, values):
            self._values = values
            self.ndim, self.shape, self.dtype = values.ndim, values.shape, values.dtype

        def __array__(self, dtype=None, copy=None):
            return self._values if dtype is None else self._values.astype(dtype)

    values = np.asarray(grid.point_data.active_scalars).reshape(grid.dimensions, order="F").astype(np.float32)
    assert np.array_equal(render(Dataset(values), "analytic", size=(32, 32)), render(values, "analytic", size=(32, 32)))
    with pytest.raises(TypeError, match="expected vtkImageData"):
        render(Dataset(values[0]), size=(32, 32))  # 2-D: not a volume
