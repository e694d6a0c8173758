"""The ParaView GUI with mipcast's representation: run as ``paraview --script=<this file>``.

Environment: ``MIPCAST_PLUGIN`` (the built MipcastRepresentation.so),
``MIPCAST_GUI_OUT`` (a folder for the pictures), PYTHONPATH with the
repository and tests/.  Loads the plugin, opens a 48^3 vessel phantom,
saves the view as ParaView shows it by default (``default.png``), switches
the representation to "mipcast" (DEMIP, a colour legend) and saves the view
again (``mipcast.png``); writes ``report.json``; then a background ``xwd``
grabs the whole screen (the main window with its Properties panel) into
``window.xwd`` a few seconds later, once the event loop has drawn the panel,
and ends this ParaView (its own process id).
"""
import inspect
import json
import os
import shutil
import subprocess

if not hasattr(inspect, "getargspec"):  # ParaView 5.11's plugin loader on Python 3.11
    inspect.getargspec = inspect.getfullargspec

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

from mipcast.data_fixtures import make_fixture

# ParaView is imported in main(): pytest's doctest collection imports this file outside ParaView.
OUT = os.environ.get("MIPCAST_GUI_OUT", "")
SIZE = [480, 400]
#: Where the Properties panel's search box is once the window fills a 1280 x 1024 screen.
SEARCH_BOX = os.environ.get("MIPCAST_GUI_SEARCH_BOX", "90 548")
WELCOME_CLOSE = os.environ.get("MIPCAST_GUI_WELCOME_CLOSE", "891 576")
SEARCH_TEXT = os.environ.get("MIPCAST_GUI_SEARCH", "depth")


def pixels(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    output = reader.GetOutput()
    width, height, _ = output.GetDimensions()
    return vtk_to_numpy(output.GetPointData().GetScalars()).reshape(height, width, -1)[..., :3].astype(int)


def main():
    from paraview.simple import (ColorBy, GetActiveViewOrCreate, LoadPlugin, OpenDataFile, Render,
                                 RenameSource, ResetCamera, SaveScreenshot, SetActiveSource, Show)

    os.makedirs(OUT, exist_ok=True)
    LoadPlugin(os.environ["MIPCAST_PLUGIN"], ns=globals())
    path = os.path.join(OUT, "vessels.vti")
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(make_fixture("vessels", size=48))
    writer.Write()

    reader = OpenDataFile(path)
    RenameSource("vessels.vti", reader)
    view = GetActiveViewOrCreate("RenderView")
    display = Show(reader, view)
    Render(view)
    ResetCamera(view)
    SaveScreenshot(os.path.join(OUT, "default.png"), view, ImageResolution=SIZE)

    display.SetRepresentationType("mipcast")
    ColorBy(display, ("POINTS", "scalars"))
    display.RescaleTransferFunctionToDataRange(True, False)
    display.MipcastMethod = "demip"
    display.demip_depth_weight = 0.3
    display.SetScalarBarVisibility(view, True)
    SetActiveSource(reader)
    camera = view.GetActiveCamera()
    camera.Azimuth(35.0)
    camera.Elevation(25.0)
    camera.OrthogonalizeViewUp()
    ResetCamera(view)
    Render(view)
    SaveScreenshot(os.path.join(OUT, "mipcast.png"), view, ImageResolution=SIZE)

    default, mipcast = pixels(os.path.join(OUT, "default.png")), pixels(os.path.join(OUT, "mipcast.png"))
    background = np.median(mipcast.reshape(-1, 3), axis=0)
    report = {
        "representation": str(display.Representation).strip("'"),
        "method": str(display.MipcastMethod).strip("'"),
        "mipcast_lit": float(np.mean(np.abs(mipcast - background).max(axis=-1) > 24)),
        "differs_from_default": float(np.mean(np.abs(mipcast - default).max(axis=-1) > 24)),
    }
    with open(os.path.join(OUT, "report.json"), "w") as handle:
        json.dump(report, handle)

    # the whole window once Qt has drawn the Properties panel, then end this ParaView; with
    # xdotool the window fills the screen first and the panel's search box gets "mipcast"
    wait = os.environ.get("MIPCAST_GUI_WAIT", "6")
    commands = [f"sleep {wait}"]
    if shutil.which("xdotool"):
        commands += [
            f"xdotool mousemove {WELCOME_CLOSE} click 1",  # the Welcome dialog's Close (no window manager)
            "sleep 1",
            "w=$(xdotool search --onlyvisible --name 'ParaView' | head -n 1)",
            '[ -n "$w" ] && xdotool windowmove "$w" 0 0 windowsize "$w" 1280 1024',
            "sleep 2",
            f'[ -n "$w" ] && xdotool mousemove {SEARCH_BOX} click 1 type --delay 30 "{SEARCH_TEXT}"',
            "sleep 2"]
    commands += [f'xwd -root -silent > "{OUT}/window.xwd"', f"kill {os.getpid()}"]
    subprocess.Popen(["sh", "-c", "; ".join(commands)], start_new_session=True)


if OUT:  # run by paraview --script with the test's environment
    main()
