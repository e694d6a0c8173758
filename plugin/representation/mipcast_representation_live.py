"""The live parts of ParaView's "mipcast" representation: refinement frames and the client's mouse gaze.

Imported by ``mipcast_representation.prepare()`` (the glue the C++ class
calls at every frame); two jobs, both only where the view has an
interactor (the GUI and pvpython; pvbatch and ``pvserver`` have none):

- **Progressive refinement** (``foveated_progressive``): while camera,
  data, settings and gaze are still, each frame of a refining foveated
  mapper widens its full-quality disc until, after
  ``foveated_refinement_frames`` frames, the picture is the method at full
  quality.  :class:`Refiner` renders those frames: after a frame that
  still needs refinement it starts a one-shot timer on the view's
  interactor (:data:`INTERVAL_MS`), and the timer asks for one more frame
  through ``interactor.Render()``, which ParaView's
  ``vtkSMViewProxyInteractorHelper`` turns into the view proxy's
  ``StillRender()`` (the whole view, the Qt widget updated, client-server
  included).  Nothing busy-waits: no timer is pending once the picture has
  converged, none fires a render during an interaction (mouse button
  held), and a change drops the mapper back to the foveated frame, after
  which refinement starts again.  In a client of a remote server the
  mappers live on the server: after each of the client's frames the
  timer is started as well, and when it fires the client reads the
  server's refinement state (the representation's information-only
  properties ``MipcastRefining``, ``MipcastRefinementStep``,
  ``MipcastFramesDrawn``, one ``UpdatePropertyInformation`` round trip,
  :func:`server_refinement`) and asks for a frame only while the server's
  mapper still refines: exactly the frames the server needs, none once it
  has converged, whatever the change was (camera, gaze, a property, the
  colour map, new data) as long as a frame of the client's showed it.  A
  change made on the server alone (no client frame follows it) is not seen
  until the client renders next: nothing polls the server.  The timers need the interactor's event loop (the GUI's
  always runs; pvpython's runs in ``Interact()``); scripts call
  :func:`refine` instead.
- **Mouse gaze in client-server sessions** (``foveated_follow_mouse``): the
  server's view has no interactor, so the client observes its own
  interactor's mouse moves (no button held) and writes the
  representation's ``foveated_gaze_point`` property, which travels to the
  server like any property change, then renders.  Builtin sessions follow
  the local interactor directly (``mipcast_representation._gaze_source``).
"""
from __future__ import annotations

import re

#: Milliseconds between a refining frame and the next (the viewer's and pyvista's interval).
INTERVAL_MS = 40

#: interactor address -> Refiner
_REFINERS: dict = {}
#: representation key -> ClientGaze
_CLIENT_GAZE: dict = {}


def _address(obj) -> int:
    """The C++ address of a VTK object (the C++ representation's key is ``%p`` of it)."""
    text = obj.__this__ if hasattr(obj, "__this__") else obj.GetAddressAsString("vtkObjectBase")
    return int(re.search(r"([0-9a-fA-F]{6,})", text.split("_p_")[0]).group(1), 16)


def _registry():
    import mipcast_representation

    return mipcast_representation._REGISTRY


def _progressive(entry) -> tuple:
    """(progressive on, refinement frames) of the entry's foveated values as ParaView set them."""
    values = entry.values.get("foveated", {})
    on = values.get("progressive", (0,))
    frames = values.get("refinement_frames", (4,))
    return bool(on[0]) if isinstance(on, (tuple, list)) else bool(on), int(frames[0] if isinstance(
        frames, (tuple, list)) else frames)


def remote_client() -> bool:
    """True in the client of a remote server (a ``vtkSMSessionClient`` session)."""
    try:
        from paraview.modules.vtkRemotingServerManager import vtkSMProxyManager
    except ImportError:
        return False
    manager = vtkSMProxyManager.GetProxyManager() if vtkSMProxyManager.IsInitialized() else None
    session = manager.GetActiveSession() if manager is not None else None
    return session is not None and session.IsA("vtkSMSessionClient")


class Refiner:
    """Renders the refining frames of the representations shown in one interactor's view.

    One per interactor: ``watch(key)`` adds a representation (a key of
    ``mipcast_representation._REGISTRY``).  After every frame of the
    interactor's window (its ``EndEvent``), if one of them still needs
    refinement and drew in that frame, a one-shot timer is started; when
    it fires (and no interaction is under way) the interactor renders.
    """

    def __init__(self, interactor, interval_ms: int = INTERVAL_MS):
        from vtkmodules.vtkCommonCore import vtkCommand, vtkWeakReference

        self.link = vtkWeakReference()
        self.link.Set(interactor)
        self.interval_ms = int(interval_ms)
        self.keys: set = set()
        self.timer = None  # the pending one-shot timer's id
        self.interacting = False
        self.requested = False  # the frame being drawn was asked for by our timer
        self.requested_remote = False  # the last frame was asked for by our timer (remote keys)
        self.renders: dict = {}  # key -> the entry's draw count when our timer asked for a frame
        self.remote: set = set()  # keys whose mapper is on the server
        self.server: dict = {}  # key -> the server's (refining, step, frames drawn), last read
        self.frames = 0  # frames this refiner asked for (tests, benchmarks)
        self.pulls = 0  # reads of the server's refinement state (tests)
        self.window = interactor.GetRenderWindow()
        from vtkmodules.util.misc import calldata_type
        from vtkmodules.util.vtkConstants import VTK_INT

        @calldata_type(VTK_INT)
        def tick(caller, event, timer_id=None):
            self._tick(caller, timer_id)

        self.observers = [
            (interactor, interactor.AddObserver(vtkCommand.TimerEvent, tick)),
            (interactor, interactor.AddObserver(vtkCommand.StartInteractionEvent, self._start)),
            (interactor, interactor.AddObserver(vtkCommand.EndInteractionEvent, self._end)),
        ]
        if self.window is not None:
            self.observers.append((self.window, self.window.AddObserver(vtkCommand.EndEvent, self._after_frame)))

    def watch(self, key: str, remote: bool = False) -> None:
        """Watch representation ``key``; ``remote``: its mapper is on the server (its refinement
        state is read from the server's information properties)."""
        self.keys.add(key)
        if remote:
            self.remote.add(key)

    # -- what needs a frame ----------------------------------------------------
    def _needs(self, key, after_frame) -> bool:
        entry = _registry().get(key)
        if entry is None:
            self.keys.discard(key)
            return False
        if key in self.remote:  # the mapper is on the server
            on, _ = _progressive(entry)
            if entry.method != "foveated" or not on:
                return False
            if after_frame:  # the server's state is read when the timer fires, outside the frame
                return True
            state = self.server.get(key)
            if state is None or not state[0]:
                return False
            # a frame we asked for in which the server's volume did not draw: do not ask again
            return not (self.requested_remote and self.renders.get(key) == state[2])
        mapper = entry.mapper
        if mapper is None or entry.mapper_method != "foveated" or not mapper.NeedsRefinement():
            return False
        volume = mapper.GetAttachedVolume() if hasattr(mapper, "GetAttachedVolume") else None
        if volume is not None and not volume.GetVisibility():
            return False
        # a frame we asked for in which the volume did not draw: do not ask again (hidden, culled)
        return not (after_frame and self.requested and self.renders.get(key) == entry.renders)

    def needs_refinement(self) -> bool:
        """Whether one of the watched representations asks for another frame."""
        return any([self._needs(key, False) for key in list(self.keys)])

    # -- observers ---------------------------------------------------------------
    def _start(self, caller, event):
        self.interacting = True

    def _end(self, caller, event):
        self.interacting = False  # ParaView renders a still frame now; its EndEvent re-arms

    def _after_frame(self, caller, event):
        needs = [self._needs(key, True) for key in list(self.keys)]
        self.requested = False
        interactor = self.link.Get()
        if any(needs) and self.timer is None and interactor is not None:
            timer = interactor.CreateOneShotTimer(self.interval_ms)
            self.timer = timer or None  # 0: the interactor takes no timers yet (not initialised)

    def pull(self) -> None:
        """Read the server's refinement state of the remote representations watched."""
        for key in list(self.remote):
            entry = _registry().get(key)
            on = entry is not None and entry.method == "foveated" and _progressive(entry)[0]
            state = server_refinement(key) if on else None
            if state is None:
                self.server.pop(key, None)
            else:
                self.server[key] = state
                self.pulls += 1

    def _tick(self, interactor, timer_id):
        if self.timer is None or (timer_id is not None and timer_id != self.timer):
            return  # another timer (ParaView's delayed still render, the user's)
        self.timer = None
        if self.interacting:
            return
        self.pull()
        if not self.needs_refinement():
            self.requested_remote = False
            return
        registry = _registry()
        self.renders = {key: registry[key].renders for key in self.keys if key in registry}
        self.renders.update({key: self.server[key][2] for key in self.remote if key in self.server})
        self.requested = self.requested_remote = True
        self.frames += 1
        interactor.Render()  # -> vtkSMViewProxyInteractorHelper -> the view proxy's StillRender()

    def stop(self) -> None:
        interactor = self.link.Get()
        if self.timer is not None and interactor is not None:
            interactor.DestroyTimer(self.timer)
        self.timer = None
        for obj, tag in self.observers:
            obj.RemoveObserver(tag)
        self.observers = []


def refiner(interactor):
    """The :class:`Refiner` of ``interactor`` (made at the first call), or None."""
    if interactor is None:
        return None
    address = _address(interactor)
    found = _REFINERS.get(address)
    if found is not None and found.link.Get() is not interactor:
        found.stop()
        found = None
    if found is None:
        found = _REFINERS[address] = Refiner(interactor)
    return found


def watch_refinement(key, entry, interactor, remote=False) -> None:
    """Called by ``prepare()`` each frame: let the interactor's timer render this representation's
    refining frames while its foveated mapper (in a remote client: the server's, read when the timer
    fires) asks for them."""
    if interactor is None:
        return
    on, _ = _progressive(entry)
    if entry.method != "foveated" or not on:
        return
    refiner(interactor).watch(key, remote)


#: vtkPVSession::CLIENT (a proxy's location bit)
_CLIENT = 0x10
#: representation key -> its vtkSMProxy of the MipcastRepresentation (a client's cache)
_PROXIES: dict = {}


def _representation_proxy(key):
    """The MipcastRepresentation (sub)proxy of the client-side representation ``key``, or None."""
    found = _PROXIES.get(key)
    if found is None:
        outer = _proxy_of(key)
        exposed = outer.GetProperty("MipcastMethod") if outer is not None else None
        found = exposed.GetParent() if exposed is not None else None  # the MipcastRepresentation subproxy
        if found is None or found.GetProperty("MipcastRefining") is None:
            return None  # a server plugin without the information properties
        _PROXIES[key] = found
    return found


def server_refinement(key):
    """The server's (refining, step, frames drawn) of representation ``key`` (a client of a
    remote server): its information-only properties, updated by one round trip; None if
    unknown.

    Examples
    --------
    >>> server_refinement.__name__   # in a client: server_refinement(key) -> (1, 2, 17)
    'server_refinement'
    """
    from mipcast_representation import REFINEMENT_INFO

    proxy = _representation_proxy(key)
    if proxy is None:
        return None
    location = proxy.GetLocation()
    server = location & ~_CLIENT
    if server and location != server and remote_client():
        # a proxy on client and servers pulls information from the client's object: ask the servers'
        proxy.SetLocation(server)
        try:
            proxy.UpdatePropertyInformation()  # -> vtkMipcastRepresentation::GetMipcast*() on the server
        finally:
            proxy.SetLocation(location)
    else:
        proxy.UpdatePropertyInformation()
    return tuple(int(proxy.GetProperty(name).GetElement(0)) for name, _ in REFINEMENT_INFO)


def refine(view=None, max_frames: int = 64) -> int:
    """Render ``view`` until every mipcast foveated representation in it has refined to full quality.

    For pvpython and pvbatch scripts, whose event loop (and so the GUI's
    refinement timer) does not run while the script does: call it after
    the change, before ``SaveScreenshot``.  In a builtin session it renders
    while a mapper of this process still refines (at most ``max_frames``);
    in a client of a remote server (the mappers are on the server) it
    renders while the server reports that a mapper still refines (the
    information properties, :func:`server_refinement`).  Returns the
    frames it rendered.

    Examples
    --------
    >>> refine.__name__   # pvpython: import mipcast_representation; mipcast_representation.refine(view)
    'refine'
    """
    from paraview.simple import GetActiveView, Render

    view = GetActiveView() if view is None else view
    registry = _registry()
    renderer = view.GetRenderer() if hasattr(view, "GetRenderer") else None
    local = [e for e in registry.values() if e.mapper is not None and e.mapper_method == "foveated"
             and (renderer is None or e.renderer.Get() is renderer)]
    frames = 0
    if local:
        while frames < max_frames and any(e.mapper.NeedsRefinement() for e in local):
            Render(view)
            frames += 1
        return frames
    remote = [key for key, e in registry.items()
              if e.mapper is None and e.method == "foveated" and _progressive(e)[0]
              and (renderer is None or e.renderer.Get() is renderer)]

    def refining():
        states = [server_refinement(key) for key in remote]
        return any(state is not None and state[0] for state in states)

    while frames < max_frames and remote and refining():
        Render(view)
        frames += 1
    return frames


# -- the client's mouse gaze (client-server) ----------------------------------------------------
def _proxy_of(key):
    """The representation proxy (its exposed properties) whose client-side mipcast representation has ``key``."""
    from paraview.modules.vtkRemotingServerManager import vtkSMProxyIterator, vtkSMProxyManager

    wanted = int(key, 16)
    iterator = vtkSMProxyIterator()
    iterator.SetSession(vtkSMProxyManager.GetProxyManager().GetActiveSession())
    iterator.SetModeToOneGroup()
    iterator.Begin("representations")
    while not iterator.IsAtEnd():
        proxy = iterator.GetProxy()
        client = proxy.GetClientSideObject() if proxy is not None else None
        active = client.GetActiveRepresentation() if client is not None and hasattr(
            client, "GetActiveRepresentation") else None
        if active is not None and _address(active) == wanted:
            return proxy
        iterator.Next()
    return None


class ClientGaze:
    """A client-side observer of the client's interactor: mouse moves write ``foveated_gaze_point``."""

    def __init__(self, key, interactor, renderer):
        from vtkmodules.vtkCommonCore import vtkCommand, vtkWeakReference

        self.key = key
        self.link, self.renderer = vtkWeakReference(), vtkWeakReference()
        self.link.Set(interactor)
        self.renderer.Set(renderer)
        self.proxy = None
        self.moves = 0  # mouse moves turned into gaze points (tests)
        self.interacting = False  # a button held: ParaView renders the interaction, we do not
        self.tags = [interactor.AddObserver(vtkCommand.MouseMoveEvent, self.moved),
                     interactor.AddObserver(vtkCommand.StartInteractionEvent, self._start),
                     interactor.AddObserver(vtkCommand.EndInteractionEvent, self._end)]

    def _start(self, caller, event):
        self.interacting = True

    def _end(self, caller, event):
        self.interacting = False

    def gaze(self, interactor):
        """The normalised viewport position of the interactor's last event (the mapper's mouse gaze)."""
        renderer = self.renderer.Get()
        x, y = interactor.GetEventPosition()
        if renderer is not None:
            x0, y0 = renderer.GetOrigin()
            width, height = renderer.GetSize()
        else:
            (x0, y0), (width, height) = (0, 0), interactor.GetRenderWindow().GetSize()
        return (x + 0.5 - x0) / max(width, 1), (y + 0.5 - y0) / max(height, 1)

    def moved(self, interactor, event):
        entry = _registry().get(self.key)
        if entry is None or entry.method != "foveated" or not _follows(entry):
            return
        if self.proxy is None:
            self.proxy = _proxy_of(self.key)
            if self.proxy is None:
                return
        gaze = self.gaze(interactor)
        prop = self.proxy.GetProperty("foveated_gaze_point")
        if prop is None:
            return
        prop.SetElement(0, gaze[0])
        prop.SetElement(1, gaze[1])
        self.proxy.UpdateVTKObjects()  # -> the server's representation: its mapper's gaze point
        self.moves += 1
        if not self.interacting:  # no rotation/pan under way (ParaView's style keeps State 0): render
            interactor.Render()

    def stop(self):
        interactor = self.link.Get()
        if interactor is not None:
            for tag in self.tags:
                interactor.RemoveObserver(tag)


def _follows(entry) -> bool:
    value = entry.values.get("foveated", {}).get("follow_mouse", (1,))
    return bool(value[0]) if isinstance(value, (tuple, list)) else bool(value)


def watch_client_gaze(key, entry, interactor, renderer) -> None:
    """Called by ``prepare()`` in a process without data: in the client of a remote server, let
    the client's mouse set the gaze point of the server's foveated mapper."""
    if interactor is None or entry.method != "foveated" or not _follows(entry) or not remote_client():
        return
    found = _CLIENT_GAZE.get(key)
    if found is not None and found.link.Get() is interactor:
        return
    if found is not None:
        found.stop()
    _CLIENT_GAZE[key] = ClientGaze(key, interactor, renderer)


def release(key) -> None:
    """The representation is gone: drop its client gaze observer."""
    found = _CLIENT_GAZE.pop(key, None)
    if found is not None:
        found.stop()
    _PROXIES.pop(key, None)
    for refiner_ in _REFINERS.values():
        refiner_.keys.discard(key)
        refiner_.remote.discard(key)
        refiner_.server.pop(key, None)
