"""VTK's own GPU MIP and MinIP writing each ray's value as depth, for exact compositing over ranks.

In a parallel ParaView render view (plugin/representation) the ``stock``
and ``stock_minip`` methods (VTK's ``vtkOpenGLGPUVolumeRayCastMapper`` with
the MAXIMUM / MINIMUM_INTENSITY blend) draw each rank's piece; ParaView's
ordered alpha blending of those pieces is no maximum or minimum.  With the
piece ``shaders/stock_depth_composite.glsl`` (``_min`` for MinIP) on the
volume's shader property, the fragment's depth is the ray's value mapped as
for mipcast's own mappers (the representation's ``depth_mapping``), and
IceT's Z-buffer compositing keeps the right rank's fragment.  VTK's sampling
is not changed: each piece's samples start at that piece's own ray entry, so
the composited maximum is over slightly different sample positions than the
one-rank picture's (see docs/methods.md for what that costs).

Examples
--------
>>> from vtkmodules.vtkRenderingCore import vtkVolume
>>> import vtkmodules.vtkRenderingOpenGL2
>>> volume = vtkVolume()
>>> install(volume, "max")
True
>>> from mipcast.mappers import shader_pieces
>>> shader_pieces.installed_tags(volume.GetShaderProperty())
['//VTK::DepthPass::Exit']
>>> install(volume, "max"), install(volume, None), shader_pieces.installed_tags(volume.GetShaderProperty())
(False, True, [])
"""
from __future__ import annotations

from typing import Optional

from mipcast.mappers import shader_pieces

#: The piece for each compositing op (the nearest fragment holds the largest / smallest value).
PIECES = {"max": "stock_depth_composite", "min": "stock_depth_composite_min"}


def install(volume, op: Optional[str]) -> bool:
    """Put the depth piece of ``op`` (``"max"``, ``"min"``; None: none) on ``volume``; True if it changed."""
    prop = volume.GetShaderProperty()
    wanted = PIECES.get(op) if op is not None else None
    now = [text for tag, text in shader_pieces._fragment_replacements(prop) if shader_pieces.MARKER in text]
    if wanted is not None and len(now) == 1 and shader_pieces.MARKER + wanted + "\n" in now[0]:
        return False
    if wanted is None and not now:
        return False
    if wanted is None:
        shader_pieces.uninstall(prop)
    else:
        shader_pieces.install(prop, [shader_pieces.load_piece(wanted)])
    return True
