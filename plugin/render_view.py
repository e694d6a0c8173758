"""mipcast live in ParaView's render view (builtin session only).

ParaView's own volume representation keeps its ``vtkVolume`` out of Python's
reach, but in a *builtin* session (the GUI or pvpython without a server
connection) the render view's ``vtkRenderer`` lives in the same process.
:func:`show` adds a ``vtkVolume`` with a mipcast mapper to it:

- its input is the source's client-side output port (through a
  ``vtkAssignAttribute`` that makes the chosen point array the active
  scalars), so upstream changes (*Apply*, changed properties) flow through;
- its colour and opacity are ParaView's own transfer functions for that
  array (``GetColorTransferFunction(name)`` / ``GetOpacityTransferFunction(name)``,
  the client-side objects themselves), so the colour map editor changes the
  mipcast picture live;
- the source keeps a representation of its own, an *Outline* coloured by the
  same array: ParaView's *Reset Camera* works from its representations'
  bounds, and the colour map editor and colour legend follow the active
  representation's array.  Re-colour the outline by another point array
  (Properties panel, ``ColorBy``) and the volume renders that array at the
  next frame;
- before each frame the volume's input asks for the view's time (time
  series follow the animation) and the volume is hidden, with one warning in
  ParaView's output window, while its input is unusable (e.g. the array was
  renamed upstream).

The volume is not a ParaView representation: it has no eye toggle in the
pipeline browser, state files do not save it, and remote (client-server)
sessions cannot use it (the data live on the server) -- there use the
``mipcast MIP Render`` filter of ``mipcast_paraview.py``.

Nothing from ParaView is imported at module level: the functions import
``paraview.simple`` when called.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple, Optional, Tuple

if TYPE_CHECKING:  # for annotations only: importing VTK here is not needed
    from vtkmodules.vtkRenderingCore import vtkVolume

__all__ = ["show", "hide", "shown", "ShownVolume"]

#: (view GlobalID, source GlobalID) -> _Entry, for every volume :func:`show` added.
_SHOWN: dict = {}
#: view GlobalID -> (its vtkRenderer, the tag of our one StartEvent observer on it).
_OBSERVED: dict = {}
#: (session proxy manager, tag of our UnRegisterEvent observer): Delete() prunes at once.
_MANAGERS: list = []


class ShownVolume(NamedTuple):
    """One volume added by :func:`show`: what is shown where."""

    source: Any
    """The source proxy whose output is rendered."""
    view: Any
    """The render view proxy."""
    method: str
    """A name of :data:`mipcast.METHODS`."""
    array: str
    """The point array rendered."""
    volume: Any
    """The ``vtkVolume`` in the view's renderer (its mapper is ``volume.GetMapper()``)."""


class _Entry:
    """Everything :func:`hide` needs to undo :func:`show`, and the per-frame work."""

    def __init__(self, shown: ShownVolume, view_object, assign, outline, saved) -> None:
        self.shown = shown
        self.view_object = view_object
        self.assign = assign
        self.outline = outline  # the display show() made an Outline, or None
        self.saved = saved  # (visible, representation, colouring) before that, or None
        self.problem: Optional[str] = None  # why the volume is hidden, if it is
        self.component: Optional[int] = None  # the drawn component (None: the magnitude)
        self.preparer = None  # VTK's own mappers: the InputPreparer in front of them

    def before_frame(self) -> None:
        """Bring the volume's input up to date at the view's time; hide it while unusable.

        VTK's mappers must never see an input without point scalars (VTK's
        CPU mapper segfaults), e.g. after the array was renamed upstream, nor
        a component the array does not have: the volume is hidden until the
        array is back.
        """
        from vtkmodules.vtkCommonCore import vtkOutputWindow
        from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

        if self.outline is not None:  # re-coloured (Properties panel, ColorBy)? follow
            association, name = self.outline.ColorArrayName
            if association == "POINTS" and name and name != self.shown.array:
                self.shown = self.shown._replace(array=name)
                _link(self.assign, self.shown.volume, name)
        self.assign.GetOutputInformation(0).Set(
            vtkStreamingDemandDrivenPipeline.UPDATE_TIME_STEP(), self.view_object.GetViewTime())
        self.assign.Update()
        problem = _problem(self.assign.GetOutputDataObject(0), self.shown.array, self.component)
        self.shown.volume.SetVisibility(problem is None)
        if problem != self.problem:  # reported once per change
            self.problem = problem
            source = _name(self.shown.source, "sources")
            if problem is None:
                vtkOutputWindow.GetInstance().DisplayText(
                    f"mipcast: the {self.shown.method!r} volume of {source} is shown again\n")
            else:
                vtkOutputWindow.GetInstance().DisplayWarningText(
                    f"mipcast: the {self.shown.method!r} volume of {source} is hidden: {problem}. "
                    f"It comes back when the array does; or show another array with "
                    f"mipcast.plugin.render_view.show(array=...), or remove it with hide()\n")


def show(source: Any = None, view: Any = None, method: str = "mip",
         array: Optional[str] = None, *, component: Any = None, outline: bool = True,
         **settings: Any) -> "vtkVolume":
    """Render a source's volume with a mipcast method in a ParaView render view.

    Adds a ``vtkVolume`` with the mipcast mapper for ``method`` to the render
    view's renderer.  Showing the same source in the same view again replaces
    the method (and settings); there is never a second volume.  Call
    ``Render()`` afterwards.

    Parameters
    ----------
    source : paraview proxy, optional
        A pipeline source or filter whose output is image data
        (``vtkImageData``).  Default: the active source.
    view : paraview render view proxy or vtkPVRenderView, optional
        Default: the active view (a render view).
    method : str, default: "mip"
        A name from ``mipcast.METHODS``.
    array : str, optional
        The point array to render.  Default: the source's active point
        scalars, else its first point array.
    component : int or "magnitude", optional
        Which component of a multi-component array to draw: as ParaView
        colours it, the magnitude by default, or component ``k`` (the array's
        colour map is set to the same vector mode, so the colour legend
        agrees).  One-component arrays are drawn as they are.
    outline : bool, default: True
        Show the source itself as an Outline coloured by ``array`` (the
        colour map editor and colour legend then show the volume's colours,
        and ParaView's camera knows the volume's bounds); re-colouring that
        outline by another point array re-colours the volume too.  False
        leaves the source's representation as it is (and the volume keeps
        ``array``).
    **settings
        Mapper settings as keyword arguments, ``name=value`` calling
        ``mapper.SetName(value)`` (see :func:`mipcast.core.parameters.set_parameters`),
        e.g. ``depth_weight=0.2`` for "demip" or ``sample_distance=0.5``.
        Defaults: one sample per voxel (the smallest spacing), no
        auto-adjust, no jittering.

    Returns
    -------
    vtkVolume
        The volume added to the view's renderer.

    Raises
    ------
    RuntimeError
        In a remote (client-server) session, or without an active source or
        render view.
    TypeError, ValueError
        Unusable data (not image data, a component the array does not have,
        every value NaN/Inf, no point array, ...), an unknown method or
        setting; the message names the fix.

    Examples
    --------
    In pvpython or the GUI's Python shell::

        from paraview.simple import *
        from mipcast.plugin.render_view import show, hide
        wavelet = Wavelet()
        volume = show(wavelet, GetActiveViewOrCreate("RenderView"), method="analytic")
        ResetCamera()
        Render()
        show(wavelet, method="demip", depth_weight=0.3)   # replaces the method
        Render()
        hide(wavelet)
    """
    from vtkmodules.vtkFiltersCore import vtkAssignAttribute
    from vtkmodules.vtkRenderingCore import vtkVolume

    from mipcast.methods import METHODS, attach, create_mapper
    from mipcast.core.parameters import set_parameters
    from mipcast.core.prepare import check_component, prepare_scalars
    from mipcast.core.validation import check_image, check_positive
    from mipcast.mappers.input_preparer import InputPreparer, fill_side

    simple = _simple()
    source = _source(source)
    view, view_object = _view(view)
    _refuse_remote(view)

    source.UpdatePipeline()
    algorithm = source.GetClientSideObject()
    data = algorithm.GetOutputDataObject(0)
    name = _array_name(source, data, array)

    assign = vtkAssignAttribute()
    assign.SetInputConnection(algorithm.GetOutputPort(0))
    assign.Assign(name, "SCALARS", "POINT_DATA")  # for check_image; _link sets it again
    assign.Update()
    image = assign.GetOutputDataObject(0)
    component = check_component(component)
    check_image(image, component)  # raises naming the problem and the fix
    prepared = prepare_scalars(image, component)  # the drawn values' finite range (magnitude, component)
    low, high = prepared.low, prepared.high
    if not high > low:
        low, high = low - 1.0, high + 1.0

    mapper = create_mapper(method)
    preparer = None
    if METHODS[method].float_readout:  # a mipcast mapper: its own preparer draws the component
        mapper.SetComponent(-1 if component is None else component)
        mapper.SetInputConnection(assign.GetOutputPort())
    else:  # VTK's own mappers: one component, missing values filled, through a preparer in front
        preparer = InputPreparer(fill_side(METHODS[method].projection))
        preparer.SetComponent(component)
        preparer.SetInputConnection(assign.GetOutputPort())
        mapper.SetInputConnection(preparer.GetOutputPort())
    mapper.SetAutoAdjustSampleDistances(False)
    mapper.SetSampleDistance(check_positive(
        "sample distance", min(abs(s) for s in image.GetSpacing())))
    if hasattr(mapper, "SetUseJittering"):  # the CPU peer has none
        mapper.SetUseJittering(False)
    set_parameters(mapper, **settings)  # checks every name before setting any

    lut = simple.GetColorTransferFunction(name)
    pwf = simple.GetOpacityTransferFunction(name)
    if image.GetPointData().GetScalars().GetNumberOfComponents() > 1:  # colour as drawn
        if component is None:
            lut.VectorMode = "Magnitude"
        else:
            lut.VectorMode = "Component"
            lut.VectorComponent = component
    _prune_deleted()
    key = _key(view, source)
    previous = _SHOWN.get(key)
    display, saved = None, previous.saved if previous is not None else None
    if outline:
        existing = simple.servermanager.GetRepresentation(source, view)
        visible = existing is not None and bool(existing.Visibility)
        display = simple.Show(source, view)
        if saved is None:  # what hide() restores
            saved = (visible, display.SMProxy.GetProperty("Representation").GetElement(0),
                     list(display.ColorArrayName))
        display.SetRepresentationType("Outline")
        # not simple.ColorBy: it rescales even a colour range the user locked
        display.SetScalarColoring(name, simple.servermanager.GetAssociationFromString("POINTS"))
    if lut.AutomaticRescaleRangeMode != "Never":  # a range the user locked stays
        lut.RescaleTransferFunction(low, high)
        pwf.RescaleTransferFunction(low, high)

    _SHOWN.pop(key, None)
    volume = previous.shown.volume if previous is not None else vtkVolume()
    if previous is not None:
        _remove(previous, keep_volume=True)
    _link(assign, volume, name)
    volume.PickableOff()  # ParaView's selection works on representations only
    attach(mapper, volume)
    if previous is None:
        view_object.AddPropToRenderer(volume)
    entry = _SHOWN[key] = _Entry(ShownVolume(source, view, method, name, volume), view_object, assign,
                                 display, saved)
    entry.component, entry.preparer = component, preparer
    _observe(key[0], view_object.GetRenderer(), view.SMProxy.GetSessionProxyManager())
    return volume


def hide(source: Any = None, view: Any = None) -> bool:
    """Remove the volume :func:`show` added for ``source`` in ``view``.

    The source's own representation in ``view`` gets back the visibility,
    representation type and colouring it had before :func:`show` made it an
    Outline.

    Parameters
    ----------
    source : paraview proxy, optional
        Default: the active source.
    view : paraview render view proxy or vtkPVRenderView, optional
        Default: the active view.

    Returns
    -------
    bool
        True if a volume was removed, False if none was shown.

    Examples
    --------
    ::

        from mipcast.plugin.render_view import show, hide
        show(method="mip")
        Render()
        hide()      # the active source, the active view
        Render()
    """
    source = _source(source)
    view, _ = _view(view)
    _prune_deleted()
    entry = _SHOWN.pop(_key(view, source), None)
    if entry is None:
        return False
    _remove(entry)
    if entry.saved is not None:
        _restore(entry.outline or _simple().GetDisplayProperties(source, view), *entry.saved)
    return True


def shown(view: Any = None) -> Tuple[ShownVolume, ...]:
    """The volumes :func:`show` added to ``view`` and that are still there.

    Parameters
    ----------
    view : paraview render view proxy or vtkPVRenderView, optional
        Default: the active view.

    Returns
    -------
    tuple of ShownVolume
        ``(source, view, method, array, volume)`` records, oldest first.

    Examples
    --------
    ::

        from mipcast.plugin.render_view import show, shown
        show(method="analytic")
        [(s.method, s.array) for s in shown()]     # [('analytic', 'RTData')]
    """
    view, _ = _view(view)
    _prune_deleted()
    prefix = view.GetGlobalIDAsString()
    return tuple(entry.shown for (view_id, _), entry in _SHOWN.items() if view_id == prefix)


# -- helpers ------------------------------------------------------------------------------
def _simple():
    """``paraview.simple``, or an ImportError that says where to run this."""
    try:
        import paraview.simple as simple
    except ImportError as error:
        raise ImportError(
            "mipcast.plugin.render_view needs ParaView's Python: run it in pvpython or in "
            "the ParaView GUI's Python shell or macros (for plain VTK or pyvista use "
            f"mipcast.create_mapper / mipcast.filters.add_volume) ({error})") from None
    return simple


def _source(source):
    simple = _simple()

    if source is None:
        source = simple.GetActiveSource()
        if source is None:
            raise RuntimeError(
                "mipcast: no active source; select the volume in the Pipeline Browser "
                "or pass source=")
    if not hasattr(source, "GetClientSideObject"):
        raise TypeError(
            f"mipcast: source must be a ParaView source proxy (e.g. GetActiveSource()), "
            f"got {type(source).__name__}")
    return source


def _view(view):
    """(render view proxy, its client-side vtkPVRenderView)."""
    simple = _simple()

    if view is None:
        view = simple.GetActiveView()
        if view is None:
            raise RuntimeError("mipcast: no active view; click into a render view or pass view=")
    if not hasattr(view, "GetClientSideObject"):  # a vtkPVRenderView itself
        matches = [v for v in simple.GetViews() if v.GetClientSideObject() is view]
        if not matches:
            raise TypeError(f"mipcast: view must be a render view proxy, got {type(view).__name__}")
        view = matches[0]
    view_object = view.GetClientSideObject()
    if view_object is None or not view_object.IsA("vtkPVRenderView"):
        kind = view.GetXMLName() if hasattr(view, "GetXMLName") else type(view).__name__
        raise TypeError(
            f"mipcast: a render view (3D) is needed, got a {kind}; click into a render "
            "view first or pass view=GetActiveViewOrCreate('RenderView')")
    return view, view_object


def _refuse_remote(view) -> None:
    session = view.GetSession()
    if session is not None and session.IsA("vtkSMSessionClient"):
        raise RuntimeError(
            "mipcast: showing a mipcast volume in the render view needs a builtin session "
            "(the data and the renderer in this process); this ParaView is connected to a "
            "remote server. Use the 'mipcast MIP Render' filter (plugin/mipcast_paraview.py, "
            "loaded on the server) instead.")


def _array_name(source, data, array: Optional[str]) -> str:
    """The point array to render: ``array``, else the active scalars, else the first."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    if not isinstance(data, vtkImageData):
        kind = "nothing" if data is None else type(data).__name__
        raise TypeError(
            f"mipcast: the source's output must be image data (vtkImageData), got {kind}; "
            "apply Filters > Resample To Image first (for multiblock data, Merge Blocks, "
            "then Resample To Image)")
    points = data.GetPointData()
    names = [points.GetArrayName(i) for i in range(points.GetNumberOfArrays())]
    if array is None:
        scalars = points.GetScalars()
        array = scalars.GetName() if scalars is not None and scalars.GetName() else None
        if array is None and names:
            array = names[0]
        if array is None:
            cells = [data.GetCellData().GetArrayName(i)
                     for i in range(data.GetCellData().GetNumberOfArrays())]
            hint = (f" (it has cell arrays {cells}: apply Filters > Cell Data to Point Data)"
                    if cells else "")
            raise ValueError(f"mipcast: the source has no point array to render{hint}")
    if array not in names:
        raise ValueError(
            f"mipcast: the source has no point array {array!r}; its point arrays are "
            f"{names or 'none'} (cell arrays: apply Filters > Cell Data to Point Data first)")
    return array


def _key(view, source) -> tuple:
    return view.GetGlobalIDAsString(), source.GetGlobalIDAsString()


def _remove(entry: _Entry, keep_volume: bool = False) -> None:
    """Undo what :func:`show` did in the renderer (``entry`` is already out of ``_SHOWN``)."""
    from mipcast.methods import detach

    volume = entry.shown.volume
    detach(volume.GetMapper())
    if not keep_volume:
        entry.view_object.RemovePropFromRenderer(volume)
    view_id = entry.shown.view.GetGlobalIDAsString()
    if view_id in _OBSERVED and not any(key[0] == view_id for key in _SHOWN):
        renderer, tag = _OBSERVED.pop(view_id)
        renderer.RemoveObserver(tag)


def _observe(view_id: str, renderer, manager) -> None:
    """One StartEvent observer per view renderer: the per-frame work for its volumes.

    And one UnRegisterEvent observer per session proxy manager: deleting a
    source or view (``Delete``, the GUI) drops its volumes at once, so
    nothing here keeps a deleted view alive.
    """
    if not any(known is manager for known, _ in _MANAGERS):
        _MANAGERS.append((manager, manager.AddObserver("UnRegisterEvent", _prune_deleted)))
    if view_id in _OBSERVED:
        return

    def before_frame(*_event) -> None:  # holds the view's id only, never the view
        _prune_deleted()
        for (key_view, _), entry in list(_SHOWN.items()):
            if key_view == view_id:
                entry.before_frame()

    _OBSERVED[view_id] = (renderer, renderer.AddObserver("StartEvent", before_frame))


def _restore(display, visible: bool, representation: str, colouring: list) -> None:
    """Give ``display`` back the state :func:`show` saved."""
    simple = _simple()
    association, name = colouring
    display.SetRepresentationType(representation)
    if name:
        display.SetScalarColoring(name, simple.servermanager.GetAssociationFromString(association))
    else:
        display.ColorArrayName = [association, ""]
    display.Visibility = int(visible)


def _link(assign, volume, name: str) -> None:
    """Render point array ``name``: the active scalars, coloured by ParaView's functions for it."""
    from vtkmodules.vtkRenderingCore import vtkVolumeProperty

    simple = _simple()
    assign.Assign(name, "SCALARS", "POINT_DATA")
    prop = vtkVolumeProperty()
    prop.SetColor(simple.GetColorTransferFunction(name).GetClientSideObject())
    prop.SetScalarOpacity(simple.GetOpacityTransferFunction(name).GetClientSideObject())
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()
    volume.SetProperty(prop)


def _problem(data, name: str, component: Optional[int] = None) -> Optional[str]:
    """Why ``data`` cannot be rendered (None if it can): image data, point scalars with ``component``."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    if not isinstance(data, vtkImageData):
        kind = "nothing" if data is None else type(data).__name__
        return f"the source's output is {kind}, not image data (vtkImageData)"
    scalars = data.GetPointData().GetScalars()
    if scalars is None:
        return f"the source's output has no point array {name!r} any more (renamed or removed upstream)"
    if component is not None and component >= scalars.GetNumberOfComponents() and component > 0:
        return (f"point array {name!r} has {scalars.GetNumberOfComponents()} component(s), "
                f"component {component} was asked for")
    return None


def _name(proxy, group: str) -> str:
    """The name ``proxy`` has in the Pipeline Browser (or its class)."""
    manager = proxy.SMProxy.GetSessionProxyManager()
    return (manager and manager.GetProxyName(group, proxy.SMProxy)) or proxy.GetXMLName()


def _registered(proxy, group: str) -> bool:
    """Whether ``proxy`` is still registered (not deleted) in the session's proxy manager."""
    manager = proxy.SMProxy.GetSessionProxyManager()
    return manager is not None and bool(manager.GetProxyName(group, proxy.SMProxy))


def _prune_deleted(*_event) -> None:
    """Remove the volumes whose source or view was deleted (``Delete``, the GUI's delete)."""
    for key, entry in list(_SHOWN.items()):
        if not (_registered(entry.shown.source, "sources")
                and _registered(entry.shown.view, "views")):
            del _SHOWN[key]
            _remove(entry)
