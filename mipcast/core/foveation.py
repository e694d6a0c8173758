"""Gaze-directed level maths: eccentricity, the level each pixel wants, blend weights.

Foveated rendering after Levoy & Whitaker (1990).  Level ``k`` of the
image pyramid casts one ray every ``2**k`` pixels (VTK's
``ImageSampleDistance = 2**k``; how it samples along the ray is
:func:`mipcast.mappers.volume_pyramid.level_sampling`).  A pixel at eccentricity
``e`` (distance to the gaze point, in viewport heights) wants the
continuous level::

    lam(e) = clip(log2(1 + gain * max(e - start, 0)), 0, top)
    gain   = (2**(L - 1) - 1) / falloff        (L levels)

and its colour is a lerp between the two bracketing levels, drawn coarsest
first, each composited *over* the one below with the premultiplied weight
``clip(k + 1 - lam, 0, 1)``.  Everything here is pure Python / numpy and is
shared by the mapper (uniforms), its float readout (composite) and its
cost accounting.  The definitions of ``start``, ``falloff`` and ``top``,
the acuity schedule and the drawing rules: docs/methods.md, section
Foveated rendering (``docs/methods.md#foveated-rendering``).
"""
from __future__ import annotations

import math
from typing import NamedTuple, Optional, Sequence, Tuple

import numpy as np

#: Display geometry behind the defaults: a 27-inch 16:9 desktop monitor
#: (59.8 x 33.6 cm) seen from 60 cm, the viewport filling its height.
SCREEN_HEIGHT_CM = 33.6
VIEWING_DISTANCE_CM = 60.0
#: The paper's sweet spot: full density inside 12 degrees of arc (a radius of
#: 6 degrees), falling to the coarsest density outside 20 degrees (10).
FOVEA_DEGREES = 6.0
PERIPHERY_DEGREES = 10.0

#: Pyramid levels drawn by default: full, 1/2 and 1/4 resolution (rays every
#: 1, 2, 4 pixels; 1, 1/4, 1/16 of the rays), as in the paper.
DEFAULT_LEVELS = 3
#: A level is used only if its grid has at least this many texels across.
MIN_TEXELS = 4
#: Bilinear reach of a texel, in texels (a pixel blends texels up to one
#: texel away in x and y: sqrt(2) < 1.5).
REACH_TEXELS = 1.5


def angle_to_height(degrees: float, screen_height_cm: float = SCREEN_HEIGHT_CM,
                    distance_cm: float = VIEWING_DISTANCE_CM,
                    viewport_height_cm: Optional[float] = None) -> float:
    """An eccentricity in degrees of visual angle as a fraction of the viewport height.

    A flat screen seen head-on from ``distance_cm`` with the gaze on it:
    ``distance * tan(degrees) / viewport height``.

    Parameters
    ----------
    degrees : float
        Eccentricity (angle between the gaze and the line of sight), >= 0.
    screen_height_cm : float, default: 33.6
        Height of the screen (a 27-inch 16:9 monitor).
    distance_cm : float, default: 60.0
        Eye-to-screen distance.
    viewport_height_cm : float, optional
        Height of the rendered viewport on the screen; default the whole
        screen height.

    Examples
    --------
    >>> round(angle_to_height(6.0), 3)     # the default foveal radius
    0.188
    >>> round(angle_to_height(6.0, viewport_height_cm=14.2), 2)  # a 512-pixel window
    0.44
    """
    if not 0.0 <= degrees < 90.0:
        raise ValueError(f"degrees must be in [0, 90), got {degrees!r}")
    height = screen_height_cm if viewport_height_cm is None else viewport_height_cm
    if not (height > 0 and distance_cm > 0):
        raise ValueError("screen/viewport height and distance must be > 0")
    return distance_cm * math.tan(math.radians(degrees)) / height


#: Default foveal radius: 6 degrees in the geometry above (0.188 of the height).
DEFAULT_RADIUS = angle_to_height(FOVEA_DEGREES)
#: Default falloff: from 6 to 10 degrees (0.127 of the height), over which
#: the ray density falls from full to the coarsest level.
DEFAULT_FALLOFF = angle_to_height(PERIPHERY_DEGREES) - DEFAULT_RADIUS

#: How peripheral levels sample along their rays (see :func:`mipcast.mappers.volume_pyramid.level_sampling`).
SAMPLING_POLICIES = ("footprint", "level", "rays")


class Layer(NamedTuple):
    """One pyramid level as drawn in one frame."""

    level: int
    #: rays every ``image_sample_distance`` pixels (VTK's setting)
    image_sample_distance: float
    #: grid of rays (texels) across and up
    grid: Tuple[int, int]
    #: rays are cast where ``cast_from <= e < cast_to`` (viewport heights)
    cast_from: float
    cast_to: float
    #: GL scissor box (x, y, width, height) around the rays this level casts,
    #: or None.  A level with a reduced grid is drawn into its own buffer
    #: (grid pixels) and then stretched over the window, both under the one
    #: scissor box: it holds the disc in both pixel spaces, and the origin.
    scissor: Optional[Tuple[int, int, int, int]]


class Plan(NamedTuple):
    """Everything one foveated frame needs, in viewport terms."""

    viewport: Tuple[int, int, int, int]   # x0, y0, width, height (window pixels)
    gaze: Tuple[float, float]             # normalised viewport coordinates
    aspect: float                         # width / height
    start: float                          # e where lam leaves 0
    gain: float                           # ray spacing 2**lam grows by gain per unit of e - start
    top: int                              # coarsest level drawn
    layers: Tuple[Layer, ...]             # coarsest first (drawing order)


def level_grid(width: int, height: int, level: int, base: float = 1.0) -> Tuple[int, int]:
    """Ray grid of a level: VTK truncates ``viewport / ImageSampleDistance``.

    Examples
    --------
    >>> level_grid(513, 512, 2)
    (128, 128)
    """
    distance = base * 2 ** level
    return int(width / distance), int(height / distance)


def plan_frame(viewport: Sequence[int], gaze: Sequence[float], radius: float, falloff: float,
               levels: int = DEFAULT_LEVELS, foveation: bool = True, max_level: int = 99,
               base_sample_distance: float = 1.0) -> Plan:
    """Which levels to draw, where each casts rays, and the blend parameters.

    Parameters
    ----------
    viewport : (x0, y0, width, height)
        The renderer's viewport in window pixels.
    gaze : (x, y)
        Gaze point, normalised viewport coordinates ((0, 0) bottom-left);
        may lie outside [0, 1].
    radius : float
        Foveal radius (full quality), viewport heights, >= 0.
    falloff : float
        Eccentricity over which the level rises from 0 to ``levels - 1``
        (the ray spacing growing linearly, see the module docstring),
        viewport heights, >= 0 (0: hard switches).
    levels : int, default: 3
        Pyramid levels available (1 = full quality only).
    foveation : bool, default: True
        False: level 0 everywhere.
    max_level : int
        Coarsest level allowed by the scene (e.g. a tiny volume).
    base_sample_distance : float, default: 1.0
        The image sample distance of level 0.

    Examples
    --------
    >>> plan = plan_frame((0, 0, 512, 512), (0.5, 0.5), 0.1, 0.1)
    >>> [(l.level, l.grid) for l in plan.layers]
    [(2, (128, 128)), (1, (256, 256)), (0, (512, 512))]
    >>> plan.layers[-1].scissor, plan.layers[1].scissor  # level 1: its buffer and the window
    ((179, 179, 154, 154), (0, 0, 370, 370))
    >>> round(plan.layers[-1].cast_to - plan.start, 4)  # level 0 stops where lam reaches 1
    0.0333
    >>> [l.level for l in plan_frame((0, 0, 512, 512), (0.5, 0.5), 2.0, 0.1).layers]
    [0]
    """
    x0, y0, width, height = (int(v) for v in viewport)
    width, height = max(width, 1), max(height, 1)
    aspect = width / height
    gx, gy = float(gaze[0]), float(gaze[1])
    usable = 0
    if foveation:
        for level in range(1, min(int(levels), int(max_level) + 1)):
            if min(level_grid(width, height, level, base_sample_distance)) < MIN_TEXELS:
                break
            usable = level
    reach = [0.0] + [REACH_TEXELS * max(1.0 / g[1], aspect / g[0]) for g in
                     (level_grid(width, height, k, base_sample_distance) for k in range(1, usable + 1))]
    gain = schedule_gain(falloff, levels)
    # no coarse level reaches into the fovea: level k is cast from its border e_(k-1) less its bilinear reach, and
    # its stretched picture reaches that far further in, so start is where e_(k-1) - 2 reach_k >= radius for every
    # k (level 1 decides with the default falloff from 256² up; a narrower falloff or a smaller view: a coarser
    # one, whose picture reached into the fovea's rim, under a semi-transparent or clipped level-0 ray)
    start = radius + max([2.0 * reach[k] - (2.0 ** (k - 1) - 1.0) / gain for k in range(1, usable + 1)], default=0.0)
    # eccentricities the viewport spans
    dx = max(0.0, -gx, gx - 1.0) * aspect
    dy = max(0.0, -gy, gy - 1.0)
    e_min = math.hypot(dx, dy)
    e_max = max(math.hypot((cx - gx) * aspect, cy - gy) for cx in (0.0, 1.0) for cy in (0.0, 1.0))
    top = min(usable, max(0, math.ceil(float(_lam(e_max - start, gain))))) if usable else 0
    layers = []
    for level in range(top, -1, -1):  # level k has a weight where k - 1 < lam < k + 1
        cast_from = -math.inf if level == 0 else _border(start, gain, level - 1) - reach[level]
        cast_to = math.inf if level == top else _border(start, gain, level + 1) + reach[level]
        if cast_to <= e_min or cast_from > e_max:
            continue
        grid = level_grid(width, height, level, base_sample_distance)
        scissor = None
        if math.isfinite(cast_to):
            scissor = _disc_box(x0, y0, width, height, gx, gy, cast_to, aspect)
            if scissor is None:
                continue
            if grid != (width, height):  # drawn into a reduced buffer, then stretched over the window
                scissor = _union(scissor, _disc_box(0, 0, grid[0], grid[1], gx, gy, cast_to, aspect))
                # from the origin: VTK clears the reduced buffer under this box only, and stretches
                # buffer texel p / 2**level onto window pixel p; a box holding the origin holds
                # p / 2**level for each of its p, so no texel of an earlier frame (another gaze)
                # is stretched into the picture
                scissor = _union(scissor, (0, 0, 1, 1))
        layers.append(Layer(level, base_sample_distance * 2 ** level, grid, cast_from, cast_to, scissor))
    return Plan((x0, y0, width, height), (gx, gy), aspect, start, gain, top, tuple(layers))


def schedule_gain(falloff: float, levels: int) -> float:
    """``gain`` of the level schedule: ray spacing grows from 1 to ``2**(levels - 1)`` over ``falloff``.

    ``(2**(levels - 1) - 1) / falloff``, the falloff taken as at least 1e-6
    (0: hard switches); 0 for a single level.

    Examples
    --------
    >>> schedule_gain(0.3, 3)
    10.0
    """
    return (2.0 ** (max(int(levels), 1) - 1) - 1.0) / max(float(falloff), 1e-6)


def _lam(x, gain):
    """Unclipped level at ``x = e - start``: ``log2(1 + gain * max(x, 0))`` (foveated_weight.glsl)."""
    return np.log2(1.0 + gain * np.maximum(x, 0.0))


def _border(start: float, gain: float, level: int) -> float:
    """Eccentricity where ``lam`` reaches ``level`` (inf if it never does)."""
    if level <= 0:
        return start
    return start + (2.0 ** level - 1.0) / gain if gain > 0 else math.inf


def level_border(plan: Plan, level: int) -> float:
    """Eccentricity (viewport heights) at which the unclipped ``lam`` reaches ``level``.

    ``plan.start + (2**level - 1) / plan.gain``: level ``k`` blends with
    level ``k + 1`` between ``level_border(plan, k)`` and
    ``level_border(plan, k + 1)``.  Beyond ``plan.top`` lam is clipped, so
    borders above it are not drawn.

    Examples
    --------
    >>> plan = plan_frame((0, 0, 512, 512), (0.5, 0.5), 0.1, 0.3)
    >>> [round(level_border(plan, k) - plan.start, 6) for k in range(3)]  # a third, then all of 0.3
    [0.0, 0.1, 0.3]
    """
    return _border(plan.start, plan.gain, int(level))


def _union(a: tuple, b: Optional[tuple]) -> tuple:
    if b is None:
        return a
    left, bottom = min(a[0], b[0]), min(a[1], b[1])
    right, top = max(a[0] + a[2], b[0] + b[2]), max(a[1] + a[3], b[1] + b[3])
    return (left, bottom, right - left, top - bottom)


def _disc_box(x0, y0, width, height, gx, gy, radius, aspect) -> Optional[tuple]:
    """Box of a ``width`` x ``height`` pixel grid holding the disc of ``radius`` viewport
    heights around the gaze (``aspect``: the viewport's), clipped to the grid; None if empty."""
    cx, cy = gx * width, gy * height
    rx, ry = radius / aspect * width, radius * height
    left, right = max(0, math.floor(cx - rx) - 2), min(width, math.ceil(cx + rx) + 2)
    bottom, top = max(0, math.floor(cy - ry) - 2), min(height, math.ceil(cy + ry) + 2)
    if right <= left or top <= bottom:
        return None
    return (x0 + left, y0 + bottom, right - left, top - bottom)


def eccentricity(grid: Sequence[int], gaze: Sequence[float], aspect: float) -> np.ndarray:
    """Eccentricity (viewport heights) of each texel centre of a grid, top row first.

    Examples
    --------
    >>> eccentricity((2, 1), (0.0, 0.5), 2.0)
    array([[0.5, 1.5]])
    """
    columns, rows = int(grid[0]), int(grid[1])
    x = (np.arange(columns) + 0.5) / columns
    y = ((np.arange(rows) + 0.5) / rows)[::-1]
    return np.hypot((x[None, :] - gaze[0]) * aspect, y[:, None] - gaze[1])


def desired_level(e: np.ndarray, plan: Plan) -> np.ndarray:
    """The continuous level ``lam(e)`` of the module docstring.

    Examples
    --------
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.2)
    >>> float(desired_level(0.0, plan)), float(desired_level(10.0, plan)) == plan.top
    (0.0, True)
    """
    return np.clip(_lam(np.asarray(e, float) - plan.start, plan.gain), 0.0, float(plan.top))


def layer_weight(level: int, lam: np.ndarray, plan: Plan) -> np.ndarray:
    """Premultiplied weight a level is drawn with (the shader's ``foveated_weight``).

    Examples
    --------
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.2)
    >>> layer_weight(0, np.array([0.0, 0.5, 1.0]), plan)
    array([1. , 0.5, 0. ])
    """
    return np.clip(level + 1.0 - np.asarray(lam, float), 0.0, 1.0)


def blend_shares(plan: Plan) -> dict:
    """Each drawn level's share of every full-resolution pixel (over compositing, opaque).

    Returns ``{level: array (height, width)}``, top row first; shares sum to 1.

    Examples
    --------
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.2)
    >>> shares = blend_shares(plan)
    >>> bool(np.allclose(sum(shares.values()), 1.0)), float(shares[0][32, 32])
    (True, 1.0)
    """
    _, _, width, height = plan.viewport
    lam = desired_level(eccentricity((width, height), plan.gaze, plan.aspect), plan)
    remaining = np.ones_like(lam)
    shares = {}
    for layer in reversed(plan.layers):  # finest first: it is drawn last, on top
        weight = layer_weight(layer.level, lam, plan)  # 1 for the coarsest: lam never exceeds top
        shares[layer.level] = weight * remaining
        remaining = remaining * (1.0 - weight)
    return shares


def upsample_bilinear(values: np.ndarray, size: Sequence[int]) -> np.ndarray:
    """Stretch a level's grid over the viewport as VTK's image-sample quad does.

    Texel ``i`` of ``columns`` spans pixels ``[i, i + 1) * width / columns``;
    interpolation is bilinear with clamped edges, over the texels that hold a
    value (NaN texels -- no ray, or a miss -- are first filled from their
    valid 8-neighbours, one texel deep, so the volume's outline does not
    shrink).  Arrays are top row first.

    Parameters
    ----------
    values : numpy.ndarray, shape (rows, columns)
    size : (width, height)

    Returns
    -------
    numpy.ndarray, shape (height, width)
        NaN where no valid texel is within reach.

    Examples
    --------
    >>> upsample_bilinear(np.array([[0.0, 4.0]]), (4, 1))
    array([[0., 1., 3., 4.]])
    """
    width, height = int(size[0]), int(size[1])
    values = np.asarray(values, dtype=np.float64)
    rows, columns = values.shape
    if (rows, columns) == (height, width):
        return values.copy()
    grid = _fill_one_texel(values)[::-1]  # bottom row first, like GL
    sx = (np.arange(width) + 0.5) * columns / width - 0.5
    sy = (np.arange(height) + 0.5) * rows / height - 0.5
    x0, y0 = np.floor(sx).astype(int), np.floor(sy).astype(int)
    fx, fy = sx - x0, sy - y0
    total = np.zeros((height, width))
    weight = np.zeros((height, width))
    for dy, wy in ((0, 1.0 - fy), (1, fy)):
        for dx, wx in ((0, 1.0 - fx), (1, fx)):
            texels = grid[np.clip(y0 + dy, 0, rows - 1)][:, np.clip(x0 + dx, 0, columns - 1)]
            w = wy[:, None] * wx[None, :] * ~np.isnan(texels)
            total += w * np.nan_to_num(texels)
            weight += w
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(weight > 1e-12, total / weight, np.nan)
    return out[::-1]


def _fill_one_texel(values: np.ndarray) -> np.ndarray:
    """NaN texels next to valid ones take the mean of their valid 8-neighbours."""
    valid = ~np.isnan(values)
    padded = np.pad(np.nan_to_num(values), 1)
    counts = np.pad(valid.astype(float), 1)
    rows, columns = values.shape
    total = np.zeros_like(values)
    number = np.zeros_like(values)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            total += padded[dy:dy + rows, dx:dx + columns]
            number += counts[dy:dy + rows, dx:dx + columns]
    filled = values.copy()
    grow = ~valid & (number > 0)
    filled[grow] = total[grow] / number[grow]
    return filled


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


def composite_values(plan: Plan, values: dict, skipped: Optional[dict] = None) -> np.ndarray:
    """The foveated image in data units from each level's float readout.

    Each level is stretched over the viewport (:func:`upsample_bilinear`)
    and weighted by its :func:`blend_shares`; a level without a value at a
    pixel (a miss) leaves its share to the others (NaN where none has one).
    A ray a content-adaptive mask left out (``skipped``) is not a miss: the
    levels beneath show through there, as they do on the GPU, so its share
    goes to them.  Where level 0 has a value outside its share (the
    silhouette band it casts, shaders/foveated_skip.glsl) the pixel is level
    0's value.

    Parameters
    ----------
    plan : Plan
    values : dict
        ``{level: array (rows, columns)}`` for the drawn levels, top row
        first, NaN where no ray was cast or the ray missed.
    skipped : dict, optional
        ``{level: bool array (rows, columns)}``, True where the level's mask
        cast no ray (the pixels whose nearest texel it is).

    Returns
    -------
    numpy.ndarray, shape (height, width), float64, top row first.

    Examples
    --------
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.2)
    >>> flat = {layer.level: np.full(layer.grid[::-1], 3.0) for layer in plan.layers}
    >>> float(np.nanmax(np.abs(composite_values(plan, flat) - 3.0)))
    0.0
    >>> flat[0][:] = np.nan   # level 0 missed everywhere: NaN where it is all of the picture
    >>> bool(np.isnan(composite_values(plan, flat)[32, 32]))
    True
    >>> skipped = {0: np.ones((64, 64), bool)}   # level 0 cast no ray: the coarser levels show through
    >>> float(composite_values(plan, flat, skipped)[32, 32])
    3.0
    """
    _, _, width, height = plan.viewport
    lam = desired_level(eccentricity((width, height), plan.gaze, plan.aspect), plan)
    total = np.zeros((height, width))
    weight = np.zeros((height, width))
    remaining = np.ones((height, width))
    band = None
    for layer in reversed(plan.layers):  # finest first: it is drawn last, on top
        if layer.level not in values:
            continue
        stretched = upsample_bilinear(values[layer.level], (width, height))
        present = ~np.isnan(stretched)
        share = layer_weight(layer.level, lam, plan) * remaining
        if skipped is not None and layer.level in skipped:
            share[coarse_texels(skipped[layer.level], (width, height))] = 0.0
        total[present] += share[present] * stretched[present]
        weight[present] += share[present]
        remaining = remaining - share
        if layer.level == 0:  # level 0 also casts in the volume's silhouette band, with weight 1 there
            band = (share <= 0) & present, stretched
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(weight > 0, total / np.where(weight > 0, weight, 1.0), np.nan)
    if band is not None:
        out[band[0]] = band[1][band[0]]
    return out


#: Edges of a box's projected outline the shaders take (a convex box projects to at most 6).
SILHOUETTE_EDGES = 6
#: The silhouette band is as wide as the rim of this level at most (shaders/foveated_skip.glsl).
SILHOUETTE_LEVEL_CAP = 2


def silhouette_edges(points: np.ndarray, aspect: float) -> Optional[np.ndarray]:
    """The outline of projected box corners as :data:`SILHOUETTE_EDGES` lines ``(nx, ny, c)``.

    ``points`` (N, 2) are normalised viewport coordinates; with ``q = (x *
    aspect, y)``, ``nx qx + ny qy + c`` is the distance inside each edge in
    viewport heights measured along the axes (the Euclidean distance divided
    by ``|cos| + |sin|`` of the edge normal: a step of ``s`` in x and ``s``
    in y changes it by at most ``s``), and the minimum over the edges the
    distance inside the convex hull (the foveated levels' silhouette band,
    shaders/foveated_skip.glsl).  Unused rows are ``(0, 0, 1e30)``.  None if
    the hull is degenerate (fewer than 3 vertices).

    Examples
    --------
    >>> square = np.array([[0.25, 0.25], [0.75, 0.25], [0.75, 0.75], [0.25, 0.75], [0.5, 0.5]])
    >>> edges = silhouette_edges(square, 1.0)
    >>> q = np.array([0.5, 0.3])
    >>> round(float(np.min(edges[:, :2] @ q + edges[:, 2])), 6)  # 0.05 from the bottom edge
    0.05
    >>> diamond = np.array([[0.5, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5]])
    >>> round(float(np.min(silhouette_edges(diamond, 1.0)[:, :2] @ [0.5, 0.5] + silhouette_edges(diamond, 1.0)[:, 2])), 6)
    0.25
    """
    q = np.unique(np.round(np.asarray(points, dtype=np.float64) * [aspect, 1.0], 12), axis=0)
    if len(q) < 3:
        return None

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []  # Andrew's monotone chain: counter-clockwise hull
    for point in q:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], point) <= 0:
            lower.pop()
        lower.append(point)
    for point in q[::-1]:
        while len(upper) >= 2 and cross(upper[-2], upper[-1], point) <= 0:
            upper.pop()
        upper.append(point)
    hull = np.array(lower[:-1] + upper[:-1])
    if len(hull) < 3 or len(hull) > SILHOUETTE_EDGES:
        return None
    edges = np.tile([0.0, 0.0, 1.0e30], (SILHOUETTE_EDGES, 1))
    for index, start in enumerate(hull):
        stop = hull[(index + 1) % len(hull)]
        direction = stop - start
        normal = np.array([-direction[1], direction[0]])  # inward (left)
        normal = normal / (abs(normal[0]) + abs(normal[1]))  # distance along the axes
        edges[index] = (normal[0], normal[1], -float(normal @ start))
    return edges


def silhouette_band(plan: Plan, silhouette, grid: Sequence[int]) -> np.ndarray:
    """Where level 0 casts rays for the volume's silhouette band (shaders/foveated_skip.glsl).

    At the texel centres of ``grid``: with ``d`` the distance inside the box's
    outline (along the axes: :func:`silhouette_edges`) and ``lam`` the level a
    pixel wants, ``0 < lam`` and ``d < (2^min(ceil(lam), 2) + 1) unit`` -- the
    pixels one of whose coarse neighbours (texel centres within one spacing
    along each axis) lies outside the outline, i.e. missed, for levels up to
    :data:`SILHOUETTE_LEVEL_CAP` (the default 3 levels: all of them; a 4th
    level's wider rim is left partly blended, as a band that wide would cost
    more rays than the level saves).  ``silhouette`` is
    ``(edges, unit)`` (one level-0 ray spacing in heights) or None (no band).

    Returns
    -------
    numpy.ndarray of bool, (rows, columns), top row first

    Examples
    --------
    >>> plan = plan_frame((0, 0, 64, 64), (0.5, 0.5), 0.1, 0.2)
    >>> square = np.array([[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.1, 0.9]])
    >>> band = silhouette_band(plan, (silhouette_edges(square, 1.0), 1 / 64), (64, 64))
    >>> bool(band[32, 7]), bool(band[32, 32]), bool(band[32, 2])
    (True, False, False)
    """
    columns, rows = int(grid[0]), int(grid[1])
    if silhouette is None:
        return np.zeros((rows, columns), bool)
    inside = outline_distance(plan, silhouette, grid)
    lam = desired_level(eccentricity(grid, plan.gaze, plan.aspect), plan)
    spacing = 2.0 ** np.minimum(np.ceil(lam), SILHOUETTE_LEVEL_CAP)
    return (lam > 0) & (inside >= 0) & (inside < (spacing + 1.0) * silhouette[1])


#: Slack (viewport heights, ~1/100 of a pixel at 1024^2) :func:`band_reaches_view` keeps over float32
#: rounding in the shader's band test.
BAND_MARGIN = 1.0e-5


def band_reaches_view(silhouette, aspect: float) -> bool:
    """Whether level 0's silhouette band (``shaders/foveated_band_dec.glsl``) can touch the view at all.

    The band holds pixels closer than ``(2^SILHOUETTE_LEVEL_CAP + 1) unit``
    inside the box's outline (:func:`silhouette_edges`).  The distance inside
    is the minimum of the edges' linear functions, so over the view's
    rectangle it is smallest at a corner: if every corner lies deeper than
    that (plus :data:`BAND_MARGIN`), no pixel is in the band -- as when the
    volume fills the view -- and level 0 can keep its scissor box (the
    pixels it would skip are discarded by its cast range anyway).
    ``silhouette``: ``(edges, unit)`` or None.

    Examples
    --------
    >>> square = np.array([[0.1, 0.1], [0.9, 0.1], [0.9, 0.9], [0.1, 0.9]])
    >>> band_reaches_view((silhouette_edges(square, 1.0), 1 / 64), 1.0)
    True
    >>> huge = np.array([[-1.0, -1.0], [2.0, -1.0], [2.0, 2.0], [-1.0, 2.0]])
    >>> band_reaches_view((silhouette_edges(huge, 1.0), 1 / 64), 1.0)
    False
    """
    if silhouette is None:
        return False
    edges, unit = np.asarray(silhouette[0], float), float(silhouette[1])
    corners = np.array([[0.0, 0.0], [aspect, 0.0], [0.0, 1.0], [aspect, 1.0]])
    inside = float((edges[:, :2] @ corners.T + edges[:, 2:3]).min())
    return inside < (2.0 ** SILHOUETTE_LEVEL_CAP + 1.0) * unit + BAND_MARGIN


def outline_distance(plan: Plan, silhouette, grid: Sequence[int], box: Optional[Sequence[int]] = None) -> np.ndarray:
    """Distance (viewport heights, along the axes) of each texel centre of ``grid`` inside the
    box's outline (:func:`silhouette_edges`; negative outside), top row first.

    ``box``: only the texels (x0, y0, columns, rows) of ``grid``, counted from its lower left.

    Examples
    --------
    >>> plan = plan_frame((0, 0, 4, 4), (0.5, 0.5), 0.1, 0.2)
    >>> square = np.array([[0.0, 0.0], [0.5, 0.0], [0.5, 1.0], [0.0, 1.0]])
    >>> outline_distance(plan, (silhouette_edges(square, 1.0), 0.25), (4, 1))
    array([[ 0.125,  0.125, -0.125, -0.375]])
    >>> outline_distance(plan, (silhouette_edges(square, 1.0), 0.25), (4, 1), (1, 0, 2, 1))
    array([[ 0.125, -0.125]])
    """
    edges = silhouette[0]
    columns, rows = int(grid[0]), int(grid[1])
    x0, y0, width, height = box if box is not None else (0, 0, columns, rows)
    x = (x0 + np.arange(width) + 0.5) / columns * plan.aspect
    y = ((y0 + np.arange(height) + 0.5) / rows)[::-1]
    inside = np.full((height, width), np.inf)
    for nx, ny, c in edges:
        inside = np.minimum(inside, nx * x[None, :] + ny * y[:, None] + c)
    return inside
