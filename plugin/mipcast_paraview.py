"""ParaView plugin: "mipcast MIP Render", a filter that renders a MIP offscreen.

ParaView Python plugins can declare sources, filters, readers and writers but
not representations, and ParaView's own volume representation keeps its
``vtkVolume`` out of Python's reach.  So mipcast enters ParaView as a filter:
it takes a volume (``vtkImageData`` with one-component point scalars),
renders it offscreen with one of :data:`mipcast.METHODS` through
:class:`mipcast.offscreen.OffscreenView`, and outputs the picture as a 2D
image (Width x Height x 1) with two point arrays:

``mip_rgb``
    uint8, 3 components, the active scalars: the rendered picture (show it
    with the Slice representation and *Map Scalars* off).
``mip_value``
    float32, each pixel's ray maximum in data units, NaN where the ray misses
    the volume.  Methods without a float readout (``"stock"``, VTK's own
    MIP) do not produce it.

Rows are in VTK order (bottom row first).

Load it in the GUI with *Tools > Manage Plugins > Load New...*, or in pvpython
with ``LoadPlugin(path_to_this_file, ns=globals())``.  ParaView 5.11 on
Python 3.11 first needs the ``inspect.getargspec`` shim defined below; see
``README.md`` next to this file.
"""
# --- ParaView 5.11 on Python 3.11 ------------------------------------------
# paraview.detail.pythonalgorithm (imported by paraview.util.vtkAlgorithm and by
# ParaView's plugin loader) does ``from inspect import getargspec``, which
# Python 3.11 removed.  Define it from getfullargspec before that import.  The
# loader imports that module *before* it runs this file, so on ParaView 5.11 +
# Python 3.11 the shim must already be in place when LoadPlugin is called:
# import this module first (``import mipcast.plugin.mipcast_paraview``) or run
# this file as a script, which installs the shim and loads the plugin (see the
# end of the file and README.md).
import collections
import inspect

if not hasattr(inspect, "getargspec"):
    _ArgSpec = collections.namedtuple("ArgSpec", "args varargs keywords defaults")

    def _getargspec(func):
        spec = inspect.getfullargspec(func)
        return _ArgSpec(spec.args, spec.varargs, spec.varkw, spec.defaults)

    inspect.getargspec = _getargspec

import importlib.util
import math
import os
import sys


def _make_mipcast_importable():
    """Append the folder holding the ``mipcast`` package to ``sys.path`` if needed.

    Installed, this file is ``site-packages/mipcast/plugin/mipcast_paraview.py``;
    in the source tree it is ``<root>/plugin/mipcast_paraview.py`` (reached
    through the ``mipcast/plugin`` symlink or directly).  The folder is
    *appended*, so ParaView's own numpy and vtkmodules keep precedence.
    """
    if importlib.util.find_spec("mipcast") is not None:
        return
    here = globals().get("__file__")  # unset when run as text (paraview --script)
    candidates = []
    for path in {os.path.abspath(here), os.path.realpath(here)} if here else ():
        folder = os.path.dirname(path)
        for _ in range(2):
            folder = os.path.dirname(folder)
            candidates.append(folder)
    for folder in candidates:
        if os.path.isfile(os.path.join(folder, "mipcast", "__init__.py")):
            if folder not in sys.path:
                sys.path.append(folder)
            return
    raise ImportError(
        f"mipcast_paraview: the mipcast package was not found next to {here} nor on "
        "ParaView's Python path; install mipcast into the Python ParaView uses, or start "
        "ParaView with PYTHONPATH set to the folder that contains the mipcast package")


_make_mipcast_importable()

# The two registries fill the Method and View lists.  mipcast.methods needs only
# vtkmodules (already loaded by ParaView); the renderer is imported in RequestData.
from mipcast.methods import METHODS  # noqa: E402
from mipcast.offscreen import VIEWS  # noqa: E402
from paraview.util.vtkAlgorithm import (  # noqa: E402
    VTKPythonAlgorithmBase,
    smdomain,
    smhint,
    smproperty,
    smproxy,
)

paraview_plugin_name = "mipcast"
paraview_plugin_version = "0.1.0"

#: Names of the output point arrays.
RGB_ARRAY = "mip_rgb"
VALUE_ARRAY = "mip_value"
MAX_SIZE = 4096


def _string_list(values):
    """XML of a StringListDomain (a drop-down list in the properties panel)."""
    entries = "".join(f'<String value="{value}"/>' for value in values)
    return f'<StringListDomain name="list">{entries}</StringListDomain>'


def _documentation(text):
    return f"<Documentation>{text}</Documentation>"


@smproxy.filter(name="MipcastMIPRender", label="mipcast MIP Render")
@smhint.xml('<ShowInMenu category="mipcast"/>')
@smhint.xml('<RepresentationType view="RenderView" type="Slice"/>')
@smproperty.input(name="Input", port_index=0)
# image data, one volume or its pieces (a multiblock), an evenly spaced rectilinear grid (netCDF's)
@smdomain.datatype(dataTypes=["vtkImageData", "vtkRectilinearGrid"], composite_data_supported=True)
@smdomain.xml('<InputArrayDomain name="input_array" attribute_type="point"/>')
class MipcastMIPRender(VTKPythonAlgorithmBase):
    """Render a volume's maximum intensity projection offscreen into a 2D image.

    Properties (ParaView names): ``Scalars`` (point array to project; default
    the active scalars), ``Method`` (a name of :data:`mipcast.METHODS`,
    default "mip"), ``View`` (a preset of :data:`mipcast.offscreen.VIEWS`,
    default "oblique"), ``Width`` and ``Height`` (pixels, 1-4096, default
    512), ``SampleDistance`` (world units, default 0 = one sample per voxel),
    ``Window`` (grey window low, high; default 0, 0 = the data range).

    Examples
    --------
    In pvpython, after ``LoadPlugin(path, ns=globals())`` (the function is
    named after the label)::

        render = mipcastMIPRender(Input=reader, Method="mip", View="front")
        render.Width, render.Height = 640, 480
        image = servermanager.Fetch(render)
    """

    def __init__(self):
        VTKPythonAlgorithmBase.__init__(self, nInputPorts=1, nOutputPorts=1,
                                        inputType="vtkDataObject", outputType="vtkImageData")
        self._method = "mip"
        self._view = "oblique"
        self._width = 512
        self._height = 512
        self._sample_distance = 0.0
        self._window = (0.0, 0.0)

    # -- properties ----------------------------------------------------------
    @smproperty.xml(f"""
        <StringVectorProperty name="Scalars" label="Scalars"
            command="SetInputArrayToProcess" number_of_elements="5"
            element_types="0 0 0 0 2" animateable="0">
          <ArrayListDomain name="array_list" attribute_type="Scalars"
              input_domain_name="input_array">
            <RequiredProperties><Property name="Input" function="Input"/></RequiredProperties>
          </ArrayListDomain>
          {_documentation("The point array to project (one component).")}
        </StringVectorProperty>""")
    def SetInputArrayToProcess(self, idx, port, connection, field, name):
        VTKPythonAlgorithmBase.SetInputArrayToProcess(self, idx, port, connection, field, name)
        self.Modified()

    @smproperty.stringvector(name="Method", number_of_elements=1, default_values="mip")
    @smdomain.xml(_string_list(METHODS))
    @smdomain.xml(_documentation(
        "Rendering method, from mipcast.METHODS ('stock' is VTK's own MIP)."))
    def SetMethod(self, method):
        self._method = str(method)
        self.Modified()

    @smproperty.stringvector(name="View", number_of_elements=1, default_values="oblique")
    @smdomain.xml(_string_list(VIEWS))
    @smdomain.xml(_documentation("Camera preset: the whole volume seen from this direction."))
    def SetView(self, view):
        self._view = str(view)
        self.Modified()

    @smproperty.intvector(name="Width", default_values=512)
    @smdomain.intrange(min=1, max=MAX_SIZE)
    @smdomain.xml(_documentation("Output width in pixels."))
    def SetWidth(self, width):
        self._width = int(width)
        self.Modified()

    @smproperty.intvector(name="Height", default_values=512)
    @smdomain.intrange(min=1, max=MAX_SIZE)
    @smdomain.xml(_documentation("Output height in pixels."))
    def SetHeight(self, height):
        self._height = int(height)
        self.Modified()

    @smproperty.doublevector(name="SampleDistance", default_values=0.0)
    @smdomain.doublerange(min=0.0)
    @smdomain.xml(_documentation(
        "World units between samples along a ray; 0 = one sample per voxel "
        "(the smallest spacing)."))
    def SetSampleDistance(self, distance):
        self._sample_distance = float(distance)
        self.Modified()

    @smproperty.doublevector(name="Window", default_values=[0.0, 0.0])
    @smdomain.xml(_documentation(
        "Grey window (low, high) in data units: black at low, white at high. "
        "Both 0 = the data range."))
    def SetWindow(self, low, high):
        self._window = (float(low), float(high))
        self.Modified()

    # -- pipeline --------------------------------------------------------------
    def FillInputPortInformation(self, port, info):
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject")
        return 1

    def RequestInformation(self, request, inInfo, outInfo):
        from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

        width = min(max(self._width, 1), MAX_SIZE)
        height = min(max(self._height, 1), MAX_SIZE)
        info = outInfo.GetInformationObject(0)
        sddp = vtkStreamingDemandDrivenPipeline
        whole = (0, width - 1, 0, height - 1, 0, 0)
        info.Set(sddp.WHOLE_EXTENT(), whole, 6)
        # A failed RequestData leaves ParaView's post filter (downstream of every
        # source) with its last request; if the picture shrank since, that request
        # exceeds the new whole extent and VTK reports an error on the next update.
        # The filter always produces the whole picture, so larger requests are fine.
        info.Set(sddp.UNRESTRICTED_UPDATE_EXTENT(), 1)
        return 1

    def RequestUpdateExtent(self, request, inInfo, outInfo):
        # A projection needs the whole volume, whatever part of the picture is asked for.
        from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline

        info = inInfo[0].GetInformationObject(0)
        sddp = vtkStreamingDemandDrivenPipeline
        if info.Has(sddp.WHOLE_EXTENT()):
            info.Set(sddp.UPDATE_EXTENT(), info.Get(sddp.WHOLE_EXTENT()), 6)
        info.Set(sddp.UPDATE_PIECE_NUMBER(), 0)
        info.Set(sddp.UPDATE_NUMBER_OF_PIECES(), 1)
        info.Set(sddp.EXACT_EXTENT(), 1)
        return 1

    def RequestData(self, request, inInfo, outInfo):
        from vtkmodules.vtkCommonCore import vtkOutputWindow
        from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData

        source = vtkDataObject.GetData(inInfo[0], 0)
        output = vtkImageData.GetData(outInfo, 0)
        try:
            image = self._volume(source)
            rgb, values = self._render(image)
        except (TypeError, ValueError) as error:
            vtkOutputWindow.GetInstance().DisplayErrorText(f"mipcast MIP Render: {error}\n")
            return 0
        _fill_output(output, rgb, values)
        return 1

    # -- helpers -------------------------------------------------------------------
    def _volume(self, source):
        """A shallow copy of the input as image data (:func:`mipcast.io.as_image_data`), the chosen array
        as active point scalars.

        A multiblock or partitioned input is the one volume it holds, or its image pieces joined
        (a .vtm / .vtpd file, a reader's multiblock output); an evenly spaced rectilinear grid (netCDF
        CF's) is image data; a left-handed direction matrix is made right-handed (voxels kept in place).
        """
        from vtkmodules.vtkCommonDataModel import vtkDataObject, vtkImageData, vtkRectilinearGrid

        from mipcast.io import as_image_data

        try:
            source = as_image_data(source) if source is not None else None
        except TypeError as error:
            if isinstance(source, vtkRectilinearGrid):  # uneven steps
                raise TypeError(f"{error} (ParaView: Filters > Resample To Image)") from None
            raise
        if not isinstance(source, vtkImageData):
            kind = "nothing" if source is None else type(source).__name__
            raise TypeError(
                f"the input must be image data (vtkImageData) or an evenly spaced rectilinear grid, got {kind}; "
                "resample it "
                "first (Filters > Resample To Image)")
        image = vtkImageData()
        image.ShallowCopy(source)
        selected = self.GetInputArrayInformation(0)
        name = selected.Get(vtkDataObject.FIELD_NAME()) if selected is not None else None
        if name:
            point_data = image.GetPointData()
            if point_data.GetArray(name) is None:
                names = [point_data.GetArrayName(i) for i in range(point_data.GetNumberOfArrays())]
                raise ValueError(
                    f"the input has no point array '{name}' (Scalars); its point arrays are "
                    f"{names or 'none'} (cell arrays cannot be projected: apply "
                    "Filters > Cell Data to Point Data first)")
            point_data.SetActiveScalars(name)
        return image

    def _render(self, image):
        """Render ``image``: (rgb uint8 (H, W, 3), values float32 (H, W) or None), top row first."""
        from mipcast.offscreen import OffscreenView
        from mipcast.core.validation import check_choice, check_image, check_positive

        for name, pixels in (("Width", self._width), ("Height", self._height)):
            if not 1 <= pixels <= MAX_SIZE:
                raise ValueError(f"{name} must be 1 to {MAX_SIZE} pixels, got {pixels}")
        check_choice("Method", self._method, tuple(METHODS))
        check_choice("View", self._view, tuple(VIEWS))
        check_image(image)
        sample_distance = None
        if self._sample_distance != 0.0:
            sample_distance = check_positive("SampleDistance", self._sample_distance)
        window = "full"  # Window 0, 0: the data range, as documented
        if self._window != (0.0, 0.0):
            window = self._window
            if not (window[1] > window[0] and all(math.isfinite(v) for v in window)):
                raise ValueError(
                    f"Window must be finite (low, high) with high > low, got {window}; "
                    "set both to 0 for the data range")
        else:
            scalars = image.GetPointData().GetScalars()
            low, high = scalars.GetRange(0)
            if not high > low:
                raise ValueError(
                    f"the scalars '{scalars.GetName()}' are constant ({low:g}): there is no "
                    "data range to map to grey levels; set Window (low, high) explicitly")
        view = OffscreenView(image, self._method, size=(self._width, self._height),
                             view=self._view, sample_distance=sample_distance, window=window)
        try:
            rgb = view.screenshot()
            values = view.float_image() if view.method.float_readout else None
        finally:
            view.render_window.Finalize()
        return rgb, values


def _fill_output(output, rgb, values):
    """Put top-row-first numpy pictures into ``output`` as VTK-ordered point arrays."""
    import numpy as np
    from vtkmodules.util.numpy_support import numpy_to_vtk

    height, width = rgb.shape[:2]
    output.SetExtent(0, width - 1, 0, height - 1, 0, 0)
    output.SetOrigin(0.0, 0.0, 0.0)
    output.SetSpacing(1.0, 1.0, 1.0)
    colours = numpy_to_vtk(np.ascontiguousarray(rgb[::-1]).reshape(-1, 3), deep=True)
    colours.SetName(RGB_ARRAY)
    output.GetPointData().SetScalars(colours)
    if values is not None:
        floats = numpy_to_vtk(
            np.ascontiguousarray(values[::-1], dtype=np.float32).reshape(-1), deep=True)
        floats.SetName(VALUE_ARRAY)
        output.GetPointData().AddArray(floats)


def _this_file():
    """This file's path, also when run from text that has no ``__file__``."""
    path = globals().get("__file__")
    if path:
        return os.path.abspath(path)
    spec = importlib.util.find_spec("mipcast.plugin.mipcast_paraview")
    return spec.origin if spec is not None else None


if __name__ == "__main__":
    # Run as a script (``paraview --script=<this file>``, the Python Shell's
    # *Run Script*, or ``pvpython <this file>``): the shim above is in place, so
    # ParaView's loader works; load this file as a plugin.
    from paraview.simple import LoadPlugin

    _path = _this_file()
    if _path is None:
        raise RuntimeError(
            "mipcast_paraview: cannot tell where this file is; the getargspec shim is "
            "installed now, so load it with Tools > Manage Plugins > Load New")
    LoadPlugin(_path, ns=globals())
