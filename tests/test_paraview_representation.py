"""ParaView's "mipcast" representation (plugin/representation), built and run for real.

The plugin is built with ``plugin/representation/build.sh`` into
``build/paraview-representation`` when it is not there yet (needs cmake, g++
and Debian's paraview-dev; skipped with the reason otherwise).  Then
``tests/paraview_representation_check.py`` runs in pvpython under xvfb, once
in a builtin session and once as the client of a ``pvserver`` this module
starts and stops itself, and the ParaView GUI is scripted once
(``tests/paraview_representation_gui.py``).  Every picture is compared with
mipcast's own offscreen render (:class:`mipcast.offscreen.OffscreenView`)
given ParaView's camera.
"""
import fcntl
import json
import os
import shutil
import socket
import subprocess
import sys
import xml.dom.minidom
from pathlib import Path

import pytest
from installed import pvpython_env
from xvfb import run_under_xvfb

ROOT = Path(__file__).resolve().parents[1]
GLUE_DIR = ROOT / "plugin" / "representation"
BUILD = ROOT / "build" / "paraview-representation"
CHECK = ROOT / "tests" / "paraview_representation_check.py"
GUI = ROOT / "tests" / "paraview_representation_gui.py"
#: Share of pixels within 1 grey level of the offscreen render.
MATCH = 0.999
#: Methods whose picture must equal mipcast's offscreen render: every method of the table that
#: renders in a view.
PARITY = tuple(name for name, method in __import__("mipcast").METHODS.items() if method.in_view)

sys.path.insert(0, str(GLUE_DIR))
import mipcast_representation  # noqa: E402  (build-time half: no ParaView needed)


# -- the generated panel (no ParaView needed) ----------------------------------------------------
def test_plugin_methods_lists_every_method_with_getter_defaults():
    import mipcast
    from mipcast.core.parameters import method_parameters, setter_name

    table = {m["name"]: m for m in mipcast_representation.plugin_methods()}
    assert set(table) == set(mipcast.METHODS)
    for name, method in table.items():
        mapper = mipcast.create_mapper(name)
        listed = {p["name"] for p in method["parameters"]}
        for parameter in method_parameters(mapper):
            if parameter in ("corner_packer",) or parameter in mipcast_representation.NOT_IN_PANEL:
                continue
            assert parameter in listed, (name, parameter)
        for p in method["parameters"]:
            if p["name"].endswith(mipcast_representation.FOLLOWS):  # on = the mapper's None
                getter = getattr(mapper, "Get" + setter_name(p["name"][:-len(mipcast_representation.FOLLOWS)])[3:])
                assert p["default"] is True and getter() is None, (name, p["name"])
                continue
            if p["name"] in mipcast_representation.FOLLOWING:
                assert p["size"] == 3 and len(p["default"]) == 3, (name, p["name"])
                continue
            getter = getattr(mapper, "Get" + setter_name(p["name"])[3:], None)
            if getter is not None and p["name"] != "region_of_interest":
                value = getter()
                flat = tuple(x for row in value for x in row) if p["shape"] else value
                expected = tuple(flat) if isinstance(flat, (tuple, list)) else flat
                assert p["default"] == expected, (name, p["name"])
    weight = {p["name"]: p for p in table["demip"]["parameters"]}["depth_weight"]
    assert weight["range"] == (0.0, 1.0) and weight["type"] == "double"
    mode = {p["name"]: p for p in table["demip"]["parameters"]}["depth_mode"]
    assert mode["choices"] == list(mipcast.mappers.demip.DEPTH_MODES)


def test_generated_xml_has_a_property_per_parameter_hidden_for_other_methods():
    methods = mipcast_representation.plugin_methods()
    document = xml.dom.minidom.parseString(mipcast_representation.server_manager_xml(methods))
    properties = {node.getAttribute("name"): node for tag in
                  ("DoubleVectorProperty", "IntVectorProperty", "StringVectorProperty")
                  for node in document.getElementsByTagName(tag)}
    method_list = [s.getAttribute("value") for s in
                   properties["MipcastMethod"].getElementsByTagName("String")]
    assert method_list == [m["name"] for m in methods]
    setters = mipcast_representation.cxx_setters(methods)
    for method in methods:
        for p in method["parameters"]:
            node = properties[mipcast_representation.property_name(method["name"], p["name"])]
            assert f'{node.getAttribute("command")}(' in setters
            assert int(node.getAttribute("number_of_elements")) == p["size"]
            decorators = [d.getAttribute("value") for d in
                          node.getElementsByTagName("PropertyWidgetDecorator")
                          if d.getAttribute("property") == "MipcastMethod"]
            assert decorators == [method["name"]]


# -- building --------------------------------------------------------------------------------------
def _plugin_file():
    found = sorted(BUILD.glob("lib/paraview-*/plugins/MipcastRepresentation/MipcastRepresentation.so"))
    return found[0] if found else None


@pytest.fixture(scope="module")
def plugin():
    missing = [t for t in ("pvpython", "Xvfb", "cmake", "c++") if shutil.which(t) is None]
    if missing:
        pytest.skip(f"{', '.join(missing)} not on PATH: the representation needs Debian's paraview, "
                    "paraview-dev, cmake, g++ and xvfb")
    BUILD.parent.mkdir(parents=True, exist_ok=True)
    with open(BUILD.parent / "paraview-representation.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # one build at a time: parallel test workers share the folder
        built = subprocess.run(["sh", str(GLUE_DIR / "build.sh"), str(BUILD)], capture_output=True,
                               text=True, timeout=900, env=pvpython_env())  # the panel from the installed mipcast
    if built.returncode != 0:
        log = Path(str(BUILD) + ".configure.log")
        text = log.read_text() if log.exists() else ""
        if "Could not find a package configuration file provided by \"ParaView\"" in text:
            pytest.skip("ParaView's CMake package is missing: apt-get install paraview-dev")
        pytest.fail(f"build.sh failed:\n{built.stdout[-3000:]}\n{built.stderr[-3000:]}\n{text[-3000:]}")
    path = _plugin_file()
    assert path is not None, built.stdout
    return path


def test_built_panel_is_the_generated_one(plugin):
    built = BUILD / "Plugin" / "MipcastRepresentations" / "MipcastRepresentation.xml"
    assert built.read_text() == mipcast_representation.server_manager_xml()


def _env():
    env = pvpython_env()  # the installed mipcast only
    env["PYTHONPATH"] += f"{os.pathsep}{ROOT / 'tests'}"
    return env


def _report(completed, server_log=""):
    lines = [line for line in completed.stdout.splitlines() if line.startswith("{")]
    assert completed.returncode == 0 and lines, (
        f"exit {completed.returncode}\nstdout:\n{completed.stdout[-3000:]}\nstderr:\n{completed.stderr[-5000:]}"
        f"\nserver log:\n{server_log[-3000:]}")
    return json.loads(lines[-1])


@pytest.fixture(scope="module")
def builtin(plugin, tmp_path_factory):
    pngs = tmp_path_factory.mktemp("pvrep-builtin")
    completed = run_under_xvfb(["pvpython", str(CHECK), "--plugin", str(plugin), "--png-dir", str(pngs)],
                               cwd=ROOT, env=_env(), timeout=300)
    return _report(completed)


def _free_port():
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        return probe.getsockname()[1]


@pytest.fixture(scope="module")
def client_server(plugin, tmp_path_factory):
    """pvserver on localhost (started and stopped here) and a pvpython client, one X server."""
    pngs = tmp_path_factory.mktemp("pvrep-cs")
    port = _free_port()
    script = (
        f'pvserver --server-port={port} > "{pngs}/server.log" 2>&1 & server=$!\n'
        f'for i in $(seq 100); do grep -q Accepting "{pngs}/server.log" && break; sleep 0.2; done\n'
        f'pvpython "{CHECK}" --plugin "{plugin}" --png-dir "{pngs}" --server localhost:{port} '
        f'--parts methods --methods {",".join(PARITY)}\n'
        # (no `wait` on the server: now and then pvserver hangs on SIGTERM after its client has gone, and the
        # script waited until the 300 s timeout, with the client's results already printed; as
        # tests/test_paraview_refinement.py does)
        'status=$?\nkill $server 2>/dev/null; sleep 1; kill -9 $server 2>/dev/null\nexit $status\n')
    for _ in range(2):  # a display now and then is not ready yet
        completed = run_under_xvfb(["sh", "-c", script], cwd=ROOT, env=_env(), timeout=300)
        log = (pngs / "server.log").read_text() if (pngs / "server.log").exists() else ""
        if completed.returncode == 0 or "bad X server connection" not in log:
            break
    report = _report(completed, "\n".join(line for line in log.splitlines() if "Broken pipe" not in line))
    report["server_log"] = log
    return report


def _matches(result, projection="mip", lit=0.25):
    assert result["within_1_share"] >= MATCH, result
    # a black picture would match a black reference; the vessel phantom's MinIP (over the data
    # range) and average (over its default window) light less of the box than its MIP, and so
    # does a slab seen edge-on
    assert result["lit_share"] > (lit if projection == "mip" else 0.05), result
    assert abs(result["lit_share"] - result["ref_lit_share"]) < 0.002, result


def _projection(method):
    import mipcast

    return mipcast.METHODS[method].projection


# -- pvpython, builtin session ------------------------------------------------------------------
def test_every_method_is_in_the_method_list(builtin):
    assert builtin["methods"]["_listed"] == builtin["methods"]["_methods"]


@pytest.mark.parametrize("method", PARITY)
def test_representation_matches_offscreen_render(builtin, method):
    _matches(builtin["methods"][method], _projection(method))


#: Methods not at parity in a tiled screenshot, and why (measured, see plugin/README.md).
TILED_GAPS = {
    "cpu": "VTK's CPU ray caster leaves dark seams between the tiles",
}
# (``foveated`` was here at 99.6 %: each coarse level, VTK's reduced-resolution render of one tile,
# was magnified within that tile, clamped at the seams; it is now drawn one coarse ray beyond the
# tile's inner edges and cropped, mipcast.mappers.foveated_tiles, tests/test_foveated_tiles.py)


@pytest.mark.parametrize("method", PARITY)
def test_tiled_screenshot_matches_offscreen_render(builtin, method):
    """SaveScreenshot bigger than the view: ParaView renders 2 x 2 tiles."""
    if method in TILED_GAPS:
        pytest.xfail(TILED_GAPS[method])
    _matches(builtin["tiled"][method], _projection(method))



@pytest.mark.parametrize("method", ["analytic_minip", "analytic"])
def test_narrow_range_matches_offscreen_and_exact_reference(builtin, method):
    """A colour range a few table texels wide inside the data range: the exact methods' display
    shortcuts start at one of its ends (before the fix ParaView's MinIP was 42 % off its offscreen
    render, up to 42 levels; both MIPs 37 % off the float64 reference, up to 6)."""
    result = builtin["narrow"][method]
    _matches(result, _projection(method), lit=0.04)
    for against in ("paraview_vs_exact", "offscreen_vs_exact"):
        # (what stays: VTK's table interpolation of answers inside the range, silhouette pixels)
        assert result[against]["within_1_share"] >= 0.99, (against, result)


@pytest.mark.parametrize("part", ["methods", "tiled"])
def test_no_opengl_error_across_method_switches(builtin, part):
    """Both parts draw ``cpu`` first, then every other method: VTK's OpenGL error reports in the
    output window (before the fix 12 and 36, the packed exact projections' gradient-opacity samplers
    after VTK's CPU ray caster had given the shared property a gradient-opacity function)."""
    assert builtin[part]["_opengl_errors"] == [], builtin[part]["_opengl_errors"][:3]


@pytest.mark.parametrize("camera", ["oblique", "head_on"])
@pytest.mark.parametrize("method", PARITY)
def test_an_image_with_a_direction_matrix_matches_offscreen_render(builtin, camera, method):
    """An oblique acquisition (a .vti whose direction matrix turns the volume 0.65 rad about z), at an
    oblique camera and head-on (its side faces edge-on): the representation draws what the offscreen view
    draws (which tests/test_edge_on_faces.py holds to the float64 reference)."""
    report = builtin["oblique"]
    assert abs(report["_direction"][1] + 0.605) < 1e-3  # ParaView's reader gave the image its direction matrix
    assert report[camera]["_opengl_errors"] == [], report[camera]["_opengl_errors"][:3]
    _matches(report[camera][method], _projection(method), lit=0.1)  # (the turned box covers 14-27 %)


def test_each_method_draws_with_its_mipcast_mapper(builtin):
    mappers = {m: r["mapper"] for m, r in builtin["methods"].items() if not m.startswith("_")}
    assert mappers["mip"] == "MIPVolumeMapper"
    assert mappers["analytic"] == "AnalyticMIPVolumeMapper"
    assert mappers["demip"] == "DEMIPVolumeMapper"
    assert mappers["foveated"] == "FoveatedVolumeMapper"


def test_parameter_change_changes_the_picture_without_a_new_shader(builtin):
    result = builtin["parameter"]
    assert result["changed_share"] > 0.1, result
    assert result["programs_after"] == result["programs_before"] == 1, result
    _matches(result["parity"])


@pytest.mark.parametrize("method", ("mip", "analytic"))
def test_slab_centre_and_normal_from_the_panel_move_the_slab(builtin, method):
    """Thickness with centre/normal following the camera, then a fixed centre, then a fixed
    normal: each picture moves and equals the offscreen view with the same slab."""
    result = builtin["slab"][method]
    for step in ("camera", "centre", "normal"):
        _matches(result[step], lit=0.15)
        assert result[step]["changed_share"] > 0.05, (step, result)
    assert result["follows_again"]["within_1_share"] == 1.0, result


def test_foveated_gaze_from_the_panel_and_the_mouse(builtin):
    """The panel's gaze point and region of interest move the fovea (each equal to the offscreen
    view with that gaze); in a builtin session a mouse move over the view takes the gaze
    (foveated_follow_mouse, default on), and switching that off goes back to the gaze point."""
    result = builtin["gaze"]
    for step in ("point", "region"):
        _matches(result[step])
        assert result[step]["changed_share"] > 0.05, (step, result)
    assert result["region_cleared"]["within_1_share"] == 1.0, result
    assert result["interactor"], result
    _matches(result["mouse"])
    assert result["mouse"]["changed_share"] > 0.05, result
    assert result["mouse_off"]["within_1_share"] == 1.0, result


def test_eye_toggle_hides_and_shows(builtin):
    result = builtin["eye"]
    assert result["shown_lit"] > 0.25 and result["hidden_lit"] == 0.0, result
    assert result["again_vs_shown"]["within_1_share"] == 1.0, result


def test_traced_property_change_replays(builtin):
    result = builtin["trace"]
    assert any("MipcastMethod = 'demip'" in line for line in result["lines"]), result
    assert any("demip_depth_weight = 0.45" in line for line in result["lines"]), result
    assert result["reset_changed"] > 0.1, result
    assert result["replayed_vs_traced"]["within_1_share"] == 1.0, result


def test_state_file_restores_method_and_parameters(builtin):
    result = builtin["state"]
    assert result["representation"] == "'mipcast'" and result["method"] == "'demip'", result
    assert result["depth_weight"] == 0.5, result
    assert result["saved_lit"] > 0.25, result
    assert result["loaded_vs_saved"]["within_1_share"] >= MATCH, result


@pytest.mark.parametrize("method", PARITY)
def test_multi_component_array_follows_the_colouring_choice(builtin, method):
    """Colour by Magnitude, then by X: each picture equals the offscreen view drawing that component
    (before: always the magnitude, whatever the choice), and the two differ."""
    result = builtin["arrays"]["vector"][method]
    for choice in ("Magnitude", "X"):
        _matches(result[choice], _projection(method))
    assert result["changed_share"] > 0.1, result


@pytest.mark.parametrize("method", ["mip", "analytic", "stock", "cpu"])
def test_cell_array_is_drawn_at_the_cell_centres(builtin, method):
    """A cell array (next to a point array of the same name, which is not drawn) equals the offscreen
    view of the cell data, drawn on the image of the cell centres (before: refused, nothing drawn)."""
    result = builtin["arrays"]["cells"][method]
    _matches(result)
    assert result["changed_from_points"] > 0.05, result


@pytest.mark.parametrize("case, words", [
    ("cell_data_one_slice", "at least 2 cells"),
    ("nan_voxels", "NaN"),
    ("out_of_range", "must be in [0, 1]"),
    ("unknown_method", "unknown method"),
])
def test_bad_input_gives_a_message_and_a_defined_picture(builtin, case, words):
    result = builtin["bad"][case]
    assert any(words in line for line in result["message"]), result
    if case in ("cell_data_one_slice", "nan_voxels"):
        assert result["lit"] == 0.0, result  # refused: nothing drawn
    else:
        assert result["lit"] > 0.25, result  # the previous value / method keeps drawing


def test_frame_time_close_to_offscreen_view(builtin):
    """Whole frame (StillRender) and the renderer's own time against the offscreen view, in wall
    and in process CPU time (llvmpipe's threads included; the waiting of a loaded machine not).

    On a 2-core llvmpipe machine the figures swing by tens of percent between
    runs (see plugin/README.md), so the ratios are only enforced with
    MIPCAST_BENCH=1 (on a quiet machine or a GPU); otherwise they are reported.
    """
    result = builtin["bench"]
    print(json.dumps(result))
    assert result["paraview_s"] > 0 and result["offscreen_s"] > 0, result
    first = result["methods"][result["method"]]
    assert first["paraview_cpu_s"] > 0 and first["offscreen_cpu_s"] > 0, result
    limit = float(os.environ.get("MIPCAST_PVREP_RATIO", "1.1"))
    if not os.environ.get("MIPCAST_BENCH"):
        pytest.skip(f"measured, not enforced (set MIPCAST_BENCH=1): frame ratio {result['ratio']:.2f}, "
                    f"CPU time {result['cpu_ratio']:.2f}, renderer {result['renderer_ratio']:.2f} (limit {limit})")
    assert result["ratio"] <= limit, result
    assert result["cpu_ratio"] <= limit, result


# -- client-server -----------------------------------------------------------------------------------
@pytest.mark.parametrize("method", PARITY)
def test_client_server_picture_equals_builtin(client_server, builtin, method):
    assert client_server["session"] == "client-server"
    assert "Client connected" in client_server["server_log"]
    _matches(client_server["methods"][method], _projection(method))
    import numpy as np
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader

    def pixels(directory):
        reader = vtkPNGReader()
        reader.SetFileName(str(Path(directory) / f"rep_{method}.png"))
        reader.Update()
        return vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars()).astype(int)

    diff = np.abs(pixels(client_server["png_dir"]) - pixels(builtin["png_dir"])).max(axis=-1)
    assert np.mean(diff <= 1) >= MATCH


def test_client_server_logs_no_opengl_error(client_server):
    """The server drew every method, ``cpu`` first (paraview_representation_check.methods_part)."""
    errors = [line for line in client_server["server_log"].splitlines()
              if "OpenGL error" in line or "glGetError" in line]
    assert errors == [], errors[:3]


# -- the GUI -------------------------------------------------------------------------------------------
def test_paraview_gui_shows_the_representation(plugin, tmp_path):
    if shutil.which("paraview") is None:
        pytest.skip("the paraview GUI binary is not installed")
    out = tmp_path / "gui"
    env = dict(_env(), MIPCAST_GUI_OUT=str(out), MIPCAST_PLUGIN=str(plugin))
    completed = run_under_xvfb(["paraview", f"--script={GUI}"], cwd=ROOT, env=env, timeout=240)
    report_file = out / "report.json"
    assert report_file.exists(), f"{completed.returncode}\n{completed.stdout[-3000:]}\n{completed.stderr[-3000:]}"
    report = json.loads(report_file.read_text())
    assert report["representation"] == "mipcast", report
    assert report["mipcast_lit"] > 0.05, report  # the volume covers about a tenth of the view
    assert report["differs_from_default"] > 0.05, report
    grab = out / "window.xwd"
    if grab.exists():  # the whole screen, main window and Properties panel (needs xwd)
        import numpy as np
        from vtk_png import write_png
        from xwd import read_xwd

        screen = read_xwd(grab)
        write_png(str(out / "window.png"), screen)
        assert screen.std() > 20 and len(np.unique(screen.reshape(-1, 3), axis=0)) > 100
