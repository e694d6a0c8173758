"""The mipcast command: demo, render, bench, and its error messages."""
import json
import subprocess
import sys

import numpy as np
import pytest
from matplotlib import pyplot
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

import mipcast
from mipcast.app.cli import main
from mipcast.data_fixtures import make_fixture
from installed import OUTSIDE


def test_demo_writes_pictures_and_error_maps(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path), "--size", "64"]) == 0
    printed = capsys.readouterr().out
    report = json.loads((tmp_path / "demo.json").read_text())
    assert {"stock", "mip", "analytic", "demip"} <= set(report)
    figure = pyplot.imread(report.pop("depth_figure")["png"])
    assert figure.shape[1] > figure.shape[0] and figure[..., :3].std() > 0.05
    for method, entry in report.items():
        picture = pyplot.imread(entry["png"])
        assert picture.shape[:2] == (64, 64)
        # an average projection draws the mean normalised scalar, not through the window (as stock
        # VTK's AVERAGE_INTENSITY blend): dim on the sparse vessels, but not black
        bright = 0.1 if mipcast.METHODS[method].projection == "average" else 0.5
        assert picture[..., :3].max() > bright, f"{method} picture is dark"
        assert entry["png"] in printed
    assert (tmp_path / "mip_error.png").exists()
    assert 0.0 < report["mip"]["within_1_grey"] < 1.0  # sampled MIP is not exact on vessels
    for exact in ("analytic", "analytic_minip", "analytic_average"):  # each against its own projection
        assert report[exact]["within_1_grey"] == 1.0, (exact, report[exact])
    assert str(tmp_path) in printed


def test_render_a_vti_file(tmp_path):
    source = _vti(tmp_path, make_fixture("spheres", size=32), "spheres.vti")
    out = tmp_path / "out.png"
    assert main(["render", str(source), "--method", "mip", "--out", str(out), "--size", "48", "40"]) == 0
    picture = pyplot.imread(out)
    assert picture.shape[:2] == (40, 48) and picture[..., :3].max() > 0.5


def test_render_a_cell_array_as_the_image_of_its_cell_centres(tmp_path):
    """A .vti whose scalars are cell data draws the picture of the same values as point data on the
    image of the cell centres (mipcast.core.prepare.cell_centres); before, the file was refused."""
    from vtkmodules.vtkFiltersCore import vtkPointDataToCellData

    from mipcast.core.prepare import cell_centres

    convert = vtkPointDataToCellData()
    convert.SetInputData(make_fixture("vessels", size=24))
    convert.Update()
    cells = convert.GetOutput()
    pictures = []
    for name, image in (("cells", cells), ("centres", cell_centres(cells))):
        source, out = _vti(tmp_path, image, f"{name}.vti"), tmp_path / f"{name}.png"
        assert main(["render", str(source), "--method", "analytic", "--out", str(out), "--size", "48", "40"]) == 0
        pictures.append(pyplot.imread(out))
    assert pictures[0][..., :3].max() > 0.5 and np.array_equal(pictures[0], pictures[1])


def test_render_with_auto_sampling_reports_and_uses_its_choice(tmp_path, capsys):
    source = _vti(tmp_path, make_fixture("vessels", size=32), "vessels.vti")
    outputs = {}
    for distance in ("auto", "1.0"):
        outputs[distance] = tmp_path / f"{distance}.png"
        assert main(["render", str(source), "--sample-distance", distance, "--out", str(outputs[distance]),
                     "--size", "64", "64"]) == 0
    said = capsys.readouterr().out
    rate = float(said.split("auto sampling: ")[1].split(" samples per voxel")[0])
    assert rate > 1.0 and "calibration rays within one grey level" in said
    assert not np.array_equal(pyplot.imread(outputs["auto"]), pyplot.imread(outputs["1.0"]))
    with pytest.raises(SystemExit):
        main(["render", str(source), "--sample-distance", "-1", "--out", str(tmp_path / "x.png")])


def test_render_out_without_a_picture_format_fails_before_reading(tmp_path, capsys):
    """--out o (no extension) failed after the render with matplotlib's "unknown file extension: "; it is
    refused first (exit 2) naming the formats; .jpg and .tiff are written as such."""
    from matplotlib import pyplot

    assert main(["render", str(tmp_path / "not-there.vti"), "--out", str(tmp_path / "o")]) == 2
    assert "names no picture format: end it in .png, .jpg" in capsys.readouterr().err
    source = _vti(tmp_path, make_fixture("vessels", size=16), "v.vti")
    for name in ("o.jpg", "o.tiff"):
        assert main(["render", str(source), "--out", str(tmp_path / name), "--size", "24", "16"]) == 0
        assert pyplot.imread(tmp_path / name).shape[:2] == (16, 24)


def test_render_a_volume_of_a_4d_nifti(tmp_path, capsys):
    """--volume K draws volume K of a 4D NIfTI: the picture of that volume saved alone; past the end: exit 2 and
    the count."""
    import nibabel
    from vtkmodules.util.numpy_support import vtk_to_numpy

    image = make_fixture("vessels", size=24)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(24, 24, 24).transpose(2, 1, 0)  # [x, y, z]
    series = np.stack([values, np.roll(values, 6, axis=0), values[::-1]], axis=-1).astype(np.float32)
    nibabel.save(nibabel.Nifti1Image(series, np.eye(4)), tmp_path / "series.nii.gz")
    nibabel.save(nibabel.Nifti1Image(series[..., 1], np.eye(4)), tmp_path / "second.nii.gz")
    shots = {}
    for name, extra in (("picked", ["--volume", "1"]), ("alone", []), ("first", ["--volume", "0"])):
        source = tmp_path / ("second.nii.gz" if name == "alone" else "series.nii.gz")
        out = tmp_path / f"{name}.png"
        assert main(["render", str(source), "--out", str(out), "--size", "48", "40", "--window", "0.2", "0.9"]
                    + extra) == 0
        shots[name] = pyplot.imread(out)
    assert np.array_equal(shots["picked"], shots["alone"]) and shots["picked"][..., :3].max() > 0.5
    assert not np.array_equal(shots["picked"], shots["first"])
    assert main(["render", str(tmp_path / "series.nii.gz"), "--volume", "3", "--out", str(tmp_path / "x.png")]) == 2
    assert "holds 3 volumes (4D NIfTI; volume 0 to 2); there is no volume 3" in capsys.readouterr().err


def test_render_a_data_set_of_a_multiblock_file(tmp_path, capsys):
    """A .vtm holding a volume and a mesh (a simulation's output, pyvista's MultiBlock.save): --volume K draws
    its data set K, the picture of that volume saved alone; without it: exit 2 naming the data sets and the
    option."""
    import pyvista

    image = pyvista.wrap(make_fixture("vessels", size=24))
    pyvista.MultiBlock({"mesh": pyvista.Sphere(), "volume": image}).save(tmp_path / "scene.vtm")
    image.save(tmp_path / "alone.vti")
    shots = {}
    for name, source, extra in (("picked", "scene.vtm", ["--volume", "1"]), ("alone", "alone.vti", [])):
        out = tmp_path / f"{name}.png"
        assert main(["render", str(tmp_path / source), "--out", str(out), "--size", "48", "40"] + extra) == 0
        shots[name] = pyplot.imread(out)
    assert np.array_equal(shots["picked"], shots["alone"]) and shots["picked"][..., :3].max() > 0.5
    assert main(["render", str(tmp_path / "scene.vtm"), "--out", str(tmp_path / "x.png")]) == 2
    error = capsys.readouterr().err
    assert "0: PolyData" in error and "1: ImageData" in error and "--volume K" in error


def test_render_average_applies_the_window(tmp_path, capsys):
    """--method average/analytic_average with two windows: two pictures (before 2026-12-04 the window was printed
    and ignored: the same picture whatever the window); stock_average (VTK's own grey) says it ignores it."""
    source = _vti(tmp_path, make_fixture("vessels", size=32), "vessels.vti")
    for method in ("average", "analytic_average"):
        shots = []
        for window in (["0", "1"], ["0", "0.25"]):
            out = tmp_path / f"{method}_{window[1]}.png"
            assert main(["render", str(source), "--method", method, "--out", str(out), "--size", "48", "40",
                         "--window"] + window) == 0
            shots.append(pyplot.imread(out)[..., :3])
        assert shots[1].mean() > 2.0 * shots[0].mean() > 0.0, method
    assert main(["render", str(source), "--method", "stock_average", "--out", str(tmp_path / "s.png"),
                 "--size", "48", "40"]) == 0
    assert "ignores the window" in capsys.readouterr().out


def test_render_errors_are_clear(tmp_path, capsys):
    assert main(["render", str(tmp_path / "missing.vti"), "--out", str(tmp_path / "x.png")]) == 2
    assert "missing.vti" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["render", "x.vti", "--method", "best", "--out", "x.png"])


def test_bench_writes_tables(tmp_path):
    assert main(["bench", "--scenes", "vessels@0.2,0.9", "--volume-size", "24", "--size", "32",
                 "--views", "oblique", "--rounds", "1", "--out", str(tmp_path)]) == 0
    rows = {row["setting"]: row for row in json.loads((tmp_path / "bench.json").read_text())}
    assert {"stock 1x", "stock 8x", "mip 1x", "analytic"} <= set(rows)
    auto = next(row for label, row in rows.items() if label.startswith("auto ("))
    assert auto["within_1_grey"] >= rows["stock 8x"]["within_1_grey"]
    assert all(row["median_ms"] > 0 for row in rows.values())
    assert rows["stock 1x"]["ratio_to_stock"] == 1.0
    assert rows["analytic"]["p99_pct"] < 0.1 <= rows["stock 1x"]["p99_pct"]  # exact vs sampled
    assert rows["stock 8x"]["p99_pct"] < rows["stock 1x"]["p99_pct"]
    assert "ratio_to_stock" in (tmp_path / "bench.md").read_text()
    assert (tmp_path / "bench.png").stat().st_size > 10000
    assert "mipcast, llvmpipe: vessels@0.2,0.9 oblique 32" in (tmp_path / "papers.md").read_text()
    assert rows["analytic"]["skipped_cells"] > 0.1  # the window lets analytic MIP skip blocks
    # (the corner's saving and the coarser periphery's error are checked at 96² below: at 32² the disc that
    # keeps every coarse level out of the fovea covers nearly the whole view)
    assert rows["foveated analytic"]["p99_pct"] >= rows["analytic"]["p99_pct"]
    assert "gaze at a corner" in (tmp_path / "papers.md").read_text()
    assert "2 passes / 1 pass" in (tmp_path / "papers.md").read_text()
    assert rows["demip two passes"]["p99_pct"] == pytest.approx(rows["demip"]["p99_pct"])  # same pictures


def test_bench_runs_on_a_volume_with_missing_values_and_counts_the_rays_that_saw_none(tmp_path):
    from mipcast.data_fixtures import image_from_array

    n = 24
    values = np.asarray(make_fixture("vessels", size=n).GetPointData().GetScalars()).reshape(n, n, n)
    holed = values.astype(np.float32)
    holed.ravel()[::7] = np.nan
    _vti(tmp_path, image_from_array(holed, "values"), "holed.vti")
    # (the sampled rays that met only missing samples were "GPU missed hit pixels" and ended the bench)
    assert main(["bench", "--scenes", str(tmp_path / "holed.vti"), "--size", "48", "--views", "oblique",
                 "--rounds", "1", "--out", str(tmp_path / "out")]) == 0
    rows = {row["setting"]: row for row in json.loads((tmp_path / "out" / "bench.json").read_text())}
    assert rows["mip 1x"].get("missing_data_misses", 0) > 0
    assert "missing_data_misses" not in rows["analytic"] and rows["analytic"]["within_1_grey"] >= 0.999
    assert "missing_data_misses" in (tmp_path / "out" / "bench.md").read_text()


def test_bench_foveation_writes_table_chart_and_ring_errors(tmp_path, capsys):
    assert main(["bench", "--foveation", "--scenes", "vessels", "--volume-size", "32", "--size", "96",
                 "--rounds", "1", "--out", str(tmp_path)]) == 0
    rows = json.loads((tmp_path / "foveation.json").read_text())
    assert {row["framing"] for row in rows} == {"fill", "whole"}
    by = {(row["framing"], row["setting"]): row for row in rows}
    for framing in ("fill", "whole"):
        assert by[framing, "full quality"]["speedup"] == 1.0
        off = by[framing, "foveation off"]
        assert off["ray_ratio"] == 1.0 and off["mean_grey_error"] == 0.0
        centre, corner = by[framing, "default | centre"], by[framing, "default | corner"]
        assert centre["fovea_within_1"] >= 0.99 and corner["fovea_within_1"] >= 0.99
        assert corner["ray_ratio"] > centre["ray_ratio"] and corner["ray_ratio"] > 1.0
        # (the whole volume at 96², gaze at the centre: the disc that keeps every coarse level out of the fovea
        # holds most of the volume, and the levels overlap: 0.95, no saving; filling the view: 2.2)
        assert centre["ray_ratio"] > (1.0 if framing == "fill" else 0.9)
        assert 1.0 < centre["ceiling"] < corner["ceiling"]
        # full quality inside the radius, coarser levels outside it
        inner = [ring for ring in centre["rings"] if ring["e_to"] <= centre["radius"]]
        outer = [ring for ring in centre["rings"] if ring["e_from"] >= centre["radius"] + centre["falloff"]]
        assert inner and max(ring["p99"] for ring in inner) <= 1
        assert outer and max(ring["mean"] for ring in outer) > 0.5
        # off-screen gaze: the coarsest level alone casts fewer rays than any gaze
        alone = by[framing, "periphery alone | off-screen"]
        assert alone["ray_ratio"] > corner["ray_ratio"] and alone["ceiling"] is None  # infinite, null in JSON
        # a 4th level's 8-pixel texels at 96² would reach into the fovea: the full-quality disc grows to keep
        # them out (start 0.27 -> 0.38 of the height), so here 4 levels cast more rays than 3, not fewer
        four = by[framing, "default, 4 levels | corner"]
        assert 1.0 < four["ray_ratio"] < corner["ray_ratio"] and four["fovea_within_1"] >= 0.99
    # the smaller fovea casts fewer rays than the default one
    assert by["fill", "radius 0.12 | centre"]["rays"] < by["fill", "default | centre"]["rays"]
    assert "Levoy & Whitaker" in (tmp_path / "foveation.md").read_text()
    assert (tmp_path / "foveation.png").stat().st_size > 10000
    assert "%|" in capsys.readouterr().err  # the progress bar
    # content-adaptive rows beside acuity-only; progressive refinement and the gaze replay
    adaptive = by["fill", "content-adaptive 2 grey | centre"]
    assert adaptive["content_tolerance"] == 2.0 and adaptive["fovea_structure_within_1"] >= 0.99
    extra = json.loads((tmp_path / "foveation-progressive.json").read_text())
    assert extra["progressive"][0]["frames_to_full"] == 4 and extra["progressive"][0]["steps"][-1]["equal"]
    assert extra["gaze"][0]["re_renders"]["fixation"] == extra["gaze"][0]["fixations"]
    assert "Progressive refinement" in (tmp_path / "foveation.md").read_text()


def test_console_script_is_installed():
    run = subprocess.run([sys.executable, "-m", "mipcast.app.cli", "--version"], capture_output=True, text=True, cwd=OUTSIDE)
    assert run.returncode == 0 and "mipcast" in run.stdout


def test_bench_stability_covers_every_method_with_its_own_measure(tmp_path):
    assert main(["bench", "--stability", "--out", str(tmp_path)]) == 0
    rows = json.loads((tmp_path / "stability.json").read_text())
    from mipcast.methods import METHODS

    assert {row["method"] for row in rows} == {name for name, m in METHODS.items() if m.float_readout}
    by = {(row["method"], row["case"]): row for row in rows}
    # every exact method against the exact reference of its own projection (maximum, minimum, average)
    assert all(row["within_1_grey"] == 1.0 for row in rows if row["method"].startswith("analytic"))
    assert by["minip", "thin vessels, defaults"]["measured"] == "minimum vs exact"
    assert by["mip", "thin vessels, 1 sample/voxel"]["p99_pct"] > by["mip", "thin vessels, 8 samples/voxel"]["p99_pct"]
    demip = [row for row in rows if row["method"] == "demip"]
    assert all(row["p99_pct"] < 1e-3 and row["measured"] == "depth vs DEMIP reference" for row in demip)
    noisy = [by["demip", name]["depth_jump_pct"] for name in (
        "noisy background, threshold 1e-4 (depth of the maximum itself)",
        "noisy background, threshold 0.1 (default)", "noisy background, threshold 0.5")]
    assert noisy[0] > noisy[1] > 2 * noisy[2]  # a tighter threshold gives noisier depth
    assert all(row["fovea_within_1_grey"] >= 0.99 for row in rows if row["method"] == "foveated")
    # specks smaller than the coarse rays' spacing: content-adaptive density keeps every one in the fovea
    for setting in ("acuity only", "content-adaptive 2 grey"):
        assert by["foveated", f"specks just above the window floor, {setting}"]["fovea_structure_within_1_grey"] == 1.0
    assert by["foveated", "'level' sampling when zoomed in"]["p99_pct"] > 2 * by[
        "foveated", "thin vessels, default radius (whole picture)"]["p99_pct"]
    assert "depth_jump_pct" in (tmp_path / "stability.md").read_text()


def _vti(tmp_path, image, name="volume.vti"):
    path = tmp_path / name
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(image)
    writer.Write()
    return path


def _offscreen_png(tmp_path, image, method, name, **settings):
    """The picture OffscreenView draws with the mapper set through its own setters."""
    from mipcast.app.cli import _write_png
    from mipcast.offscreen import OffscreenView

    view = OffscreenView(image, method, size=(48, 48))
    for setter, value in settings.items():
        getattr(view.mapper, setter)(*value)
    _write_png(tmp_path / name, view.screenshot())
    return pyplot.imread(tmp_path / name)


def test_render_sets_method_parameters_from_options(tmp_path):
    image = make_fixture("vessels", size=32)
    source = _vti(tmp_path, image)
    pictures = {}
    for weight in ("0.0", "0.9"):
        out = tmp_path / f"demip_{weight}.png"
        assert main(["render", str(source), "--method", "demip", "--out", str(out), "--size", "48", "48",
                     "--depth-weight", weight, "--depth-mode", "window"]) == 0
        pictures[weight] = pyplot.imread(out)
    assert not np.array_equal(pictures["0.0"], pictures["0.9"])
    expected = _offscreen_png(tmp_path, image, "demip", "expected.png",
                              SetDepthWeight=(0.9,), SetDepthMode=("window",))
    assert np.array_equal(pictures["0.9"], expected)
    # a name the command also has goes through --mapper-NAME; several values are unpacked
    out = tmp_path / "foveated.png"
    assert main(["render", str(source), "--method", "foveated", "--out", str(out), "--size", "48", "48",
                 "--mapper-method", "analytic", "--gaze-point", "0.1", "0.1", "--foveal-radius", "0.1"]) == 0
    expected = _offscreen_png(tmp_path, image, "foveated", "expected_foveated.png", SetMethod=("analytic",),
                              SetGazePoint=(0.1, 0.1), SetFovealRadius=(0.1,))
    assert np.array_equal(pyplot.imread(out), expected)


def test_render_refuses_unknown_or_repeated_parameters(tmp_path, capsys):
    source = _vti(tmp_path, make_fixture("spheres", size=16))
    out = tmp_path / "x.png"
    assert main(["render", str(source), "--method", "demip", "--out", str(out), "--depth-wieght", "0.3"]) == 2
    said = capsys.readouterr().err
    assert "no parameter 'depth_wieght'" in said and "depth_weight" in said
    assert main(["render", str(source), "--out", str(out), "--falloff", "0.1", "--falloff", "0.2"]) == 2
    assert "given twice" in capsys.readouterr().err
    assert not out.exists()
    with pytest.raises(SystemExit):  # other commands take no parameters
        main(["demo", "--depth-weight", "0.3"])


def test_render_scalars_picks_the_array(tmp_path, capsys):
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

    image = make_fixture("vessels", size=24)
    values = vtk_to_numpy(image.GetPointData().GetScalars())
    flipped = numpy_to_vtk(np.ascontiguousarray(values.reshape(24, 24, 24)[::-1].ravel()), deep=True)
    flipped.SetName("flipped")
    image.GetPointData().AddArray(flipped)
    source = _vti(tmp_path, image)
    outputs = {}
    for scalars in (None, "flipped"):
        outputs[scalars] = tmp_path / f"{scalars}.png"
        chosen = [] if scalars is None else ["--scalars", scalars]
        assert main(["render", str(source), "--out", str(outputs[scalars]), "--size", "48", "48", *chosen]) == 0
    assert not np.array_equal(pyplot.imread(outputs[None]), pyplot.imread(outputs["flipped"]))
    assert main(["render", str(source), "--out", str(tmp_path / "x.png"), "--scalars", "nope"]) == 2
    assert "'nope' is not a numeric point array" in capsys.readouterr().err


def test_render_parameters_must_follow_the_input(tmp_path, capsys):
    source = _vti(tmp_path, make_fixture("spheres", size=16))
    out = tmp_path / "x.png"
    assert main(["render", "--depth-weight", "0.3", str(source), "--method", "demip", "--out", str(out)]) == 2
    assert "method parameters go after the input" in capsys.readouterr().err
    assert main(["render", str(source), "--method", "demip", "--out", str(out), "--depth-weight="]) == 2
    assert "has no value" in capsys.readouterr().err
    # a setter that takes one sequence gets the values whole: SetRegionOfInterest((x, y, z))
    assert main(["render", str(source), "--method", "foveated", "--out", str(out), "--size", "32", "32",
                 "--region-of-interest", "8", "8", "8"]) == 0
    assert out.exists()


