"""First frame and steady frames of analytic MIP against stock VTK MIP, one process, interleaved.

Measures each frame the way ``mipcast bench --gpu-report`` measures first
frames (:func:`mipcast.bench.gpu_report.first_frame`: seconds from a new
:class:`mipcast.offscreen.OffscreenView` to its first finished frame), then
the frames after it one by one: the second (where a large volume's lazy
corner packing lands, :meth:`AnalyticMIPVolumeMapper.SetPackingDelay`) and
the slowest later one (where the packed copy is uploaded) and the steady
ones (median of the last half).  Rounds alternate the methods.

    python3 tests/first_frame_check.py --shape 400x512x512 --size 512 --rounds 3
    python3 tests/first_frame_check.py --profile analytic   # where one first frame's time goes
"""
from __future__ import annotations

import argparse
import json
import statistics
import time


def one_view(image, method: str, size: int, frames: int, delay=None) -> dict:
    from mipcast.offscreen import OffscreenView

    started = time.perf_counter()
    view = OffscreenView(image, method, size=(size, size))
    if delay is not None:
        view.mapper.SetPackingDelay(delay)
    view.frame_times(frames=0, warmup=1)
    first = time.perf_counter() - started
    later = view.frame_times(frames=frames, warmup=0)
    view.render_window.Finalize()
    # worst_s: the slowest later frame (with lazy packing: the one that uploads the packed copy)
    return {"first_s": first, "second_s": later[0], "worst_s": max(later),
            "steady_s": statistics.median(later[len(later) // 2:]), "frames_s": [round(t, 3) for t in later]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--shape", default="400x512x512", help="(nz)x(ny)x(nx) of the synthetic CT")
    parser.add_argument("--size", type=int, default=512, help="window edge, pixels")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--frames", type=int, default=8, help="frames after the first (>= 2)")
    parser.add_argument("--delays", default="", help="also analytic with these packing delays, e.g. 0")
    parser.add_argument("--profile", default="", help="instead: cProfile one first frame of this method")
    args = parser.parse_args()
    from mipcast.data_fixtures.ct_phantom import ct_volume

    image = ct_volume(tuple(int(n) for n in args.shape.split("x")))
    one_view(image, "stock", 64, 2)  # process warm-up (GL context, shader cache): not counted
    if args.profile:
        import cProfile
        import pstats

        profile = cProfile.Profile()
        profile.runcall(one_view, image, args.profile, args.size, 2)
        pstats.Stats(profile).sort_stats("tottime").print_stats(14)
        return
    variants = [("stock", None), ("analytic", None)] + [("analytic", int(d)) for d in args.delays.split(",") if d]
    rows = {f"{m}" + ("" if d is None else f"-delay{d}"): [] for m, d in variants}
    for round_ in range(args.rounds):
        for method, delay in (variants if round_ % 2 == 0 else variants[::-1]):
            name = method + ("" if delay is None else f"-delay{delay}")
            rows[name].append(one_view(image, method, args.size, args.frames, delay))
            print(round_, name, rows[name][-1], flush=True)
    keys = ("first_s", "second_s", "worst_s", "steady_s")
    summary = {name: {k: statistics.median(r[k] for r in runs) for k in keys} for name, runs in rows.items()}
    ratios = {name: {k: summary[name][k] / summary["stock"][k] for k in summary[name]} for name in summary}
    # per-round ratios (same round, adjacent runs): the spread under a shared machine
    per_round = {name: [runs[i]["first_s"] / rows["stock"][i]["first_s"] for i in range(len(runs))]
                 for name, runs in rows.items()}
    print(json.dumps({"shape": args.shape, "size": args.size, "median_s": summary, "over_stock": ratios,
                      "first_over_stock_per_round": per_round}, indent=1))


if __name__ == "__main__":
    main()
