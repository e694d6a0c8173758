"""Method parameters as keyword arguments: ``depth_weight=0.2`` -> ``mapper.SetDepthWeight(0.2)``.

Shared by every entry point that takes method settings as keyword
arguments (:mod:`mipcast.filters`, the viewer, ParaView's render view).
Needs nothing but the standard library, so it also runs inside ParaView's
Python (which has no pyvista).
"""
from __future__ import annotations

import re
from typing import Tuple


def set_parameters(mapper, **params) -> None:
    """Set method parameters on a mapper through its VTK-style setters.

    ``name=value`` calls ``mapper.SetName(value)``, the name converted from
    snake_case to CamelCase (``depth_weight`` -> ``SetDepthWeight``); a
    tuple or list is unpacked (``gaze_point=(0.5, 0.5)`` ->
    ``SetGazePoint(0.5, 0.5)``).  Every setter of the mapper is reachable,
    the method's own (:func:`method_parameters`) and VTK's
    (``image_sample_distance``, ``use_jittering``, ...).  All names are
    checked before any is set.

    Parameters
    ----------
    mapper : vtkVolumeMapper
        A mapper made by :func:`mipcast.create_mapper` (any VTK mapper works).
    **params
        ``name=value`` pairs.

    Raises
    ------
    TypeError
        If a name has no setter on the mapper (the message names it and lists
        the method's own parameters), or a setter refuses its value.

    Examples
    --------
    >>> import mipcast
    >>> from mipcast.parameters import set_parameters
    >>> mapper = mipcast.create_mapper("mip")
    >>> set_parameters(mapper, image_sample_distance=2.0, use_jittering=True)
    >>> mapper.GetImageSampleDistance(), mapper.GetUseJittering()
    (2.0, 1)
    >>> set_parameters(mapper, no_such_weight=0.2)
    Traceback (most recent call last):
    ...
    TypeError: MIPVolumeMapper has no parameter 'no_such_weight' (no SetNoSuchWeight): ...
    """
    setters = {}
    for name, value in params.items():
        setter = getattr(mapper, setter_name(name), None)
        if not callable(setter):
            own = ", ".join(method_parameters(mapper)) or "none"
            raise TypeError(
                f"{type(mapper).__name__} has no parameter {name!r} (no {setter_name(name)}): "
                f"its method parameters are: {own}; VTK's mapper setters work too, e.g. "
                "image_sample_distance=2.0 (SetImageSampleDistance) or use_jittering=True")
        setters[name] = setter
    for name, value in params.items():
        arguments = tuple(value) if isinstance(value, (tuple, list)) else (value,)
        try:
            setters[name](*arguments)
        except TypeError as error:
            raise TypeError(f"{name}={value!r} ({setter_name(name)}): {error}") from None


def method_parameters(mapper) -> Tuple[str, ...]:
    """Names of the parameters a method adds to VTK's mapper, in snake_case.

    These are the ``Set*`` methods that mipcast's (Python) mapper classes
    define and VTK's base mapper does not have; VTK's own setters are not
    listed.  Stock VTK MIP has none.

    Parameters
    ----------
    mapper : vtkVolumeMapper
        Any volume mapper, e.g. from :func:`mipcast.create_mapper`.

    Returns
    -------
    tuple of str
        Sorted names, usable as keyword arguments of :func:`set_parameters`,
        :func:`render` and :func:`add_volume`.

    Examples
    --------
    >>> import mipcast
    >>> from mipcast.parameters import method_parameters
    >>> method_parameters(mipcast.create_mapper("stock"))
    ()
    """
    vtk_base = next(c for c in type(mapper).__mro__ if c.__module__.startswith("vtkmodules"))
    names = set()
    for cls in type(mapper).__mro__:
        if cls.__module__.startswith("vtkmodules") or cls is object:
            continue
        for attribute, value in vars(cls).items():
            if (attribute.startswith("Set") and len(attribute) > 3 and callable(value)
                    and not hasattr(vtk_base, attribute)):
                names.add(snake_name(attribute[3:]))
    return tuple(sorted(names))


def setter_name(name: str) -> str:
    """``depth_weight`` -> ``SetDepthWeight``.

    Examples
    --------
    >>> setter_name("depth_weight")
    'SetDepthWeight'
    """
    return "Set" + "".join(part[:1].upper() + part[1:] for part in name.split("_"))


def snake_name(camel: str) -> str:
    """``DepthWeight`` -> ``depth_weight``.

    Examples
    --------
    >>> snake_name("DepthWeight")
    'depth_weight'
    """
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", camel).lower()
