"""Float64 CPU reference of depth-enhanced MIP (the definitions of :class:`DEMIPVolumeMapper`).

Same rays and samples as :func:`mipcast.reference.render` with
``method="mip"``; the transfer function is the grey ramp of
:func:`mipcast.offscreen.grey_property` over ``window`` (opaque, black at and
below the low end, white at and above the high end), so the window's ends
are the floor and ceiling of the material.  Reached through
``mipcast.reference.render(..., method="demip", ...)``.

See docs/methods.md, sections DEMIP and Reference (``docs/methods.md#reference``).
"""
from __future__ import annotations

from typing import Any

import numpy as np

from mipcast.core.camera_rays import placed
from mipcast.core.parameter_tables import DEMIP
from mipcast.core.clipping import sample_kept, sample_visible
from mipcast.core.parameters import check_values
from mipcast.core.demip_depth import DepthGeometry, enhance
from mipcast.core.shading import FLOOR_TOLERANCE
from mipcast.core.prepare import prepare_scalars, scalar_image
from mipcast.core.validation import check_choice, check_positive, check_size
from mipcast.reference.rays import BUDGET, clip_interval, cropping_setup, hit_rays, nearest, scatter, trilinear

#: What :func:`render_demip` can return.
OUTPUTS = ("depth", "rgb", "value")

#: Parameters besides the method's own (:data:`mipcast.core.parameter_tables.DEMIP`):
#: name -> default (``None``: required).
SCENE_PARAMETERS = {"sample_distance": None, "window": None, "output": "depth", "interpolation": "linear",
                    "colour": "grey"}


def render_demip(image: Any, camera: Any, size: tuple, clip_planes=None, slab=None, cropping=None, matrix=None,
                 **params: Any) -> np.ndarray:
    """Depth-enhanced MIP in float64: depth, final colour or maximum per pixel.

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        Volume with one-component point scalars (not modified).
    camera : vtkCamera
        The view (not modified); orthographic or perspective.
    size : tuple of int
        Window ``(width, height)``.
    clip_planes : (origins, normals), optional
        Clipping planes in world coordinates, as in :func:`mipcast.reference.render`:
        only samples on every plane's kept side count.
    slab : (thickness, centre, normal), optional
        The slab (world coordinates) the mapper clips with; its two planes
        must also be among ``clip_planes``.  Depth is then normalised over
        the part of the box inside the slab (its least and greatest view
        distance, or eye distance, over that region, for any slab
        orientation: :func:`mipcast.core.clipping.region_extent`), and
        ``steps`` / ``entry_plus_length`` measure from where the ray enters
        the slab instead of the box.
    cropping : (bounds, flags), optional
        VTK's cropping regions, as in :func:`mipcast.reference.render`: only
        samples in visible regions count (the maximum, the same-material
        search, LMIP, attenuation and MIDA see the visible samples only).
        Depth is normalised as without cropping (over the box, or its part
        inside the slab), and ``steps`` / ``entry_plus_length`` measure from
        the box (slab) entry.
    matrix : vtkMatrix4x4 or numpy.ndarray (4, 4), optional
        The volume's own matrix, as in :func:`mipcast.reference.render`.
    **params
        ``sample_distance : float`` (required): world units between samples
        (the volume's own with ``matrix``),
        placed as in ``method="mip"`` (``t_enter + k * sample_distance``,
        ``k = 1..K``).
        ``window : (low, high)`` (required): the grey window in data units;
        material ``m(s) = clip((s - low) / (high - low), 0, 1)``, above the
        floor when ``m(s) > FLOOR_TOLERANCE``.
        ``depth_weight : float, default: 0.15``, ``material_threshold :
        float, default: 0.1``, ``depth_mode : str, default:
        "entry_plus_length"``, ``sphere_weight : float, default: 0.0``,
        ``sphere_colors : str or (front, back), default: "red-blue"``,
        ``sphere_orientation : 3 angles or 3x3 matrix, default: identity``,
        ``chroma_depth_weight : float, default: 0.0``, ``depth_of : str,
        default: "same_material"``, ``projection : str, default: "mip"``,
        ``local_threshold : float, default: 0.5``, ``attenuation : float,
        default: 0.05``: as the setters of :class:`mipcast.DEMIPVolumeMapper`.
        ``output : {"depth", "rgb", "value"}, default: "depth"``.
        ``interpolation : {"linear", "nearest"}, default: "linear"``: the samples
        interpolate the volume trilinearly, or take the nearest point's value
        (the volume property's ``SetInterpolationTypeToNearest``).
        ``colour : callable or "grey", default: "grey"``: DEMIP's base colour,
        a function giving the straight RGB ``(N, 3)`` in [0, 1] of ``N``
        values (a colour map: the volume property's colour transfer
        function), or the grey ramp of the window. MIDA's composite stays grey.

    Returns
    -------
    numpy.ndarray
        ``"depth"``: shape (H, W), depth in [0, 1] of the first sample whose
        material is within ``material_threshold`` of the maximum's and above
        the floor; NaN where the ray misses or the maximum is not above the
        floor (no DEMIP term).  ``"rgb"``: shape (H, W, 3), the final straight colour in
        [0, 1] (Eq. 1, 2 and pseudo-chromadepth where there is a DEMIP term,
        the grey ramp of the ray's value elsewhere; MIDA's composite); NaN
        on misses.  ``"value"``: shape (H, W), the ray's value in data units
        (maximum; LMIP's local maximum; the attenuated maximum's scalar),
        NaN on misses.  Depth is NaN everywhere for ``"attenuated"`` and
        ``"mida"``.  Row 0 is the top.

    Raises
    ------
    TypeError
        For unknown or missing parameters, or values of the wrong type.
    ValueError
        For values out of range (the message names the parameter).

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> from mipcast.data_fixtures import make_fixture
    >>> image = make_fixture("frontback", size=16)
    >>> camera = vtkCamera()
    >>> camera.SetFocalPoint(7.5, 7.5, 7.5)
    >>> camera.SetPosition(7.5, 7.5, 60.0)   # on the +z side: the high-z ball is near
    >>> camera.ParallelProjectionOn()
    >>> camera.SetParallelScale(9.0)
    >>> depth = render_demip(image, camera, (16, 16), sample_distance=1.0, window=(0.05, 1.0))
    >>> near, far = depth[8, 10], depth[8, 5]  # the high-z (x ~ 10) and low-z (x ~ 6) balls
    >>> bool(near < far)
    True
    """
    image = scalar_image(image)  # cell scalars: drawn on the image of the cell centres
    prepared = prepare_scalars(image, params.pop("component", None))
    width, height = check_size(size)
    scene = {name: params[name] for name in SCENE_PARAMETERS if name in params}
    missing = [name for name, default in SCENE_PARAMETERS.items() if default is None and name not in scene]
    if missing:
        raise TypeError(f"method 'demip' requires parameter(s): {', '.join(missing)}")
    p = check_values(DEMIP, {k: v for k, v in params.items() if k not in SCENE_PARAMETERS}, "method 'demip'")
    step = check_positive("sample_distance", scene["sample_distance"])
    low, high = _window(scene["window"])
    output = check_choice("output", scene.get("output", "depth"), OUTPUTS)
    interpolation = check_choice("interpolation", scene.get("interpolation", "linear"), ("linear", "nearest"))
    colour = scene.get("colour", "grey")
    if colour != "grey" and not callable(colour):
        raise TypeError(f"colour must be a function of the values or 'grey' (the grey ramp), got {colour!r}")
    sampler = nearest if interpolation == "nearest" else trilinear
    mode = p["depth_mode"]
    eps = 0.0 if p["depth_of"] == "maximum" else p["material_threshold"]
    projection, attenuation = p["projection"], p["attenuation"]
    local = low + p["local_threshold"] * (high - low)
    local = local if projection == "lmip" else np.inf
    voxels_per_step = step / min(abs(v) for v in image.GetSpacing())

    image = placed(image, matrix)  # the volume's matrix folded in (the prepared scalars are the image's)
    clip_planes, crop = cropping_setup(image, cropping, clip_planes, matrix)
    hit, entry, direction, length = hit_rays(image, camera, (width, height))
    values = np.array(prepared.values, dtype=np.float64)
    lo, hi = clip_interval(image, entry, direction, length, clip_planes, within_box=False)

    count = np.maximum(1, np.floor(length / step + 1e-9)).astype(np.int64)
    maximum = np.empty(len(count))
    first = np.empty(len(count), dtype=np.int64)
    mida = np.empty(len(count))
    sampled = np.empty(len(count), bool)
    chunk = max(1, BUDGET // max(1, int(count.max(initial=1))))
    for start in range(0, len(count), chunk):
        part = slice(start, start + chunk)
        sample, valid = _samples(values, entry[part], direction[part], count[part], step, crop, sampler)
        if clip_planes is not None:
            at = np.arange(1, sample.shape[1] + 1)[None, :] * step
            valid = valid & sample_kept(at, lo[part, None], hi[part, None], step)  # (one on a plane too)
        sampled[part] = valid.any(axis=1)
        if projection == "attenuated":
            maximum[part] = attenuated_maximum(sample, valid, low, high, attenuation * voxels_per_step)
            first[part] = -1
        else:
            if projection == "lmip":
                valid = local_maxima(sample, valid, local)
            maximum[part], first[part] = same_material(sample, valid, low, high, eps)
        if projection == "mida":
            mida[part] = _mida(sample, valid, low, high)
            first[part] = -1
    # rays left with no sample (clipped away, or in hidden cropping regions only) or that saw no
    # finite data (their maximum lies below the finite minimum: the test of shaders/missing_exit.glsl) are background
    hit = hit.copy()
    seen = np.flatnonzero(hit)
    gone = ~np.isfinite(prepared.seen(maximum)) | ~sampled
    if gone.any():
        hit[seen[gone]] = False
        keep = ~gone
        maximum, first, mida = maximum[keep], first[keep], mida[keep]
        entry, direction = entry[keep], direction[keep]
    if output == "value":
        return scatter(maximum, hit, height, width)

    term = first >= 0
    where = entry + ((np.maximum(first, 0) + 1) * step)[:, None] * direction
    geometry = DepthGeometry(image, camera, width / height)
    if slab is not None:
        entry = geometry.narrow_to_slab(slab, entry, direction)
    depth = np.where(term, geometry.depth(mode, where, entry), np.nan)
    if output == "depth":
        return scatter(depth, hit, height, width)

    grey = mida if projection == "mida" else np.clip((maximum - low) / (high - low), 0.0, 1.0)
    base = np.repeat(grey[:, None], 3, axis=1) if colour == "grey" or projection == "mida" else \
        np.asarray(colour(maximum), dtype=np.float64).reshape(len(maximum), 3)
    color = enhance(base, depth, term, where, geometry, p)
    return scatter(color, hit, height, width)


def _window(window: Any) -> tuple:
    try:
        low, high = (float(v) for v in window)
    except (TypeError, ValueError):
        raise TypeError(f"window must be (low, high) in data units, got {window!r}") from None
    if not (np.isfinite(low) and np.isfinite(high) and high > low):
        raise ValueError(f"window must be (low, high) with high > low, got {window!r}")
    return low, high


def _samples(values, entry, direction, count, step, crop=None, sampler=trilinear) -> tuple:
    """Samples (N, K) at ``k * step``, k = 1..K (``sampler``: trilinear or nearest), and which of them exist
    (and are visible: ``crop``, :func:`mipcast.core.clipping.crop_visible`)."""
    k = np.arange(1, int(count.max()) + 1)
    position = entry[:, None, :] + (k[:, None] * step) * direction[:, None, :]
    sample = sampler(values, position.reshape(-1, 3)).reshape(len(count), len(k))
    valid = k[None, :] <= count[:, None]
    if crop is not None:
        valid &= sample_visible(position, step * direction[:, None, :], *crop)
    return sample, valid


def local_maxima(sample, valid, local) -> np.ndarray:
    """LMIP: keep the samples before the first fall below a running maximum above ``local``."""
    running = np.maximum.accumulate(np.where(valid, sample, -np.inf), axis=1)
    before = np.concatenate([np.full((len(sample), 1), -np.inf), running[:, :-1]], axis=1)
    falls = valid & (sample < before) & (before > local)
    end = np.where(falls.any(axis=1), falls.argmax(axis=1), sample.shape[1])
    return valid & (np.arange(sample.shape[1])[None, :] < end[:, None])


def attenuated_maximum(sample, valid, low, high, decay) -> np.ndarray:
    """The scalar (data units) of the largest attenuated material."""
    material = np.where(valid, np.clip((sample - low) / (high - low), 0.0, 1.0), 0.0)
    crossed = np.cumsum(material, axis=1) - material
    return low + (material * np.exp(-decay * crossed)).max(axis=1) * (high - low)


def _mida(sample, valid, low, high) -> np.ndarray:
    """MIDA (gamma 0) of the opaque grey ramp: the composited grey."""
    material = np.clip((sample - low) / (high - low), 0.0, 1.0)
    colour = np.zeros(len(sample))
    opacity = np.zeros(len(sample))
    running = np.zeros(len(sample))
    for k in range(sample.shape[1]):
        on = valid[:, k]
        beta = 1.0 - np.maximum(material[:, k] - running, 0.0)
        fresh = 1.0 - beta * opacity  # sample opacity 1
        colour = np.where(on, beta * colour + fresh * material[:, k], colour)
        opacity = np.where(on, beta * opacity + fresh, opacity)
        running = np.where(on, np.maximum(running, material[:, k]), running)
    return colour


def same_material(sample, valid, low, high, eps) -> tuple:
    """Maximum (data units) and index of the first same-material sample (-1: no DEMIP term)."""
    sample = np.where(valid, sample, -np.inf)
    maximum = sample.max(axis=1)
    material = np.clip((sample - low) / (high - low), 0.0, 1.0)
    top = np.clip((maximum - low) / (high - low), 0.0, 1.0)
    same = valid & (material >= top[:, None] - eps) & (material > FLOOR_TOLERANCE)
    first = np.where(same.any(axis=1) & (top > FLOOR_TOLERANCE), same.argmax(axis=1), -1)
    return maximum, first
