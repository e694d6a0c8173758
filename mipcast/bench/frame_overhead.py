"""What a foveated frame costs the CPU, beside its wall time: the part a fast GPU leaves.

A foveated frame draws several levels, each a pass of VTK's ray caster with
mipcast's planning, uniforms and, with content-adaptive density, refine
passes around it.  On llvmpipe the rays dominate; on a GPU whose rays cost
little, this per-frame work decides the speed-up over full quality.
:func:`measure_frame_overhead` times frames of full quality, acuity-only
and content-adaptive (2 grey) foveation, the volume filling the view, in
wall time and in the process's CPU time, with three kinds of frame:

- ``still``: the same frame again (what the foveation benchmark times);
- ``gaze moving``: the gaze moves every frame (an eye tracker's fixations
  elsewhere), the view standing still;
- ``camera turning``: the camera turns half a degree a frame, the gaze
  standing still.  VTK rebuilds every volume shader (from its cache) at
  such a frame, since its headlight follows the camera.

CPU time close to wall time says the frame is CPU-bound.  On llvmpipe the
CPU time counts the rasteriser's threads too: there it is the whole frame.
"""
from __future__ import annotations

import statistics
import time
from typing import Callable, Optional, Sequence

from mipcast.bench.foveation_bench import framed_view

#: Settings timed: (mipcast method of the view, content tolerance of a foveated view).
SETTINGS = {"full quality": ("mip", None), "acuity only": ("foveated", 0.0),
            "content-adaptive 2 grey": ("foveated", 2.0)}
#: Kinds of frame; full quality has no gaze to move.
MOVES = ("still", "gaze moving", "camera turning")
#: The gaze points a moving gaze visits in turn (normalised viewport coordinates).
GAZE_PATH = ((0.3, 0.4), (0.6, 0.55), (0.45, 0.7), (0.7, 0.3))
#: Degrees the camera turns a frame.
TURN = 0.5


def measure_frame_overhead(image, scene: str, sizes: Sequence[int] = (32, 1024), window=None, frames: int = 8,
                           warmup: int = 3, progress: Optional[Callable[[str], None]] = None) -> list:
    """Wall and CPU milliseconds a frame of each setting and kind of frame (medians of interleaved frames).

    Parameters
    ----------
    image : vtkImageData
        The scene's volume.
    scene : str
        Its name in the rows.
    sizes : sequence of int
        Square window edges (a small one: where the rays cost next to nothing).
    window : tuple of float, optional
        Grey window (default: the data range).
    frames, warmup : int
        Frames timed per view, one view after the other in turn, after ``warmup`` frames each.
    progress : callable, optional
        Called with a short label after each size.

    Returns
    -------
    list of dict
        One row per size, setting and kind of frame: ``scene``, ``size``, ``setting``, ``move``,
        ``wall_ms``, ``cpu_ms``, ``frames``, and ``wall_over_full`` (this frame's wall time over full
        quality's, still).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = measure_frame_overhead(make_fixture("spheres", size=16), "spheres", sizes=[32], frames=1, warmup=1)
    >>> [(row["setting"], row["move"]) for row in rows][:3]
    [('full quality', 'still'), ('full quality', 'camera turning'), ('acuity only', 'still')]
    """
    rows = []
    for size in sizes:
        views = {}
        for setting, (method, tolerance) in SETTINGS.items():
            for move in MOVES:
                if tolerance is None and move == "gaze moving":
                    continue
                view = views[setting, move] = framed_view(image, method, size, "fill", window)
                if tolerance is not None:
                    view.mapper.SetContentTolerance(tolerance)
        times = {key: ([], []) for key in views}
        for index in range(warmup + frames):
            for (setting, move), view in views.items():
                _move(view, move, index)
                wall, cpu = timed_frame(view)
                if index >= warmup:
                    times[setting, move][0].append(wall)
                    times[setting, move][1].append(cpu)
        full = statistics.median(times["full quality", "still"][0])
        for (setting, move), (walls, cpus) in times.items():
            wall = statistics.median(walls)
            rows.append({"scene": scene, "size": size, "setting": setting, "move": move,
                         "wall_ms": 1000 * wall, "cpu_ms": 1000 * statistics.median(cpus), "frames": len(walls),
                         "wall_over_full": wall / full})
        for view in views.values():
            view.render_window.Finalize()
        if progress is not None:
            progress(f"{scene} {size}²")
    return rows


def _move(view, move: str, index: int) -> None:
    if move == "gaze moving":
        view.mapper.SetGazePoint(*GAZE_PATH[index % len(GAZE_PATH)])
    elif move == "camera turning":
        view.renderer.GetActiveCamera().Azimuth(TURN)


def timed_frame(view) -> tuple:
    """(wall, process CPU) seconds of one frame of ``view`` (an :class:`~mipcast.offscreen.OffscreenView`),
    the GL work finished before and after.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.offscreen import OffscreenView
    >>> wall, cpu = timed_frame(OffscreenView(make_fixture("spheres", size=8), "mip", size=(16, 16)))
    >>> wall > 0 and cpu > 0
    True
    """
    window = view.render_window
    window.WaitForCompletion()
    wall, cpu = time.perf_counter(), time.process_time()
    window.Render()
    window.WaitForCompletion()
    return time.perf_counter() - wall, time.process_time() - cpu


def overhead_table(rows: Sequence[dict]) -> str:
    """Markdown: one line per size and setting, wall / CPU ms for each kind of frame.

    Examples
    --------
    >>> rows = [{"scene": "s", "size": 32, "setting": "full quality", "move": "still", "wall_ms": 4.0,
    ...          "cpu_ms": 3.5, "frames": 8, "wall_over_full": 1.0}]
    >>> print(overhead_table(rows).splitlines()[-1])
    | s 32² | full quality | 4.0 / 3.5 | - | - |
    """
    lines = ["| scene | setting | still: wall / CPU ms | gaze moving | camera turning |",
             "| --- | --- | --- | --- | --- |"]
    cells: dict = {}
    for row in rows:
        cells.setdefault((row["scene"], row["size"], row["setting"]), {})[row["move"]] = (
            f"{row['wall_ms']:.1f} / {row['cpu_ms']:.1f}")
    for (scene, size, setting), moves in cells.items():
        lines.append(f"| {scene} {size}² | {setting} | " + " | ".join(moves.get(m, "-") for m in MOVES) + " |")
    return "\n".join(lines)
