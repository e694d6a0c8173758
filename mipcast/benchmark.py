"""Frame-time ratios between methods, measured in one process on one scene.

llvmpipe (and any shared machine) drifts, so methods are timed in
interleaved rounds: each round renders every method a few frames, and each
method's time is the median over all its frames after warm-up.  Only ratios
measured this way mean something.
"""
from __future__ import annotations

import statistics
from typing import Iterable, Sequence

from .offscreen import OffscreenView


def time_methods(image, methods: Sequence[str], size=(256, 256), view: str = "oblique",
                 rounds: int = 5, frames: int = 3, warmup: int = 3,
                 sample_distance=None) -> dict:
    """Median frame time in seconds of each method, measured in interleaved rounds.

    Parameters
    ----------
    image : vtkImageData
        The scene's volume.
    methods : sequence of str
        Names from :data:`mipcast.methods.METHODS`; the first is the baseline.
    size : tuple of int, default: (256, 256)
        Window (width, height).
    view : str, default: "oblique"
        A preset of :data:`mipcast.offscreen.VIEWS`.
    rounds, frames, warmup : int
        ``rounds`` x ``frames`` timed frames per method, after ``warmup``.
    sample_distance : float, optional
        Passed to every view (default: one sample per voxel).

    Returns
    -------
    dict
        ``{method: {"median_s": float, "ratio": float, "frames": int}}`` with
        ``ratio`` = median / baseline median.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> times = time_methods(make_fixture("spheres", size=16), ["stock", "mip"],
    ...                      size=(32, 32), rounds=1, frames=1, warmup=1)
    >>> times["stock"]["ratio"]
    1.0
    """
    views = {m: OffscreenView(image, m, size=size, view=view, sample_distance=sample_distance)
             for m in methods}
    samples: dict = {m: [] for m in methods}
    for method, view_ in views.items():
        view_.frame_times(frames=0, warmup=warmup)
    for _ in range(rounds):
        for method, view_ in views.items():
            samples[method].extend(view_.frame_times(frames=frames, warmup=0))
    baseline = statistics.median(samples[methods[0]])
    return {m: {"median_s": statistics.median(t), "ratio": statistics.median(t) / baseline,
                "frames": len(t)} for m, t in samples.items()}


def markdown_table(rows: Iterable[dict], columns: Sequence[str]) -> str:
    """Format dict rows as a Markdown table with the given columns.

    Examples
    --------
    >>> print(markdown_table([{"a": 1, "b": 0.5}], ["a", "b"]))
    | a | b |
    | --- | --- |
    | 1 | 0.5 |
    """
    def cell(value):
        return f"{value:.3g}" if isinstance(value, float) else str(value)
    lines = ["| " + " | ".join(columns) + " |", "| " + " | ".join("---" for _ in columns) + " |"]
    lines += ["| " + " | ".join(cell(row.get(c, "")) for c in columns) + " |" for row in rows]
    return "\n".join(lines)
