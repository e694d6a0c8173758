"""docs/foveation-paint-beneath.png: a content-adaptive fovea on a coloured background, before and after
its rays were drawn over what lies beneath the volume (shaders/foveated_paint_beneath.glsl).

Rows: cropping regions (inverted cross, gaze (0.3, 0.5)); an opacity ramp (gaze at the centre).
Columns: full quality, content-adaptive 2 grey with the package before the change (afb70b7), after.

Usage: python tests/foveation_beneath_figure.py render OUT.npy      (with the package installed)
       python tests/foveation_beneath_figure.py compose BEFORE.npy AFTER.npy OUT.png
"""
import sys

import numpy as np

SIZE = (128, 128)


def render() -> np.ndarray:
    """(2 cases, [full quality, content-adaptive], H, W, 3) uint8."""
    from mipcast.data_fixtures import make_fixture
    from mipcast.offscreen import OffscreenView

    image = make_fixture("vessels", size=32)
    out = []
    from test_content_adaptive import _crop_fence, _opacity_ramp  # the cases the tests check

    for change, gaze in ((_crop_fence, (0.3, 0.5)), (_opacity_ramp, (0.5, 0.5))):
        row = []
        for method in ("mip", "foveated"):
            view = OffscreenView(image, method, size=SIZE, window=(0.25, 1.0))
            view.renderer.SetBackground(0.1, 0.2, 0.3)
            view.camera.Zoom(1.6)
            view.renderer.ResetCameraClippingRange()
            change(view.mapper)
            if method == "foveated":
                view.mapper.SetContentTolerance(2.0)
                view.mapper.SetGazePoint(*gaze)
            row.append(view.screenshot()[..., :3])
        out.append(row)
    return np.array(out)


def compose(before: np.ndarray, after: np.ndarray, path: str) -> None:
    from PIL import Image

    rows = [np.concatenate([after[i, 0], before[i, 1], after[i, 1]], axis=1) for i in range(len(after))]
    Image.fromarray(np.kron(np.concatenate(rows, axis=0), np.ones((2, 2, 1), np.uint8))).save(path)


if __name__ == "__main__":
    if sys.argv[1] == "render":
        np.save(sys.argv[2], render())
    else:
        compose(np.load(sys.argv[2]), np.load(sys.argv[3]), sys.argv[4])
