"""Exact distributed MIP in ParaView's MPI engine: ParaView's reader splits, mipcast composites.

Writes the 64^3 vessel phantom to a ``.vti``, reads it with ParaView's
``XMLImageDataReader`` (each server rank gets a piece), and runs
:func:`mipcast.plugin.distributed_paraview.distributed_mip` for ``mip`` and
``analytic`` (and ``demip`` with the eye-distance depth and the colour
sphere, when ``--methods`` names it); the client compares the fetched float image and its colours
with a single-process :class:`mipcast.offscreen.OffscreenView`. Also
renders ParaView's own MIP (Volume representation, BlendMode MIP) and
saves it as ``paraview-mip-n<ranks>.png`` for the contrast (compare two
runs with different rank counts). Results go to ``--out`` as JSON.

pvbatch (the script runs on rank 0, the filter on every rank)::

    mpiexec --oversubscribe -n 2 pvbatch tests/distributed_paraview_check.py --out /tmp/p.json

pvserver behind a pvpython client::

    mpiexec --oversubscribe -n 2 pvserver --server-port=11111 &
    pvpython tests/distributed_paraview_check.py --connect localhost:11111 --out /tmp/p.json
"""
import argparse
import json
import os
import tempfile

import numpy as np


def main():
    from paraview import simple  # here, not at import: pytest's doctest collection imports this file
    from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

    from mipcast.data_fixtures import make_fixture
    from mipcast import methods
    from mipcast.core.parameters import set_parameters
    from mipcast.distributed import colour, demip_picture
    from mipcast.offscreen import OffscreenView
    from mipcast.plugin.distributed_paraview import distributed_mip, fetch_images

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--out", required=True)
    parser.add_argument("--connect", default=None, help="host:port of a pvserver")
    parser.add_argument("--size", type=int, default=64)
    parser.add_argument("--image", type=int, nargs=2, default=(96, 96))
    parser.add_argument("--methods", default="mip,analytic")
    parser.add_argument("--view", default="oblique", help="the view preset (mipcast.offscreen.VIEWS)")
    parser.add_argument("--turned", type=float, default=None, metavar="ANGLE",
                        help="edge_on_check.turned's volume (the vessels on anisotropic spacing, turned ANGLE rad "
                             "about z by its direction matrix, written to the .vti) in place of the phantom")
    parser.add_argument("--png", default=None, help="folder for PNGs (ParaView's own MIP, mipcast's)")
    args = parser.parse_args()
    ranks = 1
    if args.connect:
        host, port = args.connect.rsplit(":", 1)
        simple.Connect(host, int(port))
    if args.turned is None:
        image = make_fixture("vessels", size=args.size)
    else:
        from edge_on_check import turned
        image = turned(args.size, args.turned)
    window = image.GetPointData().GetScalars().GetRange()
    span = window[1] - window[0]
    folder = tempfile.mkdtemp(prefix="mipcast-distributed-")
    path = os.path.join(folder, "vessels.vti")
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(path)
    writer.SetInputData(image)
    writer.Write()
    reader = simple.XMLImageDataReader(FileName=[path])
    reader.UpdatePipeline()
    ranks = simple.servermanager.ActiveConnection.GetNumberOfDataPartitions()
    results = {"ranks": ranks, "session": "client-server" if args.connect else "pvbatch", "cases": []}
    keep = []  # every window stays open to the end: closing one X display and opening the next aborts now and then
    for method in args.methods.split(","):
        demip = methods.METHODS[method].distributed == "demip"
        parameters = {"depth_mode": "eye_distance", "sphere_weight": 0.5} if demip else {}
        flt = distributed_mip(reader, method=method, size=tuple(args.image), view=args.view, window=window,
                              **parameters)
        images = fetch_images(flt)
        values = images["mip_value"]
        single = OffscreenView(image, method, size=tuple(args.image), view=args.view, window=window)
        set_parameters(single.mapper, **parameters)
        keep.append(single)
        reference = single.float_image()
        if demip:
            straight = np.stack([images[f"demip_{c}"] for c in ("red", "green", "blue")], axis=-1)
            rgb = demip_picture(values, straight.astype(np.float64), single.volume.GetProperty())
        else:
            rgb = colour(values, single.volume.GetProperty())
        single_rgb = single.screenshot()
        both = ~np.isnan(values) & ~np.isnan(reference)
        diff = np.abs(values[both].astype(np.float64) - reference[both])
        grey = np.abs(rgb.astype(int) - single_rgb.astype(int)).max(axis=2)
        case = {"method": method, "within_1_grey": float((grey <= 1).mean()), "max_grey_off": int(grey.max()),
                "float_max_error": float(diff.max() / span), "float_identical": float((diff == 0).mean()),
                "misses_agree": float(np.mean(np.isnan(values) == np.isnan(reference))),
                "lit": float((single_rgb.max(axis=2) > 8).mean())}
        results["cases"].append(case)
        print(json.dumps(case), flush=True)
        simple.Delete(flt)
    # ParaView's own MIP on the same split, for the contrast
    view = simple.CreateRenderView()
    view.ViewSize = list(args.image)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [0.0, 0.0, 0.0]
    display = simple.Show(reader, view)
    display.SetRepresentationType("Volume")
    simple.ColorBy(display, ("POINTS", image.GetPointData().GetScalars().GetName()))
    lut = simple.GetColorTransferFunction(image.GetPointData().GetScalars().GetName())
    lut.ApplyPreset("Grayscale", True)
    lut.RescaleTransferFunction(*window)
    pwf = simple.GetOpacityTransferFunction(image.GetPointData().GetScalars().GetName())
    pwf.Points = [window[0], 1.0, 0.5, 0.0, window[1], 1.0, 0.5, 0.0]
    # ParaView 5.11's domain lists Composite, Isosurface, Slice only; the property still
    # reaches vtkVolumeMapper::SetBlendMode on every rank: 1 = MAXIMUM_INTENSITY_BLEND.
    display.GetProperty("BlendMode").SetElement(0, 1)
    display.UpdateVTKObjects()
    view.ResetCamera()
    camera = view.GetActiveCamera()
    camera.Azimuth(33.0)
    camera.Elevation(21.0)
    view.ResetCamera()
    if args.png:
        os.makedirs(args.png, exist_ok=True)
        shot = os.path.join(args.png, f"paraview-mip-n{ranks}.png")
        simple.SaveScreenshot(shot, view, ImageResolution=list(args.image))
        results["paraview_mip_png"] = shot
    with open(args.out, "w") as handle:
        json.dump(results, handle, indent=1)


if __name__ == "__main__":
    main()
