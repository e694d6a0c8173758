"""Float64 maxima along rays: sampled as the GPU samples, and exact (cell by cell)."""
from __future__ import annotations

import numpy as np

from mipcast.reference.rays import BUDGET, cells, gather, trilinear


def sampled_maximum(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
         length: np.ndarray, step: float, keep=None) -> np.ndarray:
    """VTK-style sampled maximum along rays starting at their box entry.

    ``keep = (lo, hi)`` (N,): only samples with ``lo <= k * step <= hi`` count
    (a clipped ray keeps the unclipped ray's sample positions); ``-inf`` where
    none is left.
    """
    count = np.maximum(1, np.floor(length / step + 1e-9)).astype(np.int64)
    best = np.full(len(length), -np.inf)
    first = 1
    while first <= count.max():
        rows = np.flatnonzero(count >= first)
        k = np.arange(first, min(count.max(), first + max(1, BUDGET // len(rows)) - 1) + 1)
        position = entry[rows, None, :] + (k[:, None] * step) * direction[rows, None, :]
        sample = trilinear(values, position.reshape(-1, 3)).reshape(len(rows), len(k))
        sample[k > count[rows, None]] = -np.inf
        if keep is not None:
            at = k * step
            sample[(at < keep[0][rows, None]) | (at > keep[1][rows, None])] = -np.inf
        best[rows] = np.maximum(best[rows], sample.max(axis=1))
        first = k[-1] + 1
    return best


def _crossings(entry: np.ndarray, direction: np.ndarray, length: np.ndarray) -> np.ndarray:
    """Sorted ray parameters of box entry, exit and all grid-plane crossings.

    Returns an (N, S) array with ``0`` and ``length`` included, padded with
    ``inf``; consecutive finite values bound the segments of single cells.
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
    return np.sort(np.concatenate(columns, axis=1), axis=1)


def _lerp_poly(low: list, high: list, w0: np.ndarray, dw: np.ndarray) -> list:
    """Coefficients (low order first) of ``low + (w0 + dw s) (high - low)``."""
    diff = [h - lo for lo, h in zip(low, high)]
    out = [lo + w0 * d for lo, d in zip(low, diff)] + [0.0]
    for order, d in enumerate(diff):
        out[order + 1] = out[order + 1] + dw * d
    return out


def exact_maximum(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
           length: np.ndarray) -> np.ndarray:
    """Exact maximum of the trilinear interpolant along each ray segment."""
    bounds = _crossings(entry, direction, length)
    valid = np.isfinite(bounds[:, 1:])
    ray, column = np.nonzero(valid)
    t0, t1 = bounds[ray, column], bounds[ray, column + 1]
    start = entry[ray] + t0[:, None] * direction[ray]
    stop = entry[ray] + t1[:, None] * direction[ray]
    cell = cells(values, 0.5 * (start + stop))
    u0 = np.clip(start - cell, 0.0, 1.0)
    du = np.clip(stop - cell, 0.0, 1.0) - u0

    poly = [gather(values, cell)]
    for axis in range(3):
        poly = _lerp_poly([p[:, 0::2] for p in poly], [p[:, 1::2] for p in poly],
                          u0[:, axis, None], du[:, axis, None])
    d, c, b, a = (p[:, 0] for p in poly)

    best = np.maximum(d, ((a + b) + c) + d)
    qa, qb = 3.0 * a, 2.0 * b
    disc = qb * qb - 4.0 * qa * c
    with np.errstate(divide="ignore", invalid="ignore"):
        q = -0.5 * (qb + np.copysign(np.sqrt(np.maximum(disc, 0.0)), qb))
        for root in (q / qa, c / q):
            inside = (disc >= 0) & (root > 0) & (root < 1)
            s = np.where(inside, root, 0.0)
            best = np.where(inside, np.maximum(best, ((a * s + b) * s + c) * s + d), best)
    starts = np.concatenate([[0], np.cumsum(valid.sum(axis=1))[:-1]])
    return np.maximum.reduceat(best, starts)
