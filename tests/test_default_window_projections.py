"""The default window follows the method's projection: MIP, MinIP and average pictures all show structure.

A MinIP windowed with the MIP rule (background noise below the floor) is
black; each projection's rule (mipcast.core.windowing) must give a picture
with structure: not black, not one grey (or white) box.
"""
import numpy as np
import pytest

from mipcast.core.windowing import default_window, resolve_window, window_and_reason
from mipcast.data_fixtures import head_ct_path, load_head_ct, make_fixture
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
    assert reason.startswith("CT preset")
    scene = OffscreenView(head, method, size=(64, 64), view="front")
    if method == "minip":
        # every ray through the whole box meets the air around the head: a whole-volume
        # MinIP is black under any window; the clinical MinIP is a slab (here 20 mm)
        scene.mapper.SetSlabThickness(20.0)
    _shows_structure(_grey(scene))
