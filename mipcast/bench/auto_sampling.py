"""Sampling chosen by the scene: the cheapest sample distance that meets an error target.

Sampled MIP misses maxima that fall between samples; how badly depends on
the data (thin bright structures need dense samples, smooth data does not)
and on the view.  :func:`choose_samples_per_voxel` calibrates on the scene
itself: on a coarse grid of the same camera's rays it compares the float64
reference of sampled MIP (:func:`mipcast.reference.render`, which takes the
GPU's own sample positions) with the exact maximum, for increasing sampling
rates, and returns the lowest rate that meets the target (a bisection over
:data:`CANDIDATES`: the error falls as the rate grows).  The calibration runs
on the CPU (0.5-7 s for a 128^3 volume, most of it in the densest candidates
tried) and needs no GPU.
"""
from __future__ import annotations

from typing import NamedTuple, Sequence

import numpy as np
from vtkmodules.vtkRenderingCore import vtkCamera

from mipcast import reference
from mipcast.core.validation import check_image, check_positive, samples_per_ray_problem

#: Samples per voxel tried, cheapest first.
CANDIDATES = (1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0, 16.0, 24.0, 32.0)


class AutoSampling(NamedTuple):
    """What :func:`choose_samples_per_voxel` chose, and why."""

    samples_per_voxel: float
    sample_distance: float
    within_target: float       # share of calibration rays within the error tolerance
    met: bool                  # False: even the densest candidate missed the target
    calibration_rays: int


def choose_samples_per_voxel(image, camera, size: Sequence[int], grey_levels: float = 1.0,
                             share: float = 0.99, window=None, calibration_width: int = 96,
                             margin: float = 0.003) -> AutoSampling:
    """The fewest samples per voxel whose sampled MIP is within ``grey_levels`` on ``share`` of pixels.

    Parameters
    ----------
    image : vtkImageData
        The volume.
    camera : vtkCamera
        The view (copied, not modified).
    size : sequence of int
        The window (width, height); the calibration keeps its aspect ratio.
    grey_levels : float, default: 1.0
        Error tolerance in grey levels of ``window``.
    share : float, default: 0.99
        Share of hit pixels that must be within the tolerance.
    window : tuple of float, optional
        Display window; default the data range.
    calibration_width : int, default: 96
        Width in pixels of the calibration grid (a subset of the rays).
    margin : float, default: 0.003
        The calibration must reach ``share + margin``: its rays are a sample
        of the image's, so a little headroom keeps the full image on target.

    Returns
    -------
    AutoSampling

    Examples
    --------
    >>> from mipcast.offscreen import OffscreenView
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("noise", size=24)
    >>> view = OffscreenView(image, "mip", size=(64, 64))
    >>> choice = choose_samples_per_voxel(image, view.camera, (64, 64))
    >>> choice.met, choice.samples_per_voxel  # smooth noise, but only 24 voxels across
    (True, 32.0)
    """
    check_image(image)
    check_positive("grey_levels", grey_levels)
    if not 0.0 < share <= 1.0:
        raise ValueError(f"share must be in (0, 1], got {share}")
    low, high = window if window is not None else image.GetPointData().GetScalars().GetRange(0)
    tolerance = grey_levels * (high - low) / 255.0
    width = min(int(size[0]), max(8, int(calibration_width)))
    calibration = (width, max(1, int(round(width * size[1] / size[0]))))
    view = vtkCamera()
    view.DeepCopy(camera)
    exact = reference.render(image, view, calibration, method="analytic")
    hits = ~np.isnan(exact)
    spacing = min(abs(s) for s in image.GetSpacing())
    goal = min(1.0, share + margin)

    def within(rate: float) -> float:
        sampled = reference.render(image, view, calibration, method="mip", sample_distance=spacing / rate)
        return float(np.mean(np.abs(sampled[hits] - exact[hits]) <= tolerance)) if hits.any() else 1.0

    # rates a ray can take (at most MAX_SAMPLES_PER_RAY samples along the volume's diagonal)
    candidates = [rate for rate in CANDIDATES if samples_per_ray_problem(image, spacing / rate) is None] or [1.0]
    low_index, high_index = 0, len(candidates) - 1
    best = within(candidates[high_index])
    if best < goal:
        return AutoSampling(candidates[-1], spacing / candidates[-1], best, False, int(hits.sum()))
    while low_index < high_index:  # invariant: candidates[high_index] meets the goal
        middle = (low_index + high_index) // 2
        share_met = within(candidates[middle])
        if share_met >= goal:
            high_index, best = middle, share_met
        else:
            low_index = middle + 1
    rate = candidates[high_index]
    return AutoSampling(rate, spacing / rate, best, True, int(hits.sum()))
