"""Draw a volume larger than one 3D texture in bricks, exactly, for cell-walking methods.

Analytic MIP walks every cell a ray crosses inside one 3D texture.  A volume
beyond the GPU's 3D texture limit is split into bricks of at most ``limit``
points per axis that **share one layer of points** with their neighbours
(:func:`brick_ranges`), so every cell of the volume lies in exactly one brick,
whole.  Each brick is drawn by its own mapper (the method's factory) on its own
``vtkVolume`` placed in world space (origin moved along the direction matrix,
same spacing and direction), and the bricks' per-pixel float readouts are
combined by MAX: the maximum of the interpolant over a ray is the maximum of
its maxima over the disjoint sets of cells, so the combination is exact, not
an approximation.  (VTK's own drawing of several volumes in one renderer
blends their colours, which is not a maximum; so the bricks are composed here,
from the float readouts, and coloured through the volume property's transfer
functions on the CPU, premultiplied by opacity over the background, as
``shaders/mip_color.glsl`` does on the GPU.)

Cost: one render per brick per frame (measured in docs/reliability.md,
section "GPU limits and memory").  Used by :class:`mipcast.offscreen.OffscreenView`
when its cell-walking mapper refuses the volume for the texture limit.
"""
from __future__ import annotations

from typing import List, Sequence, Tuple

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkVolume

from mipcast.mappers.float_readout import render_float


def brick_ranges(points: int, limit: int) -> List[Tuple[int, int]]:
    """Split ``points`` along one axis into inclusive ranges of <= ``limit`` points sharing an end point.

    Consecutive ranges share one point (``(a, b), (b, c)``), so every cell
    ``[i, i + 1]`` lies in exactly one range.  The ranges are as even as
    possible.

    Examples
    --------
    >>> brick_ranges(40, 16)
    [(0, 13), (13, 26), (26, 39)]
    >>> brick_ranges(10, 16)
    [(0, 9)]
    """
    if limit < 2:
        raise ValueError(f"a brick needs at least 2 points per axis, the limit is {limit}")
    cells = points - 1
    count = max(1, -(-cells // (limit - 1)))
    edges = [round(i * cells / count) for i in range(count + 1)]
    return [(edges[i], edges[i + 1]) for i in range(count)]


def brick_extents(dims: Sequence[int], limit: int) -> List[Tuple[int, int, int, int, int, int]]:
    """Inclusive point-index extents ``(x0, x1, y0, y1, z0, z1)`` of the bricks of a ``dims`` volume.

    Examples
    --------
    >>> len(brick_extents((40, 40, 40), 16)), brick_extents((40, 10, 10), 16)[1]
    (27, (13, 26, 0, 9, 0, 9))
    """
    xs, ys, zs = (brick_ranges(int(n), int(limit)) for n in dims)
    return [(x0, x1, y0, y1, z0, z1) for (z0, z1) in zs for (y0, y1) in ys for (x0, x1) in xs]


def extract_brick(image: vtkImageData, extent: Sequence[int]) -> vtkImageData:
    """A copy of ``image``'s points in ``extent`` as its own image, placed where they were in world space.

    The copy's extent starts at 0; its origin is the original origin moved by
    the direction matrix times ``(x0, y0, z0) * spacing``; spacing, direction
    and the scalars' type and name are kept.  ``image`` is not modified.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=8)
    >>> brick = extract_brick(image, (4, 7, 0, 7, 0, 7))
    >>> brick.GetDimensions(), brick.GetBounds()[:2] == image.GetBounds()[:2]
    ((4, 8, 8), False)
    """
    x0, x1, y0, y1, z0, z1 = (int(v) for v in extent)
    dims = image.GetDimensions()
    first = image.GetExtent()[::2]
    scalars = image.GetPointData().GetScalars()
    values = vtk_to_numpy(scalars).reshape(dims[2], dims[1], dims[0])
    block = np.ascontiguousarray(values[z0:z1 + 1, y0:y1 + 1, x0:x1 + 1])
    brick = vtkImageData()
    brick.SetDimensions(x1 - x0 + 1, y1 - y0 + 1, z1 - z0 + 1)
    brick.SetSpacing(image.GetSpacing())
    direction = np.array([image.GetDirectionMatrix().GetElement(r, c) for r in range(3) for c in range(3)]).reshape(3, 3)
    offset = (np.array([x0, y0, z0]) + np.array(first)) * np.array(image.GetSpacing())
    brick.SetOrigin(*(np.array(image.GetOrigin()) + direction @ offset))
    brick.SetDirectionMatrix(image.GetDirectionMatrix())
    array = numpy_to_vtk(block.ravel(), deep=True, array_type=scalars.GetDataType())
    array.SetName(scalars.GetName() or "scalars")
    brick.GetPointData().SetScalars(array)
    return brick


class BrickedVolume:
    """One volume drawn as bricks of at most ``limit`` points per axis, composed by MAX.

    Parameters
    ----------
    image : vtkImageData
        The whole volume (not modified).
    renderer : vtkRenderer
        The renderer whose camera draws the bricks; brick volumes are added
        to it (hidden between readouts).
    volume_property : vtkVolumeProperty
        Shared by every brick (colour, opacity, interpolation).
    factory : callable
        Makes one brick's mapper (a cell-walking mipcast method's factory,
        e.g. :class:`mipcast.mappers.analytic.AnalyticMIPVolumeMapper`).
    limit : int
        Points per axis a brick may have (the GPU's 3D texture limit).
    settings : sequence of (setter name, value), optional
        Applied to every brick's mapper (e.g. ``(("SetSkipping", False),)``).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkRenderer
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
    >>> from mipcast.offscreen import grey_property
    >>> bricks = BrickedVolume(make_fixture("spheres", size=20), vtkRenderer(), grey_property((0, 1)),
    ...                        AnalyticMIPVolumeMapper, limit=12)
    >>> len(bricks.volumes)
    8
    """

    def __init__(self, image, renderer, volume_property, factory, limit: int, settings=()) -> None:
        self.image = image
        self.renderer = renderer
        self.volume_property = volume_property
        self.limit = int(limit)
        #: (mapper, vtkVolume) per brick.
        self.mappers: list = []
        self.volumes: list = []
        for extent in brick_extents(image.GetDimensions(), self.limit):
            mapper = factory()
            mapper.SetInputData(extract_brick(image, extent))
            for setter, value in settings:
                getattr(mapper, setter)(value)
            volume = vtkVolume()
            volume.SetProperty(volume_property)
            mapper.Attach(volume)
            volume.VisibilityOff()
            renderer.AddVolume(volume)
            self.mappers.append(mapper)
            self.volumes.append(volume)

    def for_each_mapper(self, setter: str, *values) -> None:
        """Call ``setter(*values)`` on every brick's mapper (sample distance, parameters...)."""
        for mapper in self.mappers:
            getattr(mapper, setter)(*values)

    def float_image(self, render_window) -> np.ndarray:
        """Each pixel's maximum in data units over all bricks (float32, NaN where no brick was hit).

        One float readout per brick (only that brick visible), combined by
        ``fmax``: exact, since the bricks' cells are disjoint and cover the
        volume.
        """
        result = None
        for volume, mapper in zip(self.volumes, self.mappers):
            volume.VisibilityOn()
            try:
                values = render_float(render_window, mapper)
            finally:
                volume.VisibilityOff()
            result = values if result is None else np.fmax(result, values)
        return result

    def colour(self, values: np.ndarray) -> np.ndarray:
        """Data values -> 8-bit RGB through the volume property, premultiplied by opacity, over the background.

        What ``shaders/mip_color.glsl`` writes, blended over the renderer's
        background; NaN (missed) pixels show the background.
        """
        colour = self.volume_property.GetRGBTransferFunction(0)
        opacity = self.volume_property.GetScalarOpacity(0)
        flat = np.asarray(values, dtype=np.float64).ravel()
        hit = ~np.isnan(flat)
        rgb = np.zeros((flat.size, 3))
        alpha = np.zeros(flat.size)
        for index in np.flatnonzero(hit):
            rgb[index] = colour.GetColor(flat[index])
            alpha[index] = opacity.GetValue(flat[index])
        background = np.array(self.renderer.GetBackground())
        out = rgb * alpha[:, None] + background[None, :] * (1.0 - alpha[:, None])
        return np.clip(np.rint(out * 255.0), 0, 255).astype(np.uint8).reshape(values.shape + (3,))

    def screenshot(self, render_window) -> np.ndarray:
        """The composed picture, 8-bit RGB (height, width, 3), top row first."""
        return self.colour(self.float_image(render_window))

    def remove(self) -> None:
        """Take the bricks' volumes out of the renderer."""
        for volume in self.volumes:
            self.renderer.RemoveVolume(volume)
