"""Frame-time ratios to stock VTK MIP of mip, DEMIP and analytic MIP, in one process: compare versions.

Run it with each installed version's Python, alternating, on an idle machine
(vessels 128^3, 256^2, oblique, full-range window; medians of 7 interleaved
rounds of 3 frames after warm-up), e.g.

    cd /tmp && for i in 1 2 3; do old/bin/python tests/version_ratio_check.py; python3 tests/version_ratio_check.py; done

Prints one JSON line: the ratios and the medians in ms.
"""
import json
import statistics

from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView


def ratios() -> dict:
    """Median frame time of each method over stock's, and the medians in ms."""
    image = make_fixture("vessels", size=128)
    window = image.GetPointData().GetScalars().GetRange(0)
    views = {m: OffscreenView(image, m, size=(256, 256), view="oblique", window=window)
             for m in ("stock", "mip", "demip", "analytic")}
    times = {m: [] for m in views}
    for view in views.values():
        view.frame_times(frames=2, warmup=2)
    for _ in range(7):
        for m, view in views.items():
            times[m] += view.frame_times(frames=3, warmup=1)
    med = {m: statistics.median(t) for m, t in times.items()}
    return {"ratio": {m: round(med[m] / med["stock"], 3) for m in med},
            "ms": {m: round(1000 * med[m], 2) for m in med}}


if __name__ == "__main__":
    print(json.dumps(ratios()))
