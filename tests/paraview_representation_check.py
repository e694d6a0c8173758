"""ParaView's "mipcast" representation (plugin/representation), measured in pvpython.

Usage (from the repository root, the plugin built by plugin/representation/build.sh)::

    PYTHONPATH=$PWD xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" pvpython \\
        tests/paraview_representation_check.py --plugin PATH [--png-dir DIR] [--server HOST:PORT] [--parts a,b]

Writes the "vessels" fixture (48^3) to a .vti, opens it with ParaView's XML
reader and shows it with ``Show(reader, view)`` and the representation type
"mipcast".  Each picture (``SaveScreenshot``, FXAA, orientation axes and
palette background off) is compared with :class:`mipcast.offscreen.OffscreenView`
of the same image and method given ParaView's camera (copied after
ParaView's render), the same size and transfer functions rebuilt from the
proxies' values.

Parts (``--parts``, default all in a builtin session): ``methods`` (every
method of the Method list), ``narrow`` (narrow colour ranges, also against the float64
reference), ``parameter`` (a DEMIP parameter changed: the
picture changes, no new shader program), ``eye`` (Hide/Show), ``trace`` (a
traced property change replayed), ``state`` (.pvsm saved, session reset,
loaded), ``arrays`` (a multi-component array by Magnitude and X in every method, a
cell array), ``oblique`` (an image with a direction matrix, every method at an oblique camera and
head-on, its side faces edge-on), ``bad`` (a cell array with no cell along an axis, NaN voxels, out-of-range
values), ``bench`` (frame time, wall and process CPU, against the offscreen view; ParaView's
Volume representation in MIP against ``stock``; ``--bench-size``, ``--bench-frames``,
``--bench-stencil``).  With
``--server HOST:PORT`` it connects to a running pvserver first and runs
``methods`` there.  Prints one JSON object on the last line of stdout; used by
tests/test_paraview_representation.py.
"""
import argparse
import json
import os
import sys
import tempfile
import time

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy

from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView
from paraview_view_check import changed_share, compare, plain_view, reference_property
from vtk_png import write_png

WIDTH, HEIGHT = 160, 128
ARRAY = "scalars"


def screenshot(view, path, size=(WIDTH, HEIGHT)):
    """SaveScreenshot to ``path``; (H, W, 3) uint8, top row first."""
    from paraview.simple import Render, SaveScreenshot
    from vtkmodules.vtkIOImage import vtkPNGReader

    Render(view)
    SaveScreenshot(path, view, ImageResolution=list(size), TransparentBackground=0)
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    output = reader.GetOutput()
    width, height, _ = output.GetDimensions()
    pixels = vtk_to_numpy(output.GetPointData().GetScalars())
    return pixels.reshape(height, width, -1)[::-1, :, :3].copy()


def set_camera(view, azimuth=35.0, elevation=25.0):
    from paraview.simple import Render

    Render(view)  # the first render resets the camera: after it, ours stays
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


def camera_of(view):
    """ParaView's camera as a vtkCamera (builtin: the view's own; client-server: rebuilt from the proxy)."""
    from vtkmodules.vtkRenderingCore import vtkCamera

    camera = vtkCamera()
    camera.SetPosition(*view.CameraPosition)
    camera.SetFocalPoint(*view.CameraFocalPoint)
    camera.SetViewUp(*view.CameraViewUp)
    camera.SetViewAngle(view.CameraViewAngle)
    camera.SetParallelProjection(int(view.CameraParallelProjection))
    camera.SetParallelScale(view.CameraParallelScale)
    client = view.GetClientSideObject()
    if client is not None and client.GetActiveCamera() is not None:
        camera.SetClippingRange(client.GetActiveCamera().GetClippingRange())
    return camera


def reference(image, method, view, size=(WIDTH, HEIGHT), array=ARRAY, component=None, **settings):
    """mipcast's own offscreen render with ParaView's camera and functions (those of ``array``)."""
    from mipcast.core.parameters import set_parameters
    from paraview.simple import GetColorTransferFunction, GetOpacityTransferFunction

    scene = OffscreenView(image, method, size=size, component=component)
    set_parameters(scene.mapper, **settings)
    scene.volume.SetProperty(reference_property(GetColorTransferFunction(array),
                                                GetOpacityTransferFunction(array)))
    scene.renderer.GetActiveCamera().DeepCopy(camera_of(view))
    pixels = scene.screenshot()
    return pixels, scene


def write_vti(image, path):
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()


def read_vti(path):
    from vtkmodules.vtkIOXML import vtkXMLImageDataReader

    reader = vtkXMLImageDataReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    image.GetPointData().SetActiveScalars(ARRAY)
    return image


def show_mipcast(source, view, method="mip"):
    from paraview.simple import ColorBy, Show

    display = Show(source, view)
    display.SetRepresentationType("mipcast")
    ColorBy(display, ("POINTS", ARRAY))
    display.RescaleTransferFunctionToDataRange(True, False)
    display.MipcastMethod = method
    return display


def glue_stats():
    """The glue's per-representation record (builtin sessions: the same process)."""
    import mipcast_representation

    return list(mipcast_representation.stats().values())


class Messages:
    """Collect VTK's output-window text (what ParaView's Output Messages shows)."""

    def __enter__(self):
        from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

        self.previous = vtkOutputWindow.GetInstance()
        self.previous.Register(None)
        self.window = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.window)
        return self

    def text(self):
        return self.window.GetOutput()

    def __exit__(self, *exc):
        from vtkmodules.vtkCommonCore import vtkOutputWindow

        vtkOutputWindow.SetInstance(self.previous)
        return False


def lit(pixels):
    return float(np.mean(pixels.max(axis=-1) > 8))


def gl_errors(text):
    """The OpenGL error reports in VTK's output-window text (ParaView's VTK checks glGetError after
    every state call: "Error glActiveTexture1 OpenGL errors detected ...")."""
    return [line for line in text.splitlines() if "OpenGL error" in line or "glGetError" in line]


def cpu_first(methods):
    """``methods`` with ``cpu`` first: VTK's CPU ray caster asks the view's volume property for its
    gradient opacity, which created a function on it for good (the later methods then logged
    OpenGL errors and ran slower: plugin/README.md; the representation now disables the
    property's gradient opacity), so every later method draws after a switch from ``cpu``."""
    return sorted(methods, key=lambda method: method != "cpu")


# -- parts --------------------------------------------------------------------------------------
def projection_range(display, image, method, array=ARRAY, component=None):
    """Colour the array (its magnitude or ``component``) over the data range, the average projection
    over its default window (its picture is dark over the data range); returns the range set."""
    import mipcast
    from mipcast.core.windowing import default_window
    from mipcast.mappers.input_preparer import prepared_image
    from paraview.simple import GetColorTransferFunction, GetOpacityTransferFunction

    projection = mipcast.METHODS[method].projection
    drawn = prepared_image(image, component)  # one component, on the cell centres for cell data
    if projection == "average":
        low, high = default_window(drawn, projection)
    else:
        low, high = drawn.GetPointData().GetScalars().GetRange()
    GetColorTransferFunction(array).RescaleTransferFunction(low, high)
    GetOpacityTransferFunction(array).RescaleTransferFunction(low, high)
    return low, high


def each_method(display, image, view, png, methods, tag, stats=False):
    """Each method (``cpu`` first) drawn at (WIDTH, HEIGHT) and compared with the offscreen view
    (pictures ``rep_<tag><method>``, ``ref_<tag><method>``); ``_opengl_errors``: VTK's OpenGL error
    reports meanwhile."""
    report = {}
    with Messages() as messages:
        for method in cpu_first(methods):
            display.MipcastMethod = method
            projection_range(display, image, method)
            pv = screenshot(view, png(f"rep_{tag}{method}"))
            ref, _ = reference(image, method, view)
            write_png(png(f"ref_{tag}{method}"), ref)
            report[method] = compare(pv, ref)
            if stats:
                report[method]["mapper"] = glue_stats()[0]["mapper"]
        report["_opengl_errors"] = gl_errors(messages.text())
    return report


def methods_part(reader, image, view, png, methods, stats=True):
    """Every method's screenshot against the offscreen view (the view is the screenshot's size:
    a bigger screenshot makes ParaView render tiles, see ``tiled_part``)."""
    import mipcast

    display = show_mipcast(reader, view)
    set_camera(view)
    report = each_method(display, image, view, png, methods, "", stats)
    report["_listed"] = sorted(display.GetProperty("MipcastMethod").SMProperty.GetDomain("list")
                               .GetString(i) for i in range(
        display.GetProperty("MipcastMethod").SMProperty.GetDomain("list").GetNumberOfStrings()))
    report["_methods"] = sorted(mipcast.METHODS)
    return report


#: Narrow colour/opacity ranges inside the vessels' data range (about 0.031-1.0): most MinIP minima
#: lie above the first's top, most MIP maxima below the second's bottom.
NARROW = {"analytic_minip": (0.032, 0.041), "analytic": (0.6, 0.609)}


def oblique_part(directory, png, methods):
    """An oblique acquisition in a .vti (``edge_on_check.turned``: the vessels 24^3 on spacing 0.7 x 1 x 1.6,
    turned 0.65 rad about z by the image's direction matrix), every method drawn by the representation
    at an oblique camera and head-on (the box's side faces edge-on: ``ray_mend``), against the offscreen
    view of the image read back (pictures ``rep_oblique_<camera>_<method>``)."""
    from paraview.simple import Delete, OpenDataFile
    from edge_on_check import turned

    image = turned(24, 0.65)
    image.GetPointData().GetScalars().SetName(ARRAY)
    path = os.path.join(directory, "oblique.vti")
    write_vti(image, path)
    image = read_vti(path)
    report = {"_direction": [image.GetDirectionMatrix().GetElement(r, c) for r in range(3) for c in range(3)]}
    for label, (azimuth, elevation) in (("oblique", (35.0, 25.0)), ("head_on", (0.0, 0.0))):
        reader = OpenDataFile(path)
        reader.PointArrayStatus = [ARRAY]
        view = plain_view((WIDTH, HEIGHT))
        display = show_mipcast(reader, view)
        set_camera(view, azimuth, elevation)
        report[label] = each_method(display, image, view, png, methods, f"oblique_{label}_")
        Delete(view)
    return report


def exact_colours(prop, values):
    """(H, W, 3) uint8: the float64 answers ``values`` (NaN: background) through ``prop``'s
    colour and opacity functions, premultiplied on black (ParaView's palette background off)."""
    colour, opacity = prop.GetRGBTransferFunction(0), prop.GetScalarOpacity(0)
    out = np.zeros(values.shape + (3,))
    for index in zip(*np.nonzero(np.isfinite(values))):
        rgb = [0.0, 0.0, 0.0]
        colour.GetColor(float(values[index]), rgb)
        out[index] = np.array(rgb) * opacity.GetValue(float(values[index]))
    return np.round(255 * np.clip(out, 0, 1)).astype(np.uint8)


def narrow_part(reader, image, view, png, ranges=None):
    """A narrow range (NARROW) per method: ParaView against the offscreen view, and both against
    the float64 reference coloured through the same functions (the exact methods' display
    shortcuts start at a bound of the range; VTK's tables interpolate between texels)."""
    import mipcast
    from paraview.simple import GetColorTransferFunction, GetOpacityTransferFunction

    display = show_mipcast(reader, view)
    set_camera(view)
    report = {}
    for method, (low, high) in (ranges or NARROW).items():
        display.MipcastMethod = method
        GetColorTransferFunction(ARRAY).RescaleTransferFunction(low, high)
        GetOpacityTransferFunction(ARRAY).RescaleTransferFunction(low, high)
        pv = screenshot(view, png(f"rep_narrow_{method}"))
        ref, scene = reference(image, method, view)
        write_png(png(f"ref_narrow_{method}"), ref)
        exact = mipcast.METHODS[method].reference(image, scene.camera, scene.size)
        colours = exact_colours(scene.volume.GetProperty(), exact)
        write_png(png(f"exact_narrow_{method}"), colours)
        report[method] = dict(compare(pv, ref), range=[low, high],
                              paraview_vs_exact=compare(pv, colours), offscreen_vs_exact=compare(ref, colours))
    return report


def tiled_part(reader, image, png, methods):
    """A screenshot bigger than the view: ParaView renders it in tiles (the window at a divisor
    of the size, VTK's TileScale/TileViewport); each method against the offscreen view at the
    screenshot's size."""
    view = plain_view((WIDTH // 2 + 32, HEIGHT // 2 + 32))  # 112 x 96: 2 x 2 tiles of 80 x 64
    display = show_mipcast(reader, view)
    set_camera(view)
    report = each_method(display, image, view, png, methods, "tiled_")
    from paraview.simple import Delete
    Delete(view)
    return report


#: The arrays part's view: smaller than the others (two pictures per method).
ARRAYS_SIZE = (96, 80)


def vector_image(size=32):
    """The vessels as a three-component point array "vec" = (vessels, spheres, vessels / 2): its
    magnitude, X and Y draw different pictures."""
    image = make_fixture("vessels", size=size)
    vessels = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32)
    spheres = vtk_to_numpy(make_fixture("spheres", size=size).GetPointData().GetScalars()).astype(np.float32)
    array = numpy_to_vtk(np.stack([vessels, spheres, 0.5 * vessels], axis=1), deep=True)
    array.SetName("vec")
    image.GetPointData().SetScalars(array)
    return image


def cell_image(image):
    """``image``'s point scalars as cell data (VTK's point-to-cell average), with the point array kept."""
    from vtkmodules.vtkFiltersCore import vtkPointDataToCellData

    convert = vtkPointDataToCellData()
    convert.SetInputData(image)
    convert.PassPointDataOn()
    convert.Update()
    cells = convert.GetOutput()
    only = cells.NewInstance()
    only.DeepCopy(cells)
    only.GetPointData().Initialize()  # the reference: the cell array alone
    return cells, only


def arrays_part(directory, png, methods):
    """Colour by a multi-component array's Magnitude and by its X component in every method, and by
    a cell array (alone, and next to a point array of the same name): each picture against the
    offscreen view of the same component / of the cell data (drawn at the cell centres)."""
    from paraview.simple import ColorBy, Delete, Hide, OpenDataFile, Show

    view = plain_view(ARRAYS_SIZE)
    report = {"vector": {}, "cells": {}}
    vectors = vector_image()
    path = os.path.join(directory, "vectors.vti")
    write_vti(vectors, path)
    source = OpenDataFile(path)
    display = Show(source, view)
    display.SetRepresentationType("mipcast")
    ColorBy(display, ("POINTS", "vec", "Magnitude"))
    set_camera(view)
    for method in cpu_first(methods):
        display.MipcastMethod = method
        result, pictures = {}, {}
        for name, component in (("Magnitude", None), ("X", 0)):
            ColorBy(display, ("POINTS", "vec", name))
            projection_range(display, vectors, method, "vec", component)
            pictures[name] = screenshot(view, png(f"rep_vec_{method}_{name}"), ARRAYS_SIZE)
            ref, _ = reference(vectors, method, view, ARRAYS_SIZE, "vec", component)
            write_png(png(f"ref_vec_{method}_{name}"), ref)
            result[name] = compare(pictures[name], ref)
        result["changed_share"] = changed_share(pictures["Magnitude"], pictures["X"])
        report["vector"][method] = result
    Hide(source, view)
    both, alone = cell_image(make_fixture("vessels", size=24))
    path = os.path.join(directory, "cells.vti")
    write_vti(both, path)
    source = OpenDataFile(path)
    display = Show(source, view)
    display.SetRepresentationType("mipcast")
    ColorBy(display, ("POINTS", ARRAY))
    set_camera(view)
    display.MipcastMethod = "mip"
    projection_range(display, both, "mip")
    points = screenshot(view, png("rep_cells_points"), ARRAYS_SIZE)
    for method in ("mip", "analytic", "stock", "cpu"):
        display.MipcastMethod = method
        ColorBy(display, ("CELLS", ARRAY))  # the point array of the same name is not drawn
        projection_range(display, alone, method)
        pixels = screenshot(view, png(f"rep_cells_{method}"), ARRAYS_SIZE)
        ref, _ = reference(alone, method, view, ARRAYS_SIZE)
        write_png(png(f"ref_cells_{method}"), ref)
        report["cells"][method] = dict(compare(pixels, ref), changed_from_points=changed_share(points, pixels))
    Delete(view)
    return report


def parameter_part(reader, image, view, png):
    display = show_mipcast(reader, view, "demip")
    set_camera(view)
    before = screenshot(view, png("param_before"))
    programs = glue_stats()[0]["programs"]
    display.demip_depth_weight = 0.6
    display.demip_sphere_weight = 0.5
    after = screenshot(view, png("param_after"))
    stats = glue_stats()[0]
    ref, _ = reference(image, "demip", view, depth_weight=0.6, sphere_weight=0.5)
    write_png(png("param_ref"), ref)
    return dict(changed_share=changed_share(before, after), programs_before=programs,
                programs_after=stats["programs"], renders=stats["renders"],
                parity=compare(after, ref))


def slab_part(reader, image, view, png, methods=("mip", "analytic")):
    """The slab from the panel: thickness with centre and normal following the camera (the
    default), then a fixed centre, then a fixed normal; each picture against the offscreen view
    with the same settings, and each change must move the picture."""
    display = show_mipcast(reader, view, methods[0])
    set_camera(view)
    bounds = image.GetBounds()
    centre = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
    thickness = 0.25 * (bounds[1] - bounds[0])
    moved = [centre[0] + 0.25 * (bounds[1] - bounds[0]), centre[1], centre[2]]
    normal = [1.0, 0.0, 0.0]
    report = {}
    for method in methods:
        display.MipcastMethod = method
        whole = screenshot(view, png(f"slab_{method}_whole"))
        steps = {}
        setattr(display, f"{method}_slab_thickness", thickness)
        steps["camera"] = (screenshot(view, png(f"rep_slab_{method}_camera")), dict(slab_thickness=thickness))
        setattr(display, f"{method}_slab_centre", moved)
        setattr(display, f"{method}_slab_centre_follows_camera", 0)
        steps["centre"] = (screenshot(view, png(f"rep_slab_{method}_centre")),
                           dict(slab_thickness=thickness, slab_centre=tuple(moved)))
        setattr(display, f"{method}_slab_normal", normal)
        setattr(display, f"{method}_slab_normal_follows_camera", 0)
        steps["normal"] = (screenshot(view, png(f"rep_slab_{method}_normal")),
                           dict(slab_thickness=thickness, slab_centre=tuple(moved), slab_normal=tuple(normal)))
        result, previous = {}, whole
        for name, (pixels, settings) in steps.items():
            ref, _ = reference(image, method, view, **settings)
            write_png(png(f"ref_slab_{method}_{name}"), ref)
            result[name] = dict(compare(pixels, ref), changed_share=changed_share(previous, pixels))
            previous = pixels
        setattr(display, f"{method}_slab_normal_follows_camera", 1)
        setattr(display, f"{method}_slab_centre_follows_camera", 1)
        back = screenshot(view, png(f"slab_{method}_back"))
        result["follows_again"] = compare(back, steps["camera"][0])
        setattr(display, f"{method}_slab_thickness", 0.0)
        report[method] = result
    return report


def gaze_part(reader, image, view, png):
    """The foveated method's gaze in the view: the panel's fixed point, a region of interest,
    and (where the view has an interactor: builtin sessions) the mouse, each against the
    offscreen view with that gaze."""
    display = show_mipcast(reader, view, "foveated")
    set_camera(view)
    report = {}
    centre = screenshot(view, png("gaze_centre"))
    display.foveated_gaze_point = [0.2, 0.3]
    fixed = screenshot(view, png("rep_gaze_point"))
    ref, _ = reference(image, "foveated", view, gaze_point=(0.2, 0.3))
    write_png(png("ref_gaze_point"), ref)
    report["point"] = dict(compare(fixed, ref), changed_share=changed_share(centre, fixed))
    bounds = image.GetBounds()
    region = (bounds[0], 0.5 * (bounds[0] + bounds[1]), bounds[2], 0.5 * (bounds[2] + bounds[3]),
              bounds[4], 0.5 * (bounds[4] + bounds[5]))
    display.foveated_region_of_interest = list(region)
    roi = screenshot(view, png("rep_gaze_region"))
    ref, _ = reference(image, "foveated", view, region_of_interest=region)
    write_png(png("ref_gaze_region"), ref)
    report["region"] = dict(compare(roi, ref), changed_share=changed_share(fixed, roi))
    display.foveated_region_of_interest = [1.0, 0.0, 1.0, 0.0, 1.0, 0.0]
    back = screenshot(view, png("gaze_point_again"))  # the gaze point until the mouse moves
    report["region_cleared"] = compare(back, fixed)
    interactor = view.GetInteractor() if hasattr(view, "GetInteractor") else None
    report["interactor"] = interactor is not None
    if interactor is not None:
        x, y = 120, 40  # display pixels, origin bottom left
        interactor.SetEventPosition(x, y)
        interactor.InvokeEvent("MouseMoveEvent")
        mouse = screenshot(view, png("rep_gaze_mouse"))
        gaze = ((x + 0.5) / WIDTH, (y + 0.5) / HEIGHT)
        ref, _ = reference(image, "foveated", view, gaze_point=gaze)
        write_png(png("ref_gaze_mouse"), ref)
        report["mouse"] = dict(compare(mouse, ref), changed_share=changed_share(fixed, mouse))
        display.foveated_follow_mouse = 0
        back = screenshot(view, png("gaze_mouse_off"))
        report["mouse_off"] = compare(back, fixed)
    return report


def eye_part(reader, image, view, png):
    from paraview.simple import Hide, Show

    show_mipcast(reader, view, "analytic")
    set_camera(view)
    shown = screenshot(view, png("eye_shown"))
    Hide(reader, view)
    hidden = screenshot(view, png("eye_hidden"))
    Show(reader, view)
    again = screenshot(view, png("eye_again"))
    return dict(shown_lit=lit(shown), hidden_lit=lit(hidden), again_vs_shown=compare(again, shown))


def trace_part(reader, image, view, png):
    """A property change traced as the Properties panel's Apply traces it, then replayed."""
    from paraview import smtrace
    import paraview.simple as simple

    display = show_mipcast(reader, view, "mip")
    set_camera(view)
    simple.SetActiveSource(reader)
    simple.SetActiveView(view)
    smtrace.start_trace()
    item = smtrace.PropertiesModified(display.SMProxy)  # what pqProxyWidget::apply() records
    display.MipcastMethod = "demip"
    display.demip_depth_weight = 0.45
    item.finalize()
    text = smtrace.stop_trace()
    traced = screenshot(view, png("trace_traced"))
    display.MipcastMethod = "mip"
    display.demip_depth_weight = 0.15
    reset = screenshot(view, png("trace_reset"))
    exec(compile(text, "trace", "exec"), {})
    replayed = screenshot(view, png("trace_replayed"))
    lines = [line.strip() for line in text.splitlines() if "Mipcast" in line or "demip_" in line]
    return dict(lines=lines, replayed_vs_traced=compare(replayed, traced),
                reset_changed=changed_share(traced, reset),
                method_after_replay=str(display.MipcastMethod))


def state_part(reader_path, view_size, png, plugin):
    from paraview.simple import (CreateView, GetActiveView, GetSources, LoadPlugin, LoadState,
                                 OpenDataFile, ResetSession, SaveState, SetActiveView)

    ResetSession()  # the state holds this scene only
    LoadPlugin(plugin, ns=globals())
    reader = OpenDataFile(reader_path)
    view = plain_view(view_size)
    display = show_mipcast(reader, view, "demip")
    display.demip_depth_weight = 0.5
    display.demip_depth_mode = "eye_distance"
    set_camera(view)
    before = screenshot(view, png("state_saved"))
    path = os.path.join(tempfile.mkdtemp(prefix="mipcast-pvsm-"), "mipcast.pvsm")
    SaveState(path)
    ResetSession()
    LoadPlugin(plugin, ns=globals())
    LoadState(path)
    import paraview.simple as simple
    from paraview import servermanager

    simple._DisableFirstRenderCameraReset()  # the state's camera stays
    found = [(v, servermanager.GetRepresentation(s, v)) for v in simple.GetViews()
             for s in GetSources().values() if v.GetXMLName() == "RenderView"]
    view, loaded = [(v, r) for v, r in found if r is not None][0]
    simple.SetActiveView(view)
    view.ViewSize = list(view_size)
    after = screenshot(view, png("state_loaded"))
    with open(path) as handle:
        saved = handle.read()
    return dict(loaded_vs_saved=compare(after, before), saved_lit=lit(before),
                representation=str(loaded.Representation), method=str(loaded.MipcastMethod),
                depth_weight=float(loaded.demip_depth_weight),
                pvsm_mentions_method="MipcastMethod" in saved)


def bad_part(directory, view, png):
    from paraview.simple import ColorBy, OpenDataFile, PointDatatoCellData, Show, Hide

    report = {}
    image = make_fixture("vessels", size=24)
    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32).copy()
    values[:] = np.nan  # every value missing (some NaN voxels are drawn as missing data)
    nan_image = make_fixture("vessels", size=24)
    array = numpy_to_vtk(values, deep=True)
    array.SetName(ARRAY)
    nan_image.GetPointData().SetScalars(array)
    nan_path = os.path.join(directory, "nan.vti")
    write_vti(nan_image, nan_path)
    good_path = os.path.join(directory, "small.vti")
    write_vti(image, good_path)

    def case(name, make, array_spec, setter=None):
        with Messages() as messages:
            source = make()
            display = Show(source, view)
            display.SetRepresentationType("mipcast")
            ColorBy(display, array_spec)
            display.MipcastMethod = "mip"
            if setter is not None:
                setter(display)
            set_camera(view)
            pixels = screenshot(view, png(f"bad_{name}"))
            Hide(source, view)
            text = messages.text()
        report[name] = dict(message=[line for line in text.splitlines() if line.strip()][:3],
                            lit=lit(pixels))

    from vtkmodules.vtkCommonDataModel import vtkImageData

    thin = vtkImageData()
    thin.SetDimensions(24, 24, 1)  # one slice: no cell along z
    ramp = numpy_to_vtk(np.linspace(0.0, 1.0, 24 * 24).astype(np.float32), deep=True)
    ramp.SetName(ARRAY)
    thin.GetPointData().SetScalars(ramp)
    thin_path = os.path.join(directory, "thin.vti")
    write_vti(thin, thin_path)
    case("cell_data_one_slice", lambda: PointDatatoCellData(Input=OpenDataFile(thin_path)), ("CELLS", ARRAY))
    case("nan_voxels", lambda: OpenDataFile(nan_path), ("POINTS", ARRAY))

    def out_of_range(display):
        display.demip_depth_weight = 5.0
        display.MipcastMethod = "demip"
    case("out_of_range", lambda: OpenDataFile(good_path), ("POINTS", ARRAY), out_of_range)

    def unknown_method(display):
        display.MipcastMethod = "no_such_method"
    case("unknown_method", lambda: OpenDataFile(good_path), ("POINTS", ARRAY), unknown_method)
    return report


class RendererClock:
    """Process CPU seconds of a renderer's last render (its StartEvent to its EndEvent)."""

    def __init__(self, renderer):
        self.renderer, self.start, self.last = renderer, 0.0, 0.0
        self.tags = [renderer.AddObserver("StartEvent", self._start), renderer.AddObserver("EndEvent", self._end)]

    def _start(self, caller, event):
        self.start = time.process_time()

    def _end(self, caller, event):
        self.last = time.process_time() - self.start

    def remove(self):
        for tag in self.tags:
            self.renderer.RemoveObserver(tag)


def frame_ratios(paraview_frame, offscreen_frame, renderers=None, frames=5, warmup=1):
    """Time ``paraview_frame`` against ``offscreen_frame``, interleaved frame by frame.

    Each frame's wall time (``perf_counter``) and process CPU time
    (``process_time``: every thread of the process, llvmpipe's rasterising
    threads included) is divided by those of the offscreen frame right after
    it; the medians of these ratios are reported (this machine's load changes
    from second to second; CPU time does not count the waiting).  With
    ``renderers`` (ParaView's, the offscreen one): the renderers' own wall
    time (``GetLastRenderTimeInSeconds``) and CPU time (:class:`RendererClock`).
    """
    def timed(frame):
        wall, cpu = time.perf_counter(), time.process_time()
        frame()
        return time.perf_counter() - wall, time.process_time() - cpu

    clocks = [RendererClock(renderer) for renderer in renderers or ()]
    for _ in range(warmup):
        paraview_frame()
        offscreen_frame()
    rows = []  # per frame: ParaView wall, cpu, offscreen wall, cpu[, renderers' wall, cpu, wall, cpu]
    for _ in range(frames):
        row = list(timed(paraview_frame))
        inside = [(renderers[0].GetLastRenderTimeInSeconds(), clocks[0].last)] if clocks else []
        row += timed(offscreen_frame)
        if clocks:
            inside.append((renderers[1].GetLastRenderTimeInSeconds(), clocks[1].last))
        rows.append(row + [value for pair in inside for value in pair])
    for clock in clocks:
        clock.remove()
    rows = np.array(rows)
    medians = np.median(rows, axis=0)
    result = dict(paraview_s=float(medians[0]), offscreen_s=float(medians[2]),
                  ratio=float(np.median(rows[:, 0] / rows[:, 2])),
                  ratio_of_minima=float(rows[:, 0].min() / rows[:, 2].min()),
                  paraview_cpu_s=float(medians[1]), offscreen_cpu_s=float(medians[3]),
                  cpu_ratio=float(np.median(rows[:, 1] / rows[:, 3])))
    if clocks:
        result.update(renderer_ratio=float(np.median(rows[:, 4] / rows[:, 6])),
                      renderer_cpu_ratio=float(np.median(rows[:, 5] / rows[:, 7])),
                      outside_renderer_cpu_s=float(np.median(rows[:, 1] - rows[:, 5])),
                      offscreen_outside_renderer_cpu_s=float(np.median(rows[:, 3] - rows[:, 7])))
    return result


def bench_part(reader, image, png, methods, size=(512, 512), frames=5, warmup=1, stencil=False):
    """Frame times, per method: ParaView's StillRender against the offscreen view's Render
    (each + WaitForCompletion), same size and camera, wall and process CPU time interleaved
    frame by frame (:func:`frame_ratios`), and the renderers' own time.  Then for contrast
    ParaView's own Volume representation in MIP blend against VTK's GPU mapper offscreen
    (``stock``), and ParaView's fixed cost: the same view with nothing shown against an empty
    offscreen window of the same size.  ``stencil``: the offscreen windows get ParaView's
    framebuffer format (a stencil buffer: depth 24 + stencil 8 bits instead of depth 32)."""
    from paraview.simple import Hide
    from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkRenderer

    view = plain_view(size)
    display = show_mipcast(reader, view, methods[0])
    set_camera(view)
    window = view.GetRenderWindow()
    renderer = view.GetRenderer()

    def paraview_frame():
        view.StillRender()
        window.WaitForCompletion()

    def against(method, name):
        pixels = screenshot(view, png(f"bench_{name}"), size)
        reference_pixels, scene = reference(image, method, view, size=size)
        if stencil:
            scene.render_window.Finalize()  # the next render makes a new context with a stencil buffer
            scene.render_window.SetStencilCapable(1)
        result = frame_ratios(paraview_frame, scene._render_and_wait, (renderer, scene.renderer), frames, warmup)
        scene.render_window.Finalize()
        return dict(result, within_1_share=compare(pixels, reference_pixels)["within_1_share"])

    report = dict(size=list(size), frames=frames, offscreen_paraview=bool(window.GetOffScreenRendering()),
                  stencil=stencil, methods={})
    for method in methods:
        display.MipcastMethod = method
        report["methods"][method] = against(method, method)
    display.SetRepresentationType("Volume")
    display.GetProperty("BlendMode").SetData(1)  # VTK's MAXIMUM_INTENSITY_BLEND (not in 5.11's menu)
    report["paraview_volume_mip"] = against("stock", "paraview_volume_mip")
    Hide(reader, view)
    empty = vtkRenderWindow()
    empty.SetOffScreenRendering(1)
    empty.SetMultiSamples(0)  # as OffscreenView's and ParaView's windows (VTK's default: 8 samples)
    empty.SetStencilCapable(int(stencil))
    empty.SetSize(*size)
    empty.AddRenderer(vtkRenderer())

    def empty_frame():
        empty.Render()
        empty.WaitForCompletion()

    report["empty"] = frame_ratios(paraview_frame, empty_frame, frames=frames, warmup=warmup)
    empty.Finalize()
    first = report["methods"][methods[0]]
    report.update({key: first[key] for key in ("paraview_s", "offscreen_s", "ratio", "renderer_ratio", "cpu_ratio")},
                  method=methods[0])
    return report


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--png-dir")
    parser.add_argument("--server", help="HOST:PORT of a running pvserver")
    parser.add_argument("--methods", help="comma-separated methods (default: all of mipcast.METHODS)")
    parser.add_argument("--parts", default="methods,tiled,narrow,parameter,slab,gaze,eye,trace,state,oblique,arrays,"
                                         "bad,bench")
    parser.add_argument("--bench-methods", help="comma-separated methods to time (default: every in-view method)")
    parser.add_argument("--bench-size", type=int, default=512, help="square view size of the bench")
    parser.add_argument("--bench-frames", type=int, default=5, help="timed frames per method of the bench")
    parser.add_argument("--bench-stencil", action="store_true",
                        help="the bench's offscreen windows with a stencil buffer, as ParaView's")
    args = parser.parse_args()
    import inspect
    if not hasattr(inspect, "getargspec"):  # ParaView 5.11's plugin loader on Python 3.11
        inspect.getargspec = inspect.getfullargspec
    from paraview.simple import Connect, Delete, GetRepresentation, LoadPlugin, OpenDataFile

    directory = tempfile.mkdtemp(prefix="mipcast-pvrep-")
    png_dir = args.png_dir or directory
    os.makedirs(png_dir, exist_ok=True)

    def png(name):
        return os.path.join(png_dir, name + ".png")

    report = {}
    if args.server:
        host, _, port = args.server.rpartition(":")
        Connect(host or "localhost", int(port))
        LoadPlugin(args.plugin, remote=True, ns=globals())
        report["session"] = "client-server"
    LoadPlugin(args.plugin, remote=False, ns=globals())
    image = make_fixture("vessels", size=48)
    path = os.path.join(directory, "vessels.vti")
    write_vti(image, path)
    image = read_vti(path)
    parts = args.parts.split(",")

    def fresh():
        reader = OpenDataFile(path)
        reader.PointArrayStatus = [ARRAY]
        return reader, plain_view((WIDTH, HEIGHT))

    import mipcast
    if "methods" in parts:
        reader, view = fresh()
        report["methods"] = methods_part(reader, image, view, png, args.methods.split(",") if args.methods
                                         else [n for n, m in mipcast.METHODS.items() if m.in_view],
                                         stats=not args.server)
        Delete(view)
    if "tiled" in parts:
        reader, _ = fresh()
        report["tiled"] = tiled_part(reader, image, png, args.methods.split(",") if args.methods
                                     else [n for n, m in mipcast.METHODS.items() if m.in_view])
    for name, part in (("narrow", narrow_part), ("parameter", parameter_part), ("slab", slab_part), ("gaze", gaze_part), ("eye", eye_part),
                       ("trace", trace_part)):
        if name in parts:
            reader, view = fresh()
            report[name] = part(reader, image, view, png)
            Delete(view)
    if "oblique" in parts:
        report["oblique"] = oblique_part(directory, png, args.methods.split(",") if args.methods
                                         else [n for n, m in mipcast.METHODS.items() if m.in_view])
    if "arrays" in parts:
        report["arrays"] = arrays_part(directory, png, args.methods.split(",") if args.methods
                                       else [n for n, m in mipcast.METHODS.items() if m.in_view])
    if "bad" in parts:
        report["bad"] = bad_part(directory, plain_view((WIDTH, HEIGHT)), png)
    if "bench" in parts:
        reader, _ = fresh()
        report["bench"] = bench_part(reader, image, png, args.bench_methods.split(",") if args.bench_methods
                                     else [n for n, m in mipcast.METHODS.items() if m.in_view],
                                     size=(args.bench_size, args.bench_size), frames=args.bench_frames,
                                     stencil=args.bench_stencil)
    if "state" in parts:  # last: it resets the session
        report["state"] = state_part(path, (WIDTH, HEIGHT), png, args.plugin)
    report["png_dir"] = png_dir
    print(json.dumps(report))


if __name__ == "__main__":
    main()
