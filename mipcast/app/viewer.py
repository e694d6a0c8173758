"""``mipcast view``: an interactive pyvista window over one volume.

Everything the viewer offers comes from the method table
(:data:`mipcast.METHODS`) and each method's parameter table.

Keys
    ``m`` next method of the table (those that render in a view), ``d``
    next depth mode (methods with a ``depth_mode`` parameter), ``w`` next
    grey window (the projection's default, a DICOM series' own windows, the
    CT presets for Hounsfield units, the data range:
    :func:`mipcast.core.windowing.window_choices`), ``[`` / ``]``
    move the slab towards / away from the camera by a quarter of its
    thickness (at least a voxel; methods with a slab, once the slab
    thickness slider is above 0), pyvista's own keys (``q`` quits, ``r``
    resets the camera, ...).
Sliders
    sample distance in voxels (methods that sample; those that walk cells
    do not), and one per float parameter with a range (:func:`slider_range`;
    the slab thickness runs from 0, no slab, to the volume's diagonal);
    values carry over when the method changes.
Mouse
    the pointer position, in normalised viewport coordinates (0..1 from the
    lower left corner), goes to ``SetGazePoint(x, y)`` on every move when the
    method has a ``gaze_point`` parameter (foveated rendering).
Legend
    methods with a ``sphere_colors`` parameter get the colour sphere in the
    lower right corner, turning with the camera like the volume: a shaded
    sphere whose colour along each world direction is the one the method
    gives a hit in that direction from the volume's centre
    (:func:`mipcast.core.shading.sphere_color`, as DEMIP's shader does).

pyvista is imported inside the functions only, so the core package keeps
working in ParaView's Python.
"""
from __future__ import annotations

import importlib
import os
import sys
from typing import Optional, Sequence

import numpy as np

from mipcast.core.parameters import Parameter, set_parameters, setter_name
from mipcast.core.shading import sphere_color
from mipcast.core.validation import check_choice
from mipcast.core.windowing import resolve_window
from mipcast.methods import METHODS
from mipcast.offscreen import set_view

#: Normalised (x0, y0, x1, y1) of the colour-sphere legend in the window.
LEGEND_VIEWPORT = (0.78, 0.0, 1.0, 0.22)
#: Slider range of the sample distance, in voxels (the smallest spacing).
SAMPLE_DISTANCE_RANGE = (0.125, 2.0)
#: Upper end of the slider of a parameter that has no upper bound, in its unit.
UNBOUNDED_SLIDER_TOP = 1.0


def slider_range(parameter: Parameter):
    """The slider range of a float parameter, or None if it gets no slider.

    ``[low, high]`` (``high`` = :data:`UNBOUNDED_SLIDER_TOP` when unbounded;
    an open lower end starts at 1 % of the range).

    Examples
    --------
    >>> from mipcast.core.parameter_tables import DEMIP
    >>> [(p.name, slider_range(p)) for p in DEMIP[:3]]
    [('depth_weight', (0.0, 1.0)), ('material_threshold', (0.01, 1.0)), ('depth_mode', None)]
    """
    if parameter.kind != "float" or parameter.low is None:
        return None
    high = UNBOUNDED_SLIDER_TOP if parameter.high is None else parameter.high
    low = parameter.low + 0.01 * (high - parameter.low) if parameter.open_low else parameter.low
    return (low, high)


def view_methods() -> tuple:
    """Names of the table's methods that render in a view, in table order (the ``m`` cycle)."""
    return tuple(name for name, method in METHODS.items() if method.in_view)


def has_display(environ=None, platform: Optional[str] = None) -> bool:
    """Whether an on-screen window can open: macOS, Windows, or ``DISPLAY`` set.

    Parameters
    ----------
    environ : mapping, optional
        Environment variables; default ``os.environ``.
    platform : str, optional
        ``sys.platform`` value; default the running one.

    Returns
    -------
    bool

    Examples
    --------
    >>> has_display({}, "linux"), has_display({"DISPLAY": ":0"}, "linux"), has_display({}, "darwin")
    (False, True, True)
    """
    environ = os.environ if environ is None else environ
    platform = sys.platform if platform is None else platform
    return platform == "darwin" or platform.startswith("win") or bool(environ.get("DISPLAY"))


def build_viewer(image, method: str = "mip", *, cmap="gray", clim: Optional[Sequence[float]] = None,
                 window_size: Sequence[int] = (900, 800), off_screen: bool = False,
                 params: Optional[dict] = None, view: Optional[str] = None, component=None,
                 stereo: Optional[str] = None):
    """Build the interactive viewer's plotter without showing it.

    The volume is added through ``plotter.mip.add_volume`` on a black
    background, with the keys, sliders, gaze observer and colour-sphere
    legend described in :mod:`mipcast.app.viewer` (they are attached to the
    plotter's interactor, which pyvista also gives off-screen plotters, so
    an off-screen viewer can be driven by simulated events).

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        The volume (one-component point scalars).
    method : str, default: "mip"
        The first method, a name from ``mipcast.METHODS``.
    cmap : str or matplotlib colormap, default: "gray"
        Colour map, as in ``Plotter.add_volume``.
    clim : sequence of float or str, optional
        Colour limits (low, high); default the window a viewer would pick
        (:func:`mipcast.core.windowing.default_window`); ``"full"`` the data range.
    window_size : sequence of int, default: (900, 800)
        Window (width, height) in pixels.
    off_screen : bool, default: False
        Render offscreen (no interaction).
    params : dict, optional
        Method parameters to start with (``{"depth_weight": 0.5}``, see
        :func:`mipcast.core.parameters.set_parameters`); carried over to other
        methods that have them.
    view : str, optional
        The first camera: a preset of ``mipcast.offscreen.VIEWS`` or a patient
        view (``"anterior"``, ...); default pyvista's.
    component : int or "magnitude", optional
        Which component of multi-component scalars to draw (default: the magnitude).
    stereo : str, optional
        A stereo pair: ``"anaglyph"`` (red-cyan) or ``"side-by-side"``
        (:data:`mipcast.mappers.stereo.STEREO_MODES`); default mono.

    Returns
    -------
    pyvista.Plotter
        Show it with ``plotter.show()`` (or use :func:`run_viewer`).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> plotter = build_viewer(make_fixture("vessels", size=24), "analytic",
    ...                        window_size=(64, 64), off_screen=True)
    >>> type(plotter.mip.volumes[0].GetMapper()).__name__
    'AnalyticMIPVolumeMapper'
    >>> plotter.screenshot().shape
    (64, 64, 3)
    >>> plotter.close()
    """
    return _Viewer(image, method, cmap=cmap, clim=clim, window_size=window_size,
                   off_screen=off_screen, params=params, view=view, component=component,
                   stereo=stereo).plotter


def run_viewer(image, method: str = "mip", **options) -> None:
    """Open the viewer window and block until it is closed.

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        The volume (one-component point scalars).
    method : str, default: "mip"
        The first method, a name from ``mipcast.METHODS``.
    **options
        Keyword arguments of :func:`build_viewer` (``cmap``, ``clim``,
        ``window_size``, ``params``, ``view``, ``stereo``).

    Raises
    ------
    RuntimeError
        If there is no display (see :func:`has_display`).

    Examples
    --------
    Opens a window and waits for it to close, so it is not run as a test
    (``tests/test_viewer.py`` runs it under ``xvfb-run`` instead):

    >>> from mipcast.data_fixtures import make_fixture
    >>> run_viewer(make_fixture("vessels", size=64), "analytic")  # doctest: +SKIP
    """
    if not has_display():
        raise RuntimeError("no display: the viewer needs a window; render to a file with "
                           "`mipcast render INPUT --out x.png` instead")
    viewer = _Viewer(image, method, off_screen=False, **options)
    viewer.plotter.show(title=f"mipcast view ({method})", before_close_callback=viewer.close)


class _Viewer:
    """The viewer's state: plotter, current method and volume, widgets, parameter values."""

    def __init__(self, image, method, *, cmap="gray", clim=None, window_size=(900, 800),
                 off_screen=False, params=None, view=None, component=None, stereo=None) -> None:
        import pyvista

        from mipcast.mappers.input_preparer import window_image
        from mipcast.mappers.stereo import set_stereo

        importlib.import_module("mipcast.filters")  # registers plotter.mip

        self.params = _checked_params(method, dict(params or {}))  # name -> value, carried across methods
        self.grid = pyvista.wrap(image)
        self.cmap = cmap
        self.component = component  # of multi-component scalars (default: the magnitude)
        projection = METHODS[method].projection if method in METHODS else "mip"  # MinIP/average: their own
        self.clim = resolve_window(window_image(self.grid, component), clim, projection)
        self.window_label = "given" if clim is not None else "auto"  # the status line's name of the window
        self.voxel = min(abs(s) for s in self.grid.GetSpacing())
        self.sample_voxels = 1.0
        self.volume = None
        self.legend = None
        self.plotter = pyvista.Plotter(off_screen=off_screen, window_size=list(window_size))
        self.plotter.set_background("black")
        if stereo is not None:
            set_stereo(self.plotter.render_window, stereo)
        self.interactive = self.plotter.iren is not None
        if self.interactive:
            self.plotter.add_key_event("m", self.next_method)
            self.plotter.add_key_event("d", self.next_depth_mode)
            self.plotter.add_key_event("w", self.next_window)
            self.plotter.add_key_event("bracketleft", lambda: self.move_slab(-1))
            self.plotter.add_key_event("bracketright", lambda: self.move_slab(1))
            self.plotter.iren.add_observer("MouseMoveEvent", self._on_mouse_move)
            from mipcast.mappers.refinement import drive_refinement  # progressive refinement: a timer

            self.refinement = drive_refinement(self.plotter.iren.interactor, lambda: [self.mapper])
        self.set_method(method)
        if view is not None:
            set_view(self.plotter.renderer, self.grid, view)
            self.plotter.camera_set = True  # else pyvista puts its own camera back on the first render
            self.plotter.render()

    @property
    def mapper(self):
        return self.volume.GetMapper()

    # -- actions --------------------------------------------------------------
    def set_method(self, method: str) -> None:
        method = check_choice("method", method, view_methods())
        camera = self.plotter.camera_position if self.volume is not None else None
        if self.volume is not None:
            self.plotter.mip.remove_volume(self.volume)
        sample_distance = self.sample_voxels * self.voxel if _uses_sample_distance(method) else None
        self.volume = self.plotter.mip.add_volume(self.grid, method, cmap=self.cmap, clim=self.clim,
                                                  sample_distance=sample_distance, render=False,
                                                  component=self.component)
        self.method = method
        for name, value in self.params.items():  # carry over what the new method accepts
            if self._has(name):
                try:
                    set_parameters(self.mapper, **{name: value})
                except (TypeError, ValueError):
                    pass  # e.g. a depth mode this method does not have: keep its default
        if camera is not None:
            self.plotter.camera_position = camera
        if self.interactive:
            self._build_sliders()
            self._build_legend()
        self._show_status()
        self.plotter.render()

    def next_method(self) -> None:
        names = list(view_methods())
        following = names[(names.index(self.method) + 1) % len(names)] if self.method in names else names[0]
        self.set_method(following)

    def next_window(self) -> None:
        """The grey window after the current one in :func:`~mipcast.core.windowing.window_choices` (for the
        current method's projection; the method, camera and parameters stay)."""
        from mipcast.core.windowing import window_choices
        from mipcast.mappers.input_preparer import window_image

        projection = METHODS[self.method].projection if self.method in METHODS else "mip"
        choices = window_choices(window_image(self.grid, self.component), projection)
        words = [word for word, _ in choices]
        index = words.index(self.window_label) + 1 if self.window_label in words else 0
        self.window_label, self.clim = choices[index % len(choices)]
        self.set_method(self.method)

    def next_depth_mode(self) -> None:
        modes = _depth_modes(self.mapper)
        if not modes:
            self._show_status(note="this method has no depth modes")
            self.plotter.render()
            return
        current = self.mapper.GetDepthMode()
        index = modes.index(current) if current in modes else -1
        self._set_param("depth_mode", modes[(index + 1) % len(modes)])
        self._show_status()
        self.plotter.render()

    def move_slab(self, steps: int) -> None:
        """Move the slab ``steps`` quarter-thicknesses along its normal (away from the camera: > 0)."""
        if not self._has("slab_thickness") or not self.mapper.GetSlabThickness():
            self._show_status(note="no slab: set the slab thickness slider above 0 first")
            self.plotter.render()
            return
        mapper, camera = self.mapper, self.plotter.renderer.GetActiveCamera()
        normal = np.array(mapper.GetSlabNormal() or camera.GetDirectionOfProjection(), float)
        normal /= np.linalg.norm(normal)
        centre = np.array(mapper.GetSlabCentre() or camera.GetFocalPoint(), float)
        bounds = self.grid.bounds
        along = np.array([[x, y, z] for x in bounds[0:2] for y in bounds[2:4] for z in bounds[4:6]]) @ normal
        step = max(self.voxel, 0.25 * mapper.GetSlabThickness())
        where = float(np.clip(centre @ normal + steps * step, along.min(), along.max()))
        self._set_param("slab_centre", tuple(float(v) for v in centre + (where - centre @ normal) * normal))
        self._show_status()
        self.plotter.render()

    def close(self, *_) -> None:
        if self.legend is not None:
            self.legend.SetEnabled(0)
            self.legend = None

    # -- helpers --------------------------------------------------------------
    def _table(self) -> dict:
        return {p.name: p for p in METHODS[self.method].parameters}

    def _has(self, name: str) -> bool:
        # the method's table, not its setters: a subclass inherits setters of parameters it does not have
        return name in self._table()

    def _set_param(self, name: str, value) -> None:
        self.params[name] = value
        set_parameters(self.mapper, **{name: value})

    def _set_sample_voxels(self, value: float) -> None:
        self.sample_voxels = float(value)
        self.mapper.SetSampleDistance(self.sample_voxels * self.voxel)
        self.plotter.render()

    def _set_weight(self, name: str, value: float) -> None:
        self._set_param(name, float(value))
        self.plotter.render()

    def _build_sliders(self) -> None:
        self.plotter.clear_slider_widgets()
        sliders = []
        if _uses_sample_distance(self.method):
            sliders.append(("sample distance (voxels)", SAMPLE_DISTANCE_RANGE, self.sample_voxels,
                            self._set_sample_voxels))
        for parameter in METHODS[self.method].parameters:
            rng = slider_range(parameter)
            if rng is not None and parameter.unit == "world units" and parameter.high is None:
                rng = (rng[0], float(np.linalg.norm(np.subtract(self.grid.bounds[1::2], self.grid.bounds[0::2]))))
            if rng is not None:
                value = self.params.get(parameter.name, getattr(self.mapper, parameter.getter)())
                sliders.append((parameter.name.replace("_", " "), rng, value,
                                lambda v, name=parameter.name: self._set_weight(name, v)))
        for row, (title, rng, value, callback) in enumerate(sliders):
            y = 0.92 - 0.13 * row
            self.plotter.add_slider_widget(callback, rng, value=value, title=title,
                                           pointa=(0.03, y), pointb=(0.3, y), style="modern",
                                           title_height=0.02, title_color="white", fmt="%.3g")

    def _build_legend(self) -> None:
        from vtkmodules.vtkInteractionWidgets import vtkOrientationMarkerWidget

        self.close()
        if "sphere_colors" not in self._table():
            return
        actor = _sphere_legend_actor(self.mapper)
        widget = vtkOrientationMarkerWidget()
        widget.SetOrientationMarker(actor)
        widget.SetInteractor(self.plotter.iren.interactor)
        widget.SetCurrentRenderer(self.plotter.renderer)
        widget.SetViewport(*LEGEND_VIEWPORT)
        widget.SetEnabled(1)
        widget.InteractiveOff()
        self.legend = widget

    def _show_status(self, note: str = "") -> None:
        lines = [f"method: {self.method}   (m: next)",
                 f"window: {self.window_label} {self.clim[0]:.6g} to {self.clim[1]:.6g}   (w: next)"]
        if _depth_modes(self.mapper):
            lines.append(f"depth mode: {self.mapper.GetDepthMode()}   (d: next)")
        if self._has("slab_thickness") and self.mapper.GetSlabThickness():
            lines.append(f"slab: {self.mapper.GetSlabThickness():.3g} thick   ([ / ]: move)")
        if note:
            lines.append(note)
        self.plotter.add_text("\n".join(lines), position="upper_right", font_size=10, color="white",
                              name="mipcast-status")

    def _on_mouse_move(self, *_) -> None:
        if "gaze_point" not in self._table():
            return
        x, y = self.plotter.iren.get_event_position()
        width, height = self.plotter.render_window.GetSize()
        x0, y0, x1, y1 = self.plotter.renderer.GetViewport()
        gaze_x = min(max((x / width - x0) / (x1 - x0), 0.0), 1.0)
        gaze_y = min(max((y / height - y0) / (y1 - y0), 0.0), 1.0)
        self.mapper.SetGazePoint(gaze_x, gaze_y)
        self.plotter.render()


def _checked_params(method: str, params: dict) -> dict:
    """``params``, refused unless every name is some method's parameter and the first method takes its values.

    Names of other methods are kept for when the viewer switches to them.
    """
    first = METHODS[check_choice("method", method, view_methods())].create()
    known = {p.name for m in METHODS.values() for p in m.parameters}
    for name in params:
        if name not in known and not callable(getattr(first, setter_name(name), None)):
            raise TypeError(f"no method has a parameter {name!r} (no {setter_name(name)}); "
                            f"see `mipcast view --help` for each method's")
    own = {p.name for p in METHODS[method].parameters}
    set_parameters(first, **{name: value for name, value in params.items()
                             if name in own or name not in known})
    return params


def _uses_sample_distance(method: str) -> bool:
    return not METHODS[method].walks_cells


def _depth_modes(mapper) -> tuple:
    """The choices of the method's ``depth_mode`` parameter (empty if it has none)."""
    table = {p.name: p for p in getattr(type(mapper), "PARAMETERS", ())}
    return table["depth_mode"].valid_choices() if "depth_mode" in table else ()


def _sphere_colours(mapper, directions: np.ndarray) -> np.ndarray:
    """RGB in 0..1 of the colour sphere along unit world ``directions`` (N, 3)."""
    front, back = mapper.GetSphereColors()
    axis = np.asarray(mapper.GetSphereOrientation(), dtype=float)[:, 2]
    return sphere_color(directions, axis, front, back)


def _sphere_legend_actor(mapper):
    """A shaded unit sphere coloured per point by the mapper's sphere colours (None if not exposed)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkFiltersSources import vtkSphereSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    source = vtkSphereSource()
    source.SetThetaResolution(48)
    source.SetPhiResolution(32)
    source.Update()
    sphere = source.GetOutput()
    points = vtk_to_numpy(sphere.GetPoints().GetData()).astype(float)
    directions = points / np.linalg.norm(points, axis=1, keepdims=True)
    colours = _sphere_colours(mapper, directions)
    if colours is None:
        return None
    rgb = numpy_to_vtk(np.round(255 * np.clip(colours, 0.0, 1.0)).astype(np.uint8), deep=True)
    rgb.SetName("sphere_colours")
    sphere.GetPointData().SetScalars(rgb)
    poly_mapper = vtkPolyDataMapper()
    poly_mapper.SetInputData(sphere)
    poly_mapper.SetColorModeToDirectScalars()
    actor = vtkActor()
    actor.SetMapper(poly_mapper)
    return actor
