"""Compressed transfer syntaxes, on pydicom's own test files of each syntax.

Lossless files are compared with their uncompressed twins (pydicom ships
both); the others with pydicom's own decoding of the same file.  Files without
patient geometry (NM, US, secondary captures) get ImagePositionPatient,
ImageOrientationPatient and PixelSpacing added to a copy, leaving their
compressed pixel data untouched.
"""
import io

import numpy as np
import pytest

pydicom = pytest.importorskip("pydicom")
from pydicom.data import get_testdata_file  # noqa: E402
from pydicom.dataset import Dataset  # noqa: E402
from pydicom.encaps import encapsulate  # noqa: E402
from pydicom.sequence import Sequence  # noqa: E402
from pydicom.uid import JPEGBaseline8Bit, JPEGLSLossless  # noqa: E402
from test_dicom import CT_IMAGE, base_dataset, save  # noqa: E402

from mipcast.io.dicom import DicomError, DicomPaddingWarning, read_dicom  # noqa: E402
from mipcast.core.validation import check_image  # noqa: E402


def pydicom_file(name):
    path = get_testdata_file(name)
    if path is None:
        pytest.skip(f"{name} needs pydicom-data (pip install pydicom-data)")
    return path


def with_geometry(name, tmp_path, spacing=(0.8, 0.6), step=2.0):
    """A copy of a test file with patient geometry (per frame if multi-frame)."""
    ds = pydicom.dcmread(pydicom_file(name))
    frames = int(ds.get("NumberOfFrames", 1) or 1)
    for keyword in ("ImagePositionPatient", "ImageOrientationPatient", "PixelSpacing",
                    "GridFrameOffsetVector"):
        if keyword in ds:
            delattr(ds, keyword)
    iop = ["1", "0", "0", "0", "1", "0"]
    if frames == 1:
        ds.ImagePositionPatient = ["-10", "20", "30"]
        ds.ImageOrientationPatient = iop
        ds.PixelSpacing = [str(v) for v in spacing]
    else:
        shared, orientation, measures = Dataset(), Dataset(), Dataset()
        orientation.ImageOrientationPatient = iop
        measures.PixelSpacing = [str(v) for v in spacing]
        shared.PlaneOrientationSequence = Sequence([orientation])
        shared.PixelMeasuresSequence = Sequence([measures])
        ds.SharedFunctionalGroupsSequence = Sequence([shared])
        groups = []
        for k in range(frames):
            group, position = Dataset(), Dataset()
            position.ImagePositionPatient = ["-10", "20", f"{30 + step * k:g}"]
            group.PlanePositionSequence = Sequence([position])
            groups.append(group)
        ds.PerFrameFunctionalGroupsSequence = Sequence(groups)
    out = tmp_path / name
    save(ds, out)
    return out


def stored(name):
    ds = pydicom.dcmread(pydicom_file(name))
    array = ds.pixel_array
    return array.reshape((int(ds.get("NumberOfFrames", 1) or 1),) + array.shape[-2:])


def rescaled(name):
    ds = pydicom.dcmread(pydicom_file(name))
    return stored(name) * float(ds.get("RescaleSlope", 1) or 1) + float(
        ds.get("RescaleIntercept", 0) or 0)


def syntax_of(path):
    return pydicom.dcmread(path, stop_before_pixels=True).file_meta.TransferSyntaxUID


@pytest.mark.parametrize("name, twin", [
    ("MR_small_RLE.dcm", "MR_small.dcm"),                       # RLE lossless
    ("MR_small_jp2klossless.dcm", "MR_small.dcm"),              # JPEG 2000 lossless
    ("MR_small_jpeg_ls_lossless.dcm", "MR_small.dcm"),          # JPEG-LS lossless
    ("693_J2KR.dcm", "693_UNCR.dcm"),                           # JPEG 2000 lossless (CT)
    ("MR2_J2KR.dcm", "MR2_UNCR.dcm"),                           # JPEG 2000 lossless (MR, 12 bit)
])
def test_lossless_single_frames_equal_their_uncompressed_twin(name, twin):
    path = pydicom_file(name)
    assert syntax_of(path).is_compressed and not syntax_of(pydicom_file(twin)).is_compressed
    image = read_dicom(path, padding="keep")
    ds = pydicom.dcmread(pydicom_file(twin))
    assert image.GetDimensions() == (ds.Columns, ds.Rows, 1)
    assert image.GetSpacing()[:2] == pytest.approx((float(ds.PixelSpacing[1]), float(ds.PixelSpacing[0])))
    assert image.GetOrigin() == pytest.approx([float(v) for v in ds.ImagePositionPatient])
    np.testing.assert_allclose(_values(image), rescaled(twin), rtol=1e-6)  # float32 if rescaled


def test_a_real_ct_s_padding_outside_its_field_of_view_is_missing_data():
    """GE's CT (693_UNCR and its lossless JPEG 2000 twin): 21 % of the pixels, the corners outside the
    scanned circle, hold PixelPaddingValue -2000; they read as NaN, everything else as the twin's HU.
    The lossy twin (693_J2KI) holds the value in 494 scattered pixels only: kept, with the reason."""
    ds = pydicom.dcmread(pydicom_file("693_UNCR.dcm"))
    padded = ds.pixel_array == -2000
    assert 0.2 < padded.mean() < 0.25 and padded[0, 0] and not padded[256, 256]
    for name in ("693_UNCR.dcm", "693_J2KR.dcm"):
        with pytest.warns(DicomPaddingWarning, match=r"55772 of 262144 pixels \(21\.3 %\)"):
            values = _values(read_dicom(pydicom_file(name)))[0]
        assert np.array_equal(np.isnan(values), padded)
        np.testing.assert_array_equal(values[~padded], rescaled("693_UNCR.dcm")[0][~padded])
    with pytest.warns(DicomPaddingWarning, match=r"lossy compressed.*494 of 262144"):
        assert not np.isnan(_values(read_dicom(pydicom_file("693_J2KI.dcm")))).any()


def _values(image):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    nx, ny, nz = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(nz, ny, nx)


@pytest.mark.parametrize("name", [
    "emri_small_RLE.dcm",                 # RLE, 10 frames
    "emri_small_jpeg_2k_lossless.dcm",    # JPEG 2000 lossless, 10 frames
    "emri_small_jpeg_ls_lossless.dcm",    # JPEG-LS lossless, 10 frames
])
def test_compressed_multiframes_equal_the_uncompressed_twin(name, tmp_path):
    image = read_dicom(with_geometry(name, tmp_path))
    assert image.GetDimensions() == (64, 64, 10)
    assert image.GetSpacing() == pytest.approx((0.6, 0.8, 2.0))
    assert image.GetOrigin() == pytest.approx((-10, 20, 30))
    np.testing.assert_array_equal(check_image(image), stored("emri_small.dcm"))


@pytest.mark.parametrize("name", [
    "JPEG-LL.dcm",                          # JPEG lossless, process 14 SV1, 16 bit
    "JPGLosslessP14SV1_1s_1f_8b.dcm",       # JPEG lossless, process 14 SV1, 8 bit
    "JPGExtended.dcm",                      # JPEG extended (process 2 and 4), 12 bit
    "JPEGLSNearLossless_16.dcm",            # JPEG-LS near-lossless
    "MR2_J2KI.dcm",                         # JPEG 2000 (lossy)
])
def test_other_syntaxes_decode_as_pydicom_does(name, tmp_path):
    path = with_geometry(name, tmp_path)
    assert syntax_of(path).is_compressed
    image = read_dicom(path)
    expected = rescaled(name)
    assert image.GetDimensions() == (expected.shape[2], expected.shape[1], 1)
    np.testing.assert_allclose(_values(image), expected, rtol=1e-6)


def test_jpeg_baseline_greyscale_generated_with_pillow(tmp_path):
    pil = pytest.importorskip("PIL.Image")
    r, c = np.mgrid[0:32, 0:48]
    pixels = (4 * r + 2 * c).astype(np.uint8)
    buffer = io.BytesIO()
    pil.fromarray(pixels).save(buffer, format="JPEG", quality=95)
    ds = base_dataset(CT_IMAGE, "1.2.826.0.1.3680043.8.498.77", modality="OT")
    ds.file_meta.TransferSyntaxUID = JPEGBaseline8Bit
    ds.ImagePositionPatient, ds.ImageOrientationPatient = ["0", "0", "0"], ["1", "0", "0", "0", "1", "0"]
    ds.PixelSpacing = ["1", "1"]
    ds.Rows, ds.Columns = pixels.shape
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 8, 8, 7, 0
    ds.PixelData = encapsulate([buffer.getvalue()])
    ds["PixelData"].VR = "OB"
    save(ds, tmp_path / "baseline.dcm")
    values = _values(read_dicom(tmp_path / "baseline.dcm"))[0]
    independent = np.asarray(pil.open(io.BytesIO(buffer.getvalue())))
    assert np.abs(values.astype(int) - independent).max() <= 1  # decoders may round differently
    assert np.abs(values.astype(int) - pixels).max() <= 8       # JPEG at quality 95


def test_colour_jpeg_and_rle_are_refused_as_colour():
    for name in ("SC_rgb_jpeg_dcmtk.dcm", "SC_rgb_rle.dcm"):
        with pytest.raises(DicomError, match="colour image"):
            read_dicom(pydicom_file(name))


def test_missing_jpeg_ls_decoder_names_the_package(monkeypatch):
    decoders = pytest.importorskip("pydicom.pixels")
    monkeypatch.setattr(decoders.get_decoder(JPEGLSLossless), "_available", {})
    with pytest.raises(DicomError, match=r"JPEG-LS.*pip install pylibjpeg pylibjpeg-libjpeg"):
        read_dicom(pydicom_file("MR_small_jpeg_ls_lossless.dcm"))
