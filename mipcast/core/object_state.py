"""Python-side state for VTK objects that outlives their Python wrappers.

VTK may drop the Python wrapper of an object that only C++ still holds (a
mapper referenced by its volume) and make a new one later; attributes set on
the old wrapper do not always survive that.  mipcast therefore keeps each
object's Python state in a table keyed by the C++ address, with a VTK weak
reference that tells whether the object still lives: an entry whose object
is gone is dropped when the address is reused and in a sweep every
:data:`SWEEP_EVERY` new entries.  (No Python DeleteEvent observer: one
running while the garbage collector frees a wrapper can crash Python, and
the state it would drop may hold VTK filters of the object being deleted.)

The wrapper keeps a shortcut to its object's state (an attribute): VTK
keeps a wrapper's attributes while the object lives, even when it drops
and remakes the wrapper, and a wrapper exists only while its object does,
so the shortcut always leads to the table's entry (a frame of a foveated
view asks a few hundred times: 2.2 -> 0.4 microseconds each).
"""
from __future__ import annotations

from vtkmodules.vtkCommonCore import vtkWeakReference

#: address -> (weak reference to the object, its state)
_STATES: dict = {}
#: New entries between two sweeps of entries whose object is gone.
SWEEP_EVERY = 64
_NEW = [0]
#: The wrapper attribute holding the shortcut.
_SHORTCUT = "_mipcast_state"


def object_state(vtk_object) -> dict:
    """Return the mutable state dict of ``vtk_object`` (created empty on first use).

    Examples
    --------
    >>> from vtkmodules.vtkCommonCore import vtkObject
    >>> obj = vtkObject()
    >>> object_state(obj)["answer"] = 42
    >>> object_state(obj)["answer"]
    42
    """
    state = getattr(vtk_object, _SHORTCUT, None)
    if state is not None:
        return state
    key = vtk_object.GetAddressAsString("vtkObjectBase")
    entry = _STATES.get(key)
    if entry is not None and entry[0].Get() is None:  # that object is gone; a new one has its address
        entry = None
    if entry is None:
        link = vtkWeakReference()
        link.Set(vtk_object)
        entry = _STATES[key] = (link, {})
        _NEW[0] += 1
        if _NEW[0] % SWEEP_EVERY == 0:
            _sweep()
    try:
        setattr(vtk_object, _SHORTCUT, entry[1])
    except AttributeError:  # a wrapper that takes no attributes: the table alone
        pass
    return entry[1]


def _sweep() -> None:
    """Drop the states of deleted objects."""
    for key in [key for key, (link, _) in _STATES.items() if link.Get() is None]:
        _STATES.pop(key, None)
