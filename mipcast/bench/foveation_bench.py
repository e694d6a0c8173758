"""Foveated rendering against the same method at full quality (``mipcast bench --foveation``).

Levoy & Whitaker's Table I on our scenes: frame time, rays cast and samples
taken, full quality / foveated, in one process (interleaved rounds, medians
after warm-up, auto-adjust and jitter off, as :mod:`mipcast.bench.benchmark`).
Two framings: ``"fill"`` zooms in until the volume fills the viewport (as a
radiologist reads a study: every pixel casts a long ray) and ``"whole"``
shows the whole volume (the central rays are the longest, so the fovea holds
more of the work and the saving is smaller).  Gaze at the centre and near a
corner.

Two figures explain each time ratio:

- ``ceiling``: full-quality samples over the samples of the foveal disc
  alone -- the speed-up of an ideal foveation whose blend zone and periphery
  cost nothing.  No design that draws the fovea at full quality beats it.
- error by eccentricity: the foveated picture against the same method at
  full quality, in grey levels, mean and p99 per ring of
  :data:`RING` viewport heights (:func:`ring_errors`), charted by
  :func:`write_ring_chart`.
"""
from __future__ import annotations

import statistics
from typing import Callable, Optional, Sequence

import numpy as np

from mipcast.bench.benchmark import apply_settings, interleaved_frame_times
from mipcast.core.foveation import eccentricity
from mipcast.core.object_state import object_state
from mipcast.offscreen import OffscreenView
from mipcast.core.ray_cost import grid_cost

#: Camera zoom after the whole volume is framed.
FRAMINGS = {"fill": 2.0, "whole": 1.0}
#: Variant key (not a mapper setting): build the content-adaptive masks on the CPU
#: (:func:`mipcast.mappers.foveated` reads the coarse picture back), as before they moved to the GPU.
MASKS_ON_CPU = "masks on CPU"
#: A variant's key for content-adaptive frames without the content level (acuity's coarsest level then cast over
#: the whole viewport unmasked): ``object_state(mapper)["no_content_level"]``, measured, not a setting.
NO_CONTENT_LEVEL = "no content level"
#: The variants' keys that are not mapper settings, and the object_state entries they set.
PRIVATE = {MASKS_ON_CPU: "masks_on_cpu", NO_CONTENT_LEVEL: "no_content_level"}
#: Gaze points, normalised viewport coordinates.
GAZES = {"centre": (0.5, 0.5), "corner": (0.1, 0.1)}
#: Foveated mapper settings compared with full quality ({} = the defaults).
VARIANTS = {
    "default": {},
    "radius 0.12": {"FovealRadius": 0.12},
    "radius 0.05, falloff 0.04": {"FovealRadius": 0.05, "Falloff": 0.04},
    "default, 'level' sampling": {"PeripheralSampling": "level"},
    "default, 4 levels": {"NumberOfLevels": 4},
    "content-adaptive 2 grey": {"ContentTolerance": 2.0},
    "content-adaptive 8 grey": {"ContentTolerance": 8.0},
    # the same masks built on the CPU from the coarse picture read back mid-frame (the path before the GPU masks)
    "content-adaptive 2 grey, CPU mask": {"ContentTolerance": 2.0, MASKS_ON_CPU: True},
    # acuity's coarsest level decides the finer ones alone: the content level pays on sparse scenes, costs on dense
    "content-adaptive 2 grey, no content level": {"ContentTolerance": 2.0, NO_CONTENT_LEVEL: True},
}
#: A gaze far outside the viewport: every pixel at the coarsest level.  Its
#: row times the periphery alone, a floor under any gaze's frame time where
#: the periphery covers most of the view (a corner gaze).
OFF_SCREEN = (-100.0, -100.0)
PERIPHERY_ONLY = "periphery alone | off-screen"
#: Width of an eccentricity ring, viewport heights.
RING = 0.025


def framed_view(image, method: str, size: int, framing: str, window=None) -> OffscreenView:
    """An oblique orthographic :class:`~mipcast.offscreen.OffscreenView` in a framing of :data:`FRAMINGS`.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = framed_view(make_fixture("spheres", size=16), "mip", 32, "fill")
    >>> view.camera.GetParallelScale() < framed_view(make_fixture("spheres", size=16), "mip", 32, "whole").camera.GetParallelScale()
    True
    """
    if framing not in FRAMINGS:
        raise ValueError(f"unknown framing {framing!r}; valid: {', '.join(map(repr, FRAMINGS))}")
    view = OffscreenView(image, method, size=(size, size), view="oblique", window=window)
    view.camera.Zoom(FRAMINGS[framing])
    view.renderer.ResetCameraClippingRange()
    return view


def fovea_share(view: OffscreenView, gaze: Sequence[float], radius: float,
                total_samples: Optional[int] = None) -> float:
    """Share of a full-quality frame's samples taken inside the foveal disc.

    ``1 / fovea_share`` is the ceiling of full / foveated time for any
    foveation that renders the disc at full quality.  ``total_samples``
    (the whole frame's, :func:`mipcast.core.ray_cost.grid_cost`) is counted here
    unless given, e.g. once for several gazes.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = framed_view(make_fixture("spheres", size=16), "mip", 32, "fill")
    >>> 0.0 < fovea_share(view, (0.5, 0.5), 0.2) < fovea_share(view, (0.5, 0.5), 0.4) < 1.0
    True
    """
    width, height = view.render_window.GetSize()
    distance = view.mapper.GetSampleDistance()
    inside = eccentricity((width, height), gaze, width / height) < radius
    total = total_samples if total_samples is not None else _frame_samples(view)
    _, fovea = grid_cost(view.image, view.camera, (width, height), (width, height), sample_distance=distance,
                         cast=inside)
    return fovea / total if total else 0.0


def _frame_samples(view: OffscreenView) -> int:
    width, height = view.render_window.GetSize()
    return grid_cost(view.image, view.camera, (width, height), (width, height),
                     sample_distance=view.mapper.GetSampleDistance())[1]


def ring_errors(full: np.ndarray, foveated: np.ndarray, gaze: Sequence[float], radius: float,
                ring: float = RING) -> dict:
    """Grey-level error of a foveated picture against full quality, by eccentricity.

    Parameters
    ----------
    full, foveated : numpy.ndarray, shape (height, width, 3 or 4), uint8
        Screenshots (top row first) of the same scene.
    gaze : (x, y)
        Normalised viewport coordinates.
    radius : float
        Foveal radius, viewport heights.
    ring : float
        Ring width, viewport heights.

    Returns
    -------
    dict
        ``fovea_within_1`` (share of pixels inside the radius within one
        grey level), ``fovea_structure_within_1`` (the same over the
        fovea's pixels where full quality shows structure: not the
        darkest value of ``full``), ``mean`` (all pixels),
        ``mean_outside`` (pixels outside the radius) and ``rings``: one dict per ring
        with ``e_from``, ``e_to``, ``pixels``, ``mean``, ``p99``, ``max``
        (largest channel difference per pixel).

    Examples
    --------
    >>> full = np.zeros((20, 20, 3), np.uint8)
    >>> blurred = full.copy(); blurred[:, :2] = 9          # errors on the left edge only
    >>> result = ring_errors(full, blurred, (0.5, 0.5), 0.2, ring=0.25)
    >>> result["fovea_within_1"], [r["max"] for r in result["rings"]], result["mean_outside"] > 0
    (1.0, [0, 9, 9], True)
    """
    height, width = full.shape[:2]
    e = eccentricity((width, height), gaze, width / height)
    error = np.abs(full[..., :3].astype(int) - foveated[..., :3].astype(int)).max(axis=-1)
    inside = e <= radius
    rings = []
    edges = np.arange(0.0, float(e.max()) + ring, ring)
    for low, high in zip(edges[:-1], edges[1:]):
        values = error[(e >= low) & (e < high)]
        if values.size:
            rings.append({"e_from": float(low), "e_to": float(high), "pixels": int(values.size),
                          "mean": float(values.mean()), "p99": float(np.percentile(values, 99)),
                          "max": int(values.max())})
    grey = full[..., :3].max(axis=-1)
    structure = inside & (grey > grey.min())
    return {"fovea_within_1": float(np.mean(error[inside] <= 1)) if inside.any() else float("nan"),
            "fovea_structure_within_1": float(np.mean(error[structure] <= 1)) if structure.any() else float("nan"),
            "mean": float(error.mean()),
            "mean_outside": float(error[~inside].mean()) if (~inside).any() else float("nan"),
            "rings": rings}


def measure_foveation(image, scene: str, method: str = "mip", sizes: Sequence[int] = (512, 1024),
                      framings: Sequence[str] = ("fill", "whole"), variants: Optional[dict] = None,
                      gazes: Optional[dict] = None, rounds: int = 3, frames: int = 2, warmup: int = 3,
                      window=None, progress: Optional[Callable[[str], None]] = None) -> list:
    """Time, cost and error of foveated variants against ``method`` at full quality.

    Parameters
    ----------
    image : vtkImageData
        The scene's volume.
    scene : str
        Its name in the rows.
    method : str, default: "mip"
        A :func:`mipcast.mappers.foveated.layer_methods` name.
    sizes : sequence of int
        Square window edges.
    framings : sequence of str
        Keys of :data:`FRAMINGS`.
    variants, gazes : dict, optional
        Default :data:`VARIANTS`, :data:`GAZES`.
    rounds, frames, warmup : int
        Interleaved timing: ``rounds`` x ``frames`` frames per setting after ``warmup``.
    window : tuple of float, optional
        Grey window (default: the data range).
    progress : callable, optional
        Called with a short label after each step (timing round or measured row).

    Returns
    -------
    list of dict
        One row per size, framing and setting (the last, :data:`PERIPHERY_ONLY`,
        with the gaze off-screen): ``median_ms``, ``speedup``
        (full / this), and for foveated rows ``gaze``, ``radius``, ``rays``,
        ``samples``, ``ray_ratio``, ``sample_ratio`` (full / foveated),
        ``ceiling``, ``fovea_within_1``, ``mean_grey_error``, ``rings``.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = measure_foveation(make_fixture("spheres", size=16), "spheres", sizes=[32], framings=["fill"],
    ...                          variants={"default": {}}, gazes={"centre": (0.5, 0.5)}, rounds=1, frames=1,
    ...                          warmup=1)
    >>> [row["setting"] for row in rows], rows[0]["speedup"]
    (['full quality', 'foveation off', 'default | centre', 'periphery alone | off-screen'], 1.0)
    """
    variants = VARIANTS if variants is None else variants
    gazes = GAZES if gazes is None else gazes
    report = progress or (lambda label: None)
    rows = []
    for size in sizes:
        for framing in framings:
            views = {"full quality": framed_view(image, method, size, framing, window)}
            off = views["foveation off"] = framed_view(image, "foveated", size, framing, window)
            off.mapper.SetMethod(method)
            off.mapper.SetFoveation(False)
            for variant, settings in variants.items():
                for gaze_name, gaze in gazes.items():
                    view = views[f"{variant} | {gaze_name}"] = framed_view(image, "foveated", size, framing, window)
                    pairs = [(name, value) for name, value in settings.items() if name not in PRIVATE]
                    for key, entry in PRIVATE.items():
                        if settings.get(key):
                            object_state(view.mapper)[entry] = True
                    apply_settings(view.mapper, (("Method", method), *pairs, ("GazePoint", gaze)))
            floor = views[PERIPHERY_ONLY] = framed_view(image, "foveated", size, framing, window)
            apply_settings(floor.mapper, (("Method", method), ("GazePoint", OFF_SCREEN)))
            times = interleaved_frame_times(views, rounds, frames, warmup,
                                            lambda label: report(f"{scene} {size}² {framing}: {label}"))
            base = statistics.median(times["full quality"])
            full_picture = views["full quality"].screenshot()
            full_samples = _frame_samples(views["full quality"])
            for label, view in views.items():
                median = statistics.median(times[label])
                row = {"scene": scene, "method": method, "size": size, "framing": framing, "setting": label,
                       "median_ms": 1000 * median, "speedup": base / median, "frames": len(times[label])}
                if label != "full quality":
                    variant, _, gaze_name = label.partition(" | ")
                    row.update(variant=variant, gaze_name=gaze_name or "-")
                    row.update(_foveated_figures(views["full quality"], full_picture, full_samples, view))
                rows.append(row)
                report(f"{scene} {size}² {framing}: {label}")
            for view in views.values():
                view.render_window.Finalize()
    return rows


def _foveated_figures(full_view: OffscreenView, full_picture: np.ndarray, full_samples: int,
                      view: OffscreenView) -> dict:
    picture = view.screenshot()
    mapper = view.mapper
    gaze, radius = mapper.GetGazePoint(), mapper.GetFovealRadius()
    cost = mapper.GetLastFrameCost()
    errors = ring_errors(full_picture, picture, gaze, radius)
    share = fovea_share(full_view, gaze, radius, full_samples) if mapper.GetFoveation() else 1.0
    return {"gaze": list(gaze), "radius": radius, "falloff": mapper.GetFalloff(),
            "sampling": mapper.GetPeripheralSampling(), "rays": cost["rays"], "samples": cost["samples"],
            "ray_ratio": cost["ray_ratio"], "sample_ratio": cost["sample_ratio"],
            "ceiling": 1.0 / share if share > 0 else float("inf"),
            "fovea_within_1": errors["fovea_within_1"], "mean_grey_error": errors["mean"],
            "fovea_structure_within_1": errors["fovea_structure_within_1"],
            "mean_grey_error_outside": errors["mean_outside"],
            "content_tolerance": mapper.GetContentTolerance(),
            "rings": errors["rings"]}


def foveation_table(rows: Sequence[dict]) -> str:
    """Markdown: the paper's Table I line, then one line per foveated row.

    Examples
    --------
    >>> row = {"scene": "s", "method": "mip", "size": 8, "framing": "fill", "setting": "default | centre",
    ...        "speedup": 2.0, "ray_ratio": 3.0, "sample_ratio": 2.5, "ceiling": 6.9,
    ...        "fovea_within_1": 1.0, "mean_grey_error": 0.5}
    >>> print(foveation_table([row]).splitlines()[-1])
    | s mip 8² fill | default \\| centre | 3.00 | 2.50 | 2.00 | 6.9 | 100.0 % | 0.50 | - | - |
    """
    from mipcast.bench.paper_tables import LEVOY_TABLE_I

    lines = ["| scene | setting | rays full / foveated | samples full / foveated | time full / foveated "
             "| ceiling | fovea within 1 grey | mean grey error | fovea structure within 1 grey "
             "| mean grey error outside the fovea |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
             "| paper (Levoy & Whitaker 1990, Table I) | | {rays:.2f} | {samples:.2f} | {time:.2f} | | | | | |".format(
                 **LEVOY_TABLE_I)]
    for row in rows:
        if "ray_ratio" not in row:
            continue
        setting = row["setting"].replace("|", "\\|")
        lines.append(f"| {row['scene']} {row['method']} {row['size']}² {row['framing']} | {setting} | "
                     f"{row['ray_ratio']:.2f} | {row['sample_ratio']:.2f} | {row['speedup']:.2f} | "
                     f"{row['ceiling']:.1f} | {_share(row['fovea_within_1'])} | {row['mean_grey_error']:.2f} | "
                     f"{_share(row.get('fovea_structure_within_1', float('nan')))} | "
                     f"{_number(row.get('mean_grey_error_outside', float('nan')))} |")
    return "\n".join(lines)


def _number(value: float) -> str:
    return f"{value:.2f}" if np.isfinite(value) else "-"


def _share(fraction: float) -> str:
    """A fraction as a percentage; "-" when undefined (no fovea in view)."""
    return f"{100 * fraction:.1f} %" if np.isfinite(fraction) else "-"


def write_ring_chart(rows: Sequence[dict], path) -> None:
    """PNG: p99 and mean grey error against eccentricity.

    One panel per scene, size and framing (rows of the figure) and gaze
    (columns), one line pair per variant; the foveal radius is marked.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> row = {"scene": "s", "method": "mip", "size": 8, "framing": "fill", "variant": "default",
    ...        "gaze_name": "centre", "radius": 0.2,
    ...        "rings": [{"e_from": 0.0, "e_to": 0.1, "mean": 0.0, "p99": 0.0},
    ...                  {"e_from": 0.1, "e_to": 0.2, "mean": 1.0, "p99": 4.0}]}
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "rings.png"
    >>> write_ring_chart([row], out); out.stat().st_size > 0
    True
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chosen = [r for r in rows if r.get("rings") and r.get("gaze_name", "-") != "-" and r.get("setting") != PERIPHERY_ONLY]
    panels = sorted({(r["scene"], r["method"], r["size"], r["framing"]) for r in chosen})
    gazes = sorted({r["gaze_name"] for r in chosen})
    variants = list(dict.fromkeys(r["variant"] for r in chosen))
    figure, axes = plt.subplots(max(len(panels), 1), max(len(gazes), 1), squeeze=False,
                                figsize=(5.0 * max(len(gazes), 1), 3.4 * max(len(panels), 1)))
    for i, panel in enumerate(panels):
        for j, gaze in enumerate(gazes):
            axis = axes[i][j]
            for row in chosen:
                if (row["scene"], row["method"], row["size"], row["framing"]) != panel or row["gaze_name"] != gaze:
                    continue
                colour = f"C{variants.index(row['variant']) % 10}"
                middle = [0.5 * (ring["e_from"] + ring["e_to"]) for ring in row["rings"]]
                axis.plot(middle, [ring["p99"] for ring in row["rings"]], "-", color=colour, label=row["variant"])
                axis.plot(middle, [ring["mean"] for ring in row["rings"]], ":", color=colour)
                axis.axvline(row["radius"], color=colour, linewidth=0.6, alpha=0.6)
            axis.axhline(1.0, color="grey", linewidth=0.6)
            axis.set_title("{} {} {}² {}, gaze: ".format(*panel) + gaze, fontsize=9)
            axis.set_xlabel("eccentricity (viewport heights)", fontsize=8)
            axis.set_ylabel("grey error vs full quality\n(solid p99, dotted mean)", fontsize=8)
            axis.legend(fontsize=6)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)


def _last_picture(view: OffscreenView) -> np.ndarray:
    """The window's last rendered picture (RGB, top row first) without rendering again."""
    from mipcast.mappers.private_draw import read_rgba

    width, height = view.render_window.GetSize()
    return read_rgba(view.render_window, (0, 0, width, height))[::-1, :, :3].copy()


def measure_progressive(image, scene: str, method: str = "mip", size: int = 1024, framing: str = "fill",
                        refinement_frames: int = 4, gaze: Sequence[float] = (0.5, 0.5), window=None,
                        warmup: int = 2) -> dict:
    """Progressive refinement: time and rays of each still frame and whether it equals full quality.

    The foveated view (progressive on, default radius) renders the foveated
    frame, ``refinement_frames`` still frames and one more once converged
    (what drawing a still, refined view again costs), after a warm-up pass;
    each is timed and compared with the method at full quality pixel for
    pixel, and its rays counted (``GetLastFrameCost``, after the timing).

    Returns
    -------
    dict
        ``scene``, ``method``, ``size``, ``framing``, ``full_ms``,
        ``full_rays``, ``steps``: one dict per frame (``step``, ``ms``,
        ``rays``, ``max_grey_error``, ``equal``), ``frames_to_full``: the
        first still frame whose picture equals full quality (None if none
        did), ``ms_to_full``: the time of the frames up to it, the foveated
        frame included.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> result = measure_progressive(make_fixture("spheres", size=16), "spheres", size=32, refinement_frames=2,
    ...                              warmup=1)
    >>> [s["step"] for s in result["steps"]], result["frames_to_full"] <= 2, result["steps"][-1]["rays"]
    ([0, 1, 2, 2], True, 0)
    """
    import time

    full = framed_view(image, method, size, framing, window)
    fov = framed_view(image, "foveated", size, framing, window)
    apply_settings(fov.mapper, (("Method", method), ("GazePoint", tuple(gaze)),
                                ("RefinementFrames", int(refinement_frames)), ("Progressive", True)))
    for _ in range(warmup):
        full.render_window.Render()
    started = time.perf_counter()
    full.render_window.Render()
    full.renderer.GetRenderWindow().WaitForCompletion()
    full_ms = 1000 * (time.perf_counter() - started)
    reference = _last_picture(full)
    for _ in range(refinement_frames + warmup + 1):  # warm every step's level mappers
        fov.render_window.Render()
    fov.camera.Azimuth(0.5)  # a change, then back: the next frame is the foveated one again
    fov.render_window.Render()
    fov.camera.Azimuth(-0.5)
    steps = []
    for _ in range(refinement_frames + 2):
        started = time.perf_counter()
        fov.render_window.Render()
        fov.render_window.WaitForCompletion()
        ms = 1000 * (time.perf_counter() - started)
        error = int(np.abs(_last_picture(fov).astype(int) - reference).max())
        cost = fov.mapper.GetLastFrameCost()
        steps.append({"step": fov.mapper.GetRefinementStep(), "ms": ms, "rays": cost["rays"],
                      "max_grey_error": error, "equal": error == 0})
    for view in (full, fov):
        view.render_window.Finalize()
    first = next((i for i, s in enumerate(steps) if s["equal"]), None)
    return {"scene": scene, "method": method, "size": size, "framing": framing, "full_ms": full_ms,
            "full_rays": cost["full_rays"], "refinement_frames": refinement_frames, "steps": steps,
            "frames_to_full": None if first is None else steps[first]["step"],
            "ms_to_full": None if first is None else sum(s["ms"] for s in steps[:first + 1])}


def measure_gaze_latency(image, scene: str, method: str = "mip", size: int = 1024, framing: str = "fill",
                         window=None, samples: Optional[int] = None) -> dict:
    """Replay :func:`mipcast.core.gaze.synthetic_trace` into a foveated view, rendering when the gaze moves.

    Each sample is pushed (:meth:`~mipcast.mappers.foveated.FoveatedVolumeMapper.PushGaze`); when it asks
    for a re-render the view renders at once, and the latency from the push to the end of that frame
    is recorded.  Re-renders are counted per kind of sample; ``pursuit_rays`` is the median share of
    full quality's rays a re-render during smooth pursuit cast (``GetLastFrameCost``, read after the
    timing), ``median_pursuit_latency_ms`` its latency.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> result = measure_gaze_latency(make_fixture("spheres", size=16), "spheres", size=32, samples=120)
    >>> result["re_renders"]["fixation"], result["frames_after_sample"]
    (2, 1)
    """
    from mipcast.core.gaze import synthetic_trace

    view = framed_view(image, "foveated", size, framing, window)
    view.mapper.SetMethod(method)
    view.render_window.Render()
    trace = synthetic_trace()[:samples]
    latencies, counts, pursuit = [], {"fixation": 0, "saccade": 0, "pursuit": 0}, []
    for sample in trace:
        if view.mapper.PushGaze(sample.t, sample.x, sample.y):
            view.render_window.Render()
            view.render_window.WaitForCompletion()
            latencies.append(1000 * view.mapper.GetLastGazeLatency())
            counts[sample.kind] += 1
            assert view.mapper.GetLastPlan().gaze == view.mapper.GetGazeStream().gaze
            if sample.kind == "pursuit":
                cost = view.mapper.GetLastFrameCost()
                pursuit.append((latencies[-1], cost["rays"] / max(cost["full_rays"], 1)))
    view.render_window.Finalize()
    kinds = [s.kind for s in trace]
    fixations = sum(1 for i, k in enumerate(kinds) if k == "fixation" and (i == 0 or kinds[i - 1] != k))
    return {"scene": scene, "method": method, "size": size, "framing": framing, "samples": len(trace),
            "fixations": fixations, "re_renders": counts,
            "median_latency_ms": statistics.median(latencies) if latencies else float("nan"),
            "max_latency_ms": max(latencies) if latencies else float("nan"), "frames_after_sample": 1,
            "median_pursuit_latency_ms": statistics.median(p[0] for p in pursuit) if pursuit else float("nan"),
            "pursuit_rays": statistics.median(p[1] for p in pursuit) if pursuit else float("nan")}


def progressive_table(results: Sequence[dict]) -> str:
    """Markdown: per scene, each still frame's time and rays against full quality, its largest grey error,
    and the time until the picture equals full quality.

    Examples
    --------
    >>> r = {"scene": "s", "method": "mip", "size": 8, "framing": "fill", "full_ms": 10.0, "full_rays": 40,
    ...      "frames_to_full": 0, "ms_to_full": 2.0,
    ...      "steps": [{"step": 0, "ms": 2.0, "rays": 10, "max_grey_error": 0, "equal": True}]}
    >>> progressive_table([r]).splitlines()[-1]
    '| s mip 8² fill | 10 | 0 | 2 ms (0.2 full frames) | 0: 2 ms (5.0x), 25 % of the rays, error 0 |'
    """
    lines = ["| scene | full quality ms | still frames until equal to full quality | time until equal "
             "(foveated frame included) | each frame: ms (full / frame), rays cast, largest grey error |",
             "| --- | --- | --- | --- | --- |"]
    for r in results:
        steps = "; ".join(f"{s['step']}: {s['ms']:.0f} ms ({r['full_ms'] / s['ms']:.1f}x), "
                          f"{100.0 * s['rays'] / max(r['full_rays'], 1):.0f} % of the rays, error {s['max_grey_error']}"
                          for s in r["steps"])
        until = ("-" if r.get("ms_to_full") is None
                 else f"{r['ms_to_full']:.0f} ms ({r['ms_to_full'] / r['full_ms']:.1f} full frames)")
        lines.append(f"| {r['scene']} {r['method']} {r['size']}² {r['framing']} | {r['full_ms']:.0f} | "
                     f"{r['frames_to_full'] if r['frames_to_full'] is not None else '-'} | {until} | {steps} |")
    return "\n".join(lines)


def gaze_table(results: Sequence[dict]) -> str:
    """Markdown: re-renders per kind of sample and the latency from sample to frame.

    Examples
    --------
    >>> r = {"scene": "s", "method": "mip", "size": 8, "framing": "fill", "samples": 10, "fixations": 2,
    ...      "re_renders": {"fixation": 2, "saccade": 0, "pursuit": 3}, "median_latency_ms": 5.0,
    ...      "max_latency_ms": 6.0, "frames_after_sample": 1}
    >>> gaze_table([r]).splitlines()[-1]
    '| s mip 8² fill | 10 | 2 | 2 / 0 / 3 | 5 | 6 | 1 |'
    """
    lines = ["| scene | samples | fixations | re-renders in fixations / saccades / pursuit | median latency ms "
             "| max latency ms | frames from sample to picture |", "| --- | --- | --- | --- | --- | --- | --- |"]
    for r in results:
        c = r["re_renders"]
        lines.append(f"| {r['scene']} {r['method']} {r['size']}² {r['framing']} | {r['samples']} | {r['fixations']} | "
                     f"{c['fixation']} / {c['saccade']} / {c['pursuit']} | {r['median_latency_ms']:.0f} | "
                     f"{r['max_latency_ms']:.0f} | {r['frames_after_sample']} |")
    return "\n".join(lines)
