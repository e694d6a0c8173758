"""Foveated rendering: exact fovea, seamless blend, edge cases, pyramid, cost accounting, gaze sources."""
import numpy as np
import pytest

from mipcast import METHODS, FoveatedVolumeMapper
from mipcast.data_fixtures import image_from_array, make_fixture
from mipcast.core import foveation
from mipcast.mappers.foveated import layer_methods
from mipcast.core.foveation import (REACH_TEXELS, blend_shares, desired_level, eccentricity, level_border,
                               plan_frame)
from mipcast.offscreen import OffscreenView
from mipcast.mappers.shader_pieces import load_piece
from mipcast.mappers.volume_pyramid import build_max_pyramid, max_reduce_axis

SIZE = (128, 96)
GAZE = (0.4, 0.6)


def _views(image, method="mip", size=SIZE, zoom=1.0, window=None, **settings):
    """(full-quality view, foveated view) of one scene; settings go to the foveated mapper."""
    full = OffscreenView(image, method, size=size, window=window)
    fov = OffscreenView(image, "foveated", size=size, window=window)
    fov.mapper.SetMethod(method)
    for view in (full, fov):
        view.camera.Zoom(zoom)
        view.renderer.ResetCameraClippingRange()
    for name, value in settings.items():
        getattr(fov.mapper, "Set" + name)(*np.atleast_1d(value))
    return full, fov


def _grey_error(a, b):
    return np.abs(a.astype(int) - b.astype(int)).max(axis=-1)


def _fovea(view, radius=None):
    width, height = view.render_window.GetSize()
    plan = view.mapper.GetLastPlan()
    radius = view.mapper.GetFovealRadius() if radius is None else radius
    return eccentricity((width, height), plan.gaze, width / height) <= radius


@pytest.mark.parametrize("method", layer_methods())
def test_fovea_equals_the_method_at_full_quality(vessels48, method):
    full, fov = _views(vessels48, method, GazePoint=GAZE, FovealRadius=0.3)
    reference, picture = full.screenshot(), fov.screenshot()
    inside = _fovea(fov)
    error = _grey_error(reference, picture)
    assert inside.mean() > 0.15 and reference[inside].max() > 200, "fovea must hold lit vessels"
    assert np.mean(error[inside] <= 1) >= 0.99
    outside = ~inside & (reference.max(axis=-1) > 0)
    assert picture[outside].max() > 150, "the periphery is drawn"
    assert error[outside].mean() > 0.2, "the periphery is coarser (foveation is on)"
    assert [layer.level for layer in fov.mapper.GetLastPlan().layers] == [2, 1, 0]


def test_foveation_off_is_full_quality_everywhere(vessels48):
    full, fov = _views(vessels48, "analytic", Foveation=False, GazePoint=(0.9, 0.1))
    assert np.all(_grey_error(full.screenshot(), fov.screenshot()) <= 1)
    cost = fov.mapper.GetLastFrameCost()
    assert cost["rays"] == cost["full_rays"] and cost["samples"] == cost["full_samples"]


def test_opaque_geometry_stops_the_rays_of_every_level(vessels48):
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    full, fov = _views(vessels48, GazePoint=(0.1, 0.5), FovealRadius=0.2)
    unoccluded = full.screenshot()
    for view in (full, fov):
        sphere = vtkSphereSource()
        sphere.SetCenter(vessels48.GetCenter())
        sphere.SetRadius(10.0)
        mapper = vtkPolyDataMapper()
        mapper.SetInputConnection(sphere.GetOutputPort())
        actor = vtkActor()
        actor.SetMapper(mapper)
        view.renderer.AddActor(actor)
        view.renderer.ResetCameraClippingRange()
    reference, picture = full.screenshot(), fov.screenshot()
    assert np.mean(_grey_error(reference, picture)[_fovea(fov)] <= 1) >= 0.99
    # rays that the sphere cuts short (their maximum lay behind it), far out in the periphery
    cut = (_grey_error(reference, unoccluded) > 40) & ~_fovea(fov, radius=0.35)
    assert cut.sum() > 30
    # every level reads the copied depth buffer: there too the rays stop at the sphere
    to_cut = _grey_error(picture, reference)[cut].mean()
    to_uncut = _grey_error(picture, unoccluded)[cut].mean()
    assert to_cut < 0.5 * to_uncut, (to_cut, to_uncut)


def test_float_readout_is_the_blended_image(vessels48):
    from mipcast.core.metrics import summary

    full, fov = _views(vessels48, GazePoint=GAZE, FovealRadius=0.3)
    exact, values = full.float_image(), fov.float_image()
    inside = _fovea(fov)
    assert np.array_equal(np.isnan(exact[inside]), np.isnan(values[inside]))
    assert np.nanmax(np.abs(exact - values)[inside]) < 1e-6
    low, high = vessels48.GetPointData().GetScalars().GetRange(0)
    stats = summary(values, exact, high - low)  # raises if a hit pixel went missing
    assert 0 < stats["mean_pct"] < 5


def _ring_steps(image, size, zoom, falloff):
    """Mean |error| in 2-pixel rings either side of each blend-zone edge, and the coarser level's own error."""
    full, fov = _views(image, size=size, zoom=zoom, FovealRadius=0.15, Falloff=falloff)
    reference = full.screenshot()[..., 0].astype(float)
    error = np.abs(fov.screenshot()[..., 0].astype(float) - reference)
    plan, cost = fov.mapper.GetLastPlan(), fov.mapper.GetLastFrameCost()
    e = eccentricity(size, plan.gaze, plan.aspect)
    ring = 2.0 / size[1]
    steps = []
    for k in range(plan.top + 1):
        edge = level_border(plan, k)
        coarser = min(k + 1, plan.top)
        level = next(entry for entry in cost["levels"] if entry["level"] == coarser)
        pure = OffscreenView(image, "mip", size=size, sample_distance=level["sample_distance"])
        pure.camera.Zoom(zoom)
        pure.renderer.ResetCameraClippingRange()
        pure.mapper.SetImageSampleDistance(2 ** coarser)
        inner, outer = (e >= edge - ring) & (e < edge), (e >= edge) & (e < edge + ring)
        own = np.abs(pure.screenshot()[..., 0].astype(float) - reference)[inner | outer].mean()
        steps.append((abs(error[outer].mean() - error[inner].mean()), own))
    return steps


def test_no_seam_at_level_borders():
    # a dense texture (smooth noise) so that every ring has coarse-level error
    image = make_fixture("noise", size=48)
    for step, own in _ring_steps(image, (128, 128), 1.6, falloff=0.3):
        assert own > 0.5, "the coarser level must have an error to compare with"
        assert step <= 0.5 * own, (step, own)
    # the same check catches a hard switch (falloff 0): it is not vacuous
    step, own = _ring_steps(image, (128, 128), 1.6, falloff=0.0)[0]
    assert step > own


@pytest.mark.parametrize("levels", [3, 4])
def test_level_schedule_follows_acuity(levels):
    # the ray spacing 2**lam grows linearly with eccentricity (as the minimum angle of
    # resolution does), from 1 at the fovea's edge to 2**(levels - 1) a falloff further out
    falloff = 0.127
    plan = plan_frame((0, 0, 1024, 1024), (0.5, 0.5), 0.188, falloff, levels)
    top = levels - 1
    assert plan.top == top
    x = np.linspace(0.0, falloff, 17)
    assert np.allclose(2.0 ** desired_level(plan.start + x, plan), 1.0 + (2 ** top - 1) * x / falloff)
    for k in range(levels):
        border = level_border(plan, k)
        assert border == pytest.approx(plan.start + falloff * (2 ** k - 1) / (2 ** top - 1))
        assert float(desired_level(border, plan)) == pytest.approx(k)
    assert float(desired_level(plan.start - 0.01, plan)) == 0.0
    assert float(desired_level(plan.start + 2 * falloff, plan)) == top


def test_first_blend_is_narrow_so_level_0_casts_fewer_rays():
    falloff = 0.127
    plan = plan_frame((0, 0, 1024, 1024), (0.5, 0.5), 0.188, falloff)
    assert float(desired_level(plan.start + falloff / 3, plan)) == pytest.approx(1.0)  # linear: 0.67
    layers = {layer.level: layer for layer in plan.layers}
    assert layers[0].cast_to == pytest.approx(plan.start + falloff / 3)  # level 0 has no bilinear reach
    assert layers[1].cast_to == pytest.approx(plan.start + falloff + 1.5 / 512)  # the outer circle is kept
    e = eccentricity((1024, 1024), plan.gaze, plan.aspect)
    rays = np.count_nonzero(e < layers[0].cast_to)
    linear = np.count_nonzero(e < plan.start + falloff / 2)
    fovea = np.count_nonzero(e < plan.start)
    assert rays < 0.85 * linear and rays - fovea < 0.7 * (linear - fovea)
    assert np.all(blend_shares(plan)[0][e >= layers[0].cast_to] == 0.0)


@pytest.mark.parametrize("viewport, gaze, radius, falloff, levels", [
    ((0, 0, 1024, 1024), (0.5, 0.5), 0.188, 0.127, 3),
    ((0, 0, 300, 200), (0.1, 0.8), 0.1, 0.3, 5),
    ((10, 20, 64, 160), (0.5, 0.2), 0.05, 0.2, 4),
    ((0, 0, 256, 256), (0.4, 0.6), 0.1, 0.0, 3),
    ((0, 0, 256, 256), (0.4, 0.6), 0.1, 0.2, 2),
    ((0, 0, 256, 256), (1.5, -0.3), 0.1, 0.2, 3),
])
def test_levels_cast_rays_wherever_they_have_a_share(viewport, gaze, radius, falloff, levels):
    plan = plan_frame(viewport, gaze, radius, falloff, levels)
    _, _, width, height = plan.viewport
    e = eccentricity((width, height), plan.gaze, plan.aspect)
    shares = blend_shares(plan)
    assert np.allclose(sum(shares.values()), 1.0)
    for layer in plan.layers:
        grid = layer.grid
        reach = 0.0 if layer.level == 0 else REACH_TEXELS * max(1.0 / grid[1], plan.aspect / grid[0])
        used = e[shares[layer.level] > 0]
        # every texel a used pixel reads (bilinear, up to `reach` away) casts its ray
        assert np.all(used >= layer.cast_from + reach - 1e-9), layer
        assert np.all(used < layer.cast_to - reach + 1e-9), layer


@pytest.mark.parametrize("viewport, falloff, levels", [
    ((0, 0, 96, 96), 0.127, 3), ((0, 0, 96, 96), 0.0, 3), ((0, 0, 128, 96), 0.05, 4), ((0, 0, 1024, 1024), 0.0, 5),
    ((0, 0, 1024, 1024), 0.127, 3),
])
def test_no_coarse_level_reaches_into_the_fovea(viewport, falloff, levels):
    # a level's picture is stretched over the window: a pixel reads texels up to `reach` away, so the texels it
    # casts (from cast_from on) show down to cast_from - reach; inside the radius only level 0 may show
    plan = plan_frame(viewport, (0.4, 0.6), 0.188, falloff, levels)
    assert plan.top >= 2
    for layer in plan.layers[:-1]:
        grid = layer.grid
        reach = REACH_TEXELS * max(1.0 / grid[1], plan.aspect / grid[0])
        assert layer.cast_from - reach >= 0.188 - 1e-9, layer


@pytest.mark.parametrize("falloff", [None, 0.0])
@pytest.mark.parametrize("cut", ["opacity ramp", "clipping plane"])
def test_a_semi_transparent_or_clipped_fovea_is_full_quality(falloff, cut):
    """Acuity-only foveation on a coloured background, where level 0's ray is semi-transparent or clipped away:
    the coarse levels drawn beneath must not show.  Before every level kept out of the fovea (start), level 2's
    stretched picture reached into the fovea's rim: vessels 96², up to 4 grey (default falloff), 41 (falloff 0)."""
    from test_content_adaptive import _clip_plane, _opacity_ramp

    image = make_fixture("vessels", size=32)
    views = []
    for name in ("mip", "foveated"):
        view = OffscreenView(image, name, size=(96, 96), window=(0.25, 1.0))
        view.renderer.SetBackground(0.1, 0.2, 0.3)
        view.camera.Zoom(1.6)
        view.renderer.ResetCameraClippingRange()
        (_opacity_ramp if cut == "opacity ramp" else _clip_plane)(view.mapper)
        views.append(view)
    full, fov = views
    if falloff is not None:
        fov.mapper.SetFalloff(falloff)
    reference = full.screenshot().astype(int)
    worst = 0
    for gaze in ((0.3, 0.5), (0.7, 0.5), (0.7, 0.1), (0.5, 0.3)):
        fov.mapper.SetGazePoint(*gaze)
        fovea = eccentricity((96, 96), gaze, 1.0) <= fov.mapper.GetFovealRadius()
        error = np.abs(fov.screenshot().astype(int) - reference).max(axis=-1)
        worst = max(worst, int(error[fovea].max()))
        assert len(fov.mapper.GetLastPlan().layers) == 3
    assert worst <= 1, worst


def test_falloff_zero_switches_levels_at_the_fovea_edge():
    plan = plan_frame((0, 0, 256, 256), (0.5, 0.5), 0.1, 0.0)
    assert plan.top == 2
    assert level_border(plan, 2) == pytest.approx(plan.start, abs=2e-6)  # falloff taken as 1e-6
    assert float(desired_level(plan.start, plan)) == 0.0
    assert float(desired_level(plan.start + 1.0 / 256, plan)) == 2.0  # one pixel out
    assert level_border(plan_frame((0, 0, 256, 256), (0.5, 0.5), 0.1, 0.2, levels=1), 1) == np.inf


def test_shader_draws_the_acuity_blend(vessels48):
    # between the fovea and level 1 the picture is w * level 0 + (1 - w) * level 1:
    # recover w where the two levels differ and compare with the CPU's 1 - lam
    size, zoom = (128, 128), 1.6
    _, fov = _views(vessels48, size=size, zoom=zoom, FovealRadius=0.15, Falloff=0.3)
    picture = fov.screenshot()[..., 0].astype(float)
    plan, cost = fov.mapper.GetLastPlan(), fov.mapper.GetLastFrameCost()
    level0 = OffscreenView(vessels48, "mip", size=size)
    level1_cost = next(entry for entry in cost["levels"] if entry["level"] == 1)
    level1 = OffscreenView(vessels48, "mip", size=size, sample_distance=level1_cost["sample_distance"])
    level1.mapper.SetImageSampleDistance(2)
    for view in (level0, level1):
        view.camera.Zoom(zoom)
        view.renderer.ResetCameraClippingRange()
    first, second = (view.screenshot()[..., 0].astype(float) for view in (level0, level1))
    e = eccentricity(size, plan.gaze, plan.aspect)
    blend = (e > plan.start) & (e < level_border(plan, 1)) & (np.abs(first - second) > 8)
    assert blend.sum() > 100
    weight = (picture - second)[blend] / (first - second)[blend]
    acuity = 1.0 - desired_level(e[blend], plan)
    linear = np.clip(1.0 - (e[blend] - plan.start) / 0.15, 0.0, 1.0)  # the old schedule
    assert np.median(np.abs(weight - acuity)) < 0.08
    assert np.median(np.abs(weight - linear)) > 0.15  # the check tells the schedules apart


def test_blend_shares_are_a_partition_with_full_quality_inside():
    plan = plan_frame((0, 0, 120, 80), (0.3, 0.6), 0.2, 0.2)
    shares = blend_shares(plan)
    assert np.allclose(sum(shares.values()), 1.0)
    inside = eccentricity((120, 80), plan.gaze, plan.aspect) <= 0.2
    assert np.all(shares[0][inside] == 1.0)
    assert all(np.all((s >= 0) & (s <= 1)) for s in shares.values())


# -- edge cases -------------------------------------------------------------------------
@pytest.mark.parametrize("gaze", [(3.0, -2.0), (-0.05, 0.5)])
def test_gaze_outside_the_viewport(vessels48, gaze):
    full, fov = _views(vessels48, GazePoint=gaze)
    picture = fov.screenshot()
    levels = [layer.level for layer in fov.mapper.GetLastPlan().layers]
    assert picture.max() > 150
    if gaze[0] > 1:  # far away: no full-quality rays at all
        assert levels == [2]
        cost = fov.mapper.GetLastFrameCost()
        assert cost["rays"] < cost["full_rays"] / 8
    else:  # the fovea overlaps the left edge
        assert levels[-1] == 0
        inside = _fovea(fov)
        assert np.mean(_grey_error(full.screenshot(), picture)[inside] <= 1) >= 0.99


def test_radius_zero_and_radius_covering_the_view(vessels48):
    full, small = _views(vessels48, FovealRadius=0.0)
    reference = full.screenshot()
    picture = small.screenshot()
    assert picture.max() > 150 and _grey_error(reference, picture).mean() > 0.5
    _, whole = _views(vessels48, FovealRadius=0.9, GazePoint=(0.5, 0.5))  # corners at 0.83 of the height
    assert np.all(_grey_error(reference, whole.screenshot()) <= 1)
    assert [layer.level for layer in whole.mapper.GetLastPlan().layers] == [0]


def test_one_pixel_window(vessels48):
    full, fov = _views(vessels48, size=(1, 1))
    assert np.all(_grey_error(full.screenshot(), fov.screenshot()) <= 1)
    assert [layer.level for layer in fov.mapper.GetLastPlan().layers] == [0]


@pytest.mark.parametrize("size, zoom", [((128, 48), 1.5), ((40, 120), 3.0)])
def test_non_square_windows_measure_eccentricity_in_heights(vessels48, size, zoom):
    full, fov = _views(vessels48, size=size, zoom=zoom, GazePoint=(0.5, 0.5), FovealRadius=0.25)
    error = _grey_error(full.screenshot(), fov.screenshot())
    inside = _fovea(fov)
    # the fovea is a circle in pixels (clipped by the window): as wide as high where it fits
    rows, columns = np.nonzero(inside)
    across = min(size[0], 0.5 * size[1] + 1)
    assert abs((columns.max() - columns.min() + 1) - min(rows.max() - rows.min() + 1, across)) <= 2
    assert np.mean(error[inside] <= 1) >= 0.99
    # outside the fovea (and the volume's silhouette band, which level 0 casts) the levels are coarser
    silhouette = fov.mapper.GetLastSilhouette()
    band = foveation.silhouette_band(fov.mapper.GetLastPlan(), silhouette, size)
    assert error[~inside & ~band].mean() > 0.1


def test_window_resize(vessels48):
    full, fov = _views(vessels48, size=(96, 64), GazePoint=GAZE, FovealRadius=0.3)
    fov.screenshot()
    for size in [(64, 112), (128, 96)]:
        full.render_window.SetSize(*size)
        fov.render_window.SetSize(*size)
        picture = fov.screenshot()
        assert picture.shape[:2] == (size[1], size[0])
        assert fov.mapper.GetLastPlan().viewport == (0, 0) + size
        assert np.mean(_grey_error(full.screenshot(), picture)[_fovea(fov)] <= 1) >= 0.99
        assert picture.max() > 150


def _image(values, spacing=(1.0, 1.0, 1.0)):
    return image_from_array(np.asarray(values, np.float32), spacing=spacing)


def test_volume_smaller_than_the_coarsest_pyramid_level():
    tiny = _image(np.random.default_rng(3).random((3, 2, 3)) + 0.2)
    assert len(build_max_pyramid(tiny, 3)) == 2  # 3 points shrink to 2, then nothing can
    assert len(build_max_pyramid(_image(np.ones((2, 2, 2))), 3)) == 1
    full, fov = _views(tiny, size=(96, 96), window="full", GazePoint=(0.9, 0.9), FovealRadius=0.0)
    picture = fov.screenshot()
    assert picture.max() > 50
    full, fov = _views(tiny, size=(96, 96), zoom=0.08, window="full", GazePoint=(0.95, 0.95), FovealRadius=0.0)
    # the volume covers a few pixels, fewer than a level-2 texel: coarse levels would miss it
    reference, picture = full.screenshot(), fov.screenshot()
    assert 0 < np.count_nonzero(reference.max(axis=-1)) < 64
    assert fov.mapper.GetLastPlan().top == 0
    assert np.all(_grey_error(reference, picture) <= 1)


# -- pyramid and sampling -----------------------------------------------------------------
def test_max_pyramid_keeps_every_peak_within_one_coarse_voxel():
    rng = np.random.default_rng(5)
    values = rng.random((17, 12, 9)).astype(np.float32)
    image = _image(values, spacing=(0.5, 1.0, 2.0))
    pyramid = build_max_pyramid(image, 4)
    assert [p.GetBounds() for p in pyramid] == [image.GetBounds()] * len(pyramid)
    from vtkmodules.util.numpy_support import vtk_to_numpy
    for level in pyramid[1:]:
        coarse = vtk_to_numpy(level.GetPointData().GetScalars())
        assert coarse.max() == values.max() and coarse.min() >= values.min()
    spike = np.zeros(11)
    spike[5] = 1.0
    assert max_reduce_axis(spike, 0).max() == 1.0


def test_zoomed_out_periphery_reads_the_max_pyramid_and_keeps_vessels():
    image = make_fixture("vessels", size=64)
    full, fov = _views(image, size=(64, 64), zoom=0.8, GazePoint=(0.05, 0.05), FovealRadius=0.0)
    reference, picture = full.screenshot()[..., 0], fov.screenshot()[..., 0]
    levels = {entry["level"]: entry["volume_level"] for entry in fov.mapper.GetLastFrameCost()["levels"]}
    assert levels[2] >= 1, levels  # rays 4 px apart, a pixel > 1 voxel: a coarse volume level
    far = _fovea(fov, radius=0.6) == 0
    # max filter: peaks are not lowered (a box filter would dim thin vessels)
    assert picture[far].max() >= reference[far].max() - 2


def test_peripheral_sampling_policies():
    image = make_fixture("vessels", size=48)
    _, fov = _views(image, size=(96, 96), zoom=1.8, GazePoint=(0.5, 0.5), FovealRadius=0.1)
    fov.screenshot()
    footprint = fov.mapper.GetLastFrameCost()
    fov.mapper.SetPeripheralSampling("rays")
    fov.screenshot()
    rays = fov.mapper.GetLastFrameCost()
    assert rays["samples"] < footprint["samples"] and rays["rays"] == footprint["rays"]
    with pytest.raises(ValueError, match="footprint"):
        fov.mapper.SetPeripheralSampling("box")


# -- cost accounting ----------------------------------------------------------------------
def test_cost_counts_rays_of_the_full_quality_image(vessels48):
    full, fov = _views(vessels48, GazePoint=GAZE)
    hits = int(np.count_nonzero(~np.isnan(full.float_image())))
    fov.screenshot()
    cost = fov.mapper.GetLastFrameCost()
    assert abs(cost["full_rays"] - hits) <= 0.03 * hits  # the outline may round either way
    assert cost["rays"] < cost["full_rays"] and cost["samples"] < cost["full_samples"]
    assert cost["ray_ratio"] == pytest.approx(cost["full_rays"] / cost["rays"])
    assert sum(level["rays"] for level in cost["levels"]) == cost["rays"]
    assert cost["unit"] == "samples"
    fov.mapper.SetMethod("analytic")
    fov.screenshot()
    assert fov.mapper.GetLastFrameCost()["unit"] == "cells"


# -- settings and gaze sources -------------------------------------------------------------
def test_settings_are_validated():
    mapper = FoveatedVolumeMapper()
    for bad in ("stock", "foveated", "nope"):
        with pytest.raises(ValueError, match="'mip'"):
            mapper.SetMethod(bad)
    with pytest.raises(ValueError):
        mapper.SetFovealRadius(-0.1)
    with pytest.raises(ValueError):
        mapper.SetGazePoint(float("nan"), 0.5)
    with pytest.raises(ValueError):
        mapper.SetNumberOfLevels(0)
    with pytest.raises(ValueError):
        mapper.SetRegionOfInterest((1, 0, 0, 1, 0, 1))
    assert "foveated" in METHODS and "foveated" not in layer_methods()


def test_level_pieces_fit_every_method():
    from mipcast.mappers.foveated_levels import level_class

    for name in layer_methods():
        tags = [load_piece(n).tag for n in level_class(METHODS[name].factory)().GetShaderPieces()]
        assert len(tags) == len(set(tags)), name


def test_region_of_interest_moves_the_gaze_and_covers_the_region(vessels48):
    _, fov = _views(vessels48, size=(96, 96), GazePoint=(0.1, 0.1), FovealRadius=0.05)
    x0, x1, y0, y1, z0, z1 = vessels48.GetBounds()
    corner = (x0, x0 + 0.2 * (x1 - x0), y0, y0 + 0.2 * (y1 - y0), z0, z0 + 0.2 * (z1 - z0))
    fov.mapper.SetRegionOfInterest(corner)
    fov.screenshot()
    assert fov.mapper.GetGazeSource() == "region"
    gaze = fov.mapper.GetGazePoint()
    display = []
    for x in corner[0:2]:
        for y in corner[2:4]:
            for z in corner[4:6]:
                fov.renderer.SetWorldPoint(x, y, z, 1.0)
                fov.renderer.WorldToView()
                display.append(fov.renderer.GetViewPoint()[:2])
    display = (np.array(display) + 1.0) / 2.0
    assert np.allclose(gaze, display.mean(axis=0), atol=0.05)
    plan = fov.mapper.GetLastPlan()
    reach = np.hypot(*(display - np.array(gaze)).T).max()
    assert plan.start >= reach  # the whole region is inside the fovea
    fov.mapper.SetRegionOfInterest(None)
    fov.screenshot()
    assert fov.mapper.GetGazeSource() == "point" and fov.mapper.GetGazePoint() == (0.1, 0.1)
    fov.mapper.SetGazePoint(0.5, 0.5)
    assert fov.mapper.GetGazeSource() == "point" and fov.mapper.GetGazePoint() == (0.5, 0.5)


def test_gaze_follows_the_mouse(vessels48):
    from vtkmodules.vtkCommonCore import vtkCommand
    from vtkmodules.vtkRenderingUI import vtkGenericRenderWindowInteractor

    _, fov = _views(vessels48, size=(100, 80))
    interactor = vtkGenericRenderWindowInteractor()
    interactor.SetRenderWindow(fov.render_window)
    fov.mapper.FollowMouse(interactor)
    assert fov.mapper.GetGazeSource() == "mouse"
    frames = []
    fov.renderer.AddObserver(vtkCommand.EndEvent, lambda *_: frames.append(1))
    interactor.SetEventPosition(24, 59)
    interactor.InvokeEvent(vtkCommand.MouseMoveEvent)
    assert frames, "a mouse move renders a frame"
    assert fov.mapper.GetGazePoint() == pytest.approx((24.5 / 100, 59.5 / 80))
    fov.mapper.FollowMouse(None)
    assert fov.mapper.GetGazeSource() == "point"


def test_analytic_levels_reading_one_volume_share_its_packed_copy():
    from mipcast.core.object_state import object_state
    from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

    image = make_fixture("vessels", size=32)
    view = OffscreenView(image, "foveated", size=(128, 128))
    view.mapper.SetMethod("analytic")
    view.camera.Zoom(3.0)  # zoomed in: every level reads the full-resolution volume
    view.renderer.ResetCameraClippingRange()
    picture = view.screenshot()
    levels = [layer.level for layer in view.mapper.GetLastPlan().layers]
    assert len(levels) >= 2 and all(entry["volume_level"] == 0 for entry in view.mapper.GetLastFrameCost()["levels"])
    mappers = [view.mapper.GetLevelMapper(level) for level in levels]
    packers = {id(object_state(m)["packer"]) for m in mappers}
    assert len(packers) == 1  # one packed copy of the volume, not one per level
    drawn = {vtkOpenGLGPUVolumeRayCastMapper.GetInput(m).GetAddressAsString("vtkObjectBase") for m in mappers}
    assert len(drawn) == 1
    assert all(m.GetInput() is image for m in mappers) and picture.max() > 100


@pytest.mark.parametrize("tolerance", [0.0, 2.0])
def test_an_extent_that_does_not_start_at_zero_draws_the_same_foveated_frame(tolerance):
    """A piece's extent (vtkExtractVOI, pyvista's extract_subset, a ParaView piece) may start anywhere: the same
    volume with extent (5..28, -3..20, 7..30) and its origin moved back draws the same picture and float readout.
    Before, the silhouette band's corners were taken at indices 0..n-1, off the volume by the extent's start:
    534 of 9216 pixels up to 153 grey off (acuity only), 19 % of the rays' hit / miss wrong."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    image = make_fixture("vessels", size=24)
    moved = vtkImageData()
    moved.DeepCopy(image)
    moved.SetExtent(5, 28, -3, 20, 7, 30)
    moved.SetOrigin(-5.0, 3.0, -7.0)
    assert moved.GetBounds() == image.GetBounds()
    for gaze in ((0.5, 0.5), (0.2, 0.7)):
        views = [OffscreenView(data, "foveated", size=(96, 96), window=(0.25, 1.0)) for data in (image, moved)]
        for view in views:
            view.mapper.SetContentTolerance(tolerance)
            view.mapper.SetGazePoint(*gaze)
        views[1].camera.DeepCopy(views[0].camera)
        views[1].renderer.ResetCameraClippingRange()
        first, second = (view.screenshot() for view in views)
        assert first.max() > 200 and np.array_equal(first, second)
        np.testing.assert_array_equal(views[0].float_image(), views[1].float_image())
