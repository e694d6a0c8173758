"""Foveated (gaze-directed) rendering: full quality where the user looks, fewer rays and samples elsewhere."""
from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Optional, Sequence

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkCommand, vtkWeakReference
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkRenderingCore import vtkCamera

from mipcast.core import content_adaptive, foveation, parameter_tables
from mipcast.core.gaze import GazeStream
from mipcast.core.parameter_tables import FOVEATION_LAYERS
from mipcast.core.parameters import parameter_accessors
from mipcast.mappers import (bricked_draw, bricked_foveated, float_readout, foveated_levels, foveated_masks,
                             foveated_tiles, refine_keep, volume_pyramid)
from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.core.camera_rays import matrix_array
from mipcast.mappers.corner_packing import CornerPacker
from mipcast.mappers.mip import MIPVolumeMapper
from mipcast.core.object_state import object_state
from mipcast.mappers.private_draw import GL_SCISSOR_BOX, auto_sample_distance, copy_drawn, rendering_renderer
from mipcast.core.ray_cost import grid_cost
from mipcast.mappers.stereo import draw_for

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
    #: Pieces every level adds to its method's own (:mod:`mipcast.mappers.foveated_levels`).
    LEVEL_PIECES = foveated_levels.LEVEL_PIECES
    #: Pieces of the finer levels with content-adaptive ray density (ContentTolerance > 0).
    MASKED_LEVEL_PIECES = foveated_levels.MASKED_LEVEL_PIECES
    #: The same with the refinement mask built on the GPU from the deciding level's picture (no readback).
    COARSE_LEVEL_PIECES = foveated_levels.COARSE_LEVEL_PIECES
    PARAMETERS = parameter_tables.FOVEATED

    def _samples_rays(self) -> bool:
        """Whether its levels' method samples its rays (the cell walks do not)."""
        return not foveated_levels.walks_cells(self._parameters()["method"])

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
        for level in foveated_levels.pyramid(state, image) if self.GetFoveation() else [image]:
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
        scalars = self.GetRenderedInput().GetPointData().GetScalars()
        raw = float_readout.encode(float_readout.from_data_units(blended, scalars))
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
    """Draw one foveated frame: the levels of its plan, coarsest first, each with its private mapper.

    :func:`_begin_frame` plans it; with content-adaptive density each finer
    level's rays are decided from the picture drawn so far
    (:func:`_decide_rays`); :func:`_draw_level` draws a level and
    :func:`_end_frame` finishes the frame.
    """
    frame = _begin_frame(mapper, state, volume, renderer)
    for index, layer in enumerate(frame.plan.layers):
        if frame.adaptive and index >= 1:  # this level's rays: where the deciding level's picture asks for them
            _decide_rays(state, volume, renderer, frame, index, layer)
        if not _draw_level(mapper, state, volume, renderer, frame, index, layer):
            if frame.depth is not None:
                frame.depth.Deactivate()
            return
    _end_frame(state, volume, renderer, frame)


def _begin_frame(mapper, state, volume, renderer) -> SimpleNamespace:
    """What this frame's levels share: its plan (gaze, refinement step, content level, tiles), the sampling,
    the picture kept from the last frame, the depth buffer's copy and, with content-adaptive density, the
    pictures its masks are decided from (:func:`_begin_masks`)."""
    image = mapper._masked_input()  # a mask's hidden points missing in every level and its pyramid
    params = mapper._parameters()
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    viewport = (x0[0], y0[0], max(width[0], 1), max(height[0], 1))
    camera = renderer.GetActiveCamera()
    whole, to_tile, tile_scale = foveated_tiles.whole_viewport(renderer, viewport)
    whole_camera = foveated_tiles.whole_camera(camera, renderer) if tile_scale != 1.0 else camera
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
    # a tile of a bigger picture (SaveScreenshot beyond the window's size): the plan is made in
    # this tile's viewport, with the gaze, radius and falloff of the whole picture carried over
    cap = foveated_levels.level_cap(image, volume, whole_camera, whole)
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
        # object_state(mapper)["no_content_level"]: measured against the content level (the benchmarks' variant
        # "content-adaptive 2 grey, no content level"; docs/foveation.md), not a setting
        plan = content_adaptive.adaptive_plan(plan, plan.layers[0].level if state.get("no_content_level") else cap)
    gl_state = renderer.GetRenderWindow().GetState()
    box = [0, 0, 0, 0]  # the render's scissor box (from the window's origin: MIPVolumeMapper's observer)
    gl_state.vtkglGetIntegerv(GL_SCISSOR_BOX, box)
    cells = foveated_levels.walks_cells(params["method"])
    spacings = volume_pyramid.pyramid_voxel_sizes(image, params["number_of_levels"])
    world_per_pixel = foveated_levels.world_per_pixel(whole_camera, volume, whole)
    base_distance = auto_sample_distance(image, volume) if auto else float(mapper.GetSampleDistance())
    depth = foveated_levels.capture_depth(state, renderer)  # the depth buffer copied once for all levels
    frame = SimpleNamespace(
        image=image, params=params, viewport=viewport, camera=camera, renderer=renderer, plan=plan, readout=readout,
        keeping=keeping, scene=scene, kept=kept, eye=eye, tolerance=tolerance, adaptive=adaptive,
        cells=cells, spacings=spacings, world_per_pixel=world_per_pixel, base_isd=base_isd,
        base_distance=base_distance, gl_state=gl_state, box=box, depth=depth,
        silhouette=foveated_levels.silhouette(image, volume, camera, viewport, base_isd),
        layers=[], values={}, skipped={},  # a readout: each level's values, and the rays its mask left out
        bricks_drawn=0, bricked_levels={}, masks={},
        tests={})  # per deciding layer: its refinement test, (edge, structure) or, GPU masks, the refine pass's texture
    _begin_masks(state, renderer, frame)
    return frame


def _begin_masks(state, renderer, frame) -> None:
    """Where content-adaptive masks come from: on the GPU (the finer levels' shader reads the coarse picture as a
    texture, no readback; ``frame.coarse``) or from the picture read back (``frame.before``, ``frame.beneath``);
    and the picture beneath over the deciding levels' stretch past the volume's outline (``frame.cover``)."""
    adaptive = frame.adaptive and not frame.readout
    frame.on_gpu = adaptive and foveated_masks.gpu_masks_possible(state, renderer)
    frame.coarse = foveated_masks.coarse_textures(state, renderer, frame.viewport) if frame.on_gpu else None
    if frame.on_gpu:
        copy_drawn(renderer, frame.viewport, frame.coarse["framebuffers"]["before"])
    frame.before = (foveated_masks.read_texels(renderer, frame.viewport, frame.viewport[2:])
                    if adaptive and not frame.on_gpu else None)
    # (the CPU masks' levels paint their rays over it)
    frame.beneath = (foveated_masks.beneath_texture(state, renderer, frame.before)
                     if frame.before is not None else None)
    frame.cover = (foveated_masks.outline_cover(renderer, frame.plan, frame.silhouette, frame.coarse, frame.before)
                   if adaptive and frame.silhouette is not None else None)


def _decide_rays(state, volume, renderer, frame, index: int, layer) -> None:
    """Layer ``index``'s rays with content-adaptive density: the refinement test of its deciding level's picture
    (run once, when that level was just drawn) and, on the CPU path, the layer's mask."""
    plan = frame.plan
    decider = content_adaptive.decided_by(plan, index)
    if decider == index - 1:  # that level was just drawn: its refinement test
        # with the texels where the data says a full-quality ray may meet structure its rays missed
        bound = None
        if decider == content_adaptive.structure_source(plan):
            boxes = foveated_masks.above_floor_boxes(state, frame.image, volume)
            bound = foveated_masks.structure_texels(state, plan, decider, frame.image, volume, frame.camera,
                                                    frame.viewport, boxes)
        if frame.coarse is not None:
            frame.coarse["bound"] = foveated_masks.bound_texture(state, renderer, plan.layers[decider].grid, bound)
        test = foveated_masks.refinement_test(state, renderer, volume, frame.viewport, plan, decider,
                                              frame.tolerance, (frame.values, frame.skipped) if frame.readout else None,
                                              frame.coarse, frame.before)
        if frame.coarse is None and bound is not None:
            test = (test[0], test[1] | bound)
        frame.tests[decider] = test
    if not frame.on_gpu:
        frame.masks[layer.level] = content_adaptive.refinement_mask(*frame.tests[decider], plan, layer)


def _draw_level(mapper, state, volume, renderer, frame, index: int, layer) -> bool:
    """Draw ``layer``: its private mapper set up (:func:`_level_entry`), its textures bound, its scissor box set;
    a readout keeps its values.  False when drawing its bricks failed (reported)."""
    plan, level = frame.plan, layer.level
    source = _level_source(mapper, state, volume, renderer, frame, layer)
    if source is None:
        return False
    volume_level, distance, level_input, values_texture, colours_texture = source
    kind = ("coarse" if frame.on_gpu else "masked") if frame.adaptive and index > 0 else None
    entry, band = _level_entry(mapper, state, volume, frame, layer, kind, source)
    level_mapper, level_volume = entry["mapper"], entry["volume"]
    # the band reaches the periphery: no scissor, unless it lies wholly outside the view (the volume
    # fills it), when every pixel the box leaves out is one the cast range discards anyway
    band_in_view = band and foveation.band_reaches_view(frame.silhouette, plan.aspect)
    scissor = layer.scissor if not frame.readout and not band_in_view else None
    # a reduced level in a tile of a bigger picture: drawn one coarse ray beyond the tile's inner
    # edges and cropped, so its magnification next to a seam blends the next tile's rays
    # (mipcast.mappers.foveated_tiles); its own framebuffer is cleared whole: no scissor
    margins = (foveated_tiles.tile_margins(renderer, frame.viewport, layer.image_sample_distance)
               if kind is None and not frame.readout and values_texture is None else None)
    if margins is not None:
        scissor = None
    if scissor is not None:
        frame.gl_state.vtkglScissor(*scissor)
    bound = _bind_level_textures(state, renderer, frame, index, layer, kind, entry, values_texture, colours_texture)
    try:
        if kind == "coarse" or values_texture is not None:
            foveated_levels.render_coarse_level(level_mapper, level_volume, renderer, plan, layer, frame.kept)
        elif margins is not None:
            foveated_tiles.draw_extended(state, renderer, frame.viewport, margins, level_volume, plan, layer,
                                         frame.depth, lambda: level_volume.RenderVolumetricGeometry(renderer))
        elif not (level == 0 and refine_keep.keeps_all(frame.kept)):  # a converged still frame keeps the whole view
            level_volume.RenderVolumetricGeometry(renderer)
    finally:
        for texture in bound:
            texture.Deactivate()
        if scissor is not None:
            frame.gl_state.vtkglScissor(*frame.box)
        if frame.readout:
            _keep_level_values(frame, layer, level_mapper, band)
    frame.layers.append((level, volume_level, distance, level_input))
    return True


def _level_source(mapper, state, volume, renderer, frame, layer):
    """(volume level, sample distance, input, values texture, colours texture) of ``layer``: the pyramid level its
    footprint asks for, its rays first composited over bricks where it exceeds one texture (then the values
    texture, and a DEMIP layer's colours, are drawn from a 2 x 2 x 2 box); None when that failed (reported)."""
    params, level = frame.params, layer.level
    footprint = frame.world_per_pixel * frame.viewport[3] / max(layer.grid[1], 1)
    volume_level, distance = volume_pyramid.level_sampling(
        level, footprint, frame.base_distance, frame.spacings, frame.cells, params["peripheral_sampling"])
    level_input = foveated_levels.pyramid(state, frame.image)[volume_level] if volume_level else frame.image
    limit = bricked_foveated.level_limit(mapper, level_input)
    if not limit:
        return volume_level, distance, level_input, None, None
    component = mapper.GetComponent() if not volume_level else -1  # coarse levels hold one component
    try:
        level_input, values_texture, colours_texture = foveated_levels.composite_level(
            mapper, state, volume, renderer, level, volume_level, level_input, component, distance, frame.plan,
            layer, frame.silhouette if len(frame.plan.layers) > 1 else None)
    except Exception as error:  # noqa: BLE001  (an observer: reported as mipcast's refusals are)
        _report_problem(mapper, state, f"drawing level {level} in bricks of {limit} points per axis "
                                       f"failed: {error!r}")
        return None
    source = state["brick_sources"][volume_level]
    frame.bricks_drawn += object_state(source["mapper"]).get("bricks_drawn", 0)
    frame.bricked_levels[level] = [brick["mapper"].GetInput()
                                   for brick in foveated_levels.level_bricks(source, limit)]
    return volume_level, distance, level_input, values_texture, colours_texture


def _level_entry(mapper, state, volume, frame, layer, kind, source) -> tuple:
    """(entry, band): ``layer``'s private mapper and volume (made at its first draw), given its input and the
    user's settings, its foveation uniforms set; ``band``: whether it casts the silhouette band."""
    volume_level, distance, level_input, values_texture, _ = source
    bricks = values_texture is not None
    component = mapper.GetComponent() if not volume_level and not bricks else -1  # coarse levels: one component
    key = layer.level if kind is None else (layer.level, kind)
    key = (key, "bricks") if bricks else key
    drawn = state.setdefault("levels_drawn", {})
    entry = drawn.get(key) or foveated_levels.new_level(frame.params["method"], kind, bricks=bricks)
    drawn[key] = entry
    level_mapper, level_volume = entry["mapper"], entry["volume"]
    if frame.depth is not None and level_mapper.GetDepthTexture() is not frame.depth:
        level_mapper.SetSharedDepthTexture(frame.depth)
    if isinstance(level_mapper, AnalyticMIPVolumeMapper):  # levels reading one volume share its packed copy
        level_mapper.SetCornerPacker(state.setdefault("packers", {}).setdefault(volume_level, CornerPacker()))
    if level_mapper.GetInput() is not level_input:
        level_mapper.SetInputData(level_input)
    if level_mapper.GetComponent() != component:
        level_mapper.SetComponent(component)
    foveated_levels.copy_settings(mapper, volume, level_mapper, level_volume, entry["matrix"], distance,
                                  layer.image_sample_distance)
    if bricks:  # the bricks honoured the cropping (shaders/foveated_brick_hooks.glsl)
        level_mapper.SetCropping(False)
    foveated_levels.set_uniforms(level_volume, frame.plan, layer, frame.kept)
    band = foveated_levels.set_silhouette(level_volume, frame.silhouette if len(frame.plan.layers) > 1 else None,
                                          layer.level)
    draw_for(level_mapper, frame.camera, frame.renderer)
    if frame.readout:
        object_state(level_mapper)["exact_readout"] = True
        level_mapper.RenderToImageOn()
        level_mapper.SetDepthImageScalarTypeToFloat()
    return entry, band


def _bind_level_textures(state, renderer, frame, index, layer, kind, entry, values_texture, colours_texture) -> list:
    """Activate the textures ``layer``'s shader reads (its mask or the refine pass's test, the picture beneath,
    composited values and colours) and note their units; returns them, to deactivate after the draw."""
    plan, level = frame.plan, layer.level
    level_mapper, level_volume = entry["mapper"], entry["volume"]
    level_state = object_state(level_mapper)
    bound = []
    if kind is not None:  # a cast ray is drawn over the picture beneath (shaders/foveated_paint_beneath.glsl)
        uniforms = level_volume.GetShaderProperty().GetFragmentCustomUniforms()
        uniforms.SetUniform2f("u_mc_fovViewSize", [float(frame.viewport[2]), float(frame.viewport[3])])
        uniforms.SetUniformf("u_mc_fovPaintBeneath", 0.0 if frame.readout else 1.0)
    if kind == "coarse":
        decider = content_adaptive.decided_by(plan, index)
        bound = [frame.tests[decider], foveated_masks.fovea_texture(state, renderer, plan, layer),
                 frame.coarse["before"]]
        foveated_levels.bind_coarse(level_mapper, level_volume, bound)
        foveated_levels.set_coarse_uniforms(level_volume, plan.layers[decider], layer)
    elif level in frame.masks and (not frame.readout or values_texture is not None):
        # (a level drawn from bricks reads one sampler more: its mask must be bound, readout or not)
        mask_texture = foveated_masks.mask_texture(state, renderer, level, frame.masks[level])
        mask_texture.Activate()
        bound.append(mask_texture)
        if frame.beneath is not None:
            frame.beneath.Activate()
            bound.append(frame.beneath)
        level_state["mask_unit"] = (mask_texture.GetTextureUnit(), bound[-1].GetTextureUnit())
        if level_state.get("mask_unit_built") not in (None, level_state["mask_unit"]):
            # VTK sets our sampler only when it builds the shader: rebuild it for the new unit
            level_mapper._install_pieces(level_volume)
    if values_texture is not None:
        values_texture.Activate()
        level_state["values_unit"] = values_texture.GetTextureUnit()
        bound.append(values_texture)
    if colours_texture is not None:  # a DEMIP level: its composited colours too
        colours_texture.Activate()
        level_state["colours_unit"] = colours_texture.GetTextureUnit()
        bound.append(colours_texture)
    return bound


def _keep_level_values(frame, layer, level_mapper, band: bool) -> None:
    """A readout: the level's float values, NaN where its mask cast no ray (level 0's silhouette band is cast
    whatever the mask)."""
    level = layer.level
    frame.values[level] = foveated_levels.level_values(level_mapper, layer.grid)
    if level in frame.masks:
        cast = frame.masks[level] | (foveation.silhouette_band(frame.plan, frame.silhouette, layer.grid)
                                     if band else False)
        frame.values[level][~cast] = np.nan
        frame.skipped[level] = ~cast
    object_state(level_mapper).pop("exact_readout", None)
    level_mapper.RenderToImageOff()


def _end_frame(state, volume, renderer, frame) -> None:
    """Cover the outline, release the depth copy, draw and keep the picture for the next frame (refine_keep), and
    note the frame (``state["frame"]``: :meth:`FoveatedVolumeMapper.GetLastFrameCost`; a readout's values)."""
    plan, viewport = frame.plan, frame.viewport
    if frame.cover is not None:
        foveated_masks.draw_cover(renderer, state, viewport, *frame.cover)
    if frame.depth is not None:
        frame.depth.Deactivate()
    if frame.kept is not None:
        refine_keep.draw_kept(state, renderer, viewport, plan, frame.kept, frame.eye)
    if frame.keeping:
        refine_keep.keep_picture(state, renderer, viewport, plan, frame.scene, frame.kept, frame.eye)
    else:
        refine_keep.forget(state)
    state["bricks_drawn"] = frame.bricks_drawn
    if frame.readout:
        state["readout"] = (plan, frame.values, frame.skipped)
    matrix = vtkMatrix4x4()
    matrix.DeepCopy(volume.GetMatrix())
    snapshot = vtkCamera()
    snapshot.DeepCopy(frame.camera)
    state["frame"] = {"plan": plan, "camera": snapshot, "matrix": matrix, "image": frame.image,
                      "silhouette": frame.silhouette, "layers": frame.layers, "cells": frame.cells,
                      "method": frame.params["method"], "masks": frame.masks, "base_distance": frame.base_distance,
                      "base_isd": frame.base_isd, "bricked": frame.bricked_levels, "kept": frame.kept}
    if frame.on_gpu:  # the masks for GetLastFrameCost: read back only when asked, after the frame
        state["frame"]["coarse"] = {"tests": frame.tests, "window": renderer.GetRenderWindow()}


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


def _frame_cost(frame) -> dict:
    plan, image, camera, matrix = frame["plan"], frame["image"], frame["camera"], frame["matrix"]
    size = plan.viewport[2:]
    if "coarse" in frame and not frame.get("masks"):
        frame["masks"] = foveated_masks.gpu_masks(frame)
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
