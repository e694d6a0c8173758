"""Rays sampled past the shader loop limit: sampled MIP (mipcast's and stock VTK's) against the float64
sampled reference on the same rays, with mipcast's refusal (``MAX_SAMPLES_PER_RAY``) lifted for the run.

    python tests/loop_limit_check.py [--size 24] [--per-voxel 1000 2100 2500 4000]

The vessels 32³, front view, window 0.2-1; prints per rate the samples on the longest ray and the worst
error in % of the data range over the pixels both hit (docs/reliability.md, "Degenerate input").
"""
import argparse

import numpy as np

import mipcast.core.validation as validation
from mipcast import reference
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=24)
    parser.add_argument("--per-voxel", type=float, nargs="+", default=[1000, 2100, 2500, 4000])
    args = parser.parse_args()
    validation.MAX_SAMPLES_PER_RAY = 2 ** 40  # measure past the limit
    image = make_fixture("vessels", size=32)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    size = (args.size, args.size)
    for per_voxel in args.per_voxel:
        distance = 1.0 / per_voxel
        view = OffscreenView(image, "mip", size=size, view="front", sample_distance=distance, window=(0.2, 1.0))
        exact = reference.render(image, view.camera, size, method="mip", sample_distance=distance)
        both = np.isfinite(exact)
        row = [f"{per_voxel:g} samples/voxel ({31 * per_voxel:.0f} on a ray)"]
        for method in ("mip", "stock"):
            values = OffscreenView(image, method, size=size, view="front", sample_distance=distance,
                                   window=(0.2, 1.0)).float_image() if method == "mip" else None
            if values is None:  # stock VTK has no float readout: its 8-bit grey against the reference's
                grey = OffscreenView(image, method, size=size, view="front", sample_distance=distance,
                                     window=(0.2, 1.0)).screenshot()[..., 0].astype(float)
                expected = np.clip((exact - 0.2) / 0.8, 0, 1) * 255
                error = np.nanmax(np.abs(grey - np.nan_to_num(expected))[both]) / 255 * 0.8 / (high - low)
            else:
                hit = both & np.isfinite(values)
                error = float(np.max(np.abs(values[hit] - exact[hit]))) / (high - low)
            row.append(f"{method} {100 * error:.3g} %")
        print(", ".join(row))


if __name__ == "__main__":
    main()
