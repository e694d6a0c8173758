"""Sampling chosen by the scene: meets its error target, and no denser than needed."""
import numpy as np
import pytest

from mipcast import reference
from mipcast.bench.auto_sampling import CANDIDATES, choose_samples_per_voxel
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

SIZE = (96, 96)


def _within_one_grey(image, view, rate):
    gpu = OffscreenView(image, "mip", size=SIZE, view=view, sample_distance=1.0 / rate, window="full")
    values = gpu.float_image()
    exact = reference.render(image, gpu.camera, SIZE, method="analytic")
    hits = ~np.isnan(exact)
    low, high = gpu.window
    return float(np.mean(np.abs(values[hits] - exact[hits]) <= (high - low) / 255))


@pytest.mark.parametrize("fixture", ["spheres", "noise"])
@pytest.mark.parametrize("view", ["oblique", "perspective"])
def test_auto_meets_the_target_on_the_gpu_and_is_minimal(fixture, view):
    image = make_fixture(fixture, size=48)
    camera = OffscreenView(image, "mip", size=SIZE, view=view).camera
    choice = choose_samples_per_voxel(image, camera, SIZE)  # calibrates on all 96 x 96 rays
    assert choice.met
    assert _within_one_grey(image, view, choice.samples_per_voxel) >= 0.99
    index = CANDIDATES.index(choice.samples_per_voxel)
    if index > 0:  # the next cheaper candidate misses the (margin-raised) target
        assert _within_one_grey(image, view, CANDIDATES[index - 1]) < 0.993 + 1e-3


def test_vessels_touching_the_box_are_reported_as_missed():
    # vessels run out through the box faces, so many rays peak exactly at
    # their entry or exit point, which sampling never hits (the first sample
    # is one step in, the last up to a step short) and the profile is steep
    # there: no rate reaches 1 grey on 99.3 % of this small scene's rays
    # (all failing rays peak at an end), and auto says so
    image = make_fixture("vessels", size=48)
    camera = OffscreenView(image, "mip", size=SIZE).camera
    choice = choose_samples_per_voxel(image, camera, SIZE)
    assert not choice.met and choice.samples_per_voxel == CANDIDATES[-1]
    assert 0.95 < choice.within_target < 0.993


def test_smooth_data_needs_fewer_samples_than_thin_vessels():
    vessels, spheres = make_fixture("vessels", size=48), make_fixture("spheres", size=48)
    camera = OffscreenView(vessels, "mip", size=SIZE).camera
    assert (choose_samples_per_voxel(spheres, camera, SIZE).samples_per_voxel
            < choose_samples_per_voxel(vessels, camera, SIZE).samples_per_voxel)


def test_bad_parameters():
    image = make_fixture("spheres", size=16)
    camera = OffscreenView(image, "mip", size=(16, 16)).camera
    with pytest.raises(ValueError, match="share"):
        choose_samples_per_voxel(image, camera, (16, 16), share=1.5)
    with pytest.raises(ValueError, match="grey_levels"):
        choose_samples_per_voxel(image, camera, (16, 16), grey_levels=0)
