"""Python-side state for VTK objects that outlives their Python wrappers.

VTK may drop the Python wrapper of an object that only C++ still holds (a
mapper referenced by its volume) and make a new one later; attributes set on
the old wrapper do not always survive that.  mipcast therefore keeps each
object's Python state in a table keyed by the C++ address, and removes the
entry when VTK deletes the object.
"""
from __future__ import annotations

from vtkmodules.vtkCommonCore import vtkCommand

_STATES: dict = {}


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
    key = vtk_object.GetAddressAsString("vtkObjectBase")
    state = _STATES.get(key)
    if state is None:
        state = _STATES[key] = {}
        vtk_object.AddObserver(vtkCommand.DeleteEvent, lambda *_: _STATES.pop(key, None))
    return state
