"""Speed and accuracy of every method on one scene, measured in one process.

llvmpipe (and any shared machine) drifts, so settings are timed in
interleaved rounds: each round renders every setting a few frames, and each
setting's time is the median over all its frames after warm-up.  Only ratios
measured this way mean something.  Errors are against the float64 exact
reference of each row's projection (:attr:`mipcast.methods.Method.exact_reference`:
the exact maximum for MIP rows, the exact minimum for MinIP rows, the exact
mean for average rows) on the same rays, from each method's float readout (the CPU peer has none: its 8-bit
picture is mapped back through the grey window, so its error includes the
8-bit floor of about 0.2 % of the window).
"""
from __future__ import annotations

import statistics
from typing import Callable, Iterable, NamedTuple, Optional, Sequence, Union

import numpy as np

from mipcast.offscreen import OffscreenView
from mipcast.core.parameters import set_parameters, snake_name


class Setting(NamedTuple):
    """One row of the benchmark: a method at a sampling rate."""

    label: str
    method: str
    samples_per_voxel: Union[float, str, None] = None  # None: no sampling (exact); "auto": chosen per scene
    readout_method: Optional[str] = None               # method whose float readout stands for it
    settings: tuple = ()                               # (Name, value) pairs for the mapper's SetName


def default_settings() -> tuple:
    """The benchmark's rows: every method's ``bench`` entries in :data:`mipcast.METHODS`, in table order.

    A method without a float readout is read out through the method its
    entry names in ``readout_by``: stock VTK MIP through mipcast's "mip",
    which takes the very same samples (parity tests: identical pictures).
    ``auto`` renders with mipcast's "mip": its sample positions are exact
    (``entry + i * step``), as its CPU calibration assumes, while VTK's
    stock loop sums its steps and drifts at dense sampling (head CT,
    100-1500 HU, 256^2, 24 samples per voxel: 1.6 % of stock's pixels are
    over one grey level from ideal sampling, none of mipcast's).

    Examples
    --------
    >>> [s.label for s in default_settings()][:5]
    ['stock 1x', 'stock 2x', 'stock 4x', 'stock 8x', 'mip 1x']
    """
    from mipcast.methods import METHODS

    return tuple(Setting(label, method.name, rate, method.readout_by, settings)
                 for method in METHODS.values() for label, rate, settings in method.bench_rows())


def resolve_settings(image, settings: Sequence[Setting], size, view: str, window=None) -> list:
    """Settings with ``"auto"`` sampling replaced by the rate chosen for this scene and view.

    The label becomes e.g. ``"auto (12x)"`` (``"auto (32x, target missed)"``
    when even the densest candidate misses the target); see
    :func:`mipcast.bench.auto_sampling.choose_samples_per_voxel`.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> chosen = [s for s in default_settings() if s.label in ("auto", "analytic")]
    >>> [s.label for s in resolve_settings(make_fixture("spheres", size=16), chosen, (32, 32), "oblique")]
    ['auto (12x)', 'analytic']
    """
    from mipcast.bench.auto_sampling import choose_samples_per_voxel

    resolved = []
    for setting in settings:
        if setting.samples_per_voxel == "auto":
            camera = OffscreenView(image, "mip", size=size, view=view, window=window).camera
            choice = choose_samples_per_voxel(image, camera, size, window=window)
            note = "" if choice.met else ", target missed"
            setting = setting._replace(label=f"{setting.label} ({choice.samples_per_voxel:g}x{note})",
                                       samples_per_voxel=choice.samples_per_voxel)
        resolved.append(setting)
    return resolved


def _view(image, setting: Setting, method: str, size, view: str, window=None) -> OffscreenView:
    spacing = min(abs(s) for s in image.GetSpacing())
    distance = spacing / setting.samples_per_voxel if setting.samples_per_voxel else spacing
    scene = OffscreenView(image, method, size=size, view=view, sample_distance=distance, window=window)
    if method == setting.method:
        apply_settings(scene.mapper, setting.settings)
    return scene


def apply_settings(mapper, pairs) -> None:
    """Call ``mapper.SetName(value)`` for each ``(Name, value)`` pair (:func:`mipcast.core.parameters.set_parameters`).

    Examples
    --------
    >>> from mipcast import FoveatedVolumeMapper
    >>> mapper = FoveatedVolumeMapper()
    >>> apply_settings(mapper, (("GazePoint", (0.2, 0.3)), ("FovealRadius", 0.1)))
    >>> mapper.GetGazePoint(), mapper.GetFovealRadius()
    ((0.2, 0.3), 0.1)
    """
    set_parameters(mapper, **{snake_name(name): value for name, value in pairs})


def time_settings(image, settings: Sequence[Setting], size=(256, 256), view: str = "oblique",
                  rounds: int = 5, frames: int = 3, warmup: int = 3, window=None,
                  progress: Optional[Callable[[str], None]] = None, views: Optional[dict] = None) -> dict:
    """Median frame time in seconds of each setting, measured in interleaved rounds.

    Parameters
    ----------
    image : vtkImageData
        The scene's volume.
    settings : sequence of Setting
        The first is the baseline of the ratios.
    size : tuple of int, default: (256, 256)
        Window (width, height).
    view : str, default: "oblique"
        A preset of :data:`mipcast.offscreen.VIEWS`.
    rounds, frames, warmup : int
        ``rounds`` x ``frames`` timed frames per setting, after ``warmup``.
    window : tuple of float, optional
        Grey window (default: the data range).
    progress : callable, optional
        Called with a short label after each round.
    views : dict, optional
        ``{label: OffscreenView}`` already built for these settings
        (:func:`setting_views`); default: built here.

    Returns
    -------
    dict
        ``{label: {"median_s": float, "ratio": float, "frames": int}}``.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> times = time_settings(make_fixture("spheres", size=16), default_settings()[:2],
    ...                       size=(32, 32), rounds=1, frames=1, warmup=1)
    >>> times["stock 1x"]["ratio"]
    1.0
    """
    views = views if views is not None else setting_views(image, settings, size, view, window)
    samples = interleaved_frame_times(views, rounds, frames, warmup, progress)
    baseline = statistics.median(samples[settings[0].label])
    return {label: {"median_s": statistics.median(t), "ratio": statistics.median(t) / baseline,
                    "frames": len(t)} for label, t in samples.items()}


def setting_views(image, settings: Sequence[Setting], size=(256, 256), view: str = "oblique",
                  window=None) -> dict:
    """``{label: OffscreenView}``: each setting's view, built once for timing, errors and counters.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> views = setting_views(make_fixture("spheres", size=8), default_settings()[:2], size=(16, 16))
    >>> sorted(views), views["stock 2x"].sample_distance
    (['stock 1x', 'stock 2x'], 0.5)
    """
    return {s.label: _view(image, s, s.method, size, view, window) for s in settings}


def interleaved_frame_times(views: dict, rounds: int, frames: int, warmup: int,
                            progress: Optional[Callable[[str], None]] = None) -> dict:
    """Frame times of several views, measured in interleaved rounds after warm-up.

    Every view renders ``warmup`` frames, then each of ``rounds`` rounds
    renders ``frames`` frames of every view in turn, so drift on a shared
    machine touches all views alike.

    Returns
    -------
    dict
        ``{label: [seconds, ...]}`` (``rounds * frames`` times each).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> views = {"a": OffscreenView(make_fixture("spheres", size=8), "mip", size=(16, 16))}
    >>> len(interleaved_frame_times(views, rounds=2, frames=3, warmup=1)["a"])
    6
    """
    for scene in views.values():
        scene.frame_times(frames=0, warmup=warmup)
    samples: dict = {label: [] for label in views}
    for number in range(rounds):
        for label, scene in views.items():
            samples[label].extend(scene.frame_times(frames=frames, warmup=0))
        if progress is not None:
            progress(f"timing round {number + 1}/{rounds}")
    return samples


def errors_of_settings(image, settings: Sequence[Setting], size=(256, 256), view: str = "oblique",
                       window=None, progress: Optional[Callable[[str], None]] = None,
                       views: Optional[dict] = None) -> dict:
    """Error of each setting's float readout against its projection's exact float64 reference.

    The reference is the method's :attr:`~mipcast.methods.Method.exact_reference`
    (exact maximum, minimum or mean), computed once per projection.  On a
    volume with missing values (NaN, Inf) a sampled setting may miss a ray
    whose samples all fell on missing data while the exact interpolant has a
    finite part between them: where the projection's sampled reference at
    the setting's sample distance misses too, that is counted
    (``missing_data_misses``), not an error.

    ``progress``, if given, is called with the setting's label after each.
    ``views`` (:func:`setting_views`) are used where the setting reads its
    own values; a setting whose ``readout_method`` differs gets a view of
    that method.

    Returns
    -------
    dict
        ``{label: metrics.summary(...)}`` plus ``"_reference_s"``: seconds the
        references took.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> analytic = [s for s in default_settings() if s.label == "analytic"]
    >>> errors = errors_of_settings(make_fixture("spheres", size=16), analytic, size=(24, 24))
    >>> errors["analytic"]["within_1_grey"]
    1.0
    """
    import time

    from mipcast.core.metrics import summary
    from mipcast.core.prepare import prepare_scalars
    from mipcast.methods import METHODS, SAMPLED_REFERENCES

    results: dict = {"_reference_s": 0.0}
    exact: dict = {}
    low, high = image.GetPointData().GetScalars().GetRange(0)
    missing = prepare_scalars(image).missing
    misses: dict = {}  # (projection, sample distance) -> rays its sampled reference misses
    for setting in settings:
        if views is not None and setting.readout_method in (None, setting.method):
            scene = views[setting.label]
        else:
            scene = _view(image, setting, setting.readout_method or setting.method, size, view, window)
        projection = METHODS[setting.method].projection
        if projection not in exact:
            started = time.perf_counter()
            exact[projection] = METHODS[setting.method].exact_reference(image, scene.camera, size)
            results["_reference_s"] += time.perf_counter() - started
        may_miss = None
        if missing and setting.samples_per_voxel is not None:
            key = (projection, scene.sample_distance)  # stock and mipcast's rows share their samples
            if key not in misses:
                started = time.perf_counter()
                misses[key] = np.isnan(SAMPLED_REFERENCES[projection](image, scene.camera, size,
                                                                      sample_distance=scene.sample_distance))
                results["_reference_s"] += time.perf_counter() - started
            may_miss = misses[key]
        results[setting.label] = summary(_values(scene), exact[projection], high - low, window=window,
                                         may_miss=may_miss)
        if progress is not None:
            progress(f"error of {setting.label}")
    return results


def _values(scene: OffscreenView) -> np.ndarray:
    """Per-pixel maxima: the float readout, or for mappers without one (the
    CPU peer) the 8-bit grey picture mapped back through the grey window."""
    if scene.method.float_readout:
        return scene.float_image()
    low, high = scene.window
    grey = scene.screenshot()[..., 0].astype(np.float64)
    return low + grey / 255.0 * (high - low)  # misses: only the reference's hits are compared


def measure_scene(image, scene: str, view: str, edge: int, rounds: int = 5, window=None,
                  progress: Optional[Callable[[str], None]] = None) -> list:
    """All of :func:`default_settings` on one scene, view and size: bench rows.

    ``progress`` (optional) is called with a short label after each of the
    ``1 + rounds + len(default_settings())`` steps (sampling choice, timing
    rounds, error of each setting).

    Each row has its projection, the time ratio to stock MIP 1x and to stock
    VTK's blend mode of its projection at one sample per voxel
    (``ratio_to_stock_blend``: MinIP rows to MINIMUM_INTENSITY, average rows to
    AVERAGE_INTENSITY), the error figures of
    :func:`errors_of_settings`, and for analytic MIP its work per ray
    (:func:`mipcast.mappers.amip_stats.work_per_ray`).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = measure_scene(make_fixture("spheres", size=12), "spheres", "oblique", 16, rounds=1)
    >>> [row["setting"] for row in rows][:2], rows[0]["ratio_to_stock"]
    (['stock 1x', 'stock 2x'], 1.0)
    """
    from mipcast.mappers.amip_stats import work_per_ray
    from mipcast.methods import METHODS

    size = (edge, edge)
    settings = resolve_settings(image, default_settings(), size, view, window)
    if progress is not None:
        progress("sampling chosen for 'auto'")
    views = setting_views(image, settings, size, view, window)
    times = time_settings(image, settings, size=size, view=view, rounds=rounds, window=window, progress=progress,
                          views=views)
    errors = errors_of_settings(image, settings, size=size, view=view, window=window, progress=progress,
                                views=views)
    stock_times = _stock_times(settings, times)
    rows = []
    for setting in settings:
        error, timing = errors[setting.label], times[setting.label]
        projection = METHODS[setting.method].projection
        row = {"scene": scene, "view": view, "size": edge, "setting": setting.label,
               "projection": projection, "median_ms": 1000 * timing["median_s"],
               "ratio_to_stock": timing["ratio"],
               "p99_pct": error["p99_pct"], "max_pct": error["max_pct"], "fg_p99_pct": error["fg_p99_pct"],
               "within_1_grey": error["within_1_grey"], "frames": timing["frames"]}
        if error["missing_data_misses"]:  # rays whose samples all fell on missing values (errors_of_settings)
            row["missing_data_misses"] = error["missing_data_misses"]
        if projection in stock_times:  # against stock VTK's blend mode of the same projection at 1x
            row["ratio_to_stock_blend"] = timing["median_s"] / stock_times[projection]
        if setting.method == "analytic":
            work = work_per_ray(views[setting.label])
            row.update(texel_fetches=work["texel_fetches"], skipped_cells=work["skipped_cells"])
        if setting.method == "foveated":  # the paper's Table I columns
            views[setting.label].screenshot()
            cost = views[setting.label].mapper.GetLastFrameCost()
            row.update(ray_ratio=cost["ray_ratio"], sample_ratio=cost["sample_ratio"])
        rows.append(row)
    for scene_view in views.values():
        scene_view.render_window.Finalize()
    return rows


def _stock_times(settings: Sequence[Setting], times: dict) -> dict:
    """Projection -> median frame time of its first row: stock VTK's blend mode for it at 1x.

    As the first row is the baseline of ``ratio_to_stock`` (stock MIP 1x),
    the first row of each projection in table order is that projection's:
    the table lists stock VTK's MIP, MINIMUM_INTENSITY and AVERAGE_INTENSITY
    blends at one sample per voxel first.
    """
    from mipcast.methods import METHODS

    found: dict = {}
    for setting in settings:
        found.setdefault(METHODS[setting.method].projection, times[setting.label]["median_s"])
    return found


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


def pareto_front(points: Sequence[tuple]) -> list:
    """Indices of the (time, error) points no other point beats in both.

    Examples
    --------
    >>> pareto_front([(1.0, 5.0), (2.0, 1.0), (3.0, 2.0), (0.5, 9.0)])
    [0, 1, 3]
    """
    front = []
    for i, (t, e) in enumerate(points):
        if not any((t2 <= t and e2 <= e) and (t2 < t or e2 < e) for t2, e2 in points):
            front.append(i)
    return front


#: Chart marker of each projection.
_MARKERS = {"mip": "o", "minip": "v", "average": "s"}


def write_chart(rows: Sequence[dict], path, error_key: str = "p99_pct") -> None:
    """Error (log) against time ratio to stock MIP 1x, one panel per scene/view/size.

    Pareto-optimal settings are circled (each projection's rows against
    its own exact reference; markers: circle MIP, triangle MinIP, square
    average); an error of 0 is drawn at the
    panel's floor (marked "exact").

    Examples
    --------
    >>> import tempfile, pathlib
    >>> rows = [{"scene": "s", "view": "v", "size": 8, "setting": name, "ratio_to_stock": r, "p99_pct": e}
    ...         for name, r, e in [("stock 1x", 1.0, 5.0), ("analytic", 3.0, 0.0)]]
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "chart.png"
    >>> write_chart(rows, path)
    >>> path.stat().st_size > 1000
    True
    """
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib import pyplot

    panels = sorted({(r["scene"], r["view"], r["size"]) for r in rows})
    settings = list(dict.fromkeys(r["setting"].split(" (")[0] for r in rows))  # "auto (16x)" -> "auto"
    colours = pyplot.get_cmap("tab20")
    columns = min(len(panels), 4)
    lines = -(-len(panels) // columns)
    ncol = max(1, min(len(settings), 2 * columns + 1, 7))  # as many legend columns as fit the width
    legend = 0.75 + 0.2 * -(-len(settings) // ncol)  # inches: title and rows
    height = 4.4 * lines + legend + 0.4
    figure, axes = pyplot.subplots(lines, columns, figsize=(5.2 * columns, height), squeeze=False)
    floor = 1e-4
    for ax, panel in zip(axes.flat, panels):
        chosen = [r for r in rows if (r["scene"], r["view"], r["size"]) == panel]
        points = [(r["ratio_to_stock"], max(r[error_key], floor)) for r in chosen]
        front = set()
        for projection in {r.get("projection", "mip") for r in chosen}:  # one front per projection
            group = [i for i, r in enumerate(chosen) if r.get("projection", "mip") == projection]
            front.update(group[i] for i in pareto_front([points[i] for i in group]))
        for index, (row, (x, y)) in enumerate(zip(chosen, points)):
            colour = colours(settings.index(row["setting"].split(" (")[0]) % 20)
            ax.scatter(x, y, s=70 if index in front else 30, color=colour,
                       marker=_MARKERS.get(row.get("projection", "mip"), "o"),
                       edgecolors="k" if index in front else "none", zorder=3)
            if index in front:  # name the Pareto-optimal settings; the legend names all
                ax.annotate(row["setting"], (x, y), textcoords="offset points", fontsize=7, xytext=(5, 3))
        ax.set_yscale("log")
        ax.set_xlabel("frame time / stock VTK MIP 1x", fontsize=8)
        ax.set_ylabel(f"error {error_key} (% of data range)", fontsize=8)
        ax.set_title(f"{panel[0]}, {panel[1]}, {panel[2]}²", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    projection_of = {r["setting"].split(" (")[0]: r.get("projection", "mip") for r in rows}
    handles = [pyplot.Line2D([], [], marker=_MARKERS.get(projection_of[name], "o"), linestyle="",
                             color=colours(i % 20), label=name)
               for i, name in enumerate(settings)]
    figure.legend(handles=handles, loc="lower center", ncol=ncol, fontsize=8, title_fontsize=8,
                  title=f"circled: Pareto front per projection (nothing both faster and more accurate);\n"
                        f"an error of 0 is drawn at {floor:g} %")
    figure.tight_layout()
    figure.subplots_adjust(bottom=(legend + 0.4) / height, hspace=0.35)
    figure.savefig(path, dpi=110)
    pyplot.close(figure)
