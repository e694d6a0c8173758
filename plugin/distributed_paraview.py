"""Exact distributed MIP inside ParaView's MPI engine (pvserver, pvbatch): a server-side filter.

``distributed_mip(source, ...)`` puts a ``ProgrammableFilter`` after
``source`` whose script runs on every server rank with that rank's piece
(ParaView's readers split image data into bricks that share a layer of
points) and renders it with :class:`mipcast.distributed.DistributedView`:
each rank its brick with the whole volume's camera, one MAX reduction
(mpi4py, over the server's MPI world), so the result equals the
single-process float readout. Its output is a ``vtkTable`` with one column
``mip_value`` (float32, data units, NaN = miss; rows top row first) on rank
0, empty on the others; :func:`fetch_image` brings it to the client as a
(height, width) array. Works in ``pvbatch`` (non-symmetric, the usual mode),
in ``pvbatch --symmetric`` and with ``mpiexec -n N pvserver`` behind a
``pvpython`` or GUI client; the server ranks need mipcast and mpi4py
(``apt-get install python3-mpi4py``).

Example (pvpython client, server started with
``mpiexec -n 2 pvserver --server-port=11111``)::

    from paraview.simple import *
    from mipcast.plugin.distributed_paraview import distributed_mip, fetch_image
    Connect("localhost", 11111)
    volume = XMLImageDataReader(FileName=["head.vti"])
    mip = distributed_mip(volume, method="analytic", size=(512, 512), view="oblique")
    values = fetch_image(mip)          # numpy (512, 512), data units
"""
from __future__ import annotations

import json
from typing import Optional, Sequence

import numpy as np

#: The server-side script (fixed text; the settings arrive as the JSON string ``mipcast_settings``).
SCRIPT = """
import json
from mipcast.distributed import DistributedView, abort_on_error, world_communicator
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData
settings = json.loads(mipcast_settings)
comm = world_communicator()
with abort_on_error(comm):
    piece = vtkImageData()
    piece.ShallowCopy(self.GetInputDataObject(0, 0))  # the user's data is not modified
    array = settings.get("array")
    if array:
        piece.GetPointData().SetActiveScalars(array)
    view = DistributedView(piece, settings["method"], size=tuple(settings["size"]), view=settings["view"],
                           window=settings["window"] or "full", comm=comm, **settings["parameters"])
    images = view.images()
    output = self.GetOutputDataObject(0)
    if comm.rank == 0:
        for name, values in images.items():
            column = numpy_to_vtk(values.ravel().astype("float32"), deep=True)
            column.SetName(name)
            output.AddColumn(column)
        values = images["mip_value"]
        output.GetFieldData().AddArray(numpy_to_vtk([float(values.shape[0]), float(values.shape[1])], deep=True))
        output.GetFieldData().GetArray(0).SetName("mip_shape")
"""


def distributed_mip(source, method: str = "mip", size: Sequence[int] = (256, 256), view: str = "oblique",
                    window: Optional[Sequence[float]] = None, array: Optional[str] = None, **parameters):
    """A server-side filter: the exact distributed float MIP of ``source`` (image data).

    Parameters
    ----------
    source : paraview proxy
        Image data with one-component point scalars (e.g. ``XMLImageDataReader``).
    method : str
        A method with a ``distributed`` route in :data:`mipcast.methods.METHODS`
        (``mip``, ``analytic``; ``demip``, ``demip_two_pass``, whose table also
        carries ``demip_depth`` and the colour ``demip_red/green/blue``:
        :func:`fetch_images`).
    size, view
        Output (width, height) and a camera preset of :data:`mipcast.offscreen.VIEW_NAMES`.
    window : (low, high), optional
        Grey window; default the whole volume's range.
    array : str, optional
        The point array (default the active scalars).
    **parameters
        The method's parameters (``packed_corners=False``, ...).

    Returns
    -------
    paraview proxy
        A ``ProgrammableFilter`` whose output is a ``vtkTable`` (see the module).
    """
    from paraview import simple

    settings = {"method": method, "size": [int(v) for v in size], "view": view,
                "window": None if window is None else [float(v) for v in window],
                "array": array, "parameters": parameters}
    flt = simple.ProgrammableFilter(Input=source)
    flt.OutputDataSetType = "vtkTable"
    # ParaView 5.11's ProgrammableFilter has no Parameters property: the settings go in
    # as one string literal (repr of the JSON text), read back with json.loads.
    flt.Script = "mipcast_settings = " + repr(json.dumps(settings)) + "\n" + SCRIPT
    return flt


def fetch_image(flt) -> np.ndarray:
    """The filter's float image on the client: numpy float32 (height, width), top row first."""
    return fetch_images(flt)["mip_value"]


def fetch_images(flt) -> dict:
    """Every image the filter's table carries (:meth:`mipcast.distributed.DistributedView.images`), by name."""
    from paraview import servermanager
    from vtkmodules.util.numpy_support import vtk_to_numpy

    table = servermanager.Fetch(flt)
    shape = table.GetFieldData().GetArray("mip_shape")
    if table.GetColumnByName("mip_value") is None or shape is None:
        raise RuntimeError("the distributed MIP filter produced no image: see the server's output "
                           "(mipcast and mpi4py must be importable on every server rank)")
    height, width = int(shape.GetValue(0)), int(shape.GetValue(1))
    return {table.GetColumnName(i): vtk_to_numpy(table.GetColumn(i)).reshape(height, width).astype(np.float32)
            for i in range(table.GetNumberOfColumns())}
