"""Where a volume property's MIP colour stops changing: below a floor, above a ceiling.

A MIP pixel's colour is the transfer functions applied to the ray maximum.
If colour and opacity are constant for all scalars up to a *floor*, every
maximum below the floor gives the same pixel, so a method may stop caring
about values below it; likewise above a *ceiling*.

See docs/methods.md, section Transfer-function floor and ceiling
(``docs/methods.md#transfer-function-floor-and-ceiling``).
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np


_ENDS: dict = {}


def constant_ends(prop, low: float, high: float) -> Tuple[float, float]:
    """The (floor, ceiling) of component 0's transfer functions over [low, high].

    Cached on the property's identity and modification time (which
    includes its transfer functions') and the range, so render hooks may
    ask every frame.

    Parameters
    ----------
    prop : vtkVolumeProperty
        Colour (RGB or grey) and scalar opacity of component 0.
    low, high : float
        The data range.

    Returns
    -------
    tuple of float
        Premultiplied colour and opacity are constant on ``[low, floor]`` and
        on ``[ceiling, high]``; ``floor == low`` / ``ceiling == high`` when
        they change right away.

    Examples
    --------
    >>> from mipcast.offscreen import grey_property
    >>> constant_ends(grey_property((100.0, 400.0)), 0.0, 1000.0)
    (100.0, 400.0)
    """
    key = (prop.GetAddressAsString("vtkObjectBase"), prop.GetMTime(), float(low), float(high))
    if key not in _ENDS:
        if len(_ENDS) > 256:
            _ENDS.clear()
        _ENDS[key] = _constant_ends(prop, float(low), float(high))
    return _ENDS[key]


def _constant_ends(prop, low: float, high: float) -> Tuple[float, float]:
    stops = sorted({float(low), float(high)} | {x for x in _node_positions(prop) if low < x < high})
    values = np.array([_premultiplied(prop, x) for x in stops])
    same_as_low = np.all(np.abs(values - values[0]) <= 1e-7, axis=1)
    same_as_high = np.all(np.abs(values - values[-1]) <= 1e-7, axis=1)
    floor = stops[int(np.argmin(same_as_low)) - 1] if not same_as_low.all() else float(high)
    ceiling = stops[len(stops) - int(np.argmin(same_as_high[::-1]))] if not same_as_high.all() else float(low)
    return floor, ceiling


def normalised_ends(prop, scalars) -> Optional[Tuple[float, float]]:
    """:func:`constant_ends` over the scalars' range, as fractions of it; None for a constant range.

    The scalars' range is VTK's (kept until they change) and
    :func:`constant_ends` is cached, so render hooks may ask every frame.

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkFloatArray
    >>> from mipcast.offscreen import grey_property
    >>> scalars = vtkFloatArray()
    >>> _ = scalars.InsertNextValue(0.0), scalars.InsertNextValue(1000.0)
    >>> normalised_ends(grey_property((100.0, 400.0)), scalars)
    (0.1, 0.4)
    """
    low, high = scalars.GetRange(0)
    if not high > low:
        return None
    return tuple((v - low) / (high - low) for v in constant_ends(prop, low, high))


def _node_positions(prop):
    opacity = prop.GetScalarOpacity(0)
    colour = prop.GetRGBTransferFunction(0) if prop.GetColorChannels(0) == 3 else prop.GetGrayTransferFunction(0)
    for function, width in ((opacity, 4), (colour, 6 if prop.GetColorChannels(0) == 3 else 4)):
        node = [0.0] * width
        for index in range(function.GetSize()):
            function.GetNodeValue(index, node)
            yield node[0]


def _premultiplied(prop, x: float) -> np.ndarray:
    alpha = prop.GetScalarOpacity(0).GetValue(x)
    if prop.GetColorChannels(0) == 3:
        rgb = [0.0, 0.0, 0.0]
        # the two-argument form: subclasses (vtkDiscretizableColorTransferFunction,
        # ParaView's colour maps) override it, which hides the one-argument form
        prop.GetRGBTransferFunction(0).GetColor(x, rgb)
        rgb = np.array(rgb)
    else:
        rgb = np.full(3, prop.GetGrayTransferFunction(0).GetValue(x))
    return np.append(rgb * alpha, alpha)
