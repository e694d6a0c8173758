"""Read a mipcast mapper's per-pixel result as float32, above the 8-bit floor.

See docs/methods.md, section Float readout (``docs/methods.md#float-readout``).
"""
from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.object_state import object_state

#: Normalised hits are written shifted by this much (see shaders/float_readout.glsl).
_SHIFT = -2.0

#: VTK's normalised scalar for 8- and 16-bit integer textures is (k * value - low) / (high - low): the texel
#: holds value / 255 (uint8), / 127 (int8), / 65535 (uint16) or / 32767 (int16), VTK's scale assumes 256,
#: 128, 65536, 32768 (16-bit: until 2026-12-05 taken as 1, a CT's 3071 HU read back as 3071.09).
_GL_UNIT = {"unsigned char": 256.0, "char": 128.0, "signed char": 128.0, "unsigned short": 65536.0, "short": 32768.0}
_TEXTURE_SCALE = {name: unit / (unit - 1.0) for name, unit in _GL_UNIT.items()}


def texture_scale(scalars) -> float:
    """The factor VTK's normalisation puts on values of this scalar type (1 except 8- and 16-bit integers).

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkUnsignedCharArray, vtkFloatArray, vtkShortArray
    >>> [round(texture_scale(array), 7) for array in (vtkUnsignedCharArray(), vtkShortArray(), vtkFloatArray())]
    [1.0039216, 1.0000305, 1.0]
    """
    return _TEXTURE_SCALE.get(scalars.GetDataTypeAsString(), 1.0)


def normalised_span(scalars) -> tuple:
    """``(low, span)``: VTK's normalised scalar of ``scalars`` is ``(value * texture_scale - low) / span``.

    ``span`` is the range's width; for a constant array (a brick all air, all padding, all a mask's hidden
    points) VTK widens the range by 1e-6 of its texture unit (``vtkVolumeTexture::GetScaleAndBias``): 1e-6
    data units for floats, 256e-6 for unsigned char.  Until 2026-12-05 taken as 1: a value carried into such
    a brick (bricked LMIP's running maximum) came back 0.0625 units off, and 1.5 of the range read as 0.

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkFloatArray, vtkUnsignedCharArray
    >>> air, bytes_ = vtkFloatArray(), vtkUnsignedCharArray()
    >>> _ = air.InsertNextValue(-3.0), bytes_.InsertNextValue(7), bytes_.InsertNextValue(9)
    >>> normalised_span(air), normalised_span(bytes_)
    ((-3.0, 1e-06), (7.0, 2.0))
    >>> _ = bytes_.SetValue(1, 7), bytes_.Modified()
    >>> normalised_span(bytes_)
    (7.0, 0.000256)
    """
    low, high = scalars.GetRange(0)
    if high > low:
        return low, high - low
    return low, 1.0e-6 * _GL_UNIT.get(scalars.GetDataTypeAsString(), 1.0)


def table_coordinate(scalars) -> tuple:
    """``(scale, bias)``: VTK's normalised scalar ``s`` of ``scalars`` -> ``s * scale + bias``, where the
    value lies in VTK's transfer-function tables, ``(v - low) / (high - low)`` over the scalars' range.

    ``(1, 0)`` except for 8- and 16-bit integers, whose normalised scalar VTK computes for ``v`` times
    :func:`texture_scale` (256/255 for unsigned char): its colour and opacity lookups read the tables 0.4 %
    of the value too high for 8-bit data (stock VTK's too), up to 1 unit of 250, 3 grey under a window 30 %
    of the range wide (16-bit: 3e-5 of the value; shaders/mip_globals.glsl, ``u_mc_tableScale``).

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkUnsignedCharArray
    >>> scalars = vtkUnsignedCharArray()
    >>> _ = scalars.InsertNextValue(8), scalars.InsertNextValue(250)
    >>> scale, bias = table_coordinate(scalars)
    >>> s = (200 * 256 / 255 - 8) / (250 - 8)  # VTK's normalised scalar of 200
    >>> round(s * scale + bias, 12) == round((200 - 8) / (250 - 8), 12)
    True
    """
    low, high = scalars.GetRange(0)
    factor = texture_scale(scalars)
    if factor == 1.0 or not high > low:
        return 1.0, 0.0
    return 1.0 / factor, low * (1.0 / factor - 1.0) / (high - low)


def read_normalised(render_window, mapper) -> np.ndarray:
    """Render once and return each pixel's value as the shader wrote it: VTK's normalised scalar.

    The common step of every readout: the mapper renders into VTK's
    RenderToImage buffers with a float "depth" image that receives its
    readout piece's value (shaders/float_readout.glsl: the maximum as VTK's
    normalised scalar; DEMIP's depth readout: a depth in [0, 1]; analytic
    MIP's work counters).  The mapper's settings are restored afterwards.

    Returns
    -------
    numpy.ndarray, shape (height, width), float64
        NaN where no ray hit the volume.  Top row first.

    Examples
    --------
    >>> from mipcast.offscreen import OffscreenView
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = OffscreenView(make_fixture("spheres", size=16), "mip", size=(32, 32))
    >>> values = read_normalised(view.render_window, view.mapper)
    >>> bool(0.0 <= np.nanmin(values) and np.nanmax(values) <= 1.0)
    True
    """
    volume = mapper.GetAttachedVolume()
    if volume is None or not mapper.IsAttached():
        raise RuntimeError("render_float needs an attached mipcast mapper: call mapper.Attach(volume)")
    saved = (mapper.GetRenderToImage(), mapper.GetDepthImageScalarType())
    object_state(mapper)["exact_readout"] = True  # adds the readout piece at the render
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
        return np.full((height, width), np.nan)
    width, height, _ = image.GetDimensions()
    return decode(vtk_to_numpy(scalars).reshape(height, width)[::-1])


def decode(raw: np.ndarray) -> np.ndarray:
    """The readout image's raw values -> normalised values (float64), NaN where no ray hit.

    Examples
    --------
    >>> decode(np.array([-1.75, 1.0]))
    array([0.25,  nan])
    """
    raw = np.asarray(raw, dtype=np.float64)
    return np.where(raw > -0.5, np.nan, raw - _SHIFT)


def encode(normalised: np.ndarray) -> np.ndarray:
    """Inverse of :func:`decode` (NaN -> the miss value 1.0), for mappers that composite readouts.

    Examples
    --------
    >>> encode(np.array([0.25, np.nan]))
    array([-1.75,  1.  ])
    """
    normalised = np.asarray(normalised, dtype=np.float64)
    return np.where(np.isnan(normalised), 1.0, normalised + _SHIFT)


def to_data_units(normalised: np.ndarray, scalars) -> np.ndarray:
    """VTK's normalised scalar of ``scalars`` (a vtkDataArray) -> data units.

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkFloatArray
    >>> scalars = vtkFloatArray()
    >>> _ = scalars.InsertNextValue(10.0), scalars.InsertNextValue(30.0)
    >>> to_data_units(np.array([0.5]), scalars)
    array([20.])
    """
    low, span = normalised_span(scalars)
    return (low + np.asarray(normalised, dtype=np.float64) * span) / texture_scale(scalars)


def from_data_units(values: np.ndarray, scalars) -> np.ndarray:
    """Inverse of :func:`to_data_units`.

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkFloatArray
    >>> scalars = vtkFloatArray()
    >>> _ = scalars.InsertNextValue(10.0), scalars.InsertNextValue(30.0)
    >>> from_data_units(np.array([20.0]), scalars)
    array([0.5])
    """
    low, span = normalised_span(scalars)
    return (np.asarray(values, dtype=np.float64) * texture_scale(scalars) - low) / span


def render_float(render_window, mapper) -> np.ndarray:
    """Render once and return each pixel's ray maximum in data units.

    :func:`read_normalised`, mapped back from VTK's normalised scalar to
    data units with the input's scalar range (and, for 8-bit data, VTK's
    normalisation factor, :func:`texture_scale`).  Shortcuts that are exact
    only for the displayed colour (see :mod:`mipcast.core.transfer_bounds`) are
    off while it renders.

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
    scalars = mapper.GetRenderedInput().GetPointData().GetScalars()  # what the GPU drew
    return to_data_units(read_normalised(render_window, mapper), scalars).astype(np.float32)
