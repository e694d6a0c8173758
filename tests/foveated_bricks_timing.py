"""Foveated rendering beyond the 3D texture limit vs one texture: agreement, frame time, rays cast.

The limit is lowered (``object_state(mapper)["texture_limit"]``) so that the foveated mapper's
levels too large for it are composited over bricks first (mipcast.mappers.bricked_foveated).
For each volume/limit, layer method and content tolerance: bricks per frame, frame time
(Render + WaitForCompletion, medians of interleaved frames after warm-up, auto-adjust off),
the picture's agreement with one texture (fraction of pixels within 1 grey level, bit for
bit), and the rays cast (the levels' own, GetLastFrameCost, and the bricks').

Usage: python tests/foveated_bricks_timing.py (prints JSON; figures in docs/methods.md,
"Foveated rendering", bricks).
"""
import json
import statistics
import time

import numpy as np

from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

SIZE = (128, 128)


def view(image, method, tolerance, limit):
    scene = OffscreenView(image, "foveated", size=SIZE, view="perspective", window="full")
    mapper = scene.mapper
    mapper.SetMethod(method)
    mapper.SetGazePoint(0.4, 0.55)
    mapper.SetContentTolerance(tolerance)
    if limit:
        object_state(mapper)["texture_limit"] = limit
    return scene


def frame(scene) -> float:
    start = time.perf_counter()
    scene.render_window.Render()
    scene.render_window.WaitForCompletion()
    return time.perf_counter() - start


def main() -> dict:
    out = {}
    for size, limit in ((48, 20), (64, 33)):
        image = make_fixture("vessels", size=size)
        for method in ("mip", "analytic", "demip"):
            for tolerance in (0.0, 8.0):
                one, bricked = view(image, method, tolerance, 0), view(image, method, tolerance, limit)
                a, b = one.screenshot().astype(int), bricked.screenshot().astype(int)
                grey = np.abs(a - b).max(axis=-1)
                times = {"one": [], "bricked": []}
                for _ in range(2):
                    frame(one), frame(bricked)
                for _ in range(7):
                    times["one"].append(frame(one))
                    times["bricked"].append(frame(bricked))
                cost_one, cost = one.mapper.GetLastFrameCost(), bricked.mapper.GetLastFrameCost()
                t1, t2 = statistics.median(times["one"]), statistics.median(times["bricked"])
                out[f"{size}^3 limit {limit} {method} tolerance {tolerance:g}"] = {
                    "bricks": bricked.mapper.GetNumberOfBricks(),
                    "within_1": float((grey <= 1).mean()), "exact": float((grey == 0).mean()),
                    "max_grey_difference": int(grey.max()), "picture_max": int(b.max()),
                    "ms_one_texture": round(1e3 * t1, 2), "ms_bricked": round(1e3 * t2, 2),
                    "time_ratio": round(t2 / t1, 2),
                    "rays_one_texture": cost_one["rays"], "rays_levels": cost["rays"],
                    "rays_bricks": cost["brick_rays"], "full_quality_rays": cost["full_rays"]}
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
