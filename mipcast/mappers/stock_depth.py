"""VTK's own GPU MIP and MinIP writing each ray's value as depth, for exact compositing over ranks.

In a parallel ParaView render view (plugin/representation) the ``stock``
and ``stock_minip`` methods (VTK's ``vtkOpenGLGPUVolumeRayCastMapper`` with
the MAXIMUM / MINIMUM_INTENSITY blend) draw each rank's piece; ParaView's
ordered alpha blending of those pieces is no maximum or minimum.  With the
piece ``shaders/stock_depth_composite.glsl`` (``_min`` for MinIP) on the
volume's shader property, the fragment's depth is the ray's value mapped as
for mipcast's own mappers (the representation's ``depth_mapping``), and
IceT's Z-buffer compositing keeps the right rank's fragment.  With the
whole volume's box given (``phase``), the piece ``shaders/stock_phase.glsl``
moves each piece's samples onto the WHOLE volume's sample positions along
the ray (VTK's loop otherwise starts at the piece's own entry), so that the
composited maximum is over the one-rank picture's samples (see
docs/methods.md for what it measures).

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
>>> install(volume, "min", ([0.01, 0.01, 0.01], [1.5, 0.99, 0.99]))
True
>>> shader_pieces.installed_tags(volume.GetShaderProperty())
['//VTK::DepthPass::Exit', '//VTK::DepthPass::Init']
"""
from __future__ import annotations

from typing import Optional, Sequence, Tuple

import numpy as np

from mipcast.mappers import shader_pieces

#: The piece for each compositing op (the nearest fragment holds the largest / smallest value).
PIECES = {"max": "stock_depth_composite", "min": "stock_depth_composite_min"}
#: The piece that puts a piece's samples on the whole volume's positions (uniforms u_mc_globalTexMin/Max).
PHASE_PIECE = "stock_phase"


def install(volume, op: Optional[str], phase: Optional[Tuple[Sequence[float], Sequence[float]]] = None) -> bool:
    """Put the depth piece of ``op`` (``"max"``, ``"min"``; None: none) on ``volume``; True if it changed.

    ``phase``: the whole volume's point bounds in this piece's texture
    coordinates, ``(low, high)``
    (:func:`mipcast.mappers.brick_rays.global_texture_box`), to take the
    whole volume's sample positions too (the ``stock_phase`` piece; with
    ``op`` only).
    """
    prop = volume.GetShaderProperty()
    wanted = [PIECES[op]] if op is not None else []
    if wanted and phase is not None:
        low, high = phase
        uniforms = prop.GetFragmentCustomUniforms()
        uniforms.SetUniform3f("u_mc_globalTexMin", [float(v) for v in low])
        uniforms.SetUniform3f("u_mc_globalTexMax", [float(v) for v in high])
        uniforms.SetUniform4f("u_mc_capTex", [0.0, 0.0, 0.0, 0.0])  # no cap until a draw's push_cap
        wanted.append(PHASE_PIECE)
    now = sorted(text.split(shader_pieces.MARKER, 1)[1].split("\n", 1)[0]
                 for tag, text in shader_pieces._fragment_replacements(prop) if shader_pieces.MARKER in text)
    if now == sorted(wanted):
        return False
    if not wanted:
        shader_pieces.uninstall(prop)
    else:
        shader_pieces.install(prop, [shader_pieces.load_piece(name) for name in wanted])
    return True


def push_cap(volume, whole, camera, piece_extent: Sequence[int], aspect: float = 1.0) -> None:
    """This frame's near-plane cap on ``volume`` for the ``stock_phase`` piece (``u_mc_capTex``).

    Where ``camera``'s near plane cuts the ``whole`` volume's box (the camera
    inside the volume) VTK starts the whole volume's rays at its cap
    (:func:`mipcast.core.camera_rays.near_cap`): the plane in the
    texture coordinates of the piece of ``piece_extent``; none (zeros)
    otherwise.  ``whole``: :func:`mipcast.mappers.brick_rays.whole_geometry`'s image.
    """
    from mipcast.core.camera_rays import near_cap
    from mipcast.mappers.brick_rays import index_plane, texture_plane

    cap = near_cap(whole, camera, aspect)
    plane = np.zeros(4) if cap is None else texture_plane(index_plane(cap, whole.GetIndexToPhysicalMatrix()),
                                                             piece_extent)
    volume.GetShaderProperty().GetFragmentCustomUniforms().SetUniform4f("u_mc_capTex", [float(v) for v in plane])
