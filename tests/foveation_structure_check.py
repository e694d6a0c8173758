"""The fovea's structure under content-adaptive density on the head CT taken every n-th point (issue 17).

Per stride, window size and gaze: the share of the foveal disc's pixels where full quality shows structure
(not black) that the content-adaptive (2 grey) picture matches within 1 grey.  A coarser head has steeper
edges and specks that clear the 100 HU floor by little: the structure smaller than the coarse rays' spacing
that the data's structure bound (mipcast.core.structure_bound) keeps in the fovea.  Figures: docs/foveation.md.

Usage: python tests/foveation_structure_check.py
"""
from mipcast.bench.foveation_bench import apply_settings, framed_view, ring_errors
from mipcast.bench.gpu_report import CLINICAL_WINDOW, head_scene

GAZES = ((0.5, 0.5), (0.1, 0.1), (0.3, 0.7), (0.8, 0.35))


def main() -> None:
    for stride in (1, 2, 3, 4, 6):
        image = head_scene(stride)
        for size in (96, 192, 384):
            full = framed_view(image, "mip", size, "fill", CLINICAL_WINDOW)
            reference = full.screenshot()
            shares = []
            for gaze in GAZES:
                view = framed_view(image, "foveated", size, "fill", CLINICAL_WINDOW)
                apply_settings(view.mapper, (("Method", "mip"), ("ContentTolerance", 2.0), ("GazePoint", gaze)))
                errors = ring_errors(reference, view.screenshot(), gaze, view.mapper.GetFovealRadius())
                shares.append(round(errors["fovea_structure_within_1"], 4))
                view.render_window.Finalize()
            full.render_window.Finalize()
            print(f"every {stride}. point {image.GetDimensions()}, {size}²: gazes {GAZES}: {shares}", flush=True)


if __name__ == "__main__":
    main()
