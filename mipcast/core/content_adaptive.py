"""Content-adaptive ray density for foveated rendering (Levoy & Whitaker 1990, section 8).

The coarsest pyramid level is cast over the whole viewport first.  Its
picture then decides, texel by texel, where the finer levels cast rays:

- everywhere: where the coarse picture's values within one coarse texel
  (its 3 x 3 neighbourhood) differ by more than the *content tolerance*
  (grey levels) -- an edge or texture a finer ray can change;
- inside the fovea (eccentricity below the plan's ``start``) also where any
  coarse texel of the neighbourhood shows structure (differs from what lay
  beneath the volume before it was drawn, i.e. the value is above the
  transfer function's floor), so the fovea stays at full quality wherever
  a structure is.

Elsewhere the finer ray is not cast and the coarser picture (bilinearly
stretched) shows through: background inside the sweet spot needs no
full-density rays, and smooth regions of the periphery keep the coarse
level.  Pure numpy, the float64 definition: the mapper
(:mod:`mipcast.mappers.foveated`) evaluates it per ray in the finer levels'
shader from the coarse picture copied into textures on the GPU
(``shaders/foveated_coarse_dec.glsl``, the fovea from :func:`fovea_spans`),
or, on its CPU path, reads the coarse picture back and uploads these masks;
the cost accounting uses these masks.
"""
from __future__ import annotations

from typing import Dict

import numpy as np

from mipcast.core.foveation import Plan, eccentricity


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


def coarse_texels(picture: np.ndarray, grid) -> np.ndarray:
    """The picture at the pixel centres nearest a coarse grid's texel centres, top row first.

    Parameters
    ----------
    picture : numpy.ndarray, shape (height, width[, channels])
        Top row first.
    grid : (columns, rows)

    Examples
    --------
    >>> coarse_texels(np.arange(16).reshape(4, 4), (2, 2)).tolist()
    [[5, 7], [13, 15]]
    """
    height, width = picture.shape[:2]
    columns, rows = int(grid[0]), int(grid[1])
    x = np.minimum(((np.arange(columns) + 0.5) * width / columns).astype(int), width - 1)
    y = np.minimum(((np.arange(rows) + 0.5) * height / rows).astype(int), height - 1)
    return picture[y][:, x]


def refinement_masks(after: np.ndarray, before: np.ndarray, plan: Plan, tolerance: float) -> Dict[int, np.ndarray]:
    """Where each finer level of ``plan`` casts rays, from the coarsest level's picture.

    Parameters
    ----------
    after, before : numpy.ndarray, shape (rows, columns, channels), uint8
        The picture at the coarsest level's texel centres (:func:`coarse_texels`)
        after and before that level was drawn, top row first.
    plan : mipcast.core.foveation.Plan
        Its first layer is the coarsest level (cast everywhere).
    tolerance : float
        Grey levels; neighbouring coarse values differing by more ask for finer rays.

    Returns
    -------
    dict
        ``{level: bool array (rows, columns) of that level's grid, top row first}``
        for every layer but the coarsest; True: cast the ray.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1)
    >>> coarse = np.zeros((16, 16, 3), np.uint8); coarse[:, 12:] = 200   # structure on the right
    >>> masks = refinement_masks(coarse, np.zeros_like(coarse), plan, 2.0)
    >>> sorted(masks), masks[0].shape, bool(masks[0][32, 32]), bool(masks[0][32, 47])
    ([0, 1], (64, 64), False, True)
    """
    after = np.asarray(after, dtype=np.float64)
    before = np.asarray(before, dtype=np.float64)
    grey = after.max(axis=-1) if after.ndim == 3 else after
    high, low = neighbourhood_range(grey)
    edges = (high - low) > float(tolerance)
    structure = np.abs(after - before)
    structure = structure.max(axis=-1) if structure.ndim == 3 else structure
    near_structure = neighbourhood_range(structure > 0)[0] > 0
    rows_c, columns_c = grey.shape
    masks = {}
    for layer in plan.layers[1:]:
        columns, rows = layer.grid
        x = np.minimum(((np.arange(columns) + 0.5) * columns_c / columns).astype(int), columns_c - 1)
        y = np.minimum(((np.arange(rows) + 0.5) * rows_c / rows).astype(int), rows_c - 1)
        fovea = eccentricity(layer.grid, plan.gaze, plan.aspect) < plan.start
        masks[layer.level] = edges[y][:, x] | (fovea & near_structure[y][:, x])
    return masks


def fovea_spans(grid, plan: Plan) -> np.ndarray:
    """Per row of ``grid`` (top row first), the columns ``[first, end)`` of its texels inside the fovea.

    Inside: the texel centre's eccentricity (float64,
    :func:`mipcast.core.foveation.eccentricity`) below the plan's ``start``,
    exactly as :func:`refinement_masks` decides; a disc, so one span per
    row (``first == end`` when the row misses it).  The GPU-built masks
    read these spans instead of recomputing the eccentricity in float32.

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1)
    >>> spans = fovea_spans((8, 8), plan)
    >>> spans.shape, spans[0].tolist(), spans[4].tolist()
    ((8, 2), [0, 0], [3, 5])
    """
    inside = eccentricity(grid, plan.gaze, plan.aspect) < plan.start
    any_inside = inside.any(axis=1)
    first = np.where(any_inside, np.argmax(inside, axis=1), 0)
    end = np.where(any_inside, inside.shape[1] - np.argmax(inside[:, ::-1], axis=1), 0)
    return np.stack([first, end], axis=1)


def adaptive_plan(plan: Plan) -> Plan:
    """``plan`` with its coarsest layer cast over the whole viewport (the picture the masks come from).

    Examples
    --------
    >>> from mipcast.core.foveation import plan_frame
    >>> plan = adaptive_plan(plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.1))
    >>> plan.layers[0].cast_from, plan.layers[0].scissor
    (-inf, None)
    """
    if len(plan.layers) < 2:
        return plan
    top = plan.layers[0]._replace(cast_from=-float("inf"), scissor=None)
    return plan._replace(layers=(top,) + tuple(plan.layers[1:]))
