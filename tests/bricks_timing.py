"""Bricked rendering inside a plain VTK pipeline vs one texture: agreement and frame time.

The 3D texture limit is lowered (``gpu_limits.max_texture_size_3d``) so that the mapper draws
the volume in bricks inside ``vtkRenderWindow.Render()``.  For each volume/limit and method:
bricks per frame, frame time (Render + WaitForCompletion, medians of interleaved frames after
warm-up), the float readout's largest error against one texture and against the float64
reference (fractions of the data range), and the RGB picture's agreement.

Usage: python tests/bricks_timing.py (prints JSON; figures in docs/reliability.md,
"GPU limits and memory").
"""
import json
import statistics
import time

import numpy as np

from mipcast.data_fixtures import make_fixture
from mipcast.mappers import gpu_limits
from mipcast.mappers.float_readout import render_float
from mipcast.methods import METHODS
from test_bricked_mapper import DISTANCE, pipeline, picture

SIZE = (128, 128)


def frame(window) -> float:
    start = time.perf_counter()
    window.Render()
    window.WaitForCompletion()
    return time.perf_counter() - start


def main() -> dict:
    import test_bricked_mapper

    test_bricked_mapper.SIZE = SIZE
    real = gpu_limits.max_texture_size_3d
    out = {}
    for size, limit in ((48, 20), (64, 33), (64, 24)):
        image = make_fixture("vessels", size=size)
        low, high = image.GetPointData().GetScalars().GetRange(0)
        for name in ("analytic", "mip"):
            one_mapper, _, one_window = pipeline(image, name)
            one_rgb, one = picture(one_window), render_float(one_window, one_mapper)
            gpu_limits.max_texture_size_3d = lambda window, limit=limit: limit
            try:
                mapper, renderer, window = pipeline(image, name)
                rgb, got = picture(window), render_float(window, mapper)
                expected = METHODS[name].reference(image, renderer.GetActiveCamera(), SIZE,
                                                   sample_distance=DISTANCE, window=(low, high))
                times_one, times_bricked = [], []
                for _ in range(2):
                    frame(one_window), frame(window)
                for _ in range(7):
                    times_one.append(frame(one_window))
                    times_bricked.append(frame(window))
                bricks = mapper.GetNumberOfBricks()
            finally:
                gpu_limits.max_texture_size_3d = real
            both = np.isfinite(got) & np.isfinite(one)
            ref = np.isfinite(got) & np.isfinite(expected)
            difference = np.abs(rgb - one_rgb).max(axis=-1)
            one_ms, bricked_ms = 1000 * statistics.median(times_one), 1000 * statistics.median(times_bricked)
            out[f"{name} {size}^3 limit {limit}"] = {
                "bricks_per_frame": bricks,
                "frame_ms_one_texture": round(one_ms, 1), "frame_ms_bricked": round(bricked_ms, 1),
                "ratio": round(bricked_ms / one_ms, 1),
                "same_hit_pixels": float(np.mean(np.isnan(got) == np.isnan(one))),
                "max_err_vs_one_texture": float(np.max(np.abs(got[both] - one[both])) / (high - low)),
                "max_err_vs_float64": float(np.max(np.abs(got[ref] - expected[ref])) / (high - low)),
                "rgb_max_diff": int(difference.max()),
                "rgb_within_1": float(np.mean(difference <= 1))}
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
