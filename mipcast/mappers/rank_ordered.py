"""DEMIP's ordered projections (LMIP, attenuated MIP, MIDA) composited exactly over the ranks of a render view.

:mod:`mipcast.mappers.rank_composite` composites DEMIP's ``projection="mip"``
by a MAX and a MIN over the ranks.  LMIP, attenuated MIP and MIDA depend on
the order along the whole ray; on one GPU beyond the texture limit they are
drawn brick after brick front to back, each brick continuing the scan from a
per-pixel state the bricks in front left
(:mod:`mipcast.mappers.demip_ordered_bricks`).  Over the ranks it is the same
problem with a rank per brick, and the same brick mappers draw it:

1. every rank's piece extent (in the whole extent, and whether its box is in
   view) is gathered by a SUM over the ranks (each rank fills its own row);
2. every rank computes the same front-to-back order of the pieces in view
   (:func:`front_to_back`: a plane splitting the pieces into two groups,
   nearer group first, recursively: exact for grids and k-d splits);
3. turn k: the rank whose piece is k-th draws it from the state so far
   (LMIP: running maximum and end flag; attenuated: best attenuated material
   and crossed material; MIDA: colour, opacity and running material) and the
   new state goes to every rank by a SUM where the others contribute zeros
   (exact: x + 0 = x; "no value" travels as -1e300);
4. LMIP's phase 2 (the first same-material sample) is DEMIP's MIN over the
   ranks; then depth, Eq. 1, the colour sphere on the CPU, as the bricks.

Every rank enters the same collectives the same number of times: the
projection is agreed first (a rank without a mapper takes it from the
others), a rank out of view or without data contributes zeros in every turn,
a failure (a rank's draw raising, pieces that cannot be ordered) is a flag in
the reduced array, so all ranks give up at the same collective with one
message, never a hang.

Examples
--------
>>> front_to_back([(0, 4, 0, 8, 0, 8), (4, 8, 0, 8, 0, 8)], {"u_mc_rayDirection": [-1.0, 0.0, 0.0],
...                                                         "u_mc_rayEye": [0.0, 0.0, 0.0, 0.0]})
[1, 0]
"""
from __future__ import annotations

from typing import Optional, Sequence, Tuple

import numpy as np

from mipcast.core.parameter_tables import DEMIP_SETTINGS

#: The projections drawn here, turn by turn; "mip" is rank_composite's (MAX / MIN).
ORDERED = ("lmip", "attenuated", "mida")
_CODES = {"mip": 0, "lmip": 1, "attenuated": 2, "mida": 3}
_LOW, _HIGH = -1.0e300, 1.0e300
#: The state each projection hands from turn to turn (the channels of the shared array).
STATE = {"lmip": ("running", "ended"), "attenuated": ("best", "crossed"),
         "mida": ("red", "green", "blue", "opacity", "material")}


def front_to_back(extents: Sequence[Sequence[int]], rays: dict) -> list:
    """Indices of the disjoint boxes ``extents`` in an order every ray crosses them in (front to back).

    Each box owns the cells ``[e0, e1)`` along each axis (pieces share a
    layer of points).  A plane between two groups of boxes (every box on one
    side) puts the group on the eye's side first (orthographic: against the
    ray direction; perspective: the eye's side of the plane); each group is
    ordered the same way.  ``rays``: :func:`mipcast.mappers.brick_rays.ray_uniforms`
    (point-index space).  Raises ValueError when no such plane exists.

    Examples
    --------
    >>> boxes = [(0, 4, 0, 8, 0, 0), (4, 8, 0, 4, 0, 0), (4, 8, 4, 8, 0, 0)]   # a k-d split, not a grid
    >>> front_to_back(boxes, {"u_mc_rayDirection": [1.0, -1.0, 0.0], "u_mc_rayEye": [0.0, 0.0, 0.0, 0.0]})
    [0, 2, 1]
    >>> front_to_back(boxes, {"u_mc_rayDirection": [0.0] * 3, "u_mc_rayEye": [6.0, 2.0, 0.0, 1.0]})
    [1, 2, 0]
    """
    boxes = [tuple(int(v) for v in e) for e in extents]
    eye, direction = rays["u_mc_rayEye"], rays["u_mc_rayDirection"]

    def order(members: list) -> list:
        if len(members) <= 1:
            return list(members)
        for axis in range(3):
            for plane in sorted({boxes[i][2 * axis] for i in members}):
                low = [i for i in members if boxes[i][2 * axis + 1] <= plane]
                high = [i for i in members if boxes[i][2 * axis] >= plane]
                if not low or not high or len(low) + len(high) != len(members):
                    continue
                if eye[3] > 0.5:
                    low_first = eye[axis] < plane
                else:
                    low_first = direction[axis] >= 0.0
                first, second = (low, high) if low_first else (high, low)
                return order(first) + order(second)
        raise ValueError(f"the ranks' pieces {[boxes[i] for i in members]} cannot be ordered front to back "
                         "(no plane separates them): split the volume into blocks of a grid (ParaView's "
                         "image readers and D3 do)")
    return order(list(range(len(boxes))))


def agreed_projection(mapper, reduce) -> Tuple[Optional[str], Optional[str]]:
    """(the ranks' DEMIP projection, None) or (None, why): one MAX over the ranks (a rank without a mapper
    takes the others').

    >>> from mipcast.mappers.demip import DEMIPVolumeMapper
    >>> from mipcast.mappers.rank_composite import single
    >>> agreed_projection(DEMIPVolumeMapper(), single)
    ('mip', None)
    """
    code = _CODES.get(mapper.GetProjection(), -2) if mapper is not None else None
    local = np.array([_LOW, _LOW]) if code is None else np.array([float(code), -float(code)])
    high, low = reduce(local, "max")
    if high <= 0.5 * _LOW:
        return None, None  # no rank has a mapper
    if high != -low or -low < 0:
        return None, "the ranks' DEMIP projections differ (or one is unknown)"
    return {c: name for name, c in _CODES.items()}[int(high)], None


def _readout(renderer, entry, whole_image, camera, shape, channel: float) -> np.ndarray:
    """One raw float32 readout of a brick's channel (1.0 where no ray was cast), top row first."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    from mipcast.core.object_state import object_state
    from mipcast.mappers.brick_rays import push_whole_rays
    from mipcast.mappers.stereo import draw_for

    brick_mapper, brick_volume = entry["mapper"], entry["volume"]
    state = object_state(brick_mapper)
    draw_for(brick_mapper, camera, renderer)
    push_whole_rays(brick_volume, brick_mapper.GetSampleDistance(), whole_image, camera, (shape[1], shape[0]))
    state["exact_readout"] = True
    brick_mapper.RenderToImageOn()
    brick_mapper.SetDepthImageScalarTypeToFloat()
    uniforms = brick_volume.GetShaderProperty().GetFragmentCustomUniforms()
    uniforms.SetUniformf("u_mc_brickChannel", float(channel))
    try:
        brick_volume.RenderVolumetricGeometry(renderer)
        image = vtkImageData()
        brick_mapper.GetDepthImage(image)
    finally:
        state.pop("exact_readout", None)
        brick_mapper.RenderToImageOff()
        uniforms.SetUniformf("u_mc_brickChannel", 0.0)
    scalars = image.GetPointData().GetScalars()
    if scalars is None:
        return np.full(shape, 1.0, dtype=np.float32)
    columns, rows, _ = image.GetDimensions()
    found = np.array(vtk_to_numpy(scalars).reshape(rows, columns)[::-1], dtype=np.float32)
    if found.shape != shape:
        raise RuntimeError(f"a piece's readout is {found.shape}, the viewport {shape}")
    return found


def _ordered_entry(mapper, entries, whole_extent, projection: str) -> dict:
    """This rank's brick entry of ``projection``'s brick mapper on its piece (cached on the mapper's state)."""
    from mipcast.core.object_state import object_state
    from mipcast.mappers.bricked_demip import ordered_brick_entry

    state = object_state(mapper)
    piece = entries[0]["mapper"].GetInput()
    key = (piece.GetAddressAsString("vtkObjectBase"), piece.GetMTime(), entries[0]["extent"], tuple(whole_extent),
           projection)
    cached = state.get("rank_ordered_brick")
    if cached is None or cached[0] != key:
        cached = (key, ordered_brick_entry(projection, piece, entries[0]["extent"], whole_extent,
                                           mapper.GetSampleDistance()))
        state["rank_ordered_brick"] = cached
    return cached[1]


def _draw_turn(projection, mapper, volume, renderer, entry, whole_image, camera, shape, state, data_range, local):
    """This rank's piece continuing ``state`` (channel -> array, in place): the projection's brick scan."""
    from mipcast.mappers import demip_ordered_bricks as ordered
    from mipcast.mappers import float_readout

    window = renderer.GetRenderWindow()
    if projection == "lmip":
        running = np.where(state["running"] <= 0.5 * _LOW, np.nan, state["running"])
        ended = state["ended"] > 0.5
        ordered.bind_running(window, entry["mapper"], running, local)
        scalars = entry["mapper"].GetRenderedInput().GetPointData().GetScalars()
        found = float_readout.decode(_readout(renderer, entry, whole_image, camera, shape, 0.0))
        brick_max = float_readout.to_data_units(np.where(np.abs(found) > 1.0e3, np.nan, found), scalars)
        brick_ended = float_readout.decode(_readout(renderer, entry, whole_image, camera, shape, 1.0))
        ordered.scan(running, ended, brick_max, brick_ended)
        state["running"] = np.where(np.isnan(running), _LOW, running)
        state["ended"] = ended.astype(np.float64)
    elif projection == "attenuated":
        crossed = state["crossed"].astype(np.float32)
        ordered.bind_crossed(window, entry["mapper"], crossed, data_range)
        found = _readout(renderer, entry, whole_image, camera, shape, 0.0)
        after = _readout(renderer, entry, whole_image, camera, shape, 1.0)
        best = np.where(state["best"] <= 0.5 * _LOW, np.nan, state["best"])
        best = np.fmax(best, np.where(found == 1.0, np.nan, -found.astype(np.float64)))
        state["best"] = np.where(np.isnan(best), _LOW, best)
        state["crossed"] = np.where(after == 1.0, crossed, -after).astype(np.float32).astype(np.float64)
    else:
        colour = np.stack([state["red"], state["green"], state["blue"]], axis=-1)
        opacity, material = state["opacity"].copy(), state["material"].copy()
        ordered.bind_mida(window, entry["mapper"], material, opacity, data_range)
        readouts = {name: _readout(renderer, entry, whole_image, camera, shape, float(channel))
                    for channel, name in enumerate(ordered.MIDA_CHANNELS)}
        ordered.mida_scan(colour, opacity, material, readouts)
        state.update(red=colour[..., 0], green=colour[..., 1], blue=colour[..., 2], opacity=opacity,
                     material=material)


def demip(mapper, volume, renderer, entries, whole_image, camera, shape, reduce, data_range, problem,
          rank: Tuple[int, int], missing: bool = False):
    """DEMIP over the ranks for every projection: ``"mip"`` by rank_composite's MAX / MIN, the ordered ones
    turn by turn.  Returns (premultiplied RGBA, None), (None, None) on a rank without data, or (None, why).

    ``entries``: rank_composite's [phase-1 MIP entry, phase-2 depth entry] of
    this rank's piece, followed and in view ([] otherwise); ``rank``:
    (this rank's index, the number of ranks); ``missing``: some rank's piece
    holds missing values (the same on every rank): attenuated MIP and MIDA
    then apply the whole ray's missing test (:func:`_whole_ray_seen`).
    """
    from mipcast.mappers import rank_composite

    projection, why = agreed_projection(mapper, reduce)
    if why is not None:
        return None, why
    if projection is None:
        return None, None
    if projection == "mip":
        return rank_composite._demip(mapper, volume, renderer, entries, whole_image, camera, shape, reduce,
                                     data_range, problem)
    return _ordered(projection, mapper, volume, renderer, entries, whole_image, camera, shape, reduce,
                    data_range, problem, rank, missing)


def _whole_ray_seen(renderer, entries, whole_image, camera, shape, reduce, problem):
    """(where the whole ray saw finite data, problem): MIDA's missing test over the ranks.

    MIDA's brick mappers have no missing test of their own (their running
    maximum is 0); as beyond the texture limit
    (:func:`mipcast.mappers.bricked_demip.compose`) a ray shows nothing when
    the whole volume's sampled maximum saw no finite data: the MAX over the
    ranks of each piece's phase-1 MIP (NaN on a piece whose samples of the
    ray were all missing: its missing test, relative to the whole range).
    Every rank enters the one reduction.
    """
    from mipcast.mappers.rank_composite import _render

    found = np.full(shape, np.nan)
    if entries and problem is None:
        try:
            found = _render(renderer, entries[0], whole_image, camera, shape)
        except Exception as error:  # noqa: BLE001  (reported; the collective still runs)
            problem = repr(error)
    reduced = reduce(np.concatenate([np.where(np.isnan(found), _LOW, 0.0).ravel(), [1.0 if problem else 0.0]]),
                     "max")
    why = (problem or "a rank failed to render its piece") if reduced[-1] > 0.0 else None
    return reduced[:-1].reshape(shape) > 0.5 * _LOW, why


def _ordered(projection, mapper, volume, renderer, entries, whole_image, camera, shape, reduce, data_range,
             problem, rank, missing=False):
    """An order-dependent projection (LMIP, attenuated MIP, MIDA) over the ranks, as :func:`demip` returns it.

    Every rank enters every reduction: 1. :func:`_turn_order`, who draws
    which piece, front to back; 2. :func:`_take_turns`, the pieces' scans
    in that order, the running state summed over the ranks; 3. LMIP's
    second phase (:func:`_lmip_matches`) or MIDA's missing test
    (:func:`_whole_ray_seen`); then the picture (:func:`_ordered_picture`).
    """
    index, count = (int(v) for v in rank)
    own, order, order_problem, problem, why = _turn_order(projection, mapper, volume, entries, whole_image, camera,
                                                          shape, reduce, problem, index, count)
    if why is not None:
        return None, why
    state, problem, why = _take_turns(projection, mapper, volume, renderer, own, whole_image, camera, shape, reduce,
                                      data_range, problem, index, order, order_problem)
    if why is not None:
        return None, why
    values, found = np.full(shape, np.nan), np.full(shape, np.inf)
    if projection == "lmip":
        values, found, why = _lmip_matches(renderer, entries, whole_image, camera, shape, reduce, data_range,
                                           problem, state)
        if why is not None:
            return None, why
    seen = None
    if projection == "mida" and missing:
        seen, why = _whole_ray_seen(renderer, entries, whole_image, camera, shape, reduce, problem)
        if why is not None:
            return None, why
    if mapper is None or whole_image is None:
        return None, None  # a rank without data: it took part, it draws nothing
    return _ordered_picture(projection, mapper, volume, whole_image, camera, state, values, found, seen, data_range,
                            missing), None


def _turn_order(projection, mapper, volume, entries, whole_image, camera, shape, reduce, problem, index, count):
    """1: who draws which piece (a row per rank: its extent), how many ranks counted, anyone failed (one SUM).

    Returns (this rank's ordered entry or None, the ranks in the order the rays cross their pieces, why
    they could not be ordered or None, this rank's problem, why the frame cannot be drawn or None).
    """
    from mipcast.mappers.brick_rays import ray_uniforms
    from mipcast.mappers.bricked_demip import follow_demip_brick

    own = None
    if not 0 <= index < count and problem is None:
        problem = f"this rank's index {index} is not in [0, {count}): pass rank=(index, count) to compose"
    if entries and problem is None:
        try:
            own = _ordered_entry(mapper, entries, whole_image.GetExtent(), projection)
            follow_demip_brick(mapper, volume, own, mapper.GetSampleDistance(), demip=True)
            # then missing values filled as in the whole volume, as the phases' entries (rank_composite.compose;
            # following gave it this piece's own range)
            own["mapper"].GetInputPreparer().SetWholeRange(entries[0]["mapper"].GetInputPreparer().GetWholeRange())
        except Exception as error:  # noqa: BLE001  (reported; the collectives still run)
            problem, own = repr(error), None
    table = np.zeros((count, 7))
    claims = np.zeros(count)
    if 0 <= index < count:
        claims[index] = 1.0
        if own is not None:
            table[index] = [1.0, *own["extent"]]
    gathered = reduce(np.concatenate([table.ravel(), claims, [1.0, 1.0 if problem else 0.0]]), "sum")
    if int(round(gathered[-2])) != count:
        return own, [], None, problem, (
            f"the ranks disagree on their number ({int(round(gathered[-2]))} took part, this rank was "
            f"told {count}): pass rank=(index, count) to rank_composite.compose")
    if gathered[-1] > 0.0:
        return own, [], None, problem, problem or "a rank failed to prepare its piece"
    claims = gathered[count * 7:-2]
    if np.any(np.abs(claims - 1.0) > 0.5):
        return own, [], None, problem, (
            f"the ranks' indices are not 0 .. {count - 1} once each (rank rows {claims.tolist()}): "
            "pass rank=(index, count) to rank_composite.compose")
    table = gathered[:count * 7].reshape(count, 7)
    drawn = [r for r in range(count) if table[r, 0] > 0.5]
    order, order_problem = list(drawn), None
    if whole_image is not None and drawn:
        try:
            rays = ray_uniforms(whole_image, camera, (shape[1], shape[0]))
            order = [drawn[i] for i in front_to_back([table[r, 1:] for r in drawn], rays)]
        except ValueError as error:
            order_problem = str(error)
    return own, order, order_problem, problem, None


def _take_turns(projection, mapper, volume, renderer, own, whole_image, camera, shape, reduce, data_range, problem,
                index, order, order_problem):
    """2: the turns, front to back, the same number on every rank: the owner of each piece continues the running
    state (:func:`_draw_turn`), which one SUM hands to every rank.  Returns (state, this rank's problem, why the
    frame cannot be drawn or None)."""
    from mipcast.mappers.demip_ordered_bricks import local_threshold

    names = STATE[projection]
    state = {name: np.zeros(shape) for name in names}
    if projection in ("lmip", "attenuated"):
        state[names[0]][:] = _LOW
    local = (local_threshold(volume.GetProperty(), data_range, mapper.GetLocalThreshold())
             if projection == "lmip" and mapper is not None else None)
    size = shape[0] * shape[1]
    for owner in order:
        contribution = np.zeros(len(names) * size + 1)
        if order_problem is not None:  # every rank that could order sees it: all stop at the first turn
            contribution[-1] = 1.0
        elif owner == index:
            try:
                _draw_turn(projection, mapper, volume, renderer, own, whole_image, camera, shape, state,
                           data_range, local)
                contribution[:-1] = np.concatenate([state[name].ravel() for name in names])
            except Exception as error:  # noqa: BLE001
                problem, contribution[-1] = repr(error), 1.0
        reduced = reduce(contribution, "sum")
        if reduced[-1] > 0.0:
            return state, problem, order_problem or problem or "a rank failed to order or draw the pieces"
        for k, name in enumerate(names):
            state[name] = reduced[k * size:(k + 1) * size].reshape(shape)
    return state, problem, None


def _lmip_matches(renderer, entries, whole_image, camera, shape, reduce, data_range, problem, state):
    """3: LMIP's phase 2 (DEMIP's first same-material sample) over the ranks, one MIN: (values, the whole-ray
    index of each ray's first sample of its value's material (inf: none), why the frame cannot be drawn or
    None)."""
    from mipcast.mappers.demip_brick import bind_maximum, match_index
    from mipcast.mappers.rank_composite import _render

    values = np.where(state["running"] <= 0.5 * _LOW, np.nan, state["running"])
    values = values.astype(np.float32).astype(np.float64)
    found = np.full(shape, np.inf)
    if entries:
        try:
            bind_maximum(renderer.GetRenderWindow(), entries[1]["mapper"], values, data_range)
            found = match_index(_render(renderer, entries[1], whole_image, camera, shape, raw=True))
        except Exception as error:  # noqa: BLE001
            problem = repr(error)
    reduced = reduce(np.concatenate([np.where(np.isfinite(found), found, _HIGH).ravel(),
                                     [-1.0 if problem else 0.0]]), "min")
    if reduced[-1] < 0.0:
        return values, found, problem or "a rank failed to render its piece"
    found = reduced[:-1].reshape(shape)
    return values, np.where(found >= 0.5 * _HIGH, np.inf, found), None


def _ordered_picture(projection, mapper, volume, whole_image, camera, state, values, found, seen, data_range,
                     missing) -> np.ndarray:
    """The premultiplied RGBA of the reduced state: MIDA's colours as they are; LMIP's and attenuated MIP's
    values through DEMIP's depth, Eq. 1 and colour sphere (:func:`mipcast.mappers.demip_composite.demip_composite`).
    The frame's floats stay on the mapper's state for :class:`mipcast.distributed.DistributedView`."""
    from mipcast.core.object_state import object_state
    from mipcast.mappers import clip_uniforms
    from mipcast.mappers.demip_composite import demip_composite, demip_premultiplied
    from mipcast.mappers.demip_ordered_bricks import attenuated_value

    if projection == "mida":
        object_state(mapper)["rank_ordered_floats"] = {}
        rgba = np.zeros(values.shape + (4,), dtype=np.float32)
        rgba[..., 0], rgba[..., 1], rgba[..., 2] = (np.clip(state[c], 0.0, 1.0) for c in ("red", "green", "blue"))
        rgba[..., 3] = np.clip(state["opacity"], 0.0, 1.0)
        if seen is not None:  # a ray that saw no finite data draws nothing, as one texture's
            rgba[~seen] = 0.0
        return rgba
    if projection == "attenuated":
        best = np.where(state["best"] <= 0.5 * _LOW, np.nan, state["best"])
        values = attenuated_value(best, volume.GetProperty(), data_range)
        if missing:  # the whole ray's missing test (its brick mappers have none): below the whole fill's threshold
            from mipcast.core.prepare import missing_fill

            values = np.where(values < missing_fill(*data_range)[1], np.nan, values)
        values = values.astype(np.float32).astype(np.float64)
    params = {p.name: getattr(mapper, p.getter)() for p in DEMIP_SETTINGS}
    depth, rgb = demip_composite(whole_image, camera, mapper.GetSampleDistance(), values, found, params,
                                 volume.GetProperty(), slab=clip_uniforms.slab_of(mapper, camera))
    # the frame's floats, for callers that offer them (mipcast.distributed.DistributedView)
    object_state(mapper)["rank_ordered_floats"] = {"value": values, "depth": depth}
    return demip_premultiplied(values, rgb, volume.GetProperty())
