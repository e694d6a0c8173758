"""Where a foveated frame's time goes, level by level, and what a coarse ray costs on its own.

``levels``: each level's draw timed alone (``glFinish`` before and after, process CPU time, which
the other engineers' load disturbs less than wall time), full quality, acuity-only and
content-adaptive (2 grey) foveation, 1024² fill, at a gaze point.  ``spacing``: full-quality MIP in
a 1024² and a 256² window at 0.5, 1 and 2 times the base sample distance (the slope is the cost
of the samples, the rest the cost per ray), an empty window, and 1024² at image sample distances
2, 4 and 8 (a reduced pass alone: against 1/isd² of the full frame, its fixed cost).  Medians of interleaved frames
after a warm-up frame, auto-adjust off.

``overhead``: frame times in 32² and 64² windows (full quality, acuity only, content-adaptive), where
the rays cost next to nothing: the per-frame work a fast GPU would leave; still frames, and content-adaptive
frames whose gaze moves or whose camera turns every frame.

``cover``: content-adaptive frames with the whole volume in view and the gaze near a corner, with and
without the outline cover (process CPU time, alternated).

``samples``: the samples each level of one frame takes, in % of full quality's
(``GetLastFrameCost()["levels"]``; counts, not times), acuity-only and content-adaptive (2 grey).

``coherence``: level 0's draw with its mask replaced by scattered rays or the same share in square blocks, and
with the real mask grown to whole blocks.

``content``: content-adaptive frames with and without the content level (times and samples per level).

``floor``: ``levels`` with every fragment discarded at the shader's start: the frame's and each level's cost
whatever their rays (on llvmpipe a fragment invocation costs about 80 ns of CPU even when it ends at once).

Usage: python tests/foveation_level_profile.py levels [SCENE] [GAZE_X GAZE_Y]
       python tests/foveation_level_profile.py floor [SCENE] [GAZE_X GAZE_Y]
       python tests/foveation_level_profile.py coherence [SCENE]
       python tests/foveation_level_profile.py content [SCENE] [GAZE_X GAZE_Y]
       python tests/foveation_level_profile.py spacing [SCENE]
       python tests/foveation_level_profile.py samples [SCENE] [GAZE_X GAZE_Y]
       python tests/foveation_level_profile.py overhead [SCENE]
       python tests/foveation_level_profile.py cover [SCENE]
(prints JSON; figures in docs/foveation.md, "The coarsest level's cost").
"""
import json
import statistics
import sys
import time

from vtkmodules.vtkRenderingCore import vtkVolume

from mipcast.core.object_state import object_state
import mipcast.mappers.foveated_levels as foveated_levels
import mipcast.mappers.foveated_masks as foveated_masks
from mipcast.app.cli import _load_scene
from mipcast.bench.foveation_bench import framed_view
from mipcast.bench.frame_overhead import timed_frame


def _timed(view) -> float:
    """Process CPU seconds of one frame (mipcast.bench.frame_overhead's timing)."""
    return timed_frame(view)[1]


def _medians(views: dict, rounds: int, moves: dict = None) -> dict:
    """ms a frame of each view: the median of interleaved rounds after the first (a warm-up).

    ``moves``: per view name, a function of the round called before its frame (a gaze or camera move)."""
    frames = {name: [] for name in views}
    for index in range(rounds):
        for name, view in views.items():
            if moves and name in moves:
                moves[name](view, index)
            frames[name].append(_timed(view))
    return {name: round(1000 * statistics.median(values[1:]), 1) for name, values in frames.items()}


def _time_level_draws(record) -> None:
    """Time each level volume's draw alone (the GL work finished before and after, process CPU time, which the
    other engineers' load disturbs less than wall time): ``record(isd, seconds)``, ``isd`` the level's image
    sample distance (None: a volume no level owns, the depth copy)."""
    class TimedVolume(vtkVolume):
        def RenderVolumetricGeometry(self, renderer):
            window = renderer.GetRenderWindow()
            window.WaitForCompletion()
            start = time.process_time()
            result = vtkVolume.RenderVolumetricGeometry(self, renderer)
            window.WaitForCompletion()
            record(getattr(self, "isd", None), time.process_time() - start)
            return result

    copy_settings = foveated_levels.copy_settings

    def noting_isd(mapper, volume, level_mapper, level_volume, matrix, distance, isd):
        level_volume.isd = isd
        return copy_settings(mapper, volume, level_mapper, level_volume, matrix, distance, isd)

    foveated_levels.vtkVolume, foveated_levels.copy_settings = TimedVolume, noting_isd


#: A fragment shader that ends before its ray starts (a replacement at the top of VTK's raycaster main()).
DISCARD_ALL = ("//VTK::CallWorker::Impl", True, "if (gl_FragCoord.x > -1.0) discard;\n//VTK::CallWorker::Impl", False)


def levels(scene: str, gaze, rounds: int = 4, discard: bool = False) -> dict:
    """ms a frame and per level draw (keyed by the level's image sample distance).

    ``discard``: every fragment of every volume draw discarded at the shader's start (no ray at all): what a
    frame costs whatever its rays, its floor on this renderer (fragment invocations in each level's box, VTK's
    stretch of a reduced level over the viewport, the refine passes, copies)."""
    draws, current = {}, [None]

    def record(isd, seconds):
        if current[0] is not None:
            key = f"isd {isd if isd is not None else '?'}"
            draws.setdefault(current[0], {}).setdefault(key, []).append(seconds)

    _time_level_draws(record)
    image, window = _load_scene(scene, 128)
    views = {}
    for name in ("full", "acuity", "content-adaptive"):
        view = framed_view(image, "mip" if name == "full" else "foveated", 1024, "fill", window)
        if name != "full":
            view.mapper.SetGazePoint(*gaze)
        if name == "content-adaptive":
            view.mapper.SetContentTolerance(2.0)
        views[name] = view
    if discard:
        for view in views.values():
            view.render_window.Render()  # the levels' volumes exist after the first frame
            drawn = object_state(view.mapper).get("levels_drawn", {})
            for volume in [view.volume] + [entry["volume"] for entry in drawn.values()]:
                volume.GetShaderProperty().AddFragmentShaderReplacement(*DISCARD_ALL)
    frames = {name: [] for name in views}
    for index in range(rounds):
        for name, view in views.items():
            current[0] = name if index else None
            frames[name].append(_timed(view))
    ms = lambda values: round(1000 * statistics.median(values), 1)  # noqa: E731
    return {"scene": scene, "gaze": list(gaze),
            "frame_ms": {name: ms(values[1:]) for name, values in frames.items()},
            "level_ms": {name: {key: ms(values) for key, values in found.items()} for name, found in draws.items()}}


def spacing(scene: str, rounds: int = 5) -> dict:
    """Full-quality MIP in 1024² and 256² windows at three sample distances, empty windows, and 1024² at three
    image sample distances."""
    image, window = _load_scene(scene, 128)
    views = {}
    for size in (256, 1024):
        for factor in (0.5, 1.0, 2.0):
            view = framed_view(image, "mip", size, "fill", window)
            view.mapper.SetAutoAdjustSampleDistances(False)
            view.mapper.SetSampleDistance(factor * view.mapper.GetSampleDistance())
            views[f"{size}² x{factor}"] = view
        view = framed_view(image, "mip", size, "fill", window)
        view.volume.VisibilityOff()
        views[f"{size}² empty"] = view
    for isd in (2.0, 4.0, 8.0):  # a reduced pass on its own: its rays' share of a full frame, plus a fixed cost
        view = framed_view(image, "mip", 1024, "fill", window)
        view.mapper.SetImageSampleDistance(isd)
        views[f"1024² isd {isd:g}"] = view
    return {"scene": scene, "ms": _medians(views, rounds)}


def overhead(scene: str, rounds: int = 9) -> dict:
    """Frame ms in 32² and 64² windows, where the GL work is next to nothing: full quality, acuity-only and
    content-adaptive (2 grey) foveation -- the per-frame work a fast GPU would leave (planning, the structure
    bound, uniforms, passes).  Still frames (the same frame again), and at 32² content-adaptive frames whose
    gaze moves every frame (an eye tracker's fixations elsewhere) or whose camera turns 1 degree a frame."""
    image, window = _load_scene(scene, 128)
    views, moves = {}, {}
    for size in (32, 64):
        for name in ("full", "acuity", "content-adaptive"):
            view = framed_view(image, "mip" if name == "full" else "foveated", size, "fill", window)
            if name == "content-adaptive":
                view.mapper.SetContentTolerance(2.0)
            views[f"{size}² {name}"] = view
    gazes = [(0.3, 0.4), (0.6, 0.55), (0.45, 0.7), (0.7, 0.3)]
    for name in ("gaze moving", "camera turning"):
        view = framed_view(image, "foveated", 32, "fill", window)
        view.mapper.SetContentTolerance(2.0)
        views[f"32² content-adaptive, {name}"] = view
    moves["32² content-adaptive, gaze moving"] = lambda view, index: view.mapper.SetGazePoint(*gazes[index % 4])
    moves["32² content-adaptive, camera turning"] = lambda view, index: view.renderer.GetActiveCamera().Azimuth(1.0)
    return {"scene": scene, "ms": _medians(views, rounds, moves)}


def cover(scene: str, gaze=(0.1, 0.1), rounds: int = 7) -> dict:
    """Frame ms of content-adaptive (2 grey) foveation, the whole volume in a 1024² view, with and without the
    outline cover (foveated_masks.outline_cover, which reads the picture beneath back where it applies), alternated."""
    image, window = _load_scene(scene, 128)
    view = framed_view(image, "foveated", 1024, "whole", window)
    view.mapper.SetContentTolerance(2.0)
    view.mapper.SetGazePoint(*gaze)
    real = foveated_masks.outline_cover
    frames = {"with": [], "without": []}
    _timed(view)
    for _ in range(rounds):
        for name in frames:
            foveated_masks.outline_cover = real if name == "with" else (lambda *args: None)
            frames[name].append(_timed(view))
    foveated_masks.outline_cover = real
    return {"scene": scene, "gaze": list(gaze), "ms": {name: round(1000 * statistics.median(values), 1)
                                                       for name, values in frames.items()}}


def coherence(scene: str, rounds: int = 4) -> dict:
    """Level 0's draw (CPU ms) with its refinement mask replaced by patterns of equal share: scattered rays
    against the same share in square blocks of 4, 8 and 16 pixels; and the real mask, alone and grown to whole
    blocks of 4, 8 and 16 pixels where any of its texels asks (its share of level 0's grid beside it; content-adaptive
    2 grey, masks made on the CPU, 1024² fill, gaze at the centre).  SIMD lanes (llvmpipe's, a GPU's warps) march
    blocks of neighbouring rays together: a block with one ray costs about what a full one does."""
    import numpy as np

    import mipcast.core.content_adaptive as content_adaptive

    timed, pattern, shares = [], [None], []
    _time_level_draws(lambda isd, seconds: timed.append(seconds) if isd == 1.0 else None)
    real_mask = content_adaptive.refinement_mask

    def patterned(edge, structure, plan, layer):
        mask = real_mask(edge, structure, plan, layer)
        if layer.level != 0 or pattern[0] is None:
            return mask
        block, share = pattern[0]
        rows, columns = mask.shape
        if share is None:  # the real mask, grown to whole blocks
            padded = np.pad(mask, ((0, -rows % block), (0, -columns % block)))
            chosen = padded.reshape(padded.shape[0] // block, block, padded.shape[1] // block, block).any(axis=(1, 3))
        else:
            chosen = np.random.default_rng(1).random((rows // block + 1, columns // block + 1)) < share
        grown = np.kron(chosen, np.ones((block, block), bool))[:rows, :columns]
        shares.append(float(grown.mean()))
        return grown

    content_adaptive.refinement_mask = patterned
    image, window = _load_scene(scene, 128)
    view = framed_view(image, "foveated", 1024, "fill", window)
    view.mapper.SetContentTolerance(2.0)
    object_state(view.mapper)["masks_on_cpu"] = True
    out = {}
    for block, share in ((1, 0.0), (1, 0.05), (4, 0.05), (8, 0.05), (16, 0.05), (1, 0.2), (8, 0.2), (1, 1.0),
                         (1, None), (4, None), (8, None), (16, None)):
        pattern[0] = (block, share)
        timed.clear()
        shares.clear()
        for _ in range(rounds):
            view.render_window.Render()
        name = f"{share:.0%} of the rays, blocks of {block}" if share is not None else (
            f"the real mask ({statistics.median(shares):.2%} of the grid), blocks of {block}")
        out[name] = round(1000 * statistics.median(timed[1:]), 1)
    return {"scene": scene, "level_0_ms": out}


def content(scene: str, gaze, rounds: int = 5) -> dict:
    """Content-adaptive frames (2 grey) with and without the content level (acuity's coarsest level then cast over
    the whole viewport unmasked, as where the level cap forbids a content level), beside full quality and acuity
    only: ms a frame (process CPU, interleaved medians) and samples per level in % of full quality's."""
    image, window = _load_scene(scene, 128)
    views = {}
    for name in ("full", "acuity", "content level", "no content level"):
        view = framed_view(image, "mip" if name == "full" else "foveated", 1024, "fill", window)
        if name != "full":
            view.mapper.SetGazePoint(*gaze)
        if name.endswith("content level"):
            view.mapper.SetContentTolerance(2.0)
        object_state(view.mapper)["no_content_level"] = name == "no content level"  # the benchmarks' variant
        views[name] = view
    frames = {name: [] for name in views}
    for _ in range(rounds):
        for name, view in views.items():
            frames[name].append(_timed(view))
    out = {"scene": scene, "gaze": list(gaze),
           "frame_ms": {name: round(1000 * statistics.median(values[1:]), 1) for name, values in frames.items()}}
    for name in ("content level", "no content level"):
        views[name].render_window.Render()
        cost = views[name].mapper.GetLastFrameCost()
        out[name] = {"sample_ratio": round(cost["sample_ratio"], 2),
                     "levels": {row["level"]: round(100.0 * row["samples"] / cost["full_samples"], 2)
                                for row in cost["levels"]}}
    return out


def samples(scene: str, gaze) -> dict:
    image, window = _load_scene(scene, 128)
    out = {}
    for name, tolerance in (("acuity only", 0.0), ("content-adaptive 2 grey", 2.0)):
        view = framed_view(image, "foveated", 1024, "fill", window)
        view.mapper.SetContentTolerance(tolerance)
        view.mapper.SetGazePoint(*gaze)
        view.render_window.Render()
        cost = view.mapper.GetLastFrameCost()
        out[name] = {"sample_ratio": cost["sample_ratio"],
                     "levels": {row["level"]: 100.0 * row["samples"] / cost["full_samples"] for row in cost["levels"]}}
        view.render_window.Finalize()
    return out


if __name__ == "__main__":
    mode = sys.argv[1] if len(sys.argv) > 1 else "levels"
    scene_name = sys.argv[2] if len(sys.argv) > 2 else "vessels@0.25,1"
    if mode in ("levels", "floor"):
        point = (float(sys.argv[3]), float(sys.argv[4])) if len(sys.argv) > 4 else (0.5, 0.5)
        print(json.dumps(levels(scene_name, point, discard=mode == "floor"), indent=1))
    elif mode == "content":
        point = (float(sys.argv[3]), float(sys.argv[4])) if len(sys.argv) > 4 else (0.5, 0.5)
        print(json.dumps(content(scene_name, point), indent=1))
    elif mode == "samples":
        point = (float(sys.argv[3]), float(sys.argv[4])) if len(sys.argv) > 4 else (0.5, 0.5)
        print(json.dumps(samples(scene_name, point), indent=1))
    elif mode == "coherence":
        print(json.dumps(coherence(scene_name), indent=1))
    elif mode == "cover":
        print(json.dumps(cover(scene_name), indent=1))
    elif mode == "overhead":
        print(json.dumps(overhead(scene_name), indent=1))
    else:
        print(json.dumps(spacing(scene_name), indent=1))
