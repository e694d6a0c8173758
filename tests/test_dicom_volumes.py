"""Several volumes in one series (echoes, time points, acquisitions, stacks).

They are listed by list_series with an ``id`` to pass as ``series_uid``;
read_dicom without one refuses, naming the ids.  Expected values and
positions come from how the files were written.
"""
import shutil

import numpy as np
import pytest

pydicom = pytest.importorskip("pydicom")
from pydicom.dataset import Dataset  # noqa: E402
from pydicom.sequence import Sequence  # noqa: E402
from pydicom.uid import generate_uid  # noqa: E402
from test_dicom import ENHANCED_CT_IMAGE, Series, base_dataset, direction, ds_numbers, physical, rotation, save  # noqa: E402,E501
from test_dicom_mosaic import Mosaic  # noqa: E402

from mipcast.io.dicom import DicomError, list_series, read_dicom  # noqa: E402
from mipcast.core.validation import check_image  # noqa: E402


def multi_volume_series(folder, keyword, values, n=5):
    """One series written once per value of ``keyword``; pixels offset by 1000 x index."""
    series = Series(n=n)
    for index, value in enumerate(values):
        part = series.write(folder.parent / f"part{index}", seed=index)
        for file in sorted(part.iterdir()):
            ds = pydicom.dcmread(str(file))
            setattr(ds, keyword, value)
            ds.SOPInstanceUID = ds.file_meta.MediaStorageSOPInstanceUID = generate_uid()
            ds.PixelData = (ds.pixel_array + 1000 * index).astype("<i2").tobytes()
            folder.mkdir(exist_ok=True)
            save(ds, folder / f"{index}_{file.name}")
    return series


@pytest.mark.parametrize("keyword, values", [("EchoNumbers", [1, 2]),
                                             ("TemporalPositionIdentifier", [1, 2, 3]),
                                             ("AcquisitionNumber", [4, 7])])
def test_volumes_of_one_series_are_listed_and_chosen(tmp_path, keyword, values):
    folder = tmp_path / "mixed"
    series = multi_volume_series(folder, keyword, values)
    listed = list_series(folder)
    assert [s["id"] for s in listed] == [f"{series.uid}#{keyword}={v}" for v in values]
    assert [(s["uid"], s["volume"], s["n_files"], s["n_slices"]) for s in listed] == [
        (series.uid, f"{keyword}={v}", 5, 5) for v in values]
    with pytest.raises(DicomError, match=rf"holds {len(values)} volumes.*told apart by {keyword}"):
        read_dicom(folder)
    for index, entry in enumerate(listed):
        image = read_dicom(folder, series_uid=entry["id"])
        assert image.GetDimensions() == (5, 4, 5)
        np.testing.assert_allclose(image.GetOrigin(), series.ipp(0), atol=1e-4)
        values_read = check_image(image)
        for k in range(5):
            np.testing.assert_array_equal(values_read[k], series.pixels(k) - 1024 + 1000 * index)
    with pytest.raises(DicomError, match="choose one with series_uid"):
        read_dicom(folder, series_uid=f"{series.uid}#{keyword}=99")


def test_a_single_volume_series_keeps_its_plain_uid(tmp_path):
    series = Series()
    (entry,) = list_series(series.write(tmp_path / "s"))
    assert (entry["id"], entry["volume"], entry["n_slices"]) == (series.uid, "", 6)


def test_time_series_of_mosaics_split_by_acquisition(tmp_path):
    mosaic = Mosaic(n=4, tile=(4, 4))
    uid = generate_uid()
    for t in (1, 2):
        path = mosaic.write(tmp_path / f"t{t}.dcm")
        ds = pydicom.dcmread(str(path))
        ds.SeriesInstanceUID, ds.AcquisitionNumber = uid, t
        save(ds, path)
    assert [s["volume"] for s in list_series(tmp_path)] == ["AcquisitionNumber=1", "AcquisitionNumber=2"]
    image = read_dicom(tmp_path, series_uid=f"{uid}#AcquisitionNumber=2")
    assert image.GetDimensions() == (4, 4, 4)
    np.testing.assert_allclose(physical(image, 1, 2, 3), mosaic.voxel(1, 2, 3), atol=1e-4)


def enhanced(path, stacks, per_frame_orientation=False):
    """An enhanced CT whose frames belong to ``stacks`` (Series per StackID), stored shuffled.

    Rescale is per frame (PixelValueTransformationSequence in each frame);
    orientation is shared, or per frame if ``per_frame_orientation``.
    """
    frames = [(sid, k) for sid in stacks for k in range(len(stacks[sid].positions))]
    frames = [frames[i] for i in np.random.default_rng(3).permutation(len(frames))]
    first = next(iter(stacks.values()))
    ds = base_dataset(ENHANCED_CT_IMAGE, first.uid)
    ds.NumberOfFrames = len(frames)
    ds.Rows, ds.Columns = first.rows, first.cols
    ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
    ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
    shared, measures = Dataset(), Dataset()
    measures.PixelSpacing = ds_numbers(first.pixel_spacing, 4)
    shared.PixelMeasuresSequence = Sequence([measures])
    groups = []
    for sid, k in frames:
        stack = stacks[sid]
        group, position, content, transform, orientation = (Dataset() for _ in range(5))
        position.ImagePositionPatient = ds_numbers(stack.ipp(k), 4)
        content.StackID, content.InStackPositionNumber = str(sid), k + 1
        transform.RescaleSlope, transform.RescaleIntercept = f"{0.5 * (k + 1):g}", f"{-10 * k}"
        transform.RescaleType = "HU"
        orientation.ImageOrientationPatient = ds_numbers(stack.iop, 6)
        group.PlanePositionSequence = Sequence([position])
        group.FrameContentSequence = Sequence([content])
        group.PixelValueTransformationSequence = Sequence([transform])
        if per_frame_orientation:
            group.PlaneOrientationSequence = Sequence([orientation])
        groups.append(group)
    if not per_frame_orientation:
        orientation = Dataset()
        orientation.ImageOrientationPatient = ds_numbers(first.iop, 6)
        shared.PlaneOrientationSequence = Sequence([orientation])
    ds.SharedFunctionalGroupsSequence = Sequence([shared])
    ds.PerFrameFunctionalGroupsSequence = Sequence(groups)
    ds.PixelData = np.stack([stacks[sid].pixels(k) for sid, k in frames]).astype("<i2").tobytes()
    save(ds, path)
    return path


def test_enhanced_multiframe_with_per_frame_rescale_and_orientation(tmp_path):
    stack = Series(rot=rotation(30, 20), n=5)
    image = read_dicom(enhanced(tmp_path / "e.dcm", {1: stack}, per_frame_orientation=True))
    assert image.GetDimensions() == (5, 4, 5)
    np.testing.assert_allclose(direction(image)[:, 2], stack.normal, atol=1e-5)
    np.testing.assert_allclose(image.GetOrigin(), stack.ipp(0), atol=1e-4)
    values = check_image(image)
    for k in range(5):
        np.testing.assert_allclose(values[k], stack.pixels(k) * 0.5 * (k + 1) - 10 * k)


def test_enhanced_multiframe_with_two_stacks_is_split_by_stack_id(tmp_path):
    a = Series(rot=rotation(30), n=4)
    b = Series(rot=rotation(30), n=4, origin=(-20.0, 35.0, 110.5))  # interleaved positions
    b.uid = a.uid
    path = enhanced(tmp_path / "e.dcm", {1: a, 2: b})
    assert [s["volume"] for s in list_series(path)] == ["StackID=1", "StackID=2"]
    image = read_dicom(path, series_uid=f"{a.uid}#StackID=2")
    np.testing.assert_allclose(image.GetOrigin(), b.ipp(0), atol=1e-4)
    assert image.GetSpacing()[2] == pytest.approx(1.25, abs=1e-4)


def test_distinct_acquisition_numbers_per_slice_do_not_split(tmp_path):
    # some CT scanners number every slice's acquisition: one clean stack stays one volume
    series = Series(n=5)
    folder = series.write(tmp_path / "s")
    for number, file in enumerate(sorted(folder.iterdir())):
        ds = pydicom.dcmread(str(file))
        ds.AcquisitionNumber = number + 1
        save(ds, file)
    (entry,) = list_series(folder)
    assert entry["volume"] == "" and entry["n_slices"] == 5
    assert read_dicom(folder).GetDimensions() == (5, 4, 5)


def test_enhanced_multiframe_time_points_split_by_temporal_position_index(tmp_path):
    stack = Series(rot=rotation(10), n=3)
    path = enhanced(tmp_path / "e.dcm", {1: stack, 2: stack})  # two "stacks" at the same place
    ds = pydicom.dcmread(str(path))
    for group in ds.PerFrameFunctionalGroupsSequence:  # make them time points of one stack
        content = group.FrameContentSequence[0]
        content.TemporalPositionIndex, content.StackID = int(content.StackID), "1"
    save(ds, path)
    assert [s["volume"] for s in list_series(path)] == ["TemporalPositionIndex=1",
                                                        "TemporalPositionIndex=2"]
    image = read_dicom(path, series_uid=f"{stack.uid}#TemporalPositionIndex=2")
    assert image.GetDimensions() == (5, 4, 3)
    np.testing.assert_allclose(image.GetOrigin(), stack.ipp(0), atol=1e-4)


def test_a_localizer_stored_in_the_series_is_left_out_with_a_warning(tmp_path):
    """A scout (ImageType ...\\LOCALIZER, another orientation and size) in the series of the volume: the volume is
    read and the warning names the file (before 2026-12-04: refused, "different sizes ... keep only the slices of one
    stack"); list_series counts the slices without it."""
    from mipcast.io.dicom import DicomSeriesWarning

    series = Series()
    folder = series.write(tmp_path / "ct")
    scout = Series(rot=rotation(0.0, 90.0), rows=7, cols=5)  # coronal, 7 rows: not a slice of the stack
    scout.uid = series.uid
    scout.write(tmp_path / "scout", ks=[0], shuffle=False)
    ds = pydicom.dcmread(str(next((tmp_path / "scout").iterdir())))
    ds.ImageType = ["ORIGINAL", "PRIMARY", "LOCALIZER"]
    save(ds, folder / "SCOUT")
    with pytest.warns(UserWarning, match=r"skipped 1 localizer image\(s\) \(ImageType LOCALIZER\): SCOUT") as caught:
        image = read_dicom(folder)
    assert any(issubclass(w.category, DicomSeriesWarning) for w in caught)
    assert image.GetDimensions() == (5, 4, 6)
    values = check_image(image)
    for k in range(6):
        np.testing.assert_array_equal(values[k], series.pixels(k) - 1024)
    (entry,) = list_series(folder)
    assert entry["n_slices"] == 6


def test_copies_of_one_image_are_read_once_with_a_warning(tmp_path):
    """Files of one SOPInstanceUID (a folder copied or exported twice: "IM0003" and "IM0003 (1)") are one image:
    read once, the copies named in a warning (before 2026-12-04: refused as duplicate slice positions)."""
    series = Series()
    folder = series.write(tmp_path / "ct")
    for name in sorted(p.name for p in folder.iterdir())[:2]:
        shutil.copy(folder / name, folder / f"{name} (1)")
    with pytest.warns(UserWarning, match=r"skipped 2 copies of an image already read.*IM\d+ \(1\) \(= IM\d+\)"):
        image = read_dicom(folder)
    values = check_image(image)
    assert image.GetDimensions() == (5, 4, 6)
    for k in range(6):
        np.testing.assert_array_equal(values[k], series.pixels(k) - 1024)
    (entry,) = list_series(folder)
    assert entry["n_slices"] == 6
