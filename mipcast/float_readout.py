"""Read a mipcast mapper's per-pixel result as float32, above the 8-bit floor."""
from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

from .object_state import object_state

#: Normalised hits are written shifted by this much (see shaders/float_readout.glsl).
_SHIFT = -2.0

#: VTK's normalised scalar for 8-bit textures is (k * value - low) / (high - low):
#: the texel holds value / 255 (uint8) or / 127 (int8), VTK's scale assumes 256 / 128.
_EIGHT_BIT_SCALE = {"unsigned char": 256.0 / 255.0, "char": 128.0 / 127.0, "signed char": 128.0 / 127.0}


def texture_scale(scalars) -> float:
    """The factor VTK's normalisation puts on values of this scalar type (1 except 8-bit).

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkUnsignedCharArray, vtkFloatArray
    >>> texture_scale(vtkUnsignedCharArray()), texture_scale(vtkFloatArray())
    (1.003921568627451, 1.0)
    """
    return _EIGHT_BIT_SCALE.get(scalars.GetDataTypeAsString(), 1.0)


def render_float(render_window, mapper) -> np.ndarray:
    """Render once and return each pixel's ray maximum in data units.

    The mapper renders into VTK's RenderToImage buffers with a float "depth"
    image that receives the raw maximum instead of a depth; the value is
    mapped back from VTK's normalised scalar to data units with the input's
    scalar range.  Shortcuts that are exact only for the displayed colour
    (see :mod:`mipcast.transfer_bounds`) are off while it renders.  The
    mapper's settings are restored afterwards.

    Parameters
    ----------
    render_window : vtkRenderWindow
        The window whose renderer holds the mapper's attached volume.
    mapper : MIPVolumeMapper
        An attached mipcast mapper.

    Returns
    -------
    numpy.ndarray, shape (height, width), float32
        Data units; NaN where no ray hit the volume. Top row first, like
        ``pyvista.Plotter.screenshot()``.

    Examples
    --------
    >>> from mipcast.offscreen import OffscreenView
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = OffscreenView(make_fixture("spheres", size=16), "mip", size=(32, 32))
    >>> render_float(view.render_window, view.mapper).shape
    (32, 32)
    """
    volume = mapper.GetAttachedVolume()
    if volume is None or not mapper.IsAttached():
        raise RuntimeError("render_float needs an attached mipcast mapper: call mapper.Attach(volume)")
    saved = (mapper.GetRenderToImage(), mapper.GetDepthImageScalarType())
    object_state(mapper)["exact_readout"] = True  # adds the float_readout piece at the render
    try:
        mapper.RenderToImageOn()
        mapper.SetDepthImageScalarTypeToFloat()
        render_window.Render()
        image = vtkImageData()
        mapper.GetDepthImage(image)
    finally:
        object_state(mapper).pop("exact_readout", None)
        mapper.SetRenderToImage(saved[0])
        mapper.SetDepthImageScalarType(saved[1])
    scalars = image.GetPointData().GetScalars()
    if scalars is None:  # nothing was drawn (volume outside the view or clipped away)
        width, height = render_window.GetSize()
        return np.full((height, width), np.nan, dtype=np.float32)
    width, height, _ = image.GetDimensions()
    raw = vtk_to_numpy(scalars).reshape(height, width)[::-1]
    scalars = mapper.GetInput().GetPointData().GetScalars()
    low, high = scalars.GetRange(0)
    normalised = raw.astype(np.float64) - _SHIFT
    values = (low + normalised * (high - low)) / texture_scale(scalars)
    values[raw > -0.5] = np.nan
    return values.astype(np.float32)
