"""The GPU report (``mipcast bench --gpu-report``): a fixed suite for one lent GPU, about 6 minutes.

Sections, in order (:func:`run_report`):

1. ``parity``: mipcast's ``mip`` against stock VTK MIP (8-bit pictures),
   ``analytic`` against the float64 exact reference, ``demip`` against its
   reference (picture and depth), at small sizes.
2. ``speed_accuracy``: every method's frame time (ratio to stock, one
   process, interleaved rounds) and error against the exact reference at
   512² and 1024², on a CT-sized synthetic volume (:func:`mipcast.data_fixtures.ct_volume`,
   512x512x400 int16) and the head CT, each with and without a clinical
   window.  Errors are computed on a fixed random subset of the hit rays
   (:func:`exact_on_rays`), the float64 reference being too slow for every
   pixel of a 1024² frame.
3. ``foveation``: :func:`mipcast.bench.foveation_bench.measure_foveation`
   with the volume filling the view, default settings, gaze at the centre and a corner.
4. ``first_frame``: seconds from a new window to its first finished frame
   (texture upload, corner packing, shader build) per method, and whether
   analytic's is within 1.5x stock's (:data:`FIRST_FRAME_GOAL`).
5. ``memory``: GPU memory per method, from the driver where it reports it
   (``nvidia-smi``, device-wide used memory before and after the view; the
   free memory OpenGL reports, which mipcast's texture budget reads:
   :func:`gl_limits`, with the 3D texture limit), and always the computed
   texture bytes (:func:`texture_bytes`).
6. ``peers``: vispy's rows (:mod:`mipcast.bench.peers`) when vispy imports.

Only vtk (``vtkmodules``), numpy, matplotlib, tqdm and mipcast are imported,
so the report runs where VTK is unpacked from a kit (docs/gpu/README.md).
``quick=True`` runs the same code at tiny sizes (volumes <= 48³, images <= 96²).

Examples
--------
>>> is_software("llvmpipe (LLVM 15.0.6, 256 bits)"), is_software("NVIDIA H200/PCIe/SSE2")
(True, False)
"""
from __future__ import annotations

import shutil
import statistics
import subprocess
import time
from pathlib import Path
from typing import Callable, NamedTuple, Optional, Sequence

import numpy as np

from mipcast.bench.report import renderer_info, strict_json
from mipcast.mappers.gpu_limits import free_gpu_memory, max_texture_size_3d
from mipcast.data_fixtures.ct_phantom import ct_volume

#: Substrings of a GL_RENDERER string that mean a CPU renderer.
SOFTWARE_RENDERERS = ("llvmpipe", "softpipe", "swrast", "software")
#: Methods of the speed x accuracy, first-frame and memory sections; the first is the baseline.
METHODS = ("stock", "mip", "analytic", "demip", "foveated")
#: Analytic's first frame may take at most this many times stock's (512x512x400 int16 CT).
FIRST_FRAME_GOAL = 1.5
#: A clinical CT window, HU.
CLINICAL_WINDOW = (100.0, 1500.0)


class Sizes(NamedTuple):
    """Sizes of one run of the report (:data:`FULL`, :data:`QUICK`)."""

    parity_volume: int          # edge of the parity fixtures
    parity_image: int           # edge of the parity images
    ct_shape: tuple             # (nz, ny, nx) of the synthetic CT
    images: tuple               # square image edges of speed x accuracy
    head_stride: int            # keep every n-th head CT point per axis
    error_rays: Optional[int]   # rays compared with the reference per image (None: all)
    rounds: int                 # interleaved timing rounds
    frames: int                 # frames per round
    phantom_volume: int         # edge of the vessel fixture of the phantoms' foveation section


FULL = Sizes(64, 128, (400, 512, 512), (512, 1024), 1, 8192, 3, 2, 128)
QUICK = Sizes(24, 48, (40, 48, 48), (64, 96), 6, None, 1, 1, 24)
#: Grey windows of issue 17's scenes (its goal, >= 6x at the centre, names the vessel fixture and the
#: windowed head CT); the foveation benchmark's rows in docs/foveation.md use the same.
PHANTOM_WINDOWS = {"vessels": (0.25, 1.0), "head": CLINICAL_WINDOW}


def is_software(renderer: str) -> bool:
    """Whether a GL_RENDERER string names a software renderer (:data:`SOFTWARE_RENDERERS`).

    Examples
    --------
    >>> is_software("softpipe"), is_software("Mesa X11 Software Rasterizer")
    (True, True)
    """
    text = renderer.lower()
    return any(name in text for name in SOFTWARE_RENDERERS)


def head_scene(stride: int = 1):
    """The head CT (every ``stride``-th point per axis), or None when it is not installed.

    Examples
    --------
    >>> image = head_scene(8)
    >>> image is None or max(image.GetDimensions()) <= 32
    True
    """
    from mipcast.data_fixtures import head_ct_path, image_from_array, load_head_ct
    from vtkmodules.util.numpy_support import vtk_to_numpy

    if head_ct_path() is None:
        return None
    image = load_head_ct()
    if stride <= 1:
        return image
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(nz, ny, nx)[::stride, ::stride, ::stride]
    spacing = tuple(s * stride for s in image.GetSpacing())
    return image_from_array(np.ascontiguousarray(values), name="hu", spacing=spacing, origin=image.GetOrigin())


def exact_on_rays(image, camera, size: Sequence[int], max_rays: Optional[int] = None, seed: int = 0) -> dict:
    """The exact maximum (float64 analytic reference) on a fixed random subset of a frame's hit rays.

    Parameters
    ----------
    image : vtkImageData
        The volume.
    camera : vtkCamera
        The view.
    size : (width, height)
        The frame.
    max_rays : int, optional
        Rays to compute; all hit rays when None or when fewer hit.
    seed : int
        Seed of the subset.

    Returns
    -------
    dict
        ``pixels`` (flat indices, top row first), ``exact`` (their maxima),
        ``silhouette`` (bool: on the outline, where a GPU miss is rounding),
        ``hit_pixels`` (all hit rays of the frame), ``seconds``.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.offscreen import OffscreenView
    >>> view = OffscreenView(make_fixture("spheres", size=16), size=(24, 24))
    >>> rays = exact_on_rays(view.image, view.camera, (24, 24), max_rays=50)
    >>> len(rays["pixels"]), rays["hit_pixels"] > 50
    (50, True)
    """
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from mipcast.core.metrics import silhouette
    from mipcast.reference.mip import exact_maximum
    from mipcast.reference.rays import BUDGET, hit_rays

    started = time.perf_counter()
    width, height = (int(v) for v in size)
    hit, entry, direction, length = hit_rays(image, camera, (width, height))
    chosen = np.arange(len(length))
    if max_rays is not None and len(length) > max_rays:
        chosen = np.sort(np.random.default_rng(seed).choice(len(length), max_rays, replace=False))
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(nz, ny, nx).astype(np.float64)
    chunk = max(1, BUDGET // (sum(values.shape) + 2))
    exact = np.empty(len(chosen))
    for start in range(0, len(chosen), chunk):
        part = chosen[start:start + chunk]
        exact[start:start + chunk] = exact_maximum(values, entry[part], direction[part], length[part])
    pixels = np.flatnonzero(hit)[chosen]
    outline = silhouette(np.where(hit.reshape(height, width), 0.0, np.nan)).ravel()[pixels]
    return {"pixels": pixels, "exact": exact, "silhouette": outline, "hit_pixels": int(hit.sum()),
            "seconds": time.perf_counter() - started}


def ray_errors(values: np.ndarray, rays: dict, data_range: float, window=None) -> dict:
    """Error of a float readout (data units, NaN = miss) against :func:`exact_on_rays`.

    Returns ``p99_pct``, ``max_pct`` (% of ``data_range``), ``within_1_grey``
    (one grey level of ``window``, or of the data range), ``rays`` compared,
    ``misses`` off the silhouette (a renderer error; on it, rounding).

    Examples
    --------
    >>> rays = {"pixels": np.array([0, 1, 2]), "exact": np.array([1.0, 2.0, 3.0]),
    ...         "silhouette": np.array([False, False, True])}
    >>> errors = ray_errors(np.array([[1.0, 2.5, np.nan]]), rays, 10.0)
    >>> errors["max_pct"], errors["rays"], errors["misses"]
    (5.0, 2, 0)
    """
    got = np.asarray(values, np.float64).ravel()[rays["pixels"]]
    compared = ~np.isnan(got)
    error = np.abs(got[compared] - rays["exact"][compared])
    grey = (float(window[1]) - float(window[0])) / 255.0 if window is not None else data_range / 255.0
    if error.size == 0:
        stats = {"p99_pct": float("nan"), "max_pct": float("nan"), "within_1_grey": float("nan")}
    else:
        stats = {"p99_pct": 100.0 * float(np.percentile(error, 99)) / data_range,
                 "max_pct": 100.0 * float(error.max()) / data_range,
                 "within_1_grey": float(np.mean(error <= grey))}
    return {**stats, "rays": int(compared.sum()), "misses": int(np.sum(~compared & ~rays["silhouette"]))}


def texture_bytes(image, method: str) -> dict:
    """Computed bytes of the volume textures a method uploads (no driver needed).

    ``volume``: points x bytes per point (VTK uploads 8/16-bit integers and
    float32 as they are, other types as float32); analytic uploads its packed
    corners, four values per point (:mod:`mipcast.mappers.corner_packing`)
    instead of the volume; foveated adds its max pyramid's coarser levels
    (:func:`mipcast.mappers.volume_pyramid.coarse_axis`, the mapper's default
    number of levels).  Frame buffers and small lookup textures are not counted.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=16)
    >>> texture_bytes(image, "stock")["total"], texture_bytes(image, "analytic")["total"]
    (16384, 65536)
    """
    from mipcast.mappers.volume_pyramid import coarse_axis

    scalars = image.GetPointData().GetScalars()
    size = scalars.GetDataTypeSize() if scalars.GetDataTypeAsString() in (
        "char", "signed char", "unsigned char", "short", "unsigned short", "float") else 4
    dims = list(image.GetDimensions())
    volume = int(np.prod(dims)) * size
    parts = {"volume": volume}
    if method == "analytic":
        parts = {"packed_corners": 4 * volume}
    elif method == "foveated":
        from mipcast.mappers.foveated import FoveatedVolumeMapper

        levels, coarse = FoveatedVolumeMapper().GetNumberOfLevels(), 0
        for _ in range(1, levels):
            dims = [coarse_axis(n) for n in dims]
            coarse += int(np.prod(dims)) * size
        parts["pyramid_levels"] = coarse
    parts["total"] = sum(parts.values())
    return parts


def driver_memory_used() -> Optional[float]:
    """Device memory in use, MiB, from ``nvidia-smi`` (None where there is none or it fails).

    Examples
    --------
    >>> value = driver_memory_used()
    >>> value is None or value >= 0
    True
    """
    if shutil.which("nvidia-smi") is None:
        return None
    try:
        output = subprocess.run(["nvidia-smi", "--query-gpu=memory.used", "--format=csv,noheader,nounits"],
                                capture_output=True, text=True, timeout=20, check=True).stdout
        return float(output.split()[0])
    except (OSError, subprocess.SubprocessError, ValueError, IndexError):
        return None


def first_frame(image, method: str, size: Sequence[int], window=None, settle_s: float = 2.0) -> dict:
    """Seconds from a new window to its first finished frame, the frames after it, and memory.

    The first frame holds the texture upload, the block maxima and shader
    build (analytic; a large volume's packed corners come later, made in the
    background: :meth:`~mipcast.mappers.analytic.AnalyticMIPVolumeMapper.SetPackingDelay`)
    or the pyramid (foveated).  Then frames are drawn for ``settle_s``
    seconds (at least 3): ``next_s`` is the median of the last 3 (the steady
    state), ``slowest_next_s`` the slowest of them all (analytic: the frame
    that uploads the packed copy).  ``memory_mib`` is the driver's used
    memory after them minus before (None without a driver that reports it).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> result = first_frame(make_fixture("spheres", size=16), "mip", (24, 24), settle_s=0.0)
    >>> result["first_s"] > 0 and result["next_s"] > 0 and result["slowest_next_s"] >= result["next_s"]
    True
    """
    from mipcast.offscreen import OffscreenView

    before = driver_memory_used()
    started = time.perf_counter()
    view = OffscreenView(image, method, size=tuple(size), window=window)
    view.frame_times(frames=0, warmup=1)
    first = time.perf_counter() - started
    later: list = []
    settled = time.perf_counter() + settle_s
    while len(later) < 3 or time.perf_counter() < settled:
        later += view.frame_times(frames=1, warmup=0)
    after = driver_memory_used()
    free = free_gpu_memory(view.render_window)
    view.render_window.Finalize()
    memory = after - before if before is not None and after is not None else None
    return {"method": method, "first_s": first, "next_s": statistics.median(later[-3:]),
            "slowest_next_s": max(later), "frames_after": len(later), "memory_mib": memory,
            "gl_free_mib": None if free is None else free / 2 ** 20,
            "texture_bytes": texture_bytes(image, method)}


def gl_limits() -> dict:
    """What mipcast asks the driver before it draws (:mod:`mipcast.mappers.gpu_limits`), from a small window.

    ``max_texture_size_3d`` (points per axis: beyond it mipcast draws bricks)
    and ``free_mib`` (``GL_NVX_gpu_memory_info`` / ``GL_ATI_meminfo``; None
    where the driver cannot say, as llvmpipe).

    Examples
    --------
    >>> limits = gl_limits()
    >>> limits["max_texture_size_3d"] > 0, sorted(limits)
    (True, ['free_mib', 'max_texture_size_3d'])
    """
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.AddRenderer(vtkRenderer())
    window.SetSize(16, 16)
    window.Render()
    free = free_gpu_memory(window)
    limits = {"max_texture_size_3d": max_texture_size_3d(window), "free_mib": None if free is None else free / 2 ** 20}
    window.Finalize()
    return limits


def parity_checks(sizes: Sizes) -> dict:
    """mip vs stock, analytic vs the exact reference, DEMIP vs its reference, at small sizes.

    Returns
    -------
    dict
        ``mip_vs_stock`` (per view: :func:`mipcast.core.metrics.grey_diff`;
        passed within 1 grey: mipcast reads VTK's colour tables where they
        hold the value, stock half a table step off, docs/methods.md),
        ``analytic_vs_exact`` (per view: p99 and max in % of the data range,
        within one grey level), ``demip_vs_reference`` (per view: share of
        pixels within 2 grey levels of the reference picture, share of depths
        within 1e-4), each with ``passed``.

    Examples
    --------
    >>> result = parity_checks(QUICK)
    >>> sorted(result)
    ['analytic_vs_exact', 'demip_vs_reference', 'mip_vs_stock']
    """
    from mipcast import reference
    from mipcast.core.metrics import grey_diff, summary
    from mipcast.data_fixtures import make_fixture
    from mipcast.mappers.demip import render_depth
    from mipcast.offscreen import OffscreenView

    image = make_fixture("vessels", size=sizes.parity_volume)
    size = (sizes.parity_image, sizes.parity_image)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    result: dict = {"mip_vs_stock": {}, "analytic_vs_exact": {}, "demip_vs_reference": {}}
    for view in ("oblique", "perspective"):
        pictures = {m: OffscreenView(image, m, size=size, view=view).screenshot() for m in ("stock", "mip")}
        diff = grey_diff(pictures["stock"], pictures["mip"])
        result["mip_vs_stock"][view] = {**diff, "passed": diff["max"] <= 1}
        analytic = OffscreenView(image, "analytic", size=size, view=view)
        exact = reference.render(image, analytic.camera, size, method="analytic")
        errors = summary(analytic.float_image(), exact, high - low)
        result["analytic_vs_exact"][view] = {"p99_pct": errors["p99_pct"], "max_pct": errors["max_pct"],
                                             "within_1_grey": errors["within_1_grey"],
                                             "passed": errors["within_1_grey"] >= 0.999}
        result["demip_vs_reference"][view] = _demip_parity(image, size, view, reference, render_depth)
    return result


def _demip_parity(image, size, view: str, reference, render_depth) -> dict:
    from mipcast.offscreen import OffscreenView

    scene = OffscreenView(image, "demip", size=size, view=view)
    picture = scene.screenshot().astype(float)
    depth = render_depth(scene.render_window, scene.mapper)
    common = dict(sample_distance=scene.sample_distance, window=scene.window)
    expected_rgb = reference.render(image, scene.camera, size, method="demip", output="rgb", **common)
    expected_depth = reference.render(image, scene.camera, size, method="demip", output="depth", **common)
    hits = ~np.isnan(expected_rgb[..., 0])
    grey = np.abs(picture - np.round(255 * np.nan_to_num(expected_rgb))).max(axis=-1)
    both = ~np.isnan(depth) & ~np.isnan(expected_depth)
    depth_ok = float(np.mean(np.abs(depth[both] - expected_depth[both]) <= 1e-4)) if both.any() else 1.0
    within = float(np.mean(grey[hits] <= 2)) if hits.any() else float("nan")
    return {"grey_within_2": within, "depth_within_1e-4": depth_ok,
            "passed": bool(within >= 0.99 and depth_ok >= 0.999)}


def speed_accuracy(image, scene: str, sizes: Sizes, windows: Sequence = (None,), methods: Sequence[str] = METHODS,
                   progress: Optional[Callable[[str], None]] = None) -> list:
    """Frame time (ratio to stock) and error against the exact reference of each method.

    One view per method is built once and reused for every window and
    size (the texture is uploaded once); the reference is computed once per
    size (the window changes the picture, not the maxima).  Stock has no
    float readout: mipcast's ``mip`` takes its very samples (``parity``), so its
    error stands for stock's.

    Returns
    -------
    list of dict
        ``scene``, ``window`` (None: data range), ``size``, ``method``,
        ``median_ms``, ``ratio_to_stock``, ``frames`` and :func:`ray_errors`'s figures.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = speed_accuracy(make_fixture("spheres", size=16), "spheres", QUICK._replace(images=(24,)),
    ...                       methods=("stock", "mip", "analytic"))
    >>> [(row["method"], row["ratio_to_stock"]) for row in rows][0], rows[2]["within_1_grey"]
    (('stock', 1.0), 1.0)
    """
    from mipcast.bench.benchmark import interleaved_frame_times
    from mipcast.offscreen import OffscreenView, grey_property

    if "stock" in methods and "mip" not in methods:
        raise ValueError("stock's error is read from mip's readout: methods must include 'mip' with 'stock'")
    report = progress or (lambda label: None)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    views = {m: OffscreenView(image, m, size=(sizes.images[0],) * 2) for m in methods}
    rows = []
    for edge in sizes.images:
        for view in views.values():
            view.render_window.SetSize(edge, edge)
        rays = exact_on_rays(image, views[methods[0]].camera, (edge, edge), sizes.error_rays)
        report(f"{scene} {edge}²: reference on {len(rays['pixels'])} rays ({rays['seconds']:.0f} s)")
        for window in windows:
            for view in views.values():
                view.window = tuple(window) if window is not None else (low, high)
                view.volume.SetProperty(grey_property(view.window))
            times = interleaved_frame_times(views, sizes.rounds, sizes.frames, 2)
            base = statistics.median(times[methods[0]])
            readouts = {m: views["mip" if m == "stock" else m].float_image() for m in methods}
            for method in methods:
                median = statistics.median(times[method])
                rows.append({"scene": scene, "window": list(window) if window is not None else None,
                             "size": edge, "method": method, "median_ms": 1000 * median,
                             "ratio_to_stock": median / base, "frames": len(times[method]),
                             "error_from": "mip readout" if method == "stock" else method,
                             **ray_errors(readouts[method], rays, high - low, window)})
            report(f"{scene} {edge}² window {window}: " + ", ".join(
                f"{r['method']} x{r['ratio_to_stock']:.2f}" for r in rows[-len(methods):]))
    for view in views.values():
        view.render_window.Finalize()
    return rows


#: Methods whose block skipping the report times against reading every sample (``SetSkipping(False)``).
SKIPPING_METHODS = ("mip", "analytic", "demip")


def skipping_rows(image, scene: str, sizes: Sizes, window=CLINICAL_WINDOW,
                  methods: Sequence[str] = SKIPPING_METHODS) -> list:
    """Block skipping against every sample (cell), per method, at the largest size, in a window with a floor.

    On llvmpipe skipping takes a third off sampled MIP and DEMIP on the vessels
    (docs/methods.md, *Block skipping*); a GPU runs a ray's samples in lockstep
    with its neighbours', so a jump only pays when the whole group jumps:
    whether the saving survives is what this section measures.

    Returns
    -------
    list of dict
        ``scene``, ``size``, ``method``, ``skipping_ms``, ``every_ms`` (medians of interleaved
        frames), ``every_over_skipping``, ``skips_blocks`` (the block loop was installed) and
        ``identical`` (the two 8-bit pictures, pixel for pixel).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = skipping_rows(make_fixture("vessels", size=24), "vessels", QUICK._replace(images=(32,)),
    ...                      window=(0.25, 1.0), methods=("mip",))
    >>> rows[0]["method"], rows[0]["identical"]
    ('mip', True)
    """
    from mipcast.bench.benchmark import interleaved_frame_times
    from mipcast.offscreen import OffscreenView

    edge = max(sizes.images)
    rows = []
    for method in methods:
        views = {}
        for skipping in (True, False):
            view = OffscreenView(image, method, size=(edge, edge), window=tuple(window))
            view.mapper.SetSkipping(skipping)
            views[skipping] = view
        times = interleaved_frame_times(views, sizes.rounds, sizes.frames, 2)
        on, off = (1000 * statistics.median(times[k]) for k in (True, False))
        rows.append({"scene": scene, "size": edge, "method": method, "skipping_ms": on, "every_ms": off,
                     "every_over_skipping": off / on,
                     "skips_blocks": any(n.endswith("_blocks") for n in views[True].mapper.GetShaderPieces()),
                     "identical": bool(np.array_equal(views[True].screenshot(), views[False].screenshot()))})
        for view in views.values():
            view.render_window.Finalize()
    return rows


def foveation_rows(image, scene: str, sizes: Sizes, window=None, progress=None,
                   variants: Sequence[str] = ("default", "content-adaptive 2 grey",
                                              "content-adaptive 2 grey, no content level")) -> list:
    """The foveation benchmark, volume filling the view, gaze at the centre and a corner.

    By default acuity-only foveation (the defaults) and content-adaptive
    density at 2 grey levels, the setting issue 17's goal (>= 6x at the
    centre) is measured with, also without its content level (on llvmpipe
    worth 1.3-1.4x on the CT-sized volume and a cost of 4-12 % on the
    phantoms: docs/foveation.md); ``variants`` names other
    :data:`mipcast.bench.foveation_bench.VARIANTS`.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = foveation_rows(make_fixture("spheres", size=16), "spheres", QUICK._replace(images=(32,)))
    >>> [row["setting"] for row in rows][:3]
    ['full quality', 'foveation off', 'default | centre']
    """
    from mipcast.bench.foveation_bench import GAZES, VARIANTS, measure_foveation

    return measure_foveation(image, scene, "mip", sizes=list(sizes.images), framings=("fill",),
                             variants={name: VARIANTS[name] for name in variants}, gazes=GAZES,
                             rounds=sizes.rounds, frames=sizes.frames, warmup=2, window=window,
                             progress=progress)


def phantom_foveation_rows(scenes: dict, sizes: Sizes, progress=None) -> list:
    """The foveation benchmark on issue 17's scenes, the vessel fixture and the windowed head CT, largest size.

    Windows :data:`PHANTOM_WINDOWS`; acuity only and content-adaptive
    density at 2 and 8 grey levels (llvmpipe, 1024²: 5.6x and 5.75x fewer
    samples than full quality on the vessels at the centre, but about 2.8x
    in time, which only a GPU can say more about).  The head comes from ``scenes``
    (:func:`_scenes`; absent when it is not installed).

    Examples
    --------
    >>> rows = phantom_foveation_rows({}, QUICK._replace(images=(32,), phantom_volume=12))
    >>> sorted({row["scene"] for row in rows}), [row["setting"] for row in rows][6:8]
    (['vessels@0.25,1'], ['content-adaptive 8 grey | centre', 'content-adaptive 8 grey | corner'])
    """
    from mipcast.data_fixtures import make_fixture

    images = {"vessels": make_fixture("vessels", size=sizes.phantom_volume), "head": scenes.get("head")}
    largest = sizes._replace(images=sizes.images[-1:])
    rows = []
    for name, image in images.items():
        if image is None:
            continue
        low, high = PHANTOM_WINDOWS[name]
        rows += foveation_rows(image, f"{name}@{low:g},{high:g}", largest, (low, high), progress,
                               variants=("default", "content-adaptive 2 grey", "content-adaptive 8 grey",
                                         "content-adaptive 2 grey, no content level"))
    return rows


def frame_overhead_rows(sizes: Sizes, progress=None) -> list:
    """Wall and CPU time of full-quality and foveated frames of the vessel fixture (its issue-17 window), still,
    gaze moving and camera turning, at 32² (the rays cost next to nothing) and the largest size
    (:func:`mipcast.bench.frame_overhead.measure_frame_overhead`): on a GPU, how much of a foveated frame is the
    CPU's work.

    Examples
    --------
    >>> rows = frame_overhead_rows(QUICK._replace(images=(32,), phantom_volume=12, frames=1))
    >>> sorted({row["size"] for row in rows}), sorted({row["move"] for row in rows})
    ([32], ['camera turning', 'gaze moving', 'still'])
    """
    from mipcast.bench.frame_overhead import measure_frame_overhead
    from mipcast.data_fixtures import make_fixture

    low, high = PHANTOM_WINDOWS["vessels"]
    image = make_fixture("vessels", size=sizes.phantom_volume)
    return measure_frame_overhead(image, f"vessels@{low:g},{high:g}", sorted({32, sizes.images[-1]}), (low, high),
                                  frames=4 * sizes.rounds * sizes.frames, progress=progress)


def run_report(out: Path, quick: bool = False, allow_software: bool = False,
               log: Callable[[str], None] = lambda line: None) -> dict:
    """Run the whole suite and write ``gpu-report.json``, ``.md`` and ``.png`` into ``out``.

    The three files are rewritten after every section (``sections_done``;
    ``complete`` stays false until the last), so a run cut short by the
    device's time limit or a failure keeps what it had measured.

    Parameters
    ----------
    out : Path
        Output folder (created).
    quick : bool
        Tiny sizes (:data:`QUICK`) instead of :data:`FULL`.
    allow_software : bool
        Run on a software renderer too (otherwise :class:`SoftwareRenderer` is raised).
    log : callable
        Called with each progress line (the CLI prints them).

    Returns
    -------
    dict
        The report, as written to ``gpu-report.json``.

    Raises
    ------
    SoftwareRenderer
        If OpenGL is a software renderer and ``allow_software`` is false.
    """
    started = time.perf_counter()
    info = renderer_info()
    log(f"OpenGL renderer: {info['renderer']} ({info['vendor']}, {info['version']}; {info['window']})")
    software = is_software(info["renderer"])
    if software and not allow_software:
        raise SoftwareRenderer(info["renderer"])
    sizes = QUICK if quick else FULL
    report: dict = {"renderer": info, "software": software, "quick": quick, "sizes": sizes._asdict(),
                    "gl_limits": gl_limits(), "notes": [], "complete": False}

    def done(section: str) -> None:  # every finished section is on disk: a run cut short keeps them
        report["sections_done"] = report.get("sections_done", []) + [section]
        report["elapsed_s"] = time.perf_counter() - started
        write_report(report, out)

    log("parity and accuracy at small sizes")
    report["parity"] = parity_checks(sizes)
    done("parity")
    scenes = _scenes(sizes, report["notes"])
    report["speed_accuracy"] = []
    for name, image in scenes.items():
        log(f"speed x accuracy: {name} {image.GetDimensions()}")
        report["speed_accuracy"] += speed_accuracy(image, name, sizes, (None, CLINICAL_WINDOW), progress=log)
        done(f"speed_accuracy {name}")
    log("block skipping against every sample, clinical window")
    report["skipping"] = [row for name, image in scenes.items() for row in skipping_rows(image, name, sizes)]
    done("skipping")
    log("foveation: volume filling the view, gaze at the centre and a corner")
    report["foveation"] = foveation_rows(scenes["ct"], "ct", sizes, CLINICAL_WINDOW)
    done("foveation")
    log("foveation on issue 17's scenes: the vessel fixture and the windowed head CT, largest size")
    report["foveation_phantoms"] = phantom_foveation_rows(scenes, sizes)
    done("foveation_phantoms")
    log("frame overhead: wall and CPU time of foveated frames, still, gaze moving, camera turning")
    report["frame_overhead"] = frame_overhead_rows(sizes, log)
    done("frame_overhead")
    log("first frame and memory per method")
    report["first_frame"] = [first_frame(scenes["ct"], m, (sizes.images[0],) * 2, settle_s=0.2 if quick else 2.0)
                             for m in METHODS]
    report["first_frame_goal"] = _first_frame_goal(report["first_frame"])
    done("first_frame")
    report["peers"] = _peer_rows(scenes, sizes, report["notes"], log)
    report["complete"] = True
    done("peers")
    log(f"wrote {out}/gpu-report.json, gpu-report.md, gpu-report.png ({report['elapsed_s']:.0f} s)")
    return report


class SoftwareRenderer(RuntimeError):
    """OpenGL is a software renderer; the message says how to go on anyway."""

    def __init__(self, renderer: str) -> None:
        super().__init__(f"OpenGL renderer is {renderer!r}, a software renderer, not a GPU: "
                         "these numbers would not be GPU numbers; pass --allow-software to run anyway")


def _scenes(sizes: Sizes, notes: list) -> dict:
    scenes = {"ct": ct_volume(sizes.ct_shape)}
    head = head_scene(sizes.head_stride)
    if head is None:
        notes.append("head CT not installed (mipcast.data_fixtures.head_ct_path() is None): scene skipped")
    else:
        scenes["head"] = head
    return scenes


def _first_frame_goal(rows: Sequence[dict]) -> dict:
    by_method = {row["method"]: row["first_s"] for row in rows}
    ratio = by_method["analytic"] / by_method["stock"]
    return {"analytic_over_stock": ratio, "goal": FIRST_FRAME_GOAL, "met": bool(ratio <= FIRST_FRAME_GOAL)}


def _peer_rows(scenes: dict, sizes: Sizes, notes: list, log) -> list:
    from mipcast.bench.peers import measure_peers, vispy_available

    if not vispy_available():
        notes.append("vispy (or PyOpenGL) not importable: no peer rows (pip install mipcast[bench])")
        return []
    rows = []
    for name, image in scenes.items():
        for edge in sizes.images:
            log(f"peers: {name} {edge}²")
            rows += measure_peers(image, name, edge, window=CLINICAL_WINDOW, rounds=sizes.rounds,
                                  frames=sizes.frames)
    return rows


def write_report(report: dict, out: Path) -> None:
    """Write ``gpu-report.json`` (strict JSON), ``gpu-report.md`` and ``gpu-report.png`` into ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "gpu-report.json").write_text(strict_json(report) + "\n")
    (out / "gpu-report.md").write_text(report_markdown(report) + "\n")
    write_chart(report, out / "gpu-report.png")


def report_markdown(report: dict) -> str:
    """The report as Markdown: renderer first, then one section per measurement.

    Examples
    --------
    >>> text = report_markdown({"renderer": {"renderer": "X", "vendor": "V", "version": "4.5", "window": "W"},
    ...                         "software": False, "quick": True, "notes": []})
    >>> text.splitlines()[0], text.splitlines()[2]
    ('# mipcast GPU report', 'OpenGL renderer: **X** (V, OpenGL 4.5, W)')
    """
    from mipcast.bench.benchmark import markdown_table

    info = report["renderer"]
    lines = ["# mipcast GPU report", "",
             f"OpenGL renderer: **{info['renderer']}** ({info['vendor']}, OpenGL {info['version']}, {info['window']})",
             ""]
    if report.get("software"):
        lines += ["**Software renderer (run with --allow-software): these are not GPU numbers.**", ""]
    if report.get("quick"):
        lines += ["Quick mode: tiny sizes, for checking the code paths only.", ""]
    if not report.get("complete", True):
        lines += [f"**Incomplete: the run stopped after {', '.join(report.get('sections_done', [])) or 'nothing'}.**",
                  ""]
    if "gl_limits" in report:
        free = report["gl_limits"]["free_mib"]
        lines.append(f"3D texture limit {report['gl_limits']['max_texture_size_3d']} points per axis; free GPU "
                     f"memory as OpenGL reports it: {'unknown' if free is None else f'{free:.0f} MiB'}.")
        lines.append("")
    lines += [f"- {note}" for note in report.get("notes", [])]
    if "parity" in report:
        lines += ["", "## Parity and accuracy (small sizes)", ""]
        for check, views in report["parity"].items():
            for view, figures in views.items():
                shown = ", ".join(f"{k} {_cell(v)}" for k, v in figures.items() if k != "passed")
                lines.append(f"- {check}, {view}: {'passed' if figures['passed'] else 'FAILED'} ({shown})")
    if report.get("speed_accuracy"):
        lines += ["", "## Speed x accuracy", "",
                  "Error against the float64 exact reference on a fixed random subset of the hit rays; "
                  "stock's from mip's readout (identical samples).", "",
                  markdown_table(report["speed_accuracy"], ["scene", "window", "size", "method", "median_ms",
                                                            "ratio_to_stock", "p99_pct", "max_pct",
                                                            "within_1_grey", "rays", "misses"])]
    if report.get("skipping"):
        lines += ["", "## Block skipping (clinical window, largest size)", "",
                  "Skipping on against every sample (analytic: every cell), same process, interleaved; "
                  "identical: the two 8-bit pictures, pixel for pixel.", "",
                  markdown_table(report["skipping"], ["scene", "size", "method", "skipping_ms", "every_ms",
                                                      "every_over_skipping", "skips_blocks", "identical"])]
    if report.get("foveation"):
        from mipcast.bench.foveation_bench import foveation_table

        lines += ["", "## Foveation (volume filling the view, default settings)", "",
                  foveation_table(report["foveation"])]
    if report.get("foveation_phantoms"):
        from mipcast.bench.foveation_bench import foveation_table

        lines += ["", "## Foveation on issue 17's scenes (vessel fixture, windowed head CT; volume filling the view)",
                  "", "Issue 17's goal: >= 6x at the centre with content-adaptive density, the default radius, "
                  "no larger mean error outside the fovea than acuity only.", "",
                  foveation_table(report["foveation_phantoms"])]
    if report.get("frame_overhead"):
        from mipcast.bench.frame_overhead import overhead_table

        lines += ["", "## Frame overhead (vessel fixture, volume filling the view)", "",
                  "Wall / CPU ms a frame (medians): still, the gaze moving every frame, the camera turning 0.5 "
                  "degrees a frame. CPU close to wall: the frame is CPU-bound (on llvmpipe the CPU time counts "
                  "the rasteriser's threads too).", "", overhead_table(report["frame_overhead"])]
    if report.get("first_frame"):
        goal = report["first_frame_goal"]
        rows = [{**row, "texture_mib": row["texture_bytes"]["total"] / 2 ** 20} for row in report["first_frame"]]
        lines += ["", "## First frame and memory (synthetic CT)", "",
                  f"Analytic's first frame is {goal['analytic_over_stock']:.2f}x stock's "
                  f"(goal <= {goal['goal']}: {'met' if goal['met'] else 'NOT met'}).", "",
                  "next_s: the steady frame (median of the last 3 of the frames drawn for a while after "
                  "the first); slowest_next_s: the slowest of them (analytic: the frame that uploads the "
                  "packed corners made in the background after the first frame); memory_mib: the "
                  "driver's used memory after them minus before (nvidia-smi; empty where no driver "
                  "reports it); gl_free_mib: free memory as OpenGL reports it then (what mipcast's "
                  "texture budget asks; empty where the driver cannot say); texture_mib: computed volume "
                  "textures (analytic: once packed).", "",
                  markdown_table(rows, ["method", "first_s", "next_s", "slowest_next_s", "memory_mib",
                                         "gl_free_mib", "texture_mib"])]
    if report.get("peers"):
        from mipcast.bench.peers import peers_table

        lines += ["", "## Peers (vispy) on equal views", "", peers_table(report["peers"])]
    if "elapsed_s" in report:
        lines += ["", f"Run time: {report['elapsed_s']:.0f} s."]
    return "\n".join(lines)


def _cell(value) -> str:
    return f"{value:.4g}" if isinstance(value, float) else str(value)


def write_chart(report: dict, path: Path) -> None:
    """PNG: error against time ratio per scene and size; first-frame seconds and texture MiB per method.

    Examples
    --------
    >>> import tempfile
    >>> path = Path(tempfile.mkdtemp()) / "r.png"
    >>> write_chart({"speed_accuracy": [], "first_frame": []}, path); path.stat().st_size > 0
    True
    """
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib import pyplot

    rows = report.get("speed_accuracy", [])
    panels = sorted({(r["scene"], str(r["window"]), r["size"]) for r in rows})
    columns = 4
    lines = -(-(len(panels) + 2) // columns)
    figure, grid = pyplot.subplots(lines, columns, figsize=(4.2 * columns, 3.8 * lines), squeeze=False)
    axes = list(grid.flat)
    colours = {method: f"C{i}" for i, method in enumerate(METHODS)}
    for axis, panel in zip(axes, panels):
        for row in rows:
            if (row["scene"], str(row["window"]), row["size"]) == panel:
                error = row["p99_pct"] if row["p99_pct"] is not None and np.isfinite(row["p99_pct"]) else 0.0
                point = (row["ratio_to_stock"], max(error, 1e-4))
                axis.scatter(*point, color=colours.get(row["method"], "k"))
                axis.annotate(row["method"], point, fontsize=7, xytext=(4, 2), textcoords="offset points")
        axis.set_yscale("log")
        axis.set_title(f"{panel[0]}, window {panel[1]}, {panel[2]}²", fontsize=8)
        axis.set_xlabel("frame time / stock", fontsize=8)
        axis.set_ylabel("p99 error, % of data range (0 at 1e-4)", fontsize=8)
    first = report.get("first_frame", [])
    names = [row["method"] for row in first]
    bars = axes[len(panels)], axes[len(panels) + 1]
    bars[0].bar(names, [row["first_s"] for row in first], color=[colours.get(n, "k") for n in names])
    bars[0].set_title("first frame (s), synthetic CT", fontsize=8)
    bars[1].bar(names, [row["texture_bytes"]["total"] / 2 ** 20 for row in first],
                color=[colours.get(n, "k") for n in names])
    bars[1].set_title("volume textures (MiB, computed)", fontsize=8)
    for axis in bars:
        axis.tick_params(axis="x", labelsize=7, rotation=30)
    for axis in axes[len(panels) + 2:]:
        axis.axis("off")
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    pyplot.close(figure)


def run_cli(args) -> int:
    """``mipcast bench --gpu-report`` / ``--peers``: run, print the renderer and progress, return the exit code.

    ``args`` has ``gpu_report``, ``peers``, ``quick``, ``allow_software``,
    ``out`` and, for ``--peers``, ``scenes``, ``size``, ``views``,
    ``rounds``, ``volume_size``.  A refused software renderer returns 2
    with a message naming ``--allow-software`` on stderr.
    """
    import sys

    if args.peers and not args.gpu_report:
        from mipcast.bench.peers import run_peers

        return run_peers(args, log=print)
    try:
        run_report(Path(args.out), quick=args.quick, allow_software=args.allow_software,
                   log=lambda line: print(line, flush=True))
    except SoftwareRenderer as error:
        print(f"mipcast bench --gpu-report: error: {error}", file=sys.stderr)
        return 2
    return 0
