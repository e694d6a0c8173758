"""Stock VTK MIP vs mipcast MIP, same scene: run in-process or under pvpython.

Also stock VTK's MINIMUM_INTENSITY blend against mipcast's ``minip``, the
``average``'s picture against its float readout coloured through the volume
property on the CPU (it colours its mean as MIP colours its maximum; VTK's
AVERAGE_INTENSITY blend draws a grey that ignores the transfer functions),
both under ``"projections"``, and the projections' float readouts against
their references.

Prints one JSON object: VTK version and, per view, the share of pixels whose
RGB channels differ by at most 1 grey level, the largest difference, the
lit share, and the float readout's largest error against the float64
sampled reference (fraction of the data range; hit masks must agree).
Used by tests/test_mip_mapper.py for VTK 9.7 (pip) and, through
``xvfb-run -a pvpython tests/parity_check.py``, for ParaView's VTK 9.2.
"""
import json
import sys

import numpy as np

from vtkmodules.vtkCommonCore import vtkVersion

from mipcast import reference
from mipcast.data_fixtures import make_fixture
from mipcast.core.metrics import grey_diff
from mipcast.offscreen import OffscreenView


def parity(fixture="vessels", size=48, window=(128, 128)):
    image = make_fixture(fixture, size=size)
    result = {"vtk": vtkVersion.GetVTKVersion()}
    for view in ("oblique", "perspective"):
        stock = OffscreenView(image, "stock", size=window, view=view, window="full").screenshot()
        mip = OffscreenView(image, "mip", size=window, view=view, window="full")
        ours = mip.screenshot()
        result[view] = grey_diff(stock, ours)
        result[view]["lit"] = float((ours.max(axis=-1) > 0).mean())
        values = mip.float_image()
        expected = reference.render(image, mip.camera, window, method="mip",
                                    sample_distance=mip.sample_distance)
        result[view]["masks_agree"] = bool(np.array_equal(np.isnan(values), np.isnan(expected)))
        result[view]["float_max_error"] = float(np.nanmax(np.abs(values - expected)))
    return result


#: (stock blend, mipcast sampled method, exact method, fixture, window) per projection.
PROJECTIONS = (("stock_minip", "minip", "analytic_minip", "airways", (0.0, 0.9)),
               ("stock_average", "average", "analytic_average", "vessels", (0.05, 0.6)))


def projections(size=40, window=(96, 96)):
    """Per projection and view: grey parity with stock, lit share, and the float errors of the
    sampled and the exact method against their references (fraction of the data range)."""
    from mipcast.methods import METHODS

    result = {}
    for stock_name, sampled, exact, fixture, grey in PROJECTIONS:
        image = make_fixture(fixture, size=size)
        low, high = image.GetPointData().GetScalars().GetRange(0)
        for view in ("oblique", "perspective"):
            ours = OffscreenView(image, sampled, size=window, view=view, window=grey)
            if stock_name == "stock_average":  # the picture is the readout coloured (shaders/average_color.glsl)
                from mipcast.mappers.bricked_draw import colour

                coloured = 255.0 * colour(ours.float_image(), ours.volume.GetProperty())[..., :3]
                expected = np.clip(np.round(coloured), 0, 255).astype(np.uint8)
            else:
                expected = OffscreenView(image, stock_name, size=window, view=view, window=grey).screenshot()
            entry = grey_diff(expected, ours.screenshot())
            entry["lit"] = float((expected.max(axis=-1) > 0).mean())
            for name in (sampled, exact):
                scene = ours if name == sampled else OffscreenView(image, name, size=window, view=view)
                values = scene.float_image()
                expected = METHODS[name].reference(image, scene.camera, window,
                                                   sample_distance=scene.sample_distance)
                entry[f"{name}_masks_agree"] = bool(np.array_equal(np.isnan(values), np.isnan(expected)))
                entry[f"{name}_max_error"] = float(np.nanmax(np.abs(values - expected)) / (high - low))
            result[f"{sampled} {view}"] = entry
    return result


if __name__ == "__main__":
    print(json.dumps(dict(parity(), projections=projections())))
    sys.stdout.flush()
