"""Content-adaptive ray density for foveated rendering (Levoy & Whitaker 1990, section 8).

The paper's adaptive refinement: local image complexity, as well as
retinal acuity, decides where rays are cast.  A *content level*, one step
coarser than acuity's coarsest (:func:`adaptive_plan`), is cast over the
whole viewport first.  Then:

- acuity's coarsest level casts a ray where the content level's picture
  has an edge (below), and everywhere inside the fovea and two of its
  texels beyond (:func:`fovea_radius`) -- so the periphery
  that acuity leaves at its coarsest level stays at the content level where
  the picture is flat there;
- every finer level casts a ray only where acuity's coarsest level's
  picture (the content level showing through where it cast none) says the
  ray can change the result.

What the picture of the deciding level (:func:`decided_by`) says
(:func:`refinement_test`, :func:`refinement_mask`):

- everywhere: an edge -- its values within one of its texels (the 3 x 3
  neighbourhood) differ by more than the *content tolerance* (grey levels);
- inside the fovea (eccentricity below the plan's ``start``) also structure
  -- any texel of that neighbourhood differs from what lay beneath the
  volume before it was drawn, i.e. the value is above the transfer
  function's floor, or the data says a full-quality ray through the
  texel's cell may meet a value above the floor
  (:mod:`mipcast.core.structure_bound`: a speck or a vessel's tip smaller
  than the ray spacing, which no coarse ray met) -- so the fovea stays at
  full quality wherever a structure is.  That picture is acuity's coarsest
  level, cast over the whole fovea, as dense as without a content level (a
  coarser picture would let more fall between its rays);
  :func:`structure_source` names it.

Elsewhere the ray is not cast and the coarser picture (bilinearly
stretched) shows through: background inside the sweet spot needs no
full-density rays, and smooth regions of the periphery keep the content
level.  Pure numpy, the float64 definition: the mapper
(:mod:`mipcast.mappers.foveated`) evaluates :func:`refinement_test` once per
texel of the deciding level in a small GPU pass
(``shaders/foveated_refine_pass.glsl``) after that level is drawn, and the
finer levels' shader reads it (``shaders/foveated_coarse_dec.glsl``, the
fovea from :func:`fovea_spans`), or, on its CPU path, reads the picture back
and uploads these masks; the cost accounting uses these masks.
"""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

from mipcast.core.foveation import (MIN_TEXELS, Layer, Plan, coarse_texels, desired_level, eccentricity, layer_weight,
                                    level_border, level_grid, outline_distance)


def neighbourhood_range(values: np.ndarray) -> tuple:
    """(max, min) of each element's 3 x 3 neighbourhood (edges clamped).

    Examples
    --------
    >>> high, low = neighbourhood_range(np.array([[0.0, 0.0, 9.0]]))
    >>> high.tolist(), low.tolist()
    ([[0.0, 9.0, 9.0]], [[0.0, 0.0, 0.0]])
    """
    values = np.asarray(values, dtype=np.float64)
    padded = np.pad(values, 1, mode="edge")
    rows, columns = values.shape
    windows = [padded[dy:dy + rows, dx:dx + columns] for dy in range(3) for dx in range(3)]
    return np.max(windows, axis=0), np.min(windows, axis=0)


def refinement_test(after: np.ndarray, before: np.ndarray, tolerance: float) -> tuple:
    """Per texel of a coarser level: (edge, structure) of its 3 x 3 neighbourhood.

    What the GPU's refine pass writes (red, green) for each texel of the
    level drawn before a finer one.

    Parameters
    ----------
    after, before : numpy.ndarray, shape (rows, columns, channels), uint8
        The picture at the coarser level's texel centres (:func:`coarse_texels`)
        after that level was drawn, and before the first level of the frame
        was drawn, top row first.
    tolerance : float
        Grey levels; neighbouring values differing by more make an edge.

    Returns
    -------
    (edge, structure) : bool arrays (rows, columns)
        ``edge``: the neighbourhood's grey (largest channel) spans more
        than ``tolerance``; ``structure``: a texel of the neighbourhood
        differs from the picture before (structure above the floor).

    Examples
    --------
    >>> coarse = np.zeros((1, 4, 3), np.uint8); coarse[0, 3] = 200
    >>> edge, structure = refinement_test(coarse, np.zeros_like(coarse), 2.0)
    >>> edge.tolist(), structure.tolist()
    ([[False, False, True, True]], [[False, False, True, True]])
    """
    after = np.asarray(after, dtype=np.float64)
    before = np.asarray(before, dtype=np.float64)
    grey = after.max(axis=-1) if after.ndim == 3 else after
    high, low = neighbourhood_range(grey)
    differs = np.abs(after - before)
    differs = differs.max(axis=-1) if differs.ndim == 3 else differs
    return (high - low) > float(tolerance), neighbourhood_range(differs > 0)[0] > 0


def decided_by(plan: Plan, index: int) -> int:
    """Index of the layer of ``plan`` (:func:`adaptive_plan`) whose picture decides layer ``index``'s rays.

    The content level decides acuity's coarsest level; that level decides
    every finer one.  Without a content level the coarsest decides all.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1))
    >>> [decided_by(plan, index) for index in range(1, len(plan.layers))]
    [0, 1, 1]
    """
    return 1 if index >= 2 and has_content_level(plan) else 0


def structure_source(plan: Plan) -> Optional[int]:
    """Index of the layer whose structure test decides the fovea's finer rays (None: no finer level tests it).

    Acuity's coarsest level under a content level (which casts the whole
    fovea itself, structure or not), else the coarsest.  The data's bound
    (:mod:`mipcast.core.structure_bound`) joins this layer's structure test.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> structure_source(adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1)))
    1
    >>> structure_source(adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1), max_level=2))
    0
    """
    sources = [decided_by(plan, index) for index in range(1, len(plan.layers))
               if not casts_whole_fovea(plan, plan.layers[index])]
    return sources[0] if sources else None


def has_content_level(plan: Plan) -> bool:
    """Whether ``plan``'s first layer is a content level (coarser than acuity's coarsest, ``plan.top``)."""
    return len(plan.layers) > 1 and plan.layers[0].level > plan.top


def refinement_mask(edge: np.ndarray, structure: np.ndarray, plan: Plan, layer) -> np.ndarray:
    """Where ``layer`` casts rays: its texels whose nearest deciding texel has an edge, or structure in the fovea.

    Acuity's coarsest level under a content level casts every ray in the
    fovea, structure or not (module docstring).

    Parameters
    ----------
    edge, structure : numpy.ndarray, bool, shape (rows, columns)
        :func:`refinement_test` of the deciding level (:func:`decided_by`).
    plan : mipcast.core.foveation.Plan
    layer : mipcast.core.foveation.Layer
        A finer layer of ``plan`` (not the first).

    Returns
    -------
    numpy.ndarray, bool, shape of ``layer``'s grid (rows, columns), top row first; True: cast the ray.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1))
    >>> [layer.level for layer in plan.layers]   # the content level 3 first
    [3, 2, 1, 0]
    >>> coarse = np.zeros((16, 16, 3), np.uint8); coarse[:, 12:] = 200   # structure on the right
    >>> edge, structure = refinement_test(coarse, np.zeros_like(coarse), 2.0)
    >>> mask = refinement_mask(edge, structure, plan, plan.layers[3])
    >>> mask.shape, bool(mask[32, 32]), bool(mask[32, 47])
    ((64, 64), False, True)
    >>> bool(refinement_mask(edge, structure, plan, plan.layers[1])[8, 8])   # level 2: the whole fovea
    True
    """
    fovea = eccentricity(layer.grid, plan.gaze, plan.aspect) < fovea_radius(plan, layer)
    if casts_whole_fovea(plan, layer):
        return coarse_texels(edge, layer.grid) | fovea
    return coarse_texels(edge, layer.grid) | (fovea & coarse_texels(structure, layer.grid))


def casts_whole_fovea(plan: Plan, layer) -> bool:
    """Whether ``layer`` is acuity's coarsest level under a content level: it casts the whole fovea, structure or not.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1))
    >>> [casts_whole_fovea(plan, layer) for layer in plan.layers[1:]]
    [True, False, False]
    """
    return layer.level == plan.top and has_content_level(plan)


def fovea_radius(plan: Plan, layer) -> float:
    """Eccentricity below which ``layer``'s mask treats a ray as inside the fovea: the plan's ``start``.

    Acuity's coarsest level under a content level casts every ray within
    two of its texels more (the whole fovea plus the neighbourhood the finer
    levels' structure test reads there: their nearest texel lies within
    sqrt(2) / 2 of a texel, its neighbours one more).

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1))
    >>> [round(fovea_radius(plan, layer) - plan.start, 4) for layer in plan.layers[1:]]   # 2 texels of 16
    [0.125, 0.0, 0.0]
    """
    if casts_whole_fovea(plan, layer):
        columns, rows = layer.grid
        return plan.start + 2.0 * max(1.0 / rows, plan.aspect / columns)
    return plan.start


def fovea_spans(grid, plan: Plan, radius: Optional[float] = None) -> np.ndarray:
    """Per row of ``grid`` (top row first), the columns ``[first, end)`` of its texels inside the fovea.

    Inside: the texel centre's eccentricity (float64,
    :func:`mipcast.core.foveation.eccentricity`) below ``radius`` (default
    the plan's ``start``; a level's :func:`fovea_radius`), exactly as
    :func:`refinement_mask` decides; a disc, so one span per row
    (``first == end`` when the row misses it).  The GPU-built masks read
    these spans instead of recomputing the eccentricity in float32.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1)
    >>> spans = fovea_spans((8, 8), plan)
    >>> spans.shape, spans[0].tolist(), spans[4].tolist()
    ((8, 2), [0, 0], [2, 6])
    """
    inside = eccentricity(grid, plan.gaze, plan.aspect) < (plan.start if radius is None else radius)
    any_inside = inside.any(axis=1)
    first = np.where(any_inside, np.argmax(inside, axis=1), 0)
    end = np.where(any_inside, inside.shape[1] - np.argmax(inside[:, ::-1], axis=1), 0)
    return np.stack([first, end], axis=1)


def adaptive_plan(plan: Plan, max_level: int = 99) -> Plan:
    """``plan`` with a content level: one level coarser than its coarsest, cast over the whole viewport first.

    Acuity's coarsest level may then cast over the whole viewport too (its
    mask decides where: the whole fovea and the content picture's edges);
    the finer levels keep their cast ranges (module docstring).  Where no
    coarser level is possible (its grid would be under
    :data:`~mipcast.core.foveation.MIN_TEXELS` texels, or coarser than
    ``max_level``, the scene's cap), acuity's coarsest level is the first,
    cast over the whole viewport unmasked.  A plan of one level is returned
    as it is.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1))
    >>> content = plan.layers[0]
    >>> content.level, content.grid, content.image_sample_distance, content.cast_from, content.scissor
    (3, (8, 8), 8.0, -inf, None)
    >>> capped = adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1), max_level=2)
    >>> [layer.level for layer in capped.layers], capped.layers[0].cast_from
    ([2, 1, 0], -inf)
    """
    if len(plan.layers) < 2:
        return plan
    coarsest = plan.layers[0]._replace(cast_from=-math.inf, scissor=None)
    layers = (coarsest,) + tuple(plan.layers[1:])
    level = coarsest.level + 1
    base = coarsest.image_sample_distance / 2 ** coarsest.level
    grid = level_grid(plan.viewport[2], plan.viewport[3], level, base)
    if level > max_level or min(grid) < MIN_TEXELS:
        return plan._replace(layers=layers)
    return plan._replace(layers=(Layer(level, base * 2 ** level, grid, -math.inf, math.inf, None),) + layers)


def outline_cover(plan: Plan, silhouette) -> Optional[tuple]:
    """Where a content-adaptive frame must be covered by what lay beneath the volume, beyond its outline.

    The deciding levels are drawn under the fovea, and their reduced
    pictures, stretched over the viewport, reach up to one of their texels
    past the volume's outline, where level 0 has no fragment to draw over
    them. There level 0 would have drawn nothing over what lay beneath (as
    ``shaders/foveated_paint_beneath.glsl`` paints a ray that draws nothing):
    the picture beneath goes over them with level 0's weight.

    Returns ``(box, weight)``: the pixel box (x0, y0, columns, rows, from the
    viewport's lower left) around level 0's blend disc, and level 0's weight
    there outside the outline (rows top first; 0 inside it), or None where
    the outline does not reach that disc (``silhouette``: ``(edges, unit)``,
    :func:`mipcast.core.foveation.silhouette_edges`).

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame, silhouette_edges
    >>> plan = plan_frame((0, 0, 64, 64), (0.1, 0.5), 0.1, 0.2)
    >>> right = (silhouette_edges(np.array([[0.1, 0.0], [1.0, 0.0], [1.0, 1.0], [0.1, 1.0]]), 1.0), 0.02)
    >>> box, weight = outline_cover(plan, right)
    >>> box[0], float(weight.max()), float(weight[:, 7:].max())   # beyond the outline (x < 0.1): level 0's weight
    (0, 1.0, 0.0)
    >>> outline_cover(plan_frame((0, 0, 64, 64), (0.6, 0.5), 0.1, 0.2), right) is None   # far inside the outline
    True
    >>> wide = (silhouette_edges(np.array([[-0.5, -0.5], [1.5, -0.5], [1.5, 1.5], [-0.5, 1.5]]), 1.0), 0.02)
    >>> outline_cover(plan_frame((0, 0, 64, 64), (0.1, 0.1), 0.3, 0.2), wide) is None   # the outline beyond the view
    True
    """
    edges = silhouette[0]
    _, _, width, height = plan.viewport
    gaze = np.array([plan.gaze[0] * plan.aspect, plan.gaze[1]])
    reach = level_border(plan, 1)  # level 0's weight is 0 beyond it
    if min(float(nx * gaze[0] + ny * gaze[1] + c) for nx, ny, c in edges) > reach:
        return None  # (the distance along the axes changes no faster than the Euclidean one)
    x0, x1 = (int(np.clip(math.floor((plan.gaze[0] - r / plan.aspect) * width), 0, width)) for r in (reach, -reach))
    y0, y1 = (int(np.clip(math.floor((plan.gaze[1] - r) * height), 0, height)) for r in (reach, -reach))
    box = (x0, y0, min(x1 + 1, width) - x0, min(y1 + 1, height) - y0)
    if box[2] <= 0 or box[3] <= 0:
        return None
    corners = [((x0 + dx) / width * plan.aspect, (y0 + dy) / height) for dx in (0, box[2]) for dy in (0, box[3])]
    if all(min(nx * cx + ny * cy for cx, cy in corners) + c >= 0.0 for nx, ny, c in edges):
        return None  # the box lies inside the (convex) outline, e.g. a volume filling the view: nothing to cover
    x = (x0 + np.arange(box[2]) + 0.5) / width
    y = ((y0 + np.arange(box[3]) + 0.5) / height)[::-1]
    e = np.hypot((x[None, :] - plan.gaze[0]) * plan.aspect, y[:, None] - plan.gaze[1])
    weight = layer_weight(0, desired_level(e, plan), plan)
    weight = np.where(outline_distance(plan, silhouette, (width, height), box) < 0.0, weight, 0.0)
    return (box, weight) if weight.any() else None


def cover_patch(weight: np.ndarray, beneath: np.ndarray) -> np.ndarray:
    """The premultiplied RGBA8 values (0 .. 255, float) :func:`outline_cover` draws: ``beneath`` (RGB 0 .. 255,
    or one colour) times ``weight``, alpha ``weight``, drawn "over" the levels.

    >>> cover_patch(np.array([[1.0, 0.5]]), np.array([100.0, 50.0, 0.0])).tolist()
    [[[100.0, 50.0, 0.0, 255.0], [50.0, 25.0, 0.0, 128.0]]]
    """
    weight = np.asarray(weight, dtype=np.float64)[..., None]
    return np.floor(np.concatenate([weight * np.asarray(beneath, dtype=np.float64), 255.0 * weight], axis=-1) + 0.5)
