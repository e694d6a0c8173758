"""Benchmark of exact distributed MIP (:mod:`mipcast.distributed`): frame, render and composite times.

One run, under MPI (each rank renders its D3-style brick; rank 0 prints)::

    mpiexec --oversubscribe -n 2 pvbatch --symmetric <this file> --size 128 --image 256 256

The table for 1, 2 and 4 ranks (runs the line above for each, then prints
Markdown; under Xvfb when there is no display)::

    python -m mipcast.bench.distributed_bench --table --ranks 1 2 4

Per frame: ``render`` (the rank's brick into the float readout, incl.
``WaitForCompletion``; median over frames, max over ranks), ``wait`` (a
barrier: the slowest rank's lead, i.e. load imbalance), ``composite`` (the
float32 ``MPI_Allreduce(MAX)`` alone) and ``frame`` (wall time of a whole
collective :meth:`~mipcast.distributed.DistributedView.float_image` on rank
0). ``ns/sample`` is the rank's render time over the samples its rays take
(lit pixels of its brick x brick depth in samples, an upper bound on the
work), the per-sample cost the 2048^3 model in plugin/README.md uses.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np


def run_ranks(args) -> None:
    """The MPI part: every rank renders its brick ``--frames`` times; rank 0 prints one JSON line."""
    from mipcast.data_fixtures import make_fixture
    from mipcast.distributed import DistributedView, abort_on_error, extract_piece, split_extents, world_communicator

    comm = world_communicator()
    with abort_on_error(comm):
        image = make_fixture("vessels", size=args.size)
        extent = split_extents(image.GetExtent(), comm.size)[comm.rank]
        brick = extract_piece(image, extent)
        del image
        rows = []
        for method in args.methods.split(","):
            view = DistributedView(brick, method, size=tuple(args.image), comm=comm, time_wait=True)
            times = {"render": [], "wait": [], "composite": [], "frame": []}
            for frame in range(args.warmup + args.frames):
                start = time.perf_counter()
                view.float_image()
                took = time.perf_counter() - start
                if frame >= args.warmup:
                    for key in ("render", "wait", "composite"):
                        times[key].append(view.last_times[key])
                    times["frame"].append(took)
            lit = int(np.sum(~np.isnan(view.last_local)))
            depth = max(extent[1::2][a] - extent[0::2][a] + 1 for a in range(3))
            medians = {key: statistics.median(values) for key, values in times.items()}
            medians["ns_per_sample"] = 1e9 * medians["render"] / max(1, lit * depth)
            everyone = comm.gather(medians, root=0) if comm.size > 1 else [medians]
            if comm.rank == 0:
                row = {"method": method, "ranks": comm.size, "size": args.size, "image": list(args.image),
                       "frame_ms": 1e3 * everyone[0]["frame"],
                       "render_ms_per_rank": [1e3 * m["render"] for m in everyone],
                       "wait_ms": 1e3 * max(m["wait"] for m in everyone),
                       "composite_ms": 1e3 * max(m["composite"] for m in everyone),
                       "ns_per_sample": max(m["ns_per_sample"] for m in everyone),
                       "composite_bytes_per_rank": 4 * args.image[0] * args.image[1],
                       "brick_bytes": 4 * brick.GetNumberOfPoints()}
                rows.append(row)
                print(json.dumps(row), flush=True)


def table(args) -> int:
    """Run :func:`run_ranks` under mpiexec for each rank count and print a Markdown table."""
    here = os.path.abspath(__file__)
    rows = []
    for ranks in args.ranks:
        command = ["mpiexec", "--oversubscribe", "-n", str(ranks), "pvbatch", "--symmetric", here,
                   "--size", str(args.size), "--image", *map(str, args.image), "--methods", args.methods,
                   "--frames", str(args.frames), "--warmup", str(args.warmup)]
        if not os.environ.get("DISPLAY") and shutil.which("xvfb-run"):
            command = ["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24 -noreset"] + command
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=1800)
        if done.returncode != 0:
            sys.stderr.write(done.stdout[-2000:] + done.stderr[-2000:])
            return done.returncode
        rows += [json.loads(line) for line in done.stdout.splitlines() if line.startswith("{")]
    cores = os.cpu_count()
    print(f"{args.size}^3 vessel phantom, {args.image[0]} x {args.image[1]}, D3 bricks, "
          f"{cores} cores (ranks above {cores} are oversubscribed), medians of {args.frames} frames\n")
    print("| method | ranks | frame ms | render ms per rank | wait ms | composite ms | ns/sample |")
    print("|---|---|---|---|---|---|---|")
    for row in rows:
        render = ", ".join(f"{v:.0f}" for v in row["render_ms_per_rank"])
        print(f"| {row['method']} | {row['ranks']} | {row['frame_ms']:.0f} | {render} | {row['wait_ms']:.0f} | "
              f"{row['composite_ms']:.2f} | {row['ns_per_sample']:.1f} |")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--size", type=int, default=128, help="vessel phantom size (points per axis)")
    parser.add_argument("--image", type=int, nargs=2, default=(256, 256), help="width height")
    parser.add_argument("--methods", default="mip,analytic")
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--warmup", type=int, default=3)
    parser.add_argument("--table", action="store_true", help="run 1, 2, 4 ranks under mpiexec and tabulate")
    parser.add_argument("--ranks", type=int, nargs="+", default=(1, 2, 4))
    args = parser.parse_args(argv)
    if args.table:
        sys.exit(table(args))
    run_ranks(args)
    return 0


if __name__ == "__main__":
    main()  # no sys.exit: under pvbatch every rank must finalize MPI
