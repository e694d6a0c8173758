"""One volume, one method, one offscreen window: the scene tests, CLI and benchmark share.

Offscreen rendering needs OpenGL 3.2+ from a GPU driver, or Mesa's EGL
(llvmpipe) on a headless machine; VTK picks EGL by itself when there is no
display.
"""
from __future__ import annotations

import time
from typing import Optional, Sequence

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import (
    vtkColorTransferFunction,
    vtkRenderer,
    vtkRenderWindow,
    vtkVolume,
    vtkVolumeProperty,
    vtkWindowToImageFilter,
)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (registers the OpenGL back end)

from mipcast import methods
from mipcast.mappers.float_readout import render_float
from mipcast.mappers.gpu_limits import max_picture_size
from mipcast.mappers.input_preparer import missing_as_background, prepared_image, window_image
from mipcast.core.patient_views import PATIENT_VIEWS, set_patient_view
from mipcast.core.prepare import scalar_image
from mipcast.core.windowing import resolve_window
from mipcast.core.validation import check_choice, check_image, check_positive, check_size, samples_per_ray_problem

#: View presets: (azimuth, elevation, parallel projection).  Azimuth and
#: elevation rotate the camera from the default view down -z.
VIEWS = {
    "oblique": (33.0, 21.0, True),
    "perspective": (-38.0, 27.0, False),
    "front": (0.0, 0.0, True),
    "back": (180.0, 0.0, True),
    "side": (90.0, 0.0, True),
}
#: Every view name: the presets of :data:`VIEWS` (volume axes) and the patient
#: views of :data:`mipcast.core.patient_views.PATIENT_VIEWS` (anterior, ...).
VIEW_NAMES = tuple(VIEWS) + tuple(PATIENT_VIEWS)


def grey_property(window: Sequence[float]) -> vtkVolumeProperty:
    """A MIP volume property: black-to-white over ``window``, opaque, trilinear.

    Examples
    --------
    >>> grey_property((0.0, 1.0)).GetInterpolationType()
    1
    """
    low, high = float(window[0]), float(window[1])
    if not (high > low and np.isfinite(low) and np.isfinite(high)):
        raise ValueError(f"window must be finite (low, high) with high > low, got {tuple(window)}")
    colour = vtkColorTransferFunction()
    colour.AddRGBPoint(low, 0.0, 0.0, 0.0)
    colour.AddRGBPoint(high, 1.0, 1.0, 1.0)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(low, 1.0)
    opacity.AddPoint(high, 1.0)
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    return prop


def set_view(renderer, image, view: str) -> None:
    """Point the renderer's camera at ``image`` from a preset of :data:`VIEWS` or a patient view.

    Patient views (``anterior``, ``posterior``, ``left``, ``right``,
    ``superior``, ``inferior``) are described in :mod:`mipcast.core.patient_views`.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderer
    >>> from mipcast.data_fixtures import make_fixture
    >>> renderer = vtkRenderer()
    >>> set_view(renderer, make_fixture("spheres", size=16), "front")
    >>> renderer.GetActiveCamera().GetParallelProjection()
    1
    """
    if check_choice("view", view, VIEW_NAMES) in PATIENT_VIEWS:
        set_patient_view(renderer, image, view)
        return
    azimuth, elevation, parallel = VIEWS[view]
    camera = renderer.GetActiveCamera()
    camera.SetPosition(0.0, 0.0, 1.0)
    camera.SetFocalPoint(0.0, 0.0, 0.0)
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.Azimuth(azimuth)
    camera.Elevation(elevation)
    camera.OrthogonalizeViewUp()
    camera.SetParallelProjection(parallel)
    camera.SetViewAngle(30.0)
    renderer.ResetCamera(image.GetBounds())


class OffscreenView:
    """An offscreen window rendering ``image`` with one method.

    Parameters
    ----------
    image : vtkImageData
        The volume (point scalars; several components: see ``component``;
        NaN/Inf voxels are missing data: docs/reliability.md).
    method : str, default: "mip"
        A name from :data:`mipcast.methods.METHODS`.
    size : tuple of int, default: (256, 256)
        Window (width, height) in pixels.
    view : str, default: "oblique"
        A preset of :data:`VIEWS` or a patient view (``"anterior"``, ...;
        :data:`VIEW_NAMES`).
    sample_distance : float, optional
        World units between samples; default one sample per voxel (the
        smallest spacing).  Auto-adjust and jittering are off.
    component : int or "magnitude", optional
        Which component of multi-component scalars to draw (default: the
        magnitude; see :mod:`mipcast.core.prepare`).
    window : tuple of float or str, optional
        Grey window (low, high) in data units, used as given; default (or
        ``"auto"``) the window a viewer would pick
        (:func:`mipcast.core.windowing.default_window` for the method's
        projection, MIP, MinIP or average: a CT preset for Hounsfield
        units, else histogram percentiles); ``"full"`` the data
        range; a preset name (:data:`mipcast.core.windowing.PRESETS`); or
        ``"dicom"`` (``"dicom:2"``, ``"dicom:BONE"``), a window a DICOM series
        carries (:func:`mipcast.core.windowing.dicom_windows`).
        The chosen (low, high) is ``self.window``.
    whole_range : (low, high), optional
        The finite range of the whole volume when ``image`` is a piece of it
        (a rank's brick, :mod:`mipcast.distributed`; mipcast's methods):
        missing values are filled as the whole volume's, and the piece may
        hold missing values only.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = OffscreenView(make_fixture("spheres", size=16), size=(32, 24))
    >>> view.screenshot().shape
    (24, 32, 3)
    """

    def __init__(self, image, method: str = "mip", size=(256, 256), view: str = "oblique",
                 sample_distance: Optional[float] = None, window=None, component=None,
                 whole_range: Optional[Sequence[float]] = None) -> None:
        check_image(image, component, whole_range)  # raises InputError naming the problem before anything renders
        self.image = image
        self.component = component
        #: The whole volume's finite range when ``image`` is a piece of it (None: ``image`` is the whole).
        self.whole_range = None if whole_range is None else (float(whole_range[0]), float(whole_range[1]))
        self.size = check_size(size)
        if sample_distance is None:
            sample_distance = min(abs(s) for s in image.GetSpacing())
        self.sample_distance = check_positive("sample_distance", sample_distance)
        #: The :class:`mipcast.methods.Method` entry.
        self.method = methods.METHODS[check_choice("method", method, tuple(methods.METHODS))]
        self.window = resolve_window(window_image(image, component, self.whole_range), window, self.method.projection)
        self.mapper = self.method.create()
        # VTK's own GPU mappers and mipcast's sampled ones: at most MAX_SAMPLES_PER_RAY samples a ray
        sampled = getattr(self.mapper, "_samples_rays", lambda: self.mapper.IsA("vtkGPUVolumeRayCastMapper"))()
        dense = samples_per_ray_problem(scalar_image(image), self.sample_distance) if sampled else None
        if dense is not None:
            raise ValueError(dense)
        self.set_input(image, component)
        self.mapper.SetAutoAdjustSampleDistances(False)
        self.mapper.SetSampleDistance(self.sample_distance)
        if hasattr(self.mapper, "SetUseJittering"):  # the CPU peer has no jittering
            self.mapper.SetUseJittering(False)
        self.volume = vtkVolume()
        self.set_window(self.window)
        methods.attach(self.mapper, self.volume)
        self.renderer = vtkRenderer()
        self.renderer.AddVolume(self.volume)
        self.render_window = vtkRenderWindow()
        self.render_window.SetOffScreenRendering(True)
        self.render_window.SetMultiSamples(0)  # MSAA would blend silhouette pixels with the background
        self.render_window.AddRenderer(self.renderer)
        self.render_window.SetSize(*self.size)
        self._fits = None  # the window size checked against the driver's largest picture (_check_fits)
        set_view(self.renderer, scalar_image(image), view)  # frames what is drawn (cell data: the centres)

    def set_input(self, image, component=None) -> None:
        """Draw ``image`` from now on (same mapper, window and camera).

        mipcast mappers take it as it is (their preparer draws one component,
        missing values filled: :mod:`mipcast.core.prepare`); VTK's own
        mappers get :func:`~mipcast.mappers.input_preparer.prepared_image`.
        """
        if self.method.float_readout:  # a mipcast mapper (the method table says so)
            self.mapper.SetComponent(component)
            self.mapper.GetInputPreparer().SetWholeRange(self.whole_range)
            self.mapper.SetInputData(image)
        else:
            self.mapper.SetInputData(prepared_image(image, component, projection=self.method.projection))
        self.image, self.component = image, component
        if getattr(self, "volume", None) is not None:
            self.set_window(self.window)  # VTK's own mappers: missing data's opacity follows the input

    def set_window(self, window: Sequence[float]) -> None:
        """Draw with the grey window ``(low, high)`` (data units) from now on: :func:`grey_property`.

        For VTK's own mappers (stock, CPU) and input with missing values the
        property makes rays that saw only missing data transparent
        (:func:`~mipcast.mappers.input_preparer.missing_as_background`).
        """
        self.window = (float(window[0]), float(window[1]))
        prop = grey_property(self.window)
        if not self.method.float_readout:
            prop = missing_as_background(self.mapper, prop, self.image, self.component, self.method.projection)
        self.volume.SetProperty(prop)

    @property
    def camera(self):
        """The renderer's active vtkCamera."""
        return self.renderer.GetActiveCamera()

    def screenshot(self) -> np.ndarray:
        """Render and return the 8-bit RGB image, shape (height, width, 3), top row first.

        A volume beyond the 3D texture limit is drawn in bricks by the
        mapper itself (:mod:`mipcast.mappers.bricked_draw`), as in any window.
        A picture larger than the driver draws is refused (:meth:`_check_fits`).
        """
        self.render_window.Render()
        self._check_fits()
        grab = vtkWindowToImageFilter()
        grab.SetInput(self.render_window)
        grab.SetInputBufferTypeToRGB()
        grab.ReadFrontBufferOff()
        grab.Update()
        output = grab.GetOutput()
        width, height, _ = output.GetDimensions()
        pixels = vtk_to_numpy(output.GetPointData().GetScalars()).reshape(height, width, 3)
        return pixels[::-1].copy()

    def float_image(self) -> np.ndarray:
        """Render and return each pixel's maximum in data units (float32, NaN = miss)."""
        values = render_float(self.render_window, self.mapper)
        self._check_fits()
        return values

    def frame_times(self, frames: int = 10, warmup: int = 3) -> list:
        """Wall-clock seconds of ``frames`` renders after ``warmup`` untimed ones.

        Each timed frame is a full re-render followed by ``WaitForCompletion``,
        so the time includes the GPU work, not just its submission.
        """
        for _ in range(warmup):
            self._render_and_wait()
            self._check_fits()
        times = []
        for _ in range(frames):
            start = time.perf_counter()
            self._render_and_wait()
            times.append(time.perf_counter() - start)
        return times

    def _check_fits(self) -> None:
        """Refuse a window larger than the driver draws (``ValueError``): VTK draws it black, silently
        (llvmpipe: 16384 pixels a side; until 2026-12-04 a 17000 x 300 screenshot came back black).  Checked
        once per window size, after a render (the driver's limit needs the window's context)."""
        size = tuple(self.render_window.GetSize())
        if self._fits == size:
            return
        limit = max_picture_size(self.render_window)
        if limit and max(size) > limit:
            raise ValueError(f"a picture of {size[0]} x {size[1]} pixels is larger than this OpenGL driver draws "
                             f"({limit} pixels a side, GL_MAX_TEXTURE_SIZE; VTK would draw it black): render at "
                             f"most {limit} x {limit}, or in tiles")
        self._fits = size

    def _render_and_wait(self) -> None:
        self.render_window.Render()
        self.render_window.WaitForCompletion()
