"""Tests of the synthetic fixtures and the head CT loader."""
import io
import plistlib
import tarfile

import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkImagingMorphological import vtkImageConnectivityFilter

from mipcast.data_fixtures import FIXTURES, head_ct_path, load_head_ct, make_fixture
from mipcast.core.validation import check_image


def voxels(name, size=32, seed=0):
    return check_image(make_fixture(name, size, seed))


@pytest.mark.parametrize("name", FIXTURES)
def test_fixture_format_and_range(name):
    image = make_fixture(name, size=24, seed=3)
    scalars = image.GetPointData().GetScalars()
    assert image.GetDimensions() == (24, 24, 24)
    assert image.GetSpacing() == (1.0, 1.0, 1.0) and image.GetOrigin() == (0.0, 0.0, 0.0)
    assert scalars.GetName() == "scalars" and vtk_to_numpy(scalars).dtype == np.float32
    values = check_image(image)
    assert values.min() >= 0.0 and values.max() <= 1.0


@pytest.mark.parametrize("name", FIXTURES)
def test_fixture_is_deterministic(name):
    np.testing.assert_array_equal(voxels(name, seed=5), voxels(name, seed=5))
    if name != "frontback":  # frontback ignores the seed
        assert not np.array_equal(voxels(name, seed=5), voxels(name, seed=6))


def test_fixture_rejects_bad_arguments():
    with pytest.raises(ValueError, match="'vessels', 'spheres', 'noise', 'frontback'"):
        make_fixture("tubes")
    for size in (7, 513):
        with pytest.raises(ValueError, match="between 8 and 512"):
            make_fixture("noise", size=size)
    with pytest.raises(TypeError, match="integer"):
        make_fixture("noise", size=32.0)
    assert make_fixture("vessels", size=8).GetDimensions() == (8, 8, 8)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_vessels_are_thin_oblique_and_on_noise(seed):
    size = 64
    values = voxels("vessels", size, seed)
    bright = values > 0.5
    assert 0.002 < bright.mean() < 0.03
    for axis in range(3):
        # an axis-aligned tube would light up a whole column of `size` voxels
        assert bright.sum(axis=axis).max() < size // 3
        # ...and project to a dot; oblique tubes project to lines
        assert (values.max(axis=axis) > 0.5).mean() > 0.1
    assert 0.03 <= values.min() and 0.08 < np.median(values) < 0.12
    assert values.max() <= 1.0


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_spheres_count_and_intensities(seed):
    image = make_fixture("spheres", size=48, seed=seed)
    regions = vtkImageConnectivityFilter()
    regions.SetInputData(image)
    regions.SetScalarRange(0.2, 1.0)
    regions.SetExtractionModeToAllRegions()
    regions.Update()
    assert regions.GetNumberOfExtractedRegions() == 5
    values = check_image(image)
    for level in (1.0, 0.85, 0.7, 0.55, 0.4):  # each flat top is present
        assert np.isclose(values, level).any()
    assert np.median(values) == 0.0


def test_noise_is_smooth_and_normalised():
    values = voxels("noise", 32)
    assert values.min() == 0.0 and values.max() == 1.0
    assert np.abs(np.diff(values, axis=2)).mean() < 0.05
    assert values.std() > 0.05


def test_frontback_structures_at_documented_depths():
    size = 64
    values = voxels("frontback", size)
    assert values.max() == 1.0 and values.min() == np.float32(0.05)
    z, y, x = np.nonzero(values > 0.5)
    low, high = x < size // 2, x >= size // 2
    assert z[low].mean() == pytest.approx(0.25 * size, abs=0.5)
    assert z[high].mean() == pytest.approx(0.75 * size, abs=0.5)
    assert x[low].mean() == pytest.approx(round(0.35 * size), abs=0.5)
    assert x[high].mean() == pytest.approx(round(0.65 * size), abs=0.5)
    # both identical: the MIP along z cannot tell them apart
    mip = values.max(axis=0)
    left, right = (mip[:, c - 10:c + 11] for c in (round(0.35 * size), round(0.65 * size)))
    np.testing.assert_array_equal(left, right)


def write_inv3(path, array, spacing, shape=None):
    meta = {"matrix": {"dtype": "int16", "filename": "matrix.dat",
                       "shape": list(shape or array.shape)},
            "spacing": list(spacing)}
    with tarfile.open(path, "w:gz") as tar:
        for name, data in (("main.plist", plistlib.dumps(meta)),
                           ("matrix.dat", array.astype("<i2").tobytes())):
            info = tarfile.TarInfo(f"tmpproject/{name}")
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))


def test_load_inv3_reads_metadata(tmp_path):
    array = np.arange(24, dtype=np.int16).reshape(2, 3, 4) - 1024
    write_inv3(tmp_path / "tiny.inv3", array, (0.5, 0.75, 2.0))
    image = load_head_ct(tmp_path / "tiny.inv3")
    assert image.GetDimensions() == (4, 3, 2)
    assert image.GetSpacing() == (0.5, 0.75, 2.0)
    assert image.GetPointData().GetScalars().GetName() == "HU"
    np.testing.assert_array_equal(check_image(image), array)
    check_image(image)  # a fresh, independent copy each call:
    vtk_to_numpy(image.GetPointData().GetScalars())[:] = 0
    np.testing.assert_array_equal(check_image(load_head_ct(tmp_path / "tiny.inv3")), array)


def test_load_inv3_rejects_inconsistent_metadata(tmp_path):
    write_inv3(tmp_path / "bad.inv3", np.zeros((2, 3, 4)), (1, 1, 1), shape=(2, 3, 5))
    with pytest.raises(ValueError, match="48 bytes.*shape \\(2, 3, 5\\)"):
        load_head_ct(tmp_path / "bad.inv3")


def test_head_ct_missing_file_says_how_to_install(tmp_path, monkeypatch):
    with pytest.raises(FileNotFoundError, match="apt-get install invesalius-examples"):
        load_head_ct(tmp_path / "absent.inv3")
    monkeypatch.setenv("MIPCAST_HEAD_CT", str(tmp_path / "absent.inv3"))
    with pytest.warns(UserWarning, match="MIPCAST_HEAD_CT"):
        head_ct_path()


def test_head_ct_path_honours_environment(tmp_path, monkeypatch):
    write_inv3(tmp_path / "mine.inv3", np.zeros((2, 2, 2)), (1, 1, 1))
    monkeypatch.setenv("MIPCAST_HEAD_CT", str(tmp_path / "mine.inv3"))
    assert head_ct_path() == tmp_path / "mine.inv3"


@pytest.mark.skipif(head_ct_path() is None,
                    reason="head CT absent: apt-get install invesalius-examples")
def test_head_ct():
    image = load_head_ct()
    assert image.GetDimensions() == (256, 256, 108)
    assert image.GetSpacing() == pytest.approx((0.9570312, 0.9570312, 1.5))
    assert image.GetOrigin() == (0.0, 0.0, 0.0)
    assert image.GetScalarTypeAsString() == "short"
    assert image.GetPointData().GetScalars().GetName() == "HU"
    hu = check_image(image)
    assert hu.min() == -1024 and 2900 < hu.max() < 3100
    assert 0.05 < (hu > 300).mean() < 0.2  # bone
    # documented orientation: dental metal at low z (inferior), high y (anterior)
    k, j, _ = np.nonzero(hu > 2000)
    assert k.max() < 10 and j.min() > 128
    assert load_head_ct() is not image
