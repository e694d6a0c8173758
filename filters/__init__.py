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

import numbers
import warnings
from typing import Optional, Sequence, Union

import numpy as np

from mipcast.io import as_image_data, with_scalars
from mipcast.io.volumes import vtk_values
from mipcast.mappers.input_preparer import missing_as_background, prepared_image, window_image
from mipcast.methods import METHODS, attach, create_mapper
from mipcast.offscreen import OffscreenView, set_view
from mipcast.core.errors import InputWarning
from mipcast.core.windowing import resolve_window
from mipcast.core.parameters import method_parameters, set_parameters
from mipcast.core.validation import check_image, check_positive


def render(image, method: str = "mip", *, scalars=None, size: Sequence[int] = (256, 256),
           view: str = "oblique", sample_distance: Optional[float] = None,
           window: Optional[Sequence[float]] = None, as_float: bool = False,
           component: Union[int, str, None] = None, clim: Union[Sequence[float], float, None] = None,
           resolution: Optional[Sequence[float]] = None, preference: str = "point", **params) -> np.ndarray:
    """Render ``image`` offscreen with a mipcast method.

    Parameters
    ----------
    image : pyvista.ImageData or numpy.ndarray
        Volume with point scalars (several components: see ``component``); a
        ``RectilinearGrid`` with evenly spaced coordinates is drawn as image data
        (:func:`mipcast.io.as_image_data`); a 3-D array indexed ``[x, y, z]`` as
        ``pyvista.wrap`` makes it image data (spacing ``resolution``), a 4-D
        one ``[x, y, z, component]`` likewise with components, complex values
        as (real, imaginary) components; a numpy masked array's masked
        entries are missing data (as NaN); an array-like of 3 or 4 dimensions
        (xarray, h5py, zarr, dask) is read with ``np.asarray``.
    method : str, default: "mip"
        A name from ``mipcast.METHODS``.
    scalars : str or array_like, optional
        Name of the point (or cell) array to project, or the values (one per
        point in point order, or per cell), as in pyvista's ``add_volume``;
        default the active scalars; masked entries of a numpy masked array
        are missing data.  The image itself is not modified.
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
        ``"full"`` the data range; a preset name such as ``"ct-bone"``; or
        ``"dicom"`` (``"dicom:2"``, ``"dicom:BONE"``), a window the DICOM series carries.
    as_float : bool, default: False
        Return each pixel's maximum in data units (float32, NaN where a ray
        misses) instead of the 8-bit RGB picture.
    component : int or "magnitude", optional
        Which component of multi-component scalars to draw; default their
        magnitude, as ParaView does (one-component scalars are drawn as they are).
    clim : sequence of float, float or str, optional
        pyvista's name for ``window`` (as in :func:`add_volume`; one number
        ``c`` means ``(-c, c)``, as in pyvista); give one of the two.
    resolution : sequence of float, optional
        The spacing of a numpy array volume (default 1), as in pyvista.
    preference : {"point", "cell"}, default: "point"
        Which array a name means when the image has a point and a cell array of it.
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
    refuse_unused(params)
    warn_stock_grey(method, window=window, clim=clim)
    scene = OffscreenView(volume_image(image, scalars, resolution, preference), method, size=size, view=view,
                          sample_distance=sample_distance, window=window if clim is None else pyvista_clim(clim),
                          component=component)
    set_parameters(scene.mapper, **params)
    return scene.float_image() if as_float else scene.screenshot()


def add_volume(plotter, image, method: str = "mip", *, scalars=None,
               cmap: Union[str, Sequence[str], object] = "gray", clim: Union[Sequence[float], float, None] = None,
               opacity: Union[float, str, Sequence[float]] = 1.0, n_colors: int = 256, flip_scalars: bool = False,
               log_scale: bool = False, sample_distance: Optional[float] = None, name: Optional[str] = None,
               reset_camera: Optional[bool] = None, render: bool = True, component: Union[int, str, None] = None,
               resolution: Optional[Sequence[float]] = None, preference: str = "point",
               blending: Optional[str] = None, user_matrix=None, pickable: bool = True,
               show_scalar_bar: bool = False, scalar_bar_args: Optional[dict] = None,
               annotations: Optional[dict] = None, **params):
    """Add ``image`` to a pyvista ``Plotter``, rendered by a mipcast method.

    The keywords are those of pyvista's ``Plotter.add_volume`` that mean
    something for a projection, with pyvista's meaning; the others
    (``shade``, ``mapper``, ``opacity_unit_distance``, ...) raise
    ``TypeError`` saying why (:data:`PYVISTA_UNUSED`).

    Parameters
    ----------
    plotter : pyvista.Plotter
        Any plotter, including ``Plotter(off_screen=True)``.
    image : pyvista.ImageData or numpy.ndarray
        Volume with point scalars (several components: see ``component``); a
        ``RectilinearGrid`` with evenly spaced coordinates is drawn as image data
        (:func:`mipcast.io.as_image_data`); a 3-D array indexed ``[x, y, z]`` as
        ``pyvista.wrap`` makes it image data (spacing ``resolution``), a 4-D
        one ``[x, y, z, component]`` likewise with components, complex values
        as (real, imaginary) components; a numpy masked array's masked
        entries are missing data (as NaN); an array-like of 3 or 4 dimensions
        (xarray, h5py, zarr, dask) is read with ``np.asarray``.
    method : str, default: "mip"
        A name from ``mipcast.METHODS``.
    scalars : str or array_like, optional
        Name of the point (or cell) array to project, or the values (one per
        point in point order, or per cell), as in pyvista; default the
        active scalars.  The image itself is not modified.
    cmap : str, list of colours or matplotlib colormap, default: "gray"
        Colour map over ``clim``, as in ``Plotter.add_volume``.
    clim : sequence of float, float or str, optional
        Colour limits (low, high); one number ``c`` means ``(-c, c)``, as in
        pyvista; default (``"auto"``) the window a viewer would pick
        (:func:`mipcast.core.windowing.default_window`); ``"full"`` the data
        range; a preset name such as ``"ct-bone"``; or ``"dicom"``
        (``"dicom:2"``, ``"dicom:BONE"``), a window a DICOM series carries
        (:func:`mipcast.core.windowing.dicom_windows`).
    opacity : float, str or sequence of float, default: 1.0
        A constant opacity, one of pyvista's opacity transfer function
        names (``"linear"``, ``"sigmoid"``, ...) or opacities spread over
        ``clim`` (interpolated to ``n_colors``), as in ``add_volume``.
    n_colors : int, default: 256
        Number of colours (and opacities) of the transfer functions.
    flip_scalars : bool, default: False
        Reverse the colour map, as in pyvista.
    log_scale : bool, default: False
        Spread the colour map logarithmically over ``clim`` (which must be
        above 0).  A maximum or minimum projection is the same whichever
        monotone scale it is coloured on.
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
    resolution : sequence of float, optional
        The spacing of a numpy array volume (default 1), as in pyvista.
    preference : {"point", "cell"}, default: "point"
        Which array a name means when the image has a point and a cell array of it.
    blending : str, optional
        pyvista's name of the projection; the method chooses it, so only the
        method's own is accepted (``"maximum"`` for ``"mip"``, ...).
    user_matrix : 4x4 array_like or vtkMatrix4x4, optional
        Placement of the volume in the scene, as in pyvista.
    pickable : bool, default: True
        As in pyvista.
    show_scalar_bar : bool, default: False
        Add a scalar bar of the colour map over ``clim`` (pyvista's theme
        shows one by default; a projection is read as a picture first).
    scalar_bar_args : dict, optional
        Keyword arguments of ``Plotter.add_scalar_bar``; the title defaults
        to the array's name.
    annotations : dict, optional
        Values and labels shown on the scalar bar, as in pyvista.
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
    >>> volume = add_volume(plotter, pv.wrap(make_fixture("spheres", size=24)), cmap=["black", "red", "white"],
    ...                     opacity=[0.2, 1.0], show_scalar_bar=True)
    >>> plotter.screenshot().shape
    (64, 64, 3)
    """
    import pyvista

    clim, cmap = params.pop("rng", clim), params.pop("colormap", cmap)  # pyvista's aliases
    refuse_unused(params)
    warn_stock_grey(method, clim=clim, cmap=cmap)
    image = volume_image(image, scalars, resolution, preference)
    check_image(image, component)  # raises mipcast.InputError before anything is added
    projection = METHODS[method].projection if method in METHODS else "mip"  # create_mapper names a bad one
    check_blending(blending, method, projection)
    low, high = resolve_window(window_image(image, component), pyvista_clim(clim), projection)
    colormap, values, colours, alphas = _transfer_points(cmap, (low, high), opacity, n_colors, flip_scalars,
                                                         log_scale)
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
    prop = _volume_property(values, colours, alphas)
    if not METHODS[method].float_readout:  # rays through missing data only: background (docs/reliability.md)
        prop = missing_as_background(mapper, prop, image, component, projection)
    volume.SetProperty(prop)
    if user_matrix is not None:
        volume.user_matrix = user_matrix
    attach(mapper, volume)
    plotter.add_actor(volume, reset_camera=reset_camera, name=name, render=render, pickable=pickable)
    if show_scalar_bar:
        table = pyvista.LookupTable(cmap=colormap, n_values=len(colours), scalar_range=(low, high),
                                    log_scale=log_scale)
        if annotations:
            table.annotations = annotations
        bar = dict(scalar_bar_args or {})
        bar.setdefault("title", image.GetPointData().GetScalars().GetName() or "Data")
        plotter.add_scalar_bar(lookup_table=table, **bar)
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
        volume = add_volume(plotter, image, method, **kwargs)
        if view is not None:
            set_view(plotter.renderer, volume.GetMapper().GetInput(), view)
            plotter.camera_set = True  # else pyvista puts its own camera back on the first render
    except BaseException:
        plotter.close()
        raise
    return plotter.show(screenshot=screenshot)


_SHADING = "a projection is not shaded (VTK's own MIP ignores shading too): drop it; method='demip' shades by depth"
#: pyvista ``add_volume`` keywords a projection has no use for: why, and what to do instead.
PYVISTA_UNUSED = {
    "mapper": "the method is the mapper: choose it with method= (a name of mipcast.METHODS)",
    "shade": _SHADING, "ambient": _SHADING, "diffuse": _SHADING, "specular": _SHADING, "specular_power": _SHADING,
    "opacity_unit_distance": "a projection does not accumulate opacity along its rays: drop it",
    "culling": "a volume has no faces to cull: drop it",
    "categories": "a projection's values are not categories (a MIP of labels shows the largest label on each "
                  "ray): give n_colors= for a stepped colour map",
    "multi_colors": "it colours the blocks of a MultiBlock, which mipcast does not draw: add each image block",
}
#: pyvista's ``blending`` name of each projection of the method table.
BLENDING = {"mip": "maximum", "minip": "minimum", "average": "average"}


def refuse_unused(params: dict) -> None:
    """Raise ``TypeError`` for a pyvista ``add_volume`` keyword of :data:`PYVISTA_UNUSED`, naming why and the fix."""
    for key in params:
        if key in PYVISTA_UNUSED:
            raise TypeError(f"{key}= is a keyword of pyvista's add_volume that mipcast does not take: "
                            f"{PYVISTA_UNUSED[key]}")


def warn_stock_grey(method: str, **given) -> None:
    """Warn that ``stock_average`` ignores the window and colour map among ``given`` (those not None).

    VTK's AVERAGE_INTENSITY blend draws a grey of the opacity-weighted mean
    normalised over the data range, whatever the window or colours; the
    caller is told so, and which methods draw the mean through them.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warn_stock_grey("stock_average", clim=(0, 1), cmap=None)
    >>> str(caught[0].message).split(":")[0]
    "stock_average draws VTK's own grey of the data range and ignores clim"
    """
    named = [name for name, value in given.items() if value is not None]
    if method == "stock_average" and named:
        warnings.warn(f"stock_average draws VTK's own grey of the data range and ignores {' and '.join(named)}: "
                      "method='average' (or 'analytic_average', exact) draws the mean through the window and "
                      "colour map", InputWarning, stacklevel=3)


def check_blending(blending: Optional[str], method: str, projection: str) -> None:
    """Accept pyvista's ``blending`` only when it names ``method``'s own projection; else ``TypeError`` with the fix."""
    if blending is None or blending == BLENDING[projection]:
        return
    by_blending = {name: sorted(m for m, row in METHODS.items() if row.projection == kind and row.in_view)
                   for kind, name in BLENDING.items()}
    choices = "; ".join(f"{name!r}: method {', '.join(map(repr, methods))}" for name, methods in by_blending.items())
    raise TypeError(f"blending={blending!r}, but method {method!r} projects by {BLENDING[projection]!r}: the "
                    f"method chooses the projection ({choices}); drop blending= or pick the method. 'composite' "
                    "and 'additive' are not projections: use pyvista's own add_volume for them")


def pyvista_clim(clim):
    """pyvista's ``clim``: one number ``c`` is ``(-c, c)``; anything else is returned as it is."""
    if isinstance(clim, numbers.Real) and not isinstance(clim, bool):
        return (-float(clim), float(clim))
    return clim


def volume_image(image, scalars=None, resolution: Optional[Sequence[float]] = None, preference: str = "point"):
    """The image data to draw: a numpy volume wrapped as pyvista does, image data made drawable, the scalars chosen.

    Examples
    --------
    >>> volume_image(np.zeros((4, 5, 6)), resolution=(1.0, 2.0, 3.0)).GetSpacing()
    (1.0, 2.0, 3.0)
    """
    if not isinstance(image, np.ndarray) and hasattr(image, "__array__") and getattr(image, "ndim", None) in (3, 4):
        image = np.asarray(image)  # an array-like volume: xarray's DataArray, h5py's or zarr's dataset, dask
    if isinstance(image, np.ndarray):
        image = _numpy_volume(image)
        image.spacing = check_resolution(resolution)
    elif resolution is not None:
        raise TypeError("resolution= is the spacing of a numpy array volume; image data has its own spacing: "
                        "set grid.spacing instead")
    return with_scalars(as_image_data(image), scalars, preference)


def _numpy_volume(values: np.ndarray):
    """A numpy volume ``[x, y, z]`` (or ``[x, y, z, component]``) as pyvista image data of spacing 1."""
    import pyvista

    if values.ndim not in (3, 4):
        raise TypeError(f"a numpy volume must be a 3-D array indexed [x, y, z] (or 4-D, [x, y, z, component]), "
                        f"got shape {values.shape}")
    if values.dtype.kind not in "iufbc":
        raise TypeError(f"a numpy volume must hold numbers, got dtype {values.dtype}: convert it first "
                        "(e.g. values.astype(np.float32))")
    values = vtk_values(values)
    if values.ndim == 3:
        return pyvista.wrap(values)
    image = pyvista.ImageData(dimensions=values.shape[:3])
    image.point_data["values"] = values.reshape(-1, values.shape[3], order="F")
    return image


def check_resolution(resolution) -> tuple:
    """``resolution`` as three positive spacings (default ``(1, 1, 1)``), or ``ValueError``."""
    if resolution is None:
        return (1.0, 1.0, 1.0)
    spacing = tuple(float(r) for r in resolution)
    if len(spacing) != 3 or not all(np.isfinite(r) and r > 0 for r in spacing):
        raise ValueError(f"resolution must be three positive spacings (x, y, z), got {tuple(resolution)}")
    return spacing


def _transfer_points(cmap, clim, opacity, n_colors: int, flip_scalars: bool, log_scale: bool) -> tuple:
    """The colour map and the (values, RGBA colours, opacities) of the transfer functions, as pyvista builds them."""
    import pyvista
    from pyvista.plotting.colors import get_cmap_safe

    low, high = float(clim[0]), float(clim[1])
    if not (high > low and np.isfinite(low) and np.isfinite(high)):
        raise ValueError(f"clim must be finite (low, high) with high > low, got {tuple(clim)}")
    if isinstance(cmap, pyvista.LookupTable):
        raise TypeError("cmap=pyvista.LookupTable is not taken: give its colour map as cmap (a name, a list of "
                        "colours or a matplotlib colormap), its range as clim and its opacity as opacity")
    if isinstance(n_colors, bool) or not isinstance(n_colors, numbers.Integral) or n_colors < 2:
        raise ValueError(f"n_colors must be an integer of at least 2, got {n_colors!r}")
    if log_scale and not low > 0:
        raise ValueError(f"log_scale needs clim above 0, got ({low:g}, {high:g}): give clim=(a positive low, high)")
    colormap = get_cmap_safe(cmap)
    if flip_scalars:
        colormap = colormap.reversed()
    colours = colormap(np.linspace(0.0, 1.0, n_colors))
    values = np.geomspace(low, high, n_colors) if log_scale else np.linspace(low, high, n_colors)
    return colormap, values, colours, _opacities(opacity, n_colors)


def _opacities(opacity, n_colors: int) -> np.ndarray:
    """pyvista's opacity mapping (a number, a transfer function name, or values to interpolate) at ``n_colors`` points."""
    import pyvista

    if isinstance(opacity, str):
        return np.asarray(pyvista.opacity_transfer_function(opacity, n_colors), dtype=float) / 255.0
    values = np.asarray(opacity, dtype=float)
    if values.ndim > 1 or values.size == 0 or not np.all((values >= 0.0) & (values <= 1.0)):
        raise ValueError(f"opacity must be within [0, 1]: a number or a sequence of them, got {opacity!r}")
    if values.ndim == 0:
        return np.full(n_colors, float(values))
    if values.size == n_colors:
        return values
    if values.size == 1:
        return np.full(n_colors, float(values[0]))
    mapped = pyvista.opacity_transfer_function(values, n_colors, interpolate=True, kind="quadratic")
    return np.clip(np.asarray(mapped, dtype=float) / 255.0, 0.0, 1.0)


def _volume_property(values, colours, alphas):
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

    colour_tf, opacity_tf = vtkColorTransferFunction(), vtkPiecewiseFunction()
    for value, rgba, alpha in zip(values, colours, alphas):
        colour_tf.AddRGBPoint(float(value), *rgba[:3])
        opacity_tf.AddPoint(float(value), float(alpha))
    prop = vtkVolumeProperty()
    prop.SetColor(colour_tf)
    prop.SetScalarOpacity(opacity_tf)
    prop.SetInterpolationTypeToLinear()
    return prop


# Registers grid.mip and plotter.mip (imports pyvista); after the functions it delegates to.
from mipcast.filters.extensions import MipAccessor, MipPlotterComponent  # noqa: E402

__all__ = ["render", "add_volume", "plot", "with_scalars", "set_parameters", "method_parameters",
           "MipAccessor", "MipPlotterComponent"]
