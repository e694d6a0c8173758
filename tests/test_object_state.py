"""mipcast.core.object_state: one state per VTK object, through wrappers that come and go."""
import gc

from vtkmodules.vtkCommonCore import vtkObject
from vtkmodules.vtkRenderingCore import vtkVolume
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.core import object_state as module
from mipcast.core.object_state import object_state


def test_the_state_outlives_its_wrapper_and_is_the_tables():
    volume = vtkVolume()
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    volume.SetMapper(mapper)
    state = object_state(mapper)
    state["answer"] = 42
    address = mapper.GetAddressAsString("vtkObjectBase")
    del mapper
    gc.collect()
    again = volume.GetMapper()  # a wrapper made again for the C++ object
    assert again.GetAddressAsString("vtkObjectBase") == address
    assert object_state(again) is state and state == {"answer": 42}
    assert module._STATES[address][1] is state  # the shortcut leads to the table's entry


def test_each_object_has_its_own_state():
    first, second = vtkObject(), vtkObject()
    object_state(first)["x"] = 1
    assert object_state(second) == {}
    assert object_state(first) == {"x": 1}
