"""Block skipping with missing values: the head CT with and without a padded rim (its corners outside a
circle of the slice's width missing, 21.5 % of the voxels, as a padded CT has them), mip and analytic, with
and without skipping, under an opacity ramp from 0 at the window floor (ParaView's transfer functions,
pyvista's opacity="linear") and under an opaque grey (OffscreenView's, `mipcast render`'s, pyvista's constant
opacity) (docs/methods.md, "Block skipping", "With missing values").

    python tests/padded_skipping_bench.py [--size 512] [--rounds 4]

Wall ms a frame, medians of rounds of 2 frames after warm-up, every view timed in turn.
"""
import argparse
import statistics
import time
import warnings

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPiecewiseFunction

from mipcast.data_fixtures import load_head_ct
from mipcast.data_fixtures.synthetic import image_from_array
from mipcast.offscreen import OffscreenView

WINDOW = (150.0, 1800.0)


def _image(like, values: np.ndarray) -> vtkImageData:
    return image_from_array(values, "HU", spacing=like.GetSpacing(), origin=like.GetOrigin())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--rounds", type=int, default=4)
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    ct = load_head_ct()
    nx, ny, nz = ct.GetDimensions()
    values = vtk_to_numpy(ct.GetPointData().GetScalars()).reshape(nz, ny, nx).astype(np.float32)
    y, x = np.mgrid[0:ny, 0:nx]
    padded = values.copy()
    padded[:, (x - nx / 2) ** 2 + (y - ny / 2) ** 2 > (0.5 * nx) ** 2] = np.nan
    views = {}
    for volume, data in (("CT", values), ("padded CT", padded)):
        for opacity in ("ramp", "opaque"):
            for method in ("mip", "analytic"):
                for skipping in (True, False):
                    view = OffscreenView(_image(ct, data), method, size=(args.size, args.size), window=WINDOW)
                    if opacity == "ramp":
                        ramp = vtkPiecewiseFunction()
                        ramp.AddPoint(WINDOW[0], 0.0)
                        ramp.AddPoint(WINDOW[1], 1.0)
                        view.volume.GetProperty().SetScalarOpacity(ramp)
                    view.mapper.SetSkipping(skipping)
                    views[volume, opacity, method, "skipping" if skipping else "every sample"] = view
    times = {key: [] for key in views}
    for view in views.values():
        view.render_window.Render()
        view.render_window.Render()
    for _ in range(args.rounds):
        for key, view in views.items():
            start = time.perf_counter()
            view.render_window.Render()
            view.render_window.Render()
            times[key].append((time.perf_counter() - start) / 2.0)
    print(f"head CT {nx}x{ny}x{nz}, {args.size}^2, window {WINDOW[0]:g}-{WINDOW[1]:g} HU; ms a frame")
    for key, samples in times.items():
        print(" | ".join(key), f"{1e3 * statistics.median(samples):.1f}")


if __name__ == "__main__":
    main()
