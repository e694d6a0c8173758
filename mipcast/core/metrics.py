"""Compare a rendered MIP with a reference: the harness of tests and benchmark.

Images are 2D float arrays in data units (the scalar value each ray reports)
with NaN where a ray misses the volume.  Screenshots are compared separately
with :func:`grey_diff`.
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from mipcast.core.validation import check_positive


def silhouette(reference: np.ndarray) -> np.ndarray:
    """Hit pixels of ``reference`` with a missed pixel (or the image edge) among their 8 neighbours.

    There a pixel centre can lie on the volume's outline, and whether the
    GPU's rasteriser covers it is a matter of rounding and fill rules.

    Examples
    --------
    >>> import numpy as np
    >>> silhouette(np.array([[np.nan, 1.0, 1.0, 1.0]] * 3)).astype(int)
    array([[0, 1, 1, 1],
           [0, 1, 0, 1],
           [0, 1, 1, 1]])
    """
    missed = np.pad(np.isnan(np.asarray(reference, dtype=np.float64)), 1, constant_values=True)
    near_miss = np.zeros(np.shape(reference), dtype=bool)
    rows, columns = np.shape(reference)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            near_miss |= missed[dy:dy + rows, dx:dx + columns]
    return near_miss & ~np.isnan(reference)


def error_map(rendered: np.ndarray, reference: np.ndarray, allow_silhouette: bool = False,
              may_miss: Optional[np.ndarray] = None) -> np.ndarray:
    """Absolute error per pixel, in data units.

    Pixels the reference misses (NaN) are NaN in the result whatever was
    rendered there: a background colour is not data.  A pixel the reference
    hits but the rendering does not is an error of the renderer, not a large
    number, so it raises instead of being averaged away; with
    ``allow_silhouette`` such pixels on the :func:`silhouette` are NaN in the
    result instead (rasterisation there is a matter of rounding), and so are
    misses inside ``may_miss`` (e.g. rays whose samples all fell on missing
    data where the exact interpolant has a finite part).

    Parameters
    ----------
    rendered : numpy.ndarray, shape (M, N)
        The image under test, data units, NaN for a miss.
    reference : numpy.ndarray, shape (M, N)
        The reference image, data units, NaN for a miss.
    allow_silhouette : bool
        Misses on the reference's :func:`silhouette` are NaN, not an error.
    may_miss : numpy.ndarray of bool, shape (M, N), optional
        Pixels where a miss is the rendering's rule, not an error.

    Returns
    -------
    numpy.ndarray, shape (M, N), float64
        ``abs(rendered - reference)``, NaN where ``reference`` is NaN.

    Raises
    ------
    ValueError
        If the shapes differ (both are named), or ``rendered`` is NaN where
        ``reference`` is a hit (the message gives the count and the first
        such pixel as ``(row, column)``).

    Examples
    --------
    >>> import numpy as np
    >>> reference = np.array([[0.0, 1.0], [np.nan, 0.5]])
    >>> error_map(np.array([[0.25, 1.0], [0.3, 0.75]]), reference)
    array([[0.25, 0.  ],
           [ nan, 0.25]])
    """
    rendered = np.asarray(rendered, dtype=np.float64)
    reference = np.asarray(reference, dtype=np.float64)
    if rendered.shape != reference.shape:
        raise ValueError(f"rendered has shape {rendered.shape} but reference has shape "
                         f"{reference.shape}; render at the reference's size")
    missed = np.isnan(rendered) & ~np.isnan(reference)
    if allow_silhouette:
        missed &= ~silhouette(reference)
    if may_miss is not None:
        missed &= ~np.asarray(may_miss, dtype=bool)
    if missed.any():
        first = tuple(int(v) for v in np.argwhere(missed)[0])
        raise ValueError(f"the GPU missed {int(missed.sum())} hit pixels (first at "
                         f"(row, column) {first}); check the camera and clipping range")
    return np.abs(rendered - reference)


def summary(rendered: np.ndarray, reference: np.ndarray, data_range: float,
            window: Optional[Tuple[float, float]] = None,
            foreground: Optional[np.ndarray] = None, may_miss: Optional[np.ndarray] = None) -> dict:
    """Error statistics of a rendering against a reference.

    Only pixels both the reference and the rendering hit count; rendered
    misses on the reference's :func:`silhouette` are counted in
    ``silhouette_misses`` (misses elsewhere raise).  One grey level is
    ``(window[1] - window[0]) / 255``, or ``data_range / 255`` without a
    window.  Percentiles interpolate linearly (``numpy.percentile``'s default).

    Parameters
    ----------
    rendered : numpy.ndarray, shape (M, N)
        The image under test, data units, NaN for a miss.
    reference : numpy.ndarray, shape (M, N)
        The reference image, data units, NaN for a miss.
    data_range : float
        Span of the data (max - min), the 100 % of the ``*_pct`` figures.
    window : (float, float), optional
        Display window ``(low, high)`` in data units.
    foreground : numpy.ndarray of bool, shape (M, N), optional
        Pixels of interest, default: ``reference > low + 0.25 * (high - low)``
        where ``(low, high)`` is ``window``, or else the minimum and maximum
        of the hit reference values.
    may_miss : numpy.ndarray of bool, shape (M, N), optional
        As :func:`error_map`: misses there (off the silhouette) are counted in
        ``missing_data_misses`` instead of raising.

    Returns
    -------
    dict
        ``mean``, ``p99``, ``max`` (error in data units), ``mean_pct``,
        ``p99_pct``, ``max_pct`` (in % of ``data_range``), ``over_1_grey``
        (share of hit pixels whose error exceeds one grey level),
        ``within_1_grey`` (1 - that), ``hit_pixels``, ``grey_level``,
        ``silhouette_misses`` and ``missing_data_misses``; then the same figures over the foreground hits, prefixed ``fg_``
        (all NaN, and ``fg_hit_pixels`` 0, if there are none).

    Raises
    ------
    ValueError
        As :func:`error_map`; if ``data_range`` is not > 0, the window is
        empty, or ``foreground`` has the wrong shape.

    Examples
    --------
    >>> import numpy as np
    >>> reference = np.array([[0.0, 1.0], [np.nan, 0.5]])
    >>> stats = summary(np.array([[0.0, 0.5], [9.0, 0.5]]), reference, 2.0)
    >>> stats["max"], stats["max_pct"], stats["over_1_grey"], stats["hit_pixels"]
    (0.5, 25.0, 0.3333333333333333, 3)
    >>> stats["fg_hit_pixels"], stats["fg_max"]
    (2, 0.5)
    """
    errors = error_map(rendered, reference, allow_silhouette=True, may_miss=may_miss)
    reference = np.asarray(reference, dtype=np.float64)
    data_range = check_positive("data_range", data_range)
    hit = ~np.isnan(reference)
    unhit = hit & np.isnan(errors)
    data_misses = 0 if may_miss is None else int(np.count_nonzero(unhit & may_miss & ~silhouette(reference)))
    silhouette_misses = int(np.count_nonzero(unhit)) - data_misses
    if window is None:
        grey = data_range / 255.0
        low, high = ((reference[hit].min(), reference[hit].max()) if hit.any()
                     else (0.0, 0.0))
    else:
        low, high = (float(v) for v in window)
        if not high > low:
            raise ValueError(f"window must be (low, high) with high > low, got {window!r}")
        grey = (high - low) / 255.0
    if foreground is None:
        with np.errstate(invalid="ignore"):
            foreground = reference > low + 0.25 * (high - low)
    foreground = np.asarray(foreground, dtype=bool)
    if foreground.shape != reference.shape:
        raise ValueError(f"foreground has shape {foreground.shape} but reference has "
                         f"shape {reference.shape}")
    result = {"grey_level": grey, "silhouette_misses": silhouette_misses, "missing_data_misses": data_misses}
    hit &= ~np.isnan(errors)
    for prefix, mask in (("", hit), ("fg_", hit & foreground)):
        values = errors[mask]
        if values.size:
            over = float(np.mean(values > grey))
            stats = {"mean": float(values.mean()), "p99": float(np.percentile(values, 99)),
                     "max": float(values.max())}
        else:
            over = float("nan")
            stats = dict.fromkeys(("mean", "p99", "max"), float("nan"))
        stats.update({f"{k}_pct": 100.0 * v / data_range for k, v in list(stats.items())})
        stats.update(over_1_grey=over, within_1_grey=1.0 - over, hit_pixels=int(values.size))
        result.update({prefix + k: v for k, v in stats.items()})
    return result


def grey_diff(a8: np.ndarray, b8: np.ndarray) -> dict:
    """Compare two 8-bit screenshots, e.g. two GPU renderings.

    Parameters
    ----------
    a8, b8 : numpy.ndarray of uint8, shape (M, N[, C])
        Screenshots (grey, RGB or RGBA) of the same size.

    Returns
    -------
    dict
        ``within_1``: share of pixels whose largest channel difference is at
        most 1; ``max``: the largest channel difference (int).

    Raises
    ------
    TypeError
        If either image is not uint8.
    ValueError
        If the shapes differ.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((1, 4, 3), np.uint8)
    >>> b = a.copy(); b[0, 1, 0] = 1; b[0, 2, 2] = 7
    >>> grey_diff(a, b)
    {'within_1': 0.75, 'max': 7}
    """
    a8, b8 = np.asarray(a8), np.asarray(b8)
    if a8.dtype != np.uint8 or b8.dtype != np.uint8:
        raise TypeError(f"expected two uint8 images, got {a8.dtype} and {b8.dtype}")
    if a8.shape != b8.shape:
        raise ValueError(f"first image has shape {a8.shape} but second has shape {b8.shape}")
    diff = np.abs(a8.astype(np.int16) - b8.astype(np.int16))
    if diff.ndim == 3:
        diff = diff.max(axis=2)
    return {"within_1": float(np.mean(diff <= 1)), "max": int(diff.max(initial=0))}
