"""Float64 projections along rays: sampled as the GPU samples, and exact (cell by cell).

Maximum, minimum and mean of the samples at ``entry + k * step``, and of the
trilinear interpolant itself: per crossed cell a cubic in the ray parameter,
whose maximum (ends and derivative roots), minimum (the maximum of the
negated cubic) and integral are exact.
"""
from __future__ import annotations

import numpy as np

from mipcast.core.clipping import crop_visible, sample_kept, sample_visible
from mipcast.reference.rays import BUDGET, cells, gather, trilinear


def _sample_count(length: np.ndarray, step: float) -> np.ndarray:
    """VTK's number of samples per ray: ``max(1, floor(length / step + 1e-9))``."""
    return np.maximum(1, np.floor(length / step + 1e-9)).astype(np.int64)


def _sampled_reduce(values: np.ndarray, entry: np.ndarray, direction: np.ndarray, length: np.ndarray,
                    step: float, reduce: np.ufunc, empty: float, keep=None, crop=None,
                    floor: float = -np.inf, sampler=trilinear) -> tuple:
    """``reduce`` (np.maximum, np.minimum, np.add) over the samples ``entry + k * step``, k = 1..K.

    ``keep = (lo, hi)`` (N,): only samples with ``lo <= k * step <= hi`` count (within
    :data:`mipcast.core.clipping.SAMPLE_ON_PLANE` steps: a sample on a plane counts).
    ``crop = (low, high, flags)`` (index space, :func:`mipcast.core.clipping.crop_visible`):
    only samples in a visible cropping region count.  Only samples ``>= floor`` count.
    ``sampler``: :func:`~mipcast.reference.rays.trilinear`, or :func:`~mipcast.reference.rays.nearest`
    (the volume property's nearest-neighbour interpolation).  Returns the reduction (``empty`` where no sample counted) and the number of
    samples that counted.
    """
    count = _sample_count(length, step)
    best = np.full(len(length), empty)
    used = np.zeros(len(length), np.int64)
    first = 1
    while first <= count.max():
        rows = np.flatnonzero(count >= first)
        k = np.arange(first, min(count.max(), first + max(1, BUDGET // len(rows)) - 1) + 1)
        position = entry[rows, None, :] + (k[:, None] * step) * direction[rows, None, :]
        sample = sampler(values, position.reshape(-1, 3)).reshape(len(rows), len(k))
        valid = k[None, :] <= count[rows, None]
        if keep is not None:  # a clipped ray keeps the unclipped ray's sample positions
            valid &= sample_kept(k * step, keep[0][rows, None], keep[1][rows, None], step)  # (one on a plane too)
        if crop is not None:  # a sample in a hidden cropping region does not count (one on a boundary does)
            valid &= sample_visible(position, step * direction[rows, None, :], *crop)
        if floor > -np.inf:
            valid &= sample >= floor
        sample[~valid] = empty
        best[rows] = reduce(best[rows], reduce.reduce(sample, axis=1))
        used[rows] += valid.sum(axis=1)
        first = k[-1] + 1
    return best, used


def sampled_maximum(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
                    length: np.ndarray, step: float, keep=None, crop=None, sampler=trilinear) -> np.ndarray:
    """VTK-style sampled maximum along rays starting at their box entry (``-inf``: no sample kept)."""
    return _sampled_reduce(values, entry, direction, length, step, np.maximum, -np.inf, keep, crop,
                           sampler=sampler)[0]


def sampled_minimum(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
                    length: np.ndarray, step: float, keep=None, crop=None, sampler=trilinear) -> np.ndarray:
    """VTK-style sampled minimum (MINIMUM_INTENSITY blend) along rays starting at their box entry."""
    return _sampled_reduce(values, entry, direction, length, step, np.minimum, np.inf, keep, crop,
                           sampler=sampler)[0]


def sampled_mean(values: np.ndarray, entry: np.ndarray, direction: np.ndarray, length: np.ndarray, step: float,
                 keep=None, crop=None, floor: float = -np.inf, sampler=trilinear) -> np.ndarray:
    """Mean of the same samples (VTK's AVERAGE_INTENSITY blend, every sample in range, opaque).

    ``floor``: only samples ``>= floor`` count (missing data: the samples
    the fill pulled below the finite minimum are missing); NaN where none counts.
    """
    total, used = _sampled_reduce(values, entry, direction, length, step, np.add, 0.0, keep, crop, floor, sampler)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(used > 0, total / np.maximum(used, 1), np.nan)


def _crossings(entry: np.ndarray, direction: np.ndarray, length: np.ndarray, crop=None) -> np.ndarray:
    """Sorted ray parameters of box entry, exit and all grid-plane crossings.

    Returns an (N, S) array with ``0`` and ``length`` included, padded with
    ``inf``; consecutive finite values bound the segments of single cells.
    With ``crop = (low, high, flags)`` the crossings of the six cropping
    planes (index space) are among them: each segment then lies in one
    cell and one cropping region.
    """
    exit_ = entry + length[:, None] * direction
    low = np.ceil(np.minimum(entry, exit_))
    count = np.where(direction != 0, np.floor(np.maximum(entry, exit_)) - low + 1, 0)
    count = np.maximum(count, 0).astype(np.int64)
    columns = [length[:, None] * 0.0, length[:, None]]
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis in range(3):
            plane = low[:, axis, None] + np.arange(count[:, axis].max())
            t = (plane - entry[:, axis, None]) / direction[:, axis, None]
            t = np.clip(t, 0.0, length[:, None])
            columns.append(np.where(np.arange(t.shape[1]) < count[:, axis, None], t, np.inf))
        if crop is not None:
            for axis in range(3):
                for plane in (crop[0][axis], crop[1][axis]):
                    t = (plane - entry[:, axis]) / direction[:, axis]
                    inside = np.isfinite(t) & (t > 0.0) & (t < length)
                    columns.append(np.where(inside, t, np.inf)[:, None])
    return np.sort(np.concatenate(columns, axis=1), axis=1)


def _lerp_poly(low: list, high: list, w0: np.ndarray, dw: np.ndarray) -> list:
    """Coefficients (low order first) of ``low + (w0 + dw s) (high - low)``."""
    diff = [h - lo for lo, h in zip(low, high)]
    out = [lo + w0 * d for lo, d in zip(low, diff)] + [0.0]
    for order, d in enumerate(diff):
        out[order + 1] = out[order + 1] + dw * d
    return out


def _cell_cubics(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
                 length: np.ndarray, crop=None, corner_bounds: bool = False, extrapolate: bool = False) -> tuple:
    """Per crossed cell segment, the cubic ``((a s + b) s + c) s + d`` (s in [0, 1]) of the interpolant.

    Returns ``(a, b, c, d, span, starts, visible)``: coefficients and length
    (world units) of each segment, the index of each ray's first segment (the
    segments of ray r are ``starts[r]`` up to ``starts[r + 1]``), and whether
    each segment counts: with ``crop = (low, high, flags)`` the segments are
    also split at the cropping planes and a segment counts where its
    midpoint's cropping region is visible (all count without ``crop``); with
    ``corner_bounds`` also the smallest and the largest of each cell's 8 corners.
    ``extrapolate``: a segment off the box is read from its cell (the
    nearest, clamped) extrapolated, not clamped onto the box: what the GPU's
    cell walk reads for a ray that starts off the box (a multisampled pixel
    whose centre lies off it, :func:`mipcast.mappers.outline_rays.face_rays`).
    """
    bounds = _crossings(entry, direction, length, crop)
    valid = np.isfinite(bounds[:, 1:])
    ray, column = np.nonzero(valid)
    t0, t1 = bounds[ray, column], bounds[ray, column + 1]
    start = entry[ray] + t0[:, None] * direction[ray]
    stop = entry[ray] + t1[:, None] * direction[ray]
    middle = 0.5 * (start + stop)
    cell = cells(values, middle)
    visible = np.ones(len(t0), bool) if crop is None else crop_visible(middle, *crop)
    u0 = start - cell if extrapolate else np.clip(start - cell, 0.0, 1.0)
    du = (stop - cell if extrapolate else np.clip(stop - cell, 0.0, 1.0)) - u0

    corners = gather(values, cell)
    poly = [corners]
    for axis in range(3):
        poly = _lerp_poly([p[:, 0::2] for p in poly], [p[:, 1::2] for p in poly],
                          u0[:, axis, None], du[:, axis, None])
    d, c, b, a = (p[:, 0] for p in poly)
    starts = np.concatenate([[0], np.cumsum(valid.sum(axis=1))[:-1]])
    if corner_bounds:
        return a, b, c, d, t1 - t0, starts, visible, corners.min(axis=1), corners.max(axis=1)
    return a, b, c, d, t1 - t0, starts, visible


def exact_maximum(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
                  length: np.ndarray, crop=None, extrapolate: bool = False) -> np.ndarray:
    """Exact maximum of the trilinear interpolant along each ray segment
    (over its visible cropping regions' pieces with ``crop``; ``-inf`` where none is;
    ``extrapolate``: see :func:`_cell_cubics`)."""
    a, b, c, d, _, starts, visible = _cell_cubics(values, entry, direction, length, crop, extrapolate=extrapolate)
    best = np.maximum(d, ((a + b) + c) + d)
    qa, qb = 3.0 * a, 2.0 * b
    disc = qb * qb - 4.0 * qa * c
    with np.errstate(divide="ignore", invalid="ignore"):
        q = -0.5 * (qb + np.copysign(np.sqrt(np.maximum(disc, 0.0)), qb))
        for root in (q / qa, c / q):
            inside = (disc >= 0) & (root > 0) & (root < 1)
            s = np.where(inside, root, 0.0)
            best = np.where(inside, np.maximum(best, ((a * s + b) * s + c) * s + d), best)
    return np.maximum.reduceat(np.where(visible, best, -np.inf), starts)


def exact_minimum(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
                  length: np.ndarray, crop=None, extrapolate: bool = False) -> np.ndarray:
    """Exact minimum of the trilinear interpolant along each ray: minus the maximum of its negation
    (negation is exact, and the negated cubics are the cubics of the negated corners)."""
    return -exact_maximum(-values, entry, direction, length, crop, extrapolate)


def exact_mean(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
               length: np.ndarray, crop=None, floor: float = -np.inf, extrapolate: bool = False,
               bounded: bool = False) -> np.ndarray:
    """Exact mean of the trilinear interpolant along each ray inside the volume.

    The integral of each cell's cubic over its segment is
    ``(d + c / 2 + b / 3 + a / 4) * span``; the mean is the sum over the
    ray's cells divided by its length.  A ray of zero length (touching an
    edge) gets the value at its entry.  With ``crop``: the integral over the
    visible pieces divided by their length (the entry of the first visible
    piece if that length is 0; NaN where no piece is visible).  ``floor``
    (missing data, filled below it): only the part of the ray where the
    interpolant is ``>= floor`` counts (its integral and its length;
    :func:`_covered_part`), the limit of :func:`sampled_mean`'s rule; NaN for
    a ray with no such part.  ``extrapolate``: see :func:`_cell_cubics`.  ``bounded``: the mean clamped
    into the smallest and largest corner of the counted cells (a cell with a missing corner: from ``floor``
    up), as the GPU clamps it with missing values (``shaders/amip_average_hooks.glsl``, MC_AVERAGE_MISSING): a no-op inside the
    box, where the mean lies there; off the box (``extrapolate``) the extrapolated cubic may leave it.
    """
    a, b, c, d, span, starts, visible, lowest, highest = _cell_cubics(values, entry, direction, length, crop,
                                                                      corner_bounds=True, extrapolate=extrapolate)
    part, covered = d + c / 2.0 + b / 3.0 + a / 4.0, np.ones_like(span)
    counts = visible.copy()
    if floor > -np.inf:
        cut = lowest < floor  # a missing corner: only the part where the interpolant is >= floor counts
        part[cut], covered[cut] = _covered_part(a[cut], b[cut], c[cut], d[cut], floor)
        counts &= ~cut | (d >= floor)  # (a cell of finite corners counts whole, even extrapolated below it)
    integral = np.add.reduceat(np.where(visible, part * span, 0.0), starts)
    total = np.add.reduceat(np.where(visible, covered * span, 0.0), starts)
    # the first counted segment's entry value (a ray of zero length)
    index = np.arange(len(d))
    first = np.minimum.reduceat(np.where(counts, index, len(d)), starts)
    entry_value = np.where(first < len(d), d[np.minimum(first, len(d) - 1)], np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        mean = np.where(total > 0, integral / np.where(total > 0, total, 1.0), entry_value)
    if bounded:
        cut = lowest < floor
        kept = visible & (~cut | (covered > 0.0))  # the cells counted: their corners bound the mean
        below = np.minimum.reduceat(np.where(kept, np.where(cut, floor, lowest), np.inf), starts)
        above = np.maximum.reduceat(np.where(kept, highest, -np.inf), starts)
        mean = np.where(below <= above, np.clip(mean, below, above), mean)
    return mean


def _covered_part(a, b, c, d, floor: float, halvings: int = 40) -> tuple:
    """Integral and length over s in [0, 1] of the part where ``((a s + b) s + c) s + d >= floor``.

    As the GPU does it (shaders/amip_average_hooks.glsl, MC_AVERAGE_MISSING): the cubic split at
    its derivative's roots (the same cancellation-free formula, clamped into
    [0, 1]) into monotone pieces; a piece crossing ``floor`` is cut at the
    crossing, found by bisection.

    Examples
    --------
    >>> one = np.ones(1)
    >>> [round(float(v[0]), 6) for v in _covered_part(0 * one, 0 * one, one, 0 * one, 0.5)]  # f = s
    [0.375, 0.5]
    """
    def at(s):
        return ((a * s + b) * s + c) * s + d

    def mean(s, t):  # over [s, t], without cancellation for short pieces
        return d + 0.5 * c * (s + t) + b * (s * s + s * t + t * t) / 3.0 + 0.25 * a * (s + t) * (s * s + t * t)

    qa, qb = 3.0 * a, 2.0 * b
    disc = np.maximum(qb * qb - 4.0 * qa * c, 0.0)
    qq = -0.5 * (qb + np.where(qb < 0.0, -1.0, 1.0) * np.sqrt(disc))
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = np.clip(np.where(np.abs(qa) > 1e-20, qq / qa, 0.0), 0.0, 1.0)
        r2 = np.clip(np.where(np.abs(qq) > 1e-20, c / qq, 0.0), 0.0, 1.0)
    ends = [np.zeros_like(a), np.minimum(r1, r2), np.maximum(r1, r2), np.ones_like(a)]
    integral, length = np.zeros_like(a), np.zeros_like(a)
    for s0, s1 in zip(ends[:-1], ends[1:]):
        below0, below1 = at(s0) < floor, at(s1) < floor
        lo, hi = s0.copy(), s1.copy()
        for _ in range(halvings):
            m = 0.5 * (lo + hi)
            same = (at(m) < floor) == below0
            lo, hi = np.where(same, m, lo), np.where(same, hi, m)
        r = 0.5 * (lo + hi)
        crossing = below0 != below1
        start = np.where(crossing & below0, r, s0)
        stop = np.where(crossing & ~below0, r, s1)
        keep = (s1 > s0) & ~(below0 & below1)
        integral += np.where(keep, (stop - start) * mean(start, stop), 0.0)
        length += np.where(keep, stop - start, 0.0)
    return integral, length
