"""The mipcast representation in a parallel ParaView: every rank draws its piece, IceT composites.

Writes the 64^3 vessel phantom as a ``.pvti`` whose pieces are slabs along
one axis that share a layer of points (:func:`mipcast.distributed.split_extents`;
``--axis`` 0, 1, 2, ``--pieces`` N), reads it with ParaView's
``XMLPImageDataReader`` (each rank its part), each rank taking its own slab (a ProgrammableFilter reading its piece file; `--axis -1`: the reader's own split of the whole extent), shows it with the
``mipcast`` representation for each method of ``--methods`` and ParaView's
own Volume representation with BlendMode MIP (``paraview-mip``, for the
contrast), and saves each picture (``SaveScreenshot``) as
``<png-dir>/<method>-n<ranks>-axis<a>.png`` (a method listed twice:
``<method>-again-...``, e.g. to check that switching methods keeps each
method's compositing). Flags after the method: ``+nan`` shows it on a second
copy of the phantom whose box :data:`NAN_BOX` holds missing values (NaN),
crossing every piece border of the splits the test uses; ``+inside`` moves
the camera inside the volume for that picture (:data:`INSIDE`); ``+moved``
gives the display a transform (``Position``, ``Orientation``, ``Scale``,
``Origin``: :data:`MOVED`) for that picture, which reaches the volume's matrix. The test
(tests/test_representation_distributed.py) compares the pictures of N ranks
with those of one rank.

pvbatch (the script runs on rank 0, every rank renders)::

    mpiexec --oversubscribe -n 2 pvbatch tests/representation_distributed_check.py \\
        --plugin PLUGIN --axis 0 --pieces 2 --data DIR --png-dir DIR --out /tmp/r.json

pvserver behind a pvpython client::

    mpiexec --oversubscribe -n 2 pvserver --server-port=11111 &
    pvpython tests/representation_distributed_check.py --connect localhost:11111 ...
"""
import argparse
import json
import math
import os

ARRAY = "scalars"
#: MinIP's grey window: the lowest part of the data range (its minima lie there).
MINIP_WINDOW = 0.25
#: The NaN voxels of the ``+nan`` copy (x, y, z index ranges, inclusive): across the borders of 2 slabs along
#: x or y (31/32) and of 4 along z (15/16, 31/32, 47/48), vessels on every side.
NAN_BOX = ((27, 36), (12, 50), (10, 52))
#: The NaN-holding copy's values at its first and last point (the corners (0, 0, 0) and (n-1, n-1, n-1)), beyond
#: the phantom's range: its pieces' finite ranges differ (missing values are filled per piece, relative to it).
NAN_CORNERS = (2.0, -1.0)
#: ``+inside``: the camera this fraction of the box's x width from the focal point (the box's centre), towards
#: where it was: inside the volume, the near plane cutting every piece's box.
INSIDE = 0.3
#: ``+moved``: the display transform (turned about the volume's centre, scaled unevenly, shifted; in view).
MOVED = {"Position": [3.0, -2.0, 1.5], "Orientation": [15.0, -25.0, 10.0], "Scale": [1.0, 1.15, 0.85]}
#: The ProgrammableFilter's script (--axis 0, 1, 2): this rank's slab, the piece file of its rank.
SLAB_SCRIPT = """
from vtkmodules.vtkIOXML import vtkXMLImageDataReader
from vtkmodules.vtkParallelCore import vtkMultiProcessController
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller is not None else 0
piece = vtkXMLImageDataReader()
piece.SetFileName(PIECES + "-%d.vti" % rank)
piece.Update()
self.GetOutputDataObject(0).ShallowCopy(piece.GetOutput())
"""


def write_pieces(folder, size, axis, pieces, nan=False):
    """The phantom as ``vessels-axis<a>-p<pieces>.pvti`` (pieces sharing a point layer); its path.

    ``nan``: the copy whose :data:`NAN_BOX` is NaN (``vessels-nan-...``)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    from mipcast.data_fixtures import make_fixture
    from mipcast.distributed import extract_piece, split_extents

    name = f"vessels{size}{'-nan' if nan else ''}-axis{axis}-p{pieces}"
    path = os.path.join(folder, name + ".pvti")
    if os.path.exists(path):
        return path
    image = make_fixture("vessels", size=size)
    scalars = image.GetPointData().GetScalars()
    scalars.SetName(ARRAY)
    if nan:
        (x0, x1), (y0, y1), (z0, z1) = NAN_BOX
        values = vtk_to_numpy(scalars)
        values.reshape(size, size, size)[z0:z1 + 1, y0:y1 + 1, x0:x1 + 1] = float("nan")
        values[0], values[-1] = NAN_CORNERS
    whole = image.GetExtent()
    lines = []
    for index, extent in enumerate(split_extents(whole, pieces, axis=axis)):
        piece_name = f"{name}-{index}.vti"
        writer = vtkXMLImageDataWriter()
        writer.SetFileName(os.path.join(folder, piece_name))
        writer.SetInputData(extract_piece(image, extent))
        writer.Write()
        lines.append(f'    <Piece Extent="{" ".join(map(str, extent))}" Source="{piece_name}"/>')
    kind = scalars.GetDataTypeAsString().replace("unsigned char", "UInt8").replace("float", "Float32") \
        .replace("double", "Float64").replace("short", "Int16")
    text = ("<?xml version=\"1.0\"?>\n"
            '<VTKFile type="PImageData" version="0.1" byte_order="LittleEndian">\n'
            f'  <PImageData WholeExtent="{" ".join(map(str, whole))}" GhostLevel="0" '
            f'Origin="{" ".join(map(repr, image.GetOrigin()))}" Spacing="{" ".join(map(repr, image.GetSpacing()))}">\n'
            f'    <PPointData Scalars="{ARRAY}"><PDataArray type="{kind}" Name="{ARRAY}"/></PPointData>\n'
            + "\n".join(lines) + "\n  </PImageData>\n</VTKFile>\n")
    with open(path + ".tmp", "w") as handle:
        handle.write(text)
    os.replace(path + ".tmp", path)
    return path


def bounds_width(reader):
    """The x width of the reader's whole volume."""
    bounds = reader.GetDataInformation().GetBounds()
    return bounds[1] - bounds[0]


def main():
    from paraview import simple
    from vtkmodules.vtkCommonExecutionModel import vtkExtentTranslator

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--png-dir", required=True)
    parser.add_argument("--data", required=True, help="folder for the .pvti and its pieces")
    parser.add_argument("--connect", default=None, help="host:port of a pvserver")
    parser.add_argument("--axis", type=int, default=0,
                        help="0, 1, 2: each rank shows the slab along that axis; -1: the reader's own split")
    parser.add_argument("--pieces", type=int, default=2, help="slabs in the file (= the ranks, for --axis >= 0)")
    parser.add_argument("--size", type=int, default=64)
    parser.add_argument("--image", type=int, nargs=2, default=(96, 96))
    parser.add_argument("--methods", default="mip,analytic,paraview-mip")
    parser.add_argument("--outline", action="store_true", help="also show an opaque outline of the volume")
    parser.add_argument("--zoom", type=float, default=0.0,
                        help="look at the first x-quarter of the volume, zoomed by this factor (pieces further along "
                             "x out of view: their ranks must still take part)")
    args = parser.parse_args()
    if args.connect:
        host, port = args.connect.rsplit(":", 1)
        simple.Connect(host, int(port))
        simple.LoadPlugin(args.plugin, remote=True, ns=globals())
    simple.LoadPlugin(args.plugin, remote=False, ns=globals())
    os.makedirs(args.data, exist_ok=True)
    os.makedirs(args.png_dir, exist_ok=True)
    split_axis = max(args.axis, 0)  # here: the plugin's names (ns=globals()) shadow builtins later

    def open_pieces(nan=False):
        path = write_pieces(args.data, args.size, split_axis, args.pieces, nan)
        reader = simple.OpenDataFile(path)  # XML Partitioned Image Data Reader
        reader.UpdatePipeline()
        source = reader
        if args.axis >= 0:
            # every rank takes the slab of the file's pieces that is its own (the reader's request
            # would re-split the whole extent its own way); the whole extent stays the reader's
            source = simple.ProgrammableFilter(Input=reader)
            source.OutputDataSetType = "vtkImageData"
            source.Script = SLAB_SCRIPT.replace("PIECES", repr(path[:-len(".pvti")]))
            source.UpdatePipeline()
        return reader, source

    reader, source = open_pieces()
    ranks = simple.servermanager.ActiveConnection.GetNumberOfDataPartitions()
    low, high = reader.PointData[ARRAY].GetRange()
    view = simple.CreateView("RenderView")
    simple.SetActiveView(view)
    view.ViewSize = list(args.image)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.BackgroundColorMode = "Single Color"
    view.Background = [0.0, 0.0, 0.0]
    view.UseFXAA = 0
    view.UseToneMapping = 0
    display = simple.Show(source, view)
    simple.ColorBy(display, ("POINTS", ARRAY))
    displays = {False: display}  # the NaN copy's display (True) made at its first method
    lut = simple.GetColorTransferFunction(ARRAY)
    lut.ApplyPreset("Grayscale", True)
    lut.AutomaticRescaleRangeMode = "Never"
    lut.RescaleTransferFunction(low, high)
    pwf = simple.GetOpacityTransferFunction(ARRAY)
    pwf.Points = [low, 0.0, 0.5, 0.0, high, 1.0, 0.5, 0.0]  # ParaView's default ramp, over the data range
    translator = vtkExtentTranslator()  # the split the reader's pipeline requests (--axis -1)
    translator.SetWholeExtent(*reader.GetDataInformation().GetExtent())
    translator.SetNumberOfPieces(ranks)
    reader_pieces = []
    for index in range(ranks):
        translator.SetPiece(index)
        translator.PieceToExtent()
        reader_pieces.append(list(translator.GetExtent()))
    if args.outline:  # opaque geometry in the same view (the volume's Outline filter, white)
        outline = simple.Show(simple.Outline(Input=source), view)
        outline.ColorArrayName = ["POINTS", ""]
        outline.AmbientColor = outline.DiffuseColor = [1.0, 1.0, 1.0]
    results = {"ranks": ranks, "reader_pieces": reader_pieces, "session": "client-server" if args.connect else "pvbatch", "axis": args.axis,
               "pieces": args.pieces, "pngs": {}}
    first = True
    applied = []
    shown = False
    for method in args.methods.split(","):
        token, *flags = method.split("+")
        nan, inside, moved = "nan" in flags, "inside" in flags, "moved" in flags
        if nan != shown:  # show the volume this method is drawn on, hide the other
            if nan not in displays:
                displays[nan] = simple.Show(open_pieces(nan=True)[1], view)
                simple.ColorBy(displays[nan], ("POINTS", ARRAY))
            simple.Hide(displays[shown].Input, view)
            simple.Show(displays[nan].Input, view)
            for prop in applied:  # the previous entry's settings back to their defaults
                display.GetProperty(prop).SMProperty.ResetToDefault()
            display.UpdateVTKObjects()
            applied, display, shown = [], displays[nan], nan
        if method == "paraview-mip":
            display.SetRepresentationType("Volume")
            # 5.11's domain lists Composite, Isosurface, Slice; the value reaches
            # vtkVolumeMapper::SetBlendMode on every rank: 1 = MAXIMUM_INTENSITY_BLEND
            display.GetProperty("BlendMode").SetElement(0, 1)
            display.UpdateVTKObjects()
        else:
            # "demip@sphere_weight=0.5@depth_mode=eye_distance": the method and some of its parameters
            name, *settings = token.split("@")
            display.SetRepresentationType("mipcast")
            display.MipcastMethod = name
            for prop in applied:  # the previous entry's settings back to their defaults
                display.GetProperty(prop).SMProperty.ResetToDefault()
            display.UpdateVTKObjects()
            applied = [f"{name}_{setting.split('=')[0]}" for setting in settings]
            for setting in settings:
                parameter, value = setting.split("=")
                for kind in (int, float):  # "1" an integer (a boolean or count), "0.5" a float, else a word
                    try:
                        value = kind(value)
                        break
                    except ValueError:
                        pass
                setattr(display, f"{name}_{parameter}", value)
        if "minip" in method:  # the minimum projections: opaque, a window on the low values
            lut.RescaleTransferFunction(low, low + MINIP_WINDOW * (high - low))
            pwf.Points = [low, 1.0, 0.5, 0.0, high, 1.0, 0.5, 0.0]
        else:
            lut.RescaleTransferFunction(low, high)
            pwf.Points = [low, 0.0, 0.5, 0.0, high, 1.0, 0.5, 0.0]
        if first:
            simple.Render(view)
            view.CameraPosition = [0.0, 0.0, 1.0]
            view.CameraFocalPoint = [0.0, 0.0, 0.0]
            view.CameraViewUp = [0.0, 1.0, 0.0]
            view.ResetCamera(False)
            camera = view.GetActiveCamera()
            camera.Azimuth(35.0)
            camera.Elevation(25.0)
            camera.OrthogonalizeViewUp()
            view.ResetCamera(False)
            if args.zoom > 0:
                bounds = reader.GetDataInformation().GetBounds()
                target = [bounds[0] + 0.125 * (bounds[1] - bounds[0]), 0.5 * (bounds[2] + bounds[3]),
                          0.5 * (bounds[4] + bounds[5])]
                focal = camera.GetFocalPoint()
                shift = [t - f for t, f in zip(target, focal)]
                camera.SetFocalPoint(*target)
                camera.SetPosition(*[p + d for p, d in zip(camera.GetPosition(), shift)])
                camera.Zoom(args.zoom)
            first = False
        camera = view.GetActiveCamera()
        outside = camera.GetPosition()
        if inside:
            focal, width = camera.GetFocalPoint(), bounds_width(reader)
            away = [p - f for p, f in zip(outside, focal)]
            norm = math.hypot(*away)  # not sum(): the plugin's names (ns=globals()) shadow the builtins
            camera.SetPosition(*[f + INSIDE * width * a / norm for f, a in zip(focal, away)])
        if moved:  # about the volume's centre (the reader's whole bounds: the same on every rank)
            bounds = reader.GetDataInformation().GetBounds()
            display.Origin = [0.5 * (bounds[2 * a] + bounds[2 * a + 1]) for a in range(3)]
            for prop, value in MOVED.items():
                setattr(display, prop, value)
        simple.Render(view)
        key = method + "-again" if method in results["pngs"] else method  # a method shown twice
        shot = os.path.join(args.png_dir, f"{key}-n{ranks}-axis{args.axis}.png")
        simple.SaveScreenshot(shot, view, ImageResolution=list(args.image), TransparentBackground=0)
        camera.SetPosition(*outside)
        if moved:
            for prop in ("Origin",) + tuple(MOVED):
                display.GetProperty(prop).SMProperty.ResetToDefault()
            display.UpdateVTKObjects()
        results["pngs"][key] = shot
        print(json.dumps({"method": method, "png": shot}), flush=True)
    with open(args.out, "w") as handle:
        json.dump(results, handle, indent=1)
    print(json.dumps(results), flush=True)


if __name__ == "__main__":
    main()
