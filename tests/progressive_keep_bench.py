"""Foveated frames keeping what the last one left at full quality against casting every ray, in one process.

For each round and scene, :func:`mipcast.bench.foveation_bench.measure_progressive` (or, with
``--gaze``, :func:`~mipcast.bench.foveation_bench.measure_gaze_latency`: the synthetic gaze trace
replayed, acuity-only) runs twice, interleaved (the order alternates between rounds): once as the
mapper draws (a frame keeps the last frame's full-quality disc where it is full quality itself,
:mod:`mipcast.mappers.refine_keep`) and once with keeping switched off (every ray cast, as
before).  1024² window, the volume filling it, default radius, 4 refinement frames, auto-adjust off.

``--overhead``: instead, what keeping costs when nothing can be kept: a camera turning 0.5 degree a
frame, 12 frames a run, foveated (acuity-only), wall and process CPU time medians.

Usage: python tests/progressive_keep_bench.py ROUNDS SCENE [SCENE ...] [--gaze | --overhead] [--out FILE.json]
(prints each run and, for refinement, the two progressive tables; figures in docs/foveation.md,
"Progressive refinement keeps what it has").
"""
import argparse
import json
import os
import statistics
import time

from mipcast.app.cli import _load_scene
from mipcast.bench.foveation_bench import framed_view, measure_gaze_latency, measure_progressive, progressive_table
from mipcast.mappers import refine_keep

#: What ``--overhead`` switches off besides the keep itself: the copy of each frame and the scene key.
_WORK = ("kept_disc", "keep_picture", "scene_key")


def turning_frames(image, window, frames: int = 12) -> dict:
    """Medians of wall and process CPU milliseconds of ``frames`` foveated frames, the camera turning."""
    view = framed_view(image, "foveated", 1024, "fill", window)
    for _ in range(2):
        view.render_window.Render()
    wall, cpu = [], []
    for _ in range(frames):
        view.camera.Azimuth(0.5)
        started, started_cpu = time.perf_counter(), time.process_time()
        view.render_window.Render()
        view.render_window.WaitForCompletion()
        wall.append(1000 * (time.perf_counter() - started))
        cpu.append(1000 * (time.process_time() - started_cpu))
    view.render_window.Finalize()
    return {"wall_ms": statistics.median(wall), "cpu_ms": statistics.median(cpu)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rounds", type=int)
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--gaze", action="store_true", help="replay the gaze trace instead")
    parser.add_argument("--overhead", action="store_true", help="time turning frames, keeping's work on and off")
    parser.add_argument("--out")
    args = parser.parse_args()
    kept = {name: getattr(refine_keep, name) for name in _WORK}
    runs = {"keep": [], "recast": []}
    for round_ in range(args.rounds):
        for scene in args.scenes:
            image, window = _load_scene(scene, 128)
            for mode in ("recast", "keep") if round_ % 2 == 0 else ("keep", "recast"):
                for name in _WORK if args.overhead else _WORK[:1]:
                    setattr(refine_keep, name, kept[name] if mode == "keep" else (lambda *_: None))
                if args.overhead:
                    result = turning_frames(image, window)
                    print(mode, scene, f"wall {result['wall_ms']:.0f} ms, CPU {result['cpu_ms']:.0f} ms", flush=True)
                elif args.gaze:
                    result = measure_gaze_latency(image, scene, "mip", size=1024, window=window)
                    print(mode, scene, f"latency median {result['median_latency_ms']:.0f} ms, "
                          f"max {result['max_latency_ms']:.0f} ms, re-renders {result['re_renders']}, pursuit: "
                          f"median {result['median_pursuit_latency_ms']:.0f} ms, "
                          f"{100 * result['pursuit_rays']:.1f} % of the rays", flush=True)
                else:
                    result = measure_progressive(image, scene, "mip", size=1024, window=window)
                    print(mode, scene, f"full {result['full_ms']:.0f} ms, until equal {result['ms_to_full']:.0f} ms",
                          [(s["step"], round(s["ms"]), s["rays"]) for s in result["steps"]], flush=True)
                result.update(mode=mode, round=round_, load=os.getloadavg()[0])
                runs[mode].append(result)
    for name, function in kept.items():
        setattr(refine_keep, name, function)
    for mode, results in runs.items():
        if not args.gaze and not args.overhead:
            print(f"\n{mode}\n{progressive_table(results)}")
    if args.out:
        with open(args.out, "w") as stream:
            json.dump(runs, stream, indent=1)


if __name__ == "__main__":
    main()
