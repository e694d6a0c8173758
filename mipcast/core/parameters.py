"""Method parameters by name: ``depth_weight=0.3`` -> ``mapper.SetDepthWeight(0.3)``.

One naming rule for every front end: the pyvista filters' keyword
arguments, the command line's ``--depth-weight 0.3``, the interactive
viewer and ParaView's render view all go through :func:`set_parameters`,
which checks every name against the mapper's setters before it sets any.
Needs nothing but the standard library, so it also runs inside ParaView's
Python (which has no pyvista).
"""
from __future__ import annotations

import inspect
import re
from typing import Any, Dict, Sequence, Tuple


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
    >>> from mipcast.core.parameters import set_parameters
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
        unpack = isinstance(value, (tuple, list)) and not _takes_one_value(setters[name])
        try:
            setters[name](*(tuple(value) if unpack else (value,)))
        except (TypeError, AttributeError) as error:  # AttributeError: e.g. text where an object is wanted
            raise TypeError(f"{name}={value!r} ({setter_name(name)}): {error}") from None


def _takes_one_value(setter) -> bool:
    """A Python setter with a single parameter (``SetRegionOfInterest(region)``) gets a sequence whole.

    VTK's wrapped C++ setters have no Python signature; they get it unpacked.
    """
    try:
        parameters = inspect.signature(setter).parameters.values()
    except (TypeError, ValueError):
        return False
    kinds = [p.kind for p in parameters]
    return kinds == [inspect.Parameter.POSITIONAL_OR_KEYWORD]


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
        :func:`mipcast.filters.render`, :func:`mipcast.filters.add_volume` and the command line.

    Examples
    --------
    >>> import mipcast
    >>> from mipcast.core.parameters import method_parameters
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
    """The setter of a snake_case parameter name.

    Examples
    --------
    >>> setter_name("depth_weight")
    'SetDepthWeight'
    """
    return "Set" + "".join(part[:1].upper() + part[1:] for part in name.split("_"))


def snake_name(camel: str) -> str:
    """The snake_case parameter name of a CamelCase setter suffix.

    Examples
    --------
    >>> snake_name("DepthWeight")
    'depth_weight'
    """
    return re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", camel).lower()


def parse_options(tokens: Sequence[str]) -> Dict[str, Any]:
    """Method parameters from command-line tokens: ``--depth-weight 0.3`` -> ``{"depth_weight": 0.3}``.

    Each ``--name`` (or ``--name=value``) starts a parameter; a
    ``--mapper-`` prefix is dropped (``--mapper-method analytic`` reaches
    ``SetMethod`` where the command has a ``--method`` of its own).  The
    tokens up to the next ``--name`` are its values: numbers become int or float,
    ``on/off``, ``true/false``, ``yes/no`` become booleans, anything else
    stays text.  One value is passed as it is, several as a list (unpacked
    into the setter), none as ``True``.

    Raises
    ------
    ValueError
        If a value comes before any ``--name``, a name is given twice, or
        ``--name=`` has nothing after the ``=``.

    Examples
    --------
    >>> parse_options(["--depth-weight", "0.3", "--gaze-point", "0.2", "-0.1", "--foveation", "off"])
    {'depth_weight': 0.3, 'gaze_point': [0.2, -0.1], 'foveation': False}
    >>> parse_options(["--depth-mode=window", "--number-of-levels", "4", "--mapper-method", "analytic"])
    {'depth_mode': 'window', 'number_of_levels': 4, 'method': 'analytic'}
    """
    options: Dict[str, list] = {}
    name = None
    for token in tokens:
        if token.startswith("--") and len(token) > 2 and not _is_number(token):
            option, equals, value = token[2:].partition("=")
            if equals and not value:
                raise ValueError(f"--{option}= has no value (e.g. --{option}=0.3, or --{option} 0.3)")
            name = option.replace("-", "_")
            name = name[len(MAPPER_PREFIX):] if name.startswith(MAPPER_PREFIX) else name
            if name in options:
                raise ValueError(f"--{option} is given twice")
            options[name] = [value] if equals else []
        elif name is None:
            raise ValueError(f"{token!r} is not a --name of a method parameter (e.g. --depth-weight 0.3)")
        else:
            options[name].append(token)
    return {key: _option_value(values) for key, values in options.items()}


#: Prefix that marks an option as the mapper's even where the command has one of that name.
MAPPER_PREFIX = "mapper_"
_BOOLEANS = {"on": True, "true": True, "yes": True, "off": False, "false": False, "no": False}


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _option_value(values: list) -> Any:
    converted = [_convert(text) for text in values]
    if not converted:
        return True
    return converted[0] if len(converted) == 1 else converted


def _convert(text: str) -> Any:
    if text.lower() in _BOOLEANS:
        return _BOOLEANS[text.lower()]
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text
