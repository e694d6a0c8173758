"""Peers side by side: vispy's volume visual against stock VTK MIP and mipcast (``mipcast bench --peers``).

vispy (an optional dependency: ``pip install mipcast[bench]``) renders
headless through its EGL backend.  Its views are *equalised* with VTK's:
the volume visual's transform is VTK's own composite projection (volume
index -> world -> NDC -> pixels), so the same pixel centres cast the same
rays; six clipping planes at the point bounds keep vispy's half-voxel
larger box (it spans ``[-0.5, n - 0.5]``) from colouring pixels VTK does not
hit.  Its ``relative_step_size`` is matched to VTK's sample distance so
both take the same number of samples per ray (counted on the CPU from the
same geometry: :func:`vtk_samples`, :func:`vispy_samples`).

Every row is timed in the same process, in interleaved rounds (medians
after warm-up), as a ratio to stock VTK; errors are against the float64
exact reference (:func:`mipcast.reference.render`, ``method="analytic"``) on
the same rays, read from each row's 8-bit picture through the grey window
(so every row carries the 8-bit floor of half a grey level), and for
mipcast's rows also from their float readout.  Only MIP rows have an error
(``attenuated_mip``, ``minip`` and ``average`` are other projections).

Examples
--------
>>> from mipcast.bench.peers import VISPY_METHODS
>>> VISPY_METHODS
('mip', 'attenuated_mip', 'minip', 'average')
"""
from __future__ import annotations

import os
import statistics
import time
from typing import Callable, Optional, Sequence

import numpy as np

from mipcast.bench.benchmark import interleaved_frame_times
from mipcast.core.camera_rays import box_interval, index_space, matrix_array, pixel_centres, unproject
from mipcast.core.ray_cost import grid_cost
from mipcast.offscreen import OffscreenView

#: vispy volume methods compared (rows ``vispy <method>``).
VISPY_METHODS = ("mip", "attenuated_mip", "minip", "average")
#: mipcast rows (VTK's mappers), the first is the baseline of the ratios.
VTK_ROWS = ("stock", "mip", "analytic")
#: Background of every peer picture: no grey pixel is pure blue, so a pixel
#: is hit when it is not this colour.
BACKGROUND = (0, 0, 255)
#: Extra texture fetches of vispy's MIP per ray after its loop (a 10-step
#: refinement around the maximum plus a re-read of its colour).
VISPY_MIP_REFINE = 11
#: The row of vispy's MIP on its own box (no clipping planes): not the same
#: pixels as VTK's, but no plane tests in its loop.
UNCLIPPED = "vispy mip, unclipped"


def vispy_available() -> bool:
    """Whether vispy and PyOpenGL can be imported (no context is created).

    Examples
    --------
    >>> isinstance(vispy_available(), bool)
    True
    """
    try:
        import OpenGL  # noqa: F401
        import vispy  # noqa: F401
    except ImportError:
        return False
    return True


def _use_egl() -> None:
    os.environ.setdefault("EGL_PLATFORM", "surfaceless")
    import vispy

    try:
        vispy.use(app="egl")
    except RuntimeError:  # an app is already chosen in this process: keep it
        pass


def index_to_pixels(image, camera, size: Sequence[int]) -> np.ndarray:
    """4x4 matrix (column vectors): volume index coordinates -> window pixels (y down), NDC z kept.

    vispy's "document" coordinates are logical pixels with y down; keeping
    NDC z and w lets its volume shader find the near and far planes as VTK has them.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> from mipcast.data_fixtures import make_fixture
    >>> camera = vtkCamera(); camera.SetPosition(7.5, 7.5, 50); camera.SetFocalPoint(7.5, 7.5, 7.5)
    >>> camera.ParallelProjectionOn(); camera.SetParallelScale(8.0)
    >>> m = index_to_pixels(make_fixture("spheres", size=16), camera, (32, 32))
    >>> (m @ [7.5, 7.5, 7.5, 1.0])[:2].round(6).tolist()
    [16.0, 16.0]
    """
    width, height = (int(v) for v in size)
    world_to_ndc = matrix_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
    to_index, _ = index_space(image)
    ndc_to_pixels = np.array([[width / 2.0, 0, 0, width / 2.0], [0, -height / 2.0, 0, height / 2.0],
                              [0, 0, 1, 0], [0, 0, 0, 1]])
    return ndc_to_pixels @ world_to_ndc @ np.linalg.inv(to_index)


def _index_rays(image, camera, size: Sequence[int]):
    """Near/far points of every pixel's ray in index space, (2, H*W, 3), rows top first."""
    width, height = (int(v) for v in size)
    world_to_ndc = matrix_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
    to_index, upper = index_space(image)
    x, y = pixel_centres(width, height)
    xs, ys = np.meshgrid(x, y)
    points = unproject(np.linalg.inv(world_to_ndc), xs.ravel(), ys.ravel())
    return points @ to_index[:3, :3].T + to_index[:3, 3], upper


def vispy_samples(image, camera, size: Sequence[int], relative_step: float, method: str = "mip",
                  clip: bool = True) -> dict:
    """Loop steps and texture fetches vispy's ray loop takes, counted from the geometry.

    vispy walks its box ``[-0.5, n - 0.5]`` (index units) from the front face
    (or the near plane) to the back face in ``int(L / relative_step + 0.5)``
    steps; steps outside the clipping planes at the point bounds skip the
    fetch.  Its MIP adds :data:`VISPY_MIP_REFINE` fetches per ray.
    Without ``clip``, every ray meeting vispy's box counts and every step fetches.

    Returns
    -------
    dict
        ``rays`` (pixels whose ray meets the point bounds), ``steps`` and
        ``fetches`` (totals over those rays).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = OffscreenView(make_fixture("spheres", size=16), "stock", size=(8, 8), view="front")
    >>> counts = vispy_samples(view.image, view.camera, (8, 8), 1.0, method="average")
    >>> counts["rays"], counts["steps"] // counts["rays"], counts["fetches"] // counts["rays"]
    (16, 16, 15)
    """
    (near, far), upper = _index_rays(image, camera, size)
    delta = far - near
    length = np.linalg.norm(delta, axis=1)
    outer = _clipped(box_interval(near + 0.5, delta, upper + 1.0))
    inner = _clipped(box_interval(near, delta, upper))
    hit = inner[0] <= inner[1] if clip else outer[0] <= outer[1]
    steps = np.floor((outer[1] - outer[0]) * length / relative_step + 0.5)[hit]
    inside = np.clip((inner[1] - inner[0]) / np.maximum(outer[1] - outer[0], 1e-30), 0.0, 1.0)[hit]
    if not clip:
        inside = np.ones_like(steps)
    fetches = np.round(steps * inside) + (VISPY_MIP_REFINE if method == "mip" else 0)
    return {"rays": int(hit.sum()), "steps": int(steps.sum()), "fetches": int(fetches.sum())}


def _clipped(interval):
    t_near, t_far = interval
    return np.maximum(t_near, 0.0), np.minimum(t_far, 1.0)


def vtk_samples(view: OffscreenView) -> dict:
    """Rays cast and samples taken by a sampled VTK loop (:func:`mipcast.core.ray_cost.grid_cost`).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> counts = vtk_samples(OffscreenView(make_fixture("spheres", size=16), "stock", size=(8, 8), view="front"))
    >>> counts["rays"], counts["samples"] // counts["rays"]
    (16, 15)
    """
    size = view.render_window.GetSize()
    rays, samples = grid_cost(view.image, view.camera, size, size, sample_distance=view.sample_distance)
    return {"rays": rays, "samples": samples}


def matched_step(image, camera, size: Sequence[int], sample_distance: float) -> float:
    """vispy's ``relative_step_size`` taking as many samples per ray as VTK at ``sample_distance``.

    The ratio of the rays' total length inside the point bounds, in index
    units, to VTK's total sample count (one voxel per sample at unit
    spacing and one sample per voxel).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = OffscreenView(make_fixture("spheres", size=16), "stock", size=(8, 8), view="front")
    >>> matched_step(view.image, view.camera, (8, 8), 1.0)
    1.0
    """
    (near, far), upper = _index_rays(image, camera, size)
    delta = far - near
    t_near, t_far = _clipped(box_interval(near, delta, upper))
    hit = t_near <= t_far
    total = float(((t_far - t_near) * np.linalg.norm(delta, axis=1))[hit].sum())
    _, samples = grid_cost(image, camera, size, size, sample_distance=sample_distance)
    return total / samples if samples else 1.0


class VispyView:
    """vispy's volume visual rendering ``image`` through the pixels of a VTK camera.

    Parameters
    ----------
    image : vtkImageData
        The volume (one-component point scalars, any numeric type).
    camera : vtkCamera
        The view to copy (read once, at construction).
    size : tuple of int
        Window (width, height).
    method : str, default: "mip"
        One of :data:`VISPY_METHODS`.
    window : tuple of float
        Grey window (vispy's ``clim``).
    relative_step : float, default: 1.0
        vispy's ``relative_step_size`` (index units per step).
    clip : bool, default: True
        Clip to the point bounds (six clipping planes), so the same pixels
        as VTK's are hit; without, vispy's box is half a voxel larger on
        every side, and its loop skips six plane tests per step.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=16)
    >>> vtk_view = OffscreenView(image, "stock", size=(32, 32))
    >>> VispyView(image, vtk_view.camera, (32, 32), window=(0.0, 1.0)).screenshot().shape  # doctest: +SKIP
    (32, 32, 3)
    """

    def __init__(self, image, camera, size: Sequence[int], method: str = "mip", window=(0.0, 1.0),
                 relative_step: float = 1.0, clip: bool = True) -> None:
        if method not in VISPY_METHODS:
            raise ValueError(f"unknown vispy method {method!r}; valid: {', '.join(VISPY_METHODS)}")
        _use_egl()
        from vispy import scene
        from vispy.visuals.transforms import MatrixTransform
        from vtkmodules.util.numpy_support import vtk_to_numpy

        self.size = (int(size[0]), int(size[1]))
        self.method = method
        self.relative_step = float(relative_step)
        nx, ny, nz = image.GetDimensions()
        values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(nz, ny, nx)
        self.canvas = scene.SceneCanvas(size=self.size, show=False,
                                        bgcolor=tuple(c / 255.0 for c in BACKGROUND))
        self.volume = scene.visuals.Volume(
            values.astype(np.float32), parent=self.canvas.scene, method=method, clim=tuple(window),
            cmap="grays", interpolation="linear", relative_step_size=self.relative_step,
            clipping_planes=_bound_planes((nx, ny, nz)) if clip else None, clipping_planes_coord_system="visual")
        self.volume.transform = MatrixTransform(index_to_pixels(image, camera, self.size).T)
        self._fbo = None

    def draw(self) -> None:
        """Draw one frame into an offscreen framebuffer and wait for the GPU (``glFinish``).

        As :meth:`screenshot` without the read-back, as VTK's frames are
        timed (render, then ``WaitForCompletion``).
        """
        from vispy import gloo
        from vispy.gloo import gl

        canvas = self.canvas
        canvas.set_current()
        if self._fbo is None:
            shape = self.size[::-1]
            self._fbo = gloo.FrameBuffer(color=gloo.RenderBuffer(shape), depth=gloo.RenderBuffer(shape))
        canvas.push_fbo(self._fbo, (0, 0), self.size)
        try:
            canvas.context.clear(color=canvas.bgcolor, depth=True)
            canvas.draw_visual(canvas.scene)
            canvas.context.flush_commands()
            gl.glFinish()
        finally:
            canvas.pop_fbo()

    def screenshot(self) -> np.ndarray:
        """Render and return the 8-bit RGB image, (height, width, 3), top row first."""
        return np.asarray(self.canvas.render(alpha=False))[..., :3].copy()

    def frame_times(self, frames: int = 10, warmup: int = 3) -> list:
        """Seconds of ``frames`` draws after ``warmup`` untimed ones, as :meth:`OffscreenView.frame_times`."""
        for _ in range(warmup):
            self.draw()
        times = []
        for _ in range(frames):
            start = time.perf_counter()
            self.draw()
            times.append(time.perf_counter() - start)
        return times

    def renderer(self) -> str:
        """The GL_RENDERER string of vispy's context."""
        from vispy.gloo import gl

        self.canvas.set_current()
        return str(gl.glGetParameter(gl.GL_RENDERER))

    def close(self) -> None:
        """Release the canvas and its context."""
        self.canvas.close()


def _bound_planes(dimensions: Sequence[int]) -> np.ndarray:
    """Six clipping planes (position, inward normal), vispy's xyz order, at the point bounds.

    vispy evaluates them at ``loc * shape`` (texture coordinate times
    shape), i.e. at index + 0.5: the bounds ``[0, n - 1]`` sit at 0.5 and n - 0.5.
    """
    planes = []
    for axis, n in enumerate(dimensions):
        normal = np.zeros(3)
        normal[axis] = 1.0
        low, high = np.zeros(3), np.zeros(3)
        low[axis], high[axis] = 0.5, n - 0.5
        planes += [(low, normal), (high, -normal)]
    return np.array(planes, dtype=np.float64)


def hit_mask(picture: np.ndarray) -> np.ndarray:
    """Pixels not of the :data:`BACKGROUND` colour.

    Examples
    --------
    >>> picture = np.zeros((1, 2, 3), np.uint8); picture[0, 1] = BACKGROUND
    >>> hit_mask(picture).tolist()
    [[True, False]]
    """
    return np.any(picture[..., :3] != np.array(BACKGROUND, np.uint8), axis=-1)


def grey_errors(picture: np.ndarray, exact: np.ndarray, window: Sequence[float]) -> dict:
    """Error of an 8-bit grey picture against the exact maxima, in grey levels of ``window``.

    Compared on the pixels both hit; ``exact`` is clipped to the window
    before it is scaled, as the transfer function clips.

    Examples
    --------
    >>> exact = np.array([[0.0, 0.5, np.nan]])
    >>> picture = np.array([[[0, 0, 0], [128, 128, 128], [0, 0, 255]]], np.uint8)
    >>> grey_errors(picture, exact, (0.0, 1.0))["within_1_grey"]
    1.0
    """
    low, high = float(window[0]), float(window[1])
    hit = hit_mask(picture) & ~np.isnan(exact)
    ideal = 255.0 * (np.clip(exact[hit], low, high) - low) / (high - low)
    error = np.abs(picture[..., 0][hit].astype(np.float64) - ideal)
    if error.size == 0:
        return {"within_1_grey": float("nan"), "p99_grey": float("nan"), "max_grey": float("nan")}
    return {"within_1_grey": float(np.mean(error <= 1.0)), "p99_grey": float(np.percentile(error, 99)),
            "max_grey": float(error.max())}


def measure_peers(image, scene: str, edge: int, view: str = "oblique", window=None, rounds: int = 3,
                  frames: int = 2, warmup: int = 2, vispy_methods: Sequence[str] = VISPY_METHODS,
                  progress: Optional[Callable[[str], None]] = None) -> list:
    """Rows of stock VTK, mipcast's mip and analytic and vispy's methods, on equal views.

    Parameters
    ----------
    image : vtkImageData
        The scene's volume.
    scene : str
        Its name in the rows.
    edge : int
        Square window edge, pixels.
    view : str, default: "oblique"
        A preset of :data:`mipcast.offscreen.VIEWS` (VTK's camera; vispy copies it).
    window : tuple of float, optional
        Grey window (default: the data range).
    rounds, frames, warmup : int
        Interleaved timing, as :func:`mipcast.bench.benchmark.interleaved_frame_times`.
    vispy_methods : sequence of str
        Subset of :data:`VISPY_METHODS`; empty (or vispy missing) gives the VTK rows only.
    progress : callable, optional
        Called with a short label after each step.

    Returns
    -------
    list of dict
        One row per renderer: ``row``, ``median_ms``, ``ratio_to_stock``,
        ``pixels_hit``, ``pixels_hit_vs_stock``, ``rays`` (pixels whose ray
        meets the point bounds, from the geometry), ``samples_per_ray``,
        ``steps_per_ray`` (vispy: loop steps, including those clipped),
        ``within_1_grey``, ``p99_grey`` (8-bit picture vs exact), and
        ``p99_pct``, ``float_within_1_grey`` for rows with a float readout.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = measure_peers(make_fixture("spheres", size=16), "spheres", 24, rounds=1, frames=1, warmup=1,
    ...                      vispy_methods=())
    >>> [row["row"] for row in rows], rows[0]["ratio_to_stock"]
    (['stock', 'mip', 'analytic'], 1.0)
    """
    from mipcast import reference
    from mipcast.core.metrics import summary

    report = progress or (lambda label: None)
    size = (edge, edge)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    window = tuple(window) if window is not None else (low, high)
    views = {name: OffscreenView(image, name, size=size, view=view, window=window) for name in VTK_ROWS}
    for scene_view in views.values():
        scene_view.renderer.SetBackground(*(c / 255.0 for c in BACKGROUND))
    camera = views["stock"].camera
    distance = views["stock"].sample_distance
    step = matched_step(image, camera, size, distance)
    methods = tuple(vispy_methods) if vispy_available() else ()
    peers = {f"vispy {m}": VispyView(image, camera, size, m, window, step) for m in methods}
    if "mip" in methods:
        peers[UNCLIPPED] = VispyView(image, camera, size, "mip", window, step, clip=False)
    times = interleaved_frame_times({**views, **peers}, rounds=rounds, frames=frames, warmup=warmup,
                                    progress=report)  # vispy views have frame_times too
    exact = reference.render(image, camera, size, method="analytic")
    report("reference")
    base = statistics.median(times["stock"])
    vtk_count = vtk_samples(views["stock"])
    pictures = {label: item.screenshot() for label, item in {**views, **peers}.items()}
    stock_hit = int(hit_mask(pictures["stock"]).sum())
    rows = []
    for label, picture in pictures.items():
        median = statistics.median(times[label])
        hit = int(hit_mask(picture).sum())
        row = {"scene": scene, "size": edge, "view": view, "window": list(window), "row": label,
               "renderer": "vispy" if label in peers else "vtk", "median_ms": 1000 * median,
               "ratio_to_stock": median / base, "frames": len(times[label]), "pixels_hit": hit,
               "pixels_hit_vs_stock": hit / stock_hit if stock_hit else float("nan")}
        if label in peers:
            count = vispy_samples(image, camera, size, step, peers[label].method, clip=label != UNCLIPPED)
            row.update(rays=count["rays"], samples_per_ray=count["fetches"] / max(count["rays"], 1),
                       steps_per_ray=count["steps"] / max(count["rays"], 1), relative_step_size=step)
        elif label == "analytic":
            row.update(rays=vtk_count["rays"], samples_per_ray=float("nan"), steps_per_ray=float("nan"))
        else:
            spr = vtk_count["samples"] / max(vtk_count["rays"], 1)
            row.update(rays=vtk_count["rays"], samples_per_ray=spr, steps_per_ray=spr,
                       sample_distance=distance)
        if label in ("stock", "mip", "analytic", "vispy mip", UNCLIPPED):
            row.update(grey_errors(picture, exact, window))
        if label in ("mip", "analytic"):
            errors = summary(views[label].float_image(), exact, high - low, window=window)
            row.update(p99_pct=errors["p99_pct"], float_within_1_grey=errors["within_1_grey"])
        rows.append(row)
        report(f"{scene} {edge}²: {label}")
    for scene_view in views.values():
        scene_view.render_window.Finalize()
    for peer in peers.values():
        peer.close()
    return rows


def peers_table(rows: Sequence[dict]) -> str:
    """Markdown table of :func:`measure_peers` rows.

    Examples
    --------
    >>> row = {"scene": "s", "size": 8, "view": "oblique", "row": "stock", "median_ms": 2.0,
    ...        "ratio_to_stock": 1.0, "pixels_hit": 40, "pixels_hit_vs_stock": 1.0, "samples_per_ray": 7.5,
    ...        "steps_per_ray": 7.5, "within_1_grey": 0.99, "p99_grey": 1.2}
    >>> print(peers_table([row]).splitlines()[-1])
    | s 8² oblique | stock | 2.00 | 1.00 | 40 (1.000) | 7.5 | 7.5 | 99.0 % | 1.2 | - |
    """
    lines = ["| scene | row | ms | × stock | pixels hit (/ stock) | samples per ray | loop steps per ray "
             "| 8-bit within 1 grey | 8-bit p99 (grey) | float p99 (% range) |",
             "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for row in rows:
        lines.append(f"| {row['scene']} {row['size']}² {row['view']} | {row['row']} | {row['median_ms']:.2f} | "
                     f"{row['ratio_to_stock']:.2f} | {row['pixels_hit']} ({row['pixels_hit_vs_stock']:.3f}) | "
                     f"{_number(row.get('samples_per_ray'))} | {_number(row.get('steps_per_ray'))} | "
                     f"{_percent(row.get('within_1_grey'))} | {_number(row.get('p99_grey'))} | "
                     f"{_number(row.get('p99_pct'), '.3g')} |")
    return "\n".join(lines)


def _number(value, spec: str = ".1f") -> str:
    return format(value, spec) if isinstance(value, (int, float)) and np.isfinite(value) else "-"


def _percent(value) -> str:
    return f"{100 * value:.1f} %" if isinstance(value, (int, float)) and np.isfinite(value) else "-"


def load_scene(scene: str, volume_size: int = 128):
    """``NAME[@LOW,HIGH]`` -> (vtkImageData, window or None); NAME a fixture, ``head``, ``ct`` or a file.

    ``ct`` is :func:`mipcast.data_fixtures.ct_phantom.ct_volume` at ``volume_size``
    points per axis (``volume_size * 25 // 32`` slices).

    Examples
    --------
    >>> image, window = load_scene("spheres@0.2,0.8", 16)
    >>> image.GetDimensions(), window
    ((16, 16, 16), (0.2, 0.8))
    """
    from mipcast.data_fixtures import FIXTURES, load_head_ct, make_fixture

    name, _, window_text = scene.partition("@")
    window = tuple(float(v) for v in window_text.split(",")) if window_text else None
    if window is not None and len(window) != 2:
        raise ValueError(f"scene window must be @LOW,HIGH, got {scene!r}")
    if name in FIXTURES:
        return make_fixture(name, size=volume_size), window
    if name == "head":
        return load_head_ct(), window
    if name == "ct":
        from mipcast.data_fixtures.ct_phantom import ct_volume

        return ct_volume((max(8, volume_size * 25 // 32), volume_size, volume_size)), window
    from pathlib import Path

    from mipcast.io import read_volume
    return read_volume(Path(name)), window


def run_peers(args, log: Callable[[str], None] = print) -> int:
    """``mipcast bench --peers``: :func:`measure_peers` per scene, view and size; peers.md and peers.json.

    ``--quick`` caps the volume at 48 points and the images at 96².
    """
    from pathlib import Path

    from mipcast.bench.report import renderer_info, strict_json

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    sizes = args.size or ([64, 96] if args.quick else [256, 512])
    volume_size = min(args.volume_size, 48) if args.quick else args.volume_size
    if args.quick:
        sizes = [min(edge, 96) for edge in sizes]
    info = renderer_info()
    log(f"OpenGL renderer: {info['renderer']} ({info['vendor']}, {info['version']})")
    if not vispy_available():
        log("vispy (or PyOpenGL) is not importable: VTK rows only (pip install mipcast[bench])")
    started = time.perf_counter()
    rows = []
    for scene in args.scenes:
        image, window = load_scene(scene, volume_size)
        for view in args.views:
            for edge in sizes:
                rows += measure_peers(image, scene, edge, view=view, window=window, rounds=args.rounds)
                log(peers_table([r for r in rows if (r["scene"], r["view"], r["size"]) == (scene, view, edge)]))
    image, _ = load_scene(args.scenes[0], volume_size)
    edges = (32, 48, 64) if args.quick else (128, 256, 384)
    costs = cost_model(image, edges=edges, view=args.views[0], rounds=args.rounds, progress=log)
    log(cost_table(costs))
    report = {"renderer": info, "rows": rows, "cost_model": costs, "elapsed_s": time.perf_counter() - started}
    (out / "peers.json").write_text(strict_json(report) + "\n")
    (out / "peers.md").write_text(f"OpenGL renderer: {info['renderer']}\n\n" + peers_table(rows) + "\n\n"
                                  f"Cost model on {args.scenes[0]} ({args.views[0]}, edges {list(edges)}, "
                                  "0.5/1/2 samples per voxel):\n\n" + cost_table(costs) + "\n")
    log(f"wrote {out}/peers.json, peers.md ({report['elapsed_s']:.0f} s)")
    return 0


#: Rows of :func:`cost_model`: what is timed.
COST_ROWS = ("empty VTK frame", "stock", "mip", "vispy mip", UNCLIPPED)


def cost_model(image, edges: Sequence[int] = (128, 256, 384), rates: Sequence[float] = (0.5, 1.0, 2.0),
               view: str = "oblique", rounds: int = 3, frames: int = 2,
               progress: Optional[Callable[[str], None]] = None) -> list:
    """Where the frame time goes: a least-squares fit ``t = fixed + per_ray * rays + per_sample * samples``.

    Every renderer is timed (interleaved, one process) at each window edge
    and sampling rate (samples per voxel), its rays and samples counted from
    the geometry (:func:`vtk_samples`, :func:`vispy_samples`: fetches).
    ``"empty VTK frame"`` is an OffscreenView with the volume hidden: VTK's
    own per-frame cost (render pass set-up, clear, blit), without any ray.

    Returns
    -------
    list of dict
        One per renderer: ``fixed_ms``, ``per_ray_ns``, ``per_sample_ns``,
        ``r2`` (of the fit), ``points`` (the measured ``edge``, ``rate``,
        ``rays``, ``samples``, ``median_ms``).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> rows = cost_model(make_fixture("spheres", size=16), edges=(16, 24), rates=(1.0, 2.0), rounds=1, frames=1)
    >>> [row["renderer"] for row in rows][:3]
    ['empty VTK frame', 'stock', 'mip']
    """
    report = progress or (lambda label: None)
    spacing = min(abs(s) for s in image.GetSpacing())
    use_vispy = vispy_available()
    points: dict = {name: [] for name in COST_ROWS if use_vispy or not name.startswith("vispy")}
    for edge in edges:
        for rate in rates:
            size = (edge, edge)
            items = {name: OffscreenView(image, "stock" if name == "empty VTK frame" else name, size=size,
                                         view=view, sample_distance=spacing / rate)
                     for name in ("empty VTK frame", "stock", "mip")}
            items["empty VTK frame"].volume.VisibilityOff()
            camera = items["stock"].camera
            count = vtk_samples(items["stock"])
            counts = {"empty VTK frame": (0, 0), "stock": (count["rays"], count["samples"]),
                      "mip": (count["rays"], count["samples"])}
            if use_vispy:
                step = matched_step(image, camera, size, spacing / rate)
                for name, clip in (("vispy mip", True), (UNCLIPPED, False)):
                    items[name] = VispyView(image, camera, size, "mip", (0.0, 1.0), step, clip=clip)
                    counted = vispy_samples(image, camera, size, step, "mip", clip=clip)
                    counts[name] = (counted["rays"], counted["fetches"])
            times = interleaved_frame_times(items, rounds=rounds, frames=frames, warmup=2)
            for name, item in items.items():
                points[name].append({"edge": edge, "rate": rate, "rays": counts[name][0],
                                     "samples": counts[name][1], "median_ms": 1000 * statistics.median(times[name])})
                if isinstance(item, VispyView):
                    item.close()
                else:
                    item.render_window.Finalize()
            report(f"cost model: {edge}², {rate:g} samples per voxel")
    return [{"renderer": name, **_fit(measured), "points": measured} for name, measured in points.items()]


def _fit(points: Sequence[dict]) -> dict:
    """Least squares of median_ms on (1, rays, samples); the empty frame on 1 alone."""
    t = np.array([p["median_ms"] for p in points])
    rays = np.array([p["rays"] for p in points], float)
    samples = np.array([p["samples"] for p in points], float)
    design = np.column_stack([np.ones_like(t), rays, samples]) if rays.any() else np.ones((len(t), 1))
    coefficients, *_ = np.linalg.lstsq(design, t, rcond=None)
    predicted = design @ coefficients
    spread = float(np.sum((t - t.mean()) ** 2))
    r2 = 1.0 - float(np.sum((t - predicted) ** 2)) / spread if spread > 0 else float("nan")
    coefficients = list(coefficients) + [0.0] * (3 - len(coefficients))
    return {"fixed_ms": float(coefficients[0]), "per_ray_ns": 1e6 * float(coefficients[1]),
            "per_sample_ns": 1e6 * float(coefficients[2]), "r2": r2}


def cost_table(rows: Sequence[dict]) -> str:
    """Markdown table of :func:`cost_model` rows.

    Examples
    --------
    >>> print(cost_table([{"renderer": "stock", "fixed_ms": 1.0, "per_ray_ns": 20.0, "per_sample_ns": 2.0,
    ...                    "r2": 0.99}]).splitlines()[-1])
    | stock | 1.00 | 20.0 | 2.00 | 0.990 |
    """
    lines = ["| renderer | fixed per frame (ms) | per ray (ns) | per sample (ns) | R² of the fit |",
             "| --- | --- | --- | --- | --- |"]
    lines += [f"| {r['renderer']} | {r['fixed_ms']:.2f} | {r['per_ray_ns']:.1f} | {r['per_sample_ns']:.2f} | "
              f"{r['r2']:.3f} |" for r in rows]
    return "\n".join(lines)
