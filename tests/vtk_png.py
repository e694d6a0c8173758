"""PNG output for the pvpython checks (VTK only: ParaView's Python has no matplotlib)."""
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData


def write_png(path, rgb):
    """Write a top-row-first uint8 (H, W, 3) array as a PNG."""
    from vtkmodules.vtkIOImage import vtkPNGWriter

    height, width = rgb.shape[:2]
    image = vtkImageData()
    image.SetDimensions(width, height, 1)
    image.GetPointData().SetScalars(
        numpy_to_vtk(np.ascontiguousarray(rgb[::-1]).reshape(-1, 3), deep=True))
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()
