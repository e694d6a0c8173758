"""Why coarse foveation levels cost more per sample on llvmpipe: ray spacing, not window size.

Usage (from the repository root)::

    python3 tests/ray_locality_check.py

Vessels 128^3, "fill" framing (as ``mipcast bench --foveation``), mipcast
``mip`` at one sample per voxel.  Each line renders a square window with the
camera zoomed so that neighbouring rays are a given distance apart in
voxels, and prints the median frame time per sample taken (samples counted
on the CPU, :func:`mipcast.core.ray_cost.grid_cost`).  A 128-pixel window whose
rays are as close as a 512-pixel window's costs the same per sample; the
same window with rays four times farther apart (a level-2 periphery at
512^2) costs about twice as much: llvmpipe has no texture cache, so
neighbouring rays that no longer share cache lines pay for memory traffic.
"""
import statistics

from mipcast.data_fixtures import make_fixture
from mipcast.bench.foveation_bench import framed_view
from mipcast.offscreen import OffscreenView
from mipcast.core.ray_cost import grid_cost

#: (window edge in pixels, extra zoom over the fill framing)
CASES = ((512, 1.0), (128, 4.0), (128, 1.0), (1024, 1.0), (256, 4.0), (256, 1.0))


def locality_rows(rounds: int = 4) -> list:
    image = make_fixture("vessels", size=128)
    views = {}
    for edge, zoom in CASES:
        view: OffscreenView = framed_view(image, "mip", edge, "fill")
        view.camera.Zoom(zoom)
        view.renderer.ResetCameraClippingRange()
        views[edge, zoom] = view
    for view in views.values():
        view.frame_times(frames=0, warmup=2)
    times = {key: [] for key in views}
    for _ in range(rounds):
        for key, view in views.items():
            times[key] += view.frame_times(frames=3, warmup=0)
    rows = []
    for (edge, zoom), view in views.items():
        rays, samples = grid_cost(image, view.camera, (edge, edge), (edge, edge),
                                  sample_distance=view.sample_distance)
        spacing = 2.0 * view.camera.GetParallelScale() / edge / min(image.GetSpacing())  # orthographic
        seconds = statistics.median(times[edge, zoom])
        rows.append({"window": edge, "zoom": zoom, "ray_spacing_voxels": spacing, "rays": rays,
                     "samples": samples, "ms": 1000 * seconds, "ns_per_sample": 1e9 * seconds / samples})
    return rows


if __name__ == "__main__":
    print("| window | extra zoom | rays apart (voxels) | samples | frame ms | ns per sample |")
    print("| --- | --- | --- | --- | --- | --- |")
    for row in locality_rows():
        print(f"| {row['window']}² | {row['zoom']:g} | {row['ray_spacing_voxels']:.2f} | {row['samples']} | "
              f"{row['ms']:.1f} | {row['ns_per_sample']:.2f} |")
