"""The mipcast representation refines the foveated picture from a timer and follows the mouse in client-server.

``tests/paraview_refinement_check.py`` runs in pvpython under xvfb, builtin
and as the client of a ``pvserver`` started here, and
``tests/paraview_refinement_gui.py`` runs in the ParaView GUI
(``paraview --script``): timer-driven frames converge to the full-quality
picture (bit for bit, sampled MIP) within ``refinement_frames`` still
frames, no timer is left once converged, a camera change drops back to the
foveated frame, no refining frame is rendered while a mouse button is held,
``refine(view)`` does the same for scripts, and the mouse
moves the fovea (client-server: through the gaze point property the client
writes; the GUI: the real X pointer moved by xdotool, or a synthetic move without it).  After
camera, opacity and data changes the timer asks for exactly the frames the
(server's) mapper still needs, read from the representation's
information-only properties before and after, and none after a change the
mapper does not draw with or with progressive refinement off.
"""
import json
import shutil

import pytest
from test_paraview_representation import ROOT, _env, _free_port, _report, plugin  # noqa: F401  (the fixture)
from xvfb import run_under_xvfb

CHECK = ROOT / "tests" / "paraview_refinement_check.py"
GUI = ROOT / "tests" / "paraview_refinement_gui.py"
FRAMES = 4  # foveated_refinement_frames in both scripts
MATCH = 0.999


def _converged(phase, remote=False):
    assert phase["bit_equal_full"] and phase["vs_full"]["max_diff"] == 0, phase
    assert phase["vs_full"]["lit_share"] > 0.25, phase  # not a black picture
    assert not phase["timer_left"], phase
    assert phase["frames_asked"] >= 1, phase  # the timer rendered some of the refining frames itself
    if not remote:  # the frame after the change is step 0, each still frame one step more
        assert phase["steps"][0] == 0 and phase["frames_to_full"] == FRAMES, phase
        # drawn again once converged (the screenshot), the kept picture: no ray cast (refine_keep; a
        # per-frame change of ParaView's renderer once kept nothing)
        assert phase["converged_rays"] == 0, phase
        assert phase["steps"][:FRAMES + 1] == list(range(FRAMES + 1)), phase
    assert phase["first_vs_full"]["within_1_share"] < 0.95, phase  # the foveated frame is not full quality


def _exact(state):
    """After each change the timer asked for exactly the frames the (server's) mapper still needed,
    read from the representation's information properties: none once it had converged."""
    for name in ("camera", "opacity", "data"):  # changes the mapper refines after
        phase = state[name]
        assert phase["before"][:2] == [1, 0] and phase["after"][:2] == [0, FRAMES], (name, phase)
        assert phase["asked"] == FRAMES - phase["untimed"] and phase["asked"] >= 1, (name, phase)
        assert phase["after"][2] - phase["before"][2] == phase["loop_frames"], (name, phase)  # all drew
    other = state["other_method"]  # a property foveated does not draw with: converged, no frame asked
    assert other["before"][:2] == [0, FRAMES] and other["asked"] == 0, other
    assert state["progressive_off"]["asked"] == 0 and state["progressive_off"]["after"][0] == 0, state


def test_timer_refines_to_full_quality_in_pvpython(plugin):
    completed = run_under_xvfb(["pvpython", str(CHECK), "--plugin", str(plugin)], cwd=ROOT, env=_env(),
                               timeout=240)
    report = _report(completed)["timer"]
    _converged(report["still"])
    _converged(report["camera_change"])  # a camera turn drops back to the foveated frame, then refines
    assert report["idle_frames_asked"] == 0, report  # converged: the timer asks for nothing
    assert report["vs_offscreen"]["within_1_share"] >= MATCH, report
    call = report["refine_call"]
    assert call["frames"] == FRAMES and call["bit_equal_full"], call
    assert call["steps"][:FRAMES + 1] == list(range(FRAMES + 1)), call
    drag = report["drag"]  # a button held: no refining frame; released: refines to full quality again
    assert drag["steps_while_held"][0] == 0 and drag["asked_while_held"] == 0, drag
    assert drag["steps"][-1] == FRAMES and drag["bit_equal_full"] and not drag["timer_left"], drag
    _exact(report["server_state"])


def test_client_mouse_moves_the_server_fovea_and_the_timer_refines(plugin, tmp_path):
    port = _free_port()
    log = tmp_path / "server.log"
    script = (
        f'pvserver --server-port={port} > "{log}" 2>&1 & server=$!\n'
        f'for i in $(seq 100); do grep -q Accepting "{log}" && break; sleep 0.2; done\n'
        f'pvpython "{CHECK}" --plugin "{plugin}" --png-dir "{tmp_path}" --server localhost:{port}\n'
        'status=$?\nkill $server 2>/dev/null; sleep 1; kill -9 $server 2>/dev/null\nexit $status\n')
    completed = run_under_xvfb(["sh", "-c", script], cwd=ROOT, env=_env(), timeout=240)
    report = _report(completed, log.read_text() if log.exists() else "")
    assert report["session"] == "client-server"
    for phase in ("still", "camera_change"):
        _converged(report["timer"][phase], remote=True)
    assert report["timer"]["idle_frames_asked"] == 0, report["timer"]  # no change seen: no frames asked
    assert report["timer"]["refine_call"]["bit_equal_full"], report["timer"]["refine_call"]
    _exact(report["timer"]["server_state"])
    camera = report["timer"]["server_state"]["camera"]  # one read per timer tick: the frames asked, then "converged"
    assert camera["pulls"] == camera["asked"] + 1, camera
    for phase in ("still", "camera_change"):  # Render + SaveScreenshot were steps 0 and 1: 2 frames
        assert report["timer"][phase]["frames_asked"] == FRAMES - 2, report["timer"][phase]
    assert report["timer"]["refine_call"]["frames"] == FRAMES, report["timer"]["refine_call"]
    mouse = report["mouse"]
    assert mouse["interactor"] and mouse["moves"] == 3, mouse
    assert mouse["property"] == pytest.approx(mouse["expected"]), mouse  # the client wrote the gaze point
    assert mouse["vs_ref"]["within_1_share"] >= MATCH and mouse["vs_ref"]["lit_share"] > 0.25, mouse
    assert mouse["changed_share"] > 0.05, mouse  # the fovea moved


def test_paraview_gui_refines_by_itself_and_follows_the_mouse(plugin, tmp_path):
    if shutil.which("paraview") is None:
        pytest.skip("the paraview GUI binary is not installed")
    out = tmp_path / "gui"
    env = dict(_env(), MIPCAST_GUI_OUT=str(out), MIPCAST_PLUGIN=str(plugin))
    completed = run_under_xvfb(["paraview", "--dr", f"--script={GUI}"], cwd=ROOT, env=env, timeout=150)
    report_file = out / "report.json"
    if not report_file.exists() and "could not connect to display" in completed.stderr.lower():
        pytest.skip("the ParaView GUI cannot start here (no X display)")
    assert report_file.exists(), f"{completed.returncode}\n{completed.stdout[-3000:]}\n{completed.stderr[-3000:]}"
    report = json.loads(report_file.read_text())
    assert report["end"] == "done", report
    still, camera = report["phases"]
    for phase in (still, camera):
        assert phase["step"] == FRAMES and phase["frames_to_full"] == FRAMES, phase
        assert phase["bit_equal_full"] and phase["vs_full"]["lit_share"] > 0.2, phase
    assert camera["asked"] >= 1, camera  # nothing but the timer renders once the script has returned
    assert report["after_camera_step"] == 0 and report["after_camera_needs"], report
    assert report["idle"]["frames"] == 0 and not report["idle"]["timer_left"], report["idle"]  # no idle cost
    mouse = report["mouse"]
    if shutil.which("xdotool"):  # the X pointer moved (no button): Qt's motion event reached the fovea
        assert mouse["pointer"] == "xdotool", (mouse, report.get("pointer"))
    assert mouse["source"] == "mouse" and mouse["vs_ref"]["within_1_share"] >= MATCH, mouse
    assert mouse["vs_ref"]["lit_share"] > 0.2 and mouse["changed_share"] > 0.05, mouse


def test_paraview_gui_client_refines_and_moves_the_server_fovea(plugin, tmp_path):
    """The GUI as the client of a pvserver (``paraview --url=cs://...``): the client's timer asks
    for the refining frames, its mouse writes the gaze point the server draws with."""
    if shutil.which("paraview") is None:
        pytest.skip("the paraview GUI binary is not installed")
    out, log, port = tmp_path / "gui", tmp_path / "server.log", _free_port()
    script = (
        f'pvserver --server-port={port} > "{log}" 2>&1 & server=$!\n'
        f'for i in $(seq 100); do grep -q Accepting "{log}" && break; sleep 0.2; done\n'
        f'paraview --dr --url=cs://localhost:{port} "--script={GUI}"\n'
        'status=$?\nkill $server 2>/dev/null; sleep 1; kill -9 $server 2>/dev/null\nexit $status\n')
    env = dict(_env(), MIPCAST_GUI_OUT=str(out), MIPCAST_PLUGIN=str(plugin), MIPCAST_GUI_REMOTE="1")
    completed = run_under_xvfb(["sh", "-c", script], cwd=ROOT, env=env, timeout=150)
    report_file = out / "report.json"
    assert report_file.exists(), (f"{completed.returncode}\n{completed.stdout[-3000:]}\n{completed.stderr[-3000:]}"
                                  f"\n{log.read_text()[-2000:] if log.exists() else ''}")
    report = json.loads(report_file.read_text())
    assert report["end"] == "done" and report["remote"], report
    for phase in report["phases"]:
        assert phase["asked"] >= 1 and phase["bit_equal_full"] and phase["vs_full"]["lit_share"] > 0.2, phase
    camera = report["phases"][1]  # the server's frames after the camera turn: exactly those it needed
    before, after = camera["server_before"], camera["server_after"]
    assert before[:2] == [1, 0] and after[:2] == [0, FRAMES], camera
    assert camera["asked"] <= FRAMES and after[2] - before[2] == FRAMES, camera
    assert report["idle"]["frames"] == 0 and not report["idle"]["timer_left"], report["idle"]
    mouse = report["mouse"]
    if shutil.which("xdotool"):
        assert mouse["pointer"] == "xdotool", (mouse, report.get("pointer"))
    assert mouse["property"] == pytest.approx(mouse["gaze"]), mouse  # written by the client
    assert mouse["vs_ref"]["within_1_share"] >= MATCH and mouse["changed_share"] > 0.05, mouse
