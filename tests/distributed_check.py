"""Exact distributed MIP under MPI: run with ``mpiexec -n N pvbatch --symmetric tests/distributed_check.py``.

Every rank builds the same 64^3 vessel phantom (``--size``), takes its brick
(:func:`mipcast.distributed.split_extents` along ``--axis`` x, y, z or
``d3``), and renders each method through
:class:`mipcast.distributed.DistributedView`; rank 0 also renders the whole
volume in one process (:class:`mipcast.offscreen.OffscreenView`, the same
camera and window) and compares: pictures (pixels within 1 grey level) and
float images (largest difference as a fraction of the range, and the
fraction of bit-identical pixels). Rank 0 writes the results as JSON to
``--out``. ``--die-rank R`` makes rank R kill itself (SIGKILL) after the
first frame, ``--raise-rank R`` makes it raise: the job must end, not hang.
``--max-voxels`` is each rank's texture budget (refused above it).

    OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 \\
    PYTHONPATH=$(python tests/installed.py) xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" \\
    mpiexec --oversubscribe -n 2 pvbatch --symmetric tests/distributed_check.py --out /tmp/d.json
"""
import argparse
import json
import os
import signal
import sys

import numpy as np

from mipcast.data_fixtures import make_fixture
from mipcast.distributed import (DistributedView, abort_on_error, colour, extract_piece, split_extents,
                                 world_communicator)
from mipcast.core.parameters import set_parameters
from mipcast.offscreen import OffscreenView

AXES = {"x": 0, "y": 1, "z": 2, "d3": None}


def compare(distributed_rgb, single_rgb, distributed_float, single_float, span):
    close = np.abs(distributed_rgb.astype(int) - single_rgb.astype(int)).max(axis=2) <= 1
    both = ~np.isnan(single_float) & ~np.isnan(distributed_float)
    miss_agree = float(np.mean(np.isnan(single_float) == np.isnan(distributed_float)))
    diff = np.abs(distributed_float[both].astype(np.float64) - single_float[both].astype(np.float64))
    return {
        "within_1_grey": float(close.mean()),
        "max_grey_off": int(np.abs(distributed_rgb.astype(int) - single_rgb.astype(int)).max()),
        "float_max_error": float(diff.max() / span) if diff.size else 0.0,
        "float_identical": float((diff == 0).mean()) if diff.size else 1.0,
        "misses_agree": miss_agree,
        "lit": float((single_rgb.max(axis=2) > 8).mean()),
    }


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", required=True)
    parser.add_argument("--size", type=int, default=64)
    parser.add_argument("--image", type=int, nargs=2, default=(96, 96))
    parser.add_argument("--axes", default="x,y,z,d3")
    parser.add_argument("--methods", default="mip,analytic")
    parser.add_argument("--set", action="append", default=[], metavar="METHOD:NAME=VALUE",
                        help="a parameter for one method, e.g. analytic:packed_corners=0")
    parser.add_argument("--ghost", type=int, default=0)
    parser.add_argument("--max-voxels", type=int, default=None)
    parser.add_argument("--die-rank", type=int, default=None)
    parser.add_argument("--raise-rank", type=int, default=None)
    parser.add_argument("--png", default=None, help="folder for rank 0's PNGs (distributed, single)")
    args = parser.parse_args(argv)
    comm = world_communicator()
    image = make_fixture("vessels", size=args.size)
    span = float(np.subtract(*image.GetPointData().GetScalars().GetRange()[::-1]))
    window = image.GetPointData().GetScalars().GetRange()
    results = {"ranks": comm.size, "cases": []}
    keep = []  # every window stays open to the end: closing one X display and opening the next aborts now and then
    with abort_on_error(comm):
        frame = 0
        for axis in args.axes.split(","):
            extents = split_extents(image.GetExtent(), comm.size, AXES[axis], ghost=args.ghost)
            brick = extract_piece(image, extents[comm.rank])
            for method in args.methods.split(","):
                settings = {}
                for item in args.set:
                    owner, pair = item.split(":", 1)
                    name, value = pair.split("=", 1)
                    if owner == method:
                        settings[name] = json.loads(value)
                view = DistributedView(brick, method, size=tuple(args.image), window=window, comm=comm,
                                       max_voxels=args.max_voxels, **settings)
                keep.append(view)
                values = view.float_image()
                # which rank's brick holds each pixel's maximum: every brick must contribute
                won = np.array([np.sum(view.last_local == values)], dtype=np.int64)
                wins = np.zeros(comm.size, dtype=np.int64)
                wins[comm.rank] = won[0]
                if comm.size > 1:
                    from mpi4py import MPI

                    comm.Allreduce(MPI.IN_PLACE, wins, op=MPI.SUM)
                rgb = colour(values, view.local.volume.GetProperty())
                frame += 1
                if args.die_rank == comm.rank and frame == 1:
                    os.kill(os.getpid(), signal.SIGKILL)
                if args.raise_rank == comm.rank and frame == 1:
                    raise RuntimeError("rank asked to fail (--raise-rank)")
                if comm.rank == 0:
                    single = OffscreenView(image, method, size=tuple(args.image), window=window)
                    keep.append(single)
                    if settings:
                        set_parameters(single.mapper, **settings)
                    single.camera.DeepCopy(view.camera)
                    single_float = single.float_image()
                    single_rgb = single.screenshot()
                    case = {"axis": axis, "method": method, "bricks": [list(e) for e in extents],
                            "pixels_won": wins.tolist(), "seconds": view.last_times,
                            **compare(rgb, single_rgb, values, single_float, span)}
                    results["cases"].append(case)
                    print(json.dumps(case), flush=True)
                    if args.png:
                        from vtk_png import write_png

                        os.makedirs(args.png, exist_ok=True)
                        write_png(os.path.join(args.png, f"{method}-{axis}-n{comm.size}.png"), rgb)
                        write_png(os.path.join(args.png, f"{method}-single.png"), single_rgb)
                        np.save(os.path.join(args.png, f"{method}-{axis}-n{comm.size}.npy"), values)
                        np.save(os.path.join(args.png, f"{method}-single.npy"), single_float)
    if comm.rank == 0:
        with open(args.out, "w") as handle:
            json.dump(results, handle, indent=1)
    return 0


if __name__ == "__main__":
    main()  # no sys.exit: pvbatch must finalize MPI on every rank
