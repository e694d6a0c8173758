"""Bricked analytic MIP vs one texture at the same size: accuracy against float64 and frame time.

Usage: python tests/bricks_timing.py (prints JSON; figures in docs/reliability.md, "GPU limits and memory").
"""
import json, time, statistics
import numpy as np
from mipcast.offscreen import OffscreenView
from mipcast.data_fixtures import make_fixture
from mipcast.mappers import gpu_limits
from mipcast.methods import METHODS

def main() -> dict:
    out = {}
    for size, limit in ((40, 16), (64, 33), (64, 24)):
        image = make_fixture("vessels", size=size)
        low, high = image.GetPointData().GetScalars().GetRange(0)
        whole = OffscreenView(image, "analytic", size=(128, 128), view="oblique", window="full")
        real = gpu_limits.max_texture_size_3d
        gpu_limits.max_texture_size_3d = lambda w, limit=limit: limit
        bricked = OffscreenView(image, "analytic", size=(128, 128), view="oblique", window="full")
        got = bricked.float_image()
        gpu_limits.max_texture_size_3d = real
        ref = METHODS["analytic"].reference(image, bricked.camera, bricked.size, sample_distance=bricked.sample_distance, window=bricked.window)
        one = whole.float_image()
        err_ref = float(np.nanmax(np.abs(got - ref)) / (high - low))
        err_one = float(np.nanmax(np.abs(got - one)) / (high - low))
        err_one_ref = float(np.nanmax(np.abs(one - ref)) / (high - low))
        # frame time: float readout (the bricked picture is made from readouts), interleaved, medians
        tw, tb = [], []
        for _ in range(2):
            whole.float_image(); bricked.float_image()
        for _ in range(9):
            t = time.perf_counter(); whole.float_image(); tw.append(time.perf_counter() - t)
            t = time.perf_counter(); bricked.float_image(); tb.append(time.perf_counter() - t)
        # the displayed picture: GPU screenshot vs composed bricks
        ts, tbs = [], []
        for _ in range(5):
            t = time.perf_counter(); whole.screenshot(); ts.append(time.perf_counter() - t)
            gpu_limits.max_texture_size_3d = lambda w, limit=limit: limit
            t = time.perf_counter(); bricked.screenshot(); tbs.append(time.perf_counter() - t)
            gpu_limits.max_texture_size_3d = real
        rgb = np.abs(whole.screenshot().astype(int) - bricked.screenshot().astype(int)).max()
        out[f"{size}^3 limit {limit}"] = {
            "bricks": bricked.mapper.GetNumberOfBricks(),
            "max_err_vs_float64_of_range": err_ref, "max_err_vs_unbricked_of_range": err_one,
            "unbricked_err_vs_float64_of_range": err_one_ref,
            "readout_ms_unbricked": round(1000 * statistics.median(tw), 1),
            "readout_ms_bricked": round(1000 * statistics.median(tb), 1),
            "screenshot_ms_unbricked": round(1000 * statistics.median(ts), 1),
            "screenshot_ms_bricked": round(1000 * statistics.median(tbs), 1),
            "rgb_max_diff": int(rgb)}
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
