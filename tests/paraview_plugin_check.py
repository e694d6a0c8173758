"""Run mipcast's ParaView plugin inside pvpython and compare it with a direct render.

Usage (from the repository root)::

    PYTHONPATH=$(python3 tests/installed.py) xvfb-run -a pvpython tests/paraview_plugin_check.py [--png out.png]

Loads ``plugin/mipcast_paraview.py`` with ``LoadPlugin``, feeds the
"vessels" fixture (32^3) through a PVTrivialProducer into the
"mipcast MIP Render" filter at 96 x 80 pixels for every method of
:data:`mipcast.METHODS`, fetches the output and compares it with
``OffscreenView(...).screenshot()`` / ``.float_image()`` rendered directly.
Then it feeds bad inputs (3-component scalars, NaN values, poly data, an
inverted window) and records the error text the filter reports, and checks
that a filter that failed updates cleanly once fixed (and resized).  Prints
one JSON object on the last line of stdout; used by
tests/test_paraview_plugin.py.
"""
import json
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow
from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData

import mipcast.plugin
from vtk_png import write_png
from mipcast import METHODS
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

# ParaView modules are imported in load_plugin(): this file is also imported
# (not run) by pytest's doctest collection, outside ParaView.

WIDTH, HEIGHT = 96, 80
PLUGIN_PATH = os.path.join(os.path.dirname(os.path.abspath(mipcast.plugin.__file__)),
                           "mipcast_paraview.py")


def load_plugin():
    """Load the plugin into this module's globals (pvpython only)."""
    # Importing the plugin module installs the inspect.getargspec shim that
    # ParaView 5.11's plugin loader needs on Python 3.11, before LoadPlugin.
    import mipcast.plugin.mipcast_paraview  # noqa: F401
    from paraview.simple import LoadPlugin

    LoadPlugin(PLUGIN_PATH, ns=globals())


def mip_render(**properties):
    """A "mipcast MIP Render" filter proxy (LoadPlugin put its function in globals())."""
    try:
        factory = globals()["mipcastMIPRender"]
    except KeyError:
        raise RuntimeError(
            f"LoadPlugin({PLUGIN_PATH!r}) did not register mipcastMIPRender") from None
    from paraview.simple import SetActiveSource

    # The Scalars list is filled from the *active* source when the proxy is
    # created, before Input is set: make the input the active source first.
    SetActiveSource(properties["Input"])
    return factory(Width=WIDTH, Height=HEIGHT, **properties)


def producer_of(data):
    """A pipeline source whose output is ``data`` (builtin session)."""
    from paraview.simple import PVTrivialProducer

    producer = PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(data)
    return producer


def fetch_arrays(render):
    """Run the filter; return (dims, rgb (H, W, 3) top row first, values (H, W) or None)."""
    from paraview import servermanager

    render.UpdatePipeline()
    output = servermanager.Fetch(render)
    width, height, depth = output.GetDimensions()
    point_data = output.GetPointData()
    rgb = vtk_to_numpy(point_data.GetArray("mip_rgb")).reshape(height, width, 3)[::-1]
    values = point_data.GetArray("mip_value")
    if values is not None:
        values = vtk_to_numpy(values).reshape(height, width)[::-1]
    active = point_data.GetScalars().GetName() if point_data.GetScalars() else None
    return [width, height, depth], rgb, values, active


def compare(image, render, method):
    """Plugin output vs a direct OffscreenView render of the same scene."""
    dims, rgb, values, active = fetch_arrays(render)
    view = OffscreenView(image, method, size=(WIDTH, HEIGHT), view="oblique", window="full")  # Window 0, 0
    direct_rgb = view.screenshot()
    diff = np.abs(rgb.astype(np.int16) - direct_rgb.astype(np.int16)).max(axis=-1)
    result = {
        "dims": dims,
        "active_scalars": active,
        "rgb_dtype": str(rgb.dtype),
        "pixels": int(WIDTH * HEIGHT),
        "lit_pixels": int(np.count_nonzero(rgb.max(axis=-1) > 0)),
        "max_rgb_diff": int(diff.max()),
        "rgb_within_1_share": float(np.mean(diff <= 1)),
        "has_values": values is not None,
    }
    if values is not None and hasattr(view.mapper, "Attach"):
        direct_values = view.float_image()
        low, high = image.GetPointData().GetScalars().GetRange(0)
        hit = np.isfinite(values) & np.isfinite(direct_values)
        result.update(
            value_dtype=str(values.dtype),
            value_range=float(high - low),
            nan_share=float(np.mean(np.isnan(values))),
            nan_mismatch=int(np.count_nonzero(np.isnan(values) != np.isnan(direct_values))),
            max_value_diff=float(np.abs(values[hit] - direct_values[hit]).max()),
        )
    return result, rgb


class CapturedLog:
    """Collect VTK's error and warning text while in the ``with`` block."""

    def __enter__(self):
        self.log = vtkStringOutputWindow()
        self.previous = vtkOutputWindow.GetInstance()
        self.previous.Register(None)  # keep it alive while it is not the instance
        vtkOutputWindow.SetInstance(self.log)
        return self

    def __exit__(self, *exc):
        vtkOutputWindow.SetInstance(self.previous)
        self.previous.UnRegister(None)

    @property
    def text(self):
        return self.log.GetOutput()


def error_text(data, **properties):
    """Apply the filter to ``data`` and return the error text it reports."""
    from paraview.simple import Delete

    with CapturedLog() as captured:
        source = producer_of(data) if isinstance(data, vtkDataObject) else data  # (else a source proxy)
        render = mip_render(Input=source, **properties)
        render.UpdatePipeline()
        Delete(render)
    text = captured.text
    lines = [line for line in text.splitlines() if "mipcast MIP Render" in line]
    return lines[0].strip() if lines else text.strip()


def recovery(image):
    """Fail (bad Window), then fix it and shrink the picture: a clean update is expected."""
    from paraview import servermanager

    render = mip_render(Input=producer_of(image), Window=[1.0, 0.5])
    with CapturedLog() as failed:
        render.UpdatePipeline()
    with CapturedLog() as fixed:
        render.Window = [0.0, 0.0]
        render.Width, render.Height = WIDTH // 2, HEIGHT // 2
        render.UpdatePipeline()
        output = servermanager.Fetch(render)
    values = output.GetPointData().GetArray("mip_value")
    return {
        "failed_reported": "mipcast MIP Render" in failed.text,
        "dims": list(output.GetDimensions()),
        "value_tuples": values.GetNumberOfTuples() if values is not None else 0,
        "log": fixed.text.strip(),
    }


def bad_volumes():
    """Inputs the filter must refuse: name -> (data or source proxy, extra properties)."""
    from paraview.simple import Sphere

    good = make_fixture("vessels", size=16)
    values = vtk_to_numpy(good.GetPointData().GetScalars())

    # (three components are drawn: their magnitude, as in ParaView)
    holes = vtkImageData()
    holes.SetDimensions(good.GetDimensions())
    broken = values.copy()
    broken[:] = np.nan  # every value missing (NaN voxels among finite ones are drawn as missing data)
    array = numpy_to_vtk(broken, deep=True)
    array.SetName("scalars")
    holes.GetPointData().SetScalars(array)
    return {
        "nan": (holes, {}),
        "polydata": (Sphere(), {}),
        "bad_window": (good, {"Window": [1.0, 0.5]}),
    }


def pieces_of_one_volume(image):
    """A multiblock of two image pieces of ``image`` (a .vtm of a volume): the filter draws the whole volume."""
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet
    from vtkmodules.vtkImagingCore import vtkExtractVOI

    blocks = vtkMultiBlockDataSet()
    for index, extent in enumerate([(0, 31, 0, 31, 0, 15), (0, 31, 0, 31, 15, 31)]):
        cut = vtkExtractVOI()
        cut.SetInputData(image)
        cut.SetVOI(*extent)
        cut.Update()
        blocks.SetBlock(index, cut.GetOutput())
    with CapturedLog() as captured:
        result, _ = compare(image, mip_render(Input=producer_of(blocks), Method="analytic"), "analytic")
    result["log"] = captured.text.strip()
    return result


def other_forms_of(image):
    """The same volume as an evenly spaced rectilinear grid with a decreasing x axis (netCDF CF's), as image
    data with a left-handed direction matrix (x flipped), and an uneven rectilinear grid (refused): the first
    two drawn as ``image``, analytic, its float readout also against the float64 reference."""
    from vtkmodules.vtkCommonDataModel import vtkRectilinearGrid

    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(nz, ny, nx)
    flipped = numpy_to_vtk(np.ascontiguousarray(values[:, :, ::-1]).ravel(), deep=True)
    flipped.SetName("scalars")
    grid = vtkRectilinearGrid()
    grid.SetDimensions(nx, ny, nz)
    for axis, count, decreasing in (("X", nx, True), ("Y", ny, False), ("Z", nz, False)):
        coordinates = np.arange(count, dtype=np.float64)
        getattr(grid, f"Set{axis}Coordinates")(numpy_to_vtk(coordinates[::-1].copy() if decreasing else coordinates,
                                                             deep=True))
    grid.GetPointData().SetScalars(flipped)
    mirrored = vtkImageData()
    mirrored.SetDimensions(nx, ny, nz)
    mirrored.SetOrigin(nx - 1.0, 0.0, 0.0)
    mirrored.SetDirectionMatrix(-1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    mirrored.GetPointData().SetScalars(flipped)
    results = {}
    for name, data in (("rectilinear", grid), ("left_handed", mirrored)):
        with CapturedLog() as captured:
            render = mip_render(Input=producer_of(data), Method="analytic")
            result, _ = compare(image, render, "analytic")
        values = fetch_arrays(render)[2]
        view = OffscreenView(image, "analytic", size=(WIDTH, HEIGHT), view="oblique", window="full")
        expected = METHODS["analytic"].reference(image, view.camera, view.size, window=view.window)
        hit = np.isfinite(values) & np.isfinite(expected)
        result["reference_nan_mismatch"] = int(np.count_nonzero(np.isnan(values) != np.isnan(expected)))
        result["max_reference_diff"] = float(np.abs(values[hit] - expected[hit]).max())
        result["log"] = captured.text.strip()
        results[name] = result
    uneven = vtkRectilinearGrid()
    uneven.DeepCopy(grid)
    uneven.SetZCoordinates(numpy_to_vtk(np.cumsum(np.linspace(0.5, 1.5, nz)), deep=True))
    results["uneven"] = error_text(uneven)
    return results


def main(argv):
    image = make_fixture("vessels", size=32)
    producer = producer_of(image)
    report = {"plugin": PLUGIN_PATH, "methods": {}}
    picture = None
    for method in METHODS:
        render = mip_render(Input=producer, Method=method)
        report["methods"][method], rgb = compare(image, render, method)
        if method == "mip":
            picture = rgb
    report.update(report["methods"]["mip"])
    report["errors"] = {name: error_text(data, **props)
                        for name, (data, props) in bad_volumes().items()}
    report["recovery"] = recovery(image)
    report["pieces"] = pieces_of_one_volume(image)
    report["forms"] = other_forms_of(image)
    if "--png" in argv:
        write_png(argv[argv.index("--png") + 1], picture)
    print(json.dumps(report))
    sys.stdout.flush()


if __name__ == "__main__":
    load_plugin()
    main(sys.argv)
