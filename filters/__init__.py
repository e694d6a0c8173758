"""pyvista wrappers: render an ImageData with a mipcast method, or add it to a Plotter.

Thin functions over :class:`mipcast.offscreen.OffscreenView` and the mipcast
mappers, in the style of pyvista's own filters.  pyvista is imported here,
never by the core package.

Importing this module also registers two pyvista extensions (pyvista 0.48+
extension API, see :mod:`mipcast.filters.extensions`):

- ``grid.mip.render(...)`` and ``grid.mip.plot(...)`` on every ``pyvista.ImageData``;
- ``plotter.mip.add_volume(...)`` on every pyvista plotter, with the added
  volumes removed (and their shader pieces detached) when the plotter closes.

Method parameters are keyword arguments passed to the mapper's VTK-style
setters: ``depth_weight=0.2`` calls ``mapper.SetDepthWeight(0.2)`` (see
:func:`mipcast.core.parameters.set_parameters`).
"""
from __future__ import annotations

from typing import Optional, Sequence, Union

import numpy as np

from mipcast.io import as_image_data, with_scalars
from mipcast.mappers.input_preparer import missing_as_background, prepared_image, window_image
from mipcast.methods import METHODS, attach, create_mapper
from mipcast.offscreen import OffscreenView, set_view
from mipcast.core.windowing import resolve_window
from mipcast.core.parameters import method_parameters, set_parameters
from mipcast.core.validation import check_image, check_positive


def render(image, method: str = "mip", *, scalars: Optional[str] = None, size: Sequence[int] = (256, 256),
           view: str = "oblique", sample_distance: Optional[float] = None,
           window: Optional[Sequence[float]] = None, as_float: bool = False,
           component: Union[int, str, None] = None, clim: Optional[Sequence[float]] = None,
           **params) -> np.ndarray:
    """Render ``image`` offscreen with a mipcast method.

    Parameters
    ----------
    image : pyvista.ImageData
        Volume with point scalars (several components: see ``component``); a
        ``RectilinearGrid`` with evenly spaced coordinates is drawn as image data
        (:func:`mipcast.io.as_image_data`).
    method : str, default: "mip"
        A name from ``mipcast.METHODS``.
    scalars : str, optional
        Name of the point array to project; default the active scalars.
        The image itself is not modified.
    size : sequence of int, default: (256, 256)
        Image (width, height) in pixels.
    view : str, default: "oblique"
        A camera preset of ``mipcast.offscreen.VIEWS`` or a patient view
        (``"anterior"``, ``"posterior"``, ``"left"``, ``"right"``,
        ``"superior"``, ``"inferior"``; see :mod:`mipcast.core.patient_views`).
    sample_distance : float, optional
        World units between samples; default one sample per voxel.
    window : sequence of float or str, optional
        Grey window (low, high) in data units; default (``"auto"``) the
        window a viewer would pick (a CT preset for HU, else histogram
        percentiles: :func:`mipcast.core.windowing.default_window`);
        ``"full"`` the data range; or a preset name such as ``"ct-bone"``.
    as_float : bool, default: False
        Return each pixel's maximum in data units (float32, NaN where a ray
        misses) instead of the 8-bit RGB picture.
    component : int or "magnitude", optional
        Which component of multi-component scalars to draw; default their
        magnitude, as ParaView does (one-component scalars are drawn as they are).
    clim : sequence of float or str, optional
        pyvista's name for ``window`` (as in :func:`add_volume`); give one of the two.
    **params
        Method parameters, passed to the mapper's setters (see
        :func:`mipcast.core.parameters.set_parameters`); an unknown name raises ``TypeError``.

    Returns
    -------
    numpy.ndarray
        (height, width, 3) uint8, or (height, width) float32, top row first.

    Raises
    ------
    mipcast.InputError
        Before anything renders, for input that cannot be drawn (the message
        names the problem and the fix); ``TypeError`` for non-image data.
        NaN/Inf voxels are drawn as missing data (docs/reliability.md).

    Examples
    --------
    >>> import pyvista as pv
    >>> from mipcast.filters import render
    >>> from mipcast.data_fixtures import make_fixture
    >>> grid = pv.wrap(make_fixture("vessels", size=32))
    >>> render(grid, size=(64, 48)).shape
    (48, 64, 3)
    >>> render(grid, "mip", size=(32, 32), as_float=True, image_sample_distance=2.0).dtype
    dtype('float32')
    """
    if clim is not None and window is not None:
        raise TypeError("give window or clim (pyvista's name for the same grey window), not both")
    if "cmap" in params:
        raise TypeError("render draws the grey picture (and as_float the values); for a colour map use "
                        "add_volume(plotter, grid, method, cmap=...) or grid.mip.plot(method, cmap=...)")
    scene = OffscreenView(with_scalars(as_image_data(image), scalars), method, size=size, view=view,
                          sample_distance=sample_distance, window=window if clim is None else clim,
                          component=component)
    set_parameters(scene.mapper, **params)
    return scene.float_image() if as_float else scene.screenshot()


def add_volume(plotter, image, method: str = "mip", *, scalars: Optional[str] = None,
               cmap: Union[str, object] = "gray", clim: Optional[Sequence[float]] = None,
               opacity: Union[float, str] = 1.0, sample_distance: Optional[float] = None,
               name: Optional[str] = None, reset_camera: Optional[bool] = None, render: bool = True,
               component: Union[int, str, None] = None, **params):
    """Add ``image`` to a pyvista ``Plotter``, rendered by a mipcast method.

    Parameters
    ----------
    plotter : pyvista.Plotter
        Any plotter, including ``Plotter(off_screen=True)``.
    image : pyvista.ImageData
        Volume with point scalars (several components: see ``component``); a
        ``RectilinearGrid`` with evenly spaced coordinates is drawn as image data
        (:func:`mipcast.io.as_image_data`).
    method : str, default: "mip"
        A name from ``mipcast.METHODS``.
    scalars : str, optional
        Name of the point array to project; default the active scalars.
        The image itself is not modified.
    cmap : str or matplotlib colormap, default: "gray"
        Colour map over ``clim``, as in ``Plotter.add_volume``.
    clim : sequence of float or str, optional
        Colour limits (low, high); default (``"auto"``) the window a viewer
        would pick (:func:`mipcast.core.windowing.default_window`);
        ``"full"`` the data range; or a preset name such as ``"ct-bone"``.
    opacity : float or str, default: 1.0
        A constant opacity, or one of pyvista's opacity transfer function
        names (``"linear"``, ``"sigmoid"``, ...), as in ``add_volume``.
    sample_distance : float, optional
        World units between samples; default one sample per voxel.
        Auto-adjust is off so the setting holds while interacting.
    name : str, optional
        Actor name, as in pyvista: adding again under the same name replaces
        the earlier volume, and ``plotter.remove_actor(name)`` removes it.
    reset_camera : bool, optional
        As in pyvista: by default the camera is reset only if it has not
        been set yet (a ``camera_position`` set before is kept).
    render : bool, default: True
        As in pyvista: render a shown window after adding.
    component : int or "magnitude", optional
        Which component of multi-component scalars to draw; default their
        magnitude, as ParaView does.
    **params
        Method parameters, passed to the mapper's setters (see
        :func:`mipcast.core.parameters.set_parameters`); an unknown name raises ``TypeError``
        before anything is added.

    Returns
    -------
    pyvista.Volume
        The added volume (a ``vtkVolume``); its mapper is ``volume.mapper``.

    Examples
    --------
    >>> import pyvista as pv
    >>> from mipcast.filters import add_volume
    >>> from mipcast.data_fixtures import make_fixture
    >>> plotter = pv.Plotter(off_screen=True, window_size=(64, 64))
    >>> volume = add_volume(plotter, pv.wrap(make_fixture("spheres", size=24)))
    >>> plotter.screenshot().shape
    (64, 64, 3)
    """
    import pyvista

    image = with_scalars(as_image_data(image), scalars)
    check_image(image, component)  # raises mipcast.InputError before anything is added
    projection = METHODS[method].projection if method in METHODS else "mip"  # create_mapper names a bad one
    low, high = resolve_window(window_image(image, component), clim, projection)
    if sample_distance is None:
        sample_distance = min(abs(s) for s in image.GetSpacing())
    mapper = create_mapper(method)
    if METHODS[method].float_readout:  # a mipcast mapper: its preparer draws the component
        mapper.SetComponent(component)
        mapper.SetInputData(image)
    else:  # VTK's own mappers draw the prepared copy
        mapper.SetInputData(prepared_image(image, component, projection=projection))
    mapper.SetAutoAdjustSampleDistances(False)
    mapper.SetSampleDistance(check_positive("sample_distance", sample_distance))
    set_parameters(mapper, **params)
    volume = pyvista.Volume()
    prop = _volume_property(cmap, (low, high), opacity)
    if not METHODS[method].float_readout:  # rays through missing data only: background (docs/reliability.md)
        prop = missing_as_background(mapper, prop, image, component, projection)
    volume.SetProperty(prop)
    attach(mapper, volume)
    plotter.add_actor(volume, reset_camera=reset_camera, name=name, render=render)
    return volume


def plot(image, method: str = "mip", *, off_screen: Optional[bool] = None,
         window_size: Optional[Sequence[int]] = None, screenshot=None, view: Optional[str] = None, **kwargs):
    """Show ``image`` in a new pyvista ``Plotter`` with a mipcast method, like ``grid.plot(volume=True)``.

    Parameters
    ----------
    image : pyvista.ImageData
        Volume with point scalars (several components: see ``component``); a
        ``RectilinearGrid`` with evenly spaced coordinates is drawn as image data
        (:func:`mipcast.io.as_image_data`).
    method : str, default: "mip"
        A name from ``mipcast.METHODS``.
    off_screen, window_size, screenshot
        As in ``pyvista.Plotter`` and ``Plotter.show`` (``screenshot``: a PNG
        path to write).
    view : str, optional
        A camera preset or patient view, as in :func:`render`
        (``"anterior"``, ...); default pyvista's camera.
    **kwargs
        Keyword arguments of :func:`add_volume` (``cmap``, ``clim``,
        ``scalars``, ... and method parameters such as ``depth_weight``).

    Returns
    -------
    object
        What ``Plotter.show`` returns: the image (numpy array) when
        ``screenshot=True``, else ``None``.

    Examples
    --------
    >>> import pyvista as pv
    >>> from mipcast.filters import plot
    >>> from mipcast.data_fixtures import make_fixture
    >>> import tempfile, os
    >>> path = os.path.join(tempfile.mkdtemp(), "analytic.png")
    >>> _ = plot(pv.wrap(make_fixture("vessels", size=24)), "analytic", off_screen=True,
    ...          window_size=(64, 64), screenshot=path)
    >>> os.path.getsize(path) > 0
    True
    """
    import pyvista

    plotter = pyvista.Plotter(off_screen=off_screen, window_size=window_size)
    try:
        add_volume(plotter, image, method, **kwargs)
        if view is not None:
            set_view(plotter.renderer, image, view)
            plotter.camera_set = True  # else pyvista puts its own camera back on the first render
    except BaseException:
        plotter.close()
        raise
    return plotter.show(screenshot=screenshot)


def _volume_property(cmap, clim, opacity):
    import pyvista
    from matplotlib import colormaps
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

    low, high = float(clim[0]), float(clim[1])
    if not high > low:
        raise ValueError(f"clim must be (low, high) with high > low, got {tuple(clim)}")
    colours = (colormaps[cmap] if isinstance(cmap, str) else cmap)(np.linspace(0.0, 1.0, 256))
    if isinstance(opacity, str):
        alphas = np.asarray(pyvista.opacity_transfer_function(opacity, 256), dtype=float)
        alphas = alphas / 255.0 if alphas.max() > 1.0 else alphas
    else:
        alphas = np.full(256, float(opacity))
        if not 0.0 <= float(opacity) <= 1.0:
            raise ValueError(f"opacity must be within [0, 1], got {opacity}")
    colour_tf, opacity_tf = vtkColorTransferFunction(), vtkPiecewiseFunction()
    for value, rgba, alpha in zip(np.linspace(low, high, 256), colours, alphas):
        colour_tf.AddRGBPoint(value, *rgba[:3])
        opacity_tf.AddPoint(value, alpha)
    prop = vtkVolumeProperty()
    prop.SetColor(colour_tf)
    prop.SetScalarOpacity(opacity_tf)
    prop.SetInterpolationTypeToLinear()
    return prop


# Registers grid.mip and plotter.mip (imports pyvista); after the functions it delegates to.
from mipcast.filters.extensions import MipAccessor, MipPlotterComponent  # noqa: E402

__all__ = ["render", "add_volume", "plot", "with_scalars", "set_parameters", "method_parameters",
           "MipAccessor", "MipPlotterComponent"]
