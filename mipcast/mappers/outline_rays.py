"""The whole volume's outline rays that no brick can sample, sampled on the CPU.

A ray grazing the whole box (its chord shorter than one sample step) has a
single sample, one step past its entry, which lies OUTSIDE the box: the
single texture reads it clamped back onto the box (texture clamp-to-edge;
the ``global_phase`` piece clamps it the same way).  With bricks
(:mod:`mipcast.mappers.bricked_draw`, :mod:`mipcast.mappers.bricked_demip`)
that clamped sample's cell may lie in the neighbouring brick, which the ray
never crosses: the only brick drawing the ray (its chord's) has no sample
of its own, the owner of the cell draws no fragment, and the ray would be
left without a value where the single texture shows one (a few pixels on
the volume's outline, off by up to ~30 grey levels).

:func:`complete` finds those rays (a brick drew a fragment, no brick had a
sample) and gives them their one sample from the volume on the CPU: the
``global_phase`` piece's ray (the same :func:`mipcast.mappers.brick_rays.ray_uniforms`),
its start (the box's entry, or VTK's near-plane cap beyond it when the
camera is inside the volume) + one step, clamped to the whole box,
interpolated trilinearly -- what ``mcGlobalSample`` would have read had the
owner drawn the ray.

Examples
--------
>>> import numpy as np
>>> trilinear(np.arange(8.0).reshape(2, 2, 2), np.array([[0.5, 0.5, 0.5]]))   # (z, y, x) array
array([3.5])
"""
from __future__ import annotations

from contextlib import contextmanager
from typing import Optional, Sequence

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

from mipcast.core.clipping import sample_kept, sample_visible
from mipcast.core.object_state import object_state
from mipcast.mappers.brick_rays import cap_steps, nearest_interpolation, ray_uniforms, whole_of
from mipcast.mappers.private_draw import read_depth


def trilinear(volume: np.ndarray, points: np.ndarray) -> np.ndarray:
    """``volume`` (z, y, x) interpolated at ``points`` ((n, 3) point indices x, y, z).

    A point off the box is read from the nearest cell's interpolant, extrapolated (clamp it first for
    the texture's clamped edge).
    """
    upper = np.array(volume.shape[::-1]) - 1
    cell = np.clip(np.floor(points), 0, np.maximum(upper - 1, 0)).astype(int)
    t = points - cell
    nxt = np.minimum(cell + 1, upper)
    out = np.zeros(len(points))
    for dx in (0, 1):
        for dy in (0, 1):
            for dz in (0, 1):
                x = np.where(dx, nxt[:, 0], cell[:, 0])
                y = np.where(dy, nxt[:, 1], cell[:, 1])
                z = np.where(dz, nxt[:, 2], cell[:, 2])
                w = ((t[:, 0] if dx else 1 - t[:, 0]) * (t[:, 1] if dy else 1 - t[:, 1])
                     * (t[:, 2] if dz else 1 - t[:, 2]))
                out += w * volume[z, y, x]
    return out


def _pixel_rays(image, camera, shape: Sequence[int], size: Sequence[int], sample_distance: float,
                pixels: np.ndarray) -> tuple:
    """The ``global_phase`` rays of ``pixels`` (bool (rows, columns), top row first) in ``image``'s index space.

    Returns each ray's point (n, 3), its step of one sample distance (n, 3),
    the pixels' rows and columns, and where each ray crosses VTK's near-plane
    cap (in steps from its point; -inf without one: the camera outside the
    volume, :func:`mipcast.mappers.brick_rays.cap_steps`).
    """
    rows, columns = int(shape[0]), int(shape[1])
    whole = whole_of(image)  # counted from the extent's first point
    rays = {name: np.array(value) for name, value in ray_uniforms(whole, camera, tuple(size)).items()}
    r, c = np.nonzero(pixels)
    x = 2.0 * (c + 0.5) / columns - 1.0
    y = 2.0 * (rows - 1 - r + 0.5) / rows - 1.0  # top row first
    point = rays["u_mc_rayPoint0"] + x[:, None] * rays["u_mc_rayPointX"] + y[:, None] * rays["u_mc_rayPointY"]
    eye = rays["u_mc_rayEye"]
    direction = (point - eye[:3]) if eye[3] > 0.5 else np.broadcast_to(rays["u_mc_rayDirection"], point.shape)
    spacing = np.abs(np.array(image.GetSpacing()))
    step = direction * (sample_distance / np.linalg.norm(direction * spacing, axis=1))[:, None]
    return point, step, r, c, cap_steps(rays, point, step)


def volume_array(image) -> np.ndarray:
    """``image``'s scalars (component 0) as a float64 (z, y, x) array."""
    dims = image.GetDimensions()
    scalars = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float64)
    return (scalars if scalars.ndim == 1 else scalars[:, 0]).reshape(dims[2], dims[1], dims[0])


def _chords(image, camera, shape, size, sample_distance: float, pixels: np.ndarray) -> tuple:
    """:func:`_pixel_rays` and where each ray starts (the whole box's entry, or VTK's near-plane cap beyond it:
    the camera inside the volume) and leaves the whole box (in steps from its point)."""
    point, step, r, c, cap = _pixel_rays(image, camera, shape, size, sample_distance, pixels)
    upper = np.array(image.GetDimensions(), dtype=float) - 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = (0.0 - point) / step, (upper - point) / step
    flat = step == 0.0
    s_in = np.max(np.where(flat, -1.0e30, np.minimum(a, b)), axis=1)
    s_out = np.min(np.where(flat, 1.0e30, np.maximum(a, b)), axis=1)
    return point, step, r, c, np.maximum(s_in, cap), s_out


def walked(image, camera, shape: Sequence[int], size: Sequence[int], pixels: np.ndarray, kernel,
           sample_distance: float) -> np.ndarray:
    """The cell walk's value (``kernel``: :func:`mipcast.reference.mip.exact_maximum`, ...) of the rays at
    ``pixels`` over their chord of the whole box, in float64; NaN where a ray misses the box or crosses one
    sample distance or more of it (not an outline ray)."""
    point, step, r, c, s_in, s_out = _chords(image, camera, shape, size, sample_distance, pixels)
    hit = (s_out >= s_in) & (s_out - s_in < 1.0)
    result = np.full((int(shape[0]), int(shape[1])), np.nan)
    if hit.any():
        entry = point[hit] + s_in[hit, None] * step[hit]
        result[r[hit], c[hit]] = kernel(volume_array(image), entry, step[hit], s_out[hit] - s_in[hit])
    return result


def single_samples(image, camera, shape: Sequence[int], size: Sequence[int], sample_distance: float,
                   pixels: np.ndarray, cut=(None, None), nearest: bool = False) -> np.ndarray:
    """The one sample (data units) of the grazing rays at ``pixels`` (bool (rows, columns), top row first).

    ``image``: the one-component volume the bricks draw (scalars in data
    units); ``shape``: the ray grid (rows, columns); ``size``: the viewport's
    (width, height), the camera's aspect; ``cut``: the mapper's clipping
    (:func:`cut_by`), which drops the sample as the loop drops it; ``nearest``: the
    volume property's nearest-neighbour interpolation (:func:`along`).  NaN where
    the ray misses the box, is not a single-sample ray (then the bricks'
    answer stands) or its sample is clipped away.
    """
    point, step, r, c, s_in, s_out = _chords(image, camera, shape, size, sample_distance, pixels)
    entry = point + s_in[:, None] * step
    values = along(image, entry, step, np.ones(len(r)), *_kept(image, entry, step, np.ones(len(r)), cut),
                   nearest=nearest)[:, 0]
    out = np.full(len(r), np.nan)
    grazing = (s_out >= s_in) & (s_out - s_in < 1.0)  # one sample, past the exit: clamped onto the box
    out[grazing] = values[grazing]
    result = np.full((int(shape[0]), int(shape[1])), np.nan)
    result[r, c] = out
    return result


def face_rays(image, camera, shape: Sequence[int], size: Sequence[int], sample_distance: float,
              face: Sequence[int], pixels: np.ndarray) -> tuple:
    """The single texture's rays at ``pixels`` through the box face ``face`` ((axis, side), side 0 the low index).

    With multisampling a pixel some of whose samples a front face of the box
    covers gets that face's fragment, shaded at the pixel centre, even where
    the centre lies off the face: its ray starts where the centre's ray
    crosses the face's PLANE, off the box (VTK interpolates the face's
    texture coordinates).  Returns the pixels' rows and columns, each ray's
    start (n, 3) and step of one sample distance (n, 3) in point indices, and
    the steps from the start to the nearest exit plane (negative: behind it).
    Sampled methods take the samples ``start + k`` steps, ``k = 1 .. 1 +
    floor(max(0, steps - 1))`` (:func:`along`); the cell walks the ray from
    the start, ``max(0, steps)`` long, a part off the box read from its
    clamped cell extrapolated (``shaders/sampled_loop.glsl``,
    ``shaders/amip_cell.glsl``).
    """
    point, step, r, c, _ = _pixel_rays(image, camera, shape, size, sample_distance, pixels)
    axis, side = int(face[0]), int(face[1])
    upper = np.array(image.GetDimensions(), dtype=float) - 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        start = point + ((side * upper[axis] - point[:, axis]) / step[:, axis])[:, None] * step
        exits = (np.where(step > 0.0, upper, 0.0) - start) / step
    return r, c, start, step, np.min(np.where(step == 0.0, 1.0e30, exits), axis=1)


def along(image, start: np.ndarray, step: np.ndarray, steps: np.ndarray, keep=None, crop=None,
          nearest: bool = False) -> np.ndarray:
    """The samples (n, k) of :func:`face_rays`' rays in a sampled loop, read clamped onto the box; NaN past a
    ray's last, and where clipping drops a sample: ``keep = (lo, hi)`` (n,) keeps the samples ``lo <= k <= hi``
    steps from the start, ``crop`` those in a visible cropping region (:func:`cut_by`).  Interpolated
    trilinearly, or with ``nearest`` the nearest point's value (``global_phase``'s ``u_mc_nearest``)."""
    from mipcast.reference.rays import nearest as nearest_point

    count = 1 + np.floor(np.maximum(0.0, steps - 1.0)).astype(int)
    k = np.arange(1, int(count.max(initial=1)) + 1)  # (one column for no rays)
    upper = np.array(image.GetDimensions(), dtype=float) - 1.0
    at = start[:, None, :] + k[None, :, None] * step[:, None, :]
    sampler = nearest_point if nearest else trilinear
    values = sampler(volume_array(image), np.clip(at, 0.0, upper).reshape(-1, 3)).reshape(len(start), len(k))
    kept = k[None, :] <= count[:, None]
    if keep is not None:  # (a sample on a plane is kept, as in the shader)
        kept &= sample_kept(k[None, :].astype(float), keep[0][:, None], keep[1][:, None])
    if crop is not None:
        steps = np.broadcast_to(step[:, None, :], at.shape).reshape(-1, 3)
        kept &= sample_visible(at.reshape(-1, 3), steps, *crop).reshape(kept.shape)
    return np.where(kept, values, np.nan)


def _kept(image, start: np.ndarray, step: np.ndarray, steps: np.ndarray, cut) -> tuple:
    """:func:`along`'s ``keep`` and ``crop`` for the rays' clipping ``cut`` (:func:`cut_by`): the samples
    between the planes (steps from the start, the sampled loop's interval) and in visible regions."""
    from mipcast.reference.rays import clip_interval

    planes, crop = cut
    return (None if planes is None else clip_interval(image, start, step, steps, planes, within_box=False)), crop


def cut_by(mapper, camera, image) -> tuple:
    """The mapper's clipping planes, slab and cropping as :func:`mipcast.reference.render` takes them:
    ``(clip_planes, crop)`` (:func:`mipcast.reference.rays.cropping_setup`; None: none); ``image`` placed by
    the mapper's volume's matrix (:func:`mipcast.mappers.brick_rays.placed`), the cropping in its own coordinates."""
    from mipcast.mappers.clip_uniforms import world_planes
    from mipcast.reference.rays import cropping_setup

    planes = world_planes(mapper, camera)
    cropping = (mapper.GetCroppingRegionPlanes(), mapper.GetCroppingRegionFlags()) if mapper.GetCropping() else None
    volume = getattr(mapper, "GetAttachedVolume", lambda: None)()  # VTK's own mappers know no attached volume
    return cropping_setup(image, cropping, planes if len(planes[0]) else None,
                          None if volume is None else volume.GetMatrix())


def _face_setup(mapper, renderer, image, shape: Sequence[int], sample_distance: float, face, pixels) -> tuple:
    """:func:`face_rays` of ``mapper``'s picture over ``renderer``'s viewport (a grid of ``shape``), each
    ended where the single texture's ray ends at opaque geometry: VTK's unsigned length from its start + one
    step to the depth buffer's point (``end``, steps from the start), ``shown`` False where the face lies
    behind the depth buffer (its fragment is discarded); and the mapper's clipping (:func:`cut_by`)."""
    size = (int(shape[1]), int(shape[0]))
    rows, columns, start, step, steps = face_rays(image, renderer.GetActiveCamera(), shape, size, sample_distance,
                                                  face, pixels)
    surface = surface_steps(renderer, image, shape, size, start, step, rows, columns)
    planes, crop = cut_by(mapper, renderer.GetActiveCamera(), image)
    return rows, columns, start, step, steps, np.abs(surface - 1.0) + 1.0, surface > 0.0, planes, crop


def face_samples(mapper, renderer, image, shape: Sequence[int], sample_distance: float, face, pixels) -> tuple:
    """The single texture's samples (n, k; NaN: none) of ``face``'s fragments at ``pixels`` (bool, ``shape``)
    in a sampled loop: :func:`along` up to the sample past opaque geometry (VTK's count, ceil(length) + 1
    from the start + one step), the clipped and hidden-region samples dropped as the loop drops them.

    Returns the pixels' rows and columns, each ray's start and step (point indices, :func:`face_rays`) and the
    samples, NaN on the rays of a face behind the depth buffer.
    """
    rows, columns, start, step, steps, end, shown, planes, crop = _face_setup(mapper, renderer, image, shape,
                                                                             sample_distance, face, pixels)
    samples = along(image, start, step, np.minimum(steps, np.ceil(end)), *_kept(image, start, step, steps,
                                                                                (planes, crop)),
                    nearest=nearest_interpolation(mapper.GetAttachedVolume()))
    return rows, columns, start, step, np.where(shown[:, None], samples, np.nan)


def face_walks(mapper, renderer, image, shape: Sequence[int], sample_distance: float, face, pixels, kernel,
               **options) -> tuple:
    """The cell walk's value (``kernel``: :func:`mipcast.reference.mip.exact_maximum`, ...; ``options``: its
    keywords) of ``face``'s fragments at ``pixels``: from the start to the face's exit or the opaque geometry
    (VTK's end), the part between the clipping planes, over the visible cropping regions, extrapolated off the
    box.  Returns the pixels' rows and columns and the values (NaN: none)."""
    rows, columns, start, step, steps, end, shown, planes, crop = _face_setup(mapper, renderer, image, shape,
                                                                             sample_distance, face, pixels)
    from mipcast.reference.rays import clip_interval

    lo, hi = clip_interval(image, start, step, np.maximum(np.minimum(steps, end), 0.0), planes)
    found = kernel(volume_array(image), start + lo[:, None] * step, step, np.maximum(hi - lo, 0.0), crop=crop,
                   extrapolate=True, **options)
    return rows, columns, np.where(shown & (lo <= hi) & np.isfinite(found), found, np.nan)


@contextmanager
def depth_held(renderer):
    """Within: :func:`scene_depth` reads ``renderer``'s depth buffer once and keeps it.

    For one bricked frame (:func:`mipcast.mappers.bricked_draw.draw_bricks`):
    its brick passes render to image and its pictures test depth without
    writing it, so the buffer does not change in between, and the outline,
    face and hidden-ray tests each asked for it again (4 readbacks a frame
    with multisampling, 48^3 in 27 bricks; now 1).
    """
    state = object_state(renderer)
    state["held_depth"] = None
    try:
        yield
    finally:
        state.pop("held_depth", None)


def _depth_buffer(renderer) -> np.ndarray:
    """``renderer``'s viewport of the depth buffer, (height, width), bottom row first (held: :func:`depth_held`)."""
    state = object_state(renderer)
    if state.get("held_depth") is not None:
        return state["held_depth"]
    width, height, x0, y0 = [0], [0], [0], [0]
    renderer.GetTiledSizeAndOrigin(width, height, x0, y0)
    width, height = max(width[0], 1), max(height[0], 1)
    depth = read_depth(renderer.GetRenderWindow(), (x0[0], y0[0], width, height))
    if "held_depth" in state:
        state["held_depth"] = depth
    return depth


def scene_depth(renderer, shape: Sequence[int]) -> np.ndarray:
    """The depth buffer (0 .. 1; 1: no opaque geometry) at the pixel of each ray of a grid of ``shape`` (rows,
    columns; top row first) over ``renderer``'s viewport."""
    depth = _depth_buffer(renderer)
    height, width = depth.shape
    rows = ((np.arange(int(shape[0])) + 0.5) * height / int(shape[0])).astype(int)
    columns = ((np.arange(int(shape[1])) + 0.5) * width / int(shape[1])).astype(int)
    return depth[::-1][np.ix_(rows, columns)]


def far(renderer, shape: Sequence[int]) -> np.ndarray:
    """The rays of a grid of ``shape`` (rows, columns; top row first) over ``renderer``'s viewport whose pixel
    holds no opaque geometry in the depth buffer (their ray ends at the box)."""
    return scene_depth(renderer, shape) >= 1.0


def surface_steps(renderer, image, shape: Sequence[int], size: Sequence[int], start: np.ndarray, step: np.ndarray,
                  rows: np.ndarray, columns: np.ndarray) -> np.ndarray:
    """Along each ray ``start + t step`` (point indices of ``image``) of the pixels ``rows``, ``columns`` of a
    grid of ``shape``: t where it meets the depth buffer's value at its pixel (the opaque geometry there, or
    the far plane).  ``size``: the viewport's (width, height), the camera's aspect."""
    from mipcast.core.camera_rays import matrix_array

    camera = renderer.GetActiveCamera()
    to_clip = (matrix_array(camera.GetCompositeProjectionTransformMatrix(size[0] / size[1], -1, 1))
               @ matrix_array(image.GetIndexToPhysicalMatrix()))
    a = np.append(start, np.ones((len(start), 1)), axis=1) @ to_clip.T
    b = np.append(step, np.zeros((len(step), 1)), axis=1) @ to_clip.T
    z = 2.0 * scene_depth(renderer, shape)[rows, columns].astype(np.float64) - 1.0  # NDC depth
    with np.errstate(divide="ignore", invalid="ignore"):
        return (z * a[:, 3] - a[:, 2]) / (b[:, 2] - z * b[:, 3])


def unhidden(renderer, image, shape: Sequence[int], size: Sequence[int], sample_distance: float,
             pixels: np.ndarray) -> np.ndarray:
    """The rays at ``pixels`` whose entry into the whole box of ``image`` lies in front of the depth buffer's
    opaque geometry: the single texture draws them (it discards a fragment of its box behind the scene depth).
    ``shape``, ``size``: as :func:`single_samples`."""
    point, step, r, c, s_in, _ = _chords(image, renderer.GetActiveCamera(), shape, size, sample_distance, pixels)
    out = np.zeros(pixels.shape, dtype=bool)
    out[r, c] = surface_steps(renderer, image, shape, size, point + s_in[:, None] * step, step, r, c) > 0.0
    return out


def undrawn(mapper, renderer, drawn: np.ndarray) -> Optional[np.ndarray]:
    """The rays (``drawn``'s grid) no brick drew a fragment for that :func:`complete` may fill in: those whose
    pixel holds no opaque geometry; None when the mapper's cropping, clipping planes or slab may have cut them."""
    from mipcast.mappers import clip_uniforms

    if clip_uniforms.cuts(mapper, renderer.GetActiveCamera()):
        return None
    return ~drawn & far(renderer, drawn.shape)


def complete(values: np.ndarray, empty: np.ndarray, image, camera, size, sample_distance: float,
             combine=np.fmax, undrawn=None, nearest: bool = False) -> np.ndarray:
    """``values`` (bricks combined, NaN: none) with the grazing rays a brick drew but none sampled filled in.

    ``empty``: the rays some brick drew a fragment for without a sample;
    ``combine``: how a value joins the bricks' (the maximum; the minimum);
    ``undrawn``: the rays no brick drew a fragment for (:func:`undrawn`),
    filled in too where they graze the whole box (the whole box's raster may
    cover a pixel centre on its outline that the bricks' faces, rastered from
    other corners, do not); ``nearest``: the volume property's nearest-neighbour interpolation.
    """
    missing = (empty if undrawn is None else empty | undrawn) & np.isnan(values)
    if not missing.any():
        return values
    found = single_samples(image, camera, values.shape, size, sample_distance, missing, nearest=nearest)
    return combine(values, found)
