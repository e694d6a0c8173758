"""mipcast's pyvista extensions: ``grid.mip`` and ``plotter.mip``.

Registered with pyvista's extension API (0.48+) when :mod:`mipcast.filters`
is imported:

- :class:`MipAccessor` via ``pyvista.register_dataset_accessor("mip",
  pyvista.ImageData)`` (and ``RectilinearGrid``, evenly spaced ones drawn as
  image data, and ``MultiBlock``, holding one volume or image pieces of one
  grid: :func:`mipcast.io.composite.one_image`): ``grid.mip.render(...)``, ``grid.mip.plot(...)``;
- :class:`MipPlotterComponent` via ``pyvista.register_plotter_component("mip")``:
  ``plotter.mip.add_volume(...)``; pyvista calls its ``__plotter_close__``
  when the plotter closes, which removes the volumes it added.

Both delegate to the functions of :mod:`mipcast.filters`; nothing else
happens here.
"""
from __future__ import annotations

import weakref
from typing import Optional, Sequence

import numpy as np
import pyvista

from mipcast.filters import add_volume, plot, render
from mipcast.methods import detach


@pyvista.register_dataset_accessor("mip", pyvista.MultiBlock)  # holding one volume (mipcast.io.composite)
@pyvista.register_dataset_accessor("mip", pyvista.RectilinearGrid)  # evenly spaced: drawn as image data
@pyvista.register_dataset_accessor("mip", pyvista.ImageData)
class MipAccessor:
    """Render an ``ImageData`` with a mipcast method: ``grid.mip.render(...)``.

    Parameters
    ----------
    grid : pyvista.ImageData
        The volume (one-component point scalars); pyvista passes it.

    Examples
    --------
    >>> import pyvista as pv
    >>> import mipcast.filters
    >>> grid = pv.ImageData(dimensions=(8, 8, 8))
    >>> grid.point_data["values"] = np.arange(grid.n_points, dtype=float)
    >>> grid.mip.render("analytic", size=(24, 16)).shape
    (16, 24, 3)
    """

    def __init__(self, grid) -> None:
        self._grid = grid

    def render(self, method: str = "mip", *, scalars=None, size: Sequence[int] = (256, 256),
               view: str = "oblique", sample_distance: Optional[float] = None,
               window: Optional[Sequence[float]] = None, as_float: bool = False, **params) -> np.ndarray:
        """Render the grid offscreen with ``method``; see :func:`mipcast.filters.render`.

        Parameters
        ----------
        method : str, default: "mip"
            A name from ``mipcast.METHODS``.
        scalars : str or array_like, optional
            Name of the point (or cell) array to project, or its values, as
            in pyvista's ``add_volume``; default the active scalars.
        size : sequence of int, default: (256, 256)
            Image (width, height) in pixels.
        view : str, default: "oblique"
            A camera preset of ``mipcast.offscreen.VIEWS`` or a patient view
            (``"anterior"``, ``"superior"``, ...).
        sample_distance : float, optional
            World units between samples; default one sample per voxel.
        window : sequence of float or str, optional
            Grey window (low, high) in data units; default the window a
            viewer would pick (``"auto"``); ``"full"`` the data range.
            ``clim=`` (pyvista's name, as in ``add_volume``) works too.
        as_float : bool, default: False
            Return each pixel's maximum in data units (float32, NaN where a
            ray misses) instead of the 8-bit RGB picture.
        **params
            Method parameters, e.g. ``depth_weight=0.2`` (see
            :func:`mipcast.filters.set_parameters`).

        Returns
        -------
        numpy.ndarray
            (height, width, 3) uint8, or (height, width) float32, top row first.

        Examples
        --------
        >>> import pyvista as pv
        >>> import mipcast.filters
        >>> from mipcast.data_fixtures import make_fixture
        >>> grid = pv.wrap(make_fixture("vessels", size=24))
        >>> values = grid.mip.render("mip", size=(32, 32), as_float=True)
        >>> values.shape, values.dtype
        ((32, 32), dtype('float32'))
        """
        return render(self._grid, method, scalars=scalars, size=size, view=view, sample_distance=sample_distance,
                      window=window, as_float=as_float, **params)

    def plot(self, method: str = "mip", *, off_screen: Optional[bool] = None,
             window_size: Optional[Sequence[int]] = None, screenshot=None, **kwargs):
        """Show the grid in a new plotter with ``method``; see :func:`mipcast.filters.plot`.

        Examples
        --------
        >>> import pyvista as pv
        >>> import mipcast.filters
        >>> from mipcast.data_fixtures import make_fixture
        >>> grid = pv.wrap(make_fixture("vessels", size=24))
        >>> image = grid.mip.plot("demip", off_screen=True, window_size=(48, 48), screenshot=True,
        ...                       depth_weight=0.5)
        >>> image.shape
        (48, 48, 3)
        """
        return plot(self._grid, method, off_screen=off_screen, window_size=window_size,
                    screenshot=screenshot, **kwargs)


@pyvista.register_plotter_component("mip")
class MipPlotterComponent:
    """Add volumes rendered by mipcast methods to a plotter: ``plotter.mip.add_volume(...)``.

    The component keeps the volumes it added; when the plotter closes it
    detaches their shader pieces and removes them from their renderers.  A
    volume pyvista takes away (``remove_actor``, or another added under its
    name) is detached too: to show one again, add it with ``add_volume``.

    Parameters
    ----------
    plotter : pyvista.Plotter
        The owning plotter; pyvista passes it (held weakly).

    Examples
    --------
    >>> import pyvista as pv
    >>> import mipcast.filters
    >>> from mipcast.data_fixtures import make_fixture
    >>> plotter = pv.Plotter(off_screen=True, window_size=(48, 48))
    >>> volume = plotter.mip.add_volume(pv.wrap(make_fixture("spheres", size=16)), "analytic")
    >>> plotter.mip.volumes == (volume,)
    True
    >>> plotter.close()
    >>> plotter.mip.volumes
    ()
    """

    def __init__(self, plotter) -> None:
        self._plotter = weakref.proxy(plotter)
        self._added = []  # (vtkVolume, vtkRenderer) in the order they were added

    @property
    def volumes(self) -> tuple:
        """The volumes this component added that are still shown, oldest first."""
        self._forget_removed()
        return tuple(volume for volume, _ in self._added)

    def _forget_removed(self) -> None:
        """Detach and forget volumes pyvista took away (``remove_actor``, or replaced by name)."""
        shown = [(volume, renderer) for volume, renderer in self._added if renderer.GetVolumes().IsItemPresent(volume)]
        for volume, renderer in self._added:
            if (volume, renderer) not in shown:
                _remove(volume, renderer)
        self._added = shown

    def add_volume(self, grid, method: str = "mip", **kwargs):
        """Add ``grid`` to the plotter's active renderer; see :func:`mipcast.filters.add_volume`.

        Parameters
        ----------
        grid : pyvista.ImageData or numpy.ndarray
            Volume with point scalars (or a 3-D array indexed ``[x, y, z]``, a
            4-D one ``[x, y, z, component]``).
        method : str, default: "mip"
            A name from ``mipcast.METHODS``.
        **kwargs
            The keywords of :func:`mipcast.filters.add_volume`: pyvista's
            (``scalars``, ``cmap``, ``clim``, ``opacity``, ``n_colors``,
            ``flip_scalars``, ``log_scale``, ``name``, ``reset_camera``,
            ``user_matrix``, ``show_scalar_bar``, ...), ``sample_distance``,
            ``component`` and method parameters, e.g. ``depth_weight=0.2``
            (see :func:`mipcast.filters.set_parameters`).

        Returns
        -------
        pyvista.Volume
            The added volume; its mapper is ``volume.mapper``.

        Examples
        --------
        >>> import pyvista as pv
        >>> import mipcast.filters
        >>> from mipcast.data_fixtures import make_fixture
        >>> plotter = pv.Plotter(off_screen=True, window_size=(64, 48))
        >>> volume = plotter.mip.add_volume(pv.wrap(make_fixture("vessels", size=24)),
        ...                                 "mip", cmap="bone", clim=(0.1, 0.9))
        >>> type(volume.GetMapper()).__name__
        'MIPVolumeMapper'
        >>> plotter.screenshot().shape
        (48, 64, 3)
        >>> plotter.close()
        """
        renderer = self._plotter.renderer
        volume = add_volume(self._plotter, grid, method, **kwargs)
        self._added.append((volume, renderer))
        self._forget_removed()
        return volume

    def remove_volume(self, volume) -> None:
        """Remove a volume this component added: detach its mapper, take it off its renderer.

        Parameters
        ----------
        volume : vtkVolume
            A volume returned by :meth:`add_volume`.

        Raises
        ------
        ValueError
            If the volume was not added by this component (or was removed).

        Examples
        --------
        >>> import pyvista as pv
        >>> import mipcast.filters
        >>> from mipcast.data_fixtures import make_fixture
        >>> plotter = pv.Plotter(off_screen=True, window_size=(32, 32))
        >>> volume = plotter.mip.add_volume(pv.wrap(make_fixture("spheres", size=16)))
        >>> plotter.mip.remove_volume(volume)
        >>> plotter.renderer.GetVolumes().GetNumberOfItems(), volume.GetMapper().IsAttached()
        (0, False)
        >>> plotter.close()
        """
        for index, (added, renderer) in enumerate(self._added):
            if added is volume:
                del self._added[index]
                _remove(added, renderer)
                return
        raise ValueError("this volume was not added by plotter.mip.add_volume (or was removed already)")

    def set_stereo(self, mode: Optional[str] = "anaglyph", *, eye_angle: Optional[float] = None) -> None:
        """Show the plotter as a stereo pair: ``"anaglyph"`` (red-cyan), ``"side-by-side"``, or None (mono).

        Every mipcast method renders both eyes (see :mod:`mipcast.mappers.stereo`);
        ``eye_angle`` (degrees, default VTK's 2) is set on the active camera.

        Examples
        --------
        >>> import pyvista as pv
        >>> import mipcast.filters
        >>> from mipcast.data_fixtures import make_fixture
        >>> plotter = pv.Plotter(off_screen=True, window_size=(48, 32))
        >>> volume = plotter.mip.add_volume(pv.wrap(make_fixture("frontback", size=16)))
        >>> plotter.mip.set_stereo("side-by-side", eye_angle=6.0)
        >>> plotter.render_window.GetStereoTypeAsString(), plotter.screenshot().shape
        ('SplitViewportHorizontal', (32, 48, 3))
        >>> plotter.mip.set_stereo(None); bool(plotter.render_window.GetStereoRender())
        False
        >>> plotter.close()
        """
        from mipcast.mappers.stereo import set_stereo

        set_stereo(self._plotter.render_window, mode, eye_angle, self._plotter.camera if eye_angle else None)

    def enable_progressive(self, interval_ms: int = 40) -> None:
        """Let a timer render the refining frames of progressive foveated volumes (``SetProgressive``).

        Each tick renders once if a volume this component added needs
        refinement (:mod:`mipcast.mappers.refinement`); nothing busy-waits.

        Examples
        --------
        >>> import pyvista as pv
        >>> import mipcast.filters
        >>> from mipcast.data_fixtures import make_fixture
        >>> plotter = pv.Plotter(off_screen=True, window_size=(32, 32))
        >>> volume = plotter.mip.add_volume(pv.wrap(make_fixture("vessels", size=16)), "foveated", progressive=True)
        >>> plotter.mip.enable_progressive()
        >>> plotter.close()
        """
        from mipcast.mappers.refinement import drive_refinement

        if self._plotter.iren is None:
            return  # no interactor (off-screen without one): render the frames yourself
        self._refinement = drive_refinement(self._plotter.iren.interactor,
                                            lambda: [volume.GetMapper() for volume in self.volumes], interval_ms)

    def __plotter_close__(self) -> None:
        """Remove every volume this component added (pyvista calls it on ``close``)."""
        while self._added:
            _remove(*self._added.pop())


def _remove(volume, renderer) -> None:
    detach(volume.GetMapper())
    renderer.RemoveVolume(volume)
