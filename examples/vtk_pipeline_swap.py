"""A plain VTK volume pipeline with its mapper swapped for mipcast's in ONE line.

    python3 examples/vtk_pipeline_swap.py OUT.png [INPUT.vti]
    PYTHONPATH=. xvfb-run -a pvpython examples/vtk_pipeline_swap.py OUT.png   # ParaView 5.11, VTK 9.2

reader -> vtkGPUVolumeRayCastMapper -> vtkVolume -> vtkRenderer, rendered
offscreen to a PNG.  Without INPUT.vti the script writes the "vessels" test
volume to a temporary .vti first and reads that back, like any file.

The swap is the line marked ``# <- mipcast``: a mipcast mapper is created and
attached to the volume in one statement (``Attach`` installs its shader pieces
on the volume and calls ``volume.SetMapper``); every other line, including the
mapper's configuration through ``volume.GetMapper()``, is shared by both.  To
go back to stock VTK, comment it out and uncomment the line marked
``# <- stock VTK``.
"""
import os
import sys
import tempfile

from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLImageDataReader, vtkXMLImageDataWriter
from vtkmodules.vtkRenderingCore import (vtkColorTransferFunction, vtkRenderer, vtkRenderWindow,
                                         vtkVolume, vtkVolumeProperty, vtkWindowToImageFilter)
from vtkmodules.vtkRenderingVolume import vtkGPUVolumeRayCastMapper  # noqa: F401  (the stock line)
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (OpenGL back end)
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401  (GPU volume mapper back end)

import mipcast


def write_test_volume(folder):
    """Write mipcast's "vessels" fixture (48^3) as a .vti file and return its path."""
    from mipcast.data_fixtures import make_fixture

    path = os.path.join(folder, "vessels.vti")
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(make_fixture("vessels", size=48))
    writer.Write()
    return path


def main(out_png, input_vti=None):
    """Render ``input_vti`` (default: a generated test volume) through the pipeline to ``out_png``."""
    if input_vti is not None:
        return render_file(input_vti, out_png)
    with tempfile.TemporaryDirectory(prefix="mipcast-example-") as folder:
        return render_file(write_test_volume(folder), out_png)


def render_file(input_vti, out_png):
    """The pipeline: read ``input_vti``, render it with a MIP mapper, write ``out_png``."""
    reader = vtkXMLImageDataReader()
    reader.SetFileName(input_vti)
    reader.Update()
    low, high = reader.GetOutput().GetScalarRange()

    colour = vtkColorTransferFunction()
    colour.AddRGBPoint(low, 0.0, 0.0, 0.0)
    colour.AddRGBPoint(high, 1.0, 1.0, 1.0)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(low, 1.0)
    opacity.AddPoint(high, 1.0)
    volume_property = vtkVolumeProperty()
    volume_property.SetColor(colour)
    volume_property.SetScalarOpacity(opacity)
    volume_property.SetInterpolationTypeToLinear()

    volume = vtkVolume()
    volume.SetProperty(volume_property)
    # volume.SetMapper(vtkGPUVolumeRayCastMapper())  # <- stock VTK
    mipcast.AnalyticMIPVolumeMapper().Attach(volume)  # <- mipcast
    mapper = volume.GetMapper()
    mapper.SetInputConnection(reader.GetOutputPort())
    mapper.SetBlendModeToMaximumIntensity()
    mapper.SetAutoAdjustSampleDistances(False)

    renderer = vtkRenderer()
    renderer.AddVolume(volume)
    camera = renderer.GetActiveCamera()
    camera.Azimuth(33.0)
    camera.Elevation(21.0)
    camera.OrthogonalizeViewUp()
    renderer.ResetCamera()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.AddRenderer(renderer)
    window.SetSize(256, 256)
    window.Render()

    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.ReadFrontBufferOff()
    writer = vtkPNGWriter()
    writer.SetFileName(out_png)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    print(f"{type(mapper).__name__}: wrote {out_png}")


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__.split("\n\n")[1])
    main(*sys.argv[1:])
