"""The ParaView GUI refines the foveated picture by itself and follows the mouse: ``paraview --script=<this>``.

Environment: ``MIPCAST_PLUGIN`` (the built MipcastRepresentation.so),
``MIPCAST_GUI_OUT`` (a folder for the pictures and ``report.json``),
PYTHONPATH with the installed mipcast and tests/.  Shows the 48^3 vessel
phantom with the mipcast representation, method ``foveated`` with progressive
refinement on, renders once and returns to the GUI's event loop: from then on
only the representation's timers render.  A poll (a repeating timer on the
view's interactor, every :data:`POLL_MS`) walks through the phases: wait
until the picture has converged (no refining frame asked for, no timer
pending), compare it with the same view with foveation off (bit for bit),
turn the camera (the next frame drops back to the foveated one) and wait
again, count the frames of a second with nothing changing, then switch progressive off, move the real X pointer onto the view with
``xdotool`` (a synthetic ``MouseMoveEvent`` on the interactor without it) and
compare the picture with mipcast's offscreen view gazing at the pixel the
interactor reports.  Writes ``report.json`` and ends this ParaView
(``os._exit``); a watchdog ends it after :data:`WATCHDOG_S` with what it has.
"""
import inspect
import json
import os
import time

if not hasattr(inspect, "getargspec"):  # ParaView 5.11's plugin loader on Python 3.11
    inspect.getargspec = inspect.getfullargspec

OUT = os.environ.get("MIPCAST_GUI_OUT", "")
#: "1": this GUI is the client of a pvserver (started with --url=cs://HOST:PORT); the mappers are there.
REMOTE = os.environ.get("MIPCAST_GUI_REMOTE") == "1"
FRAMES = 4
GAZE = (0.3, 0.6)
POLL_MS = 100
IDLE_S = 1.0  # seconds watched for frames once converged
WATCHDOG_S = 60.0
MOUSE = (0.62, 0.45)  # where the mouse moves, as a share of the view's width and height (on the volume)
#: Move the real X pointer (xdotool, when installed): Qt turns it into the interactor's MouseMoveEvent.
POINTER = os.environ.get("MIPCAST_GUI_POINTER", "xdotool") == "xdotool" and bool(__import__("shutil").which("xdotool"))
POINTER_WAIT_S = 5.0


def main():
    import numpy as np
    from paraview.simple import (ColorBy, GetActiveViewOrCreate, LoadPlugin, OpenDataFile, Render,
                                 Show)

    from mipcast.data_fixtures import make_fixture
    from paraview_representation_check import read_vti, reference, screenshot, write_vti
    from paraview_view_check import changed_share, compare

    os.makedirs(OUT, exist_ok=True)
    if REMOTE:
        LoadPlugin(os.environ["MIPCAST_PLUGIN"], remote=True, ns=globals())
    LoadPlugin(os.environ["MIPCAST_PLUGIN"], remote=False, ns=globals())
    path = os.path.join(OUT, "vessels.vti")
    write_vti(make_fixture("vessels", size=48), path)
    image = read_vti(path)
    reader = OpenDataFile(path)
    view = GetActiveViewOrCreate("RenderView")
    view.OrientationAxesVisibility = 0
    view.UseFXAA = 0
    view.UseColorPaletteForBackground = 0  # black, as mipcast's offscreen view
    view.BackgroundColorMode = "Single Color"
    view.Background = [0.0, 0.0, 0.0]
    view.UseToneMapping = 0
    display = Show(reader, view)
    display.SetRepresentationType("mipcast")
    ColorBy(display, ("POINTS", "scalars"))
    display.RescaleTransferFunctionToDataRange(True, False)
    display.MipcastMethod = "foveated"
    display.foveated_gaze_point = list(GAZE)
    display.foveated_refinement_frames = FRAMES
    display.foveated_progressive = 1
    view.ResetCamera(False)
    camera = view.GetActiveCamera()
    camera.Azimuth(35.0)
    camera.Elevation(25.0)
    camera.OrthogonalizeViewUp()
    view.ResetCamera(False)

    import mipcast_representation
    import mipcast_representation_live as live

    interactor = view.GetInteractor()
    report = {"interactor": type(interactor).__name__ if interactor is not None else None, "phases": [],
              "remote": REMOTE}
    frames = []  # (phase, step, asked by the refiner's timer, ms)
    clock = {}

    def mapper():
        found = [e.mapper for e in mipcast_representation._REGISTRY.values()
                 if e.mapper is not None and e.mapper_method == "foveated"]
        return found[0] if found else None

    def server_state():
        """The (server's) refinement state: the representation's information properties."""
        renderer = view.GetRenderer()
        keys = [k for k, e in mipcast_representation._REGISTRY.items()
                if e.method == "foveated" and e.renderer.Get() is renderer]
        return list(live.server_refinement(keys[0])) if keys else None

    def shot(name):
        return screenshot(view, os.path.join(OUT, name + ".png"), size=tuple(view.ViewSize))

    def finish(reason):
        report["end"] = reason
        report["frames"] = frames
        report["view_size"] = list(view.ViewSize)
        with open(os.path.join(OUT, "report.json"), "w") as handle:
            json.dump(report, handle)
        os._exit(0)

    if interactor is None:
        finish("no interactor")
    refiner = live.refiner(interactor)
    window = interactor.GetRenderWindow()
    state = {"phase": "still", "t0": time.perf_counter()}

    def frame_start(caller, event):
        clock["t"] = time.perf_counter()

    def frame_end(caller, event):
        m = mapper()
        frames.append((state["phase"], m.GetRefinementStep() if m is not None else None, refiner.requested,
                       round(1000.0 * (time.perf_counter() - clock.get("t", time.perf_counter())), 2)))

    window.AddObserver("StartEvent", frame_start)
    window.AddObserver("EndEvent", frame_end, 100.0)  # before the refiner's (it resets 'requested')

    def converged():
        if REMOTE:  # the mapper is on the server: the client's frame count
            asked = [f for f in frames if f[0] == state["phase"] and f[2]]
            return bool(asked) and refiner.timer is None and not refiner.needs_refinement()
        m = mapper()
        return m is not None and not m.NeedsRefinement() and refiner.timer is None

    def poll(caller, event):
        try:
            step()
        except Exception as error:  # into the report, not a hung GUI
            import traceback

            report["error"] = f"{type(error).__name__}: {error}\n{traceback.format_exc()}"
            finish("error")

    def step():
        if time.perf_counter() - state["t0"] > WATCHDOG_S:
            finish("watchdog")
        phase = state["phase"]
        if phase in ("still", "camera") and converged():
            m = mapper()
            converged_step = m.GetRefinementStep() if m is not None else None
            server_after = server_state()  # before the screenshots below render again
            pixels = shot(f"converged_{phase}")
            display.foveated_foveation = 0
            full = shot(f"full_{phase}")
            display.foveated_foveation = 1
            Render(view)
            mine = [f for f in frames if f[0] == phase]
            report["phases"].append(dict(
                phase=phase, steps=[f[1] for f in mine], asked=sum(bool(f[2]) for f in mine),
                refining_ms=[f[3] for f in mine if f[2]], step=converged_step,
                frames_to_full=[f[1] for f in mine].index(FRAMES) if FRAMES in [f[1] for f in mine] else None,
                server_before=state.get("server_before"), server_after=server_after,
                seconds=time.perf_counter() - state["t0"], bit_equal_full=bool(np.array_equal(pixels, full)),
                vs_full=compare(pixels, full)))
            if phase == "still":
                state["phase"] = "camera"
                camera.Azimuth(12.0)
                Render(view)  # the interaction's frame: back to the foveated frame
                state["server_before"] = server_state()
                report["after_camera_step"] = m.GetRefinementStep() if m is not None else None
                report["after_camera_needs"] = bool(m.NeedsRefinement() if m is not None
                                                    else refiner.needs_refinement())
            else:
                state["phase"] = "idle_wait"  # the foveation switch above was a change: converge again
        elif phase == "idle_wait" and converged():
            state.update(phase="idle", idle_t0=time.perf_counter(), idle_frames=len(frames),
                         idle_asked=refiner.frames)
        elif phase == "idle" and time.perf_counter() - state["idle_t0"] > IDLE_S:
            report["idle"] = dict(seconds=IDLE_S, frames=len(frames) - state["idle_frames"],
                                  asked=refiner.frames - state["idle_asked"], timer_left=refiner.timer is not None)
            state["phase"] = "mouse"
        elif phase == "mouse":
            display.foveated_progressive = 0
            state["before"] = shot("mouse_before")
            if POINTER and move_pointer():
                state.update(phase="pointer", pointer_t0=time.perf_counter(), moves_seen=moves[0])
            else:  # no xdotool: a synthetic event at a chosen pixel
                width, height = view.ViewSize
                x, y = int(MOUSE[0] * width), int(MOUSE[1] * height)  # display pixels, origin bottom left
                interactor.SetEventPosition(x, y)
                t0 = time.perf_counter()
                interactor.InvokeEvent("MouseMoveEvent")  # the mapper's observer renders the view
                report["mouse_render_ms"] = 1000.0 * (time.perf_counter() - t0)
                mouse_report("synthetic", (x, y))
                finish("done")
        elif phase == "pointer":  # the X server's motion event reaches the interactor through Qt
            if moves[0] > state["moves_seen"] and frames and frames[-1][0] == "pointer":
                report["mouse_render_ms"] = 1000.0 * (time.perf_counter() - state["pointer_t0"])
                mouse_report("xdotool", tuple(interactor.GetEventPosition()))
                finish("done")
            elif time.perf_counter() - state["pointer_t0"] > POINTER_WAIT_S:
                report["pointer"] = dict(moves=moves[0], seen=state["moves_seen"], targets=state.get("targets"))
                mouse_report("xdotool (no event reached the view)", None)
                finish("done")

    moves = [0]

    def count_move(caller, event):
        moves[0] += 1

    interactor.AddObserver("MouseMoveEvent", count_move, 100.0)

    def move_pointer():
        """Move the X pointer onto the render view with xdotool (real X motion events); False if it cannot."""
        import subprocess

        found = subprocess.run(["xdotool", "search", "--onlyvisible", "--name", "ParaView"], capture_output=True,
                               text=True, timeout=10).stdout.split()
        for window in found:
            shell = subprocess.run(["xdotool", "getwindowgeometry", "--shell", window], capture_output=True,
                                   text=True, timeout=10).stdout
            geometry = dict(line.split("=", 1) for line in shell.split() if "=" in line)
            if int(geometry.get("WIDTH", 0)) < 300:
                continue
            # the render view fills the main window's right part (the docks are on the left)
            x = int(geometry["X"]) + int(0.62 * int(geometry["WIDTH"]))
            y = int(geometry["Y"]) + int(0.55 * int(geometry["HEIGHT"]))
            state["targets"] = [window, x, y, geometry]
            subprocess.run(["xdotool", "mousemove", "--sync", str(x - 3), str(y - 3)], timeout=10)
            subprocess.run(["xdotool", "mousemove", "--sync", str(x), str(y)], timeout=10)
            return True
        return False

    def mouse_report(pointer, position):
        width, height = view.ViewSize
        report["mouse_position"] = list(position) if position is not None else None
        if position is None:
            report["mouse"] = dict(pointer=pointer, source=mapper().GetGazeSource() if mapper() is not None else None)
            return
        x, y = position
        moved = shot("mouse_moved")
        gaze = ((x + 0.5) / width, (y + 0.5) / height)
        ref, _ = reference(image, "foveated", view, size=(width, height), gaze_point=gaze)
        report["mouse"] = dict(vs_ref=compare(moved, ref), changed_share=changed_share(state["before"], moved),
                               gaze=list(gaze), property=list(display.foveated_gaze_point), pointer=pointer,
                               source=mapper().GetGazeSource() if mapper() is not None else None)

    interactor.AddObserver("TimerEvent", poll, -100.0)
    interactor.CreateRepeatingTimer(POLL_MS)
    Render(view)  # the first frame; the rest is the representation's timers


if OUT:  # run by paraview --script with the test's environment
    try:
        main()
    except Exception as error:  # a report, not a GUI left waiting
        import traceback

        os.makedirs(OUT, exist_ok=True)
        with open(os.path.join(OUT, "report.json"), "w") as handle:
            json.dump({"end": "error", "error": f"{error!r}\n{traceback.format_exc()}"}, handle)
        os._exit(1)
