"""The scripts in examples/ run as they are: VTK 9.7 (pip), VTK 9.2 (ParaView's pvpython), pyvista + DICOM."""
import ast
import io
import os
import shutil
import subprocess
import sys
import tokenize
from pathlib import Path

import numpy as np
import pytest
from matplotlib import pyplot

import mipcast
from installed import ROOT, plain_env, pvpython_env
from xvfb import run_under_xvfb

EXAMPLES = ROOT / "examples"
SWAP = EXAMPLES / "vtk_pipeline_swap.py"
DICOM_DEMIP = EXAMPLES / "pyvista_dicom_demip.py"
HAVE_PVPYTHON = shutil.which("pvpython") is not None and shutil.which("xvfb-run") is not None


def run(command, tmp_path, timeout=180):
    result = subprocess.run(command, cwd=tmp_path, env=plain_env(), capture_output=True, text=True,
                            timeout=timeout)
    assert result.returncode == 0, result.stdout + result.stderr
    return result


def picture(path):
    """The PNG as (H, W, 3) floats in [0, 1], checked to be a real picture, not a black/flat one."""
    pixels = pyplot.imread(path)[..., :3]
    assert pixels.max() > 0.5, f"{path.name} is dark"
    assert pixels.std() > 0.05, f"{path.name} is flat"
    return pixels


def code_lines(path):
    """Lines holding code: not blank, not comments, not the module docstring."""
    source = path.read_text()
    docstring = ast.get_docstring(ast.parse(source), clean=False)
    lines = set()
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT,
                          tokenize.DEDENT, tokenize.ENDMARKER):
            continue
        if token.type == tokenize.STRING and docstring is not None and docstring in token.string:
            continue
        lines.update(range(token.start[0], token.end[0] + 1))
    return len(lines)


# ---------------------------------------------------------------------------
# examples/vtk_pipeline_swap.py
# ---------------------------------------------------------------------------

def swap_variants():
    """(mipcast script, stock script): the example as shipped and with the stock line instead."""
    lines = SWAP.read_text().splitlines(keepends=True)
    stock = [i for i, line in enumerate(lines) if line.rstrip().endswith("# <- stock VTK")]
    ours = [i for i, line in enumerate(lines) if line.rstrip().endswith("# <- mipcast")]
    assert len(stock) == len(ours) == 1 and ours[0] == stock[0] + 1
    stock_line = lines[stock[0]].replace("# ", "", 1)  # uncomment: "    # volume.Set..." -> "    volume.Set..."
    mipcast_script = lines[:stock[0]] + lines[ours[0]:]
    stock_script = lines[:stock[0]] + [stock_line] + lines[ours[0] + 1:]
    return mipcast_script, stock_script


def test_swap_is_one_changed_line():
    mipcast_script, stock_script = swap_variants()
    changed = [(a, b) for a, b in zip(mipcast_script, stock_script) if a != b]
    assert len(mipcast_script) == len(stock_script) and len(changed) == 1, changed
    (ours, theirs), = changed
    assert ours.strip() == "mipcast.AnalyticMIPVolumeMapper().Attach(volume)  # <- mipcast"
    assert theirs.strip() == "volume.SetMapper(vtkGPUVolumeRayCastMapper())  # <- stock VTK"


def test_vtk_pipeline_swap_vtk97(tmp_path):
    mipcast_script, stock_script = swap_variants()
    (tmp_path / "stock.py").write_text("".join(stock_script))
    ours = run([sys.executable, str(SWAP), str(tmp_path / "mipcast.png")], tmp_path)
    theirs = run([sys.executable, str(tmp_path / "stock.py"), str(tmp_path / "stock.png")], tmp_path)
    assert "AnalyticMIPVolumeMapper" in ours.stdout
    assert "vtkOpenGLGPUVolumeRayCastMapper" in theirs.stdout
    ours_png, stock_png = picture(tmp_path / "mipcast.png"), picture(tmp_path / "stock.png")
    assert ours_png.shape == stock_png.shape == (256, 256, 3)
    # exact vs sampled maximum of the same volume: the same picture up to sampling error
    assert np.abs(ours_png - stock_png).mean() < 0.02
    assert np.corrcoef(ours_png.ravel(), stock_png.ravel())[0, 1] > 0.98


@pytest.mark.skipif(not HAVE_PVPYTHON, reason="needs pvpython (ParaView 5.11, VTK 9.2) and xvfb-run")
def test_vtk_pipeline_swap_vtk92_in_pvpython(tmp_path):
    result = run_under_xvfb(["pvpython", str(SWAP), str(tmp_path / "vtk92.png")], cwd=tmp_path,
                            env=pvpython_env(), timeout=180)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "AnalyticMIPVolumeMapper" in result.stdout
    run([sys.executable, str(SWAP), str(tmp_path / "vtk97.png")], tmp_path)
    vtk92, vtk97 = picture(tmp_path / "vtk92.png"), picture(tmp_path / "vtk97.png")
    assert np.abs(vtk92 - vtk97).max() <= 2 / 255  # same shader pieces, same picture


def test_vtk_pipeline_swap_reads_a_given_file(tmp_path):
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    from mipcast.data_fixtures import make_fixture

    writer = vtkXMLImageDataWriter()
    writer.SetFileName(str(tmp_path / "spheres.vti"))
    writer.SetInputData(make_fixture("spheres", size=24))
    writer.Write()
    run([sys.executable, str(SWAP), str(tmp_path / "out.png"), str(tmp_path / "spheres.vti")], tmp_path)
    picture(tmp_path / "out.png")


# ---------------------------------------------------------------------------
# examples/pyvista_dicom_demip.py
# ---------------------------------------------------------------------------

def write_ct_series(folder, shape=(16, 32, 32)):
    """A small synthetic CT (int16 + rescale to HU): two oblique bright tubes at different depths."""
    from pydicom.dataset import Dataset, FileMetaDataset
    from pydicom.uid import ExplicitVRLittleEndian, generate_uid

    ct_image = "1.2.840.10008.5.1.4.1.1.2"
    nz, ny, nx = shape
    z, y, x = np.mgrid[:nz, :ny, :nx].astype(float)
    tubes = (1400 * np.exp(-((x - 8 - y / 2) ** 2 + (z - 4) ** 2) / 4.0)
             + 1400 * np.exp(-((y - 20 + x / 3) ** 2 + (z - 12) ** 2) / 4.0))
    stored = np.round(tubes).astype("<i2")  # HU = stored - 1024: air-like background, tubes ~ bone
    series, study = generate_uid(), generate_uid()
    folder.mkdir(parents=True, exist_ok=True)
    for k in range(nz):
        meta = FileMetaDataset()
        meta.MediaStorageSOPClassUID = ct_image
        meta.MediaStorageSOPInstanceUID = generate_uid()
        meta.TransferSyntaxUID = ExplicitVRLittleEndian
        ds = Dataset()
        ds.file_meta = meta
        ds.SOPClassUID, ds.SOPInstanceUID = ct_image, meta.MediaStorageSOPInstanceUID
        ds.StudyInstanceUID, ds.SeriesInstanceUID, ds.Modality = study, series, "CT"
        ds.InstanceNumber = k + 1
        ds.ImagePositionPatient = ["-12.0", "-12.0", f"{1.5 * k:.1f}"]
        ds.ImageOrientationPatient = ["1", "0", "0", "0", "1", "0"]
        ds.PixelSpacing = ["0.75", "0.75"]
        ds.Rows, ds.Columns = ny, nx
        ds.SamplesPerPixel, ds.PhotometricInterpretation = 1, "MONOCHROME2"
        ds.BitsAllocated, ds.BitsStored, ds.HighBit, ds.PixelRepresentation = 16, 16, 15, 1
        ds.RescaleSlope, ds.RescaleIntercept = "1", "-1024"
        ds.PixelData = stored[k].tobytes()
        try:
            ds.save_as(folder / f"slice{k:03d}.dcm", enforce_file_format=True)
        except TypeError:  # pydicom 2.x
            ds.save_as(folder / f"slice{k:03d}.dcm", write_like_original=False)
    return folder


def test_dicom_demip_script_is_at_most_10_lines():
    assert code_lines(DICOM_DEMIP) <= 10
    assert '"demip"' in DICOM_DEMIP.read_text()


@pytest.mark.skipif("demip" not in mipcast.METHODS, reason="DEMIP is not registered yet")
def test_dicom_demip_script_writes_a_picture(tmp_path):
    pytest.importorskip("pydicom")
    folder = write_ct_series(tmp_path / "ct")
    run([sys.executable, str(DICOM_DEMIP), str(folder), str(tmp_path / "demip.png")], tmp_path)
    pixels = picture(tmp_path / "demip.png")
    assert (pixels.max(axis=2) > 0.5).mean() > 0.002, "the tubes are not visible"
