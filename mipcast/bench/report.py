"""What every report of the benchmarks shares: strict JSON and the renderer's strings."""
from __future__ import annotations

import json
from typing import Optional

import numpy as np


def renderer_info() -> dict:
    """OpenGL vendor, renderer and version strings of an offscreen VTK window.

    From ``vtkOpenGLRenderWindow.ReportCapabilities()``; ``window`` is the
    render window class (e.g. vtkEGLRenderWindow).

    Examples
    --------
    >>> sorted(renderer_info())
    ['renderer', 'vendor', 'version', 'window']
    """
    from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401

    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.AddRenderer(vtkRenderer())
    window.SetSize(16, 16)
    window.Render()
    info = {"window": type(window).__name__, "vendor": "", "renderer": "", "version": ""}
    for line in window.ReportCapabilities().splitlines():
        for key in ("vendor", "renderer", "version"):
            if f"OpenGL {key} string:" in line:
                info[key] = line.split(":", 1)[1].strip()
    window.Finalize()
    return info


def strict_json(value, indent: Optional[int] = None) -> str:
    """JSON strict parsers accept: NaN and infinities (e.g. a ceiling with no fovea in view) become null,
    numpy scalars plain numbers.

    Examples
    --------
    >>> strict_json({"a": float("nan"), "b": [np.float32(1.5), np.int64(2)], "c": (1, float("inf"))})
    '{"a": null, "b": [1.5, 2], "c": [1, null]}'
    """
    def plain(item):
        if isinstance(item, dict):
            return {str(key): plain(entry) for key, entry in item.items()}
        if isinstance(item, (list, tuple)):
            return [plain(entry) for entry in item]
        if isinstance(item, np.generic):
            item = item.item()
        if isinstance(item, float) and not np.isfinite(item):
            return None
        return item

    return json.dumps(plain(value), indent=indent, allow_nan=False)
