"""mipcast live in ParaView's render view, measured against mipcast's own offscreen render.

Usage (from the repository root)::

    PYTHONPATH=$(python3 tests/installed.py) xvfb-run -a pvpython tests/paraview_view_check.py [--png-dir DIR]

Writes the "vessels" fixture (48^3) to a .vti, opens it with ParaView's XML
reader and shows it in a render view (112 x 96 pixels) with
:func:`mipcast.plugin.render_view.show`.  Every picture is taken with
``SaveScreenshot`` and compared with an :class:`mipcast.offscreen.OffscreenView`
of the same image and method, given ParaView's camera (copied after
ParaView's render: position, focal point, view up, view angle, projection,
clipping range), the same size and *independent* copies of the transfer
functions rebuilt from the proxies' ``RGBPoints`` / ``ColorSpace`` /
``Points``.  The reference scene holds the same opaque geometry as
ParaView's (the source's outline, a sphere), flat-coloured (Ambient 1,
Diffuse 0) so that ParaView's light kit and VTK's headlight agree.

Measured: each method; a parallel projection; an opaque sphere through the
volume (rays must stop at it); the colour map edited through the proxies;
an upstream change (a Wavelet's extent); a time series animated (3 .vti
files); the shown array renamed upstream and back; the outline re-coloured by
another array; replacing and hiding (the source's representation
restored); deleting a view or source (no render afterwards); the macros;
refused inputs; the effect of ParaView's FXAA and of translucent geometry
with depth peeling for volumes.  Prints one JSON object on the last line of
stdout; used by tests/test_paraview_view.py.
"""
import json
import os
import sys
import tempfile

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

import mipcast.plugin
from vtk_png import write_png
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

# ParaView modules are imported inside functions: pytest's doctest collection
# imports this file outside ParaView.

WIDTH, HEIGHT = 112, 96
MACROS = os.path.join(os.path.dirname(os.path.abspath(mipcast.plugin.__file__)), "macros")
#: Methods compared with the offscreen render; the rest are reported too.
METHODS = tuple(mipcast.METHODS)  # every method of the table


# -- ParaView side ----------------------------------------------------------------------------
def plain_view(size=(WIDTH, HEIGHT)):
    """A render view with the settings that would disturb a pixel comparison switched off."""
    from paraview.simple import CreateView, SetActiveView

    view = CreateView("RenderView")
    SetActiveView(view)
    view.ViewSize = list(size)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.BackgroundColorMode = "Single Color"
    view.Background = [0.0, 0.0, 0.0]
    view.UseFXAA = 0
    view.UseToneMapping = 0
    return view


def set_camera(view, azimuth=35.0, elevation=25.0, parallel=False):
    from paraview.simple import Render

    view.CameraParallelProjection = int(parallel)
    view.CameraPosition = [0.0, 0.0, 1.0]
    view.CameraFocalPoint = [0.0, 0.0, 0.0]
    view.CameraViewUp = [0.0, 1.0, 0.0]
    view.ResetCamera(False)
    camera = view.GetActiveCamera()
    camera.Azimuth(azimuth)
    camera.Elevation(elevation)
    camera.OrthogonalizeViewUp()
    view.ResetCamera(False)
    Render(view)


def flat(display, colour):
    """Colour a ParaView display flat (no lighting), as the reference does."""
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = list(colour)
    display.DiffuseColor = list(colour)
    display.Ambient = 1.0
    display.Diffuse = 0.0
    display.Specular = 0.0


def screenshot(view, path):
    """SaveScreenshot to ``path``; return (H, W, 3) uint8, top row first."""
    from paraview.simple import Render, SaveScreenshot
    from vtkmodules.vtkIOImage import vtkPNGReader

    Render(view)
    SaveScreenshot(path, view, ImageResolution=[WIDTH, HEIGHT], TransparentBackground=0)
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    output = reader.GetOutput()
    width, height, _ = output.GetDimensions()
    pixels = vtk_to_numpy(output.GetPointData().GetScalars())
    return pixels.reshape(height, width, -1)[::-1, :, :3].copy()


# -- reference side ---------------------------------------------------------------------------
def reference_property(lut, pwf):
    """A vtkVolumeProperty rebuilt from the proxies' values (not their client-side objects)."""
    colour = vtkColorTransferFunction()
    points = list(lut.RGBPoints)
    for index in range(0, len(points), 4):
        colour.AddRGBPoint(*points[index:index + 4])
    # the proxy's enumeration is VTK's (RGB 0, HSV 1, Lab 2, Diverging 3, ...)
    colour.SetColorSpace(lut.SMProxy.GetProperty("ColorSpace").GetElement(0))
    colour.SetHSVWrap(int(lut.HSVWrap))
    opacity = vtkPiecewiseFunction()
    values = list(pwf.Points)
    for index in range(0, len(values), 4):
        opacity.AddPoint(*values[index:index + 4])
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    return prop


def flat_actor(polydata, colour):
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    mapper = vtkPolyDataMapper()
    mapper.SetInputData(polydata)
    mapper.ScalarVisibilityOff()
    actor = vtkActor()
    actor.SetMapper(mapper)
    prop = actor.GetProperty()
    prop.SetColor(*colour)
    prop.SetAmbient(1.0)
    prop.SetDiffuse(0.0)
    prop.SetSpecular(0.0)
    return actor


def outline_of(image):
    from vtkmodules.vtkFiltersModeling import vtkOutlineFilter

    outline = vtkOutlineFilter()
    outline.SetInputData(image)
    outline.Update()
    return outline.GetOutput()


def reference(image, method, view, lut, pwf, actors=(), peel_volumes=None, component=None, **settings):
    """mipcast's own offscreen render of ``image`` with ParaView's camera and functions.

    ``peel_volumes`` True/False: depth peeling on (VTK's dual depth peeling,
    ParaView's peel count), with or without volumes peeled; None: off.
    """
    from mipcast.core.parameters import set_parameters

    scene = OffscreenView(image, method, size=(WIDTH, HEIGHT), component=component)
    if peel_volumes is not None:
        scene.renderer.SetUseDepthPeeling(True)
        scene.renderer.SetUseDepthPeelingForVolumes(bool(peel_volumes))
        scene.renderer.SetMaximumNumberOfPeels(int(view.MaximumNumberOfPeels))
        scene.renderer.SetOcclusionRatio(0.0)
    set_parameters(scene.mapper, **settings)
    scene.volume.SetProperty(reference_property(lut, pwf))
    for actor in actors:
        scene.renderer.AddActor(actor)
    camera = scene.renderer.GetActiveCamera()
    camera.DeepCopy(view.GetClientSideObject().GetActiveCamera())
    pixels = scene.screenshot()
    scene.render_window.Finalize()
    return pixels, camera.GetClippingRange()


def compare(pv, ref):
    diff = np.abs(pv.astype(np.int16) - ref.astype(np.int16)).max(axis=-1)
    return {
        "within_1_share": float(np.mean(diff <= 1)),
        "max_diff": int(diff.max()),
        "lit_share": float(np.mean(pv.max(axis=-1) > 8)),
        "ref_lit_share": float(np.mean(ref.max(axis=-1) > 8)),
    }


def changed_share(a, b):
    return float(np.mean(np.abs(a.astype(np.int16) - b.astype(np.int16)).max(axis=-1) > 1))


def volume_in_clipping_range(image, view):
    """True when the whole volume lies between ParaView's near and far clipping planes."""
    camera = view.GetClientSideObject().GetActiveCamera()
    near, far = camera.GetClippingRange()
    position = np.array(camera.GetPosition())
    direction = np.array(camera.GetDirectionOfProjection())
    b = image.GetBounds()
    corners = np.array([(x, y, z) for x in b[0:2] for y in b[2:4] for z in b[4:6]])
    depths = (corners - position) @ direction
    return bool(near <= depths.min() and depths.max() <= far)


def count_in_renderer(view, volumes):
    """How many of ``volumes`` are in the view's renderer.

    ParaView's own representations of image data keep a (hidden) vtkVolume
    in the renderer too, so the total count says little.
    """
    collection = view.GetClientSideObject().GetRenderer().GetVolumes()
    items = [collection.GetItemAsObject(i) for i in range(collection.GetNumberOfItems())]
    return sum(1 for item in items if any(item is volume for volume in volumes))


# -- the measurements ---------------------------------------------------------------------------
def methods_report(reader, image, view, png):
    from mipcast.plugin.render_view import show, shown
    from paraview.simple import GetColorTransferFunction, GetDisplayProperties, \
        GetOpacityTransferFunction

    report = {}
    outline_colour = (1.0, 1.0, 0.0)
    volumes = []
    for method in METHODS:
        volumes.append(show(reader, view, method=method))
        display = GetDisplayProperties(reader, view)
        coloured_by = list(display.ColorArrayName)
        flat(GetDisplayProperties(reader, view), outline_colour)
        set_camera(view)
        pv = screenshot(view, png(f"view_{method}"))
        lut = GetColorTransferFunction("scalars")
        pwf = GetOpacityTransferFunction("scalars")
        ref, clipping = reference(image, method, view, lut, pwf,
                                  actors=[flat_actor(outline_of(image), outline_colour)])
        result = compare(pv, ref)
        result.update(volumes_in_renderer=count_in_renderer(view, volumes),
                      same_volume=all(v is volumes[0] for v in volumes),
                      representation=str(display.Representation), coloured_by=coloured_by,
                      lut_ends=[lut.RGBPoints[0], lut.RGBPoints[-4]],
                      pwf_ends=[pwf.Points[0], pwf.Points[-4]],
                      data_range=list(image.GetPointData().GetScalars().GetRange(0)),
                      shown=len(shown(view)),
                      shown_method=shown(view)[0].method,
                      volume_in_clipping_range=volume_in_clipping_range(image, view),
                      clipping=list(view.GetClientSideObject().GetActiveCamera().GetClippingRange()),
                      ref_clipping=list(clipping))
        report[method] = result
    return report


def interactive_report(reader, image, view, png):
    """An interactive render (what ParaView draws while the mouse rotates), LOD forced on."""
    from mipcast.plugin.render_view import show
    from paraview.simple import GetColorTransferFunction, GetDisplayProperties, \
        GetOpacityTransferFunction
    from vtkmodules.vtkRenderingCore import vtkWindowToImageFilter

    show(reader, view, method="analytic")
    flat(GetDisplayProperties(reader, view), (1.0, 1.0, 0.0))
    set_camera(view, azimuth=-20.0, elevation=40.0)
    threshold = view.LODThreshold
    view.LODThreshold = 0.0  # every representation switches to its LOD while interacting
    view.InteractiveRender()
    grab = vtkWindowToImageFilter()
    grab.SetInput(view.GetRenderWindow())
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    output = grab.GetOutput()
    width, height, _ = output.GetDimensions()
    pv = vtk_to_numpy(output.GetPointData().GetScalars()).reshape(height, width, 3)[::-1].copy()
    view.LODThreshold = threshold
    ref, _ = reference(image, "analytic", view, GetColorTransferFunction("scalars"),
                       GetOpacityTransferFunction("scalars"),
                       actors=[flat_actor(outline_of(image), (1.0, 1.0, 0.0))])
    write_png(png("view_interactive"), pv)
    result = compare(pv, ref)
    result["size"] = [width, height]
    return result


def without_volume(reader, view, png):
    """The same scene with the volume hidden: what show() adds."""
    from mipcast.plugin.render_view import hide, show, shown

    volume = show(reader, view, method="mip")
    set_camera(view)
    with_volume = screenshot(view, png("view_before_hide"))
    removed = hide(reader, view)
    bare = screenshot(view, png("view_hidden"))
    result = {"removed": removed, "again": hide(reader, view), "shown": len(shown(view)),
              "volumes_in_renderer": count_in_renderer(view, [volume]),
              "changed_share": changed_share(with_volume, bare),
              "lit_share": float(np.mean(bare.max(axis=-1) > 8))}
    return result


def parallel_report(reader, image, view, png):
    from mipcast.plugin.render_view import show
    from paraview.simple import GetColorTransferFunction, GetOpacityTransferFunction

    show(reader, view, method="mip", outline=False)
    from paraview.simple import Hide
    Hide(reader, view)  # the outline off: the volume alone
    set_camera(view, azimuth=-50.0, elevation=10.0, parallel=True)
    pv = screenshot(view, png("view_parallel_no_outline"))
    ref, _ = reference(image, "mip", view, GetColorTransferFunction("scalars"),
                       GetOpacityTransferFunction("scalars"))
    result = compare(pv, ref)
    result["volume_in_clipping_range"] = volume_in_clipping_range(image, view)
    return result


def sphere_report(reader, image, view, png):
    """An opaque sphere through the middle of the volume: rays stop at it."""
    from mipcast.plugin.render_view import show
    from paraview.simple import GetColorTransferFunction, GetDisplayProperties, \
        GetOpacityTransferFunction, Hide, Show, Sphere

    bounds = image.GetBounds()
    centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    sphere = Sphere(Center=centre, Radius=0.3 * (bounds[1] - bounds[0]),
                    ThetaResolution=24, PhiResolution=24)
    display = Show(sphere, view)
    flat(display, (0.0, 0.6, 0.0))
    results = {}
    for method in ("mip", "analytic", "demip"):
        show(reader, view, method=method)
        flat(GetDisplayProperties(reader, view), (1.0, 1.0, 0.0))
        set_camera(view)
        pv = screenshot(view, png(f"view_sphere_{method}"))
        lut, pwf = GetColorTransferFunction("scalars"), GetOpacityTransferFunction("scalars")
        sphere.UpdatePipeline()
        surface = sphere.GetClientSideObject().GetOutputDataObject(0)
        outline = flat_actor(outline_of(image), (1.0, 1.0, 0.0))
        ref, _ = reference(image, method, view, lut, pwf,
                           actors=[outline, flat_actor(surface, (0.0, 0.6, 0.0))])
        no_sphere, _ = reference(image, method, view, lut, pwf,
                                 actors=[flat_actor(outline_of(image), (1.0, 1.0, 0.0))])
        result = compare(pv, ref)
        # pixels where the sphere changes the picture: where rays stop at it
        result["sphere_changed_share"] = changed_share(ref, no_sphere)
        green = (pv[..., 1] > pv[..., 0] + 20) & (pv[..., 1] > pv[..., 2] + 20)
        result["sphere_pixel_share"] = float(np.mean(green))
        results[method] = result
    Hide(sphere, view)
    return results


def colour_map_report(reader, image, view, png):
    """Edit the colour map through the proxies, as the colour map editor does."""
    from mipcast.plugin.render_view import show
    from paraview.simple import GetColorTransferFunction, GetDisplayProperties, \
        GetOpacityTransferFunction

    show(reader, view, method="analytic")
    flat(GetDisplayProperties(reader, view), (1.0, 1.0, 0.0))
    set_camera(view)
    before = screenshot(view, png("view_lut_before"))
    lut = GetColorTransferFunction("scalars")
    pwf = GetOpacityTransferFunction("scalars")
    low, high = image.GetPointData().GetScalars().GetRange(0)
    middle = low + 0.4 * (high - low)
    lut.ColorSpace = "RGB"
    lut.RGBPoints = [low, 0.0, 0.0, 0.3, middle, 0.0, 0.8, 0.2, high, 1.0, 1.0, 0.9]
    pwf.Points = [low, 0.0, 0.5, 0.0, middle, 0.6, 0.5, 0.0, high, 1.0, 0.5, 0.0]
    after = screenshot(view, png("view_lut_after"))
    ref, _ = reference(image, "analytic", view, lut, pwf,
                       actors=[flat_actor(outline_of(image), (1.0, 1.0, 0.0))])
    result = compare(after, ref)
    result["changed_share"] = changed_share(before, after)
    # a range the user locked (colour map editor: custom range, or mode "Never") stays
    lut.AutomaticRescaleRangeMode = "Never"
    show(reader, view, method="analytic")
    result["locked_points_kept"] = list(lut.RGBPoints) == [
        low, 0.0, 0.0, 0.3, middle, 0.0, 0.8, 0.2, high, 1.0, 1.0, 0.9]
    lut.RescaleTransferFunction(middle, high)
    pwf.RescaleTransferFunction(middle, high)
    show(reader, view, method="analytic")
    result["locked_range"] = [lut.RGBPoints[0], lut.RGBPoints[-4]]
    result["locked_range_expected"] = [middle, high]
    lut.AutomaticRescaleRangeMode = "Grow and update on 'Apply'"
    show(reader, view, method="analytic")
    result["unlocked_range"] = [lut.RGBPoints[0], lut.RGBPoints[-4]]
    result["data_range"] = [low, high]
    result["same_object"] = (
        view.GetClientSideObject().GetRenderer().GetVolumes().GetItemAsObject(0)
        .GetProperty().GetRGBTransferFunction(0) is lut.GetClientSideObject())
    return result


def upstream_report(view, png):
    """A Wavelet shown, then its extent changed: the volume follows without show() again.

    Then the Wavelet is deleted: its volume must be gone after the next render.
    """
    from mipcast.plugin.render_view import hide, show, shown
    from paraview.simple import Delete, GetColorTransferFunction, GetDisplayProperties, \
        GetOpacityTransferFunction, Render, Wavelet

    for entry in shown(view):  # the wavelet alone
        hide(entry.source, view)
    wavelet = Wavelet()
    show(wavelet, view, method="mip")
    coloured_by = list(GetDisplayProperties(wavelet, view).ColorArrayName)
    flat(GetDisplayProperties(wavelet, view), (1.0, 1.0, 0.0))
    set_camera(view)
    before = screenshot(view, png("view_wavelet_before"))
    wavelet.WholeExtent = [-10, 10, -10, 10, -4, 4]
    after = screenshot(view, png("view_wavelet_after"))  # same camera, the slab is thinner
    wavelet.UpdatePipeline()
    image = vtkImageData()
    image.ShallowCopy(wavelet.GetClientSideObject().GetOutputDataObject(0))
    ref, _ = reference(image, "mip", view, GetColorTransferFunction("RTData"),
                       GetOpacityTransferFunction("RTData"),
                       actors=[flat_actor(outline_of(image), (1.0, 1.0, 0.0))])
    result = compare(after, ref)
    result["changed_share"] = changed_share(before, after)
    result["coloured_by"] = coloured_by
    # deleting the source (the pipeline browser's Delete) takes the volume away at the next render
    volume = shown(view)[0].volume
    Delete(wavelet)
    Render(view)
    in_renderer = count_in_renderer(view, [volume])  # before shown(), which prunes too
    result["after_delete"] = {"shown": len(shown(view)), "volumes_in_renderer": in_renderer}
    return result


def rename_report(png):
    """The shown array renamed upstream (a Calculator's result), then renamed back."""
    from mipcast.plugin.render_view import show
    from paraview.simple import Calculator, Delete, GetDisplayProperties, Wavelet
    from vtkmodules.util.misc import calldata_type
    from vtkmodules.util.vtkConstants import VTK_STRING
    from vtkmodules.vtkCommonCore import vtkOutputWindow

    warnings = []

    @calldata_type(VTK_STRING)
    def on_warning(_window, _event, text):
        warnings.append(text)

    window = vtkOutputWindow.GetInstance()
    tag = window.AddObserver("WarningEvent", on_warning)
    wavelet = Wavelet(WholeExtent=[-10, 10, -10, 10, -10, 10])
    calc = Calculator(Input=wavelet, ResultArrayName="inv", Function="300-RTData")
    view = plain_view()
    result = {}
    for method in ("mip", "analytic", "demip", "stock", "cpu"):
        volume = show(calc, view, method=method, array="inv")
        flat(GetDisplayProperties(calc, view), (1.0, 1.0, 0.0))
        set_camera(view)
        before = screenshot(view, png(f"view_rename_{method}_0"))
        del warnings[:]
        calc.ResultArrayName = "renamed"
        renamed = screenshot(view, png(f"view_rename_{method}_1"))
        hidden = {"visible": volume.GetVisibility(),
                  "lit_share": float(np.mean(renamed.max(axis=-1) > 8)),
                  "warnings": list(warnings)}
        screenshot(view, png(f"view_rename_{method}_1b"))  # a second frame: no second message
        hidden["warnings_after_second_frame"] = len(warnings)
        calc.ResultArrayName = "inv"
        back = screenshot(view, png(f"view_rename_{method}_2"))
        result[method] = {"before_lit_share": float(np.mean(before.max(axis=-1) > 8)),
                          "renamed": hidden, "visible_again": volume.GetVisibility(),
                          "back": compare(back, before)}
    window.RemoveObserver(tag)
    Delete(view)
    Delete(calc)
    Delete(wavelet)
    return result


def recolour_report(png):
    """The outline re-coloured by another array (the Properties panel's Coloring, ColorBy)."""
    from mipcast.plugin.render_view import show, shown
    from paraview.simple import Calculator, ColorBy, Delete, GetColorTransferFunction, \
        GetDisplayProperties, GetOpacityTransferFunction, Hide, Wavelet

    wavelet = Wavelet(WholeExtent=[-10, 10, -10, 10, -10, 10])
    calc = Calculator(Input=wavelet, ResultArrayName="inv", Function="300-RTData")
    view = plain_view()
    volume = show(calc, view, method="mip", array="RTData")
    display = GetDisplayProperties(calc, view)
    Hide(calc, view)  # the volume alone; the hidden outline keeps its colouring
    set_camera(view)
    before = screenshot(view, png("view_recolour_rtdata"))
    ColorBy(display, ("POINTS", "inv"))
    lut, pwf = GetColorTransferFunction("inv"), GetOpacityTransferFunction("inv")
    lut.ApplyPreset("Grayscale", True)  # what the colour map editor now shows
    after = screenshot(view, png("view_recolour_inv"))
    calc.UpdatePipeline()
    image = vtkImageData()
    image.ShallowCopy(calc.GetClientSideObject().GetOutputDataObject(0))
    image.GetPointData().SetActiveScalars("inv")
    ref, _ = reference(image, "mip", view, lut, pwf)
    result = compare(after, ref)
    result["changed_share"] = changed_share(before, after)
    result["shown_array"] = shown(view)[0].array
    result["same_lut"] = volume.GetProperty().GetRGBTransferFunction(0) is lut.GetClientSideObject()
    ColorBy(display, None)  # solid colour: the volume keeps its array
    screenshot(view, png("view_recolour_solid"))
    result["after_solid_colour"] = shown(view)[0].array
    Delete(view)
    Delete(calc)
    Delete(wavelet)
    return result


def restore_report(view):
    """hide() gives the source's representation back the state it had before show()."""
    from mipcast.plugin.render_view import hide, show
    from paraview.simple import ColorBy, Delete, GetDisplayProperties, Show, Wavelet

    def state(source):
        display = GetDisplayProperties(source, view)
        kind = display.SMProxy.GetProperty("Representation").GetElement(0)
        return [int(display.Visibility), kind, list(display.ColorArrayName)]

    surface = Wavelet(WholeExtent=[-6, 6, -6, 6, -6, 6])
    display = Show(surface, view)
    display.SetRepresentationType("Surface")
    ColorBy(display, None)
    result = {"before": state(surface)}
    show(surface, view, method="mip")
    result["shown"] = state(surface)
    show(surface, view, method="analytic")  # replacing keeps the first saved state
    hide(surface, view)
    result["hidden"] = state(surface)
    never = Wavelet(WholeExtent=[-6, 6, -6, 6, -6, 6])  # never shown in this view
    show(never, view, method="mip")
    hide(never, view)
    result["never_shown_visible_after_hide"] = int(GetDisplayProperties(never, view).Visibility)
    Delete(surface)
    Delete(never)
    return result


def deletion_report():
    """Delete(view) / Delete(source) without a later render: the volume and its view are let go."""
    import gc

    from mipcast.plugin import render_view
    from mipcast.plugin.render_view import show
    from paraview.simple import Delete, Render, Wavelet
    from vtkmodules.vtkCommonCore import vtkWeakReference

    def entries(proxy, index):
        return sum(1 for key in render_view._SHOWN if key[index] == proxy.GetGlobalIDAsString())

    source = Wavelet(WholeExtent=[-6, 6, -6, 6, -6, 6])
    view = plain_view()
    show(source, view, method="mip")
    Render(view)
    weak = vtkWeakReference()
    weak.Set(view.GetClientSideObject())
    view_id = view.GetGlobalIDAsString()
    result = {"entries_before": entries(view, 0)}
    Delete(view)
    result["entries_after_delete"] = sum(1 for key in render_view._SHOWN if key[0] == view_id)
    result["observed_after_delete"] = view_id in render_view._OBSERVED
    del view
    gc.collect()
    result["view_object_released"] = weak.Get() is None
    other = plain_view()  # deleting the source, no render afterwards
    volume = show(source, other, method="mip")
    Delete(source)
    result["source_entries_after_delete"] = entries(source, 1)
    result["volume_in_renderer_after_source_delete"] = count_in_renderer(other, [volume])
    Delete(other)
    return result


def write_vti(image, path):
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()
    return path


def blob_series(folder, steps=3, size=24):
    """``steps`` .vti files of a Gaussian blob moving along x; returns (paths, images)."""
    z, y, x = np.mgrid[0:size, 0:size, 0:size].astype(np.float32)
    paths, images = [], []
    for step in range(steps):
        centre = 5.0 + step * (size - 10.0) / max(steps - 1, 1)
        values = 100.0 * np.exp(-((x - centre) ** 2 + (y - size / 2) ** 2 + (z - size / 2) ** 2) / 10.0)
        image = vtkImageData()
        image.SetDimensions(size, size, size)
        array = numpy_to_vtk(values.astype(np.float32).ravel(), deep=True)
        array.SetName("blob")
        image.GetPointData().SetScalars(array)
        paths.append(write_vti(image, os.path.join(folder, f"blob_{step}.vti")))
        images.append(image)
    return paths, images


def time_report(folder, png):
    """A 3-file time series animated as the GUI does (AnimationTime, then Render)."""
    from mipcast.plugin.render_view import show
    from paraview.simple import Delete, GetAnimationScene, GetColorTransferFunction, \
        GetDisplayProperties, GetOpacityTransferFunction, XMLImageDataReader

    paths, images = blob_series(folder)
    reader = XMLImageDataReader(FileName=paths)
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    view = plain_view()
    show(reader, view, method="mip")
    flat(GetDisplayProperties(reader, view), (1.0, 1.0, 0.0))
    set_camera(view, azimuth=10.0, elevation=20.0)
    lut, pwf = GetColorTransferFunction("blob"), GetOpacityTransferFunction("blob")
    outline = flat_actor(outline_of(images[0]), (1.0, 1.0, 0.0))
    result, first = {}, None
    for key, step in (("0", 0), ("1", 1), ("2", 2), ("0_again", 0)):
        scene.AnimationTime = float(step)
        pv = screenshot(view, png(f"view_time_{key}"))
        ref, _ = reference(images[step], "mip", view, lut, pwf, actors=[outline])
        first = ref if first is None else first
        entry = compare(pv, ref)
        entry["ref_changed_from_step_0"] = changed_share(ref, first)
        result[key] = entry
    scene.AnimationTime = 0.0
    Delete(view)
    Delete(reader)
    return result


def macros_report(reader, view):
    """Run the macro files as ParaView runs them (exec in the Python shell's namespace)."""
    from mipcast.plugin.render_view import shown
    from paraview.simple import SetActiveSource, SetActiveView

    SetActiveSource(reader)
    SetActiveView(view)
    results = {}
    for name in sorted(os.listdir(MACROS)):
        if not name.endswith(".py"):
            continue
        namespace = {"__name__": "__main__"}
        with open(os.path.join(MACROS, name), encoding="utf-8") as handle:
            exec(compile(handle.read(), name, "exec"), namespace)
        results[name] = [entry.method for entry in shown(view)]
    return results


def errors_report(view):
    """show() on data it must refuse: the message of each error."""
    from mipcast.plugin.render_view import show, shown
    from paraview.simple import Calculator, CreateView, Delete, PVTrivialProducer, Sphere, \
        Wavelet

    def message(call):
        try:
            call()
        except Exception as error:  # noqa: BLE001 - the message is what is measured
            return f"{type(error).__name__}: {error}"
        return "no error"

    calc = Calculator(Input=Wavelet(), ResultArrayName="vectors",
                      Function="RTData*iHat + RTData*jHat + RTData*kHat")
    good = make_fixture("vessels", size=16)
    values = vtk_to_numpy(good.GetPointData().GetScalars()).copy()
    values[:] = np.nan  # every value missing (some NaN voxels are drawn as missing data)
    holes = vtkImageData()
    holes.SetDimensions(good.GetDimensions())
    array = numpy_to_vtk(values, deep=True)
    array.SetName("density")
    holes.GetPointData().SetScalars(array)
    producer = PVTrivialProducer()
    producer.GetClientSideObject().SetOutput(holes)
    spreadsheet = CreateView("SpreadSheetView")
    result = {
        "polydata": message(lambda: show(Sphere(), view)),
        "component_out_of_range": message(lambda: show(calc, view, array="vectors", component=5)),
        "nan": message(lambda: show(producer, view)),
        "missing_array": message(lambda: show(calc, view, array="nope")),
        "unknown_method": message(lambda: show(calc, view, method="best")),
        "unknown_setting": message(lambda: show(calc, view, method="mip", no_such_weight=1.0)),
        "spreadsheet": message(lambda: show(calc, spreadsheet)),
    }
    Delete(spreadsheet)
    result["shown_after_errors"] = [(entry.source is calc, entry.method) for entry in shown(view)]
    return result


def vectors_report(png):
    """A three-component array: show() draws its magnitude or a chosen component, as mipcast does."""
    from mipcast.plugin.render_view import hide, show
    from paraview.simple import Calculator, Delete, GetColorTransferFunction, GetDisplayProperties, \
        GetOpacityTransferFunction, Wavelet

    view = plain_view()  # its own view: nothing else shown

    calc = Calculator(Input=Wavelet(), ResultArrayName="vectors",
                      Function="RTData*iHat + 2*RTData*jHat + 3*RTData*kHat")
    calc.UpdatePipeline()
    image = vtkImageData()
    image.ShallowCopy(calc.GetClientSideObject().GetOutputDataObject(0))
    image.GetPointData().SetActiveScalars("vectors")
    report = {}
    for method, component in (("mip", None), ("stock", None), ("analytic", 1), ("stock", 2), ("cpu", 0)):
        show(calc, view, method=method, array="vectors", component=component)
        flat(GetDisplayProperties(calc, view), (1.0, 1.0, 0.0))
        set_camera(view)
        name = f"{method}_{'magnitude' if component is None else component}"
        pv = screenshot(view, png(f"view_vectors_{name}"))
        lut = GetColorTransferFunction("vectors")
        ref, _ = reference(image, method, view, lut, GetOpacityTransferFunction("vectors"),
                           actors=[flat_actor(outline_of(image), (1.0, 1.0, 0.0))], component=component)
        result = compare(pv, ref)
        result.update(vector_mode=str(lut.VectorMode).strip("'"), vector_component=int(lut.VectorComponent),
                      lut_range=[lut.RGBPoints[0], lut.RGBPoints[-4]])
        report[name] = result
    hide(calc, view)
    Delete(view)
    return report


def passes_report(reader, image, view, png):
    """What ParaView's own passes do to the comparison (FXAA; translucent geometry)."""
    from mipcast.plugin.render_view import show
    from paraview.simple import GetColorTransferFunction, GetDisplayProperties, \
        GetOpacityTransferFunction, Hide, Show, Sphere

    lut, pwf = GetColorTransferFunction("scalars"), GetOpacityTransferFunction("scalars")
    show(reader, view, method="mip")
    flat(GetDisplayProperties(reader, view), (1.0, 1.0, 0.0))
    set_camera(view)
    outline = flat_actor(outline_of(image), (1.0, 1.0, 0.0))
    ref, _ = reference(image, "mip", view, lut, pwf, actors=[outline])
    result = {}
    view.UseFXAA = 1
    result["fxaa"] = compare(screenshot(view, png("view_fxaa")), ref)
    view.UseFXAA = 0
    view.DepthPeeling = 0
    result["no_depth_peeling"] = compare(screenshot(view, png("view_no_peeling")), ref)
    view.DepthPeeling = 1
    # translucent geometry: ParaView's dual depth peeling, with volumes peeled too
    bounds = image.GetBounds()
    centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    glass = Sphere(Center=centre, Radius=0.3 * (bounds[1] - bounds[0]))
    display = Show(glass, view)
    flat(display, (0.0, 0.0, 1.0))
    display.Opacity = 0.5
    glass.UpdatePipeline()
    glass_actor = flat_actor(glass.GetClientSideObject().GetOutputDataObject(0), (0.0, 0.0, 1.0))
    glass_actor.GetProperty().SetOpacity(0.5)
    for setting in (1, 0):
        view.DepthPeelingForVolumes = setting
        pv = screenshot(view, png(f"view_translucent_peel_volumes_{setting}"))
        peeled, _ = reference(image, "mip", view, lut, pwf, peel_volumes=bool(setting),
                              actors=[flat_actor(outline_of(image), (1.0, 1.0, 0.0)), glass_actor])
        result[f"translucent_peel_volumes_{setting}"] = compare(pv, peeled)
        result[f"translucent_peel_volumes_{setting}"]["glass_changed_share"] = changed_share(pv, ref)
    view.DepthPeelingForVolumes = 1
    Hide(glass, view)
    return result


def remote_report():
    """Connect to a real pvserver; show() must refuse.  Skipped if pvserver is missing."""
    import shutil
    import socket
    import subprocess
    import time

    from mipcast.plugin.render_view import show
    from paraview.simple import Connect, Disconnect, GetActiveViewOrCreate, Wavelet

    if shutil.which("pvserver") is None:
        return {"skipped": "no pvserver"}
    with socket.socket() as probe:
        probe.bind(("localhost", 0))
        port = probe.getsockname()[1]
    server = subprocess.Popen(["pvserver", f"--server-port={port}"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        for _ in range(50):
            try:
                with socket.create_connection(("localhost", port), timeout=0.2):
                    break
            except OSError:
                time.sleep(0.2)
        Connect("localhost", port)
        try:
            show(Wavelet(), GetActiveViewOrCreate("RenderView"))
            text = "no error"
        except Exception as error:  # noqa: BLE001
            text = f"{type(error).__name__}: {error}"
        Disconnect()
    finally:
        server.terminate()
        server.wait(timeout=20)
    return {"message": text}


def main(argv):
    from paraview.simple import Delete, XMLImageDataReader

    png_dir = argv[argv.index("--png-dir") + 1] if "--png-dir" in argv else None
    with tempfile.TemporaryDirectory() as folder:
        out = png_dir or folder

        def png(name):
            return os.path.join(out, name + ".png")

        image = make_fixture("vessels", size=48)
        path = os.path.join(folder, "vessels.vti")
        write_vti(image, path)
        reader = XMLImageDataReader(FileName=[path])
        reader.UpdatePipeline()
        view = plain_view()
        report = {"size": [WIDTH, HEIGHT], "volume": list(image.GetDimensions())}
        report["methods"] = methods_report(reader, image, view, png)
        report["interactive"] = interactive_report(reader, image, view, png)
        report["hidden"] = without_volume(reader, view, png)
        report["sphere"] = sphere_report(reader, image, view, png)
        report["passes"] = passes_report(reader, image, view, png)
        report["colour_map"] = colour_map_report(reader, image, view, png)
        report["parallel"] = parallel_report(reader, image, view, png)
        report["upstream"] = upstream_report(view, png)
        report["restore"] = restore_report(view)
        report["deletion"] = deletion_report()
        report["macros"] = macros_report(reader, view)
        report["errors"] = errors_report(view)
        report["vectors"] = vectors_report(png)
        report["time"] = time_report(folder, png)
        report["rename"] = rename_report(png)
        report["recolour"] = recolour_report(png)
        Delete(view)
    report["remote"] = remote_report()
    print(json.dumps(report))
    sys.stdout.flush()


if __name__ == "__main__":
    main(sys.argv)
