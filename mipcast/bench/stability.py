"""Where each method degrades: measured cases for ``mipcast bench --stability``.

Each case builds a small scene that stresses one known weak point, renders
it with the method and measures it on the same rays; the report pairs the
numbers with a one-line explanation.  What is measured depends on the
method (column ``measured``):

- ``mip`` / ``analytic`` (and the other projections): the float readout
  against the exact float64 reference of the method's own projection
  (maximum, minimum or average).
- ``demip``: the GPU's depth readout against the float64 DEMIP reference
  (p99 and max in % of the box depth; within 1 grey: the picture against
  the reference's), plus ``depth_jump``: the mean depth step between
  neighbouring pixels (% of the box depth), which shows noisy depth.
- ``foveated``: the float readout against the exact maximum over the whole
  picture, and ``fovea_within_1_grey``: the foveal disc against the same
  method at full quality (``fovea_structure_within_1_grey``: over the
  disc's pixels where full quality shows structure, i.e. is not black).
"""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast import reference
from mipcast.bench.benchmark import apply_settings
from mipcast.data_fixtures import image_from_array, make_fixture
from mipcast.core.metrics import summary
from mipcast.offscreen import OffscreenView
from mipcast.core.parameters import snake_name


class Case(NamedTuple):
    """One stress case: how to build it and what it shows."""

    method: str
    name: str
    build: Callable[[], tuple]       # -> (image, view preset, camera adjustment or None, samples per voxel)
    explanation: str
    settings: tuple = ()             # (Name, value) pairs for the mapper's SetName
    size: tuple = (96, 96)
    window: object = "full"          # the grey window (OffscreenView's ``window``): the data range


def _image(values: np.ndarray, spacing=(1.0, 1.0, 1.0)) -> vtkImageData:
    return image_from_array(np.asarray(values, np.float32), spacing=spacing)


def _random(shape, seed=0, power=1.0):
    return np.random.default_rng(seed).random(shape) ** power


def _specks(edge: int = 32, count: int = 100, seed: int = 1) -> vtkImageData:
    """Single voxels of value 1 at random points of a zero volume: structures of one voxel."""
    values = np.zeros((edge,) * 3)
    points = np.random.default_rng(seed).integers(2, edge - 2, size=(count, 3))
    values[points[:, 0], points[:, 1], points[:, 2]] = 1.0
    return _image(values)


#: Specks whose peak only just clears the window's floor: their visible part is smaller than a pixel or two.
SPECK_WINDOW = (0.6, 1.0)


def _orthographic(focal, position, up, scale) -> Callable:
    """A camera adjustment: look at ``focal`` from ``position``, orthographic with parallel ``scale``."""
    def adjust(camera):
        camera.SetFocalPoint(*focal)
        camera.SetPosition(*position)
        camera.SetViewUp(*up)
        camera.SetParallelProjection(True)
        camera.SetParallelScale(scale)
    return adjust


_along_grid_lines = _orthographic((8.0, 8.0, 8.0), (8.0, 8.0, 60.0), (0.0, 1.0, 0.0), 8.25)
_grazing = _orthographic((8.0, 8.0, 4.0), (48.0, 48.0, 4.0), (0.0, 0.0, 1.0), 6.0)


def _zoom_in(camera):
    camera.Zoom(2.5)


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
    Case("demip", "noisy background, threshold 1e-4 (depth of the maximum itself)",
         lambda: (make_fixture("noise", 48), "oblique", None, 1.0),
         "a tiny threshold tracks the maximum sample itself, which jumps from pixel to pixel on noise "
         "(as the paper says): the depth is right but noisy", (("MaterialThreshold", 1e-4),)),
    Case("demip", "noisy background, threshold 0.1 (default)", lambda: (make_fixture("noise", 48), "oblique", None, 1.0),
         "the default threshold finds the first sample of the maximum's material: smoother depth"),
    Case("demip", "noisy background, threshold 0.5", lambda: (make_fixture("noise", 48), "oblique", None, 1.0),
         "a wide threshold merges the maximum's material with dimmer tissue in front: smooth, shallower "
         "depth", (("MaterialThreshold", 0.5),)),
    Case("demip", "threshold 0.9 (first faint tissue)", lambda: (make_fixture("vessels", 48), "oblique", None, 1.0),
         "a large threshold stops at the first sample above the floor: depth of the first faint "
         "tissue, not of the brightest structure", (("MaterialThreshold", 0.9),)),
    Case("demip", "grazing rays at the box edge", lambda: (_image(_random((9, 9, 9), 8)), "front", _grazing, 1.0),
         "very short rays: one or two samples; first and second march agree with the reference"),
    Case("foveated", "thin vessels, default radius (whole picture)",
         lambda: (make_fixture("vessels", 48), "oblique", None, 1.0),
         "coarser levels blur thin vessels away from the gaze (by design); inside the radius the "
         "picture is full quality", size=(128, 128)),
    Case("foveated", "'level' sampling when zoomed in",
         lambda: (make_fixture("vessels", 48), "oblique", _zoom_in, 1.0),
         "the paper's fixed schedule reads 4x-max-filtered voxels at 4 pixels per voxel: thin vessels "
         "widen far beyond their size; the default sampling does not", (("PeripheralSampling", "level"),),
         size=(128, 128)),
    Case("foveated", "window too small for a pyramid (8 x 8)",
         lambda: (make_fixture("vessels", 48), "oblique", None, 1.0),
         "levels under 4 texels across are not used: the picture is the method at full quality (the "
         "error is sampled MIP's own at 8 x 8)", size=(8, 8)),
    Case("foveated", "specks just above the window floor, acuity only",
         lambda: (_specks(), "oblique", None, 1.0),
         "one-voxel specks whose peak clears the floor by 0.4 of their height (window 0.6-1): acuity-only "
         "foveation casts every fovea ray, so the fovea shows them all", size=(128, 128), window=SPECK_WINDOW),
    Case("foveated", "specks just above the window floor, content-adaptive 2 grey",
         lambda: (_specks(), "oblique", None, 1.0),
         "the same specks: most fall between the deciding level's rays (4 pixels apart), which see "
         "nothing above the floor; the data's structure bound casts the fovea's rays there, so the fovea "
         "shows them all (without it: a third of its structure pixels)", (("ContentTolerance", 2.0),),
         size=(128, 128), window=SPECK_WINDOW),
)



def cases() -> tuple:
    """:data:`CASES`, plus a thin-vessel case for every method of the table that has none.

    Every method with a float readout is measured: those without a case of
    their own get the default scene (thin vessels, one sample per voxel
    where the method samples).

    Examples
    --------
    >>> import mipcast
    >>> {case.method for case in cases()} >= {"mip", "analytic", "demip", "foveated"}
    True
    """
    from mipcast.methods import METHODS

    covered = {case.method for case in CASES}
    extra = tuple(
        Case(name, "thin vessels, defaults",
             lambda rate=(None if method.walks_cells else 1.0): (make_fixture("vessels", 48), "oblique", None, rate),
             "the method's default settings on the thin-vessel fixture")
        for name, method in METHODS.items() if method.float_readout and name not in covered)
    return CASES + extra

def measure(case: Case, size=None) -> dict:
    """Render one case and measure it (see the module docstring for what, per method).

    Examples
    --------
    >>> row = measure(CASES[9], size=(32, 32))
    >>> row["method"], row["within_1_grey"]
    ('analytic', 1.0)
    """
    size = tuple(size or case.size)
    image, view, adjust, rate = case.build()
    spacing = min(abs(s) for s in image.GetSpacing())
    scene = OffscreenView(image, case.method, size=size, view=view,
                          sample_distance=spacing / rate if rate else None, window=case.window)
    apply_settings(scene.mapper, case.settings)
    if adjust is not None:
        adjust(scene.camera)
        scene.renderer.ResetCameraClippingRange()
    row = {"method": case.method, "case": case.name}
    if case.method == "demip":
        row.update(_demip_figures(scene, dict(case.settings)))
    else:
        from mipcast.methods import METHODS

        values = scene.float_image()
        projection = METHODS[case.method].projection  # the exact reference of the method's own projection
        exact = METHODS[case.method].exact_reference(image, scene.camera, size)
        low, high = image.GetPointData().GetScalars().GetRange(0)
        stats = summary(values, exact, high - low)
        row.update(measured=f"{_MEASURED[projection]} vs exact", p99_pct=stats["p99_pct"], max_pct=stats["max_pct"],
                   within_1_grey=stats["within_1_grey"])
        if case.method == "foveated":
            row["fovea_within_1_grey"], row["fovea_structure_within_1_grey"] = _fovea_agreement(
                scene, image, view, adjust, size, case.window)
    row["explanation"] = case.explanation
    return row


#: What a projection's float readout is compared as.
_MEASURED = {"mip": "maximum", "minip": "minimum", "average": "average"}


def _demip_figures(scene: OffscreenView, settings: dict) -> dict:
    from mipcast.mappers.demip import render_depth

    depth = render_depth(scene.render_window, scene.mapper)
    params = {"sample_distance": scene.sample_distance, "window": scene.window}
    params.update({snake_name(name): value for name, value in settings.items()})
    expected = reference.render(scene.image, scene.camera, scene.size, method="demip", output="depth", **params)
    rgb = reference.render(scene.image, scene.camera, scene.size, method="demip", output="rgb", **params)
    both = ~np.isnan(depth) & ~np.isnan(expected)
    error = 100.0 * np.abs(depth[both] - expected[both])
    hits = ~np.isnan(rgb[..., 0])
    grey = np.abs(scene.screenshot()[..., :3].astype(float) - np.round(255 * np.nan_to_num(rgb))).max(axis=-1)
    steps = np.abs(np.diff(depth, axis=1))
    return {"measured": "depth vs DEMIP reference", "p99_pct": float(np.percentile(error, 99)) if both.any() else 0.0,
            "max_pct": float(error.max(initial=0.0)), "within_1_grey": float(np.mean(grey[hits] <= 1)),
            "depth_jump_pct": float(100.0 * np.nanmean(steps)) if np.isfinite(steps).any() else 0.0,
            "pixels_with_depth": float(both.mean())}


def _fovea_agreement(scene: OffscreenView, image, view: str, adjust, size, window="full") -> tuple:
    """Shares of the foveal disc's pixels within one grey of full quality: (all, where full quality is not black)."""
    full = OffscreenView(image, scene.mapper.GetMethod(), size=size, view=view, window=window)
    if adjust is not None:
        adjust(full.camera)
        full.renderer.ResetCameraClippingRange()
    from mipcast.core.foveation import eccentricity

    inside = eccentricity(size, scene.mapper.GetGazePoint(), size[0] / size[1]) <= scene.mapper.GetFovealRadius()
    reference_picture = full.screenshot()[..., :3].astype(int)
    error = np.abs(scene.screenshot()[..., :3].astype(int) - reference_picture).max(axis=-1)
    structure = inside & (reference_picture.max(axis=-1) > 0)
    return tuple(float(np.mean(error[where] <= 1)) if where.any() else float("nan") for where in (inside, structure))
