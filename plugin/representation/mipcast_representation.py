"""Python side of ParaView's "mipcast" representation (plugin/representation).

The C++ class ``vtkMipcastRepresentation`` (a thin subclass of ParaView's
``vtkImageVolumeRepresentation``) owns a plain ``vtkVolume`` in the render
view's renderer and calls this module, through ParaView's embedded Python, to
create and configure that volume's mapper: a mipcast Python mapper made by
``mipcast.create_mapper(method)``.  So the GLSL (``shaders/*.glsl``) and the
mapper logic (uniforms, corner packing, block maxima, foveation levels) exist
once, in mipcast.

Two roles:

- **Build time** (``python mipcast_representation.py --xml OUT --header OUT
  --template IN``): :func:`plugin_methods` lists every method and its
  parameters; :func:`server_manager_xml` and :func:`cxx_setters` turn that
  list into the Properties panel (ServerManager XML) and the C++ setters the
  XML calls.  Nothing is copied by hand: re-run CMake after changing a
  method's parameters.
- **Run time** (called from C++): :func:`set_method`, :func:`set_value`,
  :func:`prepare`, :func:`release`.  Every call reports its errors in VTK's
  output window (ParaView: *Output Messages*) and never raises into C++.
"""
from __future__ import annotations

import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
#: The folder holding the ``mipcast`` package in the source tree (plugin/representation -> root).
_ROOT = os.path.dirname(os.path.dirname(_HERE))


def _import_mipcast():
    """``import mipcast``, appending the source tree's root to ``sys.path`` if needed."""
    try:
        import mipcast
    except ImportError:
        if os.path.isdir(os.path.join(_ROOT, "mipcast")) and _ROOT not in sys.path:
            sys.path.append(_ROOT)  # appended: ParaView's numpy and VTK stay first
        import mipcast
    return mipcast


# -- the method table ---------------------------------------------------------------------
#: Parameters whose getter cannot tell their type (default None), described here.
_EXTRA = {
    ("foveated", "region_of_interest"): dict(
        type="double", size=6, default=(1.0, 0.0, 1.0, 0.0, 1.0, 0.0),
        doc="World-space bounds (x0 x1 y0 y1 z0 z1) kept sharp; x0 > x1 (the default) means none."),
}
#: Parameters not in the panel (none today; kept for the tests and other front ends).
NOT_IN_PANEL = frozenset()
#: Optional point/vector parameters (None: follow the camera) -> the panel's three values
#: shown when the "follows camera" switch is off.  Two properties each: ``<name>`` (x y z, a
#: 3-element double vector with a real default) and ``<name>_follows_camera`` (bool, default
#: on = None for the mapper, which then follows the camera's focal point / view direction).
FOLLOWING = {
    "slab_centre": dict(default=(0.0, 0.0, 0.0), follows="the slab's mid-plane goes through the camera's "
                        "focal point (as the mapper's None); off: through Slab Centre"),
    "slab_normal": dict(default=(0.0, 0.0, 1.0), follows="the slab faces the camera (the view direction, "
                        "as the mapper's None); off: Slab Normal"),
}
#: Suffix of the switch property of a :data:`FOLLOWING` parameter.
FOLLOWS = "_follows_camera"
#: Parameters every method gets (VTK's sampling), prefixed "common".
_COMMON = [
    dict(name="sample_distance", type="double", size=1, default=0.0, range=(0.0, None),
         doc="World units between samples; 0 = one sample per voxel (the smallest spacing)."),
    dict(name="image_sample_distance", type="double", size=1, default=1.0, range=(0.1, 8.0),
         doc="Pixels between rays (VTK's ImageSampleDistance); 2 = half resolution."),
]
#: Representation-level extras of a method (not mapper setters), handled in prepare().
_REPRESENTATION_EXTRAS = {
    "foveated": [dict(name="follow_mouse", type="bool", size=1, default=True,
                      doc="The gaze follows the mouse over the render view (builtin sessions); "
                          "until the mouse moves, the gaze point is used.")],
}


def plugin_methods():
    """Every method the representation offers, with its parameters: from ``mipcast.METHODS``.

    The methods of the method table that render in a view, each with its
    parameter table (:mod:`mipcast.core.parameter_tables`) plus VTK's
    sampling settings.  Returns a list of ``{"name", "label", "parameters":
    [...]}``; each parameter is ``{"name", "type" ("double", "int", "bool",
    "string"), "size" (number of values), "shape" (nested tuple shape or
    None), "default", "range" ((low, high), None = open) or None, "choices"
    (strings) or None, "doc"}``.

    Examples
    --------
    >>> methods = {m["name"]: m for m in plugin_methods()}
    >>> "mip" in methods and "analytic" in methods and "demip" in methods
    True
    >>> weight = [p for p in methods["demip"]["parameters"] if p["name"] == "depth_weight"][0]
    >>> weight["type"], weight["default"], weight["range"]
    ('double', 0.15, (0.0, 1.0))
    """
    mipcast = _import_mipcast()
    table = []
    for name, method in mipcast.METHODS.items():
        if not method.in_view:
            continue
        parameters = [dict(p, name="common_" + p["name"], shape=None,
                           choices=None, range=p.get("range")) for p in _COMMON]
        for parameter in method.parameters:
            if parameter.name in NOT_IN_PANEL:
                continue
            extra = _EXTRA.get((name, parameter.name))
            following = FOLLOWING.get(parameter.name)
            if following is not None:
                parameters.append(dict(name=parameter.name + FOLLOWS, type="bool", size=1, default=True,
                                       shape=None, range=None, choices=None,
                                       doc=f"On: {following['follows']}."))
                parameters.append(dict(name=parameter.name, type="double", size=3,
                                       default=following["default"], shape=None, range=None, choices=None,
                                       doc=parameter.doc.split("; None")[0] + f" (used when "
                                       f"{_label(name, parameter.name + FOLLOWS)} is off)."))
            elif extra is not None:
                parameters.append(dict(extra, name=parameter.name, shape=None, range=None, choices=None))
            else:
                parameters.append(_describe(parameter))
        for extra in _REPRESENTATION_EXTRAS.get(name, []):
            parameters.append(dict(extra, shape=None, range=None, choices=None))
        table.append(dict(name=name, label=method.label, parameters=parameters))
    return table


def _describe(parameter):
    """A panel entry for one :class:`mipcast.core.parameters.Parameter`."""
    default = parameter.default
    entry = dict(name=parameter.name, doc=parameter.doc, shape=None, range=None, choices=None, default=default)
    if parameter.kind == "bool":
        entry.update(type="bool", size=1)
    elif parameter.kind == "int":
        entry.update(type="int", size=1, range=(int(parameter.low), int(parameter.high)))
    elif parameter.kind == "float":
        entry.update(type="double", size=1, range=(parameter.low, parameter.high))
    elif parameter.kind == "choice":
        entry.update(type="string", size=1, choices=list(parameter.valid_choices()))
    elif isinstance(default, tuple):
        flat, shape = _flatten(default)
        entry.update(type="double", size=len(flat), default=tuple(flat), shape=shape,
                     range=(0.0, 1.0) if parameter.name == "sphere_colors" else None)
    else:
        raise TypeError(f"{parameter.name}: no panel widget for {default!r}")
    return entry


def _flatten(value):
    if all(isinstance(v, (int, float)) for v in value):
        return [float(v) for v in value], None
    rows = [list(v) for v in value]
    return [float(x) for row in rows for x in row], (len(rows), len(rows[0]))


# -- generated XML and C++ ------------------------------------------------------------------
def property_name(method, parameter):
    """The ServerManager property of a method's parameter: ``demip_depth_weight``."""
    return f"{method}_{parameter}"


def _setter(method, parameter):
    return f"SetP_{method}_{parameter}"


def _label(method, parameter):
    words = parameter.replace("common_", "").split("_")
    return " ".join(w.capitalize() for w in words)


def _xml_escape(text):
    return (str(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
            .replace('"', "&quot;"))


def _format(value):
    if isinstance(value, bool):
        return str(int(value))
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _visibility(method):
    return (
        '        <Hints>\n'
        '          <PropertyWidgetDecorator type="CompositeDecorator">\n'
        '            <Expression type="and">\n'
        '              <PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
        'property="Representation" value="mipcast" />\n'
        '              <PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
        f'property="MipcastMethod" value="{method}" />\n'
        '            </Expression>\n'
        '          </PropertyWidgetDecorator>\n'
        '        </Hints>\n')


#: The information-only properties of the server's refinement state (the C++ getters
#: ``Get<name>()`` call :func:`refinement_info`), in the order of its tuple.
REFINEMENT_INFO = (
    ("MipcastRefining", "1 while this process's foveated mapper needs another frame to refine."),
    ("MipcastRefinementStep", "Still frames the foveated mapper has refined (-1: none here)."),
    ("MipcastFramesDrawn", "Frames the volume has drawn in this process."),
)


def server_manager_xml(methods=None):
    """The ServerManager XML of the representation, generated from :func:`plugin_methods`."""
    methods = plugin_methods() if methods is None else methods
    props, exposed = [], []
    names = "".join(f'          <String value="{m["name"]}" />\n' for m in methods)
    listing = "; ".join(f'{m["name"]}: {m["label"]}' for m in methods)
    props.append(
        '      <StringVectorProperty name="MipcastMethod" label="mipcast Method" '
        'command="SetMipcastMethod" number_of_elements="1" default_values="mip">\n'
        f'        <StringListDomain name="list">\n{names}        </StringListDomain>\n'
        f'        <Documentation>The mipcast method that renders the volume ({_xml_escape(listing)}).'
        '</Documentation>\n'
        '        <Hints>\n'
        '          <PropertyWidgetDecorator type="GenericDecorator" mode="visibility" '
        'property="Representation" value="mipcast" />\n'
        '        </Hints>\n'
        '      </StringVectorProperty>\n')
    exposed.append('          <Property name="MipcastMethod" />\n')
    for name, doc in REFINEMENT_INFO:  # read by a client of a remote server after a frame
        props.append(
            f'      <IntVectorProperty name="{name}" command="Get{name}" information_only="1" '
            'number_of_elements="1" default_values="0" panel_visibility="never">\n'
            '        <SimpleIntInformationHelper />\n'
            f'        <Documentation>{_xml_escape(doc)}</Documentation>\n'
            f'      </IntVectorProperty>\n')
    for method in methods:
        group = []
        for p in method["parameters"]:
            name = property_name(method["name"], p["name"])
            kind = {"double": "DoubleVectorProperty", "int": "IntVectorProperty",
                    "bool": "IntVectorProperty", "string": "StringVectorProperty"}[p["type"]]
            default = p["default"]
            values = " ".join(_format(v) for v in (default if isinstance(default, tuple) else (default,)))
            advanced = ' panel_visibility="advanced"' if p["name"].startswith("common_") or p["size"] > 3 else ""
            text = (f'      <{kind} name="{name}" label="{_label(method["name"], p["name"])}" '
                    f'command="{_setter(method["name"], p["name"])}" '
                    f'number_of_elements="{p["size"]}" default_values="{_xml_escape(values)}"{advanced}>\n')
            if p["type"] == "bool":
                text += '        <BooleanDomain name="bool" />\n'
            elif p["type"] == "string":
                choices = "".join(f'          <String value="{c}" />\n' for c in p["choices"])
                text += f'        <StringListDomain name="list">\n{choices}        </StringListDomain>\n'
            elif p["range"] is not None:
                low, high = p["range"]
                domain = "IntRangeDomain" if p["type"] == "int" else "DoubleRangeDomain"
                bounds = "".join(f' {k}="{_format(v)}"' for k, v in (("min", low), ("max", high))
                                 if v is not None)
                text += f'        <{domain} name="range"{bounds} />\n'
            text += f'        <Documentation>{_xml_escape(p["doc"])}</Documentation>\n'
            text += _visibility(method["name"])
            text += f'      </{kind}>\n'
            props.append(text)
            group.append(f'            <Property name="{name}" />\n')
        if group:
            exposed.append(f'          <PropertyGroup label="mipcast: {_xml_escape(method["label"])}">\n'
                           + "".join(group) + '          </PropertyGroup>\n')
    return (
        "<!-- Generated by plugin/representation/mipcast_representation.py from plugin_methods(); "
        "do not edit. -->\n"
        "<ServerManagerConfiguration>\n"
        '  <ProxyGroup name="representations">\n'
        '    <RepresentationProxy name="MipcastRepresentation" class="vtkMipcastRepresentation"\n'
        '        processes="client|renderserver|dataserver"\n'
        '        base_proxygroup="representations" base_proxyname="UniformGridVolumeRepresentation">\n'
        "      <Documentation>ParaView's volume representation drawn by a mipcast method "
        "(a mipcast Python mapper on a plain vtkVolume).</Documentation>\n"
        + "".join(props) +
        "    </RepresentationProxy>\n"
        '    <Extension name="UniformGridRepresentation">\n'
        '      <RepresentationType subproxy="MipcastRepresentation" text="mipcast" />\n'
        "      <SubProxy>\n"
        '        <Proxy name="MipcastRepresentation" proxygroup="representations" '
        'proxyname="MipcastRepresentation" />\n'
        '        <ShareProperties subproxy="VolumeRepresentation">\n'
        '          <Exception name="Input" />\n'
        '          <Exception name="Visibility" />\n'
        '          <Exception name="Representation" />\n'
        "        </ShareProperties>\n"
        "        <ExposedProperties>\n"
        + "".join(exposed) +
        "        </ExposedProperties>\n"
        "      </SubProxy>\n"
        "    </Extension>\n"
        "  </ProxyGroup>\n"
        "</ServerManagerConfiguration>\n")


def cxx_setters(methods=None):
    """The C++ setters the XML's commands name, one per parameter, generated like the XML."""
    methods = plugin_methods() if methods is None else methods
    lines = []
    for method in methods:
        for p in method["parameters"]:
            name, n = _setter(method["name"], p["name"]), p["size"]
            where = f'"{method["name"]}", "{p["name"]}"'
            if p["type"] == "string":
                lines.append(f"  void {name}(const char* value) {{ this->SetMipcastString({where}, value); }}")
                continue
            ctype = "double" if p["type"] == "double" else "int"
            args = ", ".join(f"{ctype} a{i}" for i in range(n))
            values = ", ".join(f"a{i}" for i in range(n))
            helper = "SetMipcastDoubles" if ctype == "double" else "SetMipcastInts"
            lines.append(f"  void {name}({args}) {{ const {ctype} v[] = {{ {values} }}; "
                         f"this->{helper}({where}, {n}, v); }}")
    return "\n".join(lines) + "\n"


# -- run time (called from vtkMipcastRepresentation) ----------------------------------------
#: Representation key (the C++ object's address) -> _Entry.
_REGISTRY: dict = {}
_TABLE: dict = {}


def _table():
    """method name -> {parameter name -> description} (built once per process)."""
    if not _TABLE:
        for method in plugin_methods():
            _TABLE[method["name"]] = {p["name"]: p for p in method["parameters"]}
    return _TABLE


class _Entry:
    """One representation's mapper and the values ParaView set."""

    def __init__(self):
        self.method = "mip"
        self.values = {}  # method -> {parameter -> value}
        self.mapper = None
        self.mapper_method = None
        self.applied = {}  # parameter -> value applied on self.mapper
        self.programs = []  # addresses of the shader programs seen after the volume drew
        self.renders = 0
        self.problem = None
        self.preparer = None  # VTK's own mapper's InputPreparer (mipcast mappers have their own)
        from vtkmodules.vtkCommonCore import vtkWeakReference

        self.render_window = vtkWeakReference()
        self.renderer = vtkWeakReference()  # a brick's rays come from its camera (global_phase)

    def stats(self):
        return dict(method=self.method, mapper=type(self.mapper).__name__ if self.mapper else None,
                    programs=len(set(self.programs)), renders=self.renders, problem=self.problem)


def _entry(key):
    entry = _REGISTRY.get(key)
    if entry is None:
        entry = _REGISTRY[key] = _Entry()
    return entry


def _report(text, error=True):
    from vtkmodules.vtkCommonCore import vtkOutputWindow

    window = vtkOutputWindow.GetInstance()
    (window.DisplayErrorText if error else window.DisplayWarningText)(f"mipcast representation: {text}\n")


def _guarded(function):
    def call(*args):
        try:
            return function(*args)
        except Exception as error:  # never into C++: a message in Output Messages instead
            _report(f"{type(error).__name__}: {error}")
            return False
    call.__name__ = function.__name__
    call.__doc__ = function.__doc__
    return call


@_guarded
def set_method(key, method):
    """ParaView set the MipcastMethod property."""
    _import_mipcast()
    if method not in _table():
        raise ValueError(f"unknown method {method!r}; the methods are {', '.join(_table())}")
    _entry(key).method = method
    return True


@_guarded
def set_value(key, method, name, value):
    """ParaView set a parameter property; applied now if ``method`` is drawing."""
    _import_mipcast()
    entry = _entry(key)
    entry.values.setdefault(method, {})[name] = value
    if entry.mapper is not None and entry.mapper_method == method:
        _apply(entry, {name: value})
    return True


def _value(description, value):
    """A property's values as the mapper's setter takes them."""
    if description["type"] == "bool":
        return bool(value[0])
    if description["type"] == "int":
        return int(value[0])
    if description["type"] == "string":
        return value
    values = [float(v) for v in value]
    if description["name"] == "region_of_interest":
        return None if values[0] > values[1] else tuple(values)
    if description["shape"] is not None:
        rows, columns = description["shape"]
        return tuple(tuple(values[r * columns:(r + 1) * columns]) for r in range(rows))
    return values[0] if len(values) == 1 else tuple(values)


def _apply(entry, values):
    """Set changed values on the entry's mapper: method parameters only, never a rebuild of ours."""
    from mipcast.core.parameters import set_parameters

    table = _table()[entry.mapper_method]
    settings = {}
    every = entry.values.get(entry.mapper_method, {})
    for name in list(values):
        if name.endswith(FOLLOWS) and name[:-len(FOLLOWS)] in FOLLOWING:
            values = dict(values)
            values[name[:-len(FOLLOWS)]] = every.get(name[:-len(FOLLOWS)], FOLLOWING[name[:-len(FOLLOWS)]]["default"])
    for name, raw in values.items():
        description = table.get(name)
        if description is None or name.endswith(FOLLOWS):
            continue
        value = _value(description, raw)
        if name in FOLLOWING and bool((every.get(name + FOLLOWS) or (1,))[0]):
            value = None  # follows the camera
        if entry.applied.get(name, object()) == value:
            continue
        entry.applied[name] = value
        if name.startswith("common_") or name in ("follow_mouse",):
            continue  # applied in prepare()
        settings[name] = value
    for name, value in settings.items():
        try:
            set_parameters(entry.mapper, **{name: value})
        except (TypeError, ValueError) as error:
            entry.applied.pop(name, None)
            description = table[name]
            _report(f"{entry.mapper_method} {name}={value!r} refused ({error}); "
                    f"kept the previous value (allowed: {description.get('range') or description.get('choices') or description['doc']})")


def _new_mapper(entry, volume, port):
    from mipcast.methods import attach, create_mapper
    from vtkmodules.vtkCommonCore import vtkCommand

    old = entry.mapper
    if old is not None and hasattr(old, "Detach"):
        old.Detach()
    mapper = create_mapper(entry.method)
    mapper.SetAutoAdjustSampleDistances(False)
    if hasattr(mapper, "SetUseJittering"):
        mapper.SetUseJittering(False)
    entry.preparer = None
    if _import_mipcast().METHODS[entry.method].float_readout:  # a mipcast mapper: its own preparer
        mapper.SetInputConnection(port)
    else:  # VTK's own: a preparer in front (one component; routed in _prepare_own)
        from mipcast.mappers.input_preparer import InputPreparer, fill_side

        entry.preparer = InputPreparer(fill_side(_import_mipcast().METHODS[entry.method].projection))
        entry.preparer.SetInputConnection(port)
        mapper.SetInputConnection(port)
    entry.mapper, entry.mapper_method, entry.applied = mapper, entry.method, {}
    _apply(entry, entry.values.get(entry.method, {}))
    attach(mapper, volume)

    def drawn(caller, event, entry=entry):
        entry.renders += 1
        window = entry.render_window.Get()
        cache = window.GetShaderCache() if window is not None and hasattr(window, "GetShaderCache") else None
        program = cache.GetLastShaderBound() if cache is not None else None
        if program is not None:
            entry.programs.append(program.GetAddressAsString("vtkObjectBase"))
    mapper.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, drawn)
    return mapper


# -- parallel render views: exact compositing by depth ---------------------------------------
#: The depth range [DEPTH_MARGIN, 1 - DEPTH_MARGIN] the values are mapped to (0 and 1 stay free).
DEPTH_MARGIN = 1.0e-4
# OpenGL enums for the state the volume draws in while it writes depth.
_GL_DEPTH_TEST, _GL_BLEND, _GL_CULL_FACE, _GL_BACK = 0x0B71, 0x0BE2, 0x0B44, 0x0405
_GL_ONE, _GL_ONE_MINUS_SRC_ALPHA = 1, 0x0303


def process_count():
    """Processes of this process's MPI job (ParaView's global controller; 1 without MPI)."""
    from vtkmodules.vtkParallelCore import vtkMultiProcessController

    controller = vtkMultiProcessController.GetGlobalController()
    return 1 if controller is None else controller.GetNumberOfProcesses()


def process_index():
    """This process's rank in its MPI job (ParaView's global controller; 0 without MPI)."""
    from vtkmodules.vtkParallelCore import vtkMultiProcessController

    controller = vtkMultiProcessController.GetGlobalController()
    return 0 if controller is None else controller.GetLocalProcessId()


def depth_composite_op(method):
    """How ``method``'s pieces composite exactly by depth: ``"max"``, ``"min"`` or None (ordered blending).

    ``"max"`` for the method table's ``distributed="max"`` entries (the
    nearest fragment is the largest value), ``"min"`` for the mipcast
    mappers of the minimum projection (``projection="minip"`` with a float
    readout: the nearest is the smallest); for ``rank_view="depth"``
    (VTK's own MIP / MinIP, :mod:`mipcast.mappers.stock_depth`) by its
    projection; None for the others.

    >>> [depth_composite_op(m) for m in ("mip", "analytic", "minip", "analytic_minip", "stock", "stock_minip",
    ...                                  "demip", "stock_average")]
    ['max', 'max', 'min', 'min', 'max', 'min', None, None]
    """
    mipcast = _import_mipcast()
    entry = mipcast.METHODS.get(method)
    if entry is None:
        return None
    if entry.distributed == "max":
        return "max"
    if entry.projection == "minip" and entry.float_readout:
        return "min"
    if entry.rank_view == "depth":  # VTK's own mapper writing its value as depth (mipcast.mappers.stock_depth)
        return {"mip": "max", "minip": "min"}.get(entry.projection)
    return None


def rank_composite_rule(method):
    """How ``method``'s pieces composite exactly by reduction over the ranks: ``"demip"``, ``"mean"`` or None.

    ``"demip"`` for the method table's ``distributed="demip"`` entries (DEMIP,
    two-pass DEMIP), ``"foveated"`` for ``rank_view="foveated"`` (each level
    reduced with MAX, then blended: :mod:`mipcast.mappers.rank_foveated`),
    ``"mean"`` for its mipcast mappers combined by their mean
    (``bricks="mean"``: average, analytic average) and for ``rank_view="mean"``
    (VTK's own average, read out by :func:`rank_brick`'s mapper); None for the
    others.  See :mod:`mipcast.mappers.rank_composite`.

    >>> [rank_composite_rule(m) for m in ("demip", "demip_two_pass", "average", "analytic_average", "mip",
    ...                                   "foveated", "stock_average", "stock")]
    ['demip', 'demip', 'mean', 'mean', None, 'foveated', 'mean', None]
    """
    mipcast = _import_mipcast()
    entry = mipcast.METHODS.get(method)
    if entry is not None and entry.rank_view == "mean":
        return "mean"
    if entry is None or not entry.float_readout:
        return None
    if entry.distributed == "demip":
        return "demip"
    if entry.rank_view == "foveated":
        return "foveated"
    if entry.bricks == "mean":
        return "mean"
    return None


def rank_brick(method):
    """The mipcast mapper class that reads ``method``'s pieces out for the reduction; None: its own mapper's.

    VTK's own mappers have no float readout: the method whose samples and weights they are (the method
    table's ``readout_by``) reads their pieces out.

    >>> rank_brick("stock_average").__name__, rank_brick("average")
    ('AverageVolumeMapper', None)
    """
    mipcast = _import_mipcast()
    entry = mipcast.METHODS.get(method)
    if entry is None or entry.float_readout or entry.readout_by is None:
        return None
    return mipcast.METHODS[entry.readout_by].factory


def rank_refusal(method, ranks=2):
    """Why ``method`` cannot draw in a parallel render view of ``ranks`` processes, or None when it composites exactly.

    A method of the table that composites neither by depth
    (:func:`depth_composite_op`) nor by reduction (:func:`rank_composite_rule`)
    would be blended by ParaView in visibility order, which is not its
    projection of the whole volume: it is refused, naming the methods of the
    same projection that are exact across ranks.

    >>> rank_refusal("mip") is None, rank_refusal("stock_average") is None
    (True, True)
    >>> "mip" in rank_refusal("cpu")
    True
    """
    mipcast = _import_mipcast()
    entry = mipcast.METHODS.get(method)
    if entry is None or depth_composite_op(method) is not None or rank_composite_rule(method) is not None:
        return None
    return (f"{method} cannot be drawn on {ranks} ranks: ParaView would blend the ranks' pieces in visibility order, "
            f"which is not the {entry.projection} projection of the whole volume (a wrong picture where pieces "
            f"overlap on screen); use {' or '.join(_exact_methods(method))}, which composite exactly over the "
            "ranks, or render on one rank")


def _exact_methods(method, missing=False):
    """The methods of ``method``'s projection that composite exactly over ranks (``missing``: mipcast's own,
    which draw missing values as the whole volume does)."""
    mipcast = _import_mipcast()
    projection = mipcast.METHODS[method].projection
    return [name for name, other in mipcast.METHODS.items()
            if other.in_view and other.projection == projection and (other.float_readout or not missing)
            and other.rank_view != "foveated"
            and (depth_composite_op(name) is not None or rank_composite_rule(name) is not None)]


@_guarded
def depth_composited(key):
    """Called at REQUEST_UPDATE: True when this rank's piece is composited by depth, not by ordered blending.

    True for the maximum and minimum projections (:func:`depth_composite_op`)
    in a job of several processes (``mpiexec -n N pvbatch`` or ``pvserver``): the C++ representation then tells the view that it needs
    no ordered compositing, so IceT composites by Z buffer, and :func:`prepare`
    has the mapper write each ray's value as its depth.
    """
    _import_mipcast()
    method = _entry(key).method
    return process_count() > 1 and (depth_composite_op(method) is not None
                                    or rank_composite_rule(method) is not None)


def depth_mapping(volume_property, scalars, op="max"):
    """(scale, bias) with ``depth = scale * n + bias`` for VTK's normalised scalar ``n`` of ``scalars``.

    ``depth = 1 - (value - low) / (high - low)`` (``op="max"``; ``"min"``:
    ``(value - low) / (high - low)``) squeezed into
    ``[DEPTH_MARGIN, 1 - DEPTH_MARGIN]``, for the value in data units
    (:func:`mipcast.mappers.float_readout.to_data_units`) and (low, high) the
    transfer functions' range, which ParaView gives every rank alike, while
    each rank's normalisation follows its own piece's range.

    >>> from vtkmodules.vtkCommonCore import vtkFloatArray
    >>> from mipcast.offscreen import grey_property
    >>> scalars = vtkFloatArray()
    >>> _ = scalars.InsertNextValue(2.0), scalars.InsertNextValue(4.0)
    >>> scale, bias = depth_mapping(grey_property((0.0, 4.0)), scalars)
    >>> round(scale * 1.0 + bias, 4), round(scale * 0.0 + bias, 4)   # value 4 (nearest), value 2
    (0.0001, 0.5)
    """
    from mipcast.mappers.float_readout import texture_scale

    ranges = [volume_property.GetRGBTransferFunction().GetRange(), volume_property.GetScalarOpacity().GetRange()]
    low, high = min(r[0] for r in ranges), max(r[1] for r in ranges)
    if not high > low:
        high = low + 1.0
    first, last = scalars.GetRange(0)
    factor = texture_scale(scalars)
    c = (1.0 - 2.0 * DEPTH_MARGIN) / (high - low)
    # value = (first + n * (last - first)) / factor
    if op == "min":
        return c * (last - first) / factor, DEPTH_MARGIN + c * (first / factor - low)
    return -c * (last - first) / factor, (1.0 - DEPTH_MARGIN) - c * (first / factor - low)


def _depth_state(entry):
    """Observers around the mapper's draw: depth writes on (VTK's volume draw turns them off)."""
    from vtkmodules.vtkCommonCore import vtkInformation
    from vtkmodules.vtkRenderingOpenGL2 import vtkOpenGLActor

    def start(mapper, event, entry=entry):
        from mipcast.core.object_state import object_state

        window = entry.render_window.Get()
        volume = mapper.GetAttachedVolume() if hasattr(mapper, "GetAttachedVolume") else entry.own_volume.Get()
        entry.pushed = None
        if not object_state(mapper).get("depth_composite") or window is None or volume is None:
            return
        keys = volume.GetPropertyKeys()
        if keys is None:
            keys = vtkInformation()
            volume.SetPropertyKeys(keys)
        # not 0 or 1: the mapper leaves the GL state as it finds it (vtkVolumeStateRAII no-op) ...
        keys.Set(vtkOpenGLActor.GLDepthMaskOverride(), 2)
        state = window.GetState()
        state.Push()
        # ... which is VTK's volume state, with depth writes on
        state.vtkglEnable(_GL_DEPTH_TEST)
        state.vtkglBlendFunc(_GL_ONE, _GL_ONE_MINUS_SRC_ALPHA)
        state.vtkglEnable(_GL_BLEND)
        state.vtkglCullFace(_GL_BACK)
        state.vtkglEnable(_GL_CULL_FACE)
        state.vtkglDepthMask(True)
        entry.pushed = (state, keys)

    def end(mapper, event, entry=entry):
        pushed, entry.pushed = getattr(entry, "pushed", None), None
        if pushed is not None:
            state, keys = pushed
            state.Pop()
            # only for this draw: another method's mapper on this volume sets VTK's state itself
            keys.Remove(vtkOpenGLActor.GLDepthMaskOverride())
    return start, end


def _ray_pusher(entry):
    """An observer of the mapper's draw: this frame's whole-volume rays for a brick (global_phase, global_cells).

    The rays come from the view's camera and size, the same on every rank
    (:func:`mipcast.distributed.ray_uniforms`), in the whole volume's point
    indices as the display transform places it (the volume's matrix), so
    that every rank samples the whole volume's rays at the same positions.  VTK's own mapper (the
    stock_phase piece) gets the near-plane cap where the camera is inside
    the volume (:func:`mipcast.mappers.stock_depth.push_cap`).
    """
    def push(mapper, event, entry=entry):
        from mipcast.core.object_state import object_state
        from mipcast.mappers.brick_rays import push_whole_rays, whole_geometry

        renderer = entry.renderer.Get()
        own = not hasattr(mapper, "GetAttachedVolume")  # VTK's own mapper knows no attached volume
        own_volume = getattr(entry, "own_volume", None)
        volume = (own_volume.Get() if own_volume is not None else None) if own else mapper.GetAttachedVolume()
        stub = getattr(entry, "whole_stub", None)
        if renderer is None or volume is None or stub is None or object_state(mapper).get("global_box") is None:
            return
        matrix = volume.GetMatrix()  # the display transform (Position, Orientation, Scale, Origin)
        key = (stub, tuple(matrix.GetElement(r, c) for r in range(4) for c in range(4)))
        cached = getattr(entry, "whole_image", None)
        if cached is None or cached[0] != key:  # built once per whole volume and transform, not per draw
            cached = entry.whole_image = (key, whole_geometry(stub, matrix))
        image = cached[1]
        width, height = renderer.GetSize()
        if own:
            from mipcast.mappers.stock_depth import push_cap

            push_cap(volume, image, renderer.GetActiveCamera(), mapper.GetInput().GetExtent(),
                     width / max(height, 1))
            return
        push_whole_rays(volume, mapper.GetSampleDistance(), image, renderer.GetActiveCamera(), (width, height))
    return push


def _set_composite(entry, volume, image, whole):
    """This rank's piece in the whole volume: global sample positions, depth compositing in parallel."""
    from mipcast.core.object_state import object_state
    from mipcast.mappers.brick_rays import global_texture_box, set_brick_uniforms

    mapper = entry.mapper
    state = object_state(mapper)
    uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
    extent = tuple(image.GetExtent())
    whole = tuple(int(v) for v in whole) if whole is not None else extent
    if whole != extent and all(whole[2 * a] <= extent[2 * a] <= extent[2 * a + 1] <= whole[2 * a + 1]
                               for a in range(3)):
        low, high = global_texture_box(extent, whole)
        uniforms.SetUniform3f("u_mc_globalTexMin", low)
        uniforms.SetUniform3f("u_mc_globalTexMax", high)
        set_brick_uniforms(uniforms, whole, extent, image.GetSpacing(), mapper.GetSampleDistance())
        direction = image.GetDirectionMatrix()
        entry.whole_stub = (whole, image.GetOrigin(), image.GetSpacing(),
                            [direction.GetElement(i, j) for i in range(3) for j in range(3)])
        if state.get("global_box") != (low, high):
            state["global_box"] = (low, high)
            mapper.Modified()
        if getattr(entry, "ray_observer", None) is not mapper:
            from vtkmodules.vtkCommonCore import vtkCommand

            mapper.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _ray_pusher(entry), -5.0)
            entry.ray_observer = mapper
    elif state.pop("global_box", None) is not None:
        mapper.Modified()
    op = depth_composite_op(entry.mapper_method) if process_count() > 1 else None
    own = not _import_mipcast().METHODS[entry.mapper_method].float_readout  # VTK's own mapper
    if own:
        from vtkmodules.vtkCommonCore import vtkWeakReference

        from mipcast.mappers.stock_depth import install

        # on several ranks also the whole volume's sample positions (stock_phase; one rank: VTK's own shader)
        install(volume, op, global_texture_box(extent, whole) if op is not None else None)
        if getattr(entry, "own_volume", None) is None:
            entry.own_volume = vtkWeakReference()  # VTK's own mapper knows no attached volume
        entry.own_volume.Set(volume)
    if op is not None:
        if _depth_uniforms(entry, mapper, volume):
            if state.get("depth_composite") != op:
                state["depth_composite"] = op
                mapper.Modified()
            if getattr(entry, "depth_observers", None) is not mapper:
                from vtkmodules.vtkCommonCore import vtkCommand

                start, end = _depth_state(entry)
                mapper.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, start, -10.0)
                mapper.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, end, 10.0)
                entry.depth_observers = mapper
            return
    if state.pop("depth_composite", None):
        mapper.Modified()


def _depth_uniforms(entry, mapper, volume) -> bool:
    """The value-as-depth mapping of the piece ``mapper`` draws now (:func:`depth_mapping`) on ``volume``'s
    uniforms; False when it has no scalars."""
    own = not _import_mipcast().METHODS[entry.mapper_method].float_readout  # VTK's own mapper
    rendered = mapper.GetInput() if own else mapper.GetRenderedInput()
    scalars = rendered.GetPointData().GetScalars() if rendered is not None else None
    if scalars is None:
        return False
    scale, bias = depth_mapping(volume.GetProperty(), scalars, depth_composite_op(entry.mapper_method))
    uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
    uniforms.SetUniformf("u_mc_depthScale", scale)
    uniforms.SetUniformf("u_mc_depthBias", bias)
    return True


# -- parallel render views: DEMIP and the averages by reduction over the ranks --------------
_OPS = {"max": "MAX_OP", "min": "MIN_OP", "sum": "SUM_OP"}


def _all_reduce(array, op):
    """``array`` reduced over every rank of ParaView's global controller (float64 AllReduce)."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkDoubleArray
    from vtkmodules.vtkParallelCore import vtkCommunicator, vtkMultiProcessController

    controller = vtkMultiProcessController.GetGlobalController()
    send = numpy_to_vtk(np.ascontiguousarray(array, dtype=np.float64).ravel(), deep=True)
    receive = vtkDoubleArray()
    receive.SetNumberOfTuples(send.GetNumberOfTuples())
    if not controller.AllReduce(send, receive, getattr(vtkCommunicator, _OPS[op])):
        raise RuntimeError(f"AllReduce ({op}) over {controller.GetNumberOfProcesses()} ranks failed")
    return vtk_to_numpy(receive).astype(np.float64).reshape(np.shape(array))


def _rank_frame(entry, image, whole):
    """At REQUEST_RENDER (every rank, data or not): this frame reduces over the ranks if its method does.

    The reductions run in the renderer's StartEvent (:func:`_rank_start`),
    which every rank's renderer passes in each render (IceT may skip a rank's
    draw when its piece is out of view; the StartEvent it does not skip).
    """
    rule = rank_composite_rule(entry.method) if process_count() > 1 else None
    entry.rank_rule = rule
    entry.rank_picture = None
    if rule != "foveated":
        _spill_bounds(entry, None)
    if rule is None and (process_count() == 1 or depth_composite_op(entry.method) is None):
        entry.rank_pending = False
        return
    entry.rank_pending = True
    entry.rank_piece = image
    if image is not None and whole is not None:
        direction = image.GetDirectionMatrix()
        entry.rank_whole = (tuple(int(v) for v in whole), image.GetOrigin(), image.GetSpacing(),
                            [direction.GetElement(i, j) for i in range(3) for j in range(3)])
    renderer = entry.renderer.Get()
    if renderer is not None and getattr(entry, "rank_observed", None) != renderer.GetAddressAsString("vtkObjectBase"):
        from vtkmodules.vtkCommonCore import vtkCommand

        renderer.AddObserver(vtkCommand.StartEvent, _rank_start(entry), -100.0)  # after the camera sync
        # the spill prop only inside a render (IceT's box); outside, ResetCamera's bounds stay the data's
        renderer.AddObserver(vtkCommand.EndEvent, lambda caller, event, entry=entry: _spill_bounds(entry, None))
        entry.rank_observed = renderer.GetAddressAsString("vtkObjectBase")


def _rank_start(entry):
    def start(renderer, event, entry=entry):
        if not getattr(entry, "rank_pending", False):
            return
        entry.rank_pending = False
        from mipcast.mappers import rank_composite, rank_foveated

        mapper = entry.mapper if entry.mapper_method == entry.method else None
        piece = entry.rank_piece if mapper is not None else None
        volume = None
        if mapper is not None:  # VTK's own mapper knows no attached volume: the representation's (_set_composite)
            volume = mapper.GetAttachedVolume() if hasattr(mapper, "GetAttachedVolume") else entry.own_volume.Get()
        whole = getattr(entry, "rank_whole", None)
        try:
            if entry.rank_rule is None:  # composited by depth: the missing values' fill agreed on
                rgba, problem = None, _whole_fill(entry, mapper, volume, piece)[1]
            elif entry.rank_rule == "foveated":
                rgba, problem = rank_foveated.compose(mapper, volume, renderer, piece, whole, _all_reduce)
            else:
                brick = rank_brick(entry.method)
                if brick is not None:  # VTK's own mapper: its piece as it draws it, filled as the whole volume
                    piece = _whole_fill(entry, mapper, volume, piece)[0]
                rgba, problem = rank_composite.compose(mapper, volume, renderer, piece, whole, _all_reduce,
                                                       entry.rank_rule, rank=(process_index(), process_count()),
                                                       brick=brick)
        except Exception as error:  # noqa: BLE001  (never into C++)
            rgba, problem = None, repr(error)
        entry.rank_picture = rgba
        if entry.rank_rule == "foveated":
            from mipcast.core.object_state import object_state

            drawn = mapper is not None and rgba is not None
            bounds = object_state(mapper).get("rank_foveated_bounds") if drawn else None
            _spill_bounds(entry, bounds, renderer)
        from mipcast.mappers.rank_composite import projection

        entry.rank_projection = projection(renderer)  # IceT shifts it for each rank's draw
        if problem is not None and problem != getattr(entry, "rank_problem", None):
            _report(problem if problem.startswith(entry.method) else
                    f"{entry.method} on {process_count()} ranks: {problem}")
        entry.rank_problem = problem
        entry.rank_piece = None
    return start


def _whole_fill(entry, mapper, volume, piece):
    """At the renderer's StartEvent (every rank): the pieces' finite ranges and missing values, reduced; where
    some piece holds missing values each rank's piece fills them as the whole volume does.  Returns (the piece
    as this rank's mapper draws it, None), or (None, why) when that failed.

    A mipcast mapper fills them itself (its preparer's whole range).  VTK's own
    mapper draws its preparer's output (:func:`_prepare_own`), filled here
    again relative to the whole volume's finite range (``fill = low - span``
    or ``high + span`` for MinIP, as one rank's preparer fills the whole
    volume): every piece's samples are the whole volume's; for the depth route
    its value-as-depth mapping follows the filled piece's range
    (:func:`_depth_uniforms`), for ``stock_average`` the filled piece is what
    its reduction reads out (:func:`mipcast.mappers.rank_composite.compose`).
    """
    import numpy as np

    from mipcast.mappers.rank_composite import piece_range

    low, high, missing = piece_range(piece)
    reduced = _all_reduce(np.array([-low, high, float(missing)]), "max")
    low, high, missing = float(-reduced[0]), float(reduced[1]), bool(reduced[2] > 0.0)
    if mapper is None:
        return None, None
    whole_range = (low, high) if missing and high >= low else None
    preparer = getattr(entry, "preparer", None)
    if preparer is None:  # a mipcast mapper: its own preparer
        mapper.GetInputPreparer().SetWholeRange(whole_range)
        return piece, None
    try:
        preparer.SetWholeRange(whole_range)
        preparer.Update()
        problem = preparer.GetProblem()
        if problem is not None:
            if volume is not None:
                volume.SetVisibility(False)  # this frame (REQUEST_RENDER sets it again)
            return None, f"{entry.method}: {problem}"
        drawn = mapper.GetInput()  # the preparer's output where it changed the data (_prepare_own), else the piece
        if entry.rank_rule is None and volume is not None:
            _depth_uniforms(entry, mapper, volume)
        return drawn, None
    except Exception as error:  # noqa: BLE001  (reported; the frame draws nothing)
        if volume is not None:
            volume.SetVisibility(False)
        return None, repr(error)


def _spill_bounds(entry, bounds, renderer=None) -> None:
    """Show (``bounds``) or hide (None) the representation's spill prop: an actor of two vertices at the
    corners of ``bounds``, which cover the foveated coarse levels' stretch beyond the volume's outline.  It
    draws nothing: its mapper clips everything away (a clipping plane beyond the box; an actor's bounds
    are its input's, whatever the planes, but only the points its cells use: vtkPolyData.GetCellsBounds).

    IceT keeps each rank's pixels only inside the projection of the bounds of the props the rank shows
    (vtkIceTCompositePass: the renderer's ComputeVisiblePropBounds -> icetBoundingBoxd), computed after the
    renderer's StartEvent, where this runs: :func:`mipcast.mappers.rank_foveated.spill_bounds`.  Shown
    only during the render (hidden again at the renderer's EndEvent): ParaView's ResetCamera reduces the
    same visible prop bounds, and must see the data's.
    """
    actor = getattr(entry, "spill_actor", None)
    if bounds is None:
        if actor is not None:
            actor.VisibilityOff()
        return
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPlane, vtkPolyData
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    if actor is None:
        actor, mapper, points, plane = vtkActor(), vtkPolyDataMapper(), vtkPoints(), vtkPlane()
        points.SetNumberOfPoints(2)
        data = vtkPolyData()
        data.SetPoints(points)
        verts = vtkCellArray()
        verts.InsertNextCell(2, [0, 1])
        data.SetVerts(verts)
        mapper.SetInputData(data)
        plane.SetNormal(1.0, 0.0, 0.0)  # keeps x >= its origin's: none of the box
        mapper.AddClippingPlane(plane)
        actor.SetMapper(mapper)
        actor.PickableOff()
        entry.spill_actor, entry.spill_points, entry.spill_plane = actor, points, plane
    entry.spill_plane.SetOrigin(bounds[1] + 1.0 + abs(bounds[1] - bounds[0]), 0.0, 0.0)
    if renderer is not None and not renderer.HasViewProp(actor):
        renderer.AddViewProp(actor)
    points = entry.spill_points
    points.SetPoint(0, bounds[0], bounds[2], bounds[4])
    points.SetPoint(1, bounds[1], bounds[3], bounds[5])
    points.Modified()
    actor.GetMapper().GetInput().Modified()
    actor.VisibilityOn()


def _rank_mapper(entry, mapper):
    """Observers on the mapper: while its method reduces over the ranks, the reduced picture replaces its draw."""
    if getattr(entry, "rank_observers", None) is mapper:
        return
    from vtkmodules.vtkCommonCore import vtkCommand

    from mipcast.core.object_state import object_state

    def start(mapper, event, entry=entry):
        if getattr(entry, "rank_rule", None) is None:
            return
        state = object_state(mapper)
        state["rank_own_draw"] = (mapper.GetCropping(), mapper.GetCroppingRegionPlanes())
        rgba = getattr(entry, "rank_picture", None)
        renderer = entry.renderer.Get()
        if rgba is not None and renderer is not None:
            from mipcast.mappers.rank_composite import draw

            width, height, x0, y0 = [0], [0], [0], [0]
            renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
            if rgba.shape[:2] == (height[0], width[0]):
                from mipcast.mappers.rank_composite import ndc_transform, projection

                ndc = ndc_transform(entry.rank_projection, projection(renderer))
                draw(state, renderer, rgba, ndc)
        mapper.SetCropping(True)  # never the own draw: invalid planes make VTK skip it silently
        mapper.SetCroppingRegionPlanes(1.0, 0.0, 1.0, 0.0, 1.0, 0.0)

    def end(mapper, event, entry=entry):
        saved = object_state(mapper).pop("rank_own_draw", None)
        if saved is not None:
            mapper.SetCropping(saved[0])
            mapper.SetCroppingRegionPlanes(*saved[1])

    mapper.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, start, 20.0)
    mapper.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, end, -20.0)
    entry.rank_observers = mapper


@_guarded
def prepare(key, volume, assign, renderer, interactor, whole=None, cells=False):
    """Before a frame: the volume's mapper for the current method, up to date; False hides it.

    ``assign`` is the C++ representation's ``vtkAssignAttribute`` (the
    coloured array made the active scalars) fed by ParaView's delivered
    piece; ``cells``: that array is a cell array (drawn at the cell centres,
    :func:`mipcast.core.prepare.cell_centres`).  A multi-component array is
    drawn as ParaView colours it (:func:`coloured_component`).  A process
    without data (a client of a remote server) hides the volume quietly;
    unusable data is refused by the mipcast mapper itself with a message.
    """
    _import_mipcast()
    entry = _entry(key)
    if renderer is not None and entry.render_window.Get() is not renderer.GetRenderWindow():
        entry.render_window.Set(renderer.GetRenderWindow())  # weak: the view owns its window
    if renderer is not None and entry.renderer.Get() is not renderer:
        entry.renderer.Set(renderer)
    assign.Update()
    image = assign.GetOutputDataObject(0)
    usable = image is not None and image.GetNumberOfPoints() > 0 and image.IsA("vtkImageData")
    _rank_frame(entry, image if usable else None, whole)  # before any return: every rank reduces
    refused = rank_refusal(entry.method, process_count()) if process_count() > 1 else None
    if refused is None and cells and process_count() > 1:
        refused = (f"a cell array cannot be drawn on {process_count()} ranks: each rank's piece is drawn between "
                   "its own cell centres, which leaves a seam half a cell wide on each side of every boundary "
                   "between pieces; colour by a point array (Cell Data to Point Data) or render on one rank")
    if refused is not None:  # never a silently wrong picture: hidden, said once per method
        if getattr(entry, "refused", None) != entry.method:
            _report(refused)
            entry.refused = entry.method
        entry.problem = refused
        return False
    entry.refused = None
    if not usable:
        _live_without_data(key, entry, interactor, renderer, image)
        return False
    port = _source_port(entry, assign, cells)
    image = port.GetProducer().GetOutputDataObject(port.GetIndex())
    if entry.mapper is None or entry.mapper_method != entry.method:
        _new_mapper(entry, volume, port)
    elif volume.GetMapper() is not entry.mapper:
        from mipcast.methods import attach
        attach(entry.mapper, volume)
    mapper = entry.mapper
    _connect(entry, port)
    component = coloured_component(volume.GetProperty(), image)
    if entry.preparer is not None and not _prepare_own(entry, port, component):
        return False
    if entry.preparer is None and mapper.GetComponent() != (-1 if component is None else component):
        mapper.SetComponent(component)
    # no per-frame _apply: set_value applies a value of the drawing method at once and
    # _new_mapper applies all of a method's values (a refused value is reported once, not
    # at every frame)
    _set_composite(entry, volume, image, whole)
    _rank_mapper(entry, mapper)
    common = entry.applied
    spacing = min(abs(s) for s in image.GetSpacing()) or 1.0
    distance = common.get("common_sample_distance", 0.0) or spacing
    if mapper.GetSampleDistance() != distance:
        mapper.SetSampleDistance(distance)
    if hasattr(mapper, "SetImageSampleDistance"):
        isd = common.get("common_image_sample_distance", 1.0)
        if mapper.GetImageSampleDistance() != isd:
            mapper.SetImageSampleDistance(isd)
    if hasattr(mapper, "FollowMouse"):
        _gaze_source(entry, mapper, interactor, common)
        _live().watch_refinement(key, entry, interactor)
    return True


def coloured_component(volume_property, image):
    """What ParaView colours of a multi-component array: None (*Magnitude*) or the component (*X*, *Y*, ...).

    Read from the colour map on ``volume_property`` (ParaView's lookup table:
    ``VectorMode`` Magnitude or Component, ``VectorComponent``), which
    ``ColorBy(display, ("POINTS", "vec", "X"))`` and the colouring menu set.
    One-component arrays: None (drawn as they are).
    """
    data = image.GetPointData().GetScalars() or image.GetCellData().GetScalars()
    colours = volume_property.GetRGBTransferFunction(0)
    if data is None or data.GetNumberOfComponents() < 2 or not hasattr(colours, "GetVectorMode"):
        return None
    if colours.GetVectorMode() == colours.COMPONENT:
        return int(colours.GetVectorComponent())  # one the array lacks is refused by the preparer
    return None


def _source_port(entry, assign, cells):
    """The port the mapper draws from: ``assign``'s (the coloured array made the active scalars); for a
    cell array, that array alone (``vtkPassArrays``: no point array left to draw instead, so it is
    drawn at the cell centres), brought up to date."""
    if not cells:
        return assign.GetOutputPort()
    keep = getattr(entry, "cells_only", None)
    if keep is None:
        from vtkmodules.vtkCommonDataModel import vtkDataObject
        from vtkmodules.vtkFiltersGeneral import vtkPassArrays

        keep = entry.cells_only = vtkPassArrays()  # shares the array
        keep.UseFieldTypesOn()
        keep.AddFieldType(vtkDataObject.POINT)  # no point array is listed: none passes
        keep.AddFieldType(vtkDataObject.CELL)
        keep.SetInputConnection(assign.GetOutputPort())
        entry.cells_only_name = None
    scalars = assign.GetOutputDataObject(0).GetCellData().GetScalars()
    name = scalars.GetName() if scalars is not None else None
    if entry.cells_only_name != name:
        keep.ClearArrays()
        keep.AddCellDataArray(name or "")
        entry.cells_only_name = name
    keep.Update()
    return keep.GetOutputPort()


def _connect(entry, port):
    """Feed the mapper (VTK's own: its preparer) from ``port``, when that changed."""
    from mipcast.mappers.mip import same_port

    preparer = entry.preparer if entry.preparer is not None else entry.mapper.GetInputPreparer()
    if not (preparer.GetNumberOfInputConnections(0) and same_port(preparer.GetInputConnection(0, 0), port)):
        (entry.preparer if entry.preparer is not None else entry.mapper).SetInputConnection(port)


def _prepare_own(entry, source, component):
    """VTK's own mapper (stock, cpu): the preparer's one component when the data needs it, else the
    delivered data itself (the same pipeline as ParaView's); False (reported once) when unusable."""
    from mipcast.mappers.mip import same_port

    preparer = entry.preparer
    preparer.SetComponent(component)
    preparer.Update()
    problem = preparer.GetProblem()
    if problem is not None:
        if entry.problem != problem:
            _report(f"{entry.method}: {problem}")
        entry.problem = problem
        return False
    entry.problem = None
    prepared = preparer.GetPrepared()
    port = source if not (prepared.changed or prepared.cells) else preparer.GetOutputPort()
    if not same_port(entry.mapper.GetInputConnection(0, 0), port):
        entry.mapper.SetInputConnection(port)
    return True


def _live():
    """mipcast_representation_live (refinement timer, client mouse gaze), next to this module."""
    if _HERE not in sys.path:
        sys.path.append(_HERE)
    import mipcast_representation_live

    return mipcast_representation_live


def _live_without_data(key, entry, interactor, renderer, image):
    """A process without data (a client of a remote server): its interactor drives the server's
    foveated mapper, the mouse through the gaze point property, the timer through frame counts."""
    if interactor is None or entry.method != "foveated":
        return
    live = _live()
    if live.remote_client():
        live.watch_client_gaze(key, entry, interactor, renderer)
        live.watch_refinement(key, entry, interactor, remote=True)


def refine(view=None, max_frames=64):
    """pvpython/pvbatch scripts: render ``view`` until its foveated representations have refined to
    full quality (:func:`mipcast_representation_live.refine`); returns the frames rendered."""
    return _live().refine(view, max_frames)


def _gaze_source(entry, mapper, interactor, common):
    """The foveated gaze: the region of interest when one is set, else the mouse (follow_mouse
    on and an interactor: builtin sessions; the gaze point until the mouse first moves), else
    the gaze point.  Setting the gaze point or clearing the region makes the mapper's source
    "point": with follow_mouse on the mouse takes over again here."""
    if common.get("region_of_interest") is not None:
        return  # SetRegionOfInterest made it the source
    follow = bool(common.get("follow_mouse", True)) and interactor is not None
    source = mapper.GetGazeSource()
    address = interactor.GetAddressAsString("vtkObjectBase") if follow else None
    if follow and (source != "mouse" or getattr(entry, "interactor", None) != address):
        mapper.FollowMouse(interactor)  # the mapper holds it weakly; so does the entry (its address)
        entry.interactor = address
    elif not follow and source == "mouse":
        mapper.FollowMouse(None)  # back to the panel's gaze point
        entry.interactor = None
        gaze = common.get("gaze_point")
        if gaze is not None:
            mapper.SetGazePoint(*gaze)


@_guarded
@_guarded
def refinement_info(key):
    """(refining, step, frames drawn) of representation ``key`` in this process: its foveated
    mapper needs another frame (1/0), the still frames it has refined (-1: no foveated mapper
    here, e.g. a client of a remote server), the frames the volume drew.

    The C++ getters behind :data:`REFINEMENT_INFO`'s information-only properties; a client
    reads the server's through ``UpdatePropertyInformation`` (``mipcast_representation_live``).

    Examples
    --------
    >>> refinement_info("no such representation")
    (0, -1, 0)
    """
    entry = _REGISTRY.get(key)
    if entry is None:
        return (0, -1, 0)
    mapper = entry.mapper
    if mapper is None or entry.mapper_method != "foveated" or entry.method != "foveated":
        return (0, -1, entry.renders)
    volume = mapper.GetAttachedVolume() if hasattr(mapper, "GetAttachedVolume") else None
    visible = volume is None or bool(volume.GetVisibility())
    return (int(visible and bool(mapper.NeedsRefinement())), int(mapper.GetRefinementStep()), entry.renders)


def release(key):
    """The C++ representation is deleted: drop its mapper."""
    entry = _REGISTRY.pop(key, None)
    if entry is not None and entry.mapper is not None and hasattr(entry.mapper, "Detach"):
        entry.mapper.Detach()
    actor = getattr(entry, "spill_actor", None) if entry is not None else None
    renderer = entry.renderer.Get() if actor is not None and getattr(entry, "renderer", None) is not None else None
    if renderer is not None and renderer.HasViewProp(actor):
        renderer.RemoveViewProp(actor)
    if "mipcast_representation_live" in sys.modules:
        sys.modules["mipcast_representation_live"].release(key)
    return True


def stats():
    """Per representation: method, mapper class, distinct shader programs seen, renders (for tests)."""
    return {key: entry.stats() for key, entry in _REGISTRY.items()}


def _main(argv):
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--xml", help="write the ServerManager XML here")
    parser.add_argument("--header", help="write the C++ header here (needs --template)")
    parser.add_argument("--template", help="the header template with @MIPCAST_SETTERS@")
    parser.add_argument("--table", action="store_true", help="print plugin_methods() as JSON")
    args = parser.parse_args(argv)
    methods = plugin_methods()
    if args.xml:
        _write(args.xml, server_manager_xml(methods))
    if args.header:
        with open(args.template) as handle:
            template = handle.read()
        _write(args.header, template.replace("@MIPCAST_SETTERS@", cxx_setters(methods)))
    if args.table:
        import json
        print(json.dumps(methods, indent=1, default=str))


def _write(path, text):
    """Write ``text`` unless the file already holds it (no needless rebuilds)."""
    if os.path.exists(path):
        with open(path) as handle:
            if handle.read() == text:
                return
    with open(path, "w") as handle:
        handle.write(text)


if __name__ == "__main__":
    _main(sys.argv[1:])
