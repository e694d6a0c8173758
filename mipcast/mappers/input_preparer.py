"""Pipeline filter between the user's image and VTK: the values :func:`prepare_scalars` defines.

Every mipcast mapper feeds VTK through its own :class:`InputPreparer`, so
``GetInput()`` still returns the user's image (never modified) while the GPU
draws one component with missing values filled (see
:mod:`mipcast.core.prepare`).  Valid finite one-component input passes
through as it is (a shallow copy: the same array, the same texture).
"""
from __future__ import annotations

import warnings
from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.errors import InputError, InputWarning
from mipcast.core.prepare import PreparedScalars, check_component, prepare_scalars


#: Arrays (address, modification time) already warned about.
_WARNED: set = set()


class InputPreparer(VTKPythonAlgorithmBase):
    """vtkImageData in, the drawn one-component values out (geometry copied).

    Input that cannot be drawn gives a 2x2x2 float zero volume (so shaders
    still compile) and :meth:`GetProblem` says why; the mapper refuses to
    draw it.  +-Inf values (drawn as missing) give one
    :class:`mipcast.InputWarning` per volume, not per frame.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> preparer = InputPreparer()
    >>> image = make_fixture("spheres", size=8)
    >>> preparer.SetInputDataObject(image)
    >>> _ = preparer.Update()
    >>> out = preparer.GetOutputDataObject(0)
    >>> out.GetPointData().GetScalars() is image.GetPointData().GetScalars(), preparer.GetProblem()
    (True, None)
    """

    def __init__(self) -> None:
        super().__init__(nInputPorts=1, inputType="vtkImageData", nOutputPorts=1, outputType="vtkImageData")
        self._component: Optional[int] = None
        self._problem: Optional[str] = None
        self._prepared: Optional[PreparedScalars] = None

    def SetComponent(self, component) -> None:
        """Component of multi-component scalars to draw (int >= 0), or -1 / None / "magnitude"."""
        component = check_component(component)
        if component != self._component:
            self._component = component
            self.Modified()

    def GetComponent(self) -> int:
        """The drawn component, -1 for the magnitude (the default)."""
        return -1 if self._component is None else self._component

    def GetProblem(self) -> Optional[str]:
        """Why the last input cannot be drawn, or None."""
        return self._problem

    def GetPrepared(self) -> Optional[PreparedScalars]:
        """What the last run prepared (None if the input was refused)."""
        return self._prepared

    def RequestData(self, request, in_info, out_info) -> int:
        source = vtkImageData.GetData(in_info[0])
        target = vtkImageData.GetData(out_info)
        try:
            prepared = prepare_scalars(source, self._component)
        except (TypeError, InputError) as error:
            self._problem, self._prepared = str(error), None
            target.SetDimensions(2, 2, 2)
            target.GetPointData().SetScalars(numpy_to_vtk(np.zeros(8, np.float32), deep=True))
            return 1
        self._problem, self._prepared = None, prepared
        if not prepared.changed:
            target.ShallowCopy(source)
            return 1
        stamp = (source.GetPointData().GetScalars().GetAddressAsString("vtkObjectBase"),
                 source.GetPointData().GetScalars().GetMTime())
        if prepared.infinite and stamp not in _WARNED:  # once per volume, even with several mappers
            _WARNED.add(stamp)
            warnings.warn(
                f"{prepared.infinite} +-Inf value(s) in '{source.GetPointData().GetScalars().GetName()}' "
                "are drawn as missing data (like NaN); replace them first to draw them "
                "(e.g. numpy.nan_to_num)", InputWarning, stacklevel=2)
        array = numpy_to_vtk(np.ascontiguousarray(prepared.values).ravel(), deep=True)
        array.SetName(source.GetPointData().GetScalars().GetName() or "scalars")
        target.CopyStructure(source)
        target.GetPointData().SetScalars(array)
        return 1


def prepared_image(image: vtkImageData, component=None, missing_allowed: bool = True) -> vtkImageData:
    """A new image holding what the GPU draws from ``image`` (``image`` itself if nothing changes).

    For VTK's own mappers (stock, CPU), which have no preparer inside.
    ``missing_allowed=False``: refuse missing values (the fill below every
    finite value is right for maximum projections only).

    Raises
    ------
    InputError
        As :func:`mipcast.core.prepare.prepare_scalars`, or missing values where they are not allowed.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("spheres", size=8)
    >>> prepared_image(image) is image
    True
    """
    prepared = prepare_scalars(image, component)
    if prepared.missing and not missing_allowed:
        raise InputError(f"{prepared.missing} NaN/Inf voxels: missing data is defined for maximum projections "
                         "only; replace them first (e.g. numpy.nan_to_num) or use a MIP method")
    if not prepared.changed:
        return image
    out = vtkImageData()
    out.CopyStructure(image)
    array = numpy_to_vtk(np.ascontiguousarray(prepared.values).ravel(), deep=True)
    array.SetName(image.GetPointData().GetScalars().GetName() or "scalars")
    out.GetPointData().SetScalars(array)
    return out
