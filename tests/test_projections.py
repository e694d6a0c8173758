"""MinIP and average projections, sampled and exact (docs/methods.md, sections MinIP and Average).

Parity of the sampled MinIP with stock VTK's MINIMUM_INTENSITY blend at the
same sample distance; the averages' readouts against their float64
references and their pictures against the readout coloured on the CPU; the exact ones against
their float64 references; known answers: an airway phantom (the exact MinIP
sees tube minima between samples) and a linear ramp (the exact mean along a
ray is the value at its midpoint).
"""
import numpy as np
import pytest

from mipcast.bench.benchmark import default_settings, errors_of_settings
from mipcast.core.metrics import grey_diff
from mipcast.data_fixtures import image_from_array, make_fixture
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView
from mipcast.reference.rays import hit_rays, scatter

SIZE = (96, 80)


def _hot_opacity(view):
    opacity = view.volume.GetProperty().GetScalarOpacity()
    opacity.RemoveAllPoints()
    opacity.AddPoint(0.0, 0.2)
    opacity.AddPoint(1.0, 1.0)


@pytest.fixture(scope="module")
def airways48():
    return make_fixture("airways", size=48)


@pytest.mark.parametrize("view, sample_distance, configure", [
    ("oblique", None, None),
    ("perspective", 0.5, None),
    ("oblique", 0.7, _hot_opacity),
])
def test_sampled_minip_equals_stock_vtk(airways48, view, sample_distance, configure):
    shots = []
    for method in ("stock_minip", "minip"):
        scene = OffscreenView(airways48, method, size=SIZE, view=view, sample_distance=sample_distance,
                              window=(0.0, 0.9))
        if configure is not None:
            configure(scene)
        shots.append(scene.screenshot())
    assert shots[1].max() > 60 and (shots[1].max(axis=-1) > 0).mean() > 0.3, "the picture is (nearly) black"
    assert grey_diff(*shots)["within_1"] >= 0.999, grey_diff(*shots)


def _counted_range(view):
    view.mapper.SetAverageIPScalarRange(0.12, 0.6)


@pytest.mark.parametrize("method", ["average", "analytic_average"])
@pytest.mark.parametrize("view, sample_distance, configure", [
    ("oblique", None, None),
    ("perspective", 0.5, None),
    ("oblique", 0.7, _hot_opacity),
    ("oblique", None, _counted_range),
])
def test_averages_colour_their_mean_through_the_transfer_functions(vessels48, method, view, sample_distance,
                                                                    configure):
    """The average's picture is its mean (the float readout, against the float64 reference) coloured through the
    volume property, as MIP colours its maximum: every pixel within 1 grey of the readout coloured on the CPU.
    Before 2026-12-04 it was VTK's AVERAGE_INTENSITY grey of the data-range-normalised mean: the window, the
    colour map and the opacity's colour did nothing (a head CT's average drew a near-black picture whatever
    the window)."""
    from mipcast.mappers.bricked_draw import colour

    if method == "analytic_average" and configure is _counted_range:
        pytest.skip("the exact average has no counted range (docs/methods.md)")
    scene = OffscreenView(vessels48, method, size=SIZE, view=view, sample_distance=sample_distance,
                          window=(0.05, 0.3))
    if configure is not None:
        configure(scene)
    picture = scene.screenshot().astype(float)
    found = scene.float_image()
    hits = np.isfinite(found)
    assert hits.mean() > 0.3
    if configure is _counted_range:  # the mean of the counted samples lies in the counted range
        assert 0.12 - 1e-6 <= np.nanmin(found) and np.nanmax(found) <= 0.6 + 1e-6
    else:
        extra = {"sample_distance": scene.sample_distance} if method == "average" else {}
        expected = METHODS[method].reference(vessels48, scene.camera, scene.size, **extra)
        assert np.array_equal(hits, np.isfinite(expected))
        assert np.abs(found[hits] - expected[hits]).max() < 1e-4
    coloured = 255.0 * colour(found, scene.volume.GetProperty())[..., :3]  # premultiplied, over black
    difference = np.abs(picture - coloured).max(axis=-1)
    assert np.mean(difference <= 1.0) >= 0.999, (np.mean(difference <= 1.0), difference.max())
    assert picture.max() > 150 and picture[hits].std() > 10, "the window shows structure"


def test_the_window_changes_the_average_but_not_vtks_own(vessels48):
    """A narrower window brightens mipcast's averages; VTK's own average (stock_average) ignores it."""
    for method, changes in (("average", True), ("analytic_average", True), ("stock_average", False)):
        wide, narrow = (OffscreenView(vessels48, method, size=SIZE, window=w).screenshot().astype(float)
                        for w in ((0.0, 1.0), (0.0, 0.25)))
        assert (np.abs(wide - narrow).max() > 40) == changes, method
        if changes:
            assert narrow.mean() > 2.0 * wide.mean()


@pytest.mark.parametrize("view", ["oblique", "perspective"])
def test_minip_skipping_blocks_equals_stock_vtk(airways48, view):
    # a ceiling below the tissue (MinIP's default window is one): MinIP jumps the tissue's blocks
    shots = []
    for method in ("stock_minip", "minip"):
        scene = OffscreenView(airways48, method, size=SIZE, view=view, window=(0.05, 0.6))
        shots.append(scene.screenshot())
    assert "minip_hooks_blocks" in scene.mapper.GetShaderPieces()
    assert shots[1].min() < 30 and (shots[1].max(axis=-1) < 255).mean() > 0.05, "no airway in the picture"
    assert grey_diff(*shots)["within_1"] >= 0.999, grey_diff(*shots)


@pytest.mark.parametrize("name, fixture, window", [("analytic_minip", "airways", "full"),
                                                   ("analytic_minip", "airways", (0.05, 0.6)),
                                                   ("analytic_average", "vessels", "full"),
                                                   ("analytic_minip", "vessels", "full"),
                                                   ("analytic_average", "airways", "full")])
def test_exact_projections_match_their_references(name, fixture, window):
    image = make_fixture(fixture, size=40)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    for view in ("oblique", "perspective"):
        scene = OffscreenView(image, name, size=(64, 56), view=view, window=window)
        got = scene.float_image()
        # (a window below the tissue: the readout jumps the blocks above its running minimum)
        assert ("amip_loop_blocks" in scene.mapper.GetShaderPieces()) == (window != "full")
        expected = METHODS[name].reference(image, scene.camera, scene.size)
        assert np.array_equal(np.isnan(got), np.isnan(expected))
        error = np.abs(got - expected)[np.isfinite(expected)] / (high - low)
        assert error.size > 0.3 * got.size
        assert (error <= 1e-3).mean() >= 0.999 and (error <= 1 / 255).mean() >= 0.995, error.max()


def test_exact_average_compiles_the_missing_value_search_only_while_values_are_missing():
    """The covered-part search of missing values is compiled in (its piece defines MC_AVERAGE_MISSING)
    and out with the input (its presence alone made llvmpipe's average 5x slower); both ways exact on
    the same view."""
    image = make_fixture("vessels", size=24)
    values = np.asarray(image.GetPointData().GetScalars()).reshape(24, 24, 24)
    holed = values.astype(np.float32)
    holed[:, :, :10] = np.nan
    holed.ravel()[::11] = np.nan
    scene = OffscreenView(image, "analytic_average", size=(64, 56), view="oblique", window=(0.0, 1.0))
    for data, missing in ((values, False), (holed, True), (values, False)):
        shown = image_from_array(data, "values")
        scene.set_input(shown)
        got = scene.float_image()
        pieces = scene.mapper.GetShaderPieces()
        assert ("amip_average_missing" in pieces) == missing, pieces
        expected = METHODS["analytic_average"].reference(shown, scene.camera, scene.size)
        assert np.array_equal(np.isnan(got), np.isnan(expected)) and np.isfinite(got).mean() > 0.3
        assert np.nanmax(np.abs(got - expected)) <= 1e-3, missing


def test_exact_minip_sees_the_airways_that_samples_miss(airways48):
    image = airways48
    exact = OffscreenView(image, "analytic_minip", size=SIZE, window="full")
    sampled = OffscreenView(image, "minip", size=SIZE, window="full")
    ours, theirs = exact.float_image(), sampled.float_image()
    hit = np.isfinite(ours)
    # rays shorter than a step (grazing an edge) sample beyond their segment (clamped), as stock does
    _, _, _, length = hit_rays(image, exact.camera, SIZE)
    inside = scatter(length, hit.ravel(), *ours.shape) >= sampled.sample_distance
    assert np.all(ours[inside] <= theirs[inside] + 1e-4), "the exact minimum is above a sample"
    missed = theirs[hit] - ours[hit]
    # the sampled MinIP misses the tubes' depth along many rays by more than 5 % of the range
    assert (missed > 0.05).mean() > 0.02, np.percentile(missed, [50, 99])
    assert ours[hit].min() < 0.05, "the exact MinIP does not reach the air in the tubes"
    picture = exact.screenshot()
    assert picture.max() > 100 and picture.min() < 30, "no contrast between tissue and airways"


def test_exact_average_of_a_linear_ramp_is_its_midpoint_value():
    n = 24
    i = np.arange(n, dtype=np.float64)
    ramp = 0.5 + 0.25 * i - 0.125 * i[:, None] + 0.5 * i[:, None, None]  # exact in float32
    image = image_from_array(ramp.astype(np.float32), "ramp")
    scene = OffscreenView(image, "analytic_average", size=(48, 40), view="perspective", window="full")
    got = scene.float_image()
    hit, entry, direction, length = hit_rays(image, scene.camera, scene.size)
    middle = entry + 0.5 * length[:, None] * direction  # (x, y, z) index space
    expected = scatter(0.5 + 0.25 * middle[:, 0] - 0.125 * middle[:, 1] + 0.5 * middle[:, 2], hit, *got.shape)
    low, high = float(ramp.min()), float(ramp.max())
    assert np.array_equal(np.isnan(got), np.isnan(expected)) and np.isfinite(got).mean() > 0.3
    assert np.nanmax(np.abs(got - expected)) <= 1e-5 * (high - low)
    reference = METHODS["analytic_average"].reference(image, scene.camera, scene.size)
    assert np.nanmax(np.abs(reference - expected)) <= 1e-9 * (high - low)


def test_bench_errors_on_missing_values_count_the_sampled_rays_that_saw_none():
    """A sampled ray whose samples all fall on missing voxels draws nothing where the exact
    interpolant has a finite part: counted (the sampled reference misses it too), not an error;
    the exact methods must not miss at all."""
    n = 24
    values = np.asarray(make_fixture("vessels", size=n).GetPointData().GetScalars()).reshape(n, n, n)
    holed = values.astype(np.float32)
    holed.ravel()[::7] = np.nan
    image = image_from_array(holed, "values")
    labels = ("stock 1x", "mip 1x", "minip 1x", "average 1x", "analytic", "analytic minip", "analytic average")
    settings = [s for s in default_settings() if s.label in labels]
    errors = errors_of_settings(image, settings, size=(64, 64))
    counted = {label: errors[label]["missing_data_misses"] for label in labels}
    assert counted["mip 1x"] > 10 and counted["stock 1x"] == counted["mip 1x"], counted
    assert counted["analytic"] == counted["analytic minip"] == counted["analytic average"] == 0, counted
    assert all(errors[label]["within_1_grey"] >= 0.999 for label in labels if label.startswith("analytic"))


def test_bench_rows_compare_each_projection_with_its_exact_reference():
    labels = ("analytic", "analytic minip", "analytic average", "minip 1x", "average 1x", "average 8x")
    settings = [s for s in default_settings() if s.label in labels]
    assert {s.label for s in settings} == set(labels)
    errors = errors_of_settings(make_fixture("airways", size=24), settings, size=(32, 32))
    for label in ("analytic", "analytic minip", "analytic average"):
        assert errors[label]["max_pct"] < 0.01, (label, errors[label])
    assert errors["minip 1x"]["max_pct"] > 1.0  # the sampled minimum misses the airways
    # the sampled mean converges to the exact mean (against the exact maximum it would not)
    assert errors["average 8x"]["p99_pct"] < 0.25 * errors["average 1x"]["p99_pct"], errors
