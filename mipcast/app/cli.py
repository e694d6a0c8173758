"""The ``mipcast`` command: ``demo``, ``render`` and ``bench``.

Everything renders offscreen (EGL/Mesa works with no GPU and no display).
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from mipcast import METHODS
from mipcast.bench.report import strict_json
from mipcast.offscreen import VIEW_NAMES, VIEWS, OffscreenView

DEMO_FIXTURE = "vessels"
#: The demo's fixture for a projection other than MIP's (MinIP shows dark
#: structure: on the vessels it would show only the background), and its
#: window: the default window is a MIP rule (above the background), which
#: leaves a MinIP black, so MinIP gets the full data range.
DEMO_FIXTURES = {"minip": "airways"}
DEMO_WINDOWS = {"minip": "full"}
DEMO_SIZE = 96


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Entry point of the ``mipcast`` console script.

    Examples
    --------
    >>> main([])  # no command: prints the help, returns 2
    usage: mipcast ...
    2
    """
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    if extra and args.command not in ("render", "view"):
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if args.command in ("render", "view"):
        from mipcast.core.parameters import parse_options

        try:
            _check_input_not_a_value(parser, args, argv)
            args.params = parse_options(extra)
        except ValueError as error:
            print(f"mipcast {args.command}: error: {error}", file=sys.stderr)
            return 2
    if args.command is None:
        parser.print_help()
        return 2
    try:
        return args.run(args)
    except (ValueError, TypeError, FileNotFoundError, ImportError) as error:
        print(f"mipcast {args.command}: error: {error}", file=sys.stderr)
        return 2


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="mipcast", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=_version())
    sub = parser.add_subparsers(dest="command")

    demo = sub.add_parser("demo", help="render the bundled scene with every method, plus error maps")
    demo.add_argument("--out", type=Path, default=Path("mipcast-demo"), help="output folder")
    demo.add_argument("--size", type=int, default=256, help="image width and height (pixels)")
    demo.set_defaults(run=_run_demo)

    render = sub.add_parser("render", help="render a volume file (.vti/.nrrd/.nii/.mha/.tif/DICOM) to PNG",
                            formatter_class=argparse.RawDescriptionHelpFormatter, allow_abbrev=False)
    render.add_argument("input", type=Path)
    render.add_argument("--method", default="mip", choices=sorted(METHODS))
    render.add_argument("--out", type=Path, required=True, help="PNG file to write (.gif/.mp4 with --turntable)")
    render.add_argument("--view", default="oblique", choices=VIEW_NAMES,
                        help="camera: volume axes (oblique, perspective, front, back, side) or the patient's "
                             "side (anterior, posterior, left, right, superior, inferior; LPS world)")
    render.add_argument("--size", type=int, nargs=2, default=(512, 512), metavar=("W", "H"))
    render.add_argument("--sample-distance", type=_distance, default=None,
                        help="world units between samples (default: one per voxel), or 'auto': the "
                             "fewest samples that keep 99%% of pixels within one grey level of the exact maximum")
    render.add_argument("--window", nargs="+", default=None, metavar=("LOW|full|PRESET", "HIGH"),
                        help=_WINDOW_HELP)
    render.add_argument("--turntable", type=int, default=None, metavar="N",
                        help="write N frames turning 360 degrees about the view-up axis (--out spin.gif, "
                             "or .mp4 with imageio[ffmpeg])")
    render.add_argument("--slab-sweep", type=int, default=None, metavar="N",
                        help="write N frames of the slab (--slab MM) moving through the volume, front to back "
                             "(--out sweep.gif or .mp4)")
    render.add_argument("--series", default=None, help="DICOM SeriesInstanceUID when a folder holds several")
    render.add_argument("--volume", type=_volume, default=None, metavar="K",
                        help=_VOLUME_HELP)
    render.add_argument("--padding", default="missing", choices=["missing", "keep"],
                        help="DICOM pixels holding the PixelPaddingValue (outside a CT's field of view): "
                             "missing data (default) or kept as values")
    render.add_argument("--scalars", default=None, help="point array to project (default: the active scalars)")
    render.add_argument("--component", type=_component, default=None, metavar="K|magnitude",
                        help="component of a multi-component array (a TIFF stack's channel) to draw "
                             "(default: the magnitude)")
    render.add_argument("--stereo", default=None, choices=["anaglyph", "side-by-side", "left", "right"],
                        help="a stereo pair of any method: red-cyan anaglyph or side by side (each eye half "
                             "width); use a perspective view (--view perspective) for depth")
    render.add_argument("--eye-angle", type=float, default=None,
                        help="degrees between the eyes with --stereo (default VTK's 2)")
    render.set_defaults(run=_run_render)
    render.epilog = _parameters_help(render)

    view = sub.add_parser("view", help="open an interactive window (keys m/d switch method/depth mode)",
                          formatter_class=argparse.RawDescriptionHelpFormatter, allow_abbrev=False)
    view.add_argument("input", type=Path)
    view.add_argument("--method", default="mip", choices=sorted(METHODS))
    view.add_argument("--window", nargs="+", default=None, metavar=("LOW|full|PRESET", "HIGH"),
                      help=_WINDOW_HELP)
    view.add_argument("--view", default=None, choices=VIEW_NAMES, help="first camera (default: pyvista's)")
    view.add_argument("--series", default=None, help="DICOM SeriesInstanceUID when a folder holds several")
    view.add_argument("--volume", type=_volume, default=None, metavar="K",
                      help=_VOLUME_HELP)
    view.add_argument("--padding", default="missing", choices=["missing", "keep"],
                      help="DICOM pixels holding the PixelPaddingValue (outside a CT's field of view): "
                           "missing data (default) or kept as values")
    view.add_argument("--scalars", default=None, help="point array to project (default: the active scalars)")
    view.add_argument("--component", type=_component, default=None, metavar="K|magnitude",
                      help="component of a multi-component array to draw (default: the magnitude)")
    view.add_argument("--stereo", nargs="?", const="anaglyph", default=None, choices=["anaglyph", "side-by-side"],
                      help="show a stereo pair (default anaglyph, red-cyan; or side-by-side)")
    view.set_defaults(run=run_view)
    view.epilog = _parameters_help(view)

    bench = sub.add_parser("bench", help="frame-time ratios of every method against stock VTK MIP")
    bench.add_argument("--scenes", nargs="+", default=["vessels"],
                       help="fixture names, 'head' for the head CT, or volume files; "
                            "NAME@LOW,HIGH sets a grey window (e.g. head@100,1500)")
    bench.add_argument("--size", type=int, nargs="+", default=None,
                       help="square window edges (default: 256 512; with --foveation 512 1024)")
    bench.add_argument("--volume-size", type=int, default=128, help="edge of synthetic fixtures")
    bench.add_argument("--views", nargs="+", default=["oblique", "perspective"], choices=sorted(VIEWS))
    bench.add_argument("--rounds", type=int, default=5)
    bench.add_argument("--out", type=Path, default=Path("mipcast-bench"))
    bench.add_argument("--stability", action="store_true",
                       help="instead: measure each method's known weak points (stability.md)")
    bench.add_argument("--foveation", action="store_true",
                       help="instead: foveated variants against full quality, volume filling the view and "
                            "whole, gaze at the centre and a corner (foveation.md/json/png)")
    bench.add_argument("--foveation-methods", nargs="+", default=["mip"],
                       help="methods the foveated variants render with (--foveation)")
    bench.add_argument("--foveation-variants", nargs="+", default=None,
                       help="names of foveation_bench.VARIANTS to measure (--foveation; default: all)")
    bench.add_argument("--framings", nargs="+", default=None, choices=["fill", "whole"],
                       help="framings measured by --foveation (default: fill and whole)")
    bench.add_argument("--gpu-report", action="store_true",
                       help="instead: the fixed GPU suite (parity, speed x accuracy at 512/1024, foveation, "
                            "first frame, memory, peers): gpu-report.md/json/png; refuses software OpenGL")
    bench.add_argument("--peers", action="store_true",
                       help="instead: vispy's volume visual beside stock VTK, mip and analytic on equal "
                            "views (peers.md/json; needs the 'bench' extra)")
    bench.add_argument("--quick", action="store_true", help="--gpu-report/--peers at tiny sizes")
    bench.add_argument("--allow-software", action="store_true",
                       help="--gpu-report on a software renderer (llvmpipe, softpipe, swrast) too")
    bench.set_defaults(run=_run_bench)
    return parser


_VOLUME_HELP = ("which volume of a 4D NIfTI or NRRD file (a time series), which time point of a TIFF stack, or "
                "which data set of a .vtm/.vtpd/.vtpc file, from 0 (default: the first volume; a composite file's one)")
_WINDOW_HELP = ("grey window: LOW HIGH in data units, 'full' (the data range), a preset (ct-mip, ct-bone, "
                "ct-angio, ct-minip, ct-soft), or 'dicom' (a DICOM series' own window; 'dicom:2', 'dicom:NAME' "
                "another); default: CT preset ct-mip (150 1800) for HU data, else histogram percentiles "
                "(docs/usage.md, 'The default window')")


def _check_input_not_a_value(parser, args, argv) -> None:
    """Refuse ``render --depth-weight 0.3 INPUT``: argparse would take ``0.3`` as the input.

    Method parameters are unknown to argparse, so a value right after one is
    a positional to it; they must come after INPUT.
    """
    tokens = list(sys.argv[1:] if argv is None else argv)
    known = parser._subparsers._group_actions[0].choices[args.command]._option_string_actions  # the command's own
    text = str(args.input)
    for before, token in zip(tokens, tokens[1:]):
        if token == text and before.startswith("--") and "=" not in before and before not in known:
            raise ValueError(f"{text!r} was read as INPUT, but it is the value of {before}: "
                             f"method parameters go after the input (mipcast {args.command} INPUT {before} {text})")
        if token == text:
            return


def _parameters_help(command: argparse.ArgumentParser) -> str:
    """The epilog of ``render`` and ``view``: how to set method parameters, and each method's own (its table)."""
    lines = ["method parameters: --NAME VALUE [VALUE ...] calls the mapper's SetName(VALUE, ...),",
             "e.g. --depth-weight 0.3, --gaze-point 0.2 0.8, --foveation off; --mapper-NAME where the",
             "command has a --NAME of its own (--mapper-method analytic). Each method's own:"]
    own_options = {option[2:].replace("-", "_") for option in command._option_string_actions}
    described = {}
    for method in METHODS.values():
        if not method.parameters:
            continue
        if method.parameters in described:
            lines.append(f"  {method.name}: as {described[method.parameters]}")
            continue
        described[method.parameters] = method.name
        lines.append(f"  {method.name}:")
        for parameter in method.parameters:
            option = "--" + ("mapper-" if parameter.name in own_options else "") + parameter.name.replace("_", "-")
            lines.append(f"    {option} ({parameter.describe()}): {parameter.summary}")
    lines.append("VTK's mapper setters work too, e.g. --image-sample-distance 2.")
    return "\n".join(lines)


def _version() -> str:
    from mipcast import __version__
    return f"mipcast {__version__}"


def _run_demo(args) -> int:
    """Render the demo fixture with every method, its float readout and error map (against the exact
    reference of the method's projection)."""
    from mipcast.data_fixtures import head_ct_path, load_head_ct, make_fixture
    from mipcast.bench.depth_figure import write_depth_figure
    from mipcast.core.metrics import summary

    images = {name: make_fixture(name, size=DEMO_SIZE) for name in {DEMO_FIXTURE, *DEMO_FIXTURES.values()}}
    image = images[DEMO_FIXTURE]
    size = (args.size, args.size)
    args.out.mkdir(parents=True, exist_ok=True)
    exact: dict = {}  # projection -> its exact float64 reference (maximum, minimum, mean)
    report = {}
    for method in sorted(METHODS):
        projection = METHODS[method].projection
        scene = images[DEMO_FIXTURES.get(projection, DEMO_FIXTURE)]
        low, high = scene.GetPointData().GetScalars().GetRange(0)
        view = OffscreenView(scene, method, size=size, view="oblique", window=DEMO_WINDOWS.get(projection))
        picture = args.out / f"{method}.png"
        _write_png(picture, view.screenshot())
        if projection not in exact:
            exact[projection] = view.method.exact_reference(scene, view.camera, size)
            if projection == "mip":
                _write_png(args.out / "reference_exact.png", _grey8(exact[projection], *view.window))
        entry = {"png": str(picture)}
        if view.method.float_readout:
            values = view.float_image()
            errors = summary(values, exact[projection], high - low)
            _write_error_map(args.out / f"{method}_error.png", values, exact[projection], high - low)
            entry.update(error_png=str(args.out / f"{method}_error.png"),
                         p99_error_pct=errors["p99_pct"], within_1_grey=errors["within_1_grey"])
        report[method] = entry
    scenes = [("vessels", image, "oblique", None)]
    if head_ct_path() is not None:
        scenes.append(("head CT", load_head_ct(), "front", (150.0, 1800.0)))
    write_depth_figure(args.out / "depth_figure.png", scenes, size=size)
    report["depth_figure"] = {"png": str(args.out / "depth_figure.png")}
    (args.out / "demo.json").write_text(strict_json(report, indent=2))
    print(f"mipcast demo: {DEMO_FIXTURE} fixture ({DEMO_SIZE}^3; MinIP: {DEMO_FIXTURES['minip']}), "
          f"{size[0]}x{size[1]} pixels")
    for method, entry in report.items():
        extra = ""
        if "p99_error_pct" in entry:
            extra = (f"  error vs exact reference: p99 {entry['p99_error_pct']:.2f}% of range, "
                     f"{100 * entry['within_1_grey']:.1f}% of pixels within 1 grey level")
        print(f"  {method:8s} {entry['png']}{extra}")
    print(f"wrote {args.out}/ (PNGs, error maps *_error.png, depth_figure.png, demo.json)")
    print("speed against accuracy of every method: `mipcast bench` (table and chart in mipcast-bench/); "
          "foveation against full quality: `mipcast bench --foveation`")
    return 0


def _run_render(args) -> int:
    """Render one volume file to a PNG."""
    from mipcast.io import read_volume, with_scalars
    from mipcast.core.parameters import set_parameters

    from mipcast.core.validation import check_image
    from mipcast.mappers.input_preparer import window_image

    if args.slab_sweep is not None and args.turntable is not None:
        raise ValueError("--slab-sweep and --turntable are two animations: give one of them")
    if args.slab_sweep is None and args.turntable is None and args.out.suffix.lower() not in PICTURE_SUFFIXES:
        raise ValueError(f"--out {args.out} names no picture format: end it in {', '.join(PICTURE_SUFFIXES)} "
                         "(an animated .gif or .mp4 with --turntable or --slab-sweep)")
    image = with_scalars(read_volume(args.input, series_uid=args.series, volume=args.volume, padding=args.padding),
                         args.scalars)
    component = getattr(args, "component", None)
    check_image(image, component)  # mipcast.InputError before anything renders
    window = _window(window_image(image, component), args.window, args.method)
    distance = args.sample_distance
    if distance == "auto":
        from mipcast.bench.auto_sampling import choose_samples_per_voxel

        camera = OffscreenView(image, "mip", size=tuple(args.size), view=args.view, window=window,
                               component=component).camera
        choice = choose_samples_per_voxel(image, camera, tuple(args.size), window=window)
        distance = choice.sample_distance
        verdict = "meets" if choice.met else "misses (densest candidate used)"
        print(f"auto sampling: {choice.samples_per_voxel:g} samples per voxel (distance {distance:.4g}); "
              f"{100 * choice.within_target:.1f}% of {choice.calibration_rays} calibration rays within one "
              f"grey level: {verdict} the target")
    view = OffscreenView(image, args.method, size=tuple(args.size), view=args.view,
                         sample_distance=distance, window=window, component=component)
    set_parameters(view.mapper, **args.params)
    if args.stereo is not None:
        from mipcast.mappers.stereo import set_stereo

        set_stereo(view.render_window, args.stereo, args.eye_angle, view.camera)
    elif args.eye_angle is not None:
        raise ValueError("--eye-angle needs --stereo anaglyph|side-by-side")
    if args.turntable is not None:
        from mipcast.app.turntable import write_turntable

        write_turntable(view, args.turntable, args.out)
        print(f"wrote {args.out} ({args.turntable} frames)")
        return 0
    if args.slab_sweep is not None:
        from mipcast.app.turntable import write_slab_sweep

        write_slab_sweep(view, args.slab_sweep, args.out)
        print(f"wrote {args.out} ({args.slab_sweep} frames)")
        return 0
    args.out.parent.mkdir(parents=True, exist_ok=True)
    _write_png(args.out, view.screenshot())
    print(f"wrote {args.out}")
    return 0


def _window(image, tokens, method: str = "mip"):
    """``--window`` tokens -> (low, high) for ``method``'s projection; says which rule chose a default one."""
    from mipcast.core.windowing import (describe_dicom_windows, dicom_windows, parse_window, resolve_window,
                                        window_and_reason)

    projection = METHODS[method].projection if method in METHODS else "mip"
    if method == "stock_average":  # VTK's AVERAGE_INTENSITY blend draws a grey of the data-range-normalised mean
        print("stock_average draws VTK's own grey, which ignores the window and colours: --method average "
              "or analytic_average draws the mean through them")
    spec = parse_window(tokens)
    if spec is None or spec == "auto":
        window, reason = window_and_reason(image, projection)
        print(f"window {window[0]:.6g} to {window[1]:.6g} ({reason}; --window full for the data range)")
        own = dicom_windows(image)
        if own:
            print(f"the series' own windows: --window {describe_dicom_windows(own)}")
        return window
    return resolve_window(image, spec, projection)


def _index(text: str, expected: str) -> int:
    """An integer >= 0 from the command line, or the ``argparse`` error naming ``expected``."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return value


def _component(text: str):
    """``--component``: an integer >= 0 or ``magnitude``."""
    if text.lower() == "magnitude":
        return None
    return _index(text, "an integer >= 0 or 'magnitude'")


def _volume(text: str) -> int:
    """``--volume``: an integer >= 0."""
    return _index(text, "an integer >= 0 (the first volume is 0)")


def _distance(text: str):
    """``--sample-distance``: a positive number or ``auto``."""
    if text == "auto":
        return text
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number or 'auto', got {text!r}") from None
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text!r}")
    return value


def run_view(args) -> int:
    """Open the interactive viewer on one volume file; without a display, say so and return 2.

    Examples
    --------
    Without a display (forced here) nothing is read: it points to ``render``.

    >>> from unittest import mock
    >>> with mock.patch("mipcast.app.viewer.has_display", return_value=False):
    ...     main(["view", "head.nii.gz"])
    2
    """
    from mipcast.app.viewer import has_display, run_viewer

    if not has_display():
        print(f"mipcast view: no display: use `mipcast render {args.input} --out x.png` "
              "to render to a file instead", file=sys.stderr)
        return 2
    from mipcast.io import read_volume, with_scalars

    from mipcast.core.validation import check_image
    from mipcast.mappers.input_preparer import window_image

    image = with_scalars(read_volume(args.input, series_uid=args.series, volume=args.volume, padding=args.padding),
                         args.scalars)
    check_image(image, args.component)  # mipcast.InputError before the window opens
    run_viewer(image, args.method, clim=_window(window_image(image, args.component), args.window, args.method),
               params=args.params, view=args.view, component=args.component,
               stereo=args.stereo)  # checks params before the window
    return 0


def _run_bench(args) -> int:
    """Time and check every setting against stock VTK MIP on each scene, view and size."""
    if args.gpu_report or args.peers:
        from mipcast.bench.gpu_report import run_cli
        return run_cli(args)
    if args.stability:
        return _run_stability(args)
    if args.foveation:
        return _run_foveation(args)
    from mipcast.bench import paper_tables
    from mipcast.bench.benchmark import default_settings, markdown_table, measure_scene, write_chart

    args.out.mkdir(parents=True, exist_ok=True)
    sizes = args.size or [256, 512]
    rows = []
    started = time.perf_counter()
    jobs = [(scene, view, edge) for scene in args.scenes for view in args.views for edge in sizes]
    steps_per_job = 1 + args.rounds + len(default_settings())  # auto's calibration, rounds, error per setting
    with _progress_bar(len(jobs) * steps_per_job) as bar:
        for number, (scene, view, edge) in enumerate(jobs, 1):
            image, window = _load_scene(scene, args.volume_size)
            bar.set_description(f"[{number}/{len(jobs)}] {scene} {view} {edge}²")
            new = measure_scene(image, scene, view, edge, rounds=args.rounds, window=window,
                                progress=lambda label: _advance(bar, label))
            rows += new
            bar.write(f"[{number}/{len(jobs)}] {scene} {view} {edge}²: " + ", ".join(
                f"{r['setting']} x{r['ratio_to_stock']:.2f} p99 {r['p99_pct']:.3g}%" for r in new))
    columns = ["scene", "view", "size", "setting", "projection", "median_ms", "ratio_to_stock",
               "ratio_to_stock_blend", "p99_pct", "fg_p99_pct", "max_pct", "within_1_grey", "frames",
               "texel_fetches", "skipped_cells", "ray_ratio", "sample_ratio"]
    if any("missing_data_misses" in r for r in rows):
        columns.insert(columns.index("frames"), "missing_data_misses")
    (args.out / "bench.json").write_text(strict_json(rows, indent=2))
    (args.out / "bench.md").write_text(markdown_table(rows, columns) + "\n")
    write_chart(rows, args.out / "bench.png")
    (args.out / "papers.md").write_text("\n\n".join(
        [paper_tables.amip_table(rows), paper_tables.demip_table(rows), paper_tables.demip_passes_table(rows),
         paper_tables.levoy_table(rows)]) + "\n")
    print(markdown_table(rows, columns))
    print(f"wrote {args.out}/bench.json, bench.md, bench.png, papers.md "
          f"({time.perf_counter() - started:.0f} s)")
    return 0


def _run_foveation(args) -> int:
    """Foveated variants against full quality (:mod:`mipcast.bench.foveation_bench`): foveation.md/json/png."""
    from mipcast.bench.foveation_bench import FRAMINGS, GAZES, VARIANTS, foveation_table, measure_foveation, write_ring_chart

    args.out.mkdir(parents=True, exist_ok=True)
    sizes = args.size or [512, 1024]
    rounds = min(args.rounds, 3)
    started = time.perf_counter()
    jobs = [(scene, method) for scene in args.scenes for method in args.foveation_methods]
    unknown = sorted(set(args.foveation_variants or ()) - set(VARIANTS))
    if unknown:
        raise SystemExit(f"unknown --foveation-variants {', '.join(map(repr, unknown))}; "
                         f"valid: {', '.join(map(repr, VARIANTS))}")
    variants = {name: VARIANTS[name] for name in (args.foveation_variants or VARIANTS)}
    framings = args.framings or list(FRAMINGS)
    views = 3 + len(variants) * len(GAZES)  # full, off, variants, periphery alone
    rows = []
    with _progress_bar(len(jobs) * len(sizes) * len(framings) * (rounds + views)) as bar:
        for scene, method in jobs:
            image, window = _load_scene(scene, args.volume_size)
            bar.set_description(f"{scene} {method}")
            rows += measure_foveation(image, scene, method, sizes=sizes, rounds=rounds, window=window,
                                      framings=framings, variants=variants,
                                      progress=lambda label: _advance(bar, label))
    from mipcast.bench.foveation_bench import gaze_table, measure_gaze_latency, measure_progressive, progressive_table

    progressive, gaze = [], []
    for scene, method in jobs:  # progressive refinement and the gaze stream at the largest size, volume filling
        image, window = _load_scene(scene, args.volume_size)
        progressive.append(measure_progressive(image, scene, method, size=max(sizes), window=window))
        gaze.append(measure_gaze_latency(image, scene, method, size=max(sizes), window=window))
    (args.out / "foveation.json").write_text(strict_json(rows, indent=2))
    (args.out / "foveation-progressive.json").write_text(strict_json({"progressive": progressive, "gaze": gaze}, indent=2))
    table = foveation_table(rows) + "\n\nProgressive refinement (gaze at the centre, default radius):\n\n" + \
        progressive_table(progressive) + "\n\nGaze stream (synthetic trace replayed, re-render only when the " \
        "stream moves the gaze):\n\n" + gaze_table(gaze)
    (args.out / "foveation.md").write_text(table + "\n")
    write_ring_chart(rows, args.out / "foveation.png")
    print(table)
    print(f"wrote {args.out}/foveation.json, foveation.md, foveation.png ({time.perf_counter() - started:.0f} s)")
    return 0


def _progress_bar(total: int):
    """A tqdm bar on stderr (plain lines when stderr is not a terminal)."""
    from tqdm import tqdm

    return tqdm(total=total, unit="step", dynamic_ncols=True, mininterval=1.0,
                bar_format="{desc} {percentage:3.0f}%|{bar}| {n}/{total} [{elapsed}<{remaining}] {postfix}")


def _advance(bar, label: str) -> None:
    bar.set_postfix_str(label[-60:], refresh=False)
    bar.update(1)


def _run_stability(args) -> int:
    """Measure every stability case (:mod:`mipcast.bench.stability`) and write stability.md/json."""
    from mipcast.bench.benchmark import markdown_table
    from mipcast.bench.stability import cases, measure

    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    all_cases = cases()
    for number, case in enumerate(all_cases, 1):
        rows.append(measure(case))
        print(f"[{number}/{len(all_cases)}] {case.method}: {case.name}: "
              f"p99 {rows[-1]['p99_pct']:.3g}% ({rows[-1]['measured']})", flush=True)
    columns = ["method", "case", "measured", "p99_pct", "max_pct", "within_1_grey", "depth_jump_pct",
               "fovea_within_1_grey", "fovea_structure_within_1_grey", "explanation"]
    (args.out / "stability.json").write_text(strict_json(rows, indent=2))
    (args.out / "stability.md").write_text(markdown_table(rows, columns) + "\n")
    print(markdown_table(rows, columns))
    print(f"wrote {args.out}/stability.json and stability.md")
    return 0


def _load_scene(scene: str, volume_size: int):
    """``NAME[@LOW,HIGH]`` -> (vtkImageData, window; default the data range).

    NAME is a fixture, ``head`` (the head CT) or a volume file; ``@LOW,HIGH``
    sets the grey window (e.g. ``head@100,1500``, a CT angiography window).
    """
    from mipcast.data_fixtures import FIXTURES, load_head_ct, make_fixture

    name, _, window_text = scene.partition("@")
    window = tuple(float(v) for v in window_text.split(",")) if window_text else None
    if window is not None and len(window) != 2:
        raise ValueError(f"scene window must be @LOW,HIGH, got {scene!r}")
    if name in FIXTURES:
        image = make_fixture(name, size=volume_size)
    elif name == "head":
        image = load_head_ct()
    else:
        from mipcast.io import read_volume
        image = read_volume(Path(name))
    # the measured tables (docs/bench.md, ...) use the data range, not the default window
    return image, window if window is not None else tuple(image.GetPointData().GetScalars().GetRange(0))


#: What ``mipcast render --out`` writes a picture as (matplotlib's imsave, through Pillow).
PICTURE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".bmp", ".webp", ".gif")


def _write_png(path: Path, pixels: np.ndarray) -> None:
    """Write an (H, W) or (H, W, 3) uint8 array, top row first, as PNG."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib import pyplot

    pyplot.imsave(path, pixels, cmap="gray" if pixels.ndim == 2 else None, vmin=0, vmax=255)


def _write_error_map(path: Path, values: np.ndarray, reference_values: np.ndarray, data_range: float) -> None:
    """Write |values - reference| in percent of the data range as a colour-mapped PNG."""
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib import pyplot

    from mipcast.core.metrics import error_map

    percent = 100.0 * error_map(values, reference_values) / data_range
    figure, axes = pyplot.subplots(figsize=(5, 4.2), dpi=100)
    shown = axes.imshow(percent, cmap="magma", vmin=0.0, vmax=max(5.0, float(np.nanmax(percent))))
    axes.set_axis_off()
    axes.set_title("|GPU - exact reference|, % of data range")
    figure.colorbar(shown, ax=axes, fraction=0.046)
    figure.savefig(path, bbox_inches="tight")
    pyplot.close(figure)


def _grey8(values: np.ndarray, low: float, high: float) -> np.ndarray:
    scaled = np.clip((np.nan_to_num(values, nan=low) - low) / (high - low), 0.0, 1.0)
    return np.round(255 * scaled).astype(np.uint8)


if __name__ == "__main__":
    sys.exit(main())
