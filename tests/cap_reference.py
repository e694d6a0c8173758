"""The float64 reference on the rays VTK's GPU ray caster casts with the camera inside the volume.

Where the camera's near plane cuts the volume's box VTK starts each ray at its near-plane cap, a thousandth
of the clipping range beyond the near plane (``vtkOpenGLGPUVolumeRayCastMapper``'s ``RenderVolumeGeometry``),
not at the near plane where :func:`mipcast.core.camera_rays.camera_rays` starts them.  Computed here from the
camera alone (not from :func:`mipcast.core.camera_rays.near_cap`, which the tests check).
"""
import numpy as np

from mipcast.core.camera_rays import camera_rays, index_space
from mipcast.mappers.outline_rays import volume_array


def from_the_cap(image, camera, size, kernel, *arguments):
    """``kernel`` (one of :mod:`mipcast.reference.mip`'s, then ``arguments``: a sampled kernel's step) of the
    pixels' rays from VTK's cap to the box's exit, float64 (rows top first; NaN: no ray)."""
    rays = camera_rays(image, camera, size)
    to_index, _ = index_space(image)
    world = rays.direction @ np.linalg.inv(to_index[:3, :3]).T  # unit world directions
    near, far = camera.GetClippingRange()
    start = np.maximum(rays.t_enter, 1.0e-3 * (far - near) / (world @ np.array(camera.GetDirectionOfProjection())))
    hit = rays.hit & (start <= rays.t_exit)
    out = np.full(rays.hit.shape, np.nan)
    out[hit] = kernel(volume_array(image), rays.origin[hit] + start[hit, None] * rays.direction[hit],
                      rays.direction[hit], rays.t_exit[hit] - start[hit], *arguments)
    return out
