"""Where each method degrades: measured cases for ``mipcast bench --stability``.

Each case builds a small scene that stresses one known weak point, renders
it with the method, and measures the error of the float readout against the
exact float64 reference on the same rays; the report pairs the number with a
one-line explanation.
"""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData

from . import reference
from .data_fixtures import image_from_array, make_fixture
from .metrics import summary
from .offscreen import OffscreenView


class Case(NamedTuple):
    """One stress case: how to build it and what it shows."""

    method: str
    name: str
    build: Callable[[], tuple]       # -> (image, view preset, camera adjustment or None, params)
    explanation: str


def _image(values: np.ndarray, spacing=(1.0, 1.0, 1.0)) -> vtkImageData:
    return image_from_array(np.asarray(values, np.float32), spacing=spacing)


def _random(shape, seed=0, power=1.0):
    return np.random.default_rng(seed).random(shape) ** power


def _along_grid_lines(camera):
    camera.SetFocalPoint(8.0, 8.0, 8.0)
    camera.SetPosition(8.0, 8.0, 60.0)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetParallelProjection(True)
    camera.SetParallelScale(8.25)


def _grazing(camera):
    camera.SetFocalPoint(8.0, 8.0, 4.0)
    camera.SetPosition(48.0, 48.0, 4.0)
    camera.SetViewUp(0.0, 0.0, 1.0)
    camera.SetParallelProjection(True)
    camera.SetParallelScale(6.0)


CASES = (
    Case("mip", "thin vessels, 1 sample/voxel", lambda: (make_fixture("vessels", 48), "oblique", None, 1.0),
         "maxima of thin structures fall between samples; the error shrinks only slowly with the rate"),
    Case("mip", "thin vessels, 8 samples/voxel", lambda: (make_fixture("vessels", 48), "oblique", None, 8.0),
         "8x costs about 6x the time and still misses peaks on the box faces (no sample at the ray ends)"),
    Case("mip", "anisotropic 1:20, 1 sample per smallest voxel",
         lambda: (_image(_random((10, 12, 14), 9, 4), (1.0, 1.0, 20.0)), "perspective", None, 1.0),
         "spiky data in 1:20 cells: one sample per smallest spacing still misses most cell peaks"),
    Case("mip", "smooth data, 1 sample/voxel", lambda: (make_fixture("spheres", 48), "oblique", None, 1.0),
         "smooth blobs: the smallest error of the sampled cases, still above 1 grey at rims and box faces"),
    Case("analytic", "thin vessels", lambda: (make_fixture("vessels", 48), "oblique", None, None),
         "exact per cell: float32 rounding only"),
    Case("analytic", "rays along voxel planes (pixel centres on grid lines)",
         lambda: (_image(_random((17, 17, 17), 7)), "front", _along_grid_lines, None),
         "ties in the cell walk: the cell is chosen by the segment midpoint, all tied axes step"),
    Case("analytic", "grazing rays at the box edge", lambda: (_image(_random((9, 9, 9), 8)), "front", _grazing, None),
         "near-zero segments: the cubic from corners needs no fit, so no ill-conditioning"),
    Case("analytic", "anisotropic 1:20", lambda: (_image(_random((10, 12, 14), 9, 4), (1.0, 1.0, 20.0)),
                                                  "perspective", None, None),
         "cells are walked in index space: spacing only changes the ray direction"),
    Case("analytic", "2x2x2 volume", lambda: (_image(_random((2, 2, 2), 10)), "perspective", None, None),
         "one cell: entry and exit faces only"),
    Case("analytic", "linear data (cubic degenerates to a line)",
         lambda: (_image(np.fromfunction(lambda k, j, i: 0.5 * i + 0.2 * j - 0.3 * k, (12, 10, 14))),
                  "perspective", None, None),
         "a ~ 0 and b ~ 0: the clamped, cancellation-free root formula falls back to the ends"),
)


def measure(case: Case, size=(96, 96)) -> dict:
    """Render one case and measure it against the exact reference.

    Examples
    --------
    >>> row = measure(CASES[-2], size=(32, 32))
    >>> row["method"], row["within_1_grey"]
    ('analytic', 1.0)
    """
    image, view, adjust, rate = case.build()
    spacing = min(abs(s) for s in image.GetSpacing())
    scene = OffscreenView(image, case.method, size=size, view=view,
                          sample_distance=spacing / rate if rate else None)
    if adjust is not None:
        adjust(scene.camera)
        scene.renderer.ResetCameraClippingRange()
    values = scene.float_image()
    exact = reference.render(image, scene.camera, size, method="exact")
    low, high = image.GetPointData().GetScalars().GetRange(0)
    stats = summary(values, exact, high - low)
    return {"method": case.method, "case": case.name, "p99_pct": stats["p99_pct"],
            "max_pct": stats["max_pct"], "within_1_grey": stats["within_1_grey"],
            "explanation": case.explanation}
