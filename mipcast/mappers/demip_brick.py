"""Distributed DEMIP, phase 2 on one brick: the first same-material sample of the WHOLE ray's maximum.

:mod:`mipcast.distributed` composites DEMIP over MPI ranks exactly as one
process defines it (``docs/methods.md#demip``): phase 1 reduces the ranks'
sampled MIP (MAX) into the whole volume's per-pixel maximum; phase 2 hands
that maximum back to every rank's GPU as a float texture, and
:class:`DEMIPBrickDepthMapper` marches the brick's share of the whole
volume's samples (the ``global_phase`` piece: the whole ray's start + (1 +
k) steps, whole-ray indices k; the start is the whole box's entry, or VTK's
near-plane cap with the camera inside the volume) to the first sample of the same material as
the global maximum (DEMIP's test, ``shaders/demip_brick_hooks.glsl``),
reading out its index k; the ranks' MIN is the whole ray's first
same-material sample.  Depth (over the whole volume's box), Eq. 1 and the
colour sphere are then applied on the CPU (:mod:`mipcast.core.demip_depth`).
"""
from __future__ import annotations

import numpy as np
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject

from mipcast.core.object_state import object_state
from mipcast.core.shading import FLOOR_TOLERANCE
from mipcast.core.transfer_bounds import constant_ends
from mipcast.mappers.demip import DEMIPVolumeMapper
from mipcast.mappers.float_readout import from_data_units, normalised_span, read_normalised

#: Texture value for "no maximum" (the ray met no data on any rank).
NO_MAXIMUM = 1.0e30

_VTK_FLOAT = 10


class DEMIPBrickDepthMapper(DEMIPVolumeMapper):
    """One brick's phase 2 of distributed DEMIP: whole-ray index of the first same-material sample.

    Takes DEMIP's settings (the same parameter table: threshold, depth of);
    the picture it would draw is not used: :func:`first_match_index` renders
    its float readout.  Needs ``global_box`` in its state and the
    ``u_mc_globalTexMin/Max`` uniforms (:class:`mipcast.distributed.DistributedView`
    sets them) so that its samples are the whole volume's.

    Examples
    --------
    >>> mapper = DEMIPBrickDepthMapper()
    >>> "demip_brick_hooks" in mapper.GetShaderPieces()
    True
    """

    PIECES = ("mip_globals", "demip_brick_fetch", "demip_helpers", "sampled_loop", "demip_brick_hooks",
              "no_stock_sample", "mip_color")

    def __init__(self) -> None:
        super().__init__()
        self.SetAutoAdjustSampleDistances(False)
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _bind_maximum, -1.0)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, _release_maximum, -1.0)

    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES` (with ``global_phase`` on a brick); the index readout while a readout renders."""
        names = self._with_readout(self.PIECES)
        return self._with_missing("demip_brick_readout" if n == "float_readout" else n for n in names)


def first_match_index(render_window, mapper: DEMIPBrickDepthMapper, maximum: np.ndarray,
                      data_range) -> np.ndarray:
    """Render phase 2 once: per pixel, the whole-ray index of this brick's first same-material sample.

    Parameters
    ----------
    render_window : vtkRenderWindow
        The window of the mapper's renderer (rendered at least once).
    mapper : DEMIPBrickDepthMapper
        Attached, its volume the only visible one.
    maximum : numpy.ndarray, shape (height, width)
        The whole volume's per-pixel maximum in data units (NaN: none), top row first.
    data_range : (low, high)
        The whole volume's scalar range (the material window's ends are the
        transfer functions' over it, :func:`mipcast.core.transfer_bounds.constant_ends`).

    Returns
    -------
    numpy.ndarray, shape (height, width), float64
        Sample index k (sample k at the whole ray's start + (1 + k) steps); +inf
        where this brick holds no same-material sample.
    """
    bind_maximum(render_window, mapper, maximum, data_range)
    return match_index(read_normalised(render_window, mapper))


def match_index(found: np.ndarray) -> np.ndarray:
    """Phase 2's readout (normalised, NaN: none) -> whole-ray sample index (+inf: none)."""
    return np.where(np.isnan(found), np.inf, np.rint(1.0 - found))


def bind_maximum(render_window, mapper: DEMIPBrickDepthMapper, maximum: np.ndarray, data_range) -> None:
    """Phase 2's inputs on ``mapper``: the material window's uniforms and the maximum as a float texture.

    As :func:`first_match_index`, without the render: the next render of
    ``mapper`` (its float readout) marches to the first same-material sample.
    """
    scalars = mapper.GetRenderedInput().GetPointData().GetScalars()
    normalised = np.where(np.isnan(maximum), NO_MAXIMUM, from_data_units(np.nan_to_num(maximum), scalars))
    ends = constant_ends(mapper.GetAttachedVolume().GetProperty(), *data_range)
    low, span = normalised_span(scalars)
    floor, ceiling = ((v - low) / span for v in ends)  # as normalised_ends (a constant brick: VTK's span)
    if not ceiling > floor:  # constant transfer functions: no ray gets a DEMIP term (as DEMIPVolumeMapper)
        floor, ceiling = 1.0e20, 2.0e20
    eps = mapper.GetMaterialThreshold() if mapper.GetDepthOf() == "same_material" else 0.0
    mapper.GetAttachedVolume().GetShaderProperty().GetFragmentCustomUniforms().SetUniform4f(
        "u_mc_brickWindow", [floor, ceiling, eps, FLOOR_TOLERANCE])
    upload_pixels(render_window, mapper, normalised)


def upload_pixels(render_window, mapper, normalised: np.ndarray, depth=None) -> None:
    """A per-pixel float image (top row first) as ``mapper``'s shared float texture (``in_depthSampler``).

    Read by the ``demip_brick_fetch`` piece (``mc_globalMax``) at the next render;
    shape (height, width) or (height, width, components) (1 to 4 components).
    ``depth`` (height, width): the scene depth (0 .. 1, the depth buffer's; 1: none) the rays end at
    (:func:`mipcast.mappers.outline_rays.scene_depth`), put in the texture's alpha (the
    ``demip_brick_fetch`` and ``demip_brick_state_fetch`` pieces; none: alpha reads 1, the far plane).
    """
    if depth is not None:
        channels = normalised.reshape(normalised.shape[:2] + (-1,))
        padding = np.zeros(normalised.shape[:2] + (3 - channels.shape[2],))
        normalised = np.concatenate([channels, padding, np.asarray(depth)[..., None]], axis=-1)
    height, width = normalised.shape[:2]
    components = normalised.shape[2] if normalised.ndim == 3 else 1
    state = object_state(mapper)
    texture = state.get("maximum_texture")
    if texture is None:
        texture = state["maximum_texture"] = vtkTextureObject()
        texture.SetMinificationFilter(vtkTextureObject.Nearest)
        texture.SetMagnificationFilter(vtkTextureObject.Nearest)
        texture.SetWrapS(vtkTextureObject.ClampToEdge)
        texture.SetWrapT(vtkTextureObject.ClampToEdge)
    texture.SetContext(render_window)
    rows = np.ascontiguousarray(normalised[::-1], dtype=np.float32)  # the texture's row 0 is the bottom
    state["maximum_rows"] = rows  # kept alive while VTK may read it
    if not texture.Create2DFromRaw(width, height, components, _VTK_FLOAT, rows):
        raise RuntimeError("could not upload the global maximum as a float texture (GL_R32F)")
    mapper.SetSharedDepthTexture(texture)


def _bind_maximum(mapper, event) -> None:
    """Activate the maximum's texture (a texture unit for in_depthSampler) until the render ends."""
    texture = object_state(mapper).get("maximum_texture")
    if texture is not None and texture.GetHandle():
        texture.Activate()
        object_state(mapper)["bound_texture"] = texture


def _release_maximum(mapper, event) -> None:
    texture = object_state(mapper).pop("bound_texture", None)
    if texture is not None:
        texture.Deactivate()
