"""Block skipping against reading every sample, and against stock VTK: sampled MIP, sampled MinIP, the
exact MinIP and DEMIP (its defaults: depth weight 0.15, same material; ``--method``).

Wall ms per frame (medians of interleaved frames after a warm-up frame, auto-adjust off, the volume
filling the view, oblique), and whether the two mipcast pictures are identical, pixel for pixel (if not,
how many pixels differ and by how many grey levels at most).

Usage: python tests/mip_skipping_bench.py [SCENE ...] [--size N ...] [--method mip|minip|analytic_minip|demip] [--slab MM]
       [--volume-size N]
(default: vessels@0.25,1 head@100,1500 at 512 and 1024, MIP; MinIP: e.g. head@-1000,-400, airways;
prints JSON; figures in docs/methods.md, Skipping).
"""
import argparse
import json
import statistics
import time

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkPlane

from mipcast.app.cli import _load_scene
from mipcast.bench.foveation_bench import framed_view


#: method: (stock VTK's counterpart, the piece that skips blocks)
METHODS = {"mip": ("stock", "mip_hooks_blocks"), "minip": ("stock_minip", "minip_hooks_blocks"),
           "analytic_minip": ("stock_minip", "amip_loop_blocks"), "demip": ("stock", "demip_hooks_blocks")}


def measure(scene: str, size: int, rounds: int = 7, method: str = "mip", slab: float = 0.0,
            volume_size: int = 128) -> dict:
    image, window = _load_scene(scene, volume_size)
    stock, piece = METHODS[method]
    views = {}
    for name in ("stock", "skipping", "no skipping"):
        view = framed_view(image, stock if name == "stock" else method, size, "fill", window)
        view.mapper.SetAutoAdjustSampleDistances(False)
        if slab > 0.0:  # through the focal point, facing the camera (stock: two clipping planes)
            _slab(view, slab)
        if name == "no skipping":
            view.mapper.SetSkipping(False)
        views[name] = view
    frames = {name: [] for name in views}
    for _ in range(rounds):
        for name, view in views.items():
            window_ = view.render_window
            window_.WaitForCompletion()
            start = time.perf_counter()
            window_.Render()
            window_.WaitForCompletion()
            frames[name].append(time.perf_counter() - start)
    ms = {name: round(1000 * statistics.median(values[1:]), 1) for name, values in frames.items()}
    skipping, every = views["skipping"].screenshot(), views["no skipping"].screenshot()
    return {"scene": scene, "size": size, "method": method, "slab": slab, "ms": ms,
            "skips_blocks": piece in views["skipping"].mapper.GetShaderPieces(),
            "no skipping / skipping": round(ms["no skipping"] / ms["skipping"], 2),
            "stock / skipping": round(ms["stock"] / ms["skipping"], 2),
            "identical": bool(np.array_equal(skipping, every)),
            # where not: rays within a table texel of the floor or ceiling (drawn as the transfer functions'
            # constant colour with skipping, through VTK's table interpolation without; docs/methods.md), and
            # for the exact MinIP float rounding of the walk restarted after a jump
            "pixels differing": int(np.any(skipping != every, axis=2).sum()),
            "largest difference": int(np.abs(skipping.astype(int) - every).max()),
            "drawn_share": round(float((every.max(axis=2) > 0).mean()), 3)}


def _slab(view, thickness: float) -> None:
    if view.method.name.startswith("stock"):
        camera = view.renderer.GetActiveCamera()
        normal = np.array(camera.GetDirectionOfProjection())
        for sign in (1.0, -1.0):
            plane = vtkPlane()
            plane.SetOrigin(np.array(camera.GetFocalPoint()) - sign * 0.5 * thickness * normal)
            plane.SetNormal(sign * normal)
            view.mapper.AddClippingPlane(plane)
    else:
        view.mapper.SetSlabThickness(thickness)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", default=["vessels@0.25,1", "head@100,1500"])
    parser.add_argument("--size", nargs="+", type=int, default=[512, 1024])
    parser.add_argument("--method", choices=sorted(METHODS), default="mip")
    parser.add_argument("--slab", type=float, default=0.0, help="slab thickness (world units) through the centre")
    parser.add_argument("--volume-size", type=int, default=128, help="edge of synthetic fixtures")
    args = parser.parse_args()
    print(json.dumps([measure(scene, size, method=args.method, slab=args.slab, volume_size=args.volume_size)
                      for scene in args.scenes for size in args.size], indent=1))


if __name__ == "__main__":
    main()
