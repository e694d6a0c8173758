"""The default window follows the method's projection: MIP, MinIP and average pictures all show structure.

A MinIP windowed with the MIP rule (background noise below the floor) is
black; each projection's rule (mipcast.core.windowing) must give a picture
with structure: not black, not one grey (or white) box.
"""
import numpy as np
import pytest

from mipcast.core.windowing import default_window, resolve_window, window_and_reason
from mipcast.data_fixtures import head_ct_path, load_head_ct, make_fixture
from mipcast.data_fixtures.synthetic import image_from_array
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView

PROJECTIONS = {"mip": "mip", "minip": "minip", "average": "average"}


def _grey(scene) -> np.ndarray:
    """The screenshot's grey levels on the pixels the volume covers (its footprint)."""
    shot = scene.screenshot().astype(float).mean(axis=2)
    values = scene.float_image() if scene.method.float_readout else None
    covered = np.isfinite(values) if values is not None else np.ones(shot.shape, bool)
    return shot[covered]


def _shows_structure(grey: np.ndarray) -> None:
    assert grey.size > 100
    black, white = np.mean(grey < 8), np.mean(grey > 247)
    assert black < 0.9 and white < 0.9, (black, white)      # not one black or white box
    assert np.std(grey) > 12, np.std(grey)                    # not one grey box
    assert 15 < np.mean(grey) < 240, np.mean(grey)


@pytest.fixture(scope="module")
def airways():
    return make_fixture("airways", size=40)


# the MIP of the airways phantom (dark tubes in tissue) has nothing to show: its MIP is the vessels phantom.
# The average's picture does not depend on the window (an opaque grey of the mean normalised scalar, as
# stock VTK's AVERAGE_INTENSITY blend): its case checks the picture, its window only sets clim / colour bars.
@pytest.mark.parametrize("method, fixture", [("mip", "vessels"), ("minip", "airways"), ("average", "airways")])
def test_the_default_window_shows_structure(method, fixture):
    image = make_fixture(fixture, size=40)
    assert METHODS[method].projection == PROJECTIONS[method]
    scene = OffscreenView(image, method, size=(64, 64), view="front")
    assert scene.window == default_window(image, METHODS[method].projection)
    _shows_structure(_grey(scene))


@pytest.mark.parametrize("method", ["mip", "analytic", "minip"])
def test_white_noise_is_drawn_not_black(method):
    """``np.random.rand`` is the first volume many users try. Its voxel percentiles put the floor at 0.995, above
    everything a ray meets (the interpolant averages white noise out between voxels): every method drew it black.
    The floor is at most the interpolant's own 99.5th percentile at the cell centres now (the ceiling of a MinIP
    mirrored), so the noise shows."""
    image = image_from_array(np.random.default_rng(3).random((32, 32, 32)).astype(np.float32))
    low, high = default_window(image, METHODS[method].projection)
    assert (0.6 < low < 0.8 < 0.99 < high) if METHODS[method].projection == "mip" else (low < 0.01 < 0.2 < high < 0.4)
    _shows_structure(_grey(OffscreenView(image, method, size=(64, 64), view="oblique")))


def test_the_mip_rule_would_black_out_the_minip(airways):
    """The defect the projection rule fixes: MIP's window on a MinIP."""
    scene = OffscreenView(airways, "minip", size=(64, 64), view="front", window=default_window(airways, "mip"))
    assert np.mean(_grey(scene)) < 8


def test_the_average_window_spans_the_average_projections():
    image = make_fixture("vessels", size=40)
    low, high = default_window(image, "average")
    values = OffscreenView(image, "average", size=(64, 64), view="front").float_image()
    inside = values[np.isfinite(values)]
    # the window covers the averages (not the voxels' much wider range): most pixels fall inside it
    assert np.mean((inside >= low) & (inside <= high)) > 0.8
    assert high - low < 0.5 * np.ptp(image.GetPointData().GetScalars().GetRange(0))


def test_explicit_windows_and_full_do_not_depend_on_the_projection(airways):
    for spec in ((0.1, 0.5), "full", "ct-bone"):
        assert {resolve_window(airways, spec, p) for p in PROJECTIONS.values()} == {resolve_window(airways, spec)}
    with pytest.raises(ValueError, match="projection must be one of"):
        default_window(airways, "maximum")


@pytest.mark.skipif(head_ct_path() is None, reason="head CT absent (apt-get install invesalius-examples)")
@pytest.mark.parametrize("method", list(PROJECTIONS))
def test_the_default_window_shows_the_head_ct(method):
    head = load_head_ct()
    reason = window_and_reason(head, METHODS[method].projection)[1]
    # a whole-head average mixes the air around it into every ray: the window of its projections, not ct-soft
    assert reason.startswith("percentiles of the average projections" if METHODS[method].projection == "average"
                             else "CT preset")
    scene = OffscreenView(head, method, size=(64, 64), view="front")
    if method == "minip":
        # every ray through the whole box meets the air around the head: a whole-volume
        # MinIP is black under any window; the clinical MinIP is a slab (here 20 mm)
        scene.mapper.SetSlabThickness(20.0)
    _shows_structure(_grey(scene))


# ---- missing voxels (NaN) are no part of a default window ------------------------------------------------

def _holed(fixture: str, share: float):
    """``fixture`` (32³, float32) with the first ``share`` of its x columns NaN (a masked or cut volume)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    image = make_fixture(fixture, size=32)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32).reshape(32, 32, 32)
    values[:, :, : max(1, int(share * 32))] = np.nan
    holed = vtkImageData()
    holed.CopyStructure(image)
    array = numpy_to_vtk(values.ravel(), deep=True)
    array.SetName("values")
    holed.GetPointData().SetScalars(array)
    return holed, values[np.isfinite(values)]


def _finite_only(values: np.ndarray):
    """An image of just the finite values (one row): the histogram rules see the same values, no NaN at all."""
    return image_from_array(np.ascontiguousarray(values, np.float32).reshape(1, 1, -1))


# MIP: 60 % missing (the fill below the data used to be most of the histogram: a window from -0.9);
# MinIP: 3 % missing (its fill lies above the data; the window used to end below every finite value).
@pytest.mark.parametrize("method, fixture, share", [("mip", "vessels", 0.6), ("minip", "airways", 0.03),
                                                    ("analytic_minip", "airways", 0.6)])
def test_missing_voxels_are_no_part_of_the_default_window(method, fixture, share, tmp_path, capsys):
    import pyvista

    from mipcast.app.cli import main
    from mipcast.filters import add_volume

    holed, finite = _holed(fixture, share)
    projection = METHODS[method].projection
    expected = default_window(_finite_only(finite), projection)
    assert finite.min() <= expected[0] < expected[1] <= finite.max()
    scene = OffscreenView(holed, method, size=(64, 64), view="front")
    assert scene.window == pytest.approx(expected)
    _shows_structure(_grey(scene))
    plotter = pyvista.Plotter(off_screen=True, window_size=(64, 64))
    volume = add_volume(plotter, pyvista.wrap(holed), method)
    assert volume.GetProperty().GetRGBTransferFunction().GetRange() == pytest.approx(expected)
    plotter.close()
    path = tmp_path / "holed.vti"
    pyvista.wrap(holed).save(path)
    assert main(["render", str(path), "--method", method, "--size", "32", "32", "--out", str(tmp_path / "o.png")]) == 0
    assert f"window {expected[0]:.6g} to {expected[1]:.6g}" in capsys.readouterr().out


def test_the_average_window_of_a_holed_volume_lies_in_its_finite_values():
    holed, finite = _holed("vessels", 0.6)
    low, high = OffscreenView(holed, "average", size=(64, 64), view="front").window
    assert finite.min() <= low < high <= finite.max()
    assert resolve_window(holed, "full") == (float(finite.min()), float(finite.max()))


@pytest.mark.parametrize("method", ["mip", "analytic", "minip", "average", "demip", "stock"])
@pytest.mark.parametrize("window", [None, "full"])
def test_a_constant_volume_draws_mid_grey_not_the_background(method, window):
    """A constant volume (a mask of ones, a flat phantom): its value mid-window, a uniform grey of 127-128 over
    the volume's footprint, seen against the black background.  Before, the default and ``full`` windows started
    at the value (the range widened upwards): every method drew the volume black, the background's colour."""
    from mipcast.data_fixtures.synthetic import image_from_array

    image = image_from_array(np.full((24, 24, 24), 7, np.int16))
    scene = OffscreenView(image, method, size=(48, 48), view="front", window=window)
    assert scene.window == (6.5, 7.5)
    shot = scene.screenshot().astype(int)
    drawn = shot.max(axis=2) > 0
    assert 0.2 < drawn.mean() < 0.95  # the box, and background around it
    assert set(np.unique(shot[drawn][:, 0])) <= {127, 128}, np.unique(shot[drawn][:, 0])
