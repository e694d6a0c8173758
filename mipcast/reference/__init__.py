"""Float64 CPU reference renderer: the ground truth for every GPU image.

Rays come from :func:`mipcast.core.camera_rays.camera_rays` (VTK's own pixel-centre
rays, in index space); the volume is interpolated trilinearly between point
values, as the GPU's clamp-to-edge 3D texture does.

See docs/methods.md, section Reference (``docs/methods.md#reference``).
"""
from __future__ import annotations

import functools
from typing import Any

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.camera_rays import placed
from mipcast.core.prepare import prepare_scalars, scalar_image
from mipcast.core.validation import check_choice, check_positive, check_size
from mipcast.reference.demip import render_demip
from mipcast.reference.mip import (exact_maximum, exact_mean, exact_minimum, sampled_maximum, sampled_mean,
                                   sampled_minimum)
from mipcast.reference.rays import BUDGET, RAY_CHUNK, clip_interval, cropping_setup, hit_rays, nearest, scatter

#: Parameters each method accepts; all of them are required ("demip" also
#: takes optional ones: :data:`mipcast.reference.demip.PARAMETERS`).
METHODS = {"mip": ("sample_distance",), "analytic": (), "demip": ("sample_distance", "window"),
           "minip": ("sample_distance",), "analytic_minip": (),
           "average": ("sample_distance",), "analytic_average": ()}
#: The kernel of each method but "demip": sampled ones take ``step``.
_KERNELS = {"mip": sampled_maximum, "analytic": exact_maximum, "minip": sampled_minimum,
            "analytic_minip": exact_minimum, "average": sampled_mean, "analytic_average": exact_mean}


def render(image: vtkImageData, camera: Any, size: tuple, method: str = "mip",
           clip_planes=None, cropping=None, matrix=None, **params: Any) -> np.ndarray:
    """Render a maximum (minimum, mean) intensity projection in float64 on the CPU.

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        Volume (not modified).  Drawn as the GPU draws it
        (:func:`mipcast.core.prepare.prepare_scalars`): several components as
        their magnitude or ``component=k``; NaN/Inf voxels are missing (filled
        below the finite minimum; rays whose result lies below the finite
        minimum are NaN, like misses; minimum projections fill them above the
        finite maximum instead; the average is the mean over the ray's finite
        part: docs/methods.md, "Missing values").  Cell scalars (and no point
        scalars): point values of the image of the cell centres
        (:func:`mipcast.core.prepare.cell_centres`).
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
        ``"analytic"``: the exact maximum of the trilinear interpolant over the
        whole ray segment inside the volume.  Per crossed cell the
        interpolant along the ray is a cubic, whose coefficients are computed
        analytically from the cell's 8 corners (three nested lerps of
        polynomials, so ``f(0)`` is exactly the trilinear value); the cell's
        maximum is taken over both ends and the real roots of the derivative
        inside the segment.  Degenerate cases (constant, linear or quadratic
        restriction, zero-length segments at edges and corners, rays along
        faces) need no special branch: every candidate is a point of the
        segment, so the result never exceeds the true maximum.
        ``"minip"`` / ``"average"``: the minimum / the mean of the ``"mip"``
        samples (VTK's MINIMUM_INTENSITY and AVERAGE_INTENSITY blends with
        every sample in the average's scalar range).
        ``"analytic_minip"``: the exact minimum of the interpolant (the
        maximum of the negated cubics).  ``"analytic_average"``: the exact
        mean of the interpolant along the ray, the sum over the crossed
        cells of each cubic's integral times its segment length, divided by
        the ray's length inside the volume.
        ``"demip"``: depth-enhanced MIP on the ``"mip"`` samples; returns
        depth, final colour or maximum (its ``output`` parameter), see
        :func:`mipcast.reference.demip.render_demip` for its parameters.
    clip_planes : (origins, normals), optional
        Planes (world coordinates, arrays (P, 3) each) that clip every ray:
        only the part of the ray inside the box on every plane's kept side
        (where ``normal . (x - origin) >= 0``) counts; ``"mip"`` keeps the
        unclipped ray's sample positions.  Slabs and cropping boxes are planes
        too (:mod:`mipcast.core.clipping`).  NaN where nothing of the ray is left.
    cropping : (bounds, flags), optional
        VTK's cropping: ``bounds`` the six ``SetCroppingRegionPlanes`` (data
        coordinates), ``flags`` ``GetCroppingRegionFlags()``.  The planes cut
        the volume into 27 regions; region ``(i, j, k)`` (0 below the first
        plane of an axis, 1 from it up to the second, 2 from the second on)
        is visible where bit ``i + 3 j + 9 k`` of ``flags`` is set.  Sampled
        methods keep only the samples in visible regions; the exact ones
        split each cell's segment at the cropping planes and take the
        maximum (minimum, integral and length) over the visible pieces.
        The sub-volume (``0x2000``) is the box's six planes, as
        ``clip_planes``.  NaN where no sample (no piece) is visible.
    matrix : vtkMatrix4x4 or numpy.ndarray (4, 4), optional
        The volume's own matrix (``vtkVolume.GetMatrix()``: user matrix,
        position, orientation, scale, origin), which places the image in the
        world as VTK draws it (:func:`mipcast.core.camera_rays.placed`); the
        sample distance is then in the volume's own units, as VTK's.
    **params
        ``sample_distance : float`` (method ``"mip"``, required): distance
        between samples in world units (the volume's own with ``matrix``), > 0
        (also ``"minip"``, ``"average"``).
        The exact methods take none.
        ``component : int or "magnitude"`` (optional, every method): see ``image``.
        ``interpolation : {"linear", "nearest"}`` (optional, ``"mip"``, ``"minip"``,
        ``"average"``, ``"demip"``): ``"nearest"`` samples the nearest point's value, as the GPU
        does under ``SetInterpolationTypeToNearest`` (a ``ValueError`` for the other
        methods: the exact ones draw the trilinear interpolant whatever the property says).

    Returns
    -------
    numpy.ndarray, shape (height, width)
        The projection (maximum, minimum, mean) along each pixel's ray in the data units of the scalars;
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
    >>> print(render(image, camera, (3, 2), method="analytic").round(3))
    [[0. 1. 2.]
     [0. 1. 2.]]
    >>> print(render(image, camera, (3, 1), method="mip", sample_distance=0.5).round(3))
    [[nan  1. nan]]
    >>> print(render(image, camera, (3, 2), method="analytic_average").round(3))
    [[0. 1. 2.]
     [0. 1. 2.]]
    """
    component = params.pop("component", None)
    interpolation = check_choice("interpolation", params.pop("interpolation", "linear"), ("linear", "nearest"))
    minimum = method in ("minip", "analytic_minip")
    image = scalar_image(image)  # cell scalars: drawn on the image of the cell centres
    prepared = prepare_scalars(image, component, "above" if minimum else "below")
    width, height = check_size(size)
    method = check_choice("method", method, tuple(METHODS))
    if interpolation == "nearest" and method not in ("mip", "minip", "average", "demip"):
        raise ValueError(f"interpolation='nearest' is drawn by the sampled mip, minip, average and demip only, not "
                         f"by {method!r} (the exact methods walk the trilinear interpolant)")
    if method == "demip":  # depth, colour or maximum: see mipcast.reference.demip
        return render_demip(image, camera, (width, height), clip_planes=clip_planes, cropping=cropping,
                            component=component, matrix=matrix, interpolation=interpolation, **params)
    allowed = METHODS[method]
    unknown = sorted(set(params) - set(allowed))
    if unknown:
        raise TypeError(f"unknown parameter(s) for method {method!r}: {', '.join(unknown)}; "
                        f"valid: {', '.join(allowed) or 'none'}")
    missing = [name for name in allowed if name not in params]
    if missing:
        raise TypeError(f"method {method!r} requires parameter(s): {', '.join(missing)}")
    sampled = "sample_distance" in allowed
    if sampled:
        step = check_positive("sample_distance", params["sample_distance"])

    image = placed(image, matrix)  # the volume's matrix folded in (the prepared scalars are the image's)
    clip_planes, crop = cropping_setup(image, cropping, clip_planes, matrix)
    hit, entry, direction, length = hit_rays(image, camera, (width, height))
    values = np.array(prepared.values, dtype=np.float64)
    lo, hi = clip_interval(image, entry, direction, length, clip_planes, within_box=not sampled)

    kernel = _KERNELS[method]
    if interpolation == "nearest":
        kernel = functools.partial(kernel, sampler=nearest)
    if method in ("average", "analytic_average") and prepared.missing:
        # the mean over the finite part of the ray: samples below the finite floor (sampled), cells
        # with a missing corner (exact) do not count (docs/methods.md, "Missing values")
        kernel = functools.partial(kernel, floor=prepared.missing_below)
    if sampled:
        chunk = RAY_CHUNK
    else:
        chunk = max(1, BUDGET // (sum(values.shape) + 2))
        keep = lo <= hi
        entry = entry + np.where(keep, lo, 0.0)[:, None] * direction
        length = np.where(keep, hi - lo, 0.0)
    found = np.empty(len(length))
    for start in range(0, len(length), chunk):
        part = slice(start, start + chunk)
        if sampled:
            found[part] = kernel(values, entry[part], direction[part], length[part], step,
                                 keep=(lo[part], hi[part]), crop=crop)
        else:
            found[part] = kernel(values, entry[part], direction[part], length[part], crop=crop)
    # clipped away, or rays that saw no finite data (below the finite minimum): background
    found = prepared.seen(np.where((lo > hi) | ~np.isfinite(found), np.nan, found))
    return scatter(found, hit, height, width)

