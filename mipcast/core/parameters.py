"""Method parameters: one table per method, and the rules every front end shares.

A method's parameters are declared once, as a tuple of :class:`Parameter`
(``mipcast.core.parameter_tables``).  From that table come the mapper's
VTK-style ``SetX``/``GetX`` (:func:`parameter_accessors`), the uniforms they
drive, the float64 reference's argument checks, the command line's options
and ``--help``, the viewer's sliders and ParaView's properties.

``depth_weight=0.3`` -> ``mapper.SetDepthWeight(0.3)``: the pyvista filters'
keyword arguments, the command line's ``--depth-weight 0.3``, the viewer and
ParaView all go through :func:`set_parameters`, which checks every name
against the mapper's setters before it sets any.  Needs nothing but the
standard library and :mod:`mipcast.core.validation`, so it also runs inside
ParaView's Python (which has no pyvista).
"""
from __future__ import annotations

import inspect
import re
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from mipcast.core.validation import check_choice, check_non_negative, check_unit

#: Kinds of parameter values.
KINDS = ("float", "int", "bool", "choice", "value")


@dataclass(frozen=True)
class Uniform:
    """A shader uniform a parameter drives: ``name`` (``u_mc_*``), GLSL ``kind`` and its value.

    ``value(v, settings)`` maps the parameter's value ``v`` (and, where the
    uniform depends on them, the method's other settings and the mapper's
    derived values such as ``floor``/``ceiling``) to the uniform's value;
    the default passes ``v`` through.
    """

    name: str
    kind: str = "float"  # "float", "int" or "vec3"
    value: Callable[[Any, Mapping], Any] = field(default=lambda v, settings: v, compare=False)


@dataclass(frozen=True)
class Parameter:
    """One method parameter: its name, kind, default, valid values, unit, uniforms and doc.

    Parameters
    ----------
    name : str
        snake_case; the setter is ``Set`` + CamelCase (``depth_weight`` ->
        ``SetDepthWeight``).
    kind : str
        ``"float"`` (in ``[low, high]``), ``"int"`` (in ``[low, high]``),
        ``"bool"``, ``"choice"`` (one of ``choices``) or ``"value"`` (checked
        by ``convert``: colours, rotations, points).
    default : object
        The value a new mapper has (already in canonical form).
    doc : str
        What it does, for a user; the first sentence is the one-line summary.
    low, high : float, optional
        Range of ``"float"`` and ``"int"`` values (``None``: unbounded).
    open_low : bool, default: False
        Exclude ``low`` itself.
    choices : tuple of str or callable, default: ()
        Valid values of a ``"choice"``, or a function returning them.
    unit : str, default: ""
        Unit of the value, for help texts and property panels.
    uniforms : tuple of Uniform, default: ()
        The shader uniforms it drives (a change uploads them; nothing recompiles).
    pieces : bool, default: False
        Changing it installs other shader pieces (one compile per variant).
    convert : callable, optional
        ``"value"`` kinds: ``convert(*values) -> canonical value``, raising
        TypeError/ValueError naming the parameter.
    numbers_only : bool, default: True
        ``"float"``: refuse strings and bools (False: anything ``float()`` takes).
    variadic : bool, default: False
        The setter takes several arguments (``SetGazePoint(x, y)``), passed to ``convert``.

    Examples
    --------
    >>> p = Parameter("depth_weight", "float", 0.15, "Weight of the depth term.", low=0.0, high=1.0)
    >>> p.setter, p.check(0.3), p.summary
    ('SetDepthWeight', 0.3, 'Weight of the depth term.')
    >>> p.check(1.5)
    Traceback (most recent call last):
    ...
    ValueError: depth_weight must be in [0, 1], got 1.5
    """

    name: str
    kind: str
    default: Any
    doc: str
    low: Optional[float] = None
    high: Optional[float] = None
    open_low: bool = False
    choices: Union[Tuple[str, ...], Callable[[], Tuple[str, ...]]] = ()
    unit: str = ""
    uniforms: Tuple[Uniform, ...] = ()
    pieces: bool = False
    convert: Optional[Callable] = field(default=None, compare=False)
    numbers_only: bool = True
    variadic: bool = False

    @property
    def setter(self) -> str:
        """Name of the VTK-style setter."""
        return setter_name(self.name)

    @property
    def getter(self) -> str:
        """Name of the VTK-style getter."""
        return "Get" + self.setter[3:]

    @property
    def summary(self) -> str:
        """The doc's first sentence."""
        return re.split(r"(?<!e\.g)(?<!Eq)(?<!i\.e)\.\s+(?=[A-Z])", self.doc)[0].rstrip(".") + "."

    def valid_choices(self) -> Tuple[str, ...]:
        """The choices of a ``"choice"`` parameter (called if given as a function)."""
        return tuple(self.choices() if callable(self.choices) else self.choices)

    def check(self, *values: Any) -> Any:
        """The canonical value for ``values`` (the setter's arguments), or raise naming the parameter."""
        if self.kind == "value":
            return self.convert(*values) if self.variadic else self.convert(_one(self.name, values))
        value = _one(self.name, values)
        if self.kind == "bool":
            return _check_bool(self.name, value)
        if self.kind == "choice":
            return check_choice(self.name, value, self.valid_choices())
        if self.kind == "int":
            return _check_int(self.name, value, self.low, self.high)
        if self.low == 0.0 and self.high == 1.0:
            return check_unit(self.name, value, open_low=self.open_low)
        if self.low == 0.0 and self.high is None:
            return check_non_negative(self.name, value, numbers_only=self.numbers_only)
        raise NotImplementedError(f"{self.name}: float range [{self.low}, {self.high}] has no check")

    def describe(self) -> str:
        """Kind, range or choices, unit and default, e.g. ``"float in [0, 1], default 0.15"``."""
        if self.kind == "choice":
            what = "one of " + ", ".join(self.valid_choices())
        elif self.kind in ("float", "int"):
            high = "inf" if self.high is None else f"{self.high:g}"
            what = f"{self.kind} in {'(' if self.open_low else '['}{self.low:g}, {high}{')' if self.high is None else ']'}"
        else:
            what = self.kind
        unit = f" {self.unit}" if self.unit else ""
        return f"{what}{unit}, default {_show(self.default)}"


def _one(name: str, values: tuple) -> Any:
    if len(values) != 1:
        raise TypeError(f"{name} takes one value, got {len(values)}: {values!r}")
    return values[0]


def _check_bool(name: str, value: Any) -> bool:
    """True/False (also 1/0 and numpy booleans); text is refused, not taken for its truth value."""
    if isinstance(value, (bool, int, np.bool_, np.integer)) and value in (0, 1):
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {value!r}")


def _check_int(name: str, value: Any, low, high) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or int(value) != value \
            or (low is not None and value < low) or (high is not None and value > high):
        raise ValueError(f"{name} must be an integer from {low:g} to {high:g}, got {value!r}")
    return int(value)


def _show(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else repr(value)


def parameter_accessors(cls):
    """Class decorator: a ``SetX``/``GetX`` pair for every entry of ``cls.PARAMETERS`` not defined by hand.

    The generated setter checks its arguments with :meth:`Parameter.check`
    and calls ``self._set_parameter(name, value)``; the getter returns
    ``self._get_parameter(name)``.  A class that must do more when a value
    changes defines the setter itself and calls the same two methods, so the
    check and the storage stay the table's.

    Examples
    --------
    >>> class Demo:
    ...     PARAMETERS = (Parameter("gain", "float", 0.5, "How much.", low=0.0, high=1.0),)
    ...     def __init__(self): self.values = {"gain": 0.5}
    ...     def _set_parameter(self, name, value): self.values[name] = value
    ...     def _get_parameter(self, name): return self.values[name]
    >>> Demo = parameter_accessors(Demo)
    >>> demo = Demo(); demo.SetGain(0.25); demo.GetGain()
    0.25
    """
    for parameter in cls.PARAMETERS:
        if parameter.setter not in vars(cls):
            setattr(cls, parameter.setter, _setter(parameter))
        if parameter.getter not in vars(cls):
            setattr(cls, parameter.getter, _getter(parameter))
    return cls


def _setter(parameter: Parameter):
    def setter(self, *values):
        self._set_parameter(parameter.name, parameter.check(*values))
    setter.__name__ = parameter.setter
    setter.__doc__ = f"{parameter.doc}\n\n{parameter.describe()}."
    return setter


def _getter(parameter: Parameter):
    def getter(self):
        return self._get_parameter(parameter.name)
    getter.__name__ = parameter.getter
    getter.__doc__ = f"The {parameter.name.replace('_', ' ')} (see :meth:`{parameter.setter}`)."
    return getter


def parameter_table(mapper) -> Tuple[Parameter, ...]:
    """The parameter table of a mapper's method (empty for VTK's own mappers).

    Examples
    --------
    >>> import mipcast
    >>> [p.name for p in parameter_table(mipcast.create_mapper("analytic"))]
    ['packed_corners', 'skipping', 'slab_thickness', 'slab_centre', 'slab_normal']
    """
    return tuple(getattr(type(mapper), "PARAMETERS", ()))


def uniform_values(table: Sequence[Parameter], settings: Mapping) -> Dict[str, Tuple[str, Any]]:
    """Each uniform the table drives -> ``(kind, value)`` for these settings.

    Examples
    --------
    >>> table = (Parameter("gain", "float", 0.5, "How much.", low=0.0, high=1.0,
    ...                    uniforms=(Uniform("u_mc_gain"),)),)
    >>> uniform_values(table, {"gain": 0.25})
    {'u_mc_gain': ('float', 0.25)}
    """
    return {u.name: (u.kind, u.value(settings[p.name], settings)) for p in table for u in p.uniforms}


def defaults(table: Sequence[Parameter]) -> Dict[str, Any]:
    """``{name: default}`` of a parameter table."""
    return {p.name: p.default for p in table}


def check_values(table: Sequence[Parameter], params: Mapping, what: str) -> Dict[str, Any]:
    """Defaults updated with ``params``, each checked by its table entry; unknown names raise TypeError.

    For callers that take parameters as keywords (the float64 references).

    Examples
    --------
    >>> table = (Parameter("gain", "float", 0.5, "How much.", low=0.0, high=1.0),)
    >>> check_values(table, {"gain": 1}, "demo")
    {'gain': 1.0}
    >>> check_values(table, {"gian": 1}, "demo")
    Traceback (most recent call last):
    ...
    TypeError: unknown parameter(s) for demo: gian; valid: gain
    """
    by_name = {p.name: p for p in table}
    unknown = sorted(set(params) - set(by_name))
    if unknown:
        raise TypeError(f"unknown parameter(s) for {what}: {', '.join(unknown)}; "
                        f"valid: {', '.join(by_name) or 'none'}")
    values = defaults(table)
    for name, value in params.items():
        parameter = by_name[name]
        if parameter.variadic and isinstance(value, (tuple, list)) and not isinstance(value, str):
            values[name] = parameter.check(*value)
        else:
            values[name] = parameter.check(value)
    return values


#: Short names front ends accept for parameters (``slab=20`` is ``slab_thickness=20``).
ALIASES = {"slab": "slab_thickness"}


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
    params = {ALIASES.get(name, name): value for name, value in params.items()}
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
    """Names of the parameters a method adds to VTK's mapper, in snake_case: its parameter table's.

    VTK's own setters are not listed (they work in :func:`set_parameters`
    too), nor are a mapper's internal setters.  Stock VTK MIP has none.

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
    >>> method_parameters(mipcast.create_mapper("analytic"))
    ('packed_corners', 'skipping', 'slab_centre', 'slab_normal', 'slab_thickness')
    """
    return tuple(sorted(p.name for p in parameter_table(mapper)))


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
