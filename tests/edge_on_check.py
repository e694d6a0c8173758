"""Faces seen (nearly) edge-on, with and without ``shaders/ray_mend.glsl``: error and time.

    python tests/edge_on_check.py sweep [METHOD]   # 30 turns about the view axis x 2 sizes, the view tilted 0-3 deg
    python tests/edge_on_check.py time [ROUNDS]    # vessels 96^3 turned 0.5 rad, 512^2 front view, mip and analytic
    python tests/edge_on_check.py moves            # where moving starts to the box's entry changes a pixel

``sweep``: the vessels 24^3 (float32, anisotropic spacing) turned 0.05-1.5 rad about z by its direction
matrix, seen head-on (``front``) and tilted by the elevation given, in 41x37 and 64x64 pictures; per tilt,
the pixels more than 1e-4 of the range off the float64 reference on the same rays and the worst of them,
without the piece (``EDGE_ON`` 0) and with it, and the smallest and largest sine at which a face is seen
(``mipcast.core.camera_rays.grazing_sine``).  ``time``: median frame ms of interleaved frames, the piece
installed against the same frames without it, in one process (auto-adjust off, llvmpipe).  ``moves``: mip and
analytic on the volume turned 0.05-1.5 rad, tilted 0.3-5 degrees and 2 degrees at 1.1 rad, each float readout
with the starts' moves forced on (``u_mc_entryMoves`` 2) and off (0): the views where a pixel differs, with
their grazing sine (``mipcast.mappers.mip.ENTRY_MOVES`` leaves the test out above 0.1).
"""
from __future__ import annotations

import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

import mipcast.mappers.mip as mip
from mipcast.core.camera_rays import grazing_sine
from mipcast.data_fixtures import make_fixture
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView
from ray_direction_check import piece_medians, piece_switch

TILTS = (0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 0.1, 0.5, 1.0, 3.0)
#: The piece installed where a face is near edge-on (True, mipcast's rule) or never (False) from now on.
use_piece = piece_switch(mip.RAY_MEND_PIECE)


def turned(size: int, angle: float) -> vtkImageData:
    """The vessels ``size``^3 (float32, 0..250) on spacing 0.7 x 1 x 1.6, turned ``angle`` rad about z."""
    values = vtk_to_numpy(make_fixture("vessels", size=size).GetPointData().GetScalars()).astype(np.float32)
    image = vtkImageData()
    image.SetDimensions(size, size, size)
    image.SetSpacing(0.7, 1.0, 1.6)
    image.SetOrigin(1.5, -2.0, 3.0)
    c, s = np.cos(angle), np.sin(angle)
    image.SetDirectionMatrix(c, -s, 0, s, c, 0, 0, 0, 1)
    scalars = numpy_to_vtk(values * 250.0, deep=True)
    scalars.SetName("s")
    image.GetPointData().SetScalars(scalars)
    return image


def tilted_scene(image, name: str, size: tuple, tilt: float, view: str = "front") -> OffscreenView:
    """A scene of ``image`` drawn by method ``name``, its ``view`` tilted by ``tilt`` degrees of elevation."""
    scene = OffscreenView(image, name, size=size, view=view)
    scene.camera.Elevation(tilt)
    scene.camera.OrthogonalizeViewUp()
    scene.renderer.ResetCameraClippingRange()
    return scene


def sweep(name: str = "analytic") -> None:
    for tilt in TILTS:
        found = {}
        sines = []
        for on in (False, True):
            use_piece(on)
            off, worst = 0, 0.0
            for angle in np.linspace(0.05, 1.5, 30):
                for size in ((41, 37), (64, 64)):
                    image = turned(24, angle)
                    scene = tilted_scene(image, name, size, tilt)
                    got = scene.float_image()
                    sampling = {} if METHODS[name].walks_cells else {"sample_distance": scene.sample_distance}
                    expected = METHODS[name].reference(image, scene.camera, size, window=scene.window, **sampling)
                    error = np.abs(got - expected) / 250.0
                    error[np.isnan(error)] = 0.0
                    off, worst = off + int((error > 1e-4).sum()), max(worst, float(error.max()))
                    if on:
                        sines.append(grazing_sine(image, scene.camera, scene.volume.GetMatrix()))
            found[on] = (off, worst)
        use_piece(True)
        print(f"tilt {tilt} deg (sines {min(sines):.3g}-{max(sines):.3g}): without the piece {found[False][0]} "
              f"pixels off, worst {found[False][1]:.3g}; with it {found[True][0]}, worst {found[True][1]:.3g}")


def moves() -> None:
    forced = {"moves": 2.0}
    mip.MIPVolumeMapper._entry_moves = lambda self, volume: forced["moves"]
    views = [(name, float(angle), tilt, size) for name in ("mip", "analytic") for angle in np.linspace(0.05, 1.5, 8)
             for tilt in (0.3, 0.5, 1.0, 2.0, 3.0, 5.0) for size in ((41, 37), (64, 64))]
    views += [("mip", 1.1, 2.0, (64, 64))]
    largest, smallest = 0.0, 1.0
    for name, angle, tilt, size in views:
        image = turned(24, angle)
        scene = tilted_scene(image, name, size, tilt)
        pictures = []
        for value in (2.0, 0.0):
            forced["moves"] = value
            pictures.append(scene.float_image())
        sine = grazing_sine(image, scene.camera, scene.volume.GetMatrix())
        smallest = min(smallest, sine)
        same = (pictures[0] == pictures[1]) | (np.isnan(pictures[0]) & np.isnan(pictures[1]))
        if not same.all():
            largest = max(largest, sine)
            print(f"{name} {angle:.3f} rad, {tilt} deg, {size}: sine {sine:.3g}, {int((~same).sum())} pixel(s) moved")
    print(f"{len(views)} views, sines {smallest:.3g} and up; the largest sine with a pixel moved: {largest:.3g}")


def timing(rounds: int = 9) -> None:
    image = turned(96, 0.5)
    for name in ("mip", "analytic"):
        without, with_piece = piece_medians(image, name, "front", use_piece, rounds)
        print(f"{name}: without the piece {without:.1f} ms, with it {with_piece:.1f} ms, "
              f"ratio {with_piece / without:.3f}")


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "sweep":
        sweep(*sys.argv[2:3])
    elif len(sys.argv) > 1 and sys.argv[1] == "moves":
        moves()
    elif len(sys.argv) > 1 and sys.argv[1] == "time":
        timing(int(sys.argv[2]) if len(sys.argv) > 2 else 9)
    else:
        sys.exit(__doc__)
