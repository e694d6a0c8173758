"""Depth-enhanced MIP (DEMIP, Díaz & Vázquez): MIP with depth shading and a colour sphere."""
from __future__ import annotations

import numpy as np

from mipcast.mappers.float_readout import read_normalised
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.core.object_state import object_state
from mipcast.core.transfer_bounds import normalised_ends
from mipcast.core.shading import (DEPTH_MODES, DEPTH_OF, FLOOR_TOLERANCE, IDENTITY, PROJECTIONS, READOUTS,
                                  SPHERE_PRESETS)
from mipcast.core import shading
from mipcast.core.validation import check_choice, check_non_negative, check_unit

_DEFAULTS = {
    "depth_weight": 0.15,
    "material_threshold": 0.1,
    "depth_mode": "entry_plus_length",
    "sphere_weight": 0.0,
    "sphere_colors": SPHERE_PRESETS["red-blue"],
    "sphere_orientation": IDENTITY,
    "readout": "value",
    "chroma_depth_weight": 0.0,
    "depth_of": "same_material",
    "projection": "mip",
    "local_threshold": 0.5,
    "attenuation": 0.05,
}


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

    PIECES = ("mip_globals", "refusal", "demip_helpers", "sampled_loop", "demip_hooks", "no_stock_sample",
              "demip_color")

    DEPTH_MODES = DEPTH_MODES
    SPHERE_PRESETS = SPHERE_PRESETS
    READOUTS = READOUTS
    PROJECTIONS = PROJECTIONS
    DEPTH_OF = DEPTH_OF

    # -- settings ---------------------------------------------------------
    def _settings(self) -> dict:
        state = object_state(self)
        if "demip" not in state:
            state["demip"] = dict(_DEFAULTS)
        return state["demip"]

    def _set(self, name: str, value) -> None:
        self._settings()[name] = value
        volume = self.GetAttachedVolume()
        if volume is not None:
            self._push_uniforms(volume.GetShaderProperty().GetFragmentCustomUniforms())
        self.Modified()

    def SetDepthWeight(self, weight: float) -> None:
        """Weight ``d_w`` of the depth term in Eq. 1, in [0, 1]; default 0.15 (the paper's).

        0 is plain MIP; larger values brighten near and darken far structures.
        """
        self._set("depth_weight", check_unit("depth_weight", weight))

    def GetDepthWeight(self) -> float:
        """The depth weight ``d_w``."""
        return self._settings()["depth_weight"]

    def SetMaterialThreshold(self, eps: float) -> None:
        """``eps``: how close (in material, i.e. fractions of the window) counts as the same, in (0, 1].

        Default 0.1.  Near 0 the depth is that of the maximum's own sample
        (noisy on noisy data); 1 accepts the first sample above the floor.
        """
        self._set("material_threshold", check_unit("material_threshold", eps, open_low=True))

    def GetMaterialThreshold(self) -> float:
        """The material threshold ``eps``."""
        return self._settings()["material_threshold"]

    def SetDepthMode(self, mode: str) -> None:
        """How depth is measured: one of :data:`DEPTH_MODES`; default ``"entry_plus_length"``."""
        self._set("depth_mode", check_choice("depth_mode", mode, DEPTH_MODES))

    def GetDepthMode(self) -> str:
        """The depth mode."""
        return self._settings()["depth_mode"]

    def SetSphereWeight(self, weight: float) -> None:
        """Weight ``sph_w`` of the colour sphere in Eq. 2, in [0, 1]; default 0 (off)."""
        self._set("sphere_weight", check_unit("sphere_weight", weight))

    def GetSphereWeight(self) -> float:
        """The colour sphere weight ``sph_w``."""
        return self._settings()["sphere_weight"]

    def SetSphereColors(self, *colors) -> None:
        """The sphere's front and back colour: a preset name or two RGB triplets in [0, 1].

        Presets (:data:`SPHERE_PRESETS`): ``"red-blue"`` (default),
        ``"green-red"``, ``"green-blue"``.  Any two colours suit users who
        tell other pairs apart better: ``SetSphereColors((1, 0.5, 0), (0, 0.6, 1))``,
        ``SetSphereColors([front, back])`` or six numbers
        (``mipcast render ... --sphere-colors 1 0.5 0 0 0.6 1``).
        """
        self._set("sphere_colors", shading.sphere_colors(colors))

    def GetSphereColors(self) -> tuple:
        """``(front, back)`` RGB triplets."""
        return self._settings()["sphere_colors"]

    def SetSphereOrientation(self, *rotation) -> None:
        """Rotate the colour sphere in world coordinates (camera and volume unaffected).

        Either three angles in degrees, ``SetSphereOrientation(rx, ry, rz)``
        (the rotation ``Rz @ Ry @ Rx``: about x first), or a 3x3 rotation
        matrix (orthonormal, determinant +1), given as one argument or as
        three rows.  The sphere's front pole, +z of its frame, points along
        the matrix's third column; the identity (default) puts it on world
        +z.  ``SetSphereOrientation(0, 180, 0)`` swaps front and back.
        """
        self._set("sphere_orientation", shading.rotation(rotation))

    def GetSphereOrientation(self) -> tuple:
        """The sphere's rotation as a 3x3 tuple of rows."""
        return self._settings()["sphere_orientation"]

    def SetReadout(self, readout: str) -> None:
        """What the float readout reports: ``"value"`` (the ray maximum, default) or ``"depth"``.

        See :func:`render_depth`, which switches to ``"depth"`` for one render.
        """
        self._set("readout", check_choice("readout", readout, READOUTS))

    def GetReadout(self) -> str:
        """The float readout's quantity."""
        return self._settings()["readout"]

    def SetChromaDepthWeight(self, weight: float) -> None:
        """Weight of pseudo-chromadepth colouring (Ropinski et al.), in [0, 1]; default 0 (off).

        After Eq. 1 and 2, ``colour = colour * (1 - w) + hue(depth) * w``
        with the hue running from red (depth 0, near) through yellow, green
        and cyan to blue (depth 1, far).  On DEMIP it colours by the depth of
        the same-material sample; for pseudo-chromadepth on plain MIP use
        ``SetDepthWeight(0)`` and ``SetDepthOf("maximum")``.
        """
        self._set("chroma_depth_weight", check_unit("chroma_depth_weight", weight))

    def GetChromaDepthWeight(self) -> float:
        """The pseudo-chromadepth weight."""
        return self._settings()["chroma_depth_weight"]

    def SetDepthOf(self, target: str) -> None:
        """Which sample's depth is used: ``"same_material"`` (default, DEMIP) or ``"maximum"``.

        ``"maximum"``: the first sample whose material equals the maximum's
        (the maximum itself, or the first sample saturating the window), as
        if ``eps`` were 0; the material threshold is then ignored.
        """
        self._set("depth_of", check_choice("depth_of", target, DEPTH_OF))

    def GetDepthOf(self) -> str:
        """Which sample gives the depth."""
        return self._settings()["depth_of"]

    def SetProjection(self, projection: str) -> None:
        """The ray's value: one of :data:`PROJECTIONS`; default ``"mip"``.

        ``"mip"``: the maximum (DEMIP as described above).
        ``"lmip"``: local MIP (Sato et al.): the first local maximum above
        :meth:`SetLocalThreshold` along the ray (the global maximum if no
        sample exceeds it); DEMIP then works on the ray up to that sample
        (the same-material search never goes past it).
        ``"attenuated"``: napari-style attenuated MIP, the largest material
        ``m_k * exp(-a * h * sum_{j<k} m_j)`` (``a``: :meth:`SetAttenuation`,
        ``h``: sample distance in voxels), shown as the scalar of that
        material; no DEMIP term.
        ``"mida"``: maximum intensity difference accumulation (Bruckner &
        Gröller), gamma 0: the transfer functions composited front to back,
        what lies in front faded by ``1 - delta`` wherever the running
        maximum of the material rises by ``delta``; no DEMIP term; the float
        readout still reports the maximum.
        Switching projections installs other shader pieces (one compile each).
        """
        self._set("projection", check_choice("projection", projection, PROJECTIONS))

    def GetProjection(self) -> str:
        """The ray projection."""
        return self._settings()["projection"]

    def SetLocalThreshold(self, threshold: float) -> None:
        """LMIP's threshold as a material (place in the window), in [0, 1]; default 0.5."""
        self._set("local_threshold", check_unit("local_threshold", threshold))

    def GetLocalThreshold(self) -> float:
        """LMIP's threshold."""
        return self._settings()["local_threshold"]

    def SetAttenuation(self, attenuation: float) -> None:
        """Attenuated MIP's attenuation per voxel of full material, >= 0; default 0.05.

        0 gives the MIP picture.
        """
        self._set("attenuation", check_non_negative("attenuation", attenuation, numbers_only=True))

    def GetAttenuation(self) -> float:
        """Attenuated MIP's attenuation."""
        return self._settings()["attenuation"]

    # -- rendering rules -----------------------------------------------------
    def SetPartitions(self, x: int, y: int, z: int) -> None:
        """Recorded so that rendering can refuse it: see :meth:`GetRenderProblem`."""
        object_state(self)["partitions"] = (int(x), int(y), int(z))
        super().SetPartitions(x, y, z)

    def GetRenderProblem(self):
        """As :meth:`MIPVolumeMapper.GetRenderProblem`, plus: no partitioned rendering.

        Depth is normalised over the whole volume's box and the same-material
        search runs along the whole ray; VTK's partitioned rendering
        (``SetPartitions``) casts each block's rays separately, so it is
        refused (with a message) instead of drawing per-block depths.
        """
        problem = super().GetRenderProblem()
        if problem is None and object_state(self).get("partitions", (1, 1, 1)) != (1, 1, 1):
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
        projection = self._settings()["projection"]
        if projection == "mip" and not self._needs_depth():
            return self._with_readout(MIPVolumeMapper.PIECES)
        swap = {"float_readout": "demip_readout"}
        if projection == "lmip":
            swap["demip_hooks"] = "demip_lmip_hooks"
        elif projection == "attenuated":
            swap["demip_hooks"] = "demip_attenuated_hooks"
        elif projection == "mida":
            swap.update(demip_hooks="demip_mida_hooks", demip_color="demip_mida_color")
        return tuple(swap.get(n, n) for n in self._with_readout(self.PIECES))

    def _needs_depth(self) -> bool:
        """Whether anything uses the depth: a weight above 0, or a depth readout rendering."""
        settings = self._settings()
        reading_depth = settings["readout"] == "depth" and bool(object_state(self).get("exact_readout"))
        return reading_depth or any(settings[name] > 0.0 for name in (
            "depth_weight", "sphere_weight", "chroma_depth_weight"))

    def _window(self) -> tuple:
        """Normalised (floor, ceiling) of the attached volume's transfer functions.

        Without a window (constant transfer functions) the floor is put above
        every value: no ray gets a DEMIP term.
        """
        image, volume = self.GetInput(), self.GetAttachedVolume()
        if image is None or volume is None or image.GetPointData().GetScalars() is None:
            return 0.0, 1.0
        ends = normalised_ends(volume.GetProperty(), image.GetPointData().GetScalars())
        return ends if ends is not None and ends[1] > ends[0] else (2.0, 3.0)

    def _push_uniforms(self, uniforms) -> None:
        settings = self._settings()
        floor, ceiling = self._window()
        front, back = settings["sphere_colors"]
        uniforms.SetUniformf("u_mc_floor", floor)
        uniforms.SetUniformf("u_mc_ceiling", ceiling)
        uniforms.SetUniformf("u_mc_floorTolerance", FLOOR_TOLERANCE)
        same = settings["depth_of"] == "same_material"
        uniforms.SetUniformf("u_mc_materialThreshold", settings["material_threshold"] if same else 0.0)
        lmip = settings["projection"] == "lmip"
        uniforms.SetUniformf("u_mc_localThreshold",
                             floor + settings["local_threshold"] * (ceiling - floor) if lmip else 1.0e30)
        uniforms.SetUniformf("u_mc_attenuation", settings["attenuation"])
        uniforms.SetUniformf("u_mc_chromaWeight", settings["chroma_depth_weight"])
        uniforms.SetUniformf("u_mc_needDepth", 1.0 if self._needs_depth() else 0.0)
        uniforms.SetUniformf("u_mc_depthWeight", settings["depth_weight"])
        uniforms.SetUniformf("u_mc_sphereWeight", settings["sphere_weight"])
        uniforms.SetUniformf("u_mc_readDepth", 1.0 if settings["readout"] == "depth" else 0.0)
        uniforms.SetUniformi("u_mc_depthMode", DEPTH_MODES.index(settings["depth_mode"]))
        uniforms.SetUniform3f("u_mc_sphereFront", list(front))
        uniforms.SetUniform3f("u_mc_sphereBack", list(back))
        uniforms.SetUniform3f("u_mc_sphereAxis", [row[2] for row in settings["sphere_orientation"]])


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
