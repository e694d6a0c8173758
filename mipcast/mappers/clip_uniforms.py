"""The planes and cropping regions every mipcast mapper clips its rays with, as shader uniforms.

One list of planes per render, in world coordinates (:mod:`mipcast.core.clipping`):

* the mapper's clipping planes (``AddClippingPlane``; at most six, as in VTK);
* its cropping box with the sub-volume flags (``SetCropping(True)``,
  ``SetCroppingRegionPlanes`` in the image's data coordinates,
  ``SetCroppingRegionFlagsToSubVolume()``, VTK's default): its six faces;
* its slab (``SetSlabThickness``, ``SetSlabCentre``, ``SetSlabNormal``; the
  centre defaults to the camera's focal point, the normal to the view
  direction, both read at every render).

They go to the shader as ``u_mc_clipCount`` and ``u_mc_clip0`` ..
``u_mc_clip13`` (a fixed set of vec4 uniforms: moving the slab uploads
numbers, it never rebuilds the shader) in texture coordinates; the loops (``sampled_loop``, ``amip_cell``)
narrow each ray to the kept interval once per ray (``mcClipRange`` in
``mip_globals``).  VTK's own clipping code is switched off (``clipping_off``:
it moves the ray's start, which would shift mipcast's samples).

Any other cropping region flags (``SetCroppingRegionFlagsToFence()``,
``...Cross()``, any of the 2^27 values of ``SetCroppingRegionFlags``) are
regions, not planes: the six cropping planes cut the volume into 27 regions
and region ``(i, j, k)`` (per axis 0 below the first plane, 1 from it up to
the second, 2 from the second on) is visible where bit ``i + 3 j + 9 k`` of
the flags is set.  They go up as ``u_mc_cropFlags`` (int) and
``u_mc_cropLow`` / ``u_mc_cropHigh`` (the planes in texture coordinates,
:func:`crop_uniforms`) with the ``clip_regions`` piece (instead of
``clip_active``): the sampled loop skips the samples of hidden regions, the
cell walk takes only the visible pieces of each cell's segment.
"""
from __future__ import annotations

from typing import Optional

import numpy as np

from mipcast.core.camera_rays import index_space, matrix_array
from mipcast.core.clipping import (MAX_PLANES, SUBVOLUME_FLAGS, box_planes, crop_box, plane_rows, region_extent,
                                   slab_planes)

#: Most user clipping planes (VTK's limit).
MAX_USER_PLANES = 6


def clipping_problem(mapper) -> Optional[str]:
    """Why the mapper's clipping planes or cropping cannot be honoured, or ``None``.

    More than six clipping planes are refused (VTK's limit); every cropping
    region flag value is honoured.

    Examples
    --------
    >>> from mipcast.mappers.mip import MIPVolumeMapper
    >>> mapper = MIPVolumeMapper()
    >>> mapper.SetCropping(True); mapper.SetCroppingRegionFlagsToFence()
    >>> clipping_problem(mapper) is None
    True
    """
    planes = mapper.GetClippingPlanes()
    if planes is not None and planes.GetNumberOfItems() > MAX_USER_PLANES:
        return (f"{planes.GetNumberOfItems()} clipping planes: mipcast methods (as VTK's GPU mapper) "
                f"take at most {MAX_USER_PLANES}; remove some with RemoveClippingPlane")
    return None


def crops_regions(mapper) -> bool:
    """Whether the mapper crops with region flags other than the sub-volume (the ``clip_regions`` piece).

    Examples
    --------
    >>> from mipcast.mappers.mip import MIPVolumeMapper
    >>> mapper = MIPVolumeMapper()
    >>> mapper.SetCropping(True)
    >>> crops_regions(mapper)
    False
    >>> mapper.SetCroppingRegionFlagsToInvertedCross()
    >>> crops_regions(mapper)
    True
    """
    return bool(mapper.GetCropping()) and mapper.GetCroppingRegionFlags() != SUBVOLUME_FLAGS


def crop_uniforms(mapper, image) -> dict:
    """``u_mc_cropFlags`` and ``u_mc_cropLow`` / ``u_mc_cropHigh``: the region flags and the
    cropping planes in texture coordinates (see the module doc).

    Examples
    --------
    >>> from mipcast.data_fixtures import make_fixture
    >>> from mipcast.mappers.mip import MIPVolumeMapper
    >>> mapper = MIPVolumeMapper()
    >>> mapper.SetCropping(True); mapper.SetCroppingRegionPlanes(1.5, 5.5, 0, 7, 0, 7)
    >>> mapper.SetCroppingRegionFlagsToFence()
    >>> values = crop_uniforms(mapper, make_fixture("spheres", size=8))
    >>> hex(values["u_mc_cropFlags"]), values["u_mc_cropLow"][0], values["u_mc_cropHigh"][0]
    ('0x2ebfeba', 0.25, 0.75)
    """
    low, high = crop_box(mapper.GetCroppingRegionPlanes(), data_to_texture(image))
    return {"u_mc_cropFlags": int(mapper.GetCroppingRegionFlags()) & ((1 << 27) - 1),
            "u_mc_cropLow": tuple(float(v) for v in low), "u_mc_cropHigh": tuple(float(v) for v in high)}


def push_crop(uniforms, values: dict) -> None:
    """Upload :func:`crop_uniforms`."""
    uniforms.SetUniformi("u_mc_cropFlags", int(values["u_mc_cropFlags"]))
    uniforms.SetUniform3f("u_mc_cropLow", list(values["u_mc_cropLow"]))
    uniforms.SetUniform3f("u_mc_cropHigh", list(values["u_mc_cropHigh"]))


def world_planes(mapper, camera) -> tuple:
    """The mapper's clipping planes and slab in world coordinates: ``(origins, normals)`` (P, 3) each.

    The cropping box is not among them (it lies in data coordinates: see
    :func:`texture_rows`).  ``camera`` gives the slab's default centre and
    normal (``None``: no slab unless centre and normal are both set).
    """
    origins, normals = [], []
    planes = mapper.GetClippingPlanes()
    if planes is not None:
        for index in range(planes.GetNumberOfItems()):
            plane = planes.GetItem(index)
            origins.append(plane.GetOrigin())
            normals.append(plane.GetNormal())
    slab = slab_of(mapper, camera)
    if slab is not None:
        o, n = slab_planes(*slab)
        origins += list(o)
        normals += list(n)
    return np.array(origins, float).reshape(-1, 3), np.array(normals, float).reshape(-1, 3)


def cuts(mapper, camera=None) -> bool:
    """Whether the mapper's cropping, clipping planes or slab (``camera``: its default centre and normal) cut the
    volume."""
    return bool(mapper.GetCropping()) or len(world_planes(mapper, camera)[0]) > 0


def slab_of(mapper, camera) -> Optional[tuple]:
    """``(thickness, centre, normal)`` of the mapper's slab now, or ``None`` without one."""
    get = getattr(mapper, "_slab_settings", None)
    if get is None:
        return None
    thickness, centre, normal = get()
    if not thickness:
        return None
    if centre is None or normal is None:
        if camera is None:
            return None
        if centre is None:
            centre = camera.GetFocalPoint()
        if normal is None:
            normal = camera.GetDirectionOfProjection()
    return float(thickness), tuple(centre), tuple(normal)


#: The slab uniforms DEMIP reads when no slab is set: depth over the box, depth from the box entry.
NO_SLAB = {"u_mc_slabDepth": (-1.0e30, 1.0e30), "u_mc_slabDistance": (-1.0e30, 1.0e30),
           "u_mc_slabNear": (0.0, 0.0, 0.0, 1.0), "u_mc_slabFar": (0.0, 0.0, 0.0, 1.0)}


def slab_uniforms(mapper, image, volume, camera) -> dict:
    """DEMIP's slab uniforms now: the depth range and entry plane of the box's part inside the slab.

    ``u_mc_slabDepth`` holds the least and greatest view distance (eye
    ``-z``) over the part of the box inside the slab (for any slab
    orientation: :func:`mipcast.core.clipping.region_extent`),
    ``u_mc_slabDistance`` the least and greatest distance from the eye
    point over it (perspective ``eye_distance``), ``u_mc_slabNear`` /
    ``u_mc_slabFar`` the slab's two faces as texture-space rows (``steps``
    and ``entry_plus_length`` measure from where the ray enters the slab).
    :data:`NO_SLAB` without a slab or without a camera.
    """
    slab = slab_of(mapper, camera)
    if slab is None or camera is None or image is None:
        return dict(NO_SLAB)
    origins, normals = slab_planes(*slab)
    from_world = np.linalg.inv(matrix_array(volume.GetMatrix())) if volume is not None else np.eye(4)
    to_index, upper = index_space(image)
    world_to_index = to_index @ from_world
    to_eye = matrix_array(camera.GetViewTransformMatrix()) @ np.linalg.inv(world_to_index)
    extent = region_extent(plane_rows(origins, normals, world_to_index), upper, to_eye)
    rows = plane_rows(origins, normals, world_to_texture(image, volume))
    rows = rows / np.linalg.norm(rows[:, :3], axis=1, keepdims=True)
    if extent is None:  # the slab misses the box: every ray is clipped away anyway
        extent = (-1.0e30, 1.0e30, -1.0e30, 1.0e30)
    return {"u_mc_slabDepth": extent[:2], "u_mc_slabDistance": extent[2:],
            "u_mc_slabNear": tuple(rows[0]), "u_mc_slabFar": tuple(rows[1])}


def push_slab(uniforms, values: dict) -> None:
    """Upload :func:`slab_uniforms` (or :data:`NO_SLAB`)."""
    for name, value in values.items():
        if len(value) == 2:
            uniforms.SetUniform2f(name, [float(v) for v in value])
        else:
            uniforms.SetUniform4f(name, [float(v) for v in value])


def world_to_texture(image, volume) -> np.ndarray:
    """4x4: world -> the volume texture's coordinates (point ``i`` at ``(i + 0.5) / N``)."""
    to_index, upper = index_space(image)
    dims = upper + 1.0
    to_texture = np.diag(list(1.0 / dims) + [1.0])
    to_texture[:3, 3] = 0.5 / dims
    from_world = np.linalg.inv(matrix_array(volume.GetMatrix())) if volume is not None else np.eye(4)
    return to_texture @ to_index @ from_world


def data_to_texture(image) -> np.ndarray:
    """4x4: the image's data (physical) coordinates -> texture coordinates."""
    to_index, upper = index_space(image)
    dims = upper + 1.0
    to_texture = np.diag(list(1.0 / dims) + [1.0])
    to_texture[:3, 3] = 0.5 / dims
    return to_texture @ to_index


def texture_rows(mapper, image, volume, camera) -> np.ndarray:
    """Every plane the mapper clips with now, as texture-space rows (P, 4) (see the module doc).

    The cropping box is among them with the sub-volume flags only (other
    flags crop by regions: :func:`crop_uniforms`).
    """
    origins, normals = world_planes(mapper, camera)
    rows = [plane_rows(origins, normals, world_to_texture(image, volume))]
    if mapper.GetCropping() and not crops_regions(mapper):
        rows.append(plane_rows(*box_planes(mapper.GetCroppingRegionPlanes()), data_to_texture(image)))
    rows = np.concatenate(rows, axis=0)
    # scale each row to unit normal length: keeps float32 comparisons well conditioned
    size = np.linalg.norm(rows[:, :3], axis=1, keepdims=True)
    return rows / np.where(size > 0, size, 1.0)


def push(uniforms, rows: np.ndarray) -> None:
    """Upload ``rows`` (P <= :data:`MAX_PLANES`, 4) as ``u_mc_clipCount`` / ``u_mc_clip0`` ..."""
    rows = np.asarray(rows, dtype=np.float64).reshape(-1, 4)
    if len(rows) > MAX_PLANES:
        raise ValueError(f"at most {MAX_PLANES} clipping planes, got {len(rows)}")
    values = np.zeros((MAX_PLANES, 4))
    values[:len(rows)] = rows
    uniforms.SetUniformi("u_mc_clipCount", len(rows))
    for index, row in enumerate(values):  # one vec4 each: VTK 9.2's uniform arrays are not safe
        uniforms.SetUniform4f(f"u_mc_clip{index}", [float(v) for v in row])


SLAB_NAMES = ("slab_thickness", "slab_centre", "slab_normal")


def copy_clipping(source, target) -> None:
    """Give a private mapper (a foveation level, a first pass) ``source``'s planes, cropping and slab.

    Setters are called only where values differ (nothing is rebuilt).  The
    private mapper draws outside the renderer's props, so it also gets the
    camera its slab follows (``object_state(target)["clip_camera"]``): the
    renderer's, or, where ``source`` is itself private (a foveated level's
    bricks' source), the one ``source`` was given.
    """
    from mipcast.core.object_state import object_state
    from mipcast.mappers.private_draw import rendering_renderer

    settings = source._slab_settings() if hasattr(source, "_slab_settings") else (0.0, None, None)
    if settings[0]:  # the slab may follow the camera; DEMIP's depth range needs it
        volume = source.GetAttachedVolume()
        renderer = rendering_renderer(source, volume) if volume is not None else None
        object_state(target)["clip_camera"] = (renderer.GetActiveCamera() if renderer is not None
                                               else object_state(source).get("clip_camera"))
    planes = source.GetClippingPlanes()
    if target.GetClippingPlanes() is not planes:
        target.SetClippingPlanes(planes)
    if target.GetCropping() != source.GetCropping():
        target.SetCropping(source.GetCropping())
    if target.GetCroppingRegionPlanes() != source.GetCroppingRegionPlanes():
        target.SetCroppingRegionPlanes(*source.GetCroppingRegionPlanes())
    if target.GetCroppingRegionFlags() != source.GetCroppingRegionFlags():
        target.SetCroppingRegionFlags(source.GetCroppingRegionFlags())
    source_slab = getattr(source, "_slab_settings", None)
    target_params = getattr(target, "_parameters", None)
    if source_slab is None or target_params is None:
        return
    params = target_params()
    for name, value in zip(SLAB_NAMES, source_slab()):
        if name in params and params[name] != value:
            target._set_parameter(name, value)
