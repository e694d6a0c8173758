"""The base mipcast mapper: VTK's GPU ray caster running mipcast's own ray loop."""
from __future__ import annotations

import numbers

from vtkmodules.vtkCommonCore import vtkCommand, vtkOutputWindow, vtkWeakReference
from vtkmodules.vtkRenderingCore import vtkVolume
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.core import parameter_tables
from mipcast.core.camera_rays import grazing_sine, near_cap, placed
from mipcast.core.object_state import object_state
from mipcast.core.errors import InputError
from mipcast.core.parameters import defaults, parameter_accessors, uniform_values
from mipcast.core.prepare import prepare_scalars, scalar_image
from mipcast.core.transfer_bounds import normalised_ends
from mipcast.core.validation import samples_per_ray_problem
from mipcast.mappers import brick_rays, bricked_draw, clip_uniforms, shader_pieces
from mipcast.mappers.float_readout import from_data_units, table_coordinate
from mipcast.mappers.input_preparer import InputPreparer
from mipcast.mappers.max_blocks import block_bytes, block_level_image
from mipcast.mappers.private_draw import rendering_renderer, scissor_from_origin
from mipcast.mappers.stereo import drawing_camera, drawing_multisamples, eye_uniforms


#: The pieces every mipcast mapper adds to its own: ray directions along the pixel's line through the
#: frustum (perspective, mono or a stereo eye), and along a parallel stereo eye's sheared direction.
PERSPECTIVE_PIECE = "perspective_ray_direction"
STEREO_PIECE = "stereo_ray_direction"
#: And, while a face of the volume's box is seen within EDGE_ON (a sine) of edge-on, the piece that sets a
#: ray up again along its pixel's line where VTK's fragment on the face's rasterised sliver lies off the box
#: (shaders/ray_mend.glsl: a front view of a volume turned about the view axis). A sweep of 30 turns about the
#: view axis, the view tilted 0 to 3 degrees (``python tests/edge_on_check.py sweep``), found such rays up to a
#: sine of 0.012 (1 degree), 56 to 147 times the data range off up to a sine of 1.2e-6, 0.026 at most from
#: there to 1.2e-5, 0.055 beyond. Installed up to a sine of 1e-4: a camera turned at random comes that near a
#: face once in ~3000 moves, each time installing the piece binds another program (compiled the first time),
#: and llvmpipe runs a branch's body on every lane, so installing it in every view cost 5-12 % of a frame.
#: Further off edge-on (a sine up to ~0.02) VTK's fragment still lies on the pixel's line, only too deep into
#: the box or in front of it: there every ray loop moves its start to the line's entry (shaders/mip_globals.glsl,
#: ``mcEntryShift``; :meth:`MIPVolumeMapper._entry_moves`), no piece needed.
RAY_MEND_PIECE = "ray_mend"
EDGE_ON = 1.0e-4
#: The grazing sine below which the ray loops move a start that VTK's rasterisation put off where its line
#: enters the box (:meth:`MIPVolumeMapper._entry_moves`): the largest seen moving, 0.016 (2 degrees; the
#: start's error grows as 1 / sine); above, the test is left out (it cost analytic MIP 4-7 % of a frame).
ENTRY_MOVES = 0.1
#: The sampled hook pieces that skip blocks, and their skipping variants (MIP's, MinIP's, DEMIP's).
_BLOCK_HOOKS = {"mip_hooks": "mip_hooks_blocks", "minip_hooks": "minip_hooks_blocks",
                "demip_hooks": "demip_hooks_blocks"}
_BLOCK_PIECES = frozenset(_BLOCK_HOOKS.values())


@parameter_accessors
class MIPVolumeMapper(vtkOpenGLGPUVolumeRayCastMapper):
    """Sampled maximum intensity projection through mipcast's shader pieces.

    A drop-in for ``vtkGPUVolumeRayCastMapper`` in MIP mode: input, sample
    distance, auto-adjust, image sample distance, the volume property's
    transfer functions and interpolation, and the image's spacing, origin and
    direction matrix all behave as they do there, with the same samples as
    stock VTK (sample ``i`` at ``entry + i * step``) in a faster, counted loop.
    VTK keeps shader code on the ``vtkVolume``, so the mapper must be attached
    to its volume with :meth:`Attach` (which also calls ``volume.SetMapper``).
    Rendering an unattached mipcast mapper, or one whose input is unusable (see
    :func:`mipcast.core.validation.check_image`), reports a VTK error event naming the
    problem (also :meth:`GetLastProblem`) and draws nothing.  NaN/Inf voxels
    are drawn as missing data and several components as their magnitude (or
    :meth:`SetComponent`), by an input preparer inside the mapper
    (:mod:`mipcast.mappers.input_preparer`; docs/reliability.md).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from mipcast.data_fixtures import make_fixture
    >>> mapper = MIPVolumeMapper()
    >>> mapper.SetInputData(make_fixture("vessels", size=32))
    >>> volume = vtkVolume()
    >>> mapper.Attach(volume)
    >>> volume.GetMapper() is mapper
    True

    See docs/methods.md, section MIP: ``docs/methods.md#mip``.
    """

    #: Shader pieces this method installs (file names in ``shaders/``):
    #: ``sampled_loop`` is the one sampled ray loop, ``mip_hooks`` fills its
    #: hooks (see :func:`sampled_projection_mapper` for other projections).
    PIECES = ("mip_globals", "refusal", "sampled_loop", "mip_hooks", "no_stock_sample", "mip_color")
    #: The method's parameter table (:mod:`mipcast.core.parameter_tables`):
    #: subclasses get a ``SetX``/``GetX`` per entry (:func:`parameter_accessors`).
    PARAMETERS = parameter_tables.MIP
    #: Missing voxels (NaN/Inf) are drawn as missing data (docs/reliability.md);
    #: a projection that cannot draw them sets this False and refuses such input.
    DRAWS_MISSING = True
    #: Where the preparer fills missing voxels: ``"below"`` every finite value
    #: (maximum and average projections) or ``"above"`` (minimum projections).
    MISSING_FILL = "below"
    #: The piece that discards a ray which saw no finite data (installed only
    #: for input with missing values), or None where the hooks do it themselves.
    MISSING_PIECE = "missing_exit"
    #: How this method's ray values over bricks of one volume combine exactly: ``"max"``,
    #: ``"min"``, or None (it cannot). A volume beyond the 3D texture limit is drawn in
    #: bricks inside the render by methods that can, refused by the others
    #: (:mod:`mipcast.mappers.bricked_draw`).
    BRICKS = "max"
    #: A brick's readout piece when the bricks combine by their mean (``BRICKS`` "mean"), else None.
    BRICK_READOUT = None

    #: What the skipping blocks bound (:mod:`mipcast.mappers.max_blocks`): ``"max"`` (maximum
    #: projections: block maxima, skipping with a transfer-function floor), ``"min"`` (minimum
    #: projections: block minima, with a ceiling), or None (no block skipping).
    BLOCK_EXTREME = "max"
    #: Cells per edge of a skipping block: the block level, in VTK's mask slot, is 1/BLOCK^3 the volume.
    BLOCK = 8
    #: Points a block's maximum reaches past its cells.  A sample on a block's face may be read from
    #: the neighbouring cell (rounding in its position or in the texture unit), so sampled rays need
    #: 1; the exact cell walk knows its cell and needs 0.
    BLOCK_MARGIN = 1

    def __init__(self) -> None:
        super().__init__()
        self.SetBlendModeToMaximumIntensity()
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _check_before_render)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, _restore_after_refused_render)
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _reduced_buffer_scissor)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, _restore_scissor)
        # after the check (priority 0), before the foveated levels (-1)
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, bricked_draw.draw_bricks, -0.5)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, bricked_draw.restore_own_draw, -0.5)

    # -- input: the user's image goes through the preparer -----------------
    def SetInputData(self, *args) -> None:
        """Render this vtkImageData (``SetInputData(image)`` or ``SetInputData(0, image)``).

        The image is never modified: the GPU draws a prepared copy where the
        values need it (several components, NaN/Inf, int64; see
        :mod:`mipcast.core.prepare`), the image itself otherwise.
        """
        image = args[-1]
        preparer = self.GetInputPreparer()
        if image is None:
            preparer.RemoveAllInputConnections(0)
            vtkOpenGLGPUVolumeRayCastMapper.RemoveAllInputConnections(self, 0)
            return
        preparer.SetInputDataObject(0, image)
        self._route_input()

    def SetInputConnection(self, *args) -> None:
        """Render the output of an algorithm port (``SetInputConnection(port)`` or ``(0, port)``)."""
        port = args[-1]
        preparer = self.GetInputPreparer()
        if port is None:
            preparer.RemoveAllInputConnections(0)
            vtkOpenGLGPUVolumeRayCastMapper.RemoveAllInputConnections(self, 0)
            return
        preparer.SetInputConnection(0, port)
        self._route_input()

    def GetInput(self):
        """Your input image (not the prepared copy the GPU may draw), or None.

        An image with cell scalars and no point scalars: the image of its cell
        centres carrying them (:func:`mipcast.core.prepare.cell_centres`, no
        value copied; the same object while your image is unchanged), whose
        geometry the drawing follows.
        """
        self._adopt_direct_input()
        preparer = self.GetInputPreparer()
        if preparer.GetNumberOfInputConnections(0) == 0:
            return None
        return _cell_centres_of(self, preparer.GetInputDataObject(0, 0))

    def GetInputPreparer(self) -> InputPreparer:
        """The filter between your input and VTK (:class:`~mipcast.mappers.input_preparer.InputPreparer`)."""
        state = object_state(self)  # made on first use: a mapper never given input keeps no state
        if "preparer" not in state:
            state["preparer"] = InputPreparer(type(self).MISSING_FILL)
        return state["preparer"]

    def GetRenderedInput(self):
        """The one-component image the GPU draws (brought up to date), or None without input."""
        preparer = self.GetInputPreparer()
        if preparer.GetNumberOfInputConnections(0) == 0:
            return None
        preparer.SetMask(self.GetMaskInput())  # (a mask modified since it was set is read again)
        preparer.Update()
        return preparer.GetOutputDataObject(0)

    def SetBlendMode(self, mode: int) -> None:
        """Fixed: VTK's maximum-intensity blend, in whose shader template every mipcast method (MIP, MinIP,
        average, DEMIP, ...) puts its own ray loop; any other mode is a ``ValueError`` naming what to use.

        Until 2026-12-04 another mode was taken: composite, isosurface and minimum drew the method's picture
        anyway, additive the whole box lit (VTK's additive template around mipcast's loop).
        """
        if mode != vtkOpenGLGPUVolumeRayCastMapper.MAXIMUM_INTENSITY_BLEND:
            raise ValueError(_blend_mode_refusal(self, mode))
        vtkOpenGLGPUVolumeRayCastMapper.SetBlendMode(self, mode)

    def SetBlendModeToComposite(self) -> None:
        """Refused (:meth:`SetBlendMode`)."""
        self.SetBlendMode(vtkOpenGLGPUVolumeRayCastMapper.COMPOSITE_BLEND)

    def SetBlendModeToMinimumIntensity(self) -> None:
        """Refused (:meth:`SetBlendMode`)."""
        self.SetBlendMode(vtkOpenGLGPUVolumeRayCastMapper.MINIMUM_INTENSITY_BLEND)

    def SetBlendModeToAverageIntensity(self) -> None:
        """Refused (:meth:`SetBlendMode`)."""
        self.SetBlendMode(vtkOpenGLGPUVolumeRayCastMapper.AVERAGE_INTENSITY_BLEND)

    def SetBlendModeToAdditive(self) -> None:
        """Refused (:meth:`SetBlendMode`)."""
        self.SetBlendMode(vtkOpenGLGPUVolumeRayCastMapper.ADDITIVE_BLEND)

    def SetBlendModeToIsoSurface(self) -> None:
        """Refused (:meth:`SetBlendMode`)."""
        self.SetBlendMode(vtkOpenGLGPUVolumeRayCastMapper.ISOSURFACE_BLEND)

    def SetBlendModeToSlice(self) -> None:
        """Refused (:meth:`SetBlendMode`)."""
        self.SetBlendMode(vtkOpenGLGPUVolumeRayCastMapper.SLICE_BLEND)

    def SetMaskInput(self, mask) -> None:
        """A binary mask (``vtkImageData`` of the volume's dimensions), or None: VTK's ``SetMaskInput``.

        Points where the mask's scalars are 0 or less are missing data in
        every method (never the maximum or minimum, left out of the averages;
        a ray through masked points only shows what lies behind), exactly,
        as VTK's own binary masks leave out the samples where the mask is not
        above 0 (CT angiography's bone removal: a mask of what is kept).  The
        mask is read again when it is modified.  VTK's mask slot itself holds
        the mapper's block level (block skipping); label-map masks are refused
        (:meth:`SetMaskType`).  Beyond the 3D texture limit the bricks carry
        the hidden points too.

        Examples
        --------
        >>> import numpy as np
        >>> from vtkmodules.util.numpy_support import numpy_to_vtk
        >>> from vtkmodules.vtkCommonDataModel import vtkImageData
        >>> mask = vtkImageData()
        >>> mask.SetDimensions(8, 8, 8)
        >>> _ = mask.GetPointData().SetScalars(numpy_to_vtk(np.ones(512, np.uint8), deep=True))
        >>> mapper = MIPVolumeMapper()
        >>> mapper.SetMaskInput(mask)
        >>> mapper.GetMaskInput() is mask
        True
        """
        if mask is not None and not (hasattr(mask, "IsA") and mask.IsA("vtkImageData")):
            raise TypeError(f"SetMaskInput takes a vtkImageData (or None), got {type(mask).__name__}")
        object_state(self)["user_mask"] = mask
        self.GetInputPreparer().SetMask(mask)
        self.Modified()

    def _masked_input(self):
        """Your input with the mask's hidden points (the preparer's masked copy,
        :meth:`~mipcast.mappers.input_preparer.InputPreparer.GetMasked`), or your input itself without a mask
        (or when the mask is refused: the render is refused then)."""
        image = self.GetInput()
        if image is None or self.GetMaskInput() is None:
            return image
        self.GetRenderedInput()  # the preparer (and its masked copy) up to date
        masked_copy = self.GetInputPreparer().GetMasked()
        return image if masked_copy is None else masked_copy

    def GetMaskInput(self):
        """The mask :meth:`SetMaskInput` set, or None (VTK's mask slot holds the block level)."""
        return object_state(self).get("user_mask")

    def SetMaskType(self, mask_type) -> None:
        """Binary only (``vtkGPUVolumeRayCastMapper.BinaryMaskType``): a label map colours samples by label,
        which a projection of one value along each ray has no use for; ``TypeError`` otherwise."""
        if mask_type != vtkOpenGLGPUVolumeRayCastMapper.BinaryMaskType:
            raise TypeError("mipcast's methods draw binary masks only (SetMaskTypeToBinary: points where the "
                            "mask is 0 are missing data); a label map colours samples by label, which a "
                            "projection keeping one value per ray cannot show")
        vtkOpenGLGPUVolumeRayCastMapper.SetMaskType(self, mask_type)

    def SetMaskTypeToLabelMap(self) -> None:
        """Refused: see :meth:`SetMaskType`."""
        self.SetMaskType(vtkOpenGLGPUVolumeRayCastMapper.LabelMapMaskType)

    def SetComponent(self, component) -> None:
        """Which component of multi-component scalars to draw: an int >= 0, or -1 / "magnitude" (default).

        The same in every method; one-component scalars are drawn as they are.
        """
        self.GetInputPreparer().SetComponent(component)
        self.Modified()

    def GetComponent(self) -> int:
        """The drawn component, -1 for the magnitude (the default)."""
        return self.GetInputPreparer().GetComponent()

    def _prepared_port(self):
        """Your input's own port when the GPU can draw it as it is, else the preparer's output.

        Valid finite one-component input therefore reaches VTK exactly as
        before (same pipeline, same requests, e.g. ParaView's time steps);
        input that needs a copy, or is refused, goes through the preparer
        (a refused input reaches VTK as the preparer's 2x2x2 stand-in).
        """
        preparer = self.GetInputPreparer()
        preparer.SetMask(self.GetMaskInput())
        preparer.Update()
        prepared = preparer.GetPrepared()
        if prepared is not None and not prepared.changed and not prepared.cells:
            return preparer.GetInputConnection(0, 0)
        return preparer.GetOutputPort()

    def _vtk_port(self):
        """The port VTK's own input connection should read (subclasses add filters)."""
        return self._prepared_port()

    def _own_ports(self) -> list:
        """Ports this mapper itself may connect VTK to."""
        preparer = self.GetInputPreparer()
        ports = [preparer.GetOutputPort()]
        if preparer.GetNumberOfInputConnections(0):
            ports.append(preparer.GetInputConnection(0, 0))
        return ports

    def _route_input(self) -> None:
        """Connect VTK to :meth:`_vtk_port` (only when that changes)."""
        if self.GetInputPreparer().GetNumberOfInputConnections(0) == 0:
            return
        port = self._vtk_port()
        if vtkOpenGLGPUVolumeRayCastMapper.GetNumberOfInputConnections(self, 0):
            current = vtkOpenGLGPUVolumeRayCastMapper.GetInputConnection(self, 0, 0)
            if same_port(current, port):
                return
        vtkOpenGLGPUVolumeRayCastMapper.SetInputConnection(self, port)

    def _adopt_direct_input(self) -> None:
        """Input set on VTK directly (from C++): move it in front of the preparer."""
        if not vtkOpenGLGPUVolumeRayCastMapper.GetNumberOfInputConnections(self, 0):
            return
        current = vtkOpenGLGPUVolumeRayCastMapper.GetInputConnection(self, 0, 0)
        if any(same_port(current, port) for port in self._own_ports()) or current.GetProducer() is None:
            return
        self.GetInputPreparer().SetInputConnection(0, current)
        self._route_input()

    def _missing_below(self):
        """Normalised threshold beyond which a ray saw only missing data, or None (nothing missing).

        Below it for fills below the data (``MISSING_FILL = "below"``), above it for fills above.
        """
        preparer = self.GetInputPreparer()
        prepared = preparer.GetPrepared()
        if prepared is None or not prepared.missing:
            return None
        threshold = prepared.missing_below if type(self).MISSING_FILL == "below" else prepared.missing_above
        whole = object_state(self).get("global_normalisation")
        if whole is not None:  # a brick of mipcast.distributed: samples normalised over the whole range (data units)
            return float(threshold * whole[0] + whole[1])
        scalars = preparer.GetOutputDataObject(0).GetPointData().GetScalars()
        return float(from_data_units(threshold, scalars))

    def GetDepthImage(self, image) -> None:
        """VTK's depth image; during a float readout of a bricked volume, the bricks' combined values."""
        if not bricked_draw.fill_depth_image(self, image):
            super().GetDepthImage(image)

    def GetNumberOfBricks(self) -> int:
        """Bricks the last frame drew (0: the volume fits one 3D texture; see :mod:`mipcast.mappers.bricked_draw`)."""
        if not bricked_draw.bricking_limit(self):
            return 0
        return object_state(self).get("bricks_drawn", 0)

    def _texture_limit(self) -> int:
        """GL_MAX_3D_TEXTURE_SIZE of the window drawing the attached volume (0 if unknown)."""
        return bricked_draw.texture_limit(self)

    def GetLastProblem(self):
        """Why the last render drew nothing (the message of its VTK error event), or None."""
        return object_state(self).get("render_problem")

    # -- attachment ---------------------------------------------------------
    def SetPartitions(self, x: int, y: int, z: int) -> None:
        """VTK's partitioned rendering, recorded (:meth:`_partitioned`) for the methods that refuse it.

        Raises ``ValueError`` unless three integers >= 1 (VTK's own setter wraps others silently).
        """
        values = (x, y, z)
        if not all(isinstance(v, numbers.Real) and not isinstance(v, bool) and float(v).is_integer() and v >= 1
                   for v in values):
            raise ValueError(f"partitions must be three integers >= 1, got {values}")
        parts = tuple(int(v) for v in values)
        object_state(self)["partitions"] = parts
        super().SetPartitions(*parts)

    def _partitioned(self) -> bool:
        """Whether :meth:`SetPartitions` asked for more than one partition."""
        return object_state(self).get("partitions", (1, 1, 1)) != (1, 1, 1)

    def Attach(self, volume: vtkVolume) -> None:
        """Install this method's shader pieces on ``volume`` and set its mapper.

        Parameters
        ----------
        volume : vtkVolume
            The volume to render.  Its shader property receives mipcast's
            pieces; replacements other code put on the same tags are refused.
        """
        if not isinstance(volume, vtkVolume):
            raise TypeError(f"Attach needs a vtkVolume, got {type(volume).__name__}")
        previous = self.GetAttachedVolume()
        if previous is not None and previous is not volume:
            self.Detach()
        self._install_pieces(volume)
        volume.GetShaderProperty().GetFragmentCustomUniforms().SetUniformf("u_mc_refused", 0.0)
        volume.GetShaderProperty().GetFragmentCustomUniforms().SetUniformf("u_mc_entryMoves", 0.0)
        volume.GetShaderProperty().GetFragmentCustomUniforms().SetUniform2f("u_mc_tableScale", [1.0, 0.0])
        clip_uniforms.push(volume.GetShaderProperty().GetFragmentCustomUniforms(), ())
        clip_uniforms.push_slab(volume.GetShaderProperty().GetFragmentCustomUniforms(), clip_uniforms.NO_SLAB)
        link = vtkWeakReference()  # a C++ weak pointer: Python wrappers come and go
        link.Set(volume)
        object_state(self)["volume"] = link
        volume.SetMapper(self)
        self._push_uniforms(volume.GetShaderProperty().GetFragmentCustomUniforms())
        self.Modified()

    def GetShaderPieces(self) -> tuple:
        """Names of the shader pieces (files in ``shaders/``) the mapper needs now.

        :data:`PIECES`, plus ``float_readout`` while
        :func:`mipcast.mappers.float_readout.render_float` renders (which also swaps
        ``refusal`` for ``image_terminate``: VTK's render-to-image reads the
        scene depth at the wrong pixels in renderers that do not start at
        the window's corner).  Subclasses whose
        pieces depend on their settings override this; the pieces are
        re-installed at the next render when the answer changes.
        """
        return self._with_blocks(self._with_missing(self._with_readout(self.PIECES)))

    def _with_blocks(self, names) -> tuple:
        """``names`` with their hook piece's block-skipping variant (``_BLOCK_HOOKS``: MIP's, MinIP's,
        DEMIP's) while :meth:`_skips_blocks`; hook pieces without one (LMIP's, ...) stay."""
        names = tuple(names)
        if not any(n in _BLOCK_HOOKS for n in names) or not self._skips_blocks():
            return names
        return tuple(_BLOCK_HOOKS.get(n, n) for n in names)

    def _skips_blocks(self) -> bool:
        """Whether a hook piece with a skipping variant skips blocks now (the block level in the mask slot).

        Skipping on, a window that leaves blocks to skip
        (:meth:`_window_bounds_blocks`), and one texture (not a brick of a
        distributed volume, whose samples are read by hand, nor drawn in
        bricks).  Missing values do not matter: the hooks tell a ray that met
        missing data only themselves (shaders/mip_hooks_blocks.glsl).
        """
        if not self._parameters().get("skipping", False) or object_state(self).get("global_box") is not None:
            return False
        return self._window_bounds_blocks() and not bricked_draw.bricking_limit(self)

    def _samples_rays(self) -> bool:
        """Whether this method samples its rays at the sample distance (not a cell walk)."""
        return "sampled_loop" in type(self).PIECES

    def _draws_blocks(self, names=None) -> bool:
        """Whether the pieces ``names`` (default: :meth:`GetShaderPieces`) skip blocks."""
        return not _BLOCK_PIECES.isdisjoint(self.GetShaderPieces() if names is None else names)

    def _window_bounds_blocks(self) -> bool:
        """Whether the transfer functions are constant beyond a bound most blocks lie past from the
        start: a floor above the data minimum (a window above the background, :data:`BLOCK_EXTREME`
        "max") or a ceiling below the data maximum ("min").  Without one a block's check costs more
        than it saves."""
        floor, ceiling = self._transfer_floor_ceiling()
        if self.BLOCK_EXTREME == "max":
            return floor > 0.0
        return self.BLOCK_EXTREME == "min" and ceiling < 1.0

    def _transfer_floor_ceiling(self) -> tuple:
        """Normalised (floor, ceiling) of the attached volume's transfer functions (:mod:`mipcast.core.transfer_bounds`)."""
        image, volume = self.GetRenderedInput(), self.GetAttachedVolume()
        if image is None or volume is None or image.GetPointData().GetScalars() is None:
            return 0.0, 1.0
        return normalised_ends(volume.GetProperty(), image.GetPointData().GetScalars()) or (0.0, 1.0)

    def _push_skipping(self, uniforms, skipping: bool) -> None:
        """The floor, ceiling and block uniforms of the skipping loops, and the block maxima (once per input).

        The float readout is exact in data units (floor and ceiling off).  With missing values rays still
        start at the fill side's bound (a MIP's floor, a MinIP's ceiling): the hooks keep whether a ray has
        met finite data apart from its running value, so a ray that met missing data only ends beyond the
        missing threshold and draws nothing whatever the transfer functions are at that bound
        (shaders/mip_hooks_blocks.glsl, amip_max_hooks.glsl and their mirrors).  Until 2026-12-04 the bound
        was given up there unless the opacity was 0 at it, and the plain loop drawn (a padded head CT under
        an opaque grey, analytic at 512^2: 286 ms a frame against 177 with blocks; docs/methods.md).
        """
        image = self.GetRenderedInput()
        dims = image.GetDimensions() if image is not None else (2, 2, 2)
        uniforms.SetUniform3f("u_mc_dims", [float(n) for n in dims])
        uniforms.SetUniformf("u_mc_blockSize", float(self.BLOCK))
        floor, ceiling = self._transfer_floor_ceiling()
        state = object_state(self)
        # counting work (mipcast.mappers.amip_stats) keeps the display's shortcuts
        exact = (state.get("exact_readout", False) and state.get("stat") is None) or not skipping
        uniforms.SetUniformf("u_mc_skipFloor", -1.0e30 if exact else floor)
        uniforms.SetUniformf("u_mc_skipCeiling", 1.0e30 if exact else ceiling)
        if image is not None and image.GetNumberOfPoints() > 0 and not bricked_draw.bricking_limit(self):
            self._update_block_level(image)  # (drawn in bricks: each brick has its own)

    def _update_block_level(self, image) -> None:
        """(Re)build the block level (maxima or minima, :data:`BLOCK_EXTREME`) when the input changed;
        it rides in the mask slot."""
        state = object_state(self)
        stamp = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime())
        if self.BLOCK_EXTREME is None or state.get("blocks_of") == stamp:
            return
        low, high = image.GetPointData().GetScalars().GetRange(0)
        values = prepare_scalars(image).values  # the prepared copy: validated already
        vtkOpenGLGPUVolumeRayCastMapper.SetMaskInput(self, block_level_image(
            values, self.BLOCK, low, high, margin=self.BLOCK_MARGIN, extreme=self.BLOCK_EXTREME))
        self.SetMaskTypeToBinary()
        state["blocks_of"] = stamp

    def _with_missing(self, names) -> tuple:
        """``names`` plus :attr:`MISSING_PIECE` while the input holds missing values."""
        if self._missing_below() is None or type(self).MISSING_PIECE is None:
            return tuple(names)
        return tuple(names) + (type(self).MISSING_PIECE,)

    def _with_readout(self, names) -> tuple:
        """``names``, adapted for a float readout while one renders (else unchanged).

        A brick of a distributed volume (``global_box`` in the mapper's state,
        set by :mod:`mipcast.distributed`) also gets ``global_phase``: the
        sampled loop then takes the whole volume's sample positions; the
        exact projections' cell walk gets ``global_cells`` (the whole
        volume's ray, walked over the brick's cells; ``global_cells`` False
        in the state keeps the plain walk, which ends at opaque geometry), and, rendering to
        image, ``whole_ray_end`` (its ray ends at opaque geometry where the whole volume's
        ray ends, counted from the whole box's entry as VTK counts it).  Both read the
        whole volume's rays from uniforms (:func:`mipcast.distributed.set_brick_uniforms`,
        :func:`mipcast.distributed.ray_uniforms`).
        ``depth_composite`` in the state (``"max"`` or ``"min"``, set by
        ParaView's mipcast representation on the ranks of a parallel render
        view) adds the piece that writes the ray's value as the fragment's
        depth, for IceT's Z-buffer compositing.
        """
        state = object_state(self)
        if state.get("global_box") is not None and "sampled_loop" in names:
            names = tuple(names) + ("global_phase",)
        elif state.get("global_box") is not None and state.get("global_cells", True) and "amip_cell" in names:
            names = tuple(names) + ("global_cells",)
        if not state.get("exact_readout"):
            composite = state.get("depth_composite")  # a rank's piece in a parallel render view (plugin/representation)
            if composite:
                names = tuple(names) + ("depth_composite_min" if composite == "min" else "depth_composite",)
            return tuple(names)
        # rendering to image: VTK's ray set-up with the viewport-offset fix (it also refuses)
        # a brick of a mapper drawn in bricks by the mean (mipcast.mappers.bricked_draw): its readout
        # piece writes the mean, its weight, ... as u_mc_brickChannel says
        readout = type(self).BRICK_READOUT if state.get("brick_mean") else None
        names = tuple("image_terminate" if n == "refusal" else n for n in names) + (readout or "float_readout",)
        if state.get("global_box") is not None and set(names) & {"image_terminate", "demip_brick_fetch",
                                                                  "demip_brick_state_fetch"}:
            names += ("whole_ray_end",)  # a brick's ray ends where the whole volume's does (opaque geometry)
        return names

    def _install_pieces(self, volume) -> None:
        names = self._pieces_now(volume)
        # every method: VTK's clipping set-up off, mipcast's loops clip (clip_uniforms)
        shader_pieces.install(volume.GetShaderProperty(),
                              [shader_pieces.load_piece(n) for n in names + ("clipping_off",)])
        object_state(self)["installed"] = names

    def _draws_reduced(self) -> bool:
        """Whether a render may use VTK's reduced buffer (image sample distance above 1, or auto-adjusted):
        then it draws in a scissor box from the window's origin (:func:`_reduced_buffer_scissor`)."""
        return bool(self.GetAutoAdjustSampleDistances()) or self.GetImageSampleDistance() > 1.0

    def _pieces_now(self, volume) -> tuple:
        """:meth:`GetShaderPieces`, plus ``perspective_ray_direction`` under a perspective camera (mono or
        a stereo eye), the stereo piece while an eye of a parallel stereo pair renders, ``ray_mend`` while
        a face of the volume's box is seen (nearly) edge-on (:data:`EDGE_ON`), and
        ``clip_active`` while something clips (planes, cropping, a slab); ``clip_regions`` instead
        while it crops with region flags other than the sub-volume."""
        names = tuple(self.GetShaderPieces())
        if self._clips():
            names += ("clip_regions" if clip_uniforms.crops_regions(self) else "clip_active",)
        camera = drawing_camera(self, volume)
        if camera is None:
            return names
        if self._box_view(camera, volume)[0] < EDGE_ON:
            names += (RAY_MEND_PIECE,)
        if not camera.GetParallelProjection():
            return names + (PERSPECTIVE_PIECE,)  # (a stereo eye's too: its sheared frustum's pixel lines)
        return names + (STEREO_PIECE,) if camera.GetStereo() else names  # (eye_uniforms' parallel eyes)

    def _box_view(self, camera, volume) -> tuple:
        """(:func:`mipcast.core.camera_rays.grazing_sine`, whether ``camera``'s near plane cuts the box:
        :func:`mipcast.core.camera_rays.near_cap`) of the input's box drawn by ``volume`` ((1.0, False) without
        input), kept until the camera, the volume or the input change (it is asked every render)."""
        image = self.GetInput()
        if image is None:
            return 1.0, False
        matrix = volume.GetMatrix()
        key = (id(camera), camera.GetMTime(), matrix.GetMTime(), id(image), image.GetMTime())
        state = object_state(self)
        if state.get("box_view", (None,))[0] != key:
            state["box_view"] = (key, (grazing_sine(image, camera, matrix),
                                       near_cap(placed(image, matrix), camera) is not None))
        return state["box_view"][1]

    def _entry_moves(self, volume) -> float:
        """Which starts off where their line enters the box the ray loops move to that entry
        (``u_mc_entryMoves``, ``mcEntryShift`` in shaders/mip_globals.glsl): 2.0, those behind it and those
        in front; 1.0, those behind only, while the window draws with MSAA (VTK starts a silhouette pixel
        off the box, in front of it, on purpose); 0.0, none, while the camera's near plane cuts the box (VTK
        starts those rays on its cap, inside the box), no face is met at a sine below :data:`ENTRY_MOVES`
        or no camera is known."""
        camera = drawing_camera(self, volume)
        if camera is None:
            return 0.0
        sine, capped = self._box_view(camera, volume)
        if capped or sine >= ENTRY_MOVES:
            return 0.0
        return 1.0 if drawing_multisamples(self, volume) > 0 else 2.0

    def _clips(self) -> bool:
        """Clipping planes, cropping or a slab: the loops then narrow each ray (``clip_active``)."""
        planes = self.GetClippingPlanes()
        return bool(self._slab_settings()[0] or self.GetCropping()
                    or (planes is not None and planes.GetNumberOfItems() > 0))

    def Detach(self) -> None:
        """Remove mipcast's pieces from the attached volume (if any)."""
        volume = self.GetAttachedVolume()
        if volume is not None:
            shader_pieces.uninstall(volume.GetShaderProperty())
        object_state(self).pop("volume", None)

    def NeedsRefinement(self) -> bool:
        """Whether a timer should render again to refine the picture (False: this method draws it at once).

        The foveated mapper with progressive refinement answers True while
        refining (:mod:`mipcast.mappers.refinement` drives it).
        """
        return False

    def GetAttachedVolume(self):
        """The volume given to :meth:`Attach`, or ``None``."""
        link = object_state(self).get("volume")
        return None if link is None else link.Get()

    def GetRenderProblem(self):
        """Why this mapper would refuse to render now, or ``None`` if it can.

        Checked at the start of every render: the mapper must be attached
        (:meth:`Attach`) and its input must pass
        :func:`mipcast.core.validation.check_image` (prepared once per input
        modification by the mapper's :class:`~mipcast.mappers.input_preparer.InputPreparer`).
        """
        if not self.IsAttached():
            return ("rendered without Attach(volume): its shader pieces are not on the "
                    "volume, so nothing is drawn. Call mapper.Attach(volume) instead of "
                    "volume.SetMapper(mapper).")
        self._adopt_direct_input()
        if self.GetNumberOfInputConnections(0) == 0:
            return "no input: call SetInputData(image) or SetInputConnection(port)"
        self._route_input()
        self.GetInputAlgorithm().Update()
        image = self.GetInput()
        if image is None:
            return "no input: call SetInputData(image) or SetInputConnection(port)"
        if self.GetBlendMode() != vtkOpenGLGPUVolumeRayCastMapper.MAXIMUM_INTENSITY_BLEND:  # set from C++
            return _blend_mode_refusal(self, self.GetBlendMode())
        clipping = clip_uniforms.clipping_problem(self)
        if clipping is not None:
            return clipping
        problem = self.GetInputPreparer().GetProblem()
        if problem is not None:
            return f"input refused, nothing is drawn: {problem}"
        too_large = bricked_draw.refusal(self) or brick_rays.jitter_problem(self)
        if too_large is not None:
            return too_large
        if self._samples_rays() and not (self.GetAutoAdjustSampleDistances()
                                         or self.GetLockSampleDistanceToInputSpacing()):
            dense = samples_per_ray_problem(image, self.GetSampleDistance())
            if dense is not None:
                return dense
        prepared = self.GetInputPreparer().GetPrepared()
        if not self.DRAWS_MISSING and prepared is not None and prepared.missing:
            return (f"input refused, nothing is drawn: {type(self).__name__} cannot draw missing values "
                    f"yet ({prepared.missing} NaN/Inf voxels; missing data is defined for maximum "
                    "projections only): replace them first, e.g. numpy.nan_to_num, or use a MIP method")
        return None

    # -- parameters (the table's values) ------------------------------------
    def _parameters(self) -> dict:
        state = object_state(self)
        if "parameters" not in state:
            state["parameters"] = defaults(type(self).PARAMETERS)
        return state["parameters"]

    def _get_parameter(self, name: str):
        return self._own_parameters(name)[name]

    def _set_parameter(self, name: str, value) -> None:
        """Store a checked value; its uniforms go up at the next render (nothing recompiles)."""
        self._own_parameters(name)[name] = value
        self.Modified()

    def _own_parameters(self, name: str) -> dict:
        """The parameter values, where ``name`` is one of this method's (a subclass inherits the
        accessors of MIP's table, e.g. ``SetSkipping``, whether or not its own table has them)."""
        parameters = self._parameters()
        if name not in parameters:
            own = ", ".join(sorted(parameters)) or "none"
            raise AttributeError(f"{type(self).__name__} has no parameter {name!r} (its parameters: {own}); "
                                 "see mipcast.core.parameters.method_parameters")
        return parameters

    def _push_uniforms(self, uniforms) -> None:
        """Write this method's custom uniforms (``u_mc_*``); called at Attach and every render.

        The table's uniforms (each parameter's :class:`~mipcast.core.parameters.Uniform`),
        then :meth:`_push_derived_uniforms`.
        """
        settings = dict(self._parameters(), **self._derived_settings())
        for name, (kind, value) in uniform_values(type(self).PARAMETERS, settings).items():
            if kind == "int":
                uniforms.SetUniformi(name, int(value))
            elif kind == "vec3":
                uniforms.SetUniform3f(name, list(value))
            else:
                uniforms.SetUniformf(name, float(value))
        self._push_derived_uniforms(uniforms, settings)
        if self._draws_blocks(object_state(self).get("installed", ())):  # the pieces drawn with
            self._push_skipping(uniforms, True)
        # the missing threshold (shaders/missing_exit.glsl; missing_exit_above.glsl for MISSING_FILL "above"),
        # also read by the skipping hooks, which take -/+1e30 for "nothing missing"
        missing = self._missing_below()
        below = type(self).MISSING_FILL == "below"
        uniforms.SetUniformf("u_mc_missingBelow" if below else "u_mc_missingAbove",
                             missing if missing is not None else (-1.0e30 if below else 1.0e30))
        uniforms.SetUniform2f("u_mc_tableScale", list(self._table_scale()))  # (shaders/mip_globals.glsl)

    def _table_scale(self) -> tuple:
        """(scale, bias) from the normalised scalar the shader draws to its place in the transfer-function
        tables (:func:`~mipcast.mappers.float_readout.table_coordinate`); (1, 0) for a brick of a
        distributed volume, whose samples are normalised over the whole range (and coloured on the CPU)."""
        if object_state(self).get("global_normalisation") is not None:
            return 1.0, 0.0
        image = self.GetInputPreparer().GetOutputDataObject(0)
        scalars = image.GetPointData().GetScalars() if image is not None else None
        return table_coordinate(scalars) if scalars is not None else (1.0, 0.0)

    def _slab_settings(self) -> tuple:
        """``(thickness, centre, normal)`` of the slab (the ``SLAB`` parameters; 0: none)."""
        params = self._parameters()
        return (params.get("slab_thickness", 0.0), params.get("slab_centre"), params.get("slab_normal"))

    def _push_clipping(self, volume) -> None:
        """Upload the planes this render clips with (clipping planes, cropping box, slab)."""
        thickness, centre, normal = self._slab_settings()
        uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
        if not self._clips():
            declared = volume.GetAddressAsString("vtkObjectBase")
            if object_state(self).get("clip_declared") == declared:
                uniforms.SetUniformi("u_mc_clipCount", 0)  # nothing clips: the rows stay as they are
                clip_uniforms.push_slab(uniforms, clip_uniforms.NO_SLAB)  # DEMIP's depth: over the box again
                return
            object_state(self)["clip_declared"] = declared  # the shader names every row: set them once
        camera = None
        if thickness:  # the camera: the slab may follow it, DEMIP's depth range needs it
            renderer = rendering_renderer(self, volume)
            camera = renderer.GetActiveCamera() if renderer is not None else object_state(self).get("clip_camera")
        rows = clip_uniforms.texture_rows(self, self.GetInput(), volume, camera)
        clip_uniforms.push(uniforms, rows)
        if clip_uniforms.crops_regions(self):
            clip_uniforms.push_crop(uniforms, clip_uniforms.crop_uniforms(self, self.GetInput()))
        clip_uniforms.push_slab(uniforms, clip_uniforms.slab_uniforms(self, self.GetInput(), volume, camera))

    def _derived_settings(self) -> dict:
        """Values besides the parameters that the table's uniforms depend on (e.g. the window)."""
        return {}

    def _push_derived_uniforms(self, uniforms, settings) -> None:
        """Uniforms that no single parameter drives (the window, readout flags, sizes)."""

    def GetTextureBytes(self) -> int:
        """Bytes of GPU texture this method uploads for its input (the 3D volume texture).

        Points x components x the uploaded component size
        (:func:`mipcast.mappers.gpu_limits.volume_texture_bytes`), plus the
        block maxima while MIP skips blocks (:meth:`SetSkipping`); the small
        transfer-function tables are not counted.  Subclasses add what their
        method uploads besides (analytic MIP's packed corners and block
        maxima, the foveated pyramid, two-pass DEMIP's first pass).

        Examples
        --------
        >>> from mipcast.data_fixtures import make_fixture
        >>> mapper = MIPVolumeMapper()
        >>> mapper.SetInputData(make_fixture("spheres", size=16))
        >>> mapper.GetTextureBytes()
        16384
        """
        from mipcast.mappers.gpu_limits import volume_texture_bytes

        image = self.GetInput()
        blocks = block_bytes(image.GetDimensions(), self.BLOCK) if image is not None and self._draws_blocks() else 0
        return volume_texture_bytes(image) + blocks

    def IsAttached(self) -> bool:
        """True when the attached volume uses this mapper and still carries its pieces."""
        volume = self.GetAttachedVolume()
        if volume is None or volume.GetMapper() is not self:
            return False
        state = object_state(self)
        names = state.get("installed", ())
        # the replacements are read again only after the shader property changed (adding or
        # clearing one modifies it; the uniforms pushed at every frame do not)
        shader_property = volume.GetShaderProperty()
        stamp = (shader_property.GetAddressAsString("vtkObjectBase"), shader_property.GetMTime(), names)
        if state.get("attached_stamp") == stamp:
            return True
        wanted = {shader_pieces.load_piece(n).vtk_tag for n in names}
        attached = wanted <= set(shader_pieces.installed_tags(shader_property))
        state["attached_stamp"] = stamp if attached else None
        return attached


def _cell_centres_of(mapper, image):
    """``image``, or for an image with cell scalars only its cell-centre image (one per image and MTime)."""
    if image is None or image.GetPointData().GetScalars() is not None or image.GetCellData().GetScalars() is None:
        return image
    key = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime())
    cached = object_state(mapper).get("cell_centres")
    if cached is None or cached[0] != key:
        try:
            cached = object_state(mapper)["cell_centres"] = (key, scalar_image(image))
        except InputError:
            return image  # refused with the reason by the preparer (GetRenderProblem)
    return cached[1]


def same_port(a, b) -> bool:
    """Whether two vtkAlgorithmOutput objects name the same output port.

    An algorithm keeps one vtkAlgorithmOutput per output port
    (``vtkAlgorithm::GetOutputPort``), which ``GetInputConnection`` returns,
    so the same port is the same object.  (Comparing producers wraps each
    in Python: tens of microseconds, at every frame.)
    """
    return a is b


def _reduced_buffer_scissor(mapper, event) -> None:
    """A render that may use VTK's reduced buffer (``_draws_reduced``) draws in a scissor box from the
    window's origin (:func:`mipcast.mappers.private_draw.scissor_from_origin`); the private draws inside it
    (foveation levels, bricks) inherit the box."""
    if not mapper._draws_reduced():
        return
    volume = mapper.GetAttachedVolume()
    renderer = rendering_renderer(mapper, volume) if volume is not None else None
    if renderer is not None and renderer.GetRenderWindow() is not None:
        object_state(mapper)["scissor_replaced"] = (renderer.GetRenderWindow(),
                                                    scissor_from_origin(renderer.GetRenderWindow()))


def _restore_scissor(mapper, event) -> None:
    window, box = object_state(mapper).pop("scissor_replaced", (None, None))
    if box is not None:
        window.GetState().vtkglScissor(*box)


def _check_before_render(mapper, event) -> None:
    """Bring pieces and uniforms up to date; refuse stock shaders or bad input.

    A refusal reports a VTK error naming the problem and draws nothing.
    """
    problem = mapper.GetRenderProblem()
    object_state(mapper)["render_problem"] = problem  # for later observers of the same render
    volume = mapper.GetAttachedVolume()
    if mapper.IsAttached():
        uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
        uniforms.SetUniformf("u_mc_refused", 0.0 if problem is None else 1.0)  # shaders/refusal.glsl
    if problem is None:
        if object_state(mapper).get("installed") != mapper._pieces_now(volume):
            mapper._install_pieces(volume)
        uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
        mapper._push_uniforms(uniforms)
        uniforms.SetUniformf("u_mc_entryMoves", mapper._entry_moves(volume))  # (mip_globals: mcEntryShift)
        eye = eye_uniforms(mapper, volume)
        if eye is not None:  # a parallel stereo eye's direction (shaders/stereo_ray_direction.glsl)
            uniforms.SetUniform3f("u_mc_eyeDirection", eye["u_mc_eyeDirection"])
        mapper._push_clipping(volume)
        return
    vtkOutputWindow.GetInstance().DisplayErrorText(f"{type(mapper).__name__}: {problem}\n")
    mapper.InvokeEvent(vtkCommand.ErrorEvent)
    # Keep VTK from touching the input at all: with cropping on and an empty
    # cropping box, vtkGPUVolumeRayCastMapper::ValidateRender silently skips
    # the render before it reads the input.  (Letting VTK draw refused input
    # with the refusal piece discarding every fragment is not enough: VTK 9.7
    # itself segfaults when scalars go from one component to three, or
    # vanish, between two renders.)  Restored at VolumeMapperRenderEndEvent.
    object_state(mapper)["refused"] = (mapper.GetCropping(), mapper.GetCroppingRegionPlanes())
    mapper.SetCropping(True)
    mapper.SetCroppingRegionPlanes(0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


def _blend_mode_refusal(mapper, mode: int) -> str:
    """Why ``mapper`` does not draw blend mode ``mode`` (:meth:`MIPVolumeMapper.SetBlendMode`)."""
    names = {getattr(vtkOpenGLGPUVolumeRayCastMapper, f"{n}_BLEND"): n.lower().replace("_", " ")
             for n in ("COMPOSITE", "MAXIMUM_INTENSITY", "MINIMUM_INTENSITY", "AVERAGE_INTENSITY", "ADDITIVE",
                       "ISOSURFACE", "SLICE")}
    return (f"{type(mapper).__name__} draws its own projection in VTK's maximum-intensity blend mode; blend "
            f"mode {names.get(mode, mode)!r} is not one of its settings: for MinIP or an average use "
            "mipcast.create_mapper('minip' / 'analytic_minip' / 'average' / 'analytic_average'), for "
            "composite, additive, isosurface or slice rendering VTK's vtkGPUVolumeRayCastMapper")


def _restore_after_refused_render(mapper, event) -> None:
    refused = object_state(mapper).pop("refused", None)
    if refused is not None:
        mapper.SetCropping(refused[0])
        mapper.SetCroppingRegionPlanes(*refused[1])


def sampled_projection_mapper(hooks: str, color: str = "mip_color") -> type:
    """A :class:`MIPVolumeMapper` subclass whose sampled loop runs the hook piece ``hooks``.

    A new sampled projection (MinIP, average, ...) is one GLSL piece that fills
    the hooks of the one sampled ray loop (``shaders/sampled_loop.glsl``
    documents them: ``mcBeginRay``, ``mcSample``, ``mcEndRay``) and leaves the
    ray's normalised value in ``mc_rayMax``; everything else (ray set-up,
    refusal, colour through the transfer functions, float readout) is MIP's.
    Pieces outside the package load from folders added with
    :func:`mipcast.mappers.shader_pieces.register_folder`.

    Parameters
    ----------
    hooks : str
        Name of the hook piece (file name without ``.glsl``).
    color : str
        The ``Shading::Exit`` piece that colours ``mc_rayMax``.

    Returns
    -------
    type
        The mapper class; its :data:`~MIPVolumeMapper.PIECES` are MIP's with
        ``mip_hooks`` (and ``mip_color``) swapped.

    Raises
    ------
    ValueError
        The piece is missing, or is not a hook piece defining every hook.

    Examples
    --------
    >>> cls = sampled_projection_mapper("mip_hooks")
    >>> cls.PIECES == MIPVolumeMapper.PIECES
    True
    """
    shader_pieces.check_hooks(shader_pieces.load_piece(hooks))
    shader_pieces.load_piece(color)
    swap = {"mip_hooks": hooks, "mip_color": color}
    return type(f"SampledProjectionMapper_{hooks}", (MIPVolumeMapper,), {
        "__doc__": f"Sampled projection through the hook piece {hooks!r} (see sampled_projection_mapper).",
        "PIECES": tuple(swap.get(name, name) for name in MIPVolumeMapper.PIECES),
        # block skipping: the hook pieces of _BLOCK_HOOKS only, with a skipping parameter (MIP's here)
        "PARAMETERS": MIPVolumeMapper.PARAMETERS if hooks == "mip_hooks" else parameter_tables.SAMPLED,
        "BRICKS": None})  # a new projection's composite over bricks is unknown: refused beyond one texture
