"""What VTK's GPU ray caster (stock and mipcast's) draws for geometry it handles badly, against the float64
reference on the same camera rays: volumes far from the origin, and a left-handed direction matrix.

Usage (prints JSON; the tables in docs/reliability.md, *Coordinates far from the origin* and *Degenerate input*)::

    python tests/geometry_precision_check.py

Far from the origin: the vessel phantom 32³ (spacing 1, window 0.2-1, 96², oblique) with its origin at (o, o, o):
the share of pixels more than 1/255 of the data range (0..1) off, the worst error in % of the range
and the hit/miss agreement.  Mirrored: the 24³ phantom with its y axis reversed and its direction matrix
diag(1, -1, 1) (the same voxels in the same places), drawn raw (the mappers now refuse it: set
``right_handed=False`` here to see the old picture through VTK's own stock mapper) and right-handed.
"""
import json

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast import reference
from mipcast.data_fixtures import make_fixture
from mipcast.io import right_handed
from mipcast.offscreen import OffscreenView

SIZE = (96, 96)


def far_from_origin(offsets=(1e4, 2e4, 1e5, 1e6)) -> dict:
    base = make_fixture("vessels", size=32)
    out = {}
    for offset in offsets:
        image = vtkImageData()
        image.DeepCopy(base)
        image.SetOrigin(offset, offset, offset)
        for method in ("mip", "analytic"):
            view = OffscreenView(image, method, size=SIZE, window=(0.2, 1.0))
            found = view.float_image()
            extra = {"sample_distance": view.sample_distance} if method == "mip" else {}
            exact = reference.render(image, view.camera, SIZE, method=method, **extra)
            both = np.isfinite(found) & np.isfinite(exact)
            error = np.abs(found[both] - exact[both])
            out[f"{offset:g} {method}"] = {"pixels_over_1_255_of_range": float(np.mean(error > 1.0 / 255)),
                                           "worst_pct_of_range": float(100 * error.max()),
                                           "misses_agree": float(np.mean(np.isfinite(found) == np.isfinite(exact)))}
    return out


def mirrored() -> dict:
    base = make_fixture("vessels", size=24)
    nx, ny, nz = base.GetDimensions()
    image = vtkImageData()
    image.SetDimensions(nx, ny, nz)
    image.SetSpacing(0.5, 0.7, 1.1)
    image.SetOrigin(3.0, -2.0 + 0.7 * (ny - 1), 5.0)
    image.SetDirectionMatrix(1, 0, 0, 0, -1, 0, 0, 0, 1)
    values = vtk_to_numpy(base.GetPointData().GetScalars()).reshape(nz, ny, nx)[:, ::-1, :]
    image.GetPointData().SetScalars(numpy_to_vtk(np.ascontiguousarray(values).ravel(), deep=True))
    fixed = right_handed(image)
    out = {}
    raw_stock = OffscreenView(fixed, "stock", size=SIZE, window=(0.25, 1.0))
    image_stock = vtkImageData()
    image_stock.DeepCopy(image)
    from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper  # VTK's own, no checks
    from mipcast.offscreen import grey_property
    from vtkmodules.vtkRenderingCore import vtkVolume
    mapper = vtkOpenGLGPUVolumeRayCastMapper()
    mapper.SetInputData(image_stock)
    mapper.SetBlendModeToMaximumIntensity()
    mapper.SetAutoAdjustSampleDistances(False)
    mapper.SetSampleDistance(raw_stock.sample_distance)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(grey_property((0.25, 1.0)))
    right = raw_stock.screenshot()
    raw_stock.renderer.RemoveVolume(raw_stock.volume)
    raw_stock.renderer.AddVolume(volume)
    left = raw_stock.screenshot()
    out["stock: mirrored against right-handed, grey levels"] = int(np.abs(left.astype(int) - right.astype(int)).max())
    out["stock: lit pixels, mirrored / right-handed"] = [int((left.max(axis=2) > 40).sum()),
                                                           int((right.max(axis=2) > 40).sum())]
    view = OffscreenView(fixed, "analytic", size=SIZE, window=(0.25, 1.0))
    found = view.float_image()
    exact = reference.render(fixed, view.camera, SIZE, method="analytic")
    both = np.isfinite(found) & np.isfinite(exact)
    out["analytic right-handed: worst error, fraction of the range"] = float(np.abs(found[both] - exact[both]).max())
    return out


if __name__ == "__main__":
    print(json.dumps({"far_from_origin": far_from_origin(), "mirrored": mirrored()}, indent=1))
