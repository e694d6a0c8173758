"""Foveated (gaze-directed) rendering: full quality where the user looks, fewer rays and samples elsewhere."""
from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import (VTK_OBJECT, VTK_UNSIGNED_CHAR, reference, vtkCommand, vtkUnsignedCharArray,
                                      vtkWeakReference)
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import vtkCamera, vtkVolume
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.core import content_adaptive, foveation, parameter_tables, structure_bound
from mipcast.core.gaze import GazeStream
from mipcast.core.parameter_tables import FOVEATION_LAYERS
from mipcast.core.parameters import parameter_accessors
from mipcast.mappers import (bricked_draw, bricked_foveated, float_readout, foveated_tiles, refine_keep,
                             refine_pass, volume_pyramid)
from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.core.camera_rays import matrix_array
from mipcast.core.prepare import prepare_scalars
from mipcast.core.transfer_bounds import constant_ends
from mipcast.mappers.corner_packing import CornerPacker
from mipcast.mappers.max_blocks import block_maxima
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.core.object_state import object_state
from mipcast.mappers import clip_uniforms
from mipcast.mappers.private_draw import (GL_SCISSOR_BOX, auto_sample_distance, copy_drawn, draw_over, follow_volume,
                                          kept_texture, rendering_renderer, texture_target)
from mipcast.core.ray_cost import grid_cost

#: Stand-in for an unbounded eccentricity in the shader's uniforms.
_FAR = 1.0e30
#: State besides the parameters: the gaze of the last render (from the current source) and its source.
_GAZE = {"gaze": (0.5, 0.5), "gaze_source": "point"}


def layer_methods() -> tuple:
    """Names of the methods a :class:`FoveatedVolumeMapper` can draw its levels with.

    The methods of :data:`mipcast.METHODS` declared as foveation layers.

    Examples
    --------
    >>> import mipcast
    >>> {"mip", "analytic"} <= set(layer_methods())
    True
    """
    return tuple(FOVEATION_LAYERS)


@parameter_accessors
class FoveatedVolumeMapper(MIPVolumeMapper):
    """Gaze-directed rendering of any mipcast method (Levoy & Whitaker 1990).

    Inside the foveal radius around the gaze point the picture is the chosen
    method at full quality, pixel for pixel.  Outside it, rays are cast on the
    coarser grids of an image pyramid (level ``k``: one ray every ``2**k``
    pixels, sampling a max-filtered coarser copy of the volume where its rays
    are far apart), blended smoothly, so there is no seam.  Drop-in:
    :meth:`Attach` it to a volume like any mipcast mapper; it draws the levels
    with private mappers of the chosen method, and nothing has to be added to
    the scene.

    Settings, with their defaults (they take effect at the next render without
    recompiling shaders):

    - :meth:`SetMethod` ``"mip"``: any of :func:`layer_methods`.
    - :meth:`SetGazePoint` ``(0.5, 0.5)``: normalised viewport coordinates,
      (0, 0) bottom-left; outside the viewport is allowed.  Or let the gaze
      follow the mouse (:meth:`FollowMouse`) or a 3D region of interest
      (:meth:`SetRegionOfInterest`).
    - :meth:`SetFovealRadius` 0.188 of the viewport height (6 degrees on a
      27-inch monitor seen from 60 cm; :func:`mipcast.core.foveation.angle_to_height`
      converts for other displays).  Halving it roughly halves the time that
      remains.
    - :meth:`SetFalloff` 0.127 of the height: from the fovea's edge to the
      coarsest level.
    - :meth:`SetNumberOfLevels` 3: full, 1/2 and 1/4 resolution.
    - :meth:`SetPeripheralSampling` ``"footprint"``; ``"rays"`` (faster,
      aliases along thin vessels), ``"level"`` (the paper's fixed schedule,
      widens thin vessels when zoomed in).
    - :meth:`SetFoveation` True; False renders the method at full quality
      everywhere.

    The float readout (:func:`mipcast.mappers.float_readout.render_float`) returns the
    foveated image in data units; :meth:`GetLastFrameCost` the rays and
    samples of the last frame against full quality.  Each drawn level holds its
    own 3D texture; a level whose volume exceeds the GPU's 3D texture limit
    composites its rays over bricks first and is then masked and blended as
    one texture (:mod:`mipcast.mappers.bricked_foveated`; MIP, analytic and
    DEMIP layers; :meth:`GetNumberOfBricks`).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> from mipcast.data_fixtures import make_fixture
    >>> mapper = FoveatedVolumeMapper()
    >>> mapper.SetInputData(make_fixture("vessels", size=32))
    >>> mapper.SetMethod("analytic")
    >>> mapper.SetGazePoint(0.3, 0.7)
    >>> mapper.Attach(vtkVolume())
    >>> mapper.GetMethod(), mapper.GetGazePoint(), round(mapper.GetFovealRadius(), 3)
    ('analytic', (0.3, 0.7), 0.188)

    See docs/methods.md, section Foveated rendering (the acuity schedule,
    blending, peripheral sampling, what the levels honour):
    ``docs/methods.md#foveated-rendering``.
    """

    #: The mapper's own (skipped) draw only needs the refusal piece (and its helper).
    #: Beyond one texture each level too large is composited over bricks first, then masked and
    #: blended (:mod:`mipcast.mappers.bricked_foveated`); refused for a layer that cannot brick.
    BRICKS = "foveated"
    PIECES = ("mip_globals", "refusal")
    #: Pieces every level adds to its method's own.
    LEVEL_PIECES = ("foveated_band_dec", "foveated_skip", "foveated_weight")
    #: Pieces of the finer levels with content-adaptive ray density (ContentTolerance > 0).
    #: A cast ray of theirs is drawn over the picture beneath the volume, not over the coarser levels.
    MASKED_LEVEL_PIECES = ("foveated_band_dec", "foveated_skip_masked", "foveated_mask_dec", "foveated_weight",
                           "foveated_paint_beneath")
    #: The same with the refinement mask built on the GPU from the deciding level's picture (no readback).
    COARSE_LEVEL_PIECES = ("foveated_band_dec", "foveated_skip_coarse", "foveated_coarse_dec", "foveated_weight",
                           "foveated_paint_beneath")
    PARAMETERS = parameter_tables.FOVEATED

    def __init__(self) -> None:
        super().__init__()
        object_state(self).update(_GAZE)
        # after MIPVolumeMapper's own check (priority 0): levels draw only if it passed
        self.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, _draw_levels, -1.0)
        self.AddObserver(vtkCommand.VolumeMapperRenderEndEvent, _restore_own_draw, -1.0)

    # -- settings with side effects (the rest come from the table) ------------
    def SetMethod(self, *method) -> None:
        """Use the mipcast method ``method`` (one of :func:`layer_methods`) for every level."""
        method = self.PARAMETERS[0].check(*method)
        if self.GetMethod() != method:
            object_state(self).pop("levels_drawn", None)  # new private mappers at the next render
            self._set_parameter("method", method)

    def _draws_reduced(self) -> bool:
        """Its coarser levels draw into VTK's reduced buffer whatever its own image sample distance."""
        return True

    def SetContentTolerance(self, *tolerance) -> None:
        """Content-adaptive ray density: grey levels a coarse neighbourhood may vary by unrefined (0 = off).

        See :mod:`mipcast.core.content_adaptive`.  Turning it on or off builds
        new private level mappers (other shader pieces) at the next render.
        """
        tolerance = _parameter("content_tolerance").check(*tolerance)
        if (tolerance > 0) != (self.GetContentTolerance() > 0):
            object_state(self).pop("levels_drawn", None)
        self._set_parameter("content_tolerance", tolerance)

    def SetGazePoint(self, *xy) -> None:
        """Look at ``(x, y)`` in normalised viewport coordinates ((0, 0) bottom-left).

        Points outside [0, 1] are allowed (the fovea is then partly or wholly
        off screen).  Stops following the mouse or a region of interest.
        """
        gaze = _parameter("gaze_point").check(*xy)
        state = object_state(self)
        state["gaze"] = gaze
        state["gaze_source"] = "point"
        self._set_parameter("gaze_point", gaze)

    def SetGazeSaccadeVelocity(self, *velocity) -> None:
        """Eye speed (viewport heights per second, > 0) above which gaze samples belong to a saccade."""
        velocity = _parameter("gaze_saccade_velocity").check(*velocity)
        if velocity <= 0:
            raise ValueError(f"gaze_saccade_velocity must be > 0, got {velocity!r}")
        self._set_parameter("gaze_saccade_velocity", velocity)

    # -- gaze streams (an eye tracker) ------------------------------------------
    def PushGaze(self, t: float, x: float, y: float) -> bool:
        """Feed one eye-tracker sample: time ``t`` (s), gaze ``(x, y)`` (normalised viewport coordinates).

        The sample goes through the mapper's :class:`mipcast.core.gaze.GazeStream`
        (fixations below :meth:`GetGazeFixationRadius` and saccades change
        nothing; see :mod:`mipcast.core.gaze`), and the gaze follows the
        stream from now on.  Returns True when the gaze to render with
        changed: render then (the sample is used by the next frame; its
        latency is :meth:`GetLastGazeLatency`).

        Examples
        --------
        >>> mapper = FoveatedVolumeMapper()
        >>> mapper.PushGaze(0.0, 0.3, 0.3), mapper.PushGaze(0.03, 0.301, 0.3), mapper.GetGazeSource()
        (True, False, 'stream')
        """
        import time

        state = object_state(self)
        stream = self.GetGazeStream()
        changed = stream.push(t, x, y)
        if state["gaze_source"] != "stream":
            state["gaze_source"] = "stream"
            changed = True
        if changed:
            state["gaze_pushed"] = time.perf_counter()
            self.Modified()
        return changed

    def SetGazeCallable(self, source) -> None:
        """Poll ``source()`` at every render for the latest tracker sample ``(t, x, y)`` (None: no news).

        ``source=None`` stops polling (the stream keeps its last gaze).  A
        tracker whose API is a callback can call :meth:`PushGaze` instead.
        """
        if source is not None and not callable(source):
            raise TypeError(f"gaze source must be callable returning (t, x, y) or None, got {source!r}")
        state = object_state(self)
        state["gaze_callable"] = source
        if source is not None:
            self.GetGazeStream()
            state["gaze_source"] = "stream"

    def GetGazeStream(self) -> GazeStream:
        """The :class:`mipcast.core.gaze.GazeStream` behind :meth:`PushGaze` (made on first use)."""
        state = object_state(self)
        params = self._parameters()
        stream = state.get("gaze_stream")
        if stream is None:
            stream = state["gaze_stream"] = GazeStream()
        stream.fixation_radius = params["gaze_fixation_radius"]
        stream.saccade_velocity = params["gaze_saccade_velocity"]
        stream.prediction = params["gaze_prediction"]
        return stream

    # -- progressive refinement ---------------------------------------------------
    def NeedsRefinement(self) -> bool:
        """True when progressive refinement is on and the last frame was not yet full quality.

        An application's timer renders again while this holds (nothing
        changes between its frames, so each refines more); see
        :meth:`GetRefinementStep`.

        Examples
        --------
        >>> FoveatedVolumeMapper().NeedsRefinement()
        False
        """
        state = object_state(self)
        # a frame drawn, here or reduced over the ranks of a parallel view (mipcast.mappers.rank_foveated)
        if not self._parameters()["progressive"] or ("frame" not in state and "rank_foveated_values" not in state):
            return False
        return state.get("refine_step", 0) < self._parameters()["refinement_frames"]

    def GetRefinementStep(self) -> int:
        """Still frames refined so far (0: the foveated frame; ``RefinementFrames``: full quality)."""
        return int(object_state(self).get("refine_step", 0))

    def GetLastGazeLatency(self) -> Optional[float]:
        """Seconds from the :meth:`PushGaze` that last moved the gaze to the end of the frame that used it.

        None before such a frame.
        """
        return object_state(self).get("gaze_latency")

    def GetGazePoint(self) -> tuple:
        """The gaze point used by the last render (or set since), normalised viewport coordinates."""
        return tuple(object_state(self)["gaze"])

    def GetGazeSource(self) -> str:
        """Where the gaze comes from: ``"point"``, ``"mouse"``, ``"region"`` or ``"stream"`` (:meth:`PushGaze`)."""
        return object_state(self)["gaze_source"]

    def FoveationOn(self) -> None:
        self.SetFoveation(True)

    def FoveationOff(self) -> None:
        self.SetFoveation(False)

    # -- gaze sources -------------------------------------------------------
    def FollowMouse(self, interactor=None) -> None:
        """Let the gaze follow the mouse of ``interactor`` (None: stop).

        The gaze is read from the interactor's last event position at every
        render, and a mouse move that nobody else renders for (no button
        held) triggers a render, so the fovea follows the pointer.
        """
        state = object_state(self)
        previous = state.pop("mouse", None)
        if previous is not None and previous[0].Get() is not None:
            previous[0].Get().RemoveObserver(previous[1])
        state.pop("mouse_seen", None)
        if interactor is None:
            if state["gaze_source"] == "mouse":
                state["gaze_source"] = "point"
            return
        mapper_link = vtkWeakReference()
        mapper_link.Set(self)

        def moved(caller, event):
            mapper = mapper_link.Get()
            if mapper is None:
                return
            object_state(mapper)["mouse_seen"] = True
            style = caller.GetInteractorStyle()
            if style is not None and hasattr(style, "GetCurrentStyle") and style.GetCurrentStyle():
                style = style.GetCurrentStyle()
            if style is None or style.GetState() == 0:  # no rotation/pan under way: render ourselves
                if caller.GetEnabled():
                    caller.Render()
                elif caller.GetRenderWindow() is not None:
                    caller.GetRenderWindow().Render()

        link = vtkWeakReference()
        link.Set(interactor)
        state["mouse"] = (link, interactor.AddObserver(vtkCommand.MouseMoveEvent, moved))
        state["gaze_source"] = "mouse"
        self.Modified()

    def SetRegionOfInterest(self, region: Optional[Sequence[float]]) -> None:
        """Keep a world-space region sharp: a point ``(x, y, z)`` or bounds ``(x0, x1, y0, y1, z0, z1)``.

        At every render the gaze moves to the region's projected centre, and
        the foveal radius grows (never shrinks) to cover its projection.
        ``None`` returns to the last explicit gaze point (:meth:`SetGazePoint`).
        """
        region = _parameter("region_of_interest").check(region)
        state = object_state(self)
        if region is None:
            if state["gaze_source"] == "region":
                state["gaze_source"] = "point"
        else:
            state["gaze_source"] = "region"
        self._set_parameter("region_of_interest", region)

    # -- what the last frame did --------------------------------------------
    def GetLastPlan(self):
        """The :class:`mipcast.core.foveation.Plan` of the last render (None before the first)."""
        frame = object_state(self).get("frame")
        return None if frame is None else frame["plan"]

    def GetLastSilhouette(self):
        """``(edges, unit)`` of the last render's silhouette band (None: no band), see
        :func:`mipcast.core.foveation.silhouette_band`."""
        frame = object_state(self).get("frame")
        return None if frame is None else frame.get("silhouette")

    def GetLastFrameCost(self) -> Optional[dict]:
        """Rays cast and samples taken by the last render, and by the same method at full quality.

        Counted on the CPU from the frame's geometry (see
        :mod:`mipcast.core.ray_cost`; a few tenths of a second at 1024^2, so only
        when asked).  Samples are volume samples for sampled methods and
        cells visited for analytic MIP; for DEMIP they count its first
        (MIP) march, not the partial second one.

        Returns
        -------
        dict or None
            ``rays``, ``samples``, ``full_rays``, ``full_samples``,
            ``ray_ratio`` and ``sample_ratio`` (full / foveated), ``band_rays``
            (level-0 rays cast only for the volume's silhouette band, included
            in ``rays``), ``brick_rays`` (rays the bricks of levels beyond
            the 3D texture limit cast before their level is drawn from
            them, :mod:`mipcast.mappers.bricked_foveated`; not in ``rays``), ``unit``
            (``"samples"`` or ``"cells"``) and ``levels``: one dict per
            drawn level (``level``, ``volume_level``, ``grid``,
            ``sample_distance``, ``rays``, ``samples``).  None before the
            first render.
        """
        frame = object_state(self).get("frame")
        if frame is None:
            return None
        if "cost" not in frame:
            frame["cost"] = _frame_cost(frame)
        return dict(frame["cost"])

    def GetTextureBytes(self) -> int:
        """GPU texture bytes of the pyramid: every level's volume as its layer method uploads it.

        Level 0 is the input itself; each coarser level is a max-reduced copy
        drawn by a private mapper of the layer method (:meth:`SetMethod`), so
        each level counts what that method's ``GetTextureBytes`` counts (for
        analytic MIP: packed corners and block maxima).  The foveated mapper's
        own draw is skipped and uploads nothing.

        Examples
        --------
        >>> from mipcast.data_fixtures import make_fixture
        >>> mapper = FoveatedVolumeMapper()
        >>> mapper.SetInputData(make_fixture("spheres", size=16))
        >>> mapper.GetTextureBytes() > 16 ** 3 * 4
        True
        """
        image = self.GetInput()
        if image is None or image.GetPointData().GetScalars() is None:
            return 0
        state = object_state(self)
        method = self._parameters()["method"]
        total = 0
        for level in _pyramid(state, image) if self.GetFoveation() else [image]:
            counter = FOVEATION_LAYERS[method].factory()
            counter.SetInputData(level)
            total += counter.GetTextureBytes()
        return total

    def GetNumberOfBricks(self) -> int:
        """Bricks the last frame drew over all its levels (0: every level's volume fits one 3D texture).

        A level whose volume exceeds the texture limit composites its rays
        over bricks first (:mod:`mipcast.mappers.bricked_foveated`).
        """
        if not bricked_draw.exceeds_limit(self):
            return 0
        return int(object_state(self).get("bricks_drawn", 0))

    def GetLevelMapper(self, level: int):
        """The private mapper drawing pyramid level ``level`` (None if never drawn).

        With content-adaptive density on, the finer levels' masked mappers.
        """
        drawn = object_state(self).get("levels_drawn", {})
        entry = drawn.get((int(level), "coarse")) or drawn.get((int(level), "masked")) or drawn.get(int(level))
        return None if entry is None else entry["mapper"]

    # -- rendering ------------------------------------------------------------
    def GetDepthImage(self, image) -> None:
        """During a float readout, the blended levels' values; otherwise VTK's depth image.

        The own draw is skipped, so VTK's depth image would be empty: while
        :func:`mipcast.mappers.float_readout.render_float` runs, every level renders
        its float readout, and this composites them (bilinear within a level,
        the blend weights between levels) into the encoding the readout
        expects.
        """
        readout = object_state(self).pop("readout", None)
        if readout is None:
            super().GetDepthImage(image)
            return
        plan, values, skipped = readout
        _, _, width, height = plan.viewport
        blended = foveation.composite_values(plan, values, skipped)
        silhouette = self.GetLastSilhouette()
        if silhouette is not None and len(plan.layers) > 1:  # rays outside the box's outline miss it
            blended[foveation.outline_distance(plan, silhouette, (width, height)) < 0] = np.nan
        raw = float_readout.encode(float_readout.from_data_units(blended, self.GetRenderedInput().GetPointData().GetScalars()))
        image.SetDimensions(width, height, 1)
        array = numpy_to_vtk(np.ascontiguousarray(raw[::-1], dtype=np.float32).ravel(), deep=True)
        image.GetPointData().SetScalars(array)


# -- per-frame work (observers: module functions, no reference cycles) ------------
def _draw_levels(mapper, event) -> None:
    """Render every pyramid level with the private mappers, then skip the own draw."""
    state = object_state(mapper)
    if object_state(mapper).get("render_problem") is not None:  # MIPVolumeMapper's observer reported it
        return
    if state.get("rank_own_draw") is not None:  # a parallel render view draws the levels reduced over its
        return  # ranks instead (plugin/representation, mipcast.mappers.rank_foveated)
    volume = mapper.GetAttachedVolume()
    renderer = rendering_renderer(mapper, volume)
    if renderer is not None:
        _draw(mapper, state, volume, renderer)
    state["own_draw"] = (mapper.GetCropping(), mapper.GetCroppingRegionPlanes())
    # invalid cropping planes make VTK skip the render silently (no texture upload)
    mapper.SetCropping(True)
    mapper.SetCroppingRegionPlanes(1.0, 0.0, 1.0, 0.0, 1.0, 0.0)


def _restore_own_draw(mapper, event) -> None:
    state = object_state(mapper)
    pushed = state.pop("gaze_in_frame", None)
    if pushed is not None:
        import time

        state["gaze_latency"] = time.perf_counter() - pushed
    saved = object_state(mapper).pop("own_draw", None)
    if saved is not None:
        mapper.SetCropping(saved[0])
        mapper.SetCroppingRegionPlanes(*saved[1])


def _draw(mapper, state, volume, renderer) -> None:
    image = mapper.GetInput()
    params = mapper._parameters()
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    viewport = (x0[0], y0[0], max(width[0], 1), max(height[0], 1))
    camera = renderer.GetActiveCamera()
    whole, to_tile, tile_scale = _whole_viewport(renderer, viewport)
    whole_camera = _whole_camera(camera, renderer) if tile_scale != 1.0 else camera
    gaze, radius = _current_gaze(state, renderer, whole_camera, whole)
    state["gaze"] = gaze
    foveate = params["foveation"]
    first_eye = counts_frame(renderer, camera)
    signature = scene_signature(params, image, volume, camera, whole)
    if params["progressive"]:
        radius, foveate = _refine(state, params, image, volume, camera, whole, gaze, radius, first_eye, signature)
    else:
        state.pop("refine_step", None)
    auto = bool(mapper.GetAutoAdjustSampleDistances())
    base_isd = 1.0 if auto else float(mapper.GetImageSampleDistance())
    base_distance = auto_sample_distance(image, volume) if auto else float(mapper.GetSampleDistance())
    # a tile of a bigger picture (SaveScreenshot beyond the window's size): the plan is made in
    # this tile's viewport, with the gaze, radius and falloff of the whole picture carried over
    cap = _level_cap(image, volume, whole_camera, whole)
    plan = foveation.plan_frame(viewport, to_tile(gaze), radius * tile_scale, params["falloff"] * tile_scale,
                                params["number_of_levels"], foveate, cap, base_isd)
    if tile_scale != 1.0:  # a tile the fovea's level 0 does not reach still casts its silhouette band
        whole_plan = foveation.plan_frame(whole, gaze, radius, params["falloff"], params["number_of_levels"],
                                          foveate, cap, base_isd)
        plan = foveated_tiles.band_layer(plan, whole_plan, base_isd)
    readout = bool(state.get("exact_readout"))
    # a frame keeps what the last one left at full quality where it is full quality itself: progressive
    # refinement's still frames, and a gaze that moved within the last fovea (refine_keep)
    keeping = (not readout and tile_scale == 1.0 and base_isd == 1.0
               and not bricked_foveated.level_limit(mapper, image))
    eye = 0 if first_eye else 1  # a stereo pair's eyes keep a picture each
    scene = (signature, refine_keep.scene_key(renderer, volume, mapper)) if keeping else None
    kept = refine_keep.kept_disc(state, scene, renderer.GetRenderWindow(), eye, plan) if keeping else None
    if kept is not None and not params["progressive"] and tuple(kept.gaze) == tuple(plan.gaze):
        kept = None  # without progressive refinement the same frame again is drawn afresh (as benchmarks time it)
    # a still frame casts acuity-only levels, whose fovea is full quality for the next to keep
    still = keeping and params["progressive"] and state.get("refine_step", 0) >= 1
    tolerance = 0.0 if still else float(params["content_tolerance"])
    adaptive = tolerance > 0 and len(plan.layers) > 1
    if adaptive:
        plan = content_adaptive.adaptive_plan(plan, cap)
    cells = _walks_cells(params["method"])
    spacings = volume_pyramid.pyramid_voxel_sizes(image, params["number_of_levels"])
    world_per_pixel = _world_per_pixel(whole_camera, volume, whole)
    drawn = state.setdefault("levels_drawn", {})
    layers, values, skipped = [], {}, {}  # a readout: each level's values, and the rays its mask left out
    bricks_drawn, bricked_levels = 0, {}
    gl_state = renderer.GetRenderWindow().GetState()
    box = [0, 0, 0, 0]  # the render's scissor box (from the window's origin: MIPVolumeMapper's observer)
    gl_state.vtkglGetIntegerv(GL_SCISSOR_BOX, box)
    depth = _capture_depth(state, renderer)
    masks = {}
    tests = {}  # per deciding layer: its refinement test, (edge, structure) or, GPU masks, the refine pass's texture
    silhouette = _silhouette(image, volume, camera, viewport, base_isd)
    # masks on the GPU: the finer levels' shader reads the coarse picture as a texture (no readback)
    on_gpu = adaptive and not readout and _gpu_masks_possible(state, renderer)
    coarse = _coarse_textures(state, renderer, viewport) if on_gpu else None
    if on_gpu:
        copy_drawn(renderer, viewport, coarse["framebuffers"]["before"])
    before = _read_texels(renderer, viewport, viewport[2:]) if adaptive and not readout and not on_gpu else None
    beneath = _beneath_texture(state, renderer, before) if before is not None else None  # the CPU masks' levels
    # the picture beneath, to go over the deciding levels' stretch past the volume's outline near the fovea
    cover = (_outline_cover(renderer, plan, silhouette, coarse, before)
             if adaptive and not readout and silhouette is not None else None)
    for index, layer in enumerate(plan.layers):
        level = layer.level
        if adaptive and index >= 1:  # this level's rays: where the deciding level's picture asks for them
            decider = content_adaptive.decided_by(plan, index)
            if decider == index - 1:  # that level was just drawn: its refinement test
                # with the texels where the data says a full-quality ray may meet structure its rays missed
                bound = (_structure_bound(state, plan, decider, image, volume, camera, viewport,
                                          _above_floor(state, image, volume))
                         if decider == content_adaptive.structure_source(plan) else None)
                if coarse is not None:
                    coarse["bound"] = _bound_texture(state, renderer, plan.layers[decider].grid, bound)
                tests[decider] = _refinement_test(state, renderer, volume, viewport, plan, decider, tolerance,
                                                  (values, skipped) if readout else None, coarse, before)
                if coarse is None and bound is not None:
                    tests[decider] = (tests[decider][0], tests[decider][1] | bound)
            if not on_gpu:
                masks[level] = content_adaptive.refinement_mask(*tests[decider], plan, layer)
        footprint = world_per_pixel * viewport[3] / max(layer.grid[1], 1)
        volume_level, distance = volume_pyramid.level_sampling(
            level, footprint, base_distance, spacings, cells, params["peripheral_sampling"])
        masked = adaptive and index > 0
        kind = ("coarse" if on_gpu else "masked") if masked else None
        level_input = _pyramid(state, image)[volume_level] if volume_level else image
        component = mapper.GetComponent() if not volume_level else -1  # coarse levels hold one component
        limit = bricked_foveated.level_limit(mapper, level_input)
        values_texture = colours_texture = None
        if limit:  # beyond one texture: composite the level's rays over its bricks first
            try:
                level_input, values_texture, colours_texture = _composite_level(
                    mapper, state, volume, renderer, level, volume_level, level_input, component, distance, plan,
                    layer, silhouette if len(plan.layers) > 1 else None)
            except Exception as error:  # noqa: BLE001  (an observer: reported as mipcast's refusals are)
                _report_problem(mapper, state, f"drawing level {level} in bricks of {limit} points per axis "
                                               f"failed: {error!r}")
                if depth is not None:
                    depth.Deactivate()
                return
            component = -1
            source = state["brick_sources"][volume_level]
            bricks_drawn += object_state(source["mapper"]).get("bricks_drawn", 0)
            bricked_levels[level] = [brick["mapper"].GetInput() for brick in _level_bricks(source, limit)]
        key = level if not masked else (level, kind)
        key = (key, "bricks") if limit else key
        entry = drawn.get(key) or _new_level(params["method"], kind, bricks=bool(limit))
        drawn[key] = entry
        level_mapper, level_volume = entry["mapper"], entry["volume"]
        if depth is not None and level_mapper.GetDepthTexture() is not depth:
            level_mapper.SetSharedDepthTexture(depth)
        if isinstance(level_mapper, AnalyticMIPVolumeMapper):  # levels reading one volume share its packed copy
            level_mapper.SetCornerPacker(state.setdefault("packers", {}).setdefault(volume_level, CornerPacker()))
        if level_mapper.GetInput() is not level_input:
            level_mapper.SetInputData(level_input)
        if level_mapper.GetComponent() != component:
            level_mapper.SetComponent(component)
        _copy_settings(mapper, volume, level_mapper, level_volume, entry["matrix"], distance,
                       layer.image_sample_distance)
        if limit:  # the bricks honoured the cropping (shaders/foveated_brick_hooks.glsl)
            level_mapper.SetCropping(False)
            level_volume.GetShaderProperty().GetFragmentCustomUniforms().SetUniformf(
                "u_mc_fovNoValueDiscard", 1.0 if mapper.GetCropping() else 0.0)
        _set_uniforms(level_volume, plan, layer, kept)
        band = _set_silhouette(level_volume, silhouette if len(plan.layers) > 1 else None, layer.level)
        object_state(level_mapper)["draw_camera"] = camera
        if readout:
            object_state(level_mapper)["exact_readout"] = True
            level_mapper.RenderToImageOn()
            level_mapper.SetDepthImageScalarTypeToFloat()
        # the band reaches the periphery: no scissor, unless it lies wholly outside the view (the volume
        # fills it), when every pixel the box leaves out is one the cast range discards anyway
        band_in_view = band and foveation.band_reaches_view(silhouette, plan.aspect)
        scissor = layer.scissor if not readout and not band_in_view else None
        # a reduced level in a tile of a bigger picture: drawn one coarse ray beyond the tile's inner
        # edges and cropped, so its magnification next to a seam blends the next tile's rays
        # (mipcast.mappers.foveated_tiles); its own framebuffer is cleared whole: no scissor
        margins = (foveated_tiles.tile_margins(renderer, viewport, layer.image_sample_distance)
                   if kind is None and not readout and values_texture is None else None)
        if margins is not None:
            scissor = None
        if scissor is not None:
            gl_state.vtkglScissor(*scissor)
        mask_texture = None
        bound = ()
        if kind is not None:  # a cast ray is drawn over the picture beneath (shaders/foveated_paint_beneath.glsl)
            uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
            uniforms.SetUniform2f("u_mc_fovViewSize", [float(viewport[2]), float(viewport[3])])
            uniforms.SetUniformf("u_mc_fovPaintBeneath", 0.0 if readout else 1.0)
        if kind == "coarse":
            bound = (tests[decider], _fovea_texture(state, renderer, plan, layer), coarse["before"])
            _bind_coarse(level_mapper, level_volume, bound)
            _set_coarse_uniforms(level_volume, plan.layers[decider], layer)
        elif level in masks and (not readout or values_texture is not None):
            # (a level drawn from bricks reads one sampler more: its mask must be bound, readout or not)
            mask_texture = _mask_texture(state, renderer, level, masks[level])
            mask_texture.Activate()
            if beneath is not None:
                beneath.Activate()
                bound = (beneath,)
            level_state = object_state(level_mapper)
            level_state["mask_unit"] = (mask_texture.GetTextureUnit(),
                                        (beneath if beneath is not None else mask_texture).GetTextureUnit())
            if level_state.get("mask_unit_built") not in (None, level_state["mask_unit"]):
                # VTK sets our sampler only when it builds the shader: rebuild it for the new unit
                level_mapper._install_pieces(level_volume)
        if values_texture is not None:
            values_texture.Activate()
            object_state(level_mapper)["values_unit"] = values_texture.GetTextureUnit()
        if colours_texture is not None:  # a DEMIP level: its composited colours too
            colours_texture.Activate()
            object_state(level_mapper)["colours_unit"] = colours_texture.GetTextureUnit()
        try:
            if kind == "coarse" or values_texture is not None:
                _render_coarse_level(level_mapper, level_volume, renderer, plan, layer)
            elif margins is not None:
                foveated_tiles.draw_extended(state, renderer, viewport, margins, level_volume, plan, layer, depth,
                                             lambda: level_volume.RenderVolumetricGeometry(renderer))
            elif not (level == 0 and refine_keep.keeps_all(kept)):  # a converged still frame keeps the whole view
                level_volume.RenderVolumetricGeometry(renderer)
        finally:
            if values_texture is not None:
                values_texture.Deactivate()
            if colours_texture is not None:
                colours_texture.Deactivate()
            if mask_texture is not None:
                mask_texture.Deactivate()
            for texture in bound:
                texture.Deactivate()
            if scissor is not None:
                gl_state.vtkglScissor(*box)
            if readout:
                values[level] = _level_values(level_mapper, layer.grid)
                if level in masks:  # rays the mask left out, but level 0's silhouette band (cast whatever the mask)
                    cast = masks[level] | (foveation.silhouette_band(plan, silhouette, layer.grid) if band else False)
                    values[level][~cast] = np.nan
                    skipped[level] = ~cast
                object_state(level_mapper).pop("exact_readout", None)
                level_mapper.RenderToImageOff()
        layers.append((level, volume_level, distance, level_input))
    if cover is not None:
        _draw_cover(renderer, state, viewport, *cover)
    if depth is not None:
        depth.Deactivate()
    if kept is not None:
        refine_keep.draw_kept(state, renderer, viewport, plan, kept, eye)
    if keeping:
        refine_keep.keep_picture(state, renderer, viewport, plan, scene, kept, eye)
    else:
        refine_keep.forget(state)
    state["bricks_drawn"] = bricks_drawn
    if readout:
        state["readout"] = (plan, values, skipped)
    matrix = vtkMatrix4x4()
    matrix.DeepCopy(volume.GetMatrix())
    snapshot = vtkCamera()
    snapshot.DeepCopy(camera)
    state["frame"] = {"plan": plan, "camera": snapshot, "matrix": matrix, "image": image, "silhouette": silhouette,
                      "layers": layers, "cells": cells, "method": params["method"], "masks": masks,
                      "base_distance": base_distance, "base_isd": base_isd, "bricked": bricked_levels,
                      "kept": kept}
    if on_gpu:  # the masks for GetLastFrameCost: read back only when asked, after the frame
        state["frame"]["coarse"] = {"tests": tests, "window": renderer.GetRenderWindow()}


def _report_problem(mapper, state, problem: str) -> None:
    """Report a failed frame as mipcast's refusals are: a VTK error naming it, kept as the render problem."""
    from vtkmodules.vtkCommonCore import vtkOutputWindow

    state["render_problem"] = problem
    vtkOutputWindow.GetInstance().DisplayErrorText(f"{type(mapper).__name__}: {problem}\n")
    mapper.InvokeEvent(vtkCommand.ErrorEvent)


def _refine(state, params, image, volume, camera, viewport, gaze, radius, advance=True, scene=None):
    """(radius, foveation) of this frame under progressive refinement; counts the still frames.

    A frame is still when the camera, the volume's matrix and property, the
    input, the settings, the viewport and the gaze are those of the frame
    before.  Still frame ``k`` of ``N`` widens the disc linearly from the
    foveal radius to the farthest viewport corner; frame ``N`` is full
    quality (one level, as with foveation off).
    """
    return refined_radius(params, viewport, gaze, radius, refine_step(state, params, image, volume, camera, viewport,
                                                                      gaze, advance, scene))


def counts_frame(renderer, camera) -> bool:
    """Whether this draw starts a new frame for progressive refinement: not the second eye of a stereo pair.

    A stereo window draws each renderer twice a frame, the left eye first
    (``vtkCamera.GetLeftEye()`` 1, then 0); both eyes then show the same
    still frame.  A window showing the right eye alone counts its one draw.
    """
    from vtkmodules.vtkRenderingCore import VTK_STEREO_RIGHT

    window = renderer.GetRenderWindow()
    if window is None or not window.GetStereoRender() or window.GetStereoType() == VTK_STEREO_RIGHT:
        return True
    return bool(camera.GetLeftEye())


def refine_step(state, params, image, volume, camera, viewport, gaze, advance: bool = True,
                scene: Optional[tuple] = None) -> int:
    """This frame's still-frame count under progressive refinement (0: something changed), kept in ``state``.

    ``advance``: False for the second eye of a stereo pair (:func:`counts_frame`), which draws the
    step its left eye drew; ``scene``: :func:`scene_signature`, if the caller has it."""
    scene = scene_signature(params, image, volume, camera, viewport) if scene is None else scene
    signature = (scene, tuple(gaze),
                 tuple(sorted((k, repr(v)) for k, v in params.items() if k.startswith("gaze_"))))
    frames = int(params["refinement_frames"])
    still = state.get("refine_signature") == signature
    step = min(state.get("refine_step", 0) + int(advance), frames) if still else 0
    state["refine_signature"], state["refine_step"] = signature, step
    return step


def scene_signature(params, image, volume, camera, viewport) -> tuple:
    """What a frame's picture depends on besides the gaze: camera, volume matrix and property, input,
    viewport and the settings but the gaze's (``gaze_*``); the stillness test of :func:`refine_step`
    adds the gaze."""
    # to 7 digits: vtkWindowToImageFilter renders with the view angle off by 1e-9 relative
    return (_rounded(camera.GetPosition() + camera.GetFocalPoint() + camera.GetViewUp()
                     + (camera.GetViewAngle(), camera.GetParallelScale(), camera.GetEyeAngle())),
            camera.GetParallelProjection(),  # not the eye: both eyes of a stereo pair refine
            tuple(matrix_array(volume.GetMatrix()).ravel()), _property_stamp(volume.GetProperty()),
            image.GetAddressAsString("vtkObjectBase"), image.GetMTime(), tuple(viewport),
            tuple(sorted((k, repr(v)) for k, v in params.items() if not k.startswith("gaze_"))))


def refined_radius(params, viewport, gaze, radius, step: int):
    """(radius, foveation) of still frame ``step`` (:func:`refine_step`): the disc widened linearly from the
    foveal radius to the farthest viewport corner; full quality from ``refinement_frames`` on."""
    frames = int(params["refinement_frames"])
    if step >= frames:
        return radius, False
    x0, y0, width, height = viewport
    aspect = width / height
    farthest = max(math.hypot((cx - gaze[0]) * aspect, cy - gaze[1]) for cx in (0.0, 1.0) for cy in (0.0, 1.0))
    return radius + max(farthest - radius, 0.0) * step / frames, params["foveation"]


def _property_stamp(prop) -> tuple:
    """What of a volume property changes the picture (its own MTime moves at the first render).
    Reads only: ``GetGradientOpacity`` would create a function on the user's property.  A discretizable
    colour map (ParaView's) rebuilds its table at its first lookup after a change, which moves its MTime,
    and a lookup may come later in the frame (the skipping floor, :mod:`mipcast.core.transfer_bounds`):
    it is built here first (as any render would), so the next frame reads the same stamp."""
    gradient = prop.GetGradientOpacity(0).GetMTime() if prop.HasGradientOpacity(0) else None
    colour = prop.GetRGBTransferFunction(0)
    colour.Build()  # a no-op for a plain vtkColorTransferFunction
    return (colour.GetMTime(), prop.GetScalarOpacity(0).GetMTime(),
            gradient, prop.GetInterpolationType(), prop.GetShade(0),
            prop.GetScalarOpacityUnitDistance(0))


def _rounded(values) -> tuple:
    return tuple(float(f"{float(v):.7g}") for v in values)


def _capture_depth(state, renderer):
    """Copy the depth buffer once for all levels; the bound texture they share, or None.

    Each VTK volume mapper copies the whole window's depth buffer before it
    draws (so rays stop at opaque geometry): about 4 ms at 512^2 on llvmpipe,
    as much as a coarse level's rays.  A private mapper with a 2x2x2 input,
    cropped to nothing, does that copy once per frame; the levels read its
    texture (``SetSharedDepthTexture``), bound while they draw.
    """
    entry = state.get("depth_capture")
    if entry is None:
        dummy = vtkImageData()
        dummy.SetDimensions(2, 2, 2)
        dummy.SetSpacing(1e-3, 1e-3, 1e-3)
        dummy.AllocateScalars(10, 1)  # VTK_FLOAT
        dummy.GetPointData().GetScalars().Fill(0.0)
        capture = vtkOpenGLGPUVolumeRayCastMapper()  # VTK's own: no mipcast checks per frame
        capture.SetBlendModeToMaximumIntensity()
        capture.SetInputData(dummy)
        capture.SetCropping(True)
        capture.SetCroppingRegionPlanes(0.0, 1e-3, 0.0, 1e-3, 0.0, 1e-3)
        capture.SetCroppingRegionFlags(0)  # every fragment is cropped away: it draws nothing
        capture_volume = vtkVolume()
        capture_volume.SetMapper(capture)
        entry = state["depth_capture"] = {"mapper": capture, "volume": capture_volume}
    entry["volume"].RenderVolumetricGeometry(renderer)
    depth = entry["mapper"].GetDepthTexture()
    if depth is not None:
        depth.Activate()
    return depth


def _new_level(method: str, kind: Optional[str] = None, bricks: bool = False) -> dict:
    """A private level mapper and volume; ``kind``: None, ``"masked"`` (CPU mask) or ``"coarse"`` (GPU mask).

    ``bricks``: a level drawn from its rays' values composited over bricks
    (:mod:`mipcast.mappers.bricked_foveated`), whatever the layer method.
    """
    base = _value_class(bricked_foveated.is_demip(method)) if bricks else FOVEATION_LAYERS[method].factory
    level_mapper = _level_class(base, kind)()
    level_volume = vtkVolume()
    level_mapper.Attach(level_volume)
    if bricks:
        level_mapper.AddObserver(vtkCommand.UpdateShaderEvent, bricked_foveated.bind_values_sampler)
    if kind == "masked":
        level_mapper.AddObserver(vtkCommand.UpdateShaderEvent, _bind_mask_sampler)
    elif kind == "coarse":
        level_mapper.AddObserver(vtkCommand.UpdateShaderEvent, _bind_coarse_samplers)
    return {"mapper": level_mapper, "volume": level_volume, "matrix": vtkMatrix4x4()}


@calldata_type(VTK_OBJECT)
def _bind_coarse_samplers(level_mapper, event, program) -> None:
    """Point a GPU-masked level's samplers (the refine pass's texture, fovea spans, the picture beneath) at their
    textures' units."""
    level_state = object_state(level_mapper)
    units = level_state.get("coarse_units")
    if program is not None and units is not None and min(units) >= 0:
        for name, unit in zip(("u_mc_fovRefine", "u_mc_fovFovea", "u_mc_fovBeneath"), units):
            program.SetUniformi(name, int(unit))
        level_state["samplers_set"] = True


_VALUE_CLASSES: dict = {}


def _value_class(colours: bool = False):
    """The mapper class of a level drawn from composited values (``shaders/foveated_brick_hooks.glsl``).

    ``colours``: a DEMIP level's, drawing the composited colours too
    (``shaders/foveated_brick_color.glsl``).
    """
    if colours not in _VALUE_CLASSES:
        from mipcast.mappers.mip import sampled_projection_mapper

        _VALUE_CLASSES[colours] = (sampled_projection_mapper(bricked_foveated.HOOKS, bricked_foveated.COLOUR)
                                   if colours else sampled_projection_mapper(bricked_foveated.HOOKS))
    return _VALUE_CLASSES[colours]


def _level_bricks(source, limit) -> list:
    """A level source's brick entries (one per brick; a DEMIP layer's phase-1 and phase-2 entries both)."""
    if bricked_foveated.is_demip(source["method"]):
        return [entry for pair in bricked_foveated.demip_bricks(source, limit) for entry in pair]
    return bricked_draw.bricks_of(source["mapper"], limit)


def _composite_level(mapper, state, volume, renderer, level, volume_level, level_input, component, distance, plan,
                     layer, silhouette):
    """A level beyond the texture limit: its rays composited over its bricks, uploaded for its draw.

    Returns (the 2 x 2 x 2 box the level draws, the values' texture, a DEMIP
    layer's colours' texture or None); see :mod:`mipcast.mappers.bricked_foveated`.
    """
    source = bricked_foveated.level_source(state, volume_level, mapper._parameters()["method"])
    source_mapper = source["mapper"]
    if source_mapper.GetInput() is not level_input:
        source_mapper.SetInputData(level_input)
    if source_mapper.GetComponent() != component:
        source_mapper.SetComponent(component)
    _copy_settings(mapper, volume, source_mapper, source["volume"], source["matrix"], distance,
                   layer.image_sample_distance)
    object_state(source_mapper)["draw_camera"] = renderer.GetActiveCamera()
    limit = bricked_foveated.level_limit(mapper, level_input)
    for brick in _level_bricks(source, limit):  # they cast only the level's rays
        _set_uniforms(brick["volume"], plan, layer)
        _set_silhouette(brick["volume"], silhouette, layer.level)
    colours = None
    if bricked_foveated.is_demip(source["method"]):
        values, rgba = bricked_foveated.composite_demip(source, volume, renderer, limit, layer.image_sample_distance,
                                                        layer.grid)
        colours = bricked_foveated.level_texture(state, renderer, level, rgba, "colours")
    else:
        values = bricked_foveated.composite(source, volume, renderer, limit, layer.image_sample_distance,
                                            layer.grid)
    rendered = source_mapper.GetRenderedInput()
    boxes = state.setdefault("value_boxes", {})
    stamp = (rendered.GetAddressAsString("vtkObjectBase"), rendered.GetMTime())
    if boxes.get(volume_level, (None,))[0] != stamp:
        boxes[volume_level] = (stamp, bricked_foveated.value_box(rendered))
    normalised = bricked_foveated.normalised_values(values, rendered)
    return boxes[volume_level][1], bricked_foveated.level_texture(state, renderer, level, normalised, "values"), colours


def _render_coarse_level(level_mapper, level_volume, renderer, plan, layer) -> None:
    """Draw a GPU-masked level, its samplers pointing at the coarse pictures.

    VTK invokes UpdateShaderEvent (where :func:`_bind_coarse_samplers` sets
    the samplers) on every draw except one that (re)builds the shader, whose
    samplers would all read unit 0.  So when the level may need a build (its
    first draw, or anything VTK's rebuild test watches changed since the last
    draw that set the samplers), it is first drawn with every ray discarded
    (the cast range emptied, the silhouette band off: the picture does not change), which builds the
    shader; the real draw then sets them.
    """
    level_state = object_state(level_mapper)
    stamp = (level_mapper.GetMTime(), level_volume.GetShaderProperty().GetShaderMTime(),
             level_volume.GetProperty().GetMTime(), renderer.GetLights().GetMTime(),
             renderer.GetRenderWindow().GetAddressAsString("vtkObjectBase"))
    if level_state.get("sampler_stamp") != stamp:
        level_state["sampler_probes"] = level_state.get("sampler_probes", 0) + 1
        uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
        uniforms.SetUniformf("u_mc_fovCastFrom", _FAR)
        uniforms.SetUniformf("u_mc_fovCastTo", _FAR)
        band = reference(0.0)
        uniforms.GetUniformf("u_mc_fovSilOn", band)
        # nor the silhouette band: level 0 casts it whatever the mask (and a level drawn from bricks reads the
        # samplers there too), so the probe drew it once more, blended over the real draw's (a frame that
        # probes: 93 % of the pixels within 1 grey, up to 35 off along the box's outline)
        uniforms.SetUniformf("u_mc_fovSilOn", 0.0)
        try:
            level_volume.RenderVolumetricGeometry(renderer)
        finally:
            _set_uniforms(level_volume, plan, layer)
            uniforms.SetUniformf("u_mc_fovSilOn", float(band))
    level_state["samplers_set"] = False
    level_volume.RenderVolumetricGeometry(renderer)
    if level_state["samplers_set"]:
        level_state["sampler_stamp"] = stamp
    else:  # built again by the real draw: this frame's masks read the wrong textures; probe next frame
        level_state.pop("sampler_stamp", None)
        level_state["sampler_misses"] = level_state.get("sampler_misses", 0) + 1


def _bind_coarse(level_mapper, level_volume, textures) -> None:
    """Activate the refine pass's texture and the fovea spans for a GPU-masked level; note their units.

    :func:`_bind_coarse_samplers` points the samplers at these units on
    every draw (see :func:`_render_coarse_level` for the draw that builds
    the shader).
    """
    for texture in textures:
        texture.Activate()
    object_state(level_mapper)["coarse_units"] = tuple(texture.GetTextureUnit() for texture in textures)


def _set_coarse_uniforms(level_volume, coarser, layer) -> None:
    """The grids ``foveated_coarse_dec``'s mask lookup needs: the level drawn before (``coarser``) and this one."""
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    for name, value in (("u_mc_fovCoarseW", coarser.grid[0]), ("u_mc_fovCoarseH", coarser.grid[1]),
                        ("u_mc_fovLevelW", layer.grid[0]), ("u_mc_fovLevelH", layer.grid[1])):
        uniforms.SetUniformi(name, int(value))


def _gpu_masks_possible(state, renderer) -> bool:
    """Whether the refinement masks can be built on the GPU (else the CPU path reads the picture back).

    Not with a VTK that cannot say which framebuffer is being drawn, and
    not when ``object_state(mapper)["masks_on_cpu"]`` asks for the CPU
    reference path.
    """
    if state.get("masks_on_cpu"):
        return False
    return hasattr(renderer.GetRenderWindow().GetState(), "GetCurrentDrawFramebufferState")


def _coarse_textures(state, renderer, viewport) -> dict:
    """The two viewport-sized RGBA8 textures a deciding level's picture is copied into (after, before the frame)."""
    window = renderer.GetRenderWindow()
    entry = state.get("coarse_textures")
    size = (viewport[2], viewport[3])
    if entry is None or entry["window"] is not window or entry["size"] != size:
        entry = {"window": window, "size": size, "framebuffers": {}}
        for name in ("after", "before"):
            entry[name], entry["framebuffers"][name] = texture_target(window, *size)
        state["coarse_textures"] = entry
    return entry


def _fovea_texture(state, renderer, plan, layer):
    """A level's fovea spans (:func:`mipcast.core.content_adaptive.fovea_spans`) as a float texture, one texel a row.

    Made again only when the grid, gaze, aspect or fovea change: it does not depend on the picture.
    """
    from vtkmodules.vtkCommonCore import VTK_FLOAT
    from vtkmodules.vtkRenderingOpenGL2 import vtkTextureObject

    window = renderer.GetRenderWindow()
    radius = content_adaptive.fovea_radius(plan, layer)
    key = (window.GetAddressAsString("vtkObjectBase"), tuple(layer.grid), tuple(plan.gaze), plan.aspect, radius)
    cache = state.setdefault("fovea_textures", {})
    cached = cache.get(layer.level)
    if cached is not None and cached[0] == key and cached[1].GetContext() is window:
        return cached[1]
    texture = cached[1] if cached is not None and cached[1].GetContext() is window else vtkTextureObject()
    texture.SetContext(window)
    texture.SetMinificationFilter(vtkTextureObject.Nearest)
    texture.SetMagnificationFilter(vtkTextureObject.Nearest)
    spans = np.ascontiguousarray(content_adaptive.fovea_spans(layer.grid, plan, radius), dtype=np.float32)
    texture.Create2DFromRaw(spans.shape[0], 1, 2, VTK_FLOAT, spans)
    texture.Deactivate()
    cache[layer.level] = (key, texture)
    return texture


def _download_texels(window, texture, grid) -> np.ndarray:
    """A coarse-picture texture (RGB, uint8) at the texel centres of ``grid``, top row first.

    A readback: only :meth:`FoveatedVolumeMapper.GetLastFrameCost` calls it, after the frame.
    """
    return content_adaptive.coarse_texels(_download_picture(window, texture), grid)


def _download_picture(window, texture) -> np.ndarray:
    """An RGBA8 picture texture's RGB (uint8), top row first (a readback)."""
    window.MakeCurrent()
    width, height = texture.GetWidth(), texture.GetHeight()
    data = np.zeros((height, width, 4), np.uint8)
    texture.Download().Download2D(VTK_UNSIGNED_CHAR, data, [width, height], 4, [0, 0])
    return data[::-1, :, :3]


def _outline_cover(renderer, plan, silhouette, coarse, before) -> Optional[tuple]:
    """(box, RGBA8 patch): the picture from before the frame's first level over the deciding levels' stretch past
    the volume's outline, with level 0's weight (:func:`mipcast.core.content_adaptive.outline_cover`), or None
    (and no readback) where the outline does not reach level 0's disc.  ``coarse``: the GPU path's copies (that
    picture read back from them), else ``before``, the picture the CPU path read."""
    cover = content_adaptive.outline_cover(plan, silhouette)
    if cover is None:
        return None
    (x0, y0, columns, rows), weight = cover
    picture = _download_picture(renderer.GetRenderWindow(), coarse["before"]) if coarse is not None else before
    height = picture.shape[0]
    beneath = picture[height - y0 - rows:height - y0, x0:x0 + columns]
    return (x0, y0, columns, rows), content_adaptive.cover_patch(weight, beneath.astype(np.float64)).astype(np.uint8)


def _draw_cover(renderer, state, viewport, box, patch) -> None:
    """Draw an :func:`_outline_cover` patch over its box of the viewport, premultiplied "over"."""
    x0, y0, columns, rows = box
    _, _, width, height = viewport
    window = renderer.GetRenderWindow()
    texture = kept_texture(state, "outline_texture", window)
    texture.Create2DFromRaw(columns, rows, 4, VTK_UNSIGNED_CHAR, np.ascontiguousarray(patch[::-1]))
    left, right = 2.0 * x0 / width - 1.0, 2.0 * (x0 + columns) / width - 1.0
    bottom, top = 2.0 * y0 / height - 1.0, 2.0 * (y0 + rows) / height - 1.0
    draw_over(window, texture, viewport, [([0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0],
                                           [left, bottom, 0.0, right, bottom, 0.0, right, top, 0.0, left, top, 0.0])])


def _gpu_masks(frame) -> dict:
    """The refinement masks of a frame whose masks the GPU built: its refine passes' tests read back."""
    coarse, plan = frame["coarse"], frame["plan"]
    tests = {}
    for source, texture in coarse["tests"].items():
        test = _download_texels(coarse["window"], texture, plan.layers[source].grid)
        tests[source] = test[..., 0] > 127, test[..., 1] > 127
    return {layer.level: content_adaptive.refinement_mask(*tests[content_adaptive.decided_by(plan, index)], plan, layer)
            for index, layer in enumerate(plan.layers) if index >= 1}


def _refinement_test(state, renderer, volume, viewport, plan, source, tolerance, values, coarse, before):
    """The refinement test of the picture the layers up to ``source`` left, at that layer's texels.

    ``values``: the levels' float readouts and the rays their masks left out
    (a readout: their composite, over black); else ``coarse``: the GPU's copies (after, before), the refine
    pass's texture returned; else the picture read back, ``before`` the
    viewport's before the frame's first level.
    """
    grid = plan.layers[source].grid
    if values is not None:
        so_far = foveation.composite_values(plan._replace(layers=plan.layers[:source + 1]), *values)
        after = _grey_texels(volume, content_adaptive.coarse_texels(so_far, grid))
        return content_adaptive.refinement_test(after, np.zeros_like(after), tolerance)
    if coarse is not None:
        copy_drawn(renderer, viewport, coarse["framebuffers"]["after"])
        return refine_pass.run_refine_pass(state, renderer.GetRenderWindow(), coarse, viewport, grid, tolerance,
                                           whole_fovea=content_adaptive.casts_whole_fovea(plan, plan.layers[source + 1]))
    after = _read_texels(renderer, viewport, grid)
    return content_adaptive.refinement_test(after, content_adaptive.coarse_texels(before, grid), tolerance)


@calldata_type(VTK_OBJECT)
def _bind_mask_sampler(level_mapper, event, program) -> None:
    """Point the masked level's ``u_mc_fovMask`` and ``u_mc_fovBeneath`` at their textures' units.

    VTK invokes UpdateShaderEvent when it builds the shader, not every frame;
    :func:`_draw` re-installs the pieces (a rebuild) should the unit change.
    """
    units = object_state(level_mapper).get("mask_unit")
    if program is not None and units is not None and min(units) >= 0:
        program.SetUniformi("u_mc_fovMask", int(units[0]))
        program.SetUniformi("u_mc_fovBeneath", int(units[1]))  # (the mask's own unit when nothing is beneath)
        object_state(level_mapper)["mask_unit_built"] = units


def _read_texels(renderer, viewport, grid) -> np.ndarray:
    """The window's picture (RGB, uint8) at the texel centres of ``grid``, top row first."""
    x0, y0, width, height = viewport
    pixels = vtkUnsignedCharArray()
    renderer.GetRenderWindow().GetRGBACharPixelData(x0, y0, x0 + width - 1, y0 + height - 1, 0, pixels)
    picture = vtk_to_numpy(pixels).reshape(height, width, 4)[::-1, :, :3]
    return content_adaptive.coarse_texels(picture, grid)


def _grey_texels(volume, values) -> np.ndarray:
    """Grey levels (over black) the volume's transfer functions give a level's float readout."""
    prop = volume.GetProperty()
    colour, opacity = prop.GetRGBTransferFunction(0), prop.GetScalarOpacity(0)
    finite = np.nan_to_num(values, nan=-np.inf)
    low, high = colour.GetRange()
    points = np.linspace(low, high, 1024)
    table = np.array([colour.GetColor(v)[0] * opacity.GetValue(v) for v in points])
    grey = np.interp(np.clip(finite, low, high), points, table) * 255.0
    return np.where(np.isfinite(finite), np.round(grey), 0.0)[..., None]


def _structure_bound(state, plan, source, image, volume, camera, viewport, boxes) -> np.ndarray:
    """Texels of ``plan.layers[source]`` near the fovea whose cell a full-quality ray above the floor may cross.

    :func:`mipcast.core.structure_bound.splat_texels` of ``boxes``, the
    blocks of ``image`` above the transfer functions' floor
    (:func:`_above_floor`; an MPI rank: its piece's); the texels that matter
    are those a fovea ray's nearest texel can be (eccentricity below the
    plan's ``start`` plus half a texel's diagonal).  The boxes' projections
    (:func:`~mipcast.core.structure_bound.texel_ranges`) are kept in
    ``state`` while the view and the boxes stand still: a moving gaze
    alone only splats them again (vessels 128³ at 1024²: 4.0 -> 2.2 ms a
    frame; head CT: 7.5 -> 3.0 ms; cProfile, 10 frames, the gaze moving).
    """
    grid = plan.layers[source].grid
    columns, rows = grid
    reach = 0.5 * math.hypot(plan.aspect / columns, 1.0 / rows)
    near_fovea = foveation.eccentricity(grid, plan.gaze, plan.aspect) < plan.start + reach
    to_ndc = structure_bound.ndc_from_index(image, camera, viewport[2] / viewport[3], volume.GetMatrix())
    view = (to_ndc.tobytes(), tuple(grid))
    kept = state.get("bound_ranges")
    if kept is None or kept[0] is not boxes or kept[1] != view:
        kept = state["bound_ranges"] = (boxes, view, structure_bound.texel_ranges(boxes, to_ndc, grid))
    return structure_bound.splat_ranges(kept[2], grid, near_fovea)


def _above_floor(state, image, volume, values=None, data_range=None, dims=None) -> np.ndarray:
    """The boxes of ``image``'s drawn values above the transfer functions' floor, in its index space.

    :func:`mipcast.core.structure_bound.blocks_above`; blocks of one cell
    (volumes up to :data:`~mipcast.core.structure_bound.FLAG_CELLS` + 1
    points along every axis) shrunk to their half cells above the floor
    (:func:`~mipcast.core.structure_bound.halved_cells`).  The block maxima
    are kept per input, the boxes per floor.  ``values`` (z, y, x; NaN:
    missing), ``data_range`` and ``dims`` (the whole volume's, for the
    block size) for an MPI rank's piece; by default the input's prepared
    values, range and dimensions.  Cell scalars (values one point fewer per
    axis: drawn on the cell centres, VTK filling the outer half cell with
    the edge values) give whole blocks grown by half a cell on every side:
    ``[lower, upper + 1]``.
    """
    component = state["preparer"].GetComponent() if "preparer" in state else -1
    dims = tuple(dims or image.GetDimensions())
    block = structure_bound.block_size(dims)
    stamp = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime(), component, data_range, dims)
    cached = state.get("block_maxima")
    if cached is None or cached[0] != stamp:
        if values is None:
            prepared = prepare_scalars(image, component)
            values, data_range = prepared.values, (prepared.low, prepared.high)
        values = np.asarray(values)
        if np.issubdtype(values.dtype, np.floating) and np.isnan(values).any():  # missing: below every value
            values = np.where(np.isnan(values), -np.inf, values)
        drawn = values.shape[::-1]
        cells = tuple(drawn) != tuple(image.GetDimensions())
        halving = values if block == 1 and not cells else None   # (a large volume's values are not kept)
        cached = state["block_maxima"] = (stamp, block_maxima(values, block), data_range, drawn, cells, halving, {})
    _, maxima, (low, high), drawn, cells, halving, found = cached
    floor = constant_ends(volume.GetProperty(), low, high)[0]
    if floor not in found:
        found.clear()  # one transfer function at a time
        boxes = structure_bound.blocks_above(maxima, floor, block, drawn)
        if cells:  # cell scalars: centre i at index i + 1/2, and half a cell more each side
            boxes[:, 1] += 1.0
        elif halving is not None:
            boxes = structure_bound.halved_cells(halving, boxes, floor)
        found[floor] = boxes
    return found[floor]


def _bound_texture(state, renderer, grid, bound: Optional[np.ndarray]):
    """The structure bound as a 2D texture of ``grid`` (:func:`_mask_texture`; zeros for None)."""
    return _mask_texture(state, renderer, "bound", np.zeros(tuple(grid)[::-1], bool) if bound is None else bound)


def _beneath_texture(state, renderer, before: np.ndarray):
    """The viewport's picture before the frame's first level (RGB, top row first) as an RGBA8 texture."""
    height, width = before.shape[:2]
    texture = kept_texture(state, "beneath_texture", renderer.GetRenderWindow())
    data = np.empty((height, width, 4), np.uint8)
    data[..., :3], data[..., 3] = before[::-1], 255
    texture.Create2DFromRaw(width, height, 4, VTK_UNSIGNED_CHAR, np.ascontiguousarray(data))
    return texture


def _mask_texture(state, renderer, level, mask):
    """A bool grid (a level's refinement mask, the structure bound) as a nearest-filtered 2D texture (bottom row
    first), kept per ``level`` key."""
    textures = state.setdefault("mask_textures", {})
    window = renderer.GetRenderWindow()
    texture = kept_texture(textures, level, window)
    data = np.ascontiguousarray(mask[::-1], dtype=np.uint8) * np.uint8(255)
    rows, columns = data.shape
    texture.Create2DFromRaw(columns, rows, 1, VTK_UNSIGNED_CHAR, data)
    return texture


_LEVEL_CLASSES: dict = {}


def _level_class(base, kind: Optional[str] = None):
    """``base`` (a mipcast mapper class) plus the foveation pieces.

    ``kind``: None, ``"masked"`` (refinement mask uploaded from the CPU) or
    ``"coarse"`` (mask built in the shader from the coarse picture).
    """
    cls = _LEVEL_CLASSES.get((base, kind))
    if cls is None:
        extra = {None: FoveatedVolumeMapper.LEVEL_PIECES, "masked": FoveatedVolumeMapper.MASKED_LEVEL_PIECES,
                 "coarse": FoveatedVolumeMapper.COARSE_LEVEL_PIECES}[kind]

        def GetShaderPieces(self):
            return tuple(base.GetShaderPieces(self)) + extra

        name = f"Foveated{base.__name__}{(kind or '').capitalize()}Level"
        members = {"__doc__": f"One pyramid level of a FoveatedVolumeMapper rendering with {base.__name__}.",
                   "GetShaderPieces": GetShaderPieces}
        if kind is not None and base.MISSING_PIECE == "missing_exit":  # coarser levels lie beneath: paint, not skip
            members["MISSING_PIECE"] = "foveated_missing_flag"
        cls = type(name, (base,), members)
        _LEVEL_CLASSES[(base, kind)] = cls
    return cls


def _copy_settings(mapper, volume, level_mapper, level_volume, matrix, distance, image_distance):
    level_mapper.SetAutoAdjustSampleDistances(False)
    if level_mapper.GetSampleDistance() != distance:
        level_mapper.SetSampleDistance(distance)
    if level_mapper.GetImageSampleDistance() != image_distance:
        level_mapper.SetImageSampleDistance(image_distance)
    follow_volume(mapper, volume, level_mapper, level_volume, matrix)
    clip_uniforms.copy_clipping(mapper, level_mapper)


def _set_uniforms(level_volume, plan, layer, kept=None) -> None:
    """The level's foveation uniforms; ``kept``: the :class:`refine_keep.Disc` level 0 casts no ray in."""
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    refine_keep.set_skip_uniforms(uniforms, kept if layer.level == 0 else None)
    uniforms.SetUniform2f("u_mc_fovGaze", [float(plan.gaze[0]), float(plan.gaze[1])])
    uniforms.SetUniformf("u_mc_fovAspect", float(plan.aspect))
    uniforms.SetUniformf("u_mc_fovCastFrom", max(layer.cast_from, -_FAR))
    uniforms.SetUniformf("u_mc_fovCastTo", min(layer.cast_to, _FAR))
    uniforms.SetUniformf("u_mc_fovStart", float(plan.start))
    uniforms.SetUniformf("u_mc_fovGain", float(plan.gain))
    uniforms.SetUniformf("u_mc_fovTop", float(plan.top))
    uniforms.SetUniformf("u_mc_fovLevel", float(layer.level))


def _silhouette(image, volume, camera, viewport, base_isd):
    """The volume box's projected outline for the silhouette band: (edges (6, 3), unit), or None.

    ``unit`` is one level-0 ray spacing in viewport heights.  None when a
    corner lies behind the camera or the outline is degenerate.
    """
    if image is None or image.GetNumberOfPoints() == 0:
        return None
    dims = image.GetDimensions()
    corners = []
    for i in (0, dims[0] - 1):
        for j in (0, dims[1] - 1):
            for k in (0, dims[2] - 1):
                point = [0.0, 0.0, 0.0]
                image.TransformIndexToPhysicalPoint(i, j, k, point)
                corners.append(point + [1.0])
    aspect = viewport[2] / viewport[3]
    world = matrix_array(volume.GetMatrix()) @ np.array(corners).T
    clip = matrix_array(camera.GetCompositeProjectionTransformMatrix(aspect, -1.0, 1.0)) @ world
    if np.any(clip[3] <= 1e-12):
        return None
    points = ((clip[:2] / clip[3]).T + 1.0) / 2.0
    edges = foveation.silhouette_edges(points, aspect)
    return None if edges is None else (edges, float(base_isd) / viewport[3])


def _set_silhouette(level_volume, silhouette, level: int) -> bool:
    """Upload the silhouette band's uniforms (shaders/foveated_skip.glsl); True when level 0 casts the band."""
    uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
    edges, unit = silhouette if silhouette is not None else (np.tile([0.0, 0.0, _FAR], (6, 1)), 0.0)
    uniforms.SetUniformf("u_mc_fovSilOn", 1.0 if silhouette is not None and level == 0 else 0.0)
    uniforms.SetUniformf("u_mc_fovSilUnit", float(unit))
    for index, edge in enumerate(edges):
        uniforms.SetUniform3f(f"u_mc_fovSil{index}", [float(v) for v in edge])
    return silhouette is not None and level == 0


def _level_values(level_mapper, grid) -> np.ndarray:
    """A level's float readout in data units, (rows, columns) top row first, NaN = no ray."""
    image = vtkImageData()
    level_mapper.GetDepthImage(image)
    scalars = image.GetPointData().GetScalars()
    columns, rows = grid
    if scalars is None:
        return np.full((rows, columns), np.nan)
    columns, rows, _ = image.GetDimensions()
    normalised = float_readout.decode(vtk_to_numpy(scalars).reshape(rows, columns)[::-1])
    return float_readout.to_data_units(normalised, level_mapper.GetRenderedInput().GetPointData().GetScalars())


def _whole_viewport(renderer, viewport):
    """(whole, to_tile, scale): the renderer's viewport in the whole picture's pixels, a function
    taking a gaze in its normalised coordinates to this tile's, and the whole viewport's height
    in tile viewport heights.  Without tiles (a window's TileScale of 1): ``viewport``, the
    identity and 1.

    A tile's pixels are the whole picture's pixels (VTK's tiles: TileScale, TileViewport), so
    eccentricities measured in the tile's viewport heights are ``scale`` times the whole
    picture's, across and up alike (the tile's aspect ratio is its own).
    """
    window = renderer.GetRenderWindow()
    sx, sy = window.GetTileScale()
    if (sx, sy) == (1, 1):
        return viewport, (lambda gaze: gaze), 1.0
    columns, rows = window.GetSize()  # the whole picture (the window's size times the tile scale)
    tile = window.GetTileViewport()
    vp = renderer.GetViewport()
    rx0, ry0 = vp[0] * columns, vp[1] * rows
    rw, rh = max((vp[2] - vp[0]) * columns, 1.0), max((vp[3] - vp[1]) * rows, 1.0)
    tx0, ty0 = tile[0] * columns, tile[1] * rows
    x0, y0, width, height = viewport

    def to_tile(gaze):
        return ((gaze[0] * rw + rx0 - tx0 - x0) / width, (gaze[1] * rh + ry0 - ty0 - y0) / height)

    whole = (int(round(rx0)), int(round(ry0)), int(round(rw)), int(round(rh)))
    return whole, to_tile, rh / height


def _whole_camera(camera, renderer):
    """The camera of the whole picture while a tile renders: vtkWindowToImageFilter narrows the
    view angle (``2 atan(tan(a / 2) / scale)``) or the parallel scale by the tile scale and moves
    the window centre for each tile; undone here (the whole picture's window centre taken as
    the middle)."""
    scale = float(renderer.GetRenderWindow().GetTileScale()[1])
    whole = vtkCamera()
    whole.DeepCopy(camera)
    whole.SetWindowCenter(0.0, 0.0)
    if camera.GetParallelProjection():
        whole.SetParallelScale(camera.GetParallelScale() * scale)
    else:
        half = math.tan(math.radians(camera.GetViewAngle()) / 2.0) * scale
        whole.SetViewAngle(math.degrees(2.0 * math.atan(half)))
    return whole


def _current_gaze(state, renderer, camera, viewport):
    """(gaze, foveal radius) for this frame from the gaze source."""
    x0, y0, width, height = viewport
    params = state["parameters"]
    radius = params["foveal_radius"]
    source = state["gaze_source"]
    if source == "stream":
        poll = state.get("gaze_callable")
        if poll is not None:
            sample = poll()
            if sample is not None:
                stream = state["gaze_stream"]
                stream.aspect = width / height
                if stream.last_time is None or float(sample[0]) > stream.last_time:
                    import time

                    if stream.push(*sample):
                        state["gaze_pushed"] = time.perf_counter()
        stream = state.get("gaze_stream")
        if stream is not None and stream.gaze is not None:
            stream.aspect = width / height
            if "gaze_pushed" in state:
                state["gaze_in_frame"] = state.pop("gaze_pushed")
            return tuple(stream.gaze), radius
    if source == "mouse" and state.get("mouse_seen"):
        interactor = state["mouse"][0].Get()
        if interactor is not None:
            x, y = interactor.GetEventPosition()
            return ((x + 0.5 - x0) / width, (y + 0.5 - y0) / height), radius
    if source == "region" and params["region_of_interest"] is not None:
        centre, reach = _project_region(params["region_of_interest"], camera, width / height)
        if centre is not None:
            return centre, max(radius, reach)
    return tuple(params["gaze_point"]), radius


def _project_region(bounds, camera, aspect):
    """Projected centre (normalised viewport) and radius (viewport heights) of a world box."""
    matrix = matrix_array(camera.GetCompositeProjectionTransformMatrix(aspect, -1, 1))
    corners = np.array([[x, y, z, 1.0] for x in bounds[0:2] for y in bounds[2:4] for z in bounds[4:6]])
    centre = np.array([0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]),
                       0.5 * (bounds[4] + bounds[5]), 1.0])
    points = np.vstack([centre, corners]) @ matrix.T
    if np.any(points[:, 3] <= 0):  # behind a perspective camera
        return None, 0.0
    xy = 0.5 * (points[:, :2] / points[:, 3:] + 1.0)
    reach = np.hypot((xy[1:, 0] - xy[0, 0]) * aspect, xy[1:, 1] - xy[0, 1]).max()
    return (float(xy[0, 0]), float(xy[0, 1])), float(reach)


def _level_cap(image, volume, camera, viewport) -> int:
    """Coarsest image level whose texels still fit MIN_TEXELS times into the volume's projection."""
    x0, y0, width, height = viewport
    bounds = volume.GetBounds()
    matrix = matrix_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
    corners = np.array([[x, y, z, 1.0] for x in bounds[0:2] for y in bounds[2:4] for z in bounds[4:6]])
    points = corners @ matrix.T
    if np.any(points[:, 3] <= 0):
        return 99  # the camera is inside or behind: the volume covers the view
    ndc = points[:, :2] / points[:, 3:]
    low, high = np.clip(ndc.min(axis=0), -1, 1), np.clip(ndc.max(axis=0), -1, 1)
    extent = min(0.5 * (high[0] - low[0]) * width, 0.5 * (high[1] - low[1]) * height)
    level = 0
    while 2 ** (level + 1) * foveation.MIN_TEXELS <= extent:
        level += 1
    return level


def _world_per_pixel(camera, volume, viewport) -> float:
    """Model-space length one pixel spans at the volume's centre."""
    height = viewport[3]
    if camera.GetParallelProjection():
        world = 2.0 * camera.GetParallelScale() / height
    else:
        centre = np.array(volume.GetCenter())
        direction = np.array(camera.GetDirectionOfProjection())
        depth = abs(float(np.dot(centre - np.array(camera.GetPosition()), direction)))
        world = 2.0 * depth * math.tan(math.radians(camera.GetViewAngle()) / 2.0) / height
    matrix = matrix_array(volume.GetMatrix())[:3, :3]
    scale = float(np.cbrt(abs(np.linalg.det(matrix)))) or 1.0
    return world / scale


def _walks_cells(method: str) -> bool:
    return FOVEATION_LAYERS[method].walks_cells


def _pyramid(state, image) -> list:
    params = state["parameters"]
    component = state["preparer"].GetComponent() if "preparer" in state else -1
    stamp = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime(), params["number_of_levels"], component)
    cached = state.get("pyramid")
    if cached is None or cached[0] != stamp:
        cached = (stamp, volume_pyramid.build_max_pyramid(image, params["number_of_levels"], component))
        state["pyramid"] = cached
    return cached[1]


def _frame_cost(frame) -> dict:
    plan, image, camera, matrix = frame["plan"], frame["image"], frame["camera"], frame["matrix"]
    size = plan.viewport[2:]
    if "coarse" in frame and not frame.get("masks"):
        frame["masks"] = _gpu_masks(frame)
    masks = frame.get("masks", {})
    rows = []
    band_rays = 0
    for (level, volume_level, distance, level_input), layer in zip(frame["layers"], plan.layers):
        e = foveation.eccentricity(layer.grid, plan.gaze, plan.aspect)
        cast = (e >= layer.cast_from) & (e < layer.cast_to)
        if level in masks:
            cast &= masks[level]
        kind = {"cells_of": level_input} if frame["cells"] else {"sample_distance": distance}
        if len(plan.layers) > 1 and level == 0:  # the silhouette band: level 0 casts it too
            added = foveation.silhouette_band(plan, frame.get("silhouette"), layer.grid)
            if added.any():
                band_rays = grid_cost(image, camera, size, layer.grid, volume_matrix=matrix,
                                      cast=added & ~cast, **kind)[0]
            cast = cast | added
        if level == 0:  # a frame that kept the last frame's full-quality disc (refine_keep) skipped it
            cast &= ~refine_keep.skipped(frame.get("kept"), layer.grid, plan)
        rays, samples = grid_cost(image, camera, size, layer.grid, volume_matrix=matrix, cast=cast, **kind)
        brick_rays = 0
        if level in frame.get("bricked", {}):  # its bricks cast the level's range and band, not its mask
            reach = (e >= layer.cast_from) & (e < layer.cast_to)
            if len(plan.layers) > 1 and level == 0:
                reach = reach | foveation.silhouette_band(plan, frame.get("silhouette"), layer.grid)
            brick_rays = sum(grid_cost(piece, camera, size, layer.grid, volume_matrix=matrix, cast=reach,
                                       sample_distance=distance)[0] for piece in frame["bricked"][level])
        rows.append({"level": level, "volume_level": volume_level, "grid": tuple(layer.grid),
                     "sample_distance": None if frame["cells"] else distance,
                     "rays": rays, "samples": samples, "brick_rays": brick_rays})
    kind = {"cells_of": image} if frame["cells"] else {"sample_distance": frame["base_distance"]}
    full_grid = foveation.level_grid(size[0], size[1], 0, frame["base_isd"])
    full_rays, full_samples = grid_cost(image, camera, size, full_grid, volume_matrix=matrix, **kind)
    rays = sum(r["rays"] for r in rows)
    samples = sum(r["samples"] for r in rows)
    return {"method": frame["method"], "unit": "cells" if frame["cells"] else "samples",
            "rays": rays, "samples": samples, "full_rays": full_rays, "full_samples": full_samples,
            "band_rays": band_rays, "brick_rays": sum(r["brick_rays"] for r in rows),
            "ray_ratio": full_rays / rays if rays else math.inf,
            "sample_ratio": full_samples / samples if samples else math.inf,
            "levels": rows}


def _parameter(name: str):
    return next(p for p in parameter_tables.FOVEATED if p.name == name)
