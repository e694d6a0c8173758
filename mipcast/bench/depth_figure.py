"""The DEMIP paper's Fig. 1/6 for our data: MIP, DEMIP, DEMIP + colour sphere, DVR side by side."""
from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from mipcast.bench.benchmark import apply_settings
from mipcast.offscreen import OffscreenView

#: Columns of the figure: (title, method, DEMIP settings).
PANELS = (
    ("MIP", "mip", {}),
    ("DEMIP", "demip", {"DepthWeight": 0.3}),
    ("DEMIP + colour sphere", "demip", {"DepthWeight": 0.3, "SphereWeight": 0.5}),
    ("DVR (stock, composite)", "stock", {}),
)


def render_panels(image, view: str = "oblique", size=(256, 256), window=None) -> list:
    """One picture per :data:`PANELS` column, (height, width, 3) uint8 each.

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> [p.shape for p in render_panels(make_fixture("frontback", size=16), size=(24, 24))]
    [(24, 24, 3), (24, 24, 3), (24, 24, 3), (24, 24, 3)]
    """
    pictures = []
    for _, method, settings in PANELS:
        scene = OffscreenView(image, method, size=size, view=view, window=window)
        apply_settings(scene.mapper, settings.items())
        if method == "stock":  # direct volume rendering: the same grey ramp, a gentle opacity ramp
            scene.mapper.SetBlendModeToComposite()
            opacity = scene.volume.GetProperty().GetScalarOpacity()
            opacity.RemoveAllPoints()
            opacity.AddPoint(scene.window[0], 0.0)
            opacity.AddPoint(scene.window[1], 0.25)
        pictures.append(scene.screenshot())
    return pictures


def write_depth_figure(path: Path, scenes: Sequence[tuple], size=(256, 256)) -> None:
    """Write the figure: one row per ``(label, image, view, window)`` scene.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> from mipcast.data_fixtures import make_fixture
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "figure.png"
    >>> write_depth_figure(path, [("blobs", make_fixture("frontback", size=16), "front", None)], size=(32, 32))
    >>> path.stat().st_size > 1000
    True
    """
    import matplotlib
    matplotlib.use("Agg")
    from matplotlib import pyplot

    figure, axes = pyplot.subplots(len(scenes), len(PANELS), figsize=(3.0 * len(PANELS), 3.0 * len(scenes)),
                                   squeeze=False)
    for row, (label, image, view, window) in enumerate(scenes):
        for column, picture in enumerate(render_panels(image, view, size, window)):
            axes[row][column].imshow(np.asarray(picture))
            axes[row][column].set_axis_off()
            if row == 0:
                axes[row][column].set_title(PANELS[column][0], fontsize=10)
        axes[row][0].text(-0.05, 0.5, label, transform=axes[row][0].transAxes, rotation=90,
                          ha="right", va="center", fontsize=10)
    figure.tight_layout()
    figure.savefig(path, dpi=90, facecolor="white")
    pyplot.close(figure)
