"""Tests of mipcast.io.dicom on pydicom's bundled files and on generated series.

Generated series are written with pydicom into tmp_path with known geometry;
expected positions are computed from the DICOM definition
(PS3.3 C.7.6.2.1.1: P = IPP + c * PixelSpacing[1] * row_cosine
+ r * PixelSpacing[0] * column_cosine), independently of the reader.
"""
import random
from pathlib import Path

import numpy as np
import pytest

pydicom = pytest.importorskip("pydicom")
from pydicom.data import get_testdata_file  # noqa: E402
from pydicom.dataset import Dataset, FileMetaDataset  # noqa: E402
from pydicom.sequence import Sequence  # noqa: E402
from pydicom.uid import ExplicitVRLittleEndian, JPEG2000, generate_uid  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkCommonDataModel import vtkImageData  # noqa: E402

from mipcast.io.dicom import DicomGeometryWarning, DicomPaddingWarning, list_series, read_dicom  # noqa: E402
from mipcast.io import read_volume  # noqa: E402
from mipcast.core.validation import check_image  # noqa: E402

CT5N = Path(get_testdata_file("dicomdirtests/98892001/CT5N/2062")).parent
CT_IMAGE = "1.2.840.10008.5.1.4.1.1.2"
ENHANCED_CT_IMAGE = "1.2.840.10008.5.1.4.1.1.2.1"
RT_STRUCT = "1.2.840.10008.5.1.4.1.1.481.3"


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------

def direction(image):
    m = image.GetDirectionMatrix()
    return np.array([[m.GetElement(r, c) for c in range(3)] for r in range(3)])


def physical(image, i, j, k):
    point = [0.0, 0.0, 0.0]
    image.TransformContinuousIndexToPhysicalPoint(i, j, k, point)
    return np.array(point)


def rotation(z_deg, x_deg=0.0):
    a, b = np.radians(z_deg), np.radians(x_deg)
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
    return rz @ rx


def ds_numbers(values, digits):
    return [f"{v:.{digits}f}" for v in values]


def save(ds, path):
    try:
        ds.save_as(path, enforce_file_format=True)
    except TypeError:  # pydicom 2.x
        ds.save_as(path, write_like_original=False)


def base_dataset(sop_class, series_uid, modality="CT", description="", number=1):
    meta = FileMetaDataset()
    meta.MediaStorageSOPClassUID = sop_class
    meta.MediaStorageSOPInstanceUID = generate_uid()
    meta.TransferSyntaxUID = ExplicitVRLittleEndian
    ds = Dataset()
    ds.file_meta = meta
    ds.SOPClassUID = sop_class
    ds.SOPInstanceUID = meta.MediaStorageSOPInstanceUID
    ds.StudyInstanceUID = "1.2.826.0.1.3680043.8.498.1"
    ds.SeriesInstanceUID = series_uid
    ds.Modality = modality
    ds.SeriesDescription = description
    ds.SeriesNumber = number
    return ds


def write_slice(path, pixels, ipp, iop, pixel_spacing, series_uid, instance, slope=1, intercept=-1024,
                **series):
    ds = base_dataset(CT_IMAGE, series_uid, **series)
    ds.InstanceNumber = instance
    ds.ImagePositionPatient = ds_numbers(ipp, 4)
    ds.ImageOrientationPatient = ds_numbers(iop, 6)
    ds.PixelSpacing = ds_numbers(pixel_spacing, 4)
    ds.SliceThickness = "99"  # deliberately wrong: the spacing must come from positions
    ds.Rows, ds.Columns = pixels.shape
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
    ds.RescaleSlope, ds.RescaleIntercept = str(slope), str(intercept)
    ds.PixelData = pixels.astype("<i2").tobytes()
    save(ds, path)


class Series:
    """Known geometry: slice k at origin + positions[k] * normal (+ drift)."""

    def __init__(self, rot=rotation(30), origin=(-20.0, 35.0, 110.0), n=6, step=1.25,
                 rows=4, cols=5, pixel_spacing=(0.7, 0.9), slope=1, intercept=-1024):
        self.row, self.col, self.normal = rot[:, 0], rot[:, 1], rot[:, 2]
        self.iop = np.round(np.concatenate([self.row, self.col]), 6)
        self.origin = np.array(origin)
        self.positions = step * np.arange(n)
        self.rows, self.cols, self.pixel_spacing = rows, cols, pixel_spacing
        self.slope, self.intercept = slope, intercept
        self.uid = generate_uid()

    def pixels(self, k):
        r, c = np.mgrid[0:self.rows, 0:self.cols]
        return 100 * k + 10 * r + c

    def ipp(self, k):
        return np.round(self.origin + self.positions[k] * self.normal, 4)

    def write(self, folder, ks=None, shuffle=True, drift=None, seed=0, **series):
        folder.mkdir(parents=True, exist_ok=True)
        ks = list(range(len(self.positions)))[::-1] if ks is None else list(ks)  # decreasing
        names = [f"IM{n:04d}" for n in range(len(ks))]
        numbers = list(range(1, len(ks) + 1))
        if shuffle:
            rng = random.Random(seed)
            rng.shuffle(names)
            rng.shuffle(numbers)
        for k, name, number in zip(ks, names, numbers):
            ipp = self.ipp(k) if drift is None else np.round(self.ipp(k) + drift(k), 4)
            write_slice(folder / name, self.pixels(k), ipp, self.iop, self.pixel_spacing, self.uid,
                        number, self.slope, self.intercept, **series)
        return folder


# ---------------------------------------------------------------------------
# pydicom's bundled files
# ---------------------------------------------------------------------------

def test_ct5n_geometry_and_values_match_the_tags():
    datasets = [pydicom.dcmread(str(f)) for f in sorted(CT5N.iterdir())]
    normal = np.cross(np.array(datasets[0].ImageOrientationPatient[:3], float),
                      np.array(datasets[0].ImageOrientationPatient[3:], float))
    datasets.sort(key=lambda ds: float(np.array(ds.ImagePositionPatient, float) @ normal))
    z = [float(np.array(ds.ImagePositionPatient, float) @ normal) for ds in datasets]
    ct = read_dicom(CT5N)
    assert isinstance(ct, vtkImageData)
    assert ct.GetDimensions() == (datasets[0].Columns, datasets[0].Rows, 5) == (16, 16, 5)
    spacing = ct.GetSpacing()
    assert spacing[:2] == pytest.approx((float(datasets[0].PixelSpacing[1]),
                                         float(datasets[0].PixelSpacing[0])))
    assert spacing[2] == pytest.approx(np.diff(z).mean()) == pytest.approx(2.5)
    assert ct.GetOrigin() == pytest.approx([float(v) for v in datasets[0].ImagePositionPatient])
    assert ct.GetOrigin()[2] == pytest.approx(min(z))  # file 3353, InstanceNumber 10
    np.testing.assert_allclose(direction(ct), np.eye(3))
    expected = np.stack([ds.pixel_array * float(ds.RescaleSlope) + float(ds.RescaleIntercept)
                         for ds in datasets])
    values = check_image(ct)
    assert values.dtype == np.int16
    np.testing.assert_array_equal(values, expected)
    assert ct.GetPointData().GetScalars().GetName() == "values"
    assert ct.GetFieldData().GetAbstractArray("units").GetValue(0) == "HU"
    # HU sanity: this tiny (16x16) CT has air/lung near -900 HU, nothing near metal
    assert -1100 < values.min() < -500 and 0 < values.max() < 4000


def test_list_series_ct5n():
    (series,) = list_series(CT5N)
    assert series["uid"] == pydicom.dcmread(str(CT5N / "2062")).SeriesInstanceUID
    assert (series["modality"], series["n_files"], series["n_images"]) == ("CT", 5, 5)
    assert series["description"] == "SmartScore - Gated 0.5 sec"


def test_rtdose_multiframe_uses_grid_frame_offsets_and_dose_scaling():
    path = get_testdata_file("rtdose.dcm")
    ds = pydicom.dcmread(path)
    dose = read_dicom(path)
    offsets = np.array(ds.GridFrameOffsetVector, float)
    assert int(ds.NumberOfFrames) == len(offsets) == 15
    assert dose.GetDimensions() == (10, 10, 15)
    assert dose.GetSpacing() == pytest.approx((10, 10, np.diff(offsets).mean()))
    assert dose.GetOrigin() == pytest.approx([float(v) for v in ds.ImagePositionPatient])
    for k in (0, 7, 14):
        assert physical(dose, 0, 0, k)[2] == pytest.approx(float(ds.ImagePositionPatient[2]) + offsets[k])
    values = check_image(dose)
    assert values.dtype == np.float32
    np.testing.assert_allclose(values, ds.pixel_array * float(ds.DoseGridScaling), rtol=1e-6)
    assert dose.GetFieldData().GetAbstractArray("units").GetValue(0) == "relative"


def test_rtdose_with_decreasing_offsets_is_sorted(tmp_path):
    ds = pydicom.dcmread(get_testdata_file("rtdose.dcm"))
    ds.GridFrameOffsetVector = [-float(v) for v in ds.GridFrameOffsetVector]
    save(ds, tmp_path / "dose.dcm")
    dose = read_dicom(tmp_path / "dose.dcm")
    assert dose.GetSpacing()[2] == pytest.approx(5.0)
    assert dose.GetOrigin()[2] == pytest.approx(float(ds.ImagePositionPatient[2]) - 70)
    np.testing.assert_allclose(check_image(dose), ds.pixel_array[::-1] * 1e-6, rtol=1e-6)


def test_ct_small_single_slice_is_read_but_not_renderable():
    path = get_testdata_file("CT_small.dcm")
    image = read_dicom(path)
    assert image.GetDimensions() == (128, 128, 1)
    with pytest.raises(ValueError, match="at least 2 points are needed along every axis") as info:
        read_volume(path)
    assert "single DICOM slice" in str(info.value)


def j2k_decoder_available():
    try:
        from pydicom.pixels import get_decoder
    except ImportError:  # pydicom 2.x
        from pydicom.pixel_data_handlers import pillow_handler
        return pillow_handler.is_available()
    return get_decoder(JPEG2000).is_available


def test_jpeg2000_decodes_or_names_the_package():
    path = get_testdata_file("693_J2KI.dcm")
    if j2k_decoder_available():
        image = read_dicom(path)
        assert image.GetDimensions() == (512, 512, 1)
        ds = pydicom.dcmread(path)
        values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(512, 512)
        np.testing.assert_array_equal(values, ds.pixel_array - 1024)
    else:
        with pytest.raises(ValueError, match="pip install pylibjpeg pylibjpeg-openjpeg"):
            read_dicom(path)


def test_missing_jpeg2000_decoder_names_the_package(monkeypatch):
    decoders = pytest.importorskip("pydicom.pixels")
    decoder = decoders.get_decoder(JPEG2000)
    monkeypatch.setattr(decoder, "_available", {})  # as if no plugin were installed
    with pytest.raises(ValueError, match=r"JPEG 2000.*pip install pylibjpeg pylibjpeg-openjpeg"):
        read_dicom(get_testdata_file("693_J2KI.dcm"))


# ---------------------------------------------------------------------------
# generated series with known geometry
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("rot", [rotation(30), rotation(30, 20),
                                 np.array([[1.0, 0, 0], [0, -1, 0], [0, 0, -1]])],
                         ids=["z30", "z30x20", "normal-down"])
def test_oblique_series_written_in_decreasing_order(tmp_path, rot):
    series = Series(rot=rot)
    image = read_dicom(series.write(tmp_path / "s"))
    n = len(series.positions)
    assert image.GetDimensions() == (series.cols, series.rows, n)
    assert image.GetSpacing() == pytest.approx((0.9, 0.7, 1.25), abs=1e-4)
    np.testing.assert_allclose(direction(image)[:, 0], series.iop[:3], atol=1e-6)
    np.testing.assert_allclose(direction(image)[:, 1], series.iop[3:], atol=1e-6)
    np.testing.assert_allclose(direction(image)[:, 2], series.normal, atol=1e-5)
    assert np.linalg.det(direction(image)) == pytest.approx(1.0, abs=1e-5)
    np.testing.assert_allclose(image.GetOrigin(), series.ipp(0), atol=1e-4)
    values = check_image(image)
    for k in range(n):
        np.testing.assert_array_equal(values[k], series.pixels(k) - 1024)
        for r, c in [(0, 0), (3, 4), (2, 1)]:  # DICOM's pixel -> patient equation
            expected = (series.ipp(k) + c * 0.9 * series.iop[:3] + r * 0.7 * series.iop[3:])
            np.testing.assert_allclose(physical(image, c, r, k), expected, atol=2e-3)


def test_rescale_type_follows_slope(tmp_path):
    image = read_dicom(Series(slope=1, intercept=-1024).write(tmp_path / "a"))
    assert check_image(image).dtype == np.int16
    image = read_dicom(Series(slope=0.5, intercept=-1024.25).write(tmp_path / "b"))
    values = check_image(image)
    assert values.dtype == np.float32
    assert values[2, 1, 3] == pytest.approx((200 + 13) * 0.5 - 1024.25)
    image = read_dicom(Series(slope=100, intercept=1000).write(tmp_path / "c"))
    assert check_image(image).dtype == np.int32  # 100 * 534 + 1000 > 32767


def tilted_values(series, tilt, steps_per_pixel):
    """What the untilted grid holds: slice k sampled k x step x tilt / row spacing rows back (NaN: off the slice)."""
    expected = np.full((len(series.positions), series.rows, series.cols), np.nan)
    r, c = np.mgrid[0:series.rows, 0:series.cols]
    for k in range(len(series.positions)):
        source = r - k * steps_per_pixel
        inside = (source >= -1e-9) & (source <= series.rows - 1 + 1e-9)
        expected[k][inside] = (100 * k + 10 * source + c - 1024)[inside]  # pixels() is linear: exact
    return expected


@pytest.mark.parametrize("degrees", [15.0, -7.5])
def test_gantry_tilt_is_corrected(tmp_path, degrees):
    """A tilted CT (slice origins drifting along the column direction): each slice is shifted onto an untilted grid
    (linear between pixels, NaN where no slice pixel lies), with a warning naming the angle; every value lands
    where the files put it.  Before 2026-12-04 tilted series were refused."""
    series = Series(rot=rotation(20), n=6, rows=12, cols=5, step=1.25)
    tilt = np.tan(np.radians(degrees))
    folder = series.write(tmp_path / "s", drift=lambda k: series.positions[k] * tilt * series.col)
    with pytest.warns(DicomGeometryWarning, match=rf"gantry tilt of about {abs(degrees):.2f} deg.*missing \(NaN\)"):
        image = read_dicom(folder)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(6, 12, 5)  # as read: NaN kept
    assert values.dtype == np.float32 and image.GetDimensions() == (5, 12, 6)
    np.testing.assert_allclose(image.GetOrigin(), series.ipp(0), atol=1e-4)  # the first slice's corner
    np.testing.assert_allclose(image.GetSpacing(), (0.9, 0.7, 1.25), atol=1e-6)
    expected = tilted_values(series, tilt, 1.25 * tilt / series.pixel_spacing[0])
    assert np.array_equal(np.isnan(values), np.isnan(expected)) and np.isnan(values).any()
    np.testing.assert_allclose(values[~np.isnan(values)], expected[~np.isnan(expected)], atol=1e-3)


def padded_series(folder, limit=None, lossy=None):
    """A CT series whose corner pixels hold PixelPaddingValue -2000 (as GE writes them), every slice."""
    series = Series(rot=rotation(0), n=5, rows=8, cols=9)
    series.write(folder)
    corner = np.zeros((8, 9), dtype=bool)
    corner[:2, :2] = corner[-2:, -3:] = True
    for file in sorted(folder.iterdir()):
        ds = pydicom.dcmread(file)
        pixels = ds.pixel_array.copy()
        pixels[corner] = -2000
        if limit is not None:
            pixels[-1, -1] = limit  # the other end of the range
            ds.add_new(0x00280121, "SS", limit)  # PixelPaddingRangeLimit (signed pixels)
        ds.add_new(0x00280120, "SS", -2000)  # PixelPaddingValue
        if lossy is not None:
            ds.LossyImageCompression = lossy
        ds.PixelData = pixels.astype("<i2").tobytes()
        save(ds, file)
    return series, corner


def test_padding_pixels_are_read_as_missing_data(tmp_path):
    """Corners outside a CT's field of view, written as PixelPaddingValue, are missing data (NaN) that no
    projection or window counts; before 2026-12-04 they were -3024 HU values pulling averages down."""
    series, corner = padded_series(tmp_path / "s")
    with pytest.warns(DicomPaddingWarning, match=r"50 of 360 pixels \(13\.9 %\) hold the PixelPaddingValue -2000"):
        image = read_dicom(tmp_path / "s")
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(5, 8, 9)
    assert values.dtype == np.float32
    assert np.array_equal(np.isnan(values), np.broadcast_to(corner, values.shape))
    expected = np.stack([series.pixels(k) - 1024 for k in range(5)]).astype(np.float32)
    np.testing.assert_array_equal(values[:, ~corner], expected[:, ~corner])
    kept = read_volume(tmp_path / "s", padding="keep")  # as stored: -2000 - 1024
    kept_values = vtk_to_numpy(kept.GetPointData().GetScalars()).reshape(5, 8, 9)
    assert kept_values.dtype == np.int16 and (kept_values[:, corner] == -3024).all()
    with pytest.raises(ValueError, match="padding must be one of"):
        read_dicom(tmp_path / "s", padding="nan")


def test_padding_range_limit_and_lossy_compression(tmp_path):
    _, corner = padded_series(tmp_path / "range", limit=-1990)
    with pytest.warns(DicomPaddingWarning, match=r"PixelPaddingValue -2000\.\.-1990"):
        image = read_dicom(tmp_path / "range")
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(5, 8, 9)
    corner[-1, -1] = True
    assert np.array_equal(np.isnan(values), np.broadcast_to(corner, values.shape))
    # lossy compression moved the padded pixels off the value: kept, with the reason
    padded_series(tmp_path / "lossy", lossy="01")
    with pytest.warns(DicomPaddingWarning, match="lossy compressed.*kept as values"):
        image = read_dicom(tmp_path / "lossy")
    assert not np.isnan(vtk_to_numpy(image.GetPointData().GetScalars())).any()


def test_a_drift_beyond_any_gantry_tilt_is_refused(tmp_path):
    series = Series(rot=rotation(0))
    steep = np.tan(np.radians(40))
    folder = series.write(tmp_path / "s", drift=lambda k: series.positions[k] * steep * series.col)
    with pytest.raises(ValueError, match=r"40\.0 deg, more than a gantry tilts.*keep the slices of one stack"):
        read_dicom(folder)


@pytest.mark.parametrize("ks", [[0, 1, 2, 4, 5], [0, 1, 2, 5], [0, 2, 3, 5]])
def test_missing_slices_are_missing_data(tmp_path, ks):
    """A series with slices missing (a step of m usual steps): the grid keeps their places as missing
    data (NaN), drawn as background, with a warning naming the gaps; every slice lands where its file
    puts it.  Before 2026-12-04 such a series was refused."""
    series = Series()
    folder = series.write(tmp_path / "s", ks=ks)
    missing = sorted(set(range(6)) - set(ks))
    with pytest.warns(DicomGeometryWarning, match=rf"{len(missing)} missing slice\(s\).*missing data \(NaN"):
        image = read_dicom(folder)
    assert image.GetDimensions() == (5, 4, 6)
    np.testing.assert_allclose(image.GetOrigin(), series.ipp(0), atol=1e-4)
    np.testing.assert_allclose(image.GetSpacing(), (0.9, 0.7, 1.25), atol=1e-6)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(6, 4, 5)
    assert values.dtype == np.float32
    for k in range(6):
        if k in missing:
            assert np.isnan(values[k]).all()
        else:
            np.testing.assert_array_equal(values[k], series.pixels(k) - 1024)
    read_volume(folder)  # renderable: check_image accepts it


def test_gaps_of_no_whole_number_of_steps_mixed_spacings_or_most_of_the_series_are_refused(tmp_path):
    series = Series()
    shifted = series.write(tmp_path / "uneven", ks=[0, 1, 2, 4, 5],
                           drift=lambda k: -0.4 * 1.25 * series.normal if k >= 4 else 0 * series.normal)
    with pytest.raises(ValueError, match=r"missing slice.*1\.6 steps\), no whole number of steps"):
        read_dicom(shifted)
    mixed = Series(n=7)
    mixed.positions = np.array([0.0, 1.25, 2.5, 5.0, 8.75, 10.0, 11.25])  # large steps in a row, no zone
    with pytest.raises(ValueError, match=r"spacing changes irregularly.*keep the slices of one stack"):
        read_dicom(mixed.write(tmp_path / "mixed"))
    sparse = Series(n=12).write(tmp_path / "sparse", ks=[0, 1, 2, 11])
    with pytest.raises(ValueError, match=r"8 missing, more than the 4 present.*copy the whole series"):
        read_dicom(sparse)


def test_duplicate_position_is_refused(tmp_path):
    series = Series()
    folder = series.write(tmp_path / "s")
    write_slice(folder / "extra", series.pixels(2), series.ipp(2), series.iop, series.pixel_spacing,
                series.uid, 99)
    with pytest.raises(ValueError, match="duplicate slice position"):
        read_dicom(folder)


def test_two_spacings_one_after_the_other_are_resampled(tmp_path):
    # Was test_non_uniform_spacing_is_refused with positions 0, 1, 2, 3.1, 4.1, 5.1, which
    # is now accepted with a warning (misplacement 3.6 % of the step; see
    # test_dicom_geometry.py).  Steps 1.0 then 1.4 were refused as mixed stacks until 2026-12-04;
    # they are zones of one series, resampled onto 10 steps of 0.96 mm (the ends kept on the grid).
    series = Series()
    series.positions = np.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.4, 6.8, 8.2, 9.6])
    with pytest.warns(DicomGeometryWarning, match=r"4 steps of 1 mm, then 4 steps of 1\.4 mm.*0\.96 mm \(11 slices"):
        image = read_dicom(series.write(tmp_path / "s"))
    assert image.GetDimensions()[2] == 11 and image.GetSpacing()[2] == pytest.approx(0.96)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(11, 4, 5)
    np.testing.assert_allclose(values[[0, -1]], np.stack([series.pixels(0), series.pixels(8)]) - 1024, atol=1e-3)


def test_small_rounding_of_positions_is_accepted(tmp_path):
    series = Series()
    series.positions = np.array([0.0, 1.25, 2.5009, 3.75, 5.0, 6.2495])  # < 1 % off
    image = read_dicom(series.write(tmp_path / "s"))  # 0.07 % of the step: no warning
    k = np.arange(6)
    assert image.GetSpacing()[2] == pytest.approx(np.polyfit(k, series.positions, 1)[0])
    assert image.GetSpacing()[2] == pytest.approx(1.2499, abs=1e-4)


def test_inconsistent_orientation_is_refused(tmp_path):
    series = Series()
    folder = series.write(tmp_path / "s")
    other = np.round(np.concatenate([rotation(35)[:, 0], rotation(35)[:, 1]]), 6)
    write_slice(folder / "IM0000", series.pixels(0), series.ipp(0), other, series.pixel_spacing,
                series.uid, 1)
    with pytest.raises(ValueError, match="inconsistent orientation"):
        read_dicom(folder)


def test_two_series_need_a_uid(tmp_path):
    first, second = Series(), Series(rot=rotation(0), n=3)
    first.write(tmp_path, description="first one", number=2)
    for k in range(3):
        write_slice(tmp_path / f"B{k}", second.pixels(k), second.ipp(k), second.iop,
                    second.pixel_spacing, second.uid, k + 1, description="second one", number=3)
    with pytest.raises(ValueError, match="2 image series") as info:
        read_dicom(tmp_path)
    for text in (first.uid, second.uid, "first one", "second one", "6 file(s)", "3 file(s)"):
        assert text in str(info.value)
    assert read_dicom(tmp_path, series_uid=second.uid).GetDimensions() == (5, 4, 3)
    assert read_volume(tmp_path, series_uid=first.uid).GetDimensions() == (5, 4, 6)
    listed = list_series(tmp_path)
    assert [(s["uid"], s["n_files"], s["description"]) for s in listed] == [
        (first.uid, 6, "first one"), (second.uid, 3, "second one")]
    with pytest.raises(ValueError, match="no image series with SeriesInstanceUID '1.2.3'"):
        read_dicom(tmp_path, series_uid="1.2.3")


def non_image(path, series_uid):
    ds = base_dataset(RT_STRUCT, series_uid, modality="RTSTRUCT")
    ds.StructureSetLabel = "contours"
    save(ds, path)


def test_non_image_objects_are_skipped(tmp_path):
    series = Series()
    folder = series.write(tmp_path / "s")
    non_image(folder / "RS.dcm", generate_uid())
    (folder / "README.txt").write_text("not DICOM")
    assert read_dicom(folder).GetDimensions() == (5, 4, 6)
    only = tmp_path / "only"
    only.mkdir()
    non_image(only / "RS.dcm", generate_uid())
    with pytest.raises(ValueError, match=r"none with pixel data \(modalities: RTSTRUCT\)"):
        read_dicom(only)


def test_no_dicom_files(tmp_path):
    (tmp_path / "notes.txt").write_text("hello")
    (tmp_path / "sub").mkdir()
    with pytest.raises(ValueError, match=r"no DICOM files in .*1 file\(s\) checked.*subfolders \(sub\)"):
        read_dicom(tmp_path)
    with pytest.raises(FileNotFoundError, match="nowhere"):
        read_dicom(tmp_path / "nowhere")
    with pytest.raises(ValueError, match="is not a DICOM file"):
        read_dicom(tmp_path / "notes.txt")


def test_colour_images_are_refused():
    with pytest.raises(ValueError, match="colour image"):
        read_dicom(get_testdata_file("SC_rgb_rle_2frame.dcm"))


def test_enhanced_multiframe_uses_functional_groups(tmp_path):
    series = Series(rot=rotation(30, 20), slope=0.5, intercept=-1000)
    order = [3, 0, 5, 1, 4, 2]  # frames stored out of order
    ds = base_dataset(ENHANCED_CT_IMAGE, series.uid)
    ds.NumberOfFrames = len(order)
    ds.Rows, ds.Columns = series.rows, series.cols
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
    shared = Dataset()
    orientation, measures, transform = Dataset(), Dataset(), Dataset()
    orientation.ImageOrientationPatient = ds_numbers(series.iop, 6)
    measures.PixelSpacing = ds_numbers(series.pixel_spacing, 4)
    measures.SliceThickness = "99"
    transform.RescaleSlope, transform.RescaleIntercept, transform.RescaleType = "0.5", "-1000", "HU"
    shared.PlaneOrientationSequence = Sequence([orientation])
    shared.PixelMeasuresSequence = Sequence([measures])
    shared.PixelValueTransformationSequence = Sequence([transform])
    ds.SharedFunctionalGroupsSequence = Sequence([shared])
    per_frame = []
    for k in order:
        group, position = Dataset(), Dataset()
        position.ImagePositionPatient = ds_numbers(series.ipp(k), 4)
        group.PlanePositionSequence = Sequence([position])
        per_frame.append(group)
    ds.PerFrameFunctionalGroupsSequence = Sequence(per_frame)
    ds.PixelData = np.stack([series.pixels(k) for k in order]).astype("<i2").tobytes()
    save(ds, tmp_path / "enhanced.dcm")

    image = read_dicom(tmp_path / "enhanced.dcm")
    assert image.GetDimensions() == (5, 4, 6)
    assert image.GetSpacing() == pytest.approx((0.9, 0.7, 1.25), abs=1e-4)
    np.testing.assert_allclose(image.GetOrigin(), series.ipp(0), atol=1e-4)
    np.testing.assert_allclose(direction(image)[:, 2], series.normal, atol=1e-5)
    values = check_image(image)
    assert values.dtype == np.float32
    for k in range(6):
        np.testing.assert_allclose(values[k], series.pixels(k) * 0.5 - 1000)


def test_cli_reads_padding_as_missing_or_keeps_it(tmp_path):
    """`mipcast render --method average` of a padded CT seen from the side: the padded corners count in
    the average only with --padding keep (they pull the mean down)."""
    import warnings

    from vtkmodules.vtkIOImage import vtkPNGReader

    from mipcast.app.cli import main

    padded_series(tmp_path / "s")
    greys = {}
    for padding in ("missing", "keep"):
        out = tmp_path / f"{padding}.png"
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            assert main(["render", str(tmp_path / "s"), "--method", "average", "--view", "side",
                         "--window", "-1100", "-500", "--padding", padding, "--out", str(out),
                         "--size", "96", "80"]) == 0
        assert any(w.category is DicomPaddingWarning for w in caught) == (padding == "missing")
        reader = vtkPNGReader()
        reader.SetFileName(str(out))
        reader.Update()
        picture = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())
        red = picture[:, 0]  # (the background is black in red)
        lit = red > 0
        greys[padding] = (int(lit.sum()), float(red[lit].mean()))
    # kept, the -3024 HU corners drag the rows through them below the window (black): 921 of 1600 lit
    assert greys["keep"][0] < 0.7 * greys["missing"][0] and greys["missing"][1] > 100, greys


def test_a_ct_with_missing_data_keeps_its_units_and_the_ct_window(tmp_path):
    """A CT read with missing data (a lost slice, padding, gantry tilt) is drawn from a copy with the missing
    voxels filled; the copy kept no field data, so the "HU" units were lost and the default window fell back
    from the CT preset to histogram percentiles."""
    from mipcast.core.windowing import window_and_reason
    from mipcast.mappers.input_preparer import window_image

    folder = Series(intercept=0).write(tmp_path / "s", ks=[0, 1, 2, 4, 5])
    with pytest.warns(DicomGeometryWarning):
        image = read_volume(folder)
    assert window_and_reason(window_image(image))[1] == "CT preset ct-mip (HU)"


@pytest.mark.parametrize("tilt_degrees", [0.0, 12.0])
def test_a_series_whose_spacing_changes_in_zones_is_resampled_onto_the_finest_step(tmp_path, tilt_degrees):
    """Three slices 1.25 mm apart, then three 2.5 mm apart (a zone reconstructed coarser): resampled linearly
    along the normal onto a 1.25 mm grid, with a warning naming the zones; every file's slice lands where the
    file puts it, and between the coarse slices the values are the linear blend.  Before 2026-12-04 refused
    (a missing-slice gap rule would have filled every other place with missing data)."""
    series = Series(rot=rotation(20), n=7, rows=12, cols=5)
    series.positions = np.array([0.0, 1.25, 2.5, 3.75, 6.25, 8.75, 11.25])
    tilt = np.tan(np.radians(tilt_degrees))
    folder = series.write(tmp_path / "s", drift=lambda k: series.positions[k] * tilt * series.col)
    with pytest.warns(DicomGeometryWarning, match=r"spacing changes along the series \(3 steps of 1\.25 mm, then "
                                                  r"3 steps of 2\.5 mm.*regular grid of 1\.25 mm \(10 slices"):
        image = read_dicom(folder)
    assert image.GetDimensions() == (5, 12, 10)
    np.testing.assert_allclose(image.GetSpacing(), (0.9, 0.7, 1.25), atol=1e-6)
    np.testing.assert_allclose(image.GetOrigin(), series.ipp(0), atol=1e-4)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(10, 12, 5)
    slice_at = np.interp(1.25 * np.arange(10), series.positions, np.arange(7))  # fractional file slice
    r, c = np.mgrid[0:12, 0:5]
    if tilt_degrees == 0.0:
        expected = 100 * slice_at[:, None, None] + 10 * r + c - 1024
        np.testing.assert_allclose(values, expected, atol=1e-3)
    else:  # untilted first: each row shifted by its slice's drift (linear in the rows), NaN where none lies
        shift = 1.25 * np.arange(10) * tilt / series.pixel_spacing[0]
        expected = 100 * slice_at[:, None, None] + 10 * (r[None] - shift[:, None, None]) + c - 1024
        inside = (r[None] - shift[:, None, None] >= -1e-3)
        assert np.isnan(values[~inside]).all() and not np.isnan(values[inside]).any()
        np.testing.assert_allclose(values[inside], expected[inside], atol=1e-3)


# ---------------------------------------------------------------------------
# the series' own grey windows (VOI LUT)
# ---------------------------------------------------------------------------

def set_tags(folder, tags_of):
    """Rewrite every file of ``folder`` with the tags ``tags_of(instance_number)`` gives (keyword: value)."""
    for path in sorted(folder.iterdir()):
        ds = pydicom.dcmread(str(path))
        for keyword, value in tags_of(int(ds.InstanceNumber)).items():
            setattr(ds, keyword, value)
        save(ds, path)


def test_the_series_windows_are_read_as_dicom_maps_them(tmp_path):
    """WindowCenter / WindowWidth (PS3.3 C.11.2.1.2) become (low, high) in the rescaled values' units:
    LINEAR maps c - 0.5 - (w - 1)/2 to black and c - 0.5 + (w - 1)/2 to white, LINEAR_EXACT c -+ w/2; several
    windows keep their order and their WindowCenterWidthExplanation; a width of 0 is no window."""
    from mipcast.core.windowing import dicom_windows

    assert dicom_windows(read_dicom(CT5N)) == [("", (-160.0, 239.0))]  # 40 / 400, every slice
    assert dicom_windows(read_dicom(get_testdata_file("MR_small.dcm"))) == [("", (-200.0, 1399.0))]  # 600 / 1600
    # an enhanced CT: the shared FrameVOILUTSequence (49 / 102)
    assert dicom_windows(read_dicom(get_testdata_file("eCT_Supplemental.dcm"))) == [("", (-2.0, 99.0))]

    folder = Series().write(tmp_path / "a")
    set_tags(folder, lambda n: {"WindowCenter": ["300", "500", "40"], "WindowWidth": ["800", "2000", "0"],
                                "WindowCenterWidthExplanation": ["ANGIO", "BONE", "BROKEN"]})
    assert dicom_windows(read_dicom(folder)) == [("ANGIO", (-100.0, 699.0)), ("BONE", (-500.0, 1499.0))]
    set_tags(folder, lambda n: {"VOILUTFunction": "LINEAR_EXACT"})
    assert dicom_windows(read_dicom(folder)) == [("ANGIO", (-100.0, 700.0)), ("BONE", (-500.0, 1500.0))]
    assert not dicom_windows(read_dicom(Series().write(tmp_path / "none")))  # no window tags: none


def test_slices_with_their_own_windows_give_the_shared_or_the_median_window(tmp_path):
    """An MR scanner windows each slice: the windows most slices share, else the slices' median centre and
    width."""
    from mipcast.core.windowing import dicom_windows

    folder = Series().write(tmp_path / "s")  # 6 slices, instance numbers 1..6
    set_tags(folder, lambda n: {"WindowCenter": "100" if n <= 4 else str(50 * n), "WindowWidth": "201"})
    assert dicom_windows(read_dicom(folder)) == [("", (-0.5, 199.5))]  # 4 of 6 share 100 / 201
    set_tags(folder, lambda n: {"WindowCenter": str(100 * n), "WindowWidth": str(100 * n)})
    # centres 100..600 and widths 100..600 (LINEAR: each window's middle is c - 0.5): medians 349.5 and 349
    assert dicom_windows(read_dicom(folder)) == [("median of the slices' windows", (175.0, 524.0))]


def test_an_enhanced_file_reads_its_per_frame_windows(tmp_path):
    """FrameVOILUTSequence per frame wins over the shared one; here every frame has its own two windows."""
    from mipcast.core.windowing import dicom_windows

    series = Series()
    ds = base_dataset(ENHANCED_CT_IMAGE, series.uid)
    ds.NumberOfFrames = 6
    ds.Rows, ds.Columns = series.rows, series.cols
    ds.SamplesPerPixel = 1
    ds.PhotometricInterpretation = "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
    shared, orientation, measures, voi = Dataset(), Dataset(), Dataset(), Dataset()
    orientation.ImageOrientationPatient = ds_numbers(series.iop, 6)
    measures.PixelSpacing = ds_numbers(series.pixel_spacing, 4)
    voi.WindowCenter, voi.WindowWidth = "40", "400"
    shared.PlaneOrientationSequence = Sequence([orientation])
    shared.PixelMeasuresSequence = Sequence([measures])
    shared.FrameVOILUTSequence = Sequence([voi])
    ds.SharedFunctionalGroupsSequence = Sequence([shared])
    groups = []
    for k in range(6):
        group, position, own = Dataset(), Dataset(), Dataset()
        position.ImagePositionPatient = ds_numbers(series.ipp(k), 4)
        own.WindowCenter, own.WindowWidth = ["300", "500"], ["801", "2001"]
        own.WindowCenterWidthExplanation = ["ANGIO", "BONE"]
        group.PlanePositionSequence = Sequence([position])
        group.FrameVOILUTSequence = Sequence([own])
        groups.append(group)
    ds.PerFrameFunctionalGroupsSequence = Sequence(groups)
    ds.PixelData = np.stack([series.pixels(k) for k in range(6)]).astype("<i2").tobytes()
    save(ds, tmp_path / "enhanced.dcm")
    assert dicom_windows(read_dicom(tmp_path / "enhanced.dcm")) == [("ANGIO", (-100.5, 699.5)),
                                                                     ("BONE", (-500.5, 1499.5))]


def angio_series(folder):
    """A small CT angiography series: a bright tube (400 HU) in soft tissue (40 HU) and a bone slab (1200 HU),
    noise-free, carrying an ANGIO (300 / 800) and a BONE (500 / 2000) window."""
    series = Series(rot=rotation(0), n=24, rows=24, cols=24, pixel_spacing=(1.0, 1.0), step=1.0, intercept=-1024)
    z, r, c = np.mgrid[0:24, 0:24, 0:24]
    hu = np.full((24, 24, 24), 40.0)
    hu[(r - 12) ** 2 + (c - 10) ** 2 < 9] = 400.0
    hu[:, :, 18:21] = 1200.0
    series.pixels = lambda k: (hu[k] + 1024).astype(np.int16)
    series.write(folder)
    set_tags(folder, lambda n: {"WindowCenter": ["300", "500"], "WindowWidth": ["800", "2000"],
                                "WindowCenterWidthExplanation": ["ANGIO", "BONE"]})
    return folder


def test_the_dicom_window_draws_as_its_ends_in_the_cli_and_in_pyvista(tmp_path, capsys):
    """``--window dicom`` draws the picture of ``--window LOW HIGH`` with the series' first window (not the
    default window's), ``dicom:BONE`` and ``dicom:2`` the second; the default run lists them; pyvista's
    ``clim="dicom"`` is its ``clim=(low, high)``; a volume without DICOM windows refuses the word, naming why."""
    from matplotlib.image import imread

    from mipcast.app.cli import main

    folder = angio_series(tmp_path / "s")

    def render(*window):
        out = tmp_path / f"{'_'.join(window) or 'default'}.png"
        args = ["render", str(folder), "--method", "mip", "--size", "64", "64", "--out", str(out)]
        assert main(args + (["--window", *window] if window else [])) == 0
        return imread(out)

    default = render()
    printed = capsys.readouterr().out
    assert "the series' own windows: --window dicom (ANGIO: -100 to 699), dicom:2 (BONE: -500 to 1499)" in printed
    angio = render("dicom")
    assert np.array_equal(angio, render("-100", "699"))
    assert not np.array_equal(angio, default)  # the default is ct-mip, 150 to 1800
    bone = render("dicom:BONE")
    assert np.array_equal(bone, render("dicom:2")) and np.array_equal(bone, render("-500", "1499"))
    assert not np.array_equal(bone, angio)
    assert main(["render", str(folder), "--window", "dicom:LUNG", "--out", str(tmp_path / "x.png")]) == 2
    assert "the series' windows are dicom (ANGIO: -100 to 699), dicom:2 (BONE: -500 to 1499)" in capsys.readouterr().err

    pv = pytest.importorskip("pyvista")
    import mipcast.filters  # noqa: F401  (registers grid.mip)
    grid = read_dicom(folder)
    assert np.array_equal(grid.mip.render("analytic", size=(48, 48), clim="dicom"),
                          grid.mip.render("analytic", size=(48, 48), clim=(-100, 699)))
    with pytest.raises(ValueError, match="carries none"):
        pv.wrap(np.asarray(grid.point_data["values"]).reshape(24, 24, 24)).mip.render("mip", clim="dicom")


def test_the_viewer_cycles_the_series_windows(tmp_path):
    """`mipcast view`'s `w` key: the default window, then the series' own (ANGIO, BONE), the CT presets that
    meet the data, the data range, round again; each drawn (the volume's colour range is the window)."""
    from mipcast.app.viewer import _Viewer

    viewer = _Viewer(read_dicom(angio_series(tmp_path / "s")), "mip", off_screen=True, window_size=(48, 48))
    first = viewer.plotter.screenshot()
    seen = []
    for _ in range(8):
        viewer.next_window()
        colours = viewer.volume.GetProperty().GetRGBTransferFunction(0).GetRange()
        seen.append((viewer.window_label, tuple(colours)))
    viewer.plotter.close()
    assert seen[:2] == [("dicom (ANGIO)", (-100.0, 699.0)), ("dicom:2 (BONE)", (-500.0, 1499.0))]
    words = [word for word, _ in seen]
    assert words[2:7] == ["ct-mip", "ct-angio", "ct-bone", "ct-soft", "full"]  # ct-minip lies below the data
    assert words[7] == "auto"  # round again
    assert first.max() > 100
