"""DEMIP composited from bricks on the CPU: depth, Eq. 1, the colour sphere and the picture.

The common last step of DEMIP drawn over bricks, whether the bricks are MPI
ranks' (:mod:`mipcast.distributed`) or a volume beyond the 3D texture limit
drawn by the mapper itself (:mod:`mipcast.mappers.bricked_demip`): given
each pixel's whole-volume maximum (phase 1, MAX over the bricks) and the
whole-ray index of its first same-material sample (phase 2, MIN over the
bricks), the depth over the WHOLE volume's box, Eq. 1, the sphere and
pseudo-chromadepth come from :mod:`mipcast.core.demip_depth`, the maths of
the float64 reference.

Examples
--------
>>> from mipcast.offscreen import grey_property
>>> demip_picture(np.array([[0.5, np.nan]]), np.full((1, 2, 3), 0.5), grey_property((0.0, 1.0)))[0, :, 0]
array([128,   0], dtype=uint8)
"""
from __future__ import annotations

from typing import Optional, Tuple

import numpy as np

from mipcast.core.camera_rays import camera_rays, index_space, near_cap
from mipcast.core.demip_depth import DepthGeometry, enhance
from mipcast.mappers.brick_rays import cap_steps, index_plane


def demip_composite(whole, camera, sample_distance: float, values: np.ndarray, index: np.ndarray, params: dict,
                    volume_property, slab=None, aspect: Optional[float] = None,
                    rays: Optional[Tuple[np.ndarray, np.ndarray]] = None,
                    base_rgb: Optional[np.ndarray] = None) -> Tuple[np.ndarray, np.ndarray]:
    """(depth, straight RGB) of DEMIP from the bricks' maximum and first same-material sample index.

    Parameters
    ----------
    whole : vtkImageData
        The whole volume's geometry (extent, origin, spacing, direction; scalars not needed), placed by the
        volume's matrix (:func:`mipcast.mappers.brick_rays.placed`).
    camera : vtkCamera
    sample_distance : float
        Distance between samples in the volume's own units, as VTK's (sample k at the ray's start + (1 + k) steps:
        the box entry, or VTK's near-plane cap beyond it when the camera is inside the volume,
        :func:`mipcast.core.camera_rays.near_cap`).
    values : numpy.ndarray, shape (height, width)
        The whole-ray maximum in data units (NaN: miss), top row first.
    index : numpy.ndarray, shape (height, width)
        The whole-ray index of the first same-material sample (+inf: no DEMIP term).
    params : dict
        DEMIP's settings (name -> value of :data:`mipcast.core.parameter_tables.DEMIP`).
    volume_property : vtkVolumeProperty
    slab : (thickness, centre, normal), optional
        The slab the bricks clipped with (world coordinates,
        :func:`mipcast.mappers.clip_uniforms.slab_of`): depth is then
        normalised over the box's part inside it and ``steps`` /
        ``entry_plus_length`` measure from the ray's slab entry, as the
        float64 reference (:meth:`mipcast.core.demip_depth.DepthGeometry.narrow_to_slab`).
    aspect : float, optional
        The viewport's aspect ratio when ``values`` lie on a coarser ray grid
        than its pixels (a foveated level, whose grid VTK truncates): the
        camera's projection keeps the viewport's.
    rays : (start, step), optional
        Each ray's start and one sample step, point indices, shape
        ``values.shape + (3,)``: sample k at start + (1 + k) steps, and the
        depth measured from the start (the rays of a multisampled picture's
        box faces, which start off the box:
        :func:`mipcast.mappers.outline_rays.face_samples`); by default the
        camera's pixel rays from their box entry.
    base_rgb : numpy.ndarray, shape (height, width, 3), optional
        The straight colour of each ray's maximum as the caller's GPU looks it
        up (default :func:`transfer_colour`).

    Returns
    -------
    depth : numpy.ndarray, float64
        In [0, 1], NaN where there is no DEMIP term.
    rgb : numpy.ndarray, shape (height, width, 3), float64
        Straight colour in [0, 1] (0 on misses).
    """
    height, width = values.shape
    aspect = width / height if aspect is None else float(aspect)
    if rays is None:
        pixel_rays = camera_rays(whole, camera, (width, height), aspect)
        start = pixel_rays.t_enter
        cap = near_cap(whole, camera, aspect)
        if cap is not None:  # the camera inside the volume: VTK's rays start at its near-plane cap, not the near plane
            plane = index_plane(cap, np.linalg.inv(index_space(whole)[0]))
            start = np.maximum(start, cap_steps({"u_mc_rayCap": plane}, pixel_rays.origin, pixel_rays.direction))
        entry = pixel_rays.origin + start[..., None] * pixel_rays.direction
        # one sample distance in the volume's own units (the bricks' u_mc_raySpacing), not the world's: they differ
        # where the volume's matrix scales (``whole`` placed by it, brick_rays.placed)
        own = np.linalg.norm(pixel_rays.direction * np.abs(np.array(whole.GetSpacing())), axis=-1)
        step, inside = sample_distance * pixel_rays.direction / own[..., None], pixel_rays.hit
    else:
        (entry, step), inside = rays, True
    hit = ~np.isnan(values)
    term = hit & np.isfinite(index) & inside
    where = entry + (np.where(term, index, 0.0) + 1.0)[..., None] * step
    geometry = DepthGeometry(whole, camera, aspect)
    if slab is not None and term.any():
        entry = entry.copy()
        entry[term] = geometry.narrow_to_slab(slab, entry[term], step[term])
    depth = np.full(values.shape, np.nan)
    depth[term] = geometry.depth(params["depth_mode"], where[term], entry[term])
    rgb = transfer_colour(np.where(hit, values, 0.0), volume_property) if base_rgb is None else np.array(base_rgb)
    rgb[term] = enhance(rgb[term], depth[term], np.ones(int(term.sum()), dtype=bool), where[term], geometry,
                        params)
    rgb[~hit] = 0.0
    return depth, rgb


def transfer_colour(values: np.ndarray, volume_property, entries: int = 4096) -> np.ndarray:
    """The colour transfer function's straight RGB in [0, 1] at ``values`` (float64, shape + (3,))."""
    function = volume_property.GetRGBTransferFunction()
    low, high = function.GetRange()
    if not high > low:
        return np.repeat(np.full(values.shape, 0.0)[..., None], 3, axis=-1) + np.array(function.GetColor(low))
    table = np.zeros(3 * entries)
    function.GetTable(low, high, entries, table)
    table = table.reshape(entries, 3)
    at = np.linspace(low, high, entries)
    return np.stack([np.interp(values, at, table[:, c]) for c in range(3)], axis=-1)


def opacity(values: np.ndarray, volume_property) -> np.ndarray:
    """The scalar opacity at ``values``."""
    function = volume_property.GetScalarOpacity()
    flat = np.asarray(values, dtype=np.float64).ravel()
    return np.array([function.GetValue(v) for v in flat]).reshape(np.shape(values))


def demip_premultiplied(values: np.ndarray, rgb: np.ndarray, volume_property) -> np.ndarray:
    """Float RGBA, premultiplied: straight colour times the maximum's opacity (alpha); 0 where missed."""
    alpha = np.where(np.isnan(values), 0.0, opacity(np.nan_to_num(values), volume_property))
    out = np.zeros(values.shape + (4,))
    out[..., :3] = np.nan_to_num(rgb) * alpha[..., None]
    out[..., 3] = alpha
    return out


def mida_composite(samples: np.ndarray, valid: np.ndarray, volume_property, floor: float,
                   ceiling: float) -> np.ndarray:
    """MIDA's premultiplied RGBA (n, 4) of each ray's ``samples`` (n, k; those ``valid``), front to back.

    As ``shaders/demip_mida_hooks.glsl`` (``mcMidaStep``): a sample of
    material m (its place in the window ``[floor, ceiling]``), opacity a and
    colour c (the transfer functions) fades what is in front by
    beta = 1 - max(m - running maximum material, 0), then C = beta C + (1 -
    beta A) a c, A = beta A + (1 - beta A) a; clamped to [0, 1].

    Examples
    --------
    >>> from mipcast.offscreen import grey_property
    >>> # opaque grey: 0.25, then 1 fades it by beta = 0.25: C = 0.25 * 0.25 + 0.75 * 1
    >>> mida_composite(np.array([[0.25, 1.0]]), np.array([[True, True]]), grey_property((0.0, 1.0)), 0.0,
    ...                1.0).round(4).tolist()
    [[0.8125, 0.8125, 0.8125, 1.0]]
    """
    values = np.where(valid, samples, floor)
    material = np.clip((values - floor) / (ceiling - floor), 0.0, 1.0)
    alpha = opacity(values, volume_property)
    colour = transfer_colour(values, volume_property)
    out, running = np.zeros((len(values), 4)), np.zeros(len(values))
    for k in range(values.shape[1]):
        beta = 1.0 - np.maximum(material[:, k] - running, 0.0)
        fresh = (1.0 - beta * out[:, 3]) * alpha[:, k]
        step = np.concatenate([beta[:, None] * out[:, :3] + fresh[:, None] * colour[:, k],
                               (beta * out[:, 3] + fresh)[:, None]], axis=1)
        out = np.where(valid[:, k, None], step, out)
        running = np.where(valid[:, k], np.maximum(running, material[:, k]), running)
    return np.clip(out, 0.0, 1.0)


def demip_picture(values: np.ndarray, rgb: np.ndarray, volume_property) -> np.ndarray:
    """The 8-bit picture: straight colour times the maximum's opacity, black where the ray missed.

    As DEMIP's colour exit (``shaders/demip_color.glsl``): the opacity is
    MIP's, premultiplied.
    """
    out = demip_premultiplied(values, rgb, volume_property)[..., :3] * 255.0
    return np.clip(np.rint(out), 0, 255).astype(np.uint8)
