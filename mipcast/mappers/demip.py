"""Depth-enhanced MIP (DEMIP, Díaz & Vázquez): MIP with depth shading and a colour sphere."""
from __future__ import annotations

import numpy as np

from mipcast.mappers.float_readout import read_normalised
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.core.object_state import object_state
from mipcast.core.transfer_bounds import normalised_ends
from mipcast.core.shading import (DEPTH_MODES, DEPTH_OF, FLOOR_TOLERANCE, PROJECTIONS, READOUTS,
                                  SPHERE_PRESETS)
from mipcast.core import parameter_tables
from mipcast.core.parameters import parameter_accessors
from mipcast.core.validation import check_choice



@parameter_accessors
class DEMIPVolumeMapper(MIPVolumeMapper):
    """Depth-enhanced MIP: the MIP picture, brighter where its material is near.

    Díaz & Vázquez's DEMIP in one fragment shader per ray: the sampled MIP
    march (exactly the samples of the ``"mip"`` method), then a second march to
    the first sample of the *same material* as the maximum, whose depth in
    [0, 1] brightens near and darkens far structures (Eq. 1,
    ``colour = MIP_colour * (1 - d_w) + 2 d_w (1 - depth)``), optionally
    tinted by a world-fixed colour sphere (Eq. 2) or by pseudo-chromadepth.
    Only rays whose maximum lies above the transfer functions' window floor
    get the depth term: the background stays as MIP shows it.  With all
    weights 0 the picture is bit-identical to ``"mip"``, at its speed.

    Settings (VTK-style ``SetX``/``GetX``, validated in the setter):
    :meth:`SetDepthWeight` (``d_w``, default 0.15),
    :meth:`SetMaterialThreshold` (``eps``, default 0.1, in fractions of the
    window), :meth:`SetDepthMode` (``"window"``, ``"steps"``,
    ``"entry_plus_length"`` (default), ``"eye_distance"``),
    :meth:`SetSphereWeight`, :meth:`SetSphereColors`,
    :meth:`SetSphereOrientation`, :meth:`SetChromaDepthWeight`,
    :meth:`SetDepthOf`, :meth:`SetProjection` (``"mip"``, ``"lmip"``,
    ``"attenuated"``, ``"mida"``) with :meth:`SetLocalThreshold` and
    :meth:`SetAttenuation`, and :meth:`SetReadout` for the float readout.
    Partitioned rendering (``SetPartitions``) is refused.

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from mipcast.data_fixtures import make_fixture
    >>> mapper = DEMIPVolumeMapper()
    >>> mapper.SetInputData(make_fixture("frontback", size=32))
    >>> mapper.SetDepthWeight(0.3)
    >>> mapper.SetDepthMode("eye_distance")
    >>> mapper.Attach(vtkVolume())
    >>> mapper.GetDepthWeight(), mapper.GetDepthMode()
    (0.3, 'eye_distance')

    See docs/methods.md, section DEMIP (definitions of window, material, same
    material and floor rule; the depth modes; the colour sphere; LMIP,
    attenuated MIP and MIDA): ``docs/methods.md#demip``.
    """

    #: Drawn in bricks in two phases (:mod:`mipcast.mappers.bricked_demip`): the whole ray's maximum,
    #: then its material's first sample over the bricks.
    BRICKS = "demip"
    PIECES = ("mip_globals", "refusal", "demip_helpers", "sampled_loop", "demip_hooks", "no_stock_sample",
              "demip_color")

    PARAMETERS = parameter_tables.DEMIP
    DEPTH_MODES = DEPTH_MODES
    SPHERE_PRESETS = SPHERE_PRESETS
    READOUTS = READOUTS
    PROJECTIONS = PROJECTIONS
    DEPTH_OF = DEPTH_OF

    # -- the float readout's quantity (internal: render_depth switches it) ----
    def SetReadout(self, readout: str) -> None:
        """What the float readout reports: ``"value"`` (the ray maximum, default) or ``"depth"``.

        Internal to :func:`render_depth`, which switches to ``"depth"`` for one render.
        """
        object_state(self)["readout"] = check_choice("readout", readout, READOUTS)
        self.Modified()

    def GetReadout(self) -> str:
        """The float readout's quantity."""
        return object_state(self).get("readout", "value")

    # -- rendering rules -----------------------------------------------------
    def GetRenderProblem(self):
        """As :meth:`MIPVolumeMapper.GetRenderProblem`, plus: no partitioned rendering.

        Depth is normalised over the whole volume's box and the same-material
        search runs along the whole ray; VTK's partitioned rendering
        (``SetPartitions``) casts each block's rays separately, so it is
        refused (with a message) instead of drawing per-block depths.
        """
        problem = super().GetRenderProblem()
        if problem is None and self._partitioned():
            problem = ("DEMIP needs the whole ray in one texture: partitioned rendering "
                       "(SetPartitions) would measure depth per block; call SetPartitions(1, 1, 1)")
        return problem

    # -- shader -------------------------------------------------------------
    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES` while there is a DEMIP term to draw or a depth to read, else MIP's.

        With depth weight 0, sphere weight 0 and no depth readout, the pieces
        are those of :class:`MIPVolumeMapper`: the picture is bit-identical to
        the ``"mip"`` method and costs the same (switching compiles the
        other shader once; VTK caches both).  A float readout uses DEMIP's
        own readout piece (value or depth, :meth:`SetReadout`).
        """
        projection = self.GetProjection()
        if projection == "mip" and not self._needs_depth():
            return self._with_blocks(self._with_missing(self._with_readout(MIPVolumeMapper.PIECES)))
        swap = {"float_readout": "demip_readout"}
        if projection == "lmip":
            swap["demip_hooks"] = "demip_lmip_hooks"
        elif projection == "attenuated":
            swap["demip_hooks"] = "demip_attenuated_hooks"
        elif projection == "mida":
            swap.update(demip_hooks="demip_mida_hooks", demip_color="demip_mida_color")
        return self._with_blocks(self._with_missing(swap.get(n, n) for n in self._with_readout(self.PIECES)))

    def _needs_depth(self) -> bool:
        """Whether anything uses the depth: a weight above 0, or a depth readout rendering."""
        settings = self._parameters()
        reading_depth = self.GetReadout() == "depth" and bool(object_state(self).get("exact_readout"))
        return reading_depth or any(settings[name] > 0.0 for name in (
            "depth_weight", "sphere_weight", "chroma_depth_weight"))

    def _window(self) -> tuple:
        """Normalised (floor, ceiling) of the attached volume's transfer functions.

        Without a window (constant transfer functions) the floor is put above
        every value: no ray gets a DEMIP term.
        """
        image, volume = self.GetRenderedInput(), self.GetAttachedVolume()
        if image is None or volume is None or image.GetPointData().GetScalars() is None:
            return 0.0, 1.0
        ends = normalised_ends(volume.GetProperty(), image.GetPointData().GetScalars())
        return ends if ends is not None and ends[1] > ends[0] else (2.0, 3.0)

    def _derived_settings(self) -> dict:
        floor, ceiling = self._window()
        return {"floor": floor, "ceiling": ceiling}

    def _push_derived_uniforms(self, uniforms, settings) -> None:
        uniforms.SetUniformf("u_mc_floor", settings["floor"])
        uniforms.SetUniformf("u_mc_ceiling", settings["ceiling"])
        uniforms.SetUniformf("u_mc_floorTolerance", FLOOR_TOLERANCE)
        uniforms.SetUniformf("u_mc_needDepth", 1.0 if self._needs_depth() else 0.0)
        uniforms.SetUniformf("u_mc_readDepth", 1.0 if self.GetReadout() == "depth" else 0.0)


def render_depth(render_window, mapper: DEMIPVolumeMapper) -> np.ndarray:
    """Render once and return each pixel's DEMIP depth as float64, above the 8-bit floor.

    Parameters
    ----------
    render_window : vtkRenderWindow
        The window whose renderer holds the mapper's attached volume.
    mapper : DEMIPVolumeMapper
        An attached DEMIP mapper; its settings (depth mode, threshold,
        window) are used as they are, its readout setting is restored.

    Returns
    -------
    numpy.ndarray, shape (height, width), float64
        Depth in [0, 1] (0 = near side of the box); NaN where the ray misses
        the volume or gets no DEMIP term (maximum at or below the floor).
        Top row first.  Float32 precision (about 1e-7).

    Examples
    --------
    >>> import numpy as np
    >>> from mipcast.offscreen import OffscreenView
    >>> from mipcast.data_fixtures import make_fixture
    >>> view = OffscreenView(make_fixture("frontback", size=16), "demip", size=(24, 24))
    >>> depth = render_depth(view.render_window, view.mapper)
    >>> bool(np.nanmin(depth) >= 0.0 and np.nanmax(depth) <= 1.0)
    True
    """
    if not isinstance(mapper, DEMIPVolumeMapper):
        raise TypeError(f"render_depth needs a DEMIPVolumeMapper, got {type(mapper).__name__}")
    saved = mapper.GetReadout()
    mapper.SetReadout("depth")
    try:
        return read_normalised(render_window, mapper)  # the depth as the shader wrote it
    finally:
        mapper.SetReadout(saved)
