"""Analytic MIP: the exact maximum of the trilinear interpolant, cell by cell."""
from __future__ import annotations

import math
import numbers

from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.core import parameter_tables
from mipcast.core.object_state import object_state
from mipcast.core.parameters import parameter_accessors
from mipcast.mappers import bricked_draw
from mipcast.mappers.corner_packing import CornerPacker, packable
from mipcast.mappers.max_blocks import block_bytes
from mipcast.mappers.mip import MIPVolumeMapper, same_port


@parameter_accessors
class AnalyticMIPVolumeMapper(MIPVolumeMapper):
    """Exact MIP on the GPU: no samples to miss, no sample distance to choose.

    Each ray walks the cells it crosses; in every cell the trilinear
    interpolant along the ray is a cubic built exactly from the cell's 8
    corner values, and its maximum is taken at the segment ends and the
    derivative's roots (``shaders/amip_cell.glsl``).  Work that cannot change
    the answer is skipped.  The sample distance setting is ignored; colour and
    opacity come from the volume property exactly as in stock MIP;
    interpolation is always trilinear.  Partitioned rendering is refused
    with a message; a volume larger than one 3D texture is drawn exactly in
    bricks inside the render (:mod:`mipcast.mappers.bricked_draw`).  :meth:`GetTextureBytes` says what the method uploads;
    :meth:`SetTextureBudget` caps the packed copy (beyond it: unpacked, warned once);
    :meth:`SetPackingDelay` draws a large new input's first frame unpacked (default: automatic).

    Settings: :meth:`SetPackedCorners` (default True: two fetches per cell from
    a four-component copy of the volume made inside the mapper, four times the
    texture memory; a large input's first frame is drawn unpacked, the copy
    following from a later frame: :meth:`SetPackingDelay`; :meth:`GetInput`
    still returns your image, never modified; turn it off on GPUs short of
    memory) and :meth:`SetSkipping`
    (default True; False only to measure what skipping saves; both exact).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from mipcast.data_fixtures import make_fixture
    >>> mapper = AnalyticMIPVolumeMapper()
    >>> mapper.SetInputData(make_fixture("vessels", size=32))
    >>> volume = vtkVolume()
    >>> mapper.Attach(volume)
    >>> mapper.IsAttached()
    True

    See docs/methods.md, section Analytic MIP (the cell walk, the cubic, corner
    packing, skipping): ``docs/methods.md#analytic-mip``.
    """

    #: ``amip_max_hooks`` fills the cell walk's hooks (the exact maximum; see
    #: :mod:`mipcast.mappers.projections` for the exact minimum and mean).
    PIECES = ("mip_globals", "refusal", "amip_corners", "amip_cell", "amip_max_hooks", "amip_loop",
              "no_stock_sample", "mip_color")
    PARAMETERS = parameter_tables.ANALYTIC
    #: Replacements of pieces while the packed four-component copy is drawn.
    PACKED = {"amip_corners": "amip_corners_packed", "mip_color": "mip_color_packed"}

    #: The cell walk knows each value's cell: a block's maximum covers its own cells only.
    BLOCK_MARGIN = 0
    #: Largest packed copy (bytes) made for a new input's first frame under the automatic
    #: packing delay (:meth:`SetPackingDelay`); larger ones wait one frame.  32 MiB: a 128^3 int16
    #: volume packs at once, a 512x512x400 CT (800 MiB packed) draws its first frame unpacked.
    LAZY_PACKING_BYTES = 32 * 2 ** 20

    def __init__(self) -> None:
        super().__init__()
        state = object_state(self)
        state["packer"] = CornerPacker()
        # before MIPVolumeMapper's check (priority 0) updates the input
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _route_before_render, 1.0)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, _pack_after_render, 1.0)

    # -- input: the prepared image goes through the corner packer ----------
    def _vtk_port(self):
        """The packed copy of the prepared input, or the prepared input itself."""
        packer, source = object_state(self)["packer"], self._prepared_port()
        if packer.GetNumberOfInputConnections(0) == 0 or not same_port(packer.GetInputConnection(0, 0), source):
            packer.SetInputConnection(0, source)
        return packer.GetOutputPort() if self._packing_active() else source

    def _route_input(self) -> None:
        """As :meth:`MIPVolumeMapper._route_input`; going from the volume's own texture to the packed
        copy first releases the mapper's graphics resources (VTK 9.7 crashes drawing four components
        where it drew one; the one-component texture would be replaced anyway)."""
        if self.GetInputPreparer().GetNumberOfInputConnections(0) and \
                vtkOpenGLGPUVolumeRayCastMapper.GetNumberOfInputConnections(self, 0):
            packed = object_state(self)["packer"].GetOutputPort()
            current = vtkOpenGLGPUVolumeRayCastMapper.GetInputConnection(self, 0, 0)
            if not same_port(current, packed) and same_port(self._vtk_port(), packed):
                from mipcast.mappers.gpu_limits import window_of

                window = window_of(self.GetAttachedVolume())
                if window is not None:
                    self.ReleaseGraphicsResources(window)
        super()._route_input()

    def _own_ports(self) -> list:
        return super()._own_ports() + [object_state(self)["packer"].GetOutputPort()]

    def SetPackedCorners(self, *packed) -> None:
        """Read four corners per texel from a packed copy of the volume (default True).

        True: two texture fetches per cell, four times the texture memory.
        False: the volume's own one-component texture, eight fetches per cell.
        """
        packed = parameter_tables.ANALYTIC[0].check(*packed)
        if self.GetPackedCorners() != packed:
            self._set_parameter("packed_corners", packed)
            self._route_input()

    def SetCornerPacker(self, packer: CornerPacker) -> None:
        """Pack through ``packer`` (shared by mappers that draw the same volume) instead of an own one."""
        if not isinstance(packer, CornerPacker):
            raise TypeError(f"SetCornerPacker needs a CornerPacker (mipcast.mappers.corner_packing), "
                            f"got {type(packer).__name__}")
        state = object_state(self)
        previous = state["packer"]
        if previous is not packer:
            state["packer"] = packer
            shared = object_state(packer).get("preparer")  # mappers sharing a packer share its preparer
            if shared is None:
                object_state(packer)["preparer"] = self.GetInputPreparer()
            else:
                if shared is not self.GetInputPreparer():
                    mine = self.GetInputPreparer()
                    if shared.GetNumberOfInputConnections(0) == 0 and mine.GetNumberOfInputConnections(0):
                        shared.SetInputConnection(0, mine.GetInputConnection(0, 0))
                    shared.SetComponent(mine.GetComponent())
                    state["preparer"] = shared
            self._route_input()

    def PackedCornersOn(self) -> None:
        self.SetPackedCorners(True)

    def PackedCornersOff(self) -> None:
        self.SetPackedCorners(False)

    def SkippingOn(self) -> None:
        self.SetSkipping(True)

    def SkippingOff(self) -> None:
        self.SetSkipping(False)

    def SetPackingDelay(self, frames: int) -> None:
        """Frames of a new input drawn unpacked before the packed copy is made; -1 (default): automatic.

        Packing copies the volume into a four-component texture (four times
        its memory) once per input; on a 512x512x400 CT that copy and its
        upload cost more than the rest of the first frame.  With a delay of
        ``frames``, the first ``frames`` frames of each input are drawn from
        the volume's own texture (eight fetches per cell instead of two, the
        same exact picture); the copy is then made in a background thread
        (:meth:`CornerPacker.StartPacking`) and drawn from the first frame
        that finds it ready (frames before that stay unpacked), so no frame
        waits for the packing and a view that draws a large volume once (a
        batch render) never packs.
        0: pack for the very first frame.  -1: 0 while the packed copy takes
        at most :data:`LAZY_PACKING_BYTES` (packing is then cheap), else 1.
        """
        if isinstance(frames, bool) or not isinstance(frames, numbers.Integral) or frames < -1:
            raise ValueError(f"the packing delay is a whole number of frames >= 0 (0: pack for the first "
                             f"frame) or -1 (automatic), got {frames!r}")
        state = object_state(self)
        if state.get("packing_delay", -1) != int(frames):
            state["packing_delay"] = int(frames)
            self.Modified()
            self._route_input()

    def GetPackingDelay(self) -> int:
        """The delay :meth:`SetPackingDelay` set (-1: automatic)."""
        return object_state(self).get("packing_delay", -1)

    def _delay_for(self, image) -> int:
        """Frames of ``image`` drawn unpacked first (:meth:`SetPackingDelay`, -1 resolved)."""
        delay = object_state(self).get("packing_delay", -1)
        if delay >= 0:
            return delay
        from mipcast.mappers.gpu_limits import volume_texture_bytes

        return 0 if volume_texture_bytes(image, 4) <= self.LAZY_PACKING_BYTES else 1

    def GetFramesDrawnUnchanged(self) -> int:
        """Frames started with the current input unchanged before the latest (0: a new input's first)."""
        return object_state(self).get("frames_drawn", 0)

    def _count_frame(self, image) -> None:
        """At a render's start: count the frames the (unchanged) prepared input has been drawn."""
        state = object_state(self)
        stamp = None if image is None else (image.GetAddressAsString("vtkObjectBase"), image.GetMTime())
        if stamp is not None and state.get("frames_of") == stamp:
            state["frames_drawn"] = state.get("frames_drawn", 0) + 1
        else:
            state["frames_of"], state["frames_drawn"] = stamp, 0

    def _packing_active(self) -> bool:
        """The packed copy is drawn: packing is wanted (:meth:`_packing_wanted`) and either there is
        no delay or the copy made after the delay's frames is ready."""
        if not self._packing_wanted():
            return False
        # with a delay: once the copy (started in the background after the last frame the delay
        # keeps unpacked: _pack_in_background) is ready, so that no frame waits for the packing;
        # a copy already made for this input is drawn whatever the delay
        # (latched at the render's start, _latch_packing: a thread finishing mid-render changes nothing)
        if self._delay_for(self.GetRenderedInput()) == 0:
            return True
        latched = object_state(self).get("packing_ready")
        return latched is not None and latched == object_state(self)["packer"].InputStamp()

    def _latch_packing(self) -> None:
        """At a render's start: whether the background copy is ready, for the whole render."""
        state = object_state(self)
        state["packing_ready"] = state["packer"].ReadyStamp()

    def _pack_in_background(self) -> None:
        """After a frame drawn unpacked: start packing for a later frame once the delay is over."""
        state = object_state(self)
        if state.get("frames_of") is None or self._packing_active() or not self._packing_wanted():
            return
        if state.get("frames_drawn", 0) + 1 >= self._delay_for(self.GetRenderedInput()):
            state["packer"].StartPacking()

    def _packing_wanted(self) -> bool:
        """Packed corners are set, the attached volume draws components independently,
        and the input's values pack exactly (:func:`mipcast.mappers.corner_packing.packable`)."""
        volume = self.GetAttachedVolume()
        if not self.GetPackedCorners() or (volume is not None and not volume.GetProperty().GetIndependentComponents()):
            return False
        if bricked_draw.bricking_limit(self):
            return False  # drawn in bricks (each packs its own): no packed copy of the whole volume
        image = self.GetRenderedInput()
        scalars = image.GetPointData().GetScalars() if image is not None else None
        if scalars is None or scalars.GetNumberOfComponents() != 1:
            return False  # refused (GetRenderProblem); VTK's own checks then see the input as it is
        if not packable(vtk_to_numpy(scalars)):  # a view: only its type is read
            return False
        return self._packing_fits(image)

    # -- texture memory -------------------------------------------------------
    def GetTextureBytes(self) -> int:
        """GPU texture bytes for the current input: the volume (packed: 4x) plus the block maxima.

        With packed corners wanted the volume texture holds four components
        (four times the unpacked volume) in the steady state; the first
        :meth:`GetPackingDelay` frames of an input draw the one-component
        volume (1x) instead.  The block level (maxima, the exact MinIP's minima;
        float32, one value per :data:`BLOCK`^3 cells) rides in the mask
        texture; the exact average has none.

        Examples
        --------
        >>> from mipcast.data_fixtures import make_fixture
        >>> mapper = AnalyticMIPVolumeMapper()
        >>> mapper.SetInputData(make_fixture("spheres", size=17))   # float32, 17^3 points
        >>> mapper.GetTextureBytes() == 17 ** 3 * 4 * 4 + 2 ** 3 * 4
        True
        """
        from mipcast.mappers.gpu_limits import volume_texture_bytes

        image = self.GetInput()
        if image is None or image.GetPointData().GetScalars() is None:
            return 0
        volume = volume_texture_bytes(image, 4 if self._packing_wanted() else None)
        return volume + (block_bytes(image.GetDimensions(), self.BLOCK) if self.BLOCK_EXTREME else 0)

    def SetTextureBudget(self, budget: int) -> None:
        """Most bytes of texture the packed corners may take; 0 (default): the driver's free memory.

        When the packed copy (four times the volume) plus the block maxima
        would exceed the budget, the mapper draws the volume's own
        one-component texture instead (eight fetches per cell instead of two,
        the same exact picture) and warns once.  With the default, the budget
        is the free GPU memory the driver reports
        (:func:`mipcast.mappers.gpu_limits.free_gpu_memory`, asked once per
        window); where the driver cannot say (e.g. Mesa), there is no budget.
        """
        if isinstance(budget, bool) or not isinstance(budget, numbers.Real) or not math.isfinite(budget):
            raise TypeError(f"the texture budget is a finite number of bytes >= 0 (0: the driver's), "
                            f"got {budget!r}")
        budget = int(budget)
        if budget < 0:
            raise ValueError(f"the texture budget is a number of bytes >= 0 (0: the driver's), got {budget}")
        state = object_state(self)
        if state.get("texture_budget", 0) != budget:
            state["texture_budget"] = budget
            state.pop("budget_warned", None)
            self.Modified()
            self._route_input()

    def GetTextureBudget(self) -> int:
        """The budget :meth:`SetTextureBudget` set (0: the driver's free memory, where it reports one)."""
        return object_state(self).get("texture_budget", 0)

    def _effective_budget(self):
        """Bytes the packed corners may use, or None (no budget known)."""
        state = object_state(self)
        if state.get("texture_budget", 0):
            return state["texture_budget"]
        if "driver_budget" not in state:
            from mipcast.mappers.gpu_limits import free_gpu_memory, window_of

            window = window_of(self.GetAttachedVolume())
            if window is None or window.GetNeverRendered():
                return None  # asked again once the window has a context
            state["driver_budget"] = free_gpu_memory(window)
        return state["driver_budget"]

    def _packing_fits(self, image) -> bool:
        budget = self._effective_budget()
        if budget is None:
            return True
        from mipcast.mappers.gpu_limits import volume_texture_bytes

        packed = volume_texture_bytes(image, 4) + block_bytes(image.GetDimensions(), self.BLOCK)
        if packed <= budget:
            return True
        state = object_state(self)
        if not state.get("budget_warned"):
            state["budget_warned"] = True
            from vtkmodules.vtkCommonCore import vtkOutputWindow

            vtkOutputWindow.GetInstance().DisplayWarningText(
                f"{type(self).__name__}: packed corners would take {packed} bytes of texture, over the "
                f"budget of {budget} bytes; drawing the volume unpacked (same picture, eight fetches "
                "per cell instead of two). Raise it with SetTextureBudget(bytes) or turn "
                "SetPackedCorners(False) to silence this.\n")
        return False

    def GetRenderProblem(self):
        """As :meth:`MIPVolumeMapper.GetRenderProblem`, plus the one-texture rule.

        The cell walk needs its volume in one 3D texture: VTK's partitioned
        rendering (``SetPartitions``) is refused with a message, instead of
        drawing each partition as if it were the volume.  A volume beyond
        the GPU's 3D texture limit is drawn in bricks inside the render
        (:mod:`mipcast.mappers.bricked_draw`, exact).
        """
        problem = super().GetRenderProblem()
        if problem is not None:
            return problem
        if self._partitioned():
            return ("analytic MIP walks the whole volume in one 3D texture, so partitioned "
                    "rendering (SetPartitions) would not be exact: call SetPartitions(1, 1, 1) "
                    "(a volume beyond the 3D texture limit is drawn in bricks by the mapper itself)")
        return None

    def GetShaderPieces(self) -> tuple:
        """:data:`PIECES`, with the block-skipping loop when the transfer functions have a floor
        (the exact MinIP: a ceiling).

        Skipping blocks pays only when most of them lie below the running
        maximum from the start, i.e. when colour and opacity are constant
        from the data minimum up to a floor (a window above the background;
        mirrored for the minimum, :meth:`_window_bounds_blocks`).  Without one
        the check costs more than it saves on llvmpipe, so the plain loop is
        used.
        """
        names = self._packed_pieces(super().GetShaderPieces())
        state = object_state(self)
        # a brick walking the whole volume's ray (global_cells): the plain walk
        distributed = state.get("global_box") is not None and state.get("global_cells", True)
        if self.GetSkipping() and self._window_bounds_blocks() and not distributed:
            names = tuple("amip_loop_blocks" if n == "amip_loop" else n for n in names)
        if object_state(self).get("stat") is not None:  # mipcast.mappers.amip_stats reads work counters
            names = tuple("amip_stats_readout" if n == "float_readout" else n for n in names)
        return names

    def _packed_pieces(self, names) -> tuple:
        """``names`` with the packed-corner variants (:data:`PACKED`) while packing is active, plus
        ``gradient_opacity_packed`` (VTK's gradient opacity of component 0 only: the corner
        components have no function, and VTK gave their samplers texture unit -1)."""
        if not self._packing_active():
            return tuple(names)
        return tuple(self.PACKED.get(n, n) for n in names) + ("gradient_opacity_packed",)

    def _push_derived_uniforms(self, uniforms, settings) -> None:
        uniforms.SetUniformf("u_mc_stat", float(object_state(self).get("stat") or 0))
        self._push_skipping(uniforms, settings["skipping"])


def _route_before_render(mapper, event) -> None:
    mapper._adopt_direct_input()
    # the prepared data, to decide whether it packs exactly, and whether it is new (packing delay)
    mapper._count_frame(mapper.GetRenderedInput())
    mapper._latch_packing()
    mapper._route_input()


def _pack_after_render(mapper, event) -> None:
    mapper._pack_in_background()
