"""Drive progressive refinement from an interactor's timer (never a busy loop).

A foveated mapper with progressive refinement on
(:meth:`mipcast.mappers.foveated.FoveatedVolumeMapper.SetProgressive`)
refines its picture one step per frame while nothing changes; someone has
to render those frames.  :func:`drive_refinement` adds a repeating timer to
an interactor: at each tick, if any of the given mappers says
``NeedsRefinement()`` (every mipcast mapper has the method; only a
refining foveated one answers True), the window renders once.  Idle
windows cost one cheap check per tick.
"""
from __future__ import annotations

from typing import Callable, Iterable

from vtkmodules.vtkCommonCore import vtkCommand

#: Milliseconds between refinement checks.
DEFAULT_INTERVAL_MS = 40


def drive_refinement(interactor, mappers: Callable[[], Iterable], interval_ms: int = DEFAULT_INTERVAL_MS) -> dict:
    """Render ``interactor``'s window from a timer while one of ``mappers()`` needs refinement.

    The timer is created at the window's first render after the
    interactor is initialised (VTK refuses timers before).  Returns a
    handle for :func:`stop_refinement`.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderWindowInteractor
    >>> import vtkmodules.vtkRenderingOpenGL2
    >>> window = vtkRenderWindow(); interactor = vtkRenderWindowInteractor()
    >>> interactor.SetRenderWindow(window)
    >>> handle = drive_refinement(interactor, lambda: [])
    >>> sorted(handle)
    ['interactor', 'observers', 'timer']
    >>> stop_refinement(handle)
    """
    if not (isinstance(interval_ms, int) and interval_ms > 0):
        raise ValueError(f"interval_ms must be a positive int, got {interval_ms!r}")
    handle = {"interactor": interactor, "timer": None, "observers": []}

    def tick(caller, event):
        window = caller.GetRenderWindow()
        if window is not None and any(m is not None and m.NeedsRefinement() for m in mappers()):
            window.Render()

    def start_timer(caller, event):
        if handle["timer"] is None and interactor.GetInitialized():
            handle["timer"] = interactor.CreateRepeatingTimer(int(interval_ms))

    handle["observers"].append((interactor, interactor.AddObserver(vtkCommand.TimerEvent, tick)))
    window = interactor.GetRenderWindow()
    if window is not None:
        handle["observers"].append((window, window.AddObserver(vtkCommand.EndEvent, start_timer)))
    start_timer(None, None)
    return handle


def stop_refinement(handle: dict) -> None:
    """Remove the timer and observers :func:`drive_refinement` added."""
    if handle.get("timer") is not None:
        handle["interactor"].DestroyTimer(handle["timer"])
        handle["timer"] = None
    for obj, tag in handle.get("observers", ()):
        obj.RemoveObserver(tag)
    handle["observers"] = []
