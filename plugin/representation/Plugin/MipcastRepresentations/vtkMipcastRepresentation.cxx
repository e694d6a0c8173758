#include "vtkPython.h" // first: Python's own headers want to come first
#include "vtkMipcastRepresentation.h"

#include "vtkAlgorithmOutput.h"
#include "vtkAssignAttribute.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkOutputWindow.h"
#include "vtkPVLODVolume.h"
#include "vtkPVRenderView.h"
#include "vtkPythonInterpreter.h"
#include "vtkPythonUtil.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSmartPyObject.h"
#include "vtkVolume.h"
#include "vtkVolumeProperty.h"

#include <cstdio>

namespace
{
// The glue module, imported once per process (nullptr if that failed).
PyObject* Glue()
{
  static PyObject* module = nullptr;
  static bool tried = false;
  if (module || tried)
  {
    return module;
  }
  tried = true;
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  PyObject* path = PySys_GetObject("path"); // borrowed
  vtkSmartPyObject dir(PyUnicode_FromString(MIPCAST_GLUE_DIR));
  if (path && PySequence_Contains(path, dir) == 0)
  {
    PyList_Append(path, dir);
  }
  module = PyImport_ImportModule("mipcast_representation");
  if (!module)
  {
    PyErr_Print();
    vtkOutputWindow::GetInstance()->DisplayErrorText(
      "mipcast representation: cannot import mipcast_representation from " MIPCAST_GLUE_DIR
      " (or mipcast itself): the volume is not drawn. Put the folder that holds the mipcast "
      "package on PYTHONPATH.\n");
  }
  return module;
}

// glue.<function>(*args); steals args; true if it returned True.
bool Call(const char* function, PyObject* args)
{
  vtkPythonScopeGilEnsurer gil;
  vtkSmartPyObject arguments(args);
  PyObject* module = Glue();
  if (!module || !args)
  {
    return false;
  }
  vtkSmartPyObject callable(PyObject_GetAttrString(module, function));
  if (!callable)
  {
    PyErr_Print();
    return false;
  }
  vtkSmartPyObject result(PyObject_CallObject(callable, arguments));
  if (!result)
  {
    PyErr_Print();
    return false;
  }
  return PyObject_IsTrue(result) == 1;
}

PyObject* Wrap(vtkObjectBase* object)
{
  if (!object)
  {
    Py_RETURN_NONE;
  }
  return vtkPythonUtil::GetObjectFromPointer(object);
}
}

vtkStandardNewMacro(vtkMipcastRepresentation);

//----------------------------------------------------------------------------
vtkMipcastRepresentation::vtkMipcastRepresentation()
{
  char key[64];
  std::snprintf(key, sizeof(key), "%p", static_cast<void*>(this));
  this->Key = key;
  this->MipcastVolume->SetVisibility(false);
  this->MipcastVolume->PickableOff();
  // VTK's CPU ray caster (method cpu) asks the property for its gradient opacity, which creates
  // one (constant 1) on it for good: every GPU method drawn after it then evaluated gradients at
  // each sample (the same picture, 20 % slower). ParaView's gradient opacity never reaches the
  // mipcast mappers; disabled, asking gives VTK's default function and stores none.
  this->Property->DisableGradientOpacityOn();
  this->SetMipcastMethod("mip");
}

//----------------------------------------------------------------------------
vtkMipcastRepresentation::~vtkMipcastRepresentation()
{
  if (Py_IsInitialized())
  {
    vtkPythonScopeGilEnsurer gil;
    Call("release", Py_BuildValue("(s)", this->Key.c_str()));
  }
  delete[] this->MipcastMethod;
}

//----------------------------------------------------------------------------
vtkVolume* vtkMipcastRepresentation::GetMipcastVolume()
{
  return this->MipcastVolume;
}

//----------------------------------------------------------------------------
void vtkMipcastRepresentation::SetMipcastMethod(const char* method)
{
  if (!method)
  {
    return;
  }
  delete[] this->MipcastMethod;
  this->MipcastMethod = new char[strlen(method) + 1];
  strcpy(this->MipcastMethod, method);
  {
    vtkPythonInterpreter::Initialize();
    vtkPythonScopeGilEnsurer gil;
    Call("set_method", Py_BuildValue("(ss)", this->Key.c_str(), method));
  }
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkMipcastRepresentation::SetMipcastDoubles(
  const char* method, const char* name, int n, const double* values)
{
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  PyObject* tuple = PyTuple_New(n);
  for (int i = 0; i < n; ++i)
  {
    PyTuple_SET_ITEM(tuple, i, PyFloat_FromDouble(values[i]));
  }
  Call("set_value", Py_BuildValue("(sssN)", this->Key.c_str(), method, name, tuple));
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkMipcastRepresentation::SetMipcastInts(
  const char* method, const char* name, int n, const int* values)
{
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  PyObject* tuple = PyTuple_New(n);
  for (int i = 0; i < n; ++i)
  {
    PyTuple_SET_ITEM(tuple, i, PyLong_FromLong(values[i]));
  }
  Call("set_value", Py_BuildValue("(sssN)", this->Key.c_str(), method, name, tuple));
  this->Modified();
}

//----------------------------------------------------------------------------
void vtkMipcastRepresentation::SetMipcastString(
  const char* method, const char* name, const char* value)
{
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  Call("set_value", Py_BuildValue("(ssss)", this->Key.c_str(), method, name, value ? value : ""));
  this->Modified();
}

//----------------------------------------------------------------------------
int vtkMipcastRepresentation::RefinementInfo(int index)
{
  vtkPythonInterpreter::Initialize();
  vtkPythonScopeGilEnsurer gil;
  PyObject* module = Glue();
  if (!module)
  {
    return index == 0 ? 0 : -1;
  }
  vtkSmartPyObject result(
    PyObject_CallMethod(module, "refinement_info", "(s)", this->Key.c_str()));
  if (!result || !PyTuple_Check(result) || PyTuple_Size(result) <= index)
  {
    if (PyErr_Occurred())
    {
      PyErr_Print();
    }
    return index == 0 ? 0 : -1;
  }
  return static_cast<int>(PyLong_AsLong(PyTuple_GET_ITEM(result.GetPointer(), index)));
}

int vtkMipcastRepresentation::GetMipcastRefining()
{
  return this->RefinementInfo(0);
}

int vtkMipcastRepresentation::GetMipcastRefinementStep()
{
  return this->RefinementInfo(1);
}

int vtkMipcastRepresentation::GetMipcastFramesDrawn()
{
  return this->RefinementInfo(2);
}

//----------------------------------------------------------------------------
void vtkMipcastRepresentation::SetVisibility(bool val)
{
  this->Superclass::SetVisibility(val);
  if (!val)
  {
    this->MipcastVolume->SetVisibility(false);
  }
}

//----------------------------------------------------------------------------
int vtkMipcastRepresentation::ProcessViewRequest(
  vtkInformationRequestKey* request_type, vtkInformation* inInfo, vtkInformation* outInfo)
{
  if (!this->Superclass::ProcessViewRequest(request_type, inInfo, outInfo))
  {
    this->MipcastVolume->SetVisibility(false);
    return 0;
  }
  if (request_type == vtkPVView::REQUEST_UPDATE())
  {
    // The maximum (and minimum) projections composite exactly by depth on several ranks
    // (each rank's fragment depth decreases (increases) with its ray's value; see
    // mipcast_representation.py's depth_composited):
    // no ordered (alpha-blended) compositing then, IceT keeps the nearest fragment.
    vtkPythonInterpreter::Initialize();
    vtkPythonScopeGilEnsurer gil;
    if (Call("depth_composited", Py_BuildValue("(s)", this->Key.c_str())))
    {
      outInfo->Set(vtkPVRenderView::NEED_ORDERED_COMPOSITING(), 0);
    }
  }
  if (request_type == vtkPVView::REQUEST_RENDER())
  {
    // the superclass gave its own (hidden) volume the delivered piece; ours gets it too
    this->Assign->SetInputConnection(vtkPVRenderView::GetPieceProducer(inInfo, this, 0));
    const char* name = nullptr;
    int association = vtkDataObject::FIELD_ASSOCIATION_POINTS;
    vtkInformation* info = this->GetInputArrayInformation(0);
    if (info && info->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
      info->Has(vtkDataObject::FIELD_NAME()))
    {
      name = info->Get(vtkDataObject::FIELD_NAME());
      association = info->Get(vtkDataObject::FIELD_ASSOCIATION());
    }
    bool visible = name != nullptr && name[0] != 0;
    if (visible)
    {
      // vtkAssignAttribute::Assign() always calls Modified(): at every frame that re-ran it and
      // gave the mapper a "new" input, whose texture (and the analytic corner packing) the
      // mapper then rebuilt each frame. Only when the array changes.
      if (this->AssignedName != name || this->AssignedAssociation != association)
      {
        this->Assign->Assign(name, vtkDataSetAttributes::SCALARS,
          association == vtkDataObject::FIELD_ASSOCIATION_CELLS ? vtkAssignAttribute::CELL_DATA
                                                                : vtkAssignAttribute::POINT_DATA);
        this->AssignedName = name;
        this->AssignedAssociation = association;
      }
      this->MipcastVolume->SetProperty(this->Property);
      this->MipcastVolume->SetPosition(this->Actor->GetPosition());
      this->MipcastVolume->SetOrientation(this->Actor->GetOrientation());
      this->MipcastVolume->SetScale(this->Actor->GetScale());
      this->MipcastVolume->SetOrigin(this->Actor->GetOrigin());
      vtkPVRenderView* view = this->RenderView;
      vtkRenderer* renderer = view ? view->GetRenderer() : nullptr;
      vtkRenderWindowInteractor* interactor = view ? view->GetInteractor() : nullptr;
      vtkPythonInterpreter::Initialize();
      vtkPythonScopeGilEnsurer gil;
      const int* whole = this->WholeExtent; // the whole volume's extent (this rank draws a piece)
      visible = Call("prepare",
        Py_BuildValue("(sNNNN(iiiiii)i)", this->Key.c_str(), Wrap(this->MipcastVolume),
          Wrap(this->Assign), Wrap(renderer), Wrap(interactor), whole[0], whole[1], whole[2],
          whole[3], whole[4], whole[5], association == vtkDataObject::FIELD_ASSOCIATION_CELLS));
    }
    this->MipcastVolume->SetVisibility(visible && this->GetVisibility());
    // ParaView's own volume stays out of the picture
    this->Actor->SetVisibility(false);
  }
  return 1;
}

//----------------------------------------------------------------------------
bool vtkMipcastRepresentation::AddToView(vtkView* view)
{
  vtkPVRenderView* rview = vtkPVRenderView::SafeDownCast(view);
  if (!rview || !this->Superclass::AddToView(view))
  {
    return false;
  }
  rview->GetRenderer()->RemoveActor(this->Actor);
  rview->GetRenderer()->AddVolume(this->MipcastVolume);
  this->RenderView = rview;
  return true;
}

//----------------------------------------------------------------------------
bool vtkMipcastRepresentation::RemoveFromView(vtkView* view)
{
  vtkPVRenderView* rview = vtkPVRenderView::SafeDownCast(view);
  if (rview)
  {
    rview->GetRenderer()->RemoveVolume(this->MipcastVolume);
    this->RenderView = nullptr;
  }
  return this->Superclass::RemoveFromView(view);
}

//----------------------------------------------------------------------------
void vtkMipcastRepresentation::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MipcastMethod: " << (this->MipcastMethod ? this->MipcastMethod : "(none)")
     << endl;
}
