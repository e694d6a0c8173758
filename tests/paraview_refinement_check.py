"""The mipcast representation's refinement timer and client mouse gaze, measured in pvpython.

Usage (from the repository root, the plugin built by plugin/representation/build.sh)::

    PYTHONPATH=$(python tests/installed.py):$PWD/tests xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
        pvpython tests/paraview_refinement_check.py --plugin PATH [--server HOST:PORT] [--png-dir DIR]

Shows the 48^3 vessel phantom with the ``foveated`` method, progressive
refinement on (``foveated_refinement_frames`` = :data:`FRAMES`), a gaze point
off centre, then runs the view interactor's event loop
(``interactor.Start()``, ended by a watchdog timer or once converged): the
representation's one-shot timers render the refining frames by themselves.
Measured: the frames the timer asked for, the step reached, the time per
refining frame, whether a timer is left once converged, the converged
picture against the same view with ``foveated_foveation`` off (the method at
full quality, bit for bit) and against mipcast's offscreen view; then a
camera change drops back to the foveated frame and the timer converges again;
then a camera drag (left button held: no refining frame) and its release, and
:func:`mipcast_representation.refine` (the scripts' API) does the same
without an event loop.  With ``--server`` (a client of a running
``pvserver``) it also moves the client's mouse (``MouseMoveEvent`` on the
client's interactor) and checks the server's picture follows it
(``foveated_gaze_point`` written by the client).  Prints one JSON object on
the last line; used by tests/test_paraview_refinement.py.
"""
import argparse
import inspect
import json
import os
import tempfile
import time

import numpy as np

from paraview_representation_check import (ARRAY, HEIGHT, WIDTH, read_vti, reference, screenshot, set_camera,
                                           show_mipcast, write_vti)
from paraview_view_check import changed_share, compare, plain_view
from mipcast.data_fixtures import make_fixture
from vtk_png import write_png

#: foveated_refinement_frames of the check.
FRAMES = 4
GAZE = (0.3, 0.6)
#: Seconds the event loop may run before the watchdog ends it.
WATCHDOG_S = 30.0


def run_loop(view, live, until, watchdog_s=WATCHDOG_S):
    """Run the view interactor's event loop until ``until()`` holds after a frame (or the watchdog)."""
    interactor = view.GetInteractor()
    window = interactor.GetRenderWindow()
    times = []
    started = {}

    def frame_start(caller, event):
        started["t"] = time.perf_counter()

    def frame_end(caller, event):
        times.append((started.get("t", time.perf_counter()), time.perf_counter()))
        if until():
            interactor.TerminateApp()

    watchdog = interactor.CreateOneShotTimer(int(watchdog_s * 1000))

    def timer(caller, timer_id):
        if timer_id == watchdog or (until() and not any(r.timer for r in live._REFINERS.values())):
            interactor.TerminateApp()

    tags = [(window, window.AddObserver("StartEvent", frame_start)),
            (window, window.AddObserver("EndEvent", frame_end, -100.0)),  # after the refiner's
            (interactor, interactor.AddObserver("TimerEvent", _on_timer(timer), -100.0))]
    t0 = time.perf_counter()
    interactor.Start()
    wall = time.perf_counter() - t0
    interactor.DestroyTimer(watchdog)
    for obj, tag in tags:
        obj.RemoveObserver(tag)
    return times, wall


def _on_timer(function):
    """A TimerEvent observer called with the timer's id (VTK passes it as call data)."""
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_INT

    @calldata_type(VTK_INT)
    def observer(caller, event, timer_id=None):
        function(caller, timer_id)
    return observer


def idle(view, refiner, seconds=0.4):
    """(frames rendered, frames the refiner asked for) while the event loop runs ``seconds``."""
    interactor = view.GetInteractor()
    window = interactor.GetRenderWindow()
    count, asked = [], refiner.frames
    tag = window.AddObserver("EndEvent", lambda c, e: count.append(1))
    stop = interactor.CreateOneShotTimer(int(seconds * 1000))
    tag2 = interactor.AddObserver("TimerEvent", _on_timer(
        lambda caller, timer_id: interactor.TerminateApp() if timer_id == stop else None))
    interactor.Start()
    interactor.DestroyTimer(stop)
    window.RemoveObserver(tag)
    interactor.RemoveObserver(tag2)
    return len(count), refiner.frames - asked


def full_quality(display, view, png, name):
    """The same view with foveation off (the method at full quality), then foveation back on."""
    display.foveated_foveation = 0
    pixels = screenshot(view, png(name))
    display.foveated_foveation = 1
    return pixels


def _mappers():
    import mipcast_representation

    return [e.mapper for e in mipcast_representation._REGISTRY.values()
            if e.mapper is not None and e.mapper_method == "foveated"]


class Recorder:
    """Every frame of the view's window since ``start()``: (refinement step or None, asked by the
    refiner's timer, milliseconds)."""

    def __init__(self, view, refiner, remote):
        self.window, self.refiner, self.remote, self.frames = view.GetRenderWindow(), refiner, remote, []
        self.window.AddObserver("StartEvent", self.begin)
        self.window.AddObserver("EndEvent", self.end, 100.0)  # before the refiner's: it resets 'requested'

    def begin(self, caller, event):
        self.t0 = time.perf_counter()

    def end(self, caller, event):
        step = None if self.remote else _mappers()[0].GetRefinementStep()
        self.frames.append((step, self.refiner.requested, 1000.0 * (time.perf_counter() - self.t0)))

    def start(self):
        self.frames = []


def timer_part(reader, image, view, png, live, remote):
    display = show_mipcast(reader, view, "foveated")
    display.foveated_gaze_point = list(GAZE)
    display.foveated_follow_mouse = 0
    display.foveated_refinement_frames = FRAMES
    set_camera(view)
    refiner = live.refiner(view.GetInteractor())
    recorder = Recorder(view, refiner, remote)
    report = {}

    def converged():
        if remote:
            return refiner.timer is None and not refiner.needs_refinement()
        return not any(m.NeedsRefinement() for m in _mappers())

    for name in ("still", "camera_change"):
        recorder.start()
        if name == "camera_change":  # converged; the camera turns: back to the foveated frame
            view.GetActiveCamera().Azimuth(12.0)
        else:
            display.foveated_progressive = 1  # a change: the next frame is the foveated one
        first = screenshot(view, png(f"first_{name}"))  # two frames (Render, SaveScreenshot)
        asked = refiner.frames
        times, wall = run_loop(view, live, converged)
        frames = list(recorder.frames)
        converged_pixels = screenshot(view, png(f"converged_{name}"))
        # rays the screenshot's still frame cast: none when it kept the converged picture (builtin only)
        converged_rays = None if remote else _mappers()[0].GetLastFrameCost()["rays"]
        full = full_quality(display, view, png, f"full_{name}")
        run_loop(view, live, converged)  # the foveation switch was a change: converge again
        steps = [f[0] for f in frames]
        report[name] = dict(
            steps=steps, asked_by_timer=[f[1] for f in frames], frames_asked=sum(bool(f[1]) for f in frames),
            frames_to_full=(steps.index(FRAMES) if FRAMES in steps else None),  # after the change's frame
            refining_frame_ms=[round(f[2], 2) for f in frames if f[1]], wall_s=wall,
            timer_left=refiner.timer is not None, first_vs_full=compare(first, full), converged_rays=converged_rays,
            bit_equal_full=bool(np.array_equal(converged_pixels, full)), vs_full=compare(converged_pixels, full))
    idles = [idle(view, refiner), idle(view, refiner)]  # interactor.Start() itself renders once
    report["idle_frames"] = [i[0] for i in idles]
    report["idle_frames_asked"] = sum(i[1] for i in idles)
    ref, _ = reference(image, "foveated", view, gaze_point=GAZE, foveation=False)
    write_png(png("ref_full"), ref)
    report["vs_offscreen"] = compare(screenshot(view, png("converged_final")), ref)
    # the scripts' API: no event loop
    import mipcast_representation
    from paraview.simple import Render

    view.GetActiveCamera().Azimuth(-12.0)
    full = full_quality(display, view, png, "full_refine")  # foveation off and on: a change
    recorder.start()
    Render(view)
    frames = mipcast_representation.refine(view)
    pixels = screenshot(view, png("refined_by_call"))
    report["refine_call"] = dict(frames=frames, steps=[f[0] for f in recorder.frames],
                                 bit_equal_full=bool(np.array_equal(pixels, full)), vs_full=compare(pixels, full))
    report["drag"] = drag(view, display, png, live, refiner, recorder, converged)
    report["server_state"] = server_state(view, display, reader, live, refiner, recorder, converged)
    display.foveated_progressive = 0
    return report


def server_state(view, display, reader, live, refiner, recorder, converged):
    """After each change, the timer asks for exactly the frames the (server's) mapper still needs:
    its refinement state read from the representation's information properties before and after."""
    from paraview.simple import Render

    renderer = view.GetRenderer()
    key = next(k for k, e in live._registry().items() if e.method == "foveated" and e.renderer.Get() is renderer)
    changes = (("camera", lambda: view.GetActiveCamera().Azimuth(6.0)),
               ("other_method", lambda: setattr(display, "mip_slab_thickness", 0.25)),  # not what foveated draws
               ("opacity", lambda: setattr(display, "ScalarOpacityUnitDistance",
                                           2.0 * display.ScalarOpacityUnitDistance)),  # not a mipcast value
               ("data", lambda: setattr(reader, "FileName", reader.FileName[0].replace(".vti", "_b.vti"))))
    report = {}
    for name, change in changes:
        change()
        Render(view)
        before, asked, pulls = live.server_refinement(key), refiner.frames, refiner.pulls
        recorder.start()
        t0 = time.perf_counter()
        run_loop(view, live, converged)
        wall = time.perf_counter() - t0
        after, frames = live.server_refinement(key), list(recorder.frames)
        report[name] = dict(before=before, after=after, asked=refiner.frames - asked, loop_frames=len(frames),
                            untimed=sum(not f[1] for f in frames), pulls=refiner.pulls - pulls, wall_s=wall,
                            frame_ms=[round(f[2], 2) for f in frames])
    display.foveated_progressive = 0
    Render(view)
    frames, asked = idle(view, refiner, 0.3)
    report["progressive_off"] = dict(frames=frames, asked=asked, after=live.server_refinement(key))
    t0 = time.perf_counter()
    for _ in range(10):
        live.server_refinement(key)
    report["pull_ms"] = 100.0 * (time.perf_counter() - t0)  # one read of the state (a round trip remote)
    display.foveated_progressive = 1
    return report


def drag(view, display, png, live, refiner, recorder, converged):
    """A camera drag (left button held, the mouse moved) from a converged picture: no refining
    frame while the button is held, refinement again after the release."""
    interactor = view.GetInteractor()
    interactor.SetEventPosition(80, 64)
    interactor.InvokeEvent("LeftButtonPressEvent")
    interactor.SetEventPosition(92, 70)
    recorder.start()
    interactor.InvokeEvent("MouseMoveEvent")  # ParaView rotates the camera and renders
    held = idle(view, refiner, 0.3)  # the event loop runs with the button held
    during = list(recorder.frames)
    interactor.InvokeEvent("LeftButtonReleaseEvent")  # ParaView's still render, then our timer
    times, wall = run_loop(view, live, converged)
    frames, timer_left = list(recorder.frames), refiner.timer is not None
    pixels = screenshot(view, png("converged_drag"))
    full = full_quality(display, view, png, "full_drag")
    return dict(steps_while_held=[f[0] for f in during], asked_while_held=held[1],
                steps=[f[0] for f in frames], asked=sum(bool(f[1]) for f in frames),
                bit_equal_full=bool(np.array_equal(pixels, full)), timer_left=timer_left)


def mouse_part(reader, image, view, png, live):
    """The client's mouse moves the server's fovea (``foveated_gaze_point`` written by the client)."""
    display = show_mipcast(reader, view, "foveated")
    set_camera(view)
    before = screenshot(view, png("mouse_before"))
    interactor = view.GetInteractor()
    report = {"interactor": interactor is not None}
    if interactor is None:
        return report
    latencies = []
    for x, y in ((120, 40), (30, 100), (120, 40)):
        interactor.SetEventPosition(x, y)
        t0 = time.perf_counter()
        interactor.InvokeEvent("MouseMoveEvent")  # the client's handler writes the property and renders
        latencies.append(1000.0 * (time.perf_counter() - t0))
    x, y = 120, 40
    moved = screenshot(view, png("mouse_moved"))
    gaze = ((x + 0.5) / WIDTH, (y + 0.5) / HEIGHT)
    ref, _ = reference(image, "foveated", view, gaze_point=gaze)
    write_png(png("ref_mouse"), ref)
    report.update(property=list(display.foveated_gaze_point), expected=list(gaze),
                  moves=sum(g.moves for g in live._CLIENT_GAZE.values()), latency_ms=latencies,
                  vs_ref=compare(moved, ref), changed_share=changed_share(before, moved))
    return report


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--png-dir")
    parser.add_argument("--server", help="HOST:PORT of a running pvserver")
    args = parser.parse_args()
    if not hasattr(inspect, "getargspec"):  # ParaView 5.11's plugin loader on Python 3.11
        inspect.getargspec = inspect.getfullargspec
    from paraview.simple import Connect, Delete, LoadPlugin, OpenDataFile

    directory = tempfile.mkdtemp(prefix="mipcast-pvrefine-")
    png_dir = args.png_dir or directory
    os.makedirs(png_dir, exist_ok=True)

    def png(name):
        return os.path.join(png_dir, name + ".png")

    report = {"session": "builtin"}
    if args.server:
        host, _, port = args.server.rpartition(":")
        Connect(host or "localhost", int(port))
        LoadPlugin(args.plugin, remote=True, ns=globals())
        report["session"] = "client-server"
    LoadPlugin(args.plugin, remote=False, ns=globals())
    image = make_fixture("vessels", size=48)
    path = os.path.join(directory, "vessels.vti")
    write_vti(image, path)
    write_vti(make_fixture("vessels", size=48, seed=1), path.replace(".vti", "_b.vti"))  # the "data" change
    image = read_vti(path)
    import sys
    sys.path.append(os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "plugin",
                                 "representation"))  # where the plugin puts it (appended at its first frame)
    import mipcast_representation_live as live

    def fresh():
        reader = OpenDataFile(path)
        reader.PointArrayStatus = [ARRAY]
        return reader, plain_view((WIDTH, HEIGHT))

    reader, view = fresh()
    report["timer"] = timer_part(reader, image, view, png, live, bool(args.server))
    Delete(view)
    if args.server:
        reader, view = fresh()
        report["mouse"] = mouse_part(reader, image, view, png, live)
        Delete(view)
    report["png_dir"] = png_dir
    print(json.dumps(report))


if __name__ == "__main__":
    main()
