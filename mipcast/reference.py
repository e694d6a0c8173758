"""Float64 CPU reference renderer: the ground truth for every GPU image.

Rays come from :func:`mipcast.camera_rays.camera_rays` (VTK's own pixel-centre
rays, in index space); the volume is interpolated trilinearly between point
values, as the GPU's clamp-to-edge 3D texture does.

See docs/methods.md, section Reference (``docs/methods.md#reference``).
"""
from __future__ import annotations

from functools import partial
from typing import Any

import numpy as np
from numpy.lib.stride_tricks import as_strided
from vtkmodules.vtkCommonDataModel import vtkImageData

from .camera_rays import camera_rays
from .validation import check_choice, check_image, check_positive, check_size

#: Parameters each method accepts; all of them are required ("demip" also
#: takes optional ones: :data:`mipcast.reference_demip.PARAMETERS`).
METHODS = {"mip": ("sample_distance",), "exact": (), "demip": ("sample_distance", "window")}

_RAY_CHUNK = 65536      # rays per chunk
_BUDGET = 1 << 20       # samples or segments held in memory at once


def render(image: vtkImageData, camera: Any, size: tuple, method: str = "mip",
           **params: Any) -> np.ndarray:
    """Render a maximum intensity projection in float64 on the CPU.

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        Volume with one-component point scalars (not modified).
    camera : vtkCamera
        The view (not modified); orthographic or perspective.
    size : tuple of int
        Window size ``(width, height)`` in pixels.
    method : str, default: "mip"
        ``"mip"``: VTK's sampled GPU MIP.  Samples sit at
        ``t_enter + k * sample_distance`` for ``k = 1..K``,
        ``K = max(1, floor((t_exit - t_enter) / sample_distance + 1e-9))``
        (VTK steps once before its first sample); each position is clamped
        to the point bounds and interpolated trilinearly.
        ``"exact"``: the exact maximum of the trilinear interpolant over the
        whole ray segment inside the volume.  Per crossed cell the
        interpolant along the ray is a cubic, whose coefficients are computed
        analytically from the cell's 8 corners (three nested lerps of
        polynomials, so ``f(0)`` is exactly the trilinear value); the cell's
        maximum is taken over both ends and the real roots of the derivative
        inside the segment.  Degenerate cases (constant, linear or quadratic
        restriction, zero-length segments at edges and corners, rays along
        faces) need no special branch: every candidate is a point of the
        segment, so the result never exceeds the true maximum.
        ``"demip"``: depth-enhanced MIP on the ``"mip"`` samples; returns
        depth, final colour or maximum (its ``output`` parameter), see
        :func:`mipcast.reference_demip.render_demip` for its parameters.
    **params
        ``sample_distance : float`` (method ``"mip"``, required): distance
        between samples in world units, > 0.  Method ``"exact"`` takes none.

    Returns
    -------
    numpy.ndarray, shape (height, width)
        Maximum along each pixel's ray in the data units of the scalars;
        NaN where the ray misses the volume.  Row 0 is the top row.

    Raises
    ------
    TypeError
        If the image is not image data, a parameter is unknown or missing.
    ValueError
        If the image, size, method or a parameter value is invalid.

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.util.numpy_support import numpy_to_vtk
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> image = vtkImageData()
    >>> image.SetDimensions(3, 3, 3)
    >>> x = np.tile(np.arange(3.0), 9)            # value = i index
    >>> _ = image.GetPointData().SetScalars(numpy_to_vtk(x, deep=True))
    >>> camera = vtkCamera()
    >>> camera.SetPosition(1, 1, 10)
    >>> camera.SetFocalPoint(1, 1, 0)
    >>> camera.ParallelProjectionOn()
    >>> camera.SetParallelScale(1.0)
    >>> print(render(image, camera, (3, 2), method="exact").round(3))
    [[0. 1. 2.]
     [0. 1. 2.]]
    >>> print(render(image, camera, (3, 1), method="mip", sample_distance=0.5).round(3))
    [[nan  1. nan]]
    """
    volume = check_image(image)
    width, height = check_size(size)
    method = check_choice("method", method, tuple(METHODS))
    if method == "demip":  # depth, colour or maximum: see mipcast.reference_demip
        from .reference_demip import render_demip
        return render_demip(image, camera, (width, height), **params)
    allowed = METHODS[method]
    unknown = sorted(set(params) - set(allowed))
    if unknown:
        raise TypeError(f"unknown parameter(s) for method {method!r}: {', '.join(unknown)}; "
                        f"valid: {', '.join(allowed) or 'none'}")
    missing = [name for name in allowed if name not in params]
    if missing:
        raise TypeError(f"method {method!r} requires parameter(s): {', '.join(missing)}")
    if method == "mip":
        step = check_positive("sample_distance", params["sample_distance"])

    hit, entry, direction, length = _hit_rays(image, camera, (width, height))
    values = np.array(volume, dtype=np.float64)

    if method == "mip":
        chunk, kernel = _RAY_CHUNK, partial(_mip, step=step)
    else:
        chunk, kernel = max(1, _BUDGET // (sum(values.shape) + 2)), _exact
    found = np.empty(len(length))
    for start in range(0, len(length), chunk):
        part = slice(start, start + chunk)
        found[part] = kernel(values, entry[part], direction[part], length[part])
    return _scatter(found, hit, height, width)


def _hit_rays(image: vtkImageData, camera: Any, size: tuple) -> tuple:
    """The pixels' rays that meet the volume, in index space.

    Returns ``hit`` (bool, H*W, row-major, top row first) and, per hit ray,
    its ``entry`` point (N, 3), ``direction`` (N, 3, per unit world length)
    and ``length`` (N,) inside the box (world units).
    """
    rays = camera_rays(image, camera, size)
    hit = rays.hit.ravel()
    t_enter = rays.t_enter.ravel()[hit]
    length = rays.t_exit.ravel()[hit] - t_enter
    direction = rays.direction.reshape(-1, 3)[hit]
    entry = rays.origin.reshape(-1, 3)[hit] + t_enter[:, None] * direction
    return hit, entry, direction, length


def _scatter(found: np.ndarray, hit: np.ndarray, height: int, width: int) -> np.ndarray:
    """Per-hit-ray results (N, ...) as an (H, W, ...) image, NaN where the ray misses."""
    out = np.full((width * height,) + found.shape[1:], np.nan)
    out[hit] = found
    return out.reshape((height, width) + found.shape[1:])


def _gather(values: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """Corner values (M, 8) of cells ``cell`` (M, 3); column b = dx + 2 dy + 4 dz."""
    nz, ny, nx = values.shape
    flat = values.ravel()
    step = flat.strides[0]
    # item n of this view is the 2x2x2 block of points whose first corner is point n
    blocks = as_strided(flat, shape=(flat.size - nx * ny - nx - 1, 2, 2, 2),
                        strides=(step, nx * ny * step, nx * step, step), writeable=False)
    return blocks[cell[:, 0] + nx * (cell[:, 1] + ny * cell[:, 2])].reshape(-1, 8)


def _cells(values: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Index (M, 3) of the cell holding each position, clipped to the grid."""
    top = np.array(values.shape[::-1]) - 2
    return np.clip(np.floor(position), 0, top).astype(np.int64)


def _trilinear(values: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Clamp-to-edge trilinear interpolation at index positions (M, 3)."""
    position = np.clip(position, 0, np.array(values.shape[::-1]) - 1.0)
    cell = _cells(values, position)
    corner = _gather(values, cell)
    weight = position - cell
    for axis in range(3):
        w = weight[:, axis, None]
        corner = corner[:, 0::2] + w * (corner[:, 1::2] - corner[:, 0::2])
    return corner[:, 0]


def _mip(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
         length: np.ndarray, step: float) -> np.ndarray:
    """VTK-style sampled maximum along rays starting at their box entry."""
    count = np.maximum(1, np.floor(length / step + 1e-9)).astype(np.int64)
    best = np.full(len(length), -np.inf)
    first = 1
    while first <= count.max():
        rows = np.flatnonzero(count >= first)
        k = np.arange(first, min(count.max(), first + max(1, _BUDGET // len(rows)) - 1) + 1)
        position = entry[rows, None, :] + (k[:, None] * step) * direction[rows, None, :]
        sample = _trilinear(values, position.reshape(-1, 3)).reshape(len(rows), len(k))
        sample[k > count[rows, None]] = -np.inf
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


def _exact(values: np.ndarray, entry: np.ndarray, direction: np.ndarray,
           length: np.ndarray) -> np.ndarray:
    """Exact maximum of the trilinear interpolant along each ray segment."""
    bounds = _crossings(entry, direction, length)
    valid = np.isfinite(bounds[:, 1:])
    ray, column = np.nonzero(valid)
    t0, t1 = bounds[ray, column], bounds[ray, column + 1]
    start = entry[ray] + t0[:, None] * direction[ray]
    stop = entry[ray] + t1[:, None] * direction[ray]
    cell = _cells(values, 0.5 * (start + stop))
    u0 = np.clip(start - cell, 0.0, 1.0)
    du = np.clip(stop - cell, 0.0, 1.0) - u0

    poly = [_gather(values, cell)]
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
