"""The volume property's interpolation (``SetInterpolationTypeToNearest``, ParaView's Interpolation Type):
the sampled projections sample the nearest voxel, as VTK's own do, in one texture and in bricks, against
the float64 reference sampling it too; the exact projections walk the trilinear interpolant whatever it is."""
import numpy as np
import pytest

from mipcast import reference
from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView

SIZE = (48, 48)


@pytest.fixture(scope="module")
def image():
    return make_fixture("vessels", size=24)


@pytest.mark.parametrize("view, bricks", [("oblique", False), ("perspective", False), ("front", False),
                                          ("perspective", True), ("oblique", True)])
@pytest.mark.parametrize("name", ["mip", "minip", "average", "demip", "demip_two_pass"])
def test_sampled_projections_sample_the_nearest_voxel(image, name, view, bricks):
    """In one texture and in bricks (texture limit 12: the bricks take the whole volume's samples by hand,
    ``global_phase``, which until 2026-12-05 interpolated them linearly whatever the property said: every
    pixel but 0-2 of 1233 off, up to 0.46 of the range; and the CPU's one sample of a grazing outline ray,
    ``outline_rays``, was linear too: 1 pixel of 1233 off by 0.047 once the bricks were right). DEMIP's
    value (its maximum) against its reference's, which takes ``interpolation`` since 2026-12-05."""
    scene = OffscreenView(image, name, size=SIZE, window=(0.25, 1.0), view=view)
    if bricks:
        object_state(scene.mapper)["texture_limit"] = 12
    scene.volume.GetProperty().SetInterpolationTypeToNearest()
    got = scene.float_image()
    assert (scene.mapper.GetNumberOfBricks() > 1) == bricks
    nearest, linear = (METHODS[name].reference(image, scene.camera, scene.size, sample_distance=scene.sample_distance,
                                               window=scene.window, interpolation=kind)
                       for kind in ("nearest", "linear"))
    both = np.isfinite(got) & np.isfinite(nearest)
    assert both.sum() > 500 and np.mean(np.isnan(got) != np.isnan(nearest)) < 0.01  # (silhouette pixels)
    assert np.abs(got[both] - nearest[both]).max() <= METHODS[name].reference_tolerance
    assert np.abs(got[both] - linear[both]).max() > 0.04  # the property is honoured: not the linear picture


@pytest.mark.parametrize("name", ["analytic", "analytic_minip", "analytic_average"])
def test_exact_projections_draw_the_trilinear_interpolant_whatever_the_interpolation_type(image, name):
    """VTK's default volume property interpolates nearest: a plain pipeline that never sets it gets the exact
    projection of the trilinear interpolant, the picture of one that sets linear (docs/methods.md)."""
    scene = OffscreenView(image, name, size=SIZE, window=(0.25, 1.0))
    linear = scene.float_image()
    scene.volume.GetProperty().SetInterpolationTypeToNearest()
    nearest = scene.float_image()
    assert scene.mapper.GetLastProblem() is None and np.isfinite(nearest).sum() > 500
    np.testing.assert_array_equal(nearest, linear)
    expected = METHODS[name].reference(image, scene.camera, scene.size, window=scene.window)
    both = np.isfinite(nearest) & np.isfinite(expected)
    assert np.abs(nearest[both] - expected[both]).max() <= METHODS[name].reference_tolerance


def test_the_reference_draws_nearest_for_the_sampled_projections_only(image):
    scene = OffscreenView(image, "analytic", size=SIZE)
    with pytest.raises(ValueError, match="interpolation='nearest' is drawn by the sampled mip, minip, average and demip"):
        reference.render(image, scene.camera, SIZE, "analytic", interpolation="nearest")
    with pytest.raises(ValueError, match="interpolation must be one of|unknown interpolation"):
        reference.render(image, scene.camera, SIZE, "mip", sample_distance=1.0, interpolation="cubic")
