"""Sampled MIP's block skipping against reading every sample, and against stock VTK MIP.

Wall ms per frame (medians of interleaved frames after a warm-up frame, auto-adjust off, the volume
filling the view, oblique), and whether the two mipcast pictures are identical, pixel for pixel.

Usage: python tests/mip_skipping_bench.py [SCENE ...] [--size N ...]
(default: vessels@0.25,1 head@100,1500 at 512 and 1024; prints JSON; figures in docs/methods.md, Skipping).
"""
import argparse
import json
import statistics
import time

import numpy as np

from mipcast.app.cli import _load_scene
from mipcast.bench.foveation_bench import framed_view


def measure(scene: str, size: int, rounds: int = 7) -> dict:
    image, window = _load_scene(scene, 128)
    views = {}
    for name in ("stock", "mip", "mip, no skipping"):
        view = framed_view(image, "stock" if name == "stock" else "mip", size, "fill", window)
        view.mapper.SetAutoAdjustSampleDistances(False)
        if name == "mip, no skipping":
            view.mapper.SetSkipping(False)
        views[name] = view
    frames = {name: [] for name in views}
    for _ in range(rounds):
        for name, view in views.items():
            window_ = view.render_window
            window_.WaitForCompletion()
            start = time.perf_counter()
            window_.Render()
            window_.WaitForCompletion()
            frames[name].append(time.perf_counter() - start)
    ms = {name: round(1000 * statistics.median(values[1:]), 1) for name, values in frames.items()}
    skipping, every = views["mip"].screenshot(), views["mip, no skipping"].screenshot()
    return {"scene": scene, "size": size, "ms": ms,
            "skips_blocks": "mip_hooks_blocks" in views["mip"].mapper.GetShaderPieces(),
            "no skipping / skipping": round(ms["mip, no skipping"] / ms["mip"], 2),
            "stock / skipping": round(ms["stock"] / ms["mip"], 2),
            "identical": bool(np.array_equal(skipping, every)),
            "drawn_share": round(float((every.max(axis=2) > 0).mean()), 3)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=["vessels@0.25,1", "head@100,1500"])
    parser.add_argument("--size", nargs="+", type=int, default=[512, 1024])
    args = parser.parse_args()
    print(json.dumps([measure(scene, size) for scene in args.scenes for size in args.size], indent=1))


if __name__ == "__main__":
    main()
