"""Analytic MIP against the exact float64 reference: the accuracy table of issue #3.

Usage (from the repository root)::

    python3 tests/analytic_accuracy.py            # Markdown table on stdout

Per fixture (vessels, spheres, noise at 64^3, and the head CT when
installed) and view (oblique orthographic, perspective), at 128 x 128:
the share of hit pixels whose float readout is within 1e-3 of the data
range of the exact maximum, its largest error, and the share of hit pixels
whose 8-bit grey is within one level of the reference's.  The pass/fail
thresholds are asserted in tests/test_analytic.py; this prints the numbers.
"""
import numpy as np

from mipcast import reference
from mipcast.data_fixtures import head_ct_path, load_head_ct, make_fixture
from mipcast.offscreen import OffscreenView


def accuracy_rows(size=(128, 128)):
    scenes = [(name, make_fixture(name, size=64)) for name in ("vessels", "spheres", "noise")]
    if head_ct_path() is not None:
        scenes.append(("head CT", load_head_ct()))
    rows = []
    for name, image in scenes:
        low, high = image.GetPointData().GetScalars().GetRange(0)
        for view in ("oblique", "perspective"):
            gpu = OffscreenView(image, "analytic", size=size, view=view, window="full")
            values, picture = gpu.float_image(), gpu.screenshot()
            exact = reference.render(image, gpu.camera, size, method="analytic")
            hits = ~np.isnan(exact) & ~np.isnan(values)
            error = np.abs(values[hits] - exact[hits]) / (high - low)
            grey = np.abs(picture[..., 0][hits] - np.round(255 * (exact[hits] - low) / (high - low)))
            rows.append((name, view, float(np.mean(error <= 1e-3)), float(error.max()), float(np.mean(grey <= 1))))
    return rows


if __name__ == "__main__":
    print("| scene | view | float within 1e-3 of range | largest float error (of range) | 8-bit within 1 grey |")
    print("| --- | --- | --- | --- | --- |")
    for name, view, ok, worst, grey in accuracy_rows():
        print(f"| {name} | {view} | {100 * ok:.2f} % | {worst:.2g} | {100 * grey:.2f} % |")
