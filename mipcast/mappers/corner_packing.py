"""Four cell corners per texel, so analytic MIP reads a cell in two fetches.

:func:`packed_corners` builds a four-component copy of a volume whose
texel ``(x, y, z)`` holds the values at ``(x, y, z)``, ``(x, y+1, z)``,
``(x, y, z+1)`` and ``(x, y+1, z+1)``; a cell's 8 corners are then the
texels at ``x`` and ``x + 1`` (``shaders/amip_corners_packed.glsl``).
Values are copied, not rescaled, so the walk stays exact; only 8/16-bit
integers and float32 are packed (:func:`packable`), other types are drawn
unpacked.  The packed texture is four times the volume's.
:class:`CornerPacker` does it inside a VTK pipeline (between the user's
input and the mapper), so the user's image is never modified and the
packing reruns only when the input changes.  Why these types and not
others: docs/methods.md, section Corner packing
(``docs/methods.md#corner-packing``).
"""
from __future__ import annotations

import threading
from typing import Optional

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtkmodules.vtkCommonCore import vtkDataArray
from vtkmodules.vtkCommonDataModel import vtkImageData


#: Types VTK uploads to the texture the same way for every component.
_UNIFORM_TYPES = (np.int8, np.uint8, np.int16, np.uint16, np.float32)


def packable(values: np.ndarray) -> bool:
    """Whether :class:`CornerPacker` packs these values exactly: 8/16-bit integers and float32.

    Examples
    --------
    >>> packable(np.arange(10, dtype=np.int16)), packable(np.arange(10.0))
    (True, False)
    """
    return values.dtype in _UNIFORM_TYPES


def packed_corners(values: np.ndarray, out: Optional[np.ndarray] = None) -> np.ndarray:
    """``(nz, ny, nx)`` values -> ``(nz, ny, nx, 4)``: each point with its +y, +z and +y+z neighbours.

    The type is kept (VTK draws only :func:`packable` types exactly).
    ``out`` (that shape and type, e.g. a view of a VTK array) receives the
    result instead of a new array; slices, no gathers, no temporaries.

    Examples
    --------
    >>> values = np.arange(8.0).reshape(2, 2, 2)      # (z, y, x)
    >>> packed_corners(values)[0, 0, 0].tolist()       # (x, y, z) = 0: itself, +y, +z, +y+z
    [0.0, 2.0, 4.0, 6.0]
    >>> packed_corners(values)[1, 1, 1].tolist()       # the last point repeats itself
    [7.0, 7.0, 7.0, 7.0]
    """
    packed = np.empty(values.shape + (4,), dtype=values.dtype) if out is None else out
    if packed.shape != values.shape + (4,) or packed.dtype != values.dtype:
        raise ValueError(f"out must be {values.shape + (4,)} {values.dtype}, got {packed.shape} {packed.dtype}")
    nz, ny = values.shape[:2]
    packed[..., 0] = values
    if nz < 2 or ny < 2:  # degenerate (the mapper refuses such volumes): clamp by index
        up_y, up_z = np.minimum(np.arange(ny) + 1, ny - 1), np.minimum(np.arange(nz) + 1, nz - 1)
        packed[..., 1], packed[..., 2] = values[:, up_y], values[up_z]
        packed[..., 3] = values[up_z][:, up_y]
        return packed
    for component, (dz, dy) in enumerate(((0, 1), (1, 0), (1, 1)), start=1):
        # the neighbour dz, dy further on; the last row/slice repeats the one before (no cell reads it)
        target = packed[..., component]
        target[:nz - dz, :ny - dy] = values[dz:, dy:]
        if dy:
            target[:nz - dz, -1] = target[:nz - dz, -2]
        if dz:
            target[-1] = target[-2]
    return packed


class CornerPacker(VTKPythonAlgorithmBase):
    """Pipeline filter: one-component vtkImageData in, :func:`packed_corners` out.

    Geometry (extent, spacing, origin, direction) is copied.  Input the
    packing cannot handle (no scalars, several components, fewer than 2
    points along an axis) gives a 2x2x2 zero volume with four components,
    so the packed shader still compiles; the mapper refuses such input
    itself and draws nothing.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> packer = CornerPacker()
    >>> packer.SetInputDataObject(make_fixture("spheres", size=8))
    >>> _ = packer.Update()
    >>> packer.GetOutputDataObject(0).GetPointData().GetScalars().GetNumberOfComponents()
    4
    """

    def __init__(self) -> None:
        super().__init__(nInputPorts=1, inputType="vtkImageData", nOutputPorts=1, outputType="vtkImageData")
        self._pending = None     # the background packing (StartPacking) under way or done, not yet taken
        self._packed_for = None  # the input stamp the output holds the packed copy of

    def InputStamp(self):
        """(address, MTime, dims, scalars) of the input data object as it is now, or None."""
        if self.GetNumberOfInputConnections(0) == 0:
            return None
        source = self.GetInputDataObject(0, 0)
        if source is None:
            return None
        return _stamp(source)

    def StartPacking(self) -> bool:
        """Pack the current input (brought up to date) in a background thread; False if it cannot.

        The copy is filled while the caller goes on (numpy's slice copies
        release the GIL); :meth:`RequestData` takes it when it matches the
        input then, waiting for the thread if needed, and packs anew if the
        input changed meanwhile.  The thread only writes into its own new
        array; it reads the input's values, which the caller keeps alive.
        """
        if self.GetNumberOfInputConnections(0) == 0:
            return False
        self.GetInputAlgorithm(0, 0).Update(self.GetInputConnection(0, 0).GetIndex())  # what the thread reads
        source = self.GetInputDataObject(0, 0)
        stamp = _stamp(source) if source is not None else None
        if stamp is None or stamp == self._packed_for or (self._pending and self._pending["stamp"] == stamp):
            return stamp is not None
        scalars = source.GetPointData().GetScalars()
        dims = source.GetDimensions()
        if scalars is None or scalars.GetNumberOfComponents() != 1 or min(dims) < 2:
            return False
        packed = _packed_array(scalars)
        values = vtk_to_numpy(scalars).reshape(dims[2], dims[1], dims[0])
        out = vtk_to_numpy(packed).reshape(values.shape + (4,))
        pending = {"stamp": stamp, "array": packed, "source": source, "error": None}

        def fill() -> None:
            try:
                packed_corners(values, out=out)
            except BaseException as error:  # reported by packing anew in RequestData
                pending["error"] = error

        pending["thread"] = threading.Thread(target=fill, name="mipcast-corner-packing")
        pending["thread"].start()
        self._pending = pending
        return True

    def ReadyStamp(self):
        """:meth:`InputStamp` when the output for the current input needs no packing work in the
        render (the packed copy is there already, or :meth:`StartPacking`'s thread has finished
        it), else None."""
        stamp = self.InputStamp()
        if stamp is None:
            return None
        if stamp == self._packed_for:
            return stamp
        pending = self._pending
        if pending is not None and pending["stamp"] == stamp and not pending["thread"].is_alive():
            return stamp
        return None

    def RequestData(self, request, in_info, out_info) -> int:
        source = vtkImageData.GetData(in_info[0])
        target = vtkImageData.GetData(out_info)
        scalars = source.GetPointData().GetScalars()
        dims = source.GetDimensions()
        if scalars is None or scalars.GetNumberOfComponents() != 1 or min(dims) < 2:
            target.SetDimensions(2, 2, 2)
            target.GetPointData().SetScalars(numpy_to_vtk(np.zeros((8, 4), np.float32), deep=True))
            self._packed_for = None
            return 1
        stamp, pending, self._pending = _stamp(source), self._pending, None
        packed = None
        if pending is not None:
            pending["thread"].join()
            if pending["stamp"] == stamp and pending["error"] is None:
                packed = pending["array"]
        if packed is None:
            values = vtk_to_numpy(scalars).reshape(dims[2], dims[1], dims[0])
            packed = _packed_array(scalars)  # filled in place: no copy of a 4x volume
            packed_corners(values, out=vtk_to_numpy(packed).reshape(values.shape + (4,)))
        packed.SetName(scalars.GetName() or "scalars")
        target.CopyStructure(source)
        target.GetPointData().SetScalars(packed)
        self._packed_for = stamp
        return 1


def _stamp(image) -> tuple:
    scalars = image.GetPointData().GetScalars()
    return (image.GetAddressAsString("vtkObjectBase"), image.GetMTime(), image.GetDimensions(),
            None if scalars is None else (scalars.GetAddressAsString("vtkObjectBase"), scalars.GetMTime()))


def _packed_array(scalars) -> vtkDataArray:
    """A new four-component array of ``scalars``' type and tuple count (standard AOS layout)."""
    packed = vtkDataArray.CreateDataArray(scalars.GetDataType())
    packed.SetNumberOfComponents(4)
    packed.SetNumberOfTuples(scalars.GetNumberOfTuples())
    return packed
