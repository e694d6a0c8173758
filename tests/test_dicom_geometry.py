"""Slice spacing from positions as scanners write them (rounded, slightly uneven).

The expected geometry is computed here independently of the reader: the
slice normal from ImageOrientationPatient, each slice's coordinate along it,
and a least-squares line through those coordinates (numpy.polyfit).
"""
import warnings

import numpy as np
import pytest

pytest.importorskip("pydicom")
from test_dicom import Series, direction, physical, rotation  # noqa: E402

from mipcast.io.dicom import DicomError, DicomGeometryWarning, read_dicom  # noqa: E402
from mipcast.core.validation import check_image  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402


class RoundedSeries(Series):
    """A series whose ImagePositionPatient is rounded to ``digits`` decimals."""

    digits = 1

    def ipp(self, k):
        return np.round(self.origin + self.positions[k] * self.normal, self.digits)


def expected_grid(series):
    """Least-squares step and origin from the rounded positions, as the tags say."""
    row, col = series.iop[:3], series.iop[3:]
    normal = np.cross(row, col)
    normal /= np.linalg.norm(normal)
    ipps = np.array([series.ipp(k) for k in range(len(series.positions))])
    along = ipps @ normal
    step, intercept = np.polyfit(np.arange(len(along)), along, 1)
    lateral = ipps - np.outer(along, normal)
    origin = intercept * normal + lateral.mean(axis=0)
    return np.diff(along), step, origin, normal


def test_rounded_oblique_mr_is_read_with_one_warning(tmp_path):
    # like the motivating oblique MR: 7 mm slices, positions rounded to 0.1 mm
    series = RoundedSeries(rot=rotation(25, 17), origin=(-61.37, 18.21, 44.83), n=24, step=7.0,
                           rows=6, cols=7, pixel_spacing=(0.6, 0.6))
    steps, step, origin, normal = expected_grid(series)
    assert np.abs(steps - steps.mean()).max() > 0.01 * 7.0  # the old 1 % rule refused this
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        image = read_dicom(series.write(tmp_path / "s"))
    geometry = [w for w in caught if issubclass(w.category, DicomGeometryWarning)]
    assert len(geometry) == 1
    assert "least-squares step" in str(geometry[0].message)
    assert geometry[0].filename == __file__  # points at the caller of read_dicom
    assert image.GetDimensions() == (7, 6, 24)
    assert image.GetSpacing() == pytest.approx((0.6, 0.6, step), abs=1e-9)
    np.testing.assert_allclose(image.GetOrigin(), origin, atol=1e-9)
    np.testing.assert_allclose(direction(image)[:, 2], normal, atol=1e-9)
    # every slice lands within a small fraction of a voxel of its header position
    for k in range(24):
        misplacement = np.linalg.norm(physical(image, 0, 0, k) - series.ipp(k))
        assert misplacement < 0.1 * step
    values = check_image(image)
    for k in range(24):
        np.testing.assert_array_equal(values[k], series.pixels(k) - 1024)


def test_slightly_uneven_steps_are_accepted_with_the_worst_slice_named(tmp_path):
    series = Series()
    series.positions = np.array([0.0, 1.0, 2.0, 3.1, 4.1, 5.1])  # refused before (10 % step)
    with pytest.warns(DicomGeometryWarning, match=r"largest misplacement is 0\.037\d* mm .* at IM"):
        image = read_dicom(series.write(tmp_path / "s"))
    assert image.GetSpacing()[2] == pytest.approx(np.polyfit(np.arange(6), series.positions, 1)[0])


def test_exact_positions_give_no_warning(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        image = read_dicom(Series(rot=rotation(30, 20)).write(tmp_path / "s"))
    assert image.GetSpacing()[2] == pytest.approx(1.25, abs=1e-4)


def test_gap_in_a_rounded_series_is_missing_data_naming_the_slices(tmp_path):
    series = RoundedSeries(rot=rotation(25, 17), n=10, step=7.0, pixel_spacing=(0.6, 0.6))
    with pytest.warns(DicomGeometryWarning, match=r"2 missing slice\(s\).*between IM\d+ .* and IM\d+ .*3 steps"):
        image = read_dicom(series.write(tmp_path / "s", ks=[0, 1, 2, 3, 6, 7, 8, 9]))
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(10, series.rows, series.cols)
    assert image.GetSpacing()[2] == pytest.approx(7.0, abs=0.01)
    assert [bool(np.isnan(plane).all()) for plane in values] == [k in (4, 5) for k in range(10)]


def test_duplicate_in_a_rounded_series_is_refused(tmp_path):
    series = RoundedSeries(rot=rotation(25, 17), n=6, step=7.0)
    series.positions = np.array([0.0, 7.0, 14.0, 14.04, 21.0, 28.0])
    with pytest.raises(ValueError, match=r"1 duplicate slice position\(s\).*IM\d+ and IM\d+"):
        read_dicom(series.write(tmp_path / "s"))


def test_scattered_origins_are_refused_as_mixed_stacks(tmp_path):
    series = Series(rot=rotation(0), n=6)
    shift = {3: 2.0 * series.col}  # one slice from a stack shifted by 2 mm (> 0.5 pixel)
    folder = series.write(tmp_path / "s", drift=lambda k: shift.get(k, np.zeros(3)))
    with pytest.raises(DicomError, match=r"scattered sideways.*IM\d+ is .* mm off the others"):
        read_dicom(folder)


def test_rounding_does_not_look_like_gantry_tilt(tmp_path):
    # lateral rounding noise up to ~0.09 mm on 0.5 mm pixels (more than 0.1 pixel)
    series = RoundedSeries(rot=rotation(40, 33), n=12, step=3.0, pixel_spacing=(0.5, 0.5))
    with pytest.warns(DicomGeometryWarning):
        image = read_dicom(series.write(tmp_path / "s"))
    assert image.GetDimensions()[2] == 12


def test_small_gantry_tilt_is_still_corrected(tmp_path):
    series = Series(rot=rotation(0), n=8, step=2.0, pixel_spacing=(0.5, 0.5))
    tilt = np.tan(np.radians(1.0))  # 1 degree over 14 mm: 0.24 mm drift
    folder = series.write(tmp_path / "s", drift=lambda k: series.positions[k] * tilt * series.col)
    with pytest.warns(DicomGeometryWarning, match=r"gantry tilt of about 1\.00 deg"):
        image = read_dicom(folder)
    assert image.GetDimensions()[2] == 8 and np.isnan(image.point_data["values"]).any()
