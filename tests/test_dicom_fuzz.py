"""A short fuzz run (a few hundred mutated files, < 30 s); the long run is tests/dicom_fuzz.py.

Every mutated file must be read or refused with DicomError (a ValueError)
within 5 s, tracing at most dicom_fuzz.MEMORY_BOUND bytes.
"""
import tempfile
from pathlib import Path

import pytest

pytest.importorskip("pydicom")
hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings, strategies as st  # noqa: E402

import dicom_fuzz  # noqa: E402

SEEDS = dicom_fuzz.seeds()
OFFSETS = [dicom_fuzz.element_offsets(data) for _, data in SEEDS]
FOLDER = Path(tempfile.mkdtemp(prefix="mipcast-fuzz-"))


@settings(max_examples=300, deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(index=st.integers(0, len(SEEDS) - 1), kind=st.sampled_from(dicom_fuzz.KINDS),
       params=st.lists(st.integers(0, 2 ** 32 - 1), min_size=4, max_size=4))
def test_mutated_files_are_read_or_refused_with_dicom_error(index, kind, params):
    dicom_fuzz.setup()
    data = dicom_fuzz.mutate(SEEDS[index][1], OFFSETS[index], kind, params)
    outcome, seconds, traced = dicom_fuzz.run_case(data, FOLDER / "case.dcm")
    assert outcome in ("read", "DicomError"), f"{kind} of {SEEDS[index][0]} {params}: {outcome}"
    assert seconds < dicom_fuzz.TIME_LIMIT_S
    assert traced < dicom_fuzz.MEMORY_BOUND


def test_lying_dimensions_are_refused_before_allocating(tmp_path):
    import pydicom
    from pydicom.data import get_testdata_file
    from test_dicom_codecs import with_geometry

    from mipcast.io.dicom import DicomError, read_dicom

    multiframe = with_geometry("emri_small_RLE.dcm", tmp_path)  # 10 RLE frames with positions
    for source, lies, message in [
            (get_testdata_file("CT_small.dcm"), {"Rows": 65535, "Columns": 65535}, "GiB"),
            (get_testdata_file("CT_small.dcm"), {"Rows": 4000}, "but the file holds"),
            (get_testdata_file("MR_small_RLE.dcm"), {"Rows": 6000, "Columns": 6000},
             "compressed bytes"),
            (multiframe, {"Rows": 30000, "Columns": 30000}, "GiB"),
            (multiframe, {"Rows": 3000, "Columns": 3000}, "compressed bytes")]:
        ds = pydicom.dcmread(source)
        for keyword, value in lies.items():
            setattr(ds, keyword, value)
        ds.save_as(tmp_path / "lie.dcm")
        dicom_fuzz.setup()
        outcome, seconds, traced = dicom_fuzz.run_case((tmp_path / "lie.dcm").read_bytes(),
                                                       tmp_path / "case.dcm")
        assert outcome == "DicomError" and traced < 16 * 2 ** 20, (lies, outcome, traced)
        with pytest.raises(DicomError, match=message):
            read_dicom(tmp_path / "lie.dcm")
