"""Content-adaptive ray density: fewer rays where the coarse picture is flat, the fovea exact on structure."""
import numpy as np
import pytest

from mipcast.core.content_adaptive import adaptive_plan, refinement_mask, refinement_test
from mipcast.core.foveation import eccentricity, plan_frame, silhouette_band
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

SIZE = (96, 96)
WINDOW = (0.25, 1.0)  # the vessels' background below the floor: black


@pytest.fixture(scope="module")
def vessels():
    return make_fixture("vessels", size=32)


def _pair(image, method, **settings):
    full = OffscreenView(image, method, size=SIZE, window=WINDOW)
    fov = OffscreenView(image, "foveated", size=SIZE, window=WINDOW)
    fov.mapper.SetMethod(method)
    for view in (full, fov):
        view.camera.Zoom(1.6)
        view.renderer.ResetCameraClippingRange()
    for name, value in settings.items():
        getattr(fov.mapper, "Set" + name)(*np.atleast_1d(value))
    return full, fov


def test_masks_follow_edges_everywhere_and_structure_in_the_fovea():
    plan = adaptive_plan(plan_frame((0, 0, 64, 64), (0.25, 0.5), 0.15, 0.1))
    assert [layer.level for layer in plan.layers] == [3, 2, 1, 0]
    assert plan.layers[0].cast_from == plan.layers[1].cast_from == -np.inf  # acuity's coarsest: its mask decides
    coarse = np.zeros((16, 16, 3), np.uint8)   # the picture at level 2's texels
    coarse[:, 2:6] = 120        # flat structure under the gaze
    coarse[:, 12:] = 120        # flat structure in the periphery, with an edge at column 12
    test = refinement_test(coarse, np.zeros_like(coarse), 4.0)
    fine = refinement_mask(*test, plan, plan.layers[3])
    assert fine[32, 16] and fine[32, 12]          # structure inside the fovea: cast
    assert not fine[32, 40]                       # background, no edge: interpolated
    level1 = refinement_mask(*test, plan, plan.layers[2])
    assert level1[16, 23] and not level1[16, 29]  # the periphery's edge only, not its flat inside
    # the next finer level follows the picture its coarser level left: an edge it drew is refined again
    refined = coarse.copy()
    refined[:, 13] = 60
    assert refinement_mask(*refinement_test(refined, np.zeros_like(refined), 4.0), plan, plan.layers[2])[16, 28]


def test_content_level_is_one_coarser_than_acuity_unless_the_scene_caps_it():
    acuity = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1)
    plan = adaptive_plan(acuity)
    content = plan.layers[0]
    assert content.level == acuity.top + 1 and content.grid == (8, 8) and content.scissor is None
    assert plan.layers[2:] == acuity.layers[1:] and plan.layers[1].level == acuity.top
    capped = adaptive_plan(acuity, max_level=acuity.top)
    assert [layer.level for layer in capped.layers] == [layer.level for layer in acuity.layers]
    assert capped.layers[0].cast_from == -np.inf   # the coarsest level cast everywhere instead
    tiny = adaptive_plan(plan_frame((0, 0, 24, 24), (0.5, 0.5), 0.1, 0.1))   # 3 texels at level 3: too few
    assert tiny.layers[0].level == 2


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_fovea_stays_full_quality_on_structure_with_fewer_rays(vessels, method):
    full, fov = _pair(vessels, method, GazePoint=(0.5, 0.5), ContentTolerance=2.0)
    _, acuity = _pair(vessels, method, GazePoint=(0.5, 0.5))
    reference, picture, plain = full.screenshot(), fov.screenshot(), acuity.screenshot()
    assert reference.max() > 200 and (reference.max(axis=-1) == 0).mean() > 0.3, "vessels on black"
    e = eccentricity(SIZE, (0.5, 0.5), 1.0)
    fovea = e <= fov.mapper.GetFovealRadius()
    structure = fovea & (reference.max(axis=-1) > 0)
    error = np.abs(reference.astype(int) - picture).max(axis=-1)
    assert structure.sum() > 200
    assert np.all(error[structure] <= 1)
    assert np.all(error[fovea] <= 1)  # background in the fovea: the coarse level shows black too
    plain_error = np.abs(reference.astype(int) - plain).max(axis=-1)
    assert error[~fovea].mean() <= plain_error[~fovea].mean() + 0.05
    cost, plain_cost = fov.mapper.GetLastFrameCost(), acuity.mapper.GetLastFrameCost()
    # the 1024² benchmark saves more (docs/foveation.md); both cast the same level-0 rays of the
    # volume's silhouette band (the same plan), which content-adaptive density does not touch
    assert cost["band_rays"] == plain_cost["band_rays"]
    band = cost["band_rays"]
    assert cost["rays"] - band < 0.92 * (plain_cost["rays"] - band)


def test_the_benchmarks_variant_without_the_content_level_keeps_the_fovea(vessels):
    """``object_state(mapper)["no_content_level"]`` (the benchmarks' "content-adaptive 2 grey, no content level",
    docs/foveation.md): acuity's coarsest level decides alone, cast over the whole viewport unmasked; the fovea's
    structure stays within 1 grey of full quality and the periphery no worse than acuity only's."""
    from mipcast.core.object_state import object_state

    full, fov = _pair(vessels, "mip", GazePoint=(0.5, 0.5), ContentTolerance=2.0)
    _, acuity = _pair(vessels, "mip", GazePoint=(0.5, 0.5))
    object_state(fov.mapper)["no_content_level"] = True
    reference, picture, plain = full.screenshot(), fov.screenshot(), acuity.screenshot()
    levels = [layer.level for layer in fov.mapper.GetLastPlan().layers]
    assert levels == [layer.level for layer in acuity.mapper.GetLastPlan().layers]  # no level 3 first
    assert fov.mapper.GetLastPlan().layers[0].cast_from == -np.inf
    fovea = eccentricity(SIZE, (0.5, 0.5), 1.0) <= fov.mapper.GetFovealRadius()
    error = np.abs(reference.astype(int) - picture).max(axis=-1)
    assert (fovea & (reference.max(axis=-1) > 0)).sum() > 200 and np.all(error[fovea] <= 1)
    plain_error = np.abs(reference.astype(int) - plain).max(axis=-1)
    assert error[~fovea].mean() <= plain_error[~fovea].mean() + 0.05
    object_state(fov.mapper)["no_content_level"] = False
    fov.screenshot()
    assert fov.mapper.GetLastPlan().layers[0].level == levels[0] + 1  # the content level again


def test_analytic_fovea_is_exact_on_structure_in_the_float_readout(vessels):
    full, fov = _pair(vessels, "analytic", GazePoint=(0.4, 0.55), ContentTolerance=2.0)
    reference, values = full.float_image(), fov.float_image()
    e = eccentricity(SIZE, (0.4, 0.55), 1.0)
    structure = (e <= fov.mapper.GetFovealRadius()) & (np.nan_to_num(reference, nan=-1.0) > WINDOW[0])
    assert structure.sum() > 100
    assert np.allclose(values[structure], reference[structure], rtol=1e-5, atol=1e-6)
    # level 0 casts the volume's silhouette band whatever the refinement mask says: exact there too
    band = silhouette_band(fov.mapper.GetLastPlan(), fov.mapper.GetLastSilhouette(), SIZE)
    band &= ~np.isnan(reference)
    assert band.sum() > 100
    assert np.allclose(values[band], reference[band], rtol=1e-5, atol=1e-6)


def test_tolerance_zero_is_the_acuity_only_picture(vessels):
    _, adaptive = _pair(vessels, "mip", ContentTolerance=3.0)
    _, plain = _pair(vessels, "mip")
    adaptive.mapper.SetContentTolerance(0.0)
    assert np.array_equal(adaptive.screenshot(), plain.screenshot())
    with pytest.raises(ValueError):
        adaptive.mapper.SetContentTolerance(-1.0)


def test_a_flat_periphery_stays_at_the_content_level():
    """Acuity's coarsest level casts only the fovea and the content level's edges: fewer rays than acuity
    alone asks (before the content level it was cast over the whole view), the error outside the fovea
    no larger."""
    spheres = make_fixture("spheres", size=32)
    size, gaze = (128, 128), (0.15, 0.15)
    views = {}
    for name, tolerance in (("full", None), ("adaptive", 2.0), ("acuity", 0.0)):
        view = OffscreenView(spheres, "mip" if tolerance is None else "foveated", size=size, window=WINDOW)
        view.camera.Zoom(1.6)
        view.renderer.ResetCameraClippingRange()
        if tolerance is not None:
            view.mapper.SetGazePoint(*gaze)
            view.mapper.SetContentTolerance(tolerance)
        views[name] = (view.screenshot().astype(int), view)
    fov, acuity = views["adaptive"][1].mapper, views["acuity"][1].mapper
    top = acuity.GetLastPlan().top
    assert fov.GetLastPlan().layers[0].level == top + 1 and fov.GetLastPlan().layers[0].grid == (16, 16)
    rows = {row["level"]: row["rays"] for row in fov.GetLastFrameCost()["levels"]}
    plain_rows = {row["level"]: row["rays"] for row in acuity.GetLastFrameCost()["levels"]}
    assert rows[top + 1] == 16 * 16
    assert 0 < rows[top] < 0.9 * plain_rows[top], (rows, plain_rows)
    outside = eccentricity(size, gaze, 1.0) > fov.GetFovealRadius()
    reference = views["full"][0]
    error = np.abs(reference - views["adaptive"][0]).max(axis=-1)
    plain_error = np.abs(reference - views["acuity"][0]).max(axis=-1)
    assert error[outside].mean() <= plain_error[outside].mean() + 0.05


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_the_float_readout_has_a_value_wherever_a_ray_meets_the_volume(vessels, method):
    """Rays a mask left out show the coarser levels (as on the GPU), not 'no ray hit the volume' (NaN)."""
    full, fov = _pair(vessels, method, GazePoint=(0.5, 0.5), ContentTolerance=2.0)
    reference, values = full.float_image(), fov.float_image()
    assert fov.mapper.GetLastFrameCost()["rays"] < 0.6 * SIZE[0] * SIZE[1]   # the masks left rays out
    assert np.array_equal(np.isnan(values), np.isnan(reference))
    e = eccentricity(SIZE, (0.5, 0.5), 1.0)
    background = (e <= fov.mapper.GetFovealRadius()) & (reference <= WINDOW[0])
    assert background.sum() > 100 and np.all(values[background] <= WINDOW[0] + 0.02)   # below the floor there too


def _speck_views(method, view="oblique", turn=None, **settings):
    from mipcast.bench.stability import SPECK_WINDOW, _specks

    image = _specks()   # one-voxel specks that clear the window's floor by 0.4 of their height
    full = OffscreenView(image, method, size=(128, 128), view=view, window=SPECK_WINDOW)
    fov = OffscreenView(image, "foveated", size=(128, 128), view=view, window=SPECK_WINDOW)
    fov.mapper.SetMethod(method)
    for scene in (full, fov):
        if turn is not None:   # the volume placed by its matrix: turned, stretched, moved, and framed again
            turn(scene.volume)
            scene.renderer.ResetCamera()
            scene.camera.Zoom(2.0)
            scene.renderer.ResetCameraClippingRange()
    for name, value in settings.items():
        getattr(fov.mapper, "Set" + name)(*np.atleast_1d(value))
    return full, fov


def _fovea_structure_errors(full, fov, gaze):
    reference, picture = full.screenshot()[..., :3].astype(int), fov.screenshot()[..., :3].astype(int)
    fovea = eccentricity((128, 128), gaze, 1.0) <= fov.mapper.GetFovealRadius()
    structure = fovea & (reference.max(axis=-1) > 0)
    return structure.sum(), int(np.sum(np.abs(reference - picture).max(axis=-1)[structure] > 1))


def _turn(volume):
    volume.RotateZ(25.0)
    volume.RotateX(-40.0)
    volume.SetScale(1.0, 1.3, 0.8)
    volume.SetPosition(3.0, -2.0, 1.0)


@pytest.mark.parametrize("view, turn", [("oblique", None), ("perspective", _turn)],
                         ids=["oblique", "perspective-turned"])
def test_specks_between_the_coarse_rays_stay_in_the_fovea(view, turn, monkeypatch):
    """Structure smaller than the deciding level's ray spacing: the data's bound casts the fovea's rays there.

    Without the bound (mipcast.core.structure_bound) most of these specks fell between acuity's coarsest
    rays (4 pixels apart), no coarse ray saw them above the floor, and they vanished from the fovea.
    """
    import mipcast.mappers.foveated_masks as foveated_masks

    gaze = (0.5, 0.5)
    full, fov = _speck_views("mip", view, turn, GazePoint=gaze, ContentTolerance=2.0)
    structure, wrong = _fovea_structure_errors(full, fov, gaze)
    assert structure >= 20 and wrong == 0
    assert fov.mapper.GetLastFrameCost()["sample_ratio"] > 1.05   # it still skips rays
    monkeypatch.setattr(foveated_masks, "structure_texels", lambda *args: None)   # the picture alone decides
    assert _fovea_structure_errors(full, fov, gaze)[1] > 0.3 * structure


def test_analytic_specks_stay_exact_in_the_fovea_of_the_float_readout():
    from mipcast.bench.stability import SPECK_WINDOW

    gaze = (0.45, 0.5)
    full, fov = _speck_views("analytic", GazePoint=gaze, ContentTolerance=2.0)
    reference, values = full.float_image(), fov.float_image()
    fovea = eccentricity((128, 128), gaze, 1.0) <= fov.mapper.GetFovealRadius()
    structure = fovea & (np.nan_to_num(reference, nan=-1.0) > SPECK_WINDOW[0])
    assert structure.sum() >= 20
    assert np.allclose(values[structure], reference[structure], rtol=1e-5, atol=1e-6)


@pytest.mark.parametrize("masks_on_cpu", [False, True], ids=["GPU masks", "CPU masks"])
def test_a_fovea_ray_through_missing_data_only_shows_the_background_not_the_coarse_levels(masks_on_cpu):
    """Missing (NaN) voxels around two small finite blocks.  The coarse levels are drawn under the fovea; a cast
    ray that meets missing data only paints what lay beneath (shaders/foveated_paint_beneath.glsl).  When it
    drew nothing, their stretched picture showed through: 640 lit pixels against full quality's 66."""
    from mipcast.core.object_state import object_state
    from mipcast.data_fixtures import image_from_array

    values = np.full((32, 32, 32), np.nan, np.float32)
    values[0, :4, :4] = 1.0
    values[10:14, 10:14, 10:14] = 0.9
    image = image_from_array(values)
    full = OffscreenView(image, "mip", size=SIZE, window=(0.2, 1.0))
    fov = OffscreenView(image, "foveated", size=SIZE, window=(0.2, 1.0))
    fov.renderer.SetBackground(0.1, 0.2, 0.3)   # beneath: not black, so painting black would show
    full.renderer.SetBackground(0.1, 0.2, 0.3)
    object_state(fov.mapper)["masks_on_cpu"] = masks_on_cpu
    fov.mapper.SetContentTolerance(2.0)
    reference, picture = full.screenshot()[..., :3].astype(int), fov.screenshot()[..., :3].astype(int)
    background = np.all(reference == reference[0, 0], axis=-1)
    assert (~background).sum() > 20
    fovea = eccentricity(SIZE, (0.5, 0.5), 1.0) <= fov.mapper.GetFovealRadius()
    assert np.abs(reference - picture).max(axis=-1)[fovea].max() <= 1
    # the float readout keeps the misses: no value where full quality has none
    readout, exact = fov.float_image(), full.float_image()
    assert np.array_equal(np.isnan(readout)[fovea], np.isnan(exact)[fovea])


def _crop_fence(mapper):
    mapper.SetCropping(True)
    mapper.SetCroppingRegionPlanes(6.5, 22.3, 8.1, 24.7, 5.2, 20.9)
    mapper.SetCroppingRegionFlagsToInvertedCross()


def _clip_plane(mapper):
    from vtkmodules.vtkCommonDataModel import vtkPlane

    plane = vtkPlane()
    plane.SetOrigin(15.5, 15.5, 15.5)
    plane.SetNormal(0.3, 1.0, 0.2)
    mapper.AddClippingPlane(plane)


def _opacity_ramp(mapper):
    opacity = mapper.GetAttachedVolume().GetProperty().GetScalarOpacity()
    opacity.RemoveAllPoints()
    opacity.AddPoint(0.0, 0.0)
    opacity.AddPoint(0.3, 0.0)
    opacity.AddPoint(1.0, 0.8)


@pytest.mark.parametrize("method", ["mip", "analytic"])
@pytest.mark.parametrize("masks_on_cpu", [False, True], ids=["GPU masks", "CPU masks"])
@pytest.mark.parametrize("change", [_crop_fence, _clip_plane, _opacity_ramp], ids=["cropping", "clipping", "opacity"])
def test_a_cast_fovea_ray_is_drawn_over_the_background_not_over_the_coarse_levels(vessels, change, masks_on_cpu,
                                                                                   method):
    """A finer level's cast ray is drawn over what lay beneath the volume, as full quality draws it, not over
    the coarser levels drawn under the fovea (shaders/foveated_paint_beneath.glsl): a ray cropped or clipped
    away paints the background instead of drawing nothing, and a semi-transparent ray shows the background
    through it.  Before, the coarse levels showed through: up to 163 fovea pixels 72 grey off with the
    clipping plane, 140 pixels 71 grey off with the cropping, every fovea pixel with the opacity ramp."""
    from mipcast.core.object_state import object_state

    views = []
    for name in (method, "foveated"):
        view = OffscreenView(vessels, name, size=SIZE, window=WINDOW)
        view.renderer.SetBackground(0.1, 0.2, 0.3)   # not black: painting black or the coarse levels would show
        view.camera.Zoom(1.6)
        view.renderer.ResetCameraClippingRange()
        change(view.mapper)
        views.append(view)
    full, fov = views
    fov.mapper.SetMethod(method)
    fov.mapper.SetContentTolerance(2.0)
    object_state(fov.mapper)["masks_on_cpu"] = masks_on_cpu
    reference = full.screenshot()[..., :3].astype(int)
    assert (np.abs(reference - reference[0, 0]).max(axis=-1) > 2).mean() > 0.1, "structure drawn"
    for gaze in ((0.3, 0.5), (0.5, 0.3), (0.7, 0.1)):   # (the volume's silhouette outside these foveae)
        fov.mapper.SetGazePoint(*gaze)
        picture = fov.screenshot()[..., :3].astype(int)
        fovea = eccentricity(SIZE, gaze, 1.0) <= fov.mapper.GetFovealRadius()
        error = np.abs(reference - picture).max(axis=-1)[fovea]
        assert error.max() <= 1, f"gaze {gaze}: {np.count_nonzero(error > 1)} fovea pixels up to {error.max()} grey off"
        assert fov.mapper.GetLastFrameCost()["sample_ratio"] > 1.05   # it still skips rays


def test_the_content_adaptive_fovea_shows_the_background_beyond_the_volumes_edge(vessels):
    """Gaze near a corner, where the volume's outline crosses the fovea, on a coloured background: full
    quality shows the background beyond the edge.  The deciding coarse levels drawn under the fovea are
    stretched up to one of their texels past the edge, where level 0 has no fragment; the picture beneath
    now goes over them there with level 0's weight (foveated_masks.outline_cover).  Before, 14 pixels were 76
    grey off (the coarse levels' black); acuity only is exact either way (its coarse levels are not drawn
    in the fovea)."""
    views = []
    for name in ("mip", "foveated"):
        view = OffscreenView(vessels, name, size=SIZE, window=WINDOW)
        view.renderer.SetBackground(0.1, 0.2, 0.3)
        view.camera.Zoom(1.6)
        view.renderer.ResetCameraClippingRange()
        views.append(view)
    full, fov = views
    fov.mapper.SetGazePoint(0.1, 0.9)
    reference = full.screenshot()[..., :3].astype(int)
    fovea = eccentricity(SIZE, (0.1, 0.9), 1.0) <= fov.mapper.GetFovealRadius()
    fov.mapper.SetContentTolerance(0.0)
    assert np.abs(reference - fov.screenshot()[..., :3]).max(axis=-1)[fovea].max() <= 1   # acuity only
    fov.mapper.SetContentTolerance(2.0)
    error = np.abs(reference - fov.screenshot()[..., :3]).max(axis=-1)[fovea]
    assert error.max() <= 1, f"{np.count_nonzero(error > 1)} fovea pixels up to {error.max()} grey off"
