"""DEMIP's depth and colour maths in float64 (numpy only): depth modes, Eq. 1, the colour sphere, chromadepth.

One definition shared by the float64 reference (:func:`mipcast.reference.demip.render_demip`)
and the distributed DEMIP composite (:mod:`mipcast.distributed`, which
reduces each pixel's maximum and first same-material sample index over MPI
ranks and colours on the CPU).  See docs/methods.md, section DEMIP.
"""
from __future__ import annotations

import numpy as np

from mipcast.core.camera_rays import index_space, matrix_array
from mipcast.core.clipping import plane_rows, ray_interval, region_extent, slab_planes
from mipcast.core.shading import chroma_color, sphere_color


def enhance(color: np.ndarray, depth: np.ndarray, term: np.ndarray, where: np.ndarray, geometry: "DepthGeometry",
            params: dict) -> np.ndarray:
    """DEMIP's straight colour: Eq. 1, the colour sphere (Eq. 2) and pseudo-chromadepth where ``term``.

    Parameters
    ----------
    color : numpy.ndarray, shape (N, 3)
        The MIP colour of each ray's maximum (straight, in [0, 1]).
    depth : numpy.ndarray, shape (N,)
        Normalised depth (NaN where there is no DEMIP term).
    term : numpy.ndarray of bool, shape (N,)
        Rays with a DEMIP term (a same-material sample above the floor).
    where : numpy.ndarray, shape (N, 3)
        The same-material sample's position (index space of ``geometry``).
    geometry : DepthGeometry
    params : dict
        ``depth_weight``, ``sphere_weight``, ``sphere_colors`` (front, back),
        ``sphere_orientation`` (3x3), ``chroma_depth_weight``: the checked
        values of :data:`mipcast.core.parameter_tables.DEMIP`.

    Returns
    -------
    numpy.ndarray, shape (N, 3)
        Clipped to [0, 1] where ``term``, ``color`` elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> params = {"depth_weight": 0.5, "sphere_weight": 0.0, "sphere_colors": ((1, 0, 0), (0, 0, 1)),
    ...           "sphere_orientation": np.eye(3), "chroma_depth_weight": 0.0}
    >>> enhance(np.full((1, 3), 0.4), np.array([1.0]), np.array([True]), np.zeros((1, 3)), None, params)
    array([[0.2, 0.2, 0.2]])
    """
    depth_weight, sphere_weight = params["depth_weight"], params["sphere_weight"]
    chroma_weight = params["chroma_depth_weight"]
    front, back = params["sphere_colors"]
    known = np.nan_to_num(depth)
    enhanced = color * (1.0 - depth_weight) + 2.0 * depth_weight * (1.0 - known)[:, None]
    if sphere_weight > 0:
        axis = np.array(params["sphere_orientation"])[:, 2]
        sphere = geometry.sphere_color(where, axis, np.array(front), np.array(back))
        enhanced = enhanced * (1.0 - sphere_weight) + sphere * sphere_weight
    enhanced = enhanced * (1.0 - chroma_weight) + chroma_color(known) * chroma_weight
    return np.where(term[:, None], np.clip(enhanced, 0.0, 1.0), color)


class DepthGeometry:
    """Index <-> world <-> eye for one image and camera; the box's depth range (DEMIP's depth modes).

    The float64 definitions of DEMIP's depth (``depth``, every mode of
    :data:`mipcast.core.shading.DEPTH_MODES`, normalised over the whole box,
    or the box's part inside a slab after :meth:`narrow_to_slab`) and of the
    colour sphere's direction.  Used by the float64 reference
    (:mod:`mipcast.reference.demip`) and by the distributed DEMIP composite
    (:mod:`mipcast.distributed`), so both apply the same maths.

    Examples
    --------
    >>> import numpy as np
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> image = vtkImageData()
    >>> image.SetDimensions(11, 11, 11)
    >>> camera = vtkCamera()
    >>> camera.SetFocalPoint(5, 5, 5); camera.SetPosition(5, 5, 50); camera.ParallelProjectionOn()
    >>> geometry = DepthGeometry(image, camera, 1.0)
    >>> entry = np.array([[5.0, 5.0, 10.0]])
    >>> float(geometry.depth("steps", np.array([[5.0, 5.0, 5.0]]), entry)[0])
    0.5
    """

    def __init__(self, image, camera, aspect: float) -> None:
        to_index, upper = index_space(image)
        self.to_world = np.linalg.inv(to_index)
        self.view = matrix_array(camera.GetViewTransformMatrix())
        self.projection = matrix_array(camera.GetProjectionTransformMatrix(aspect, -1, 1))
        self.parallel = bool(camera.GetParallelProjection())
        self.upper = upper
        corners = np.array([[x, y, z] for x in (0, upper[0]) for y in (0, upper[1]) for z in (0, upper[2])])
        corner_eye = self.eye(corners)
        self.near, self.far = (-corner_eye[:, 2]).min(), (-corner_eye[:, 2]).max()
        eye_index = to_index[:3, :3] @ np.array(camera.GetPosition()) + to_index[:3, 3]
        self.nearest = np.linalg.norm(self.eye(np.clip(eye_index, 0.0, upper)[None])[0])
        self.farthest = np.linalg.norm(corner_eye, axis=1).max()
        self.centre = self.world(0.5 * upper[None])[0]

    def narrow_to_slab(self, slab, entry: np.ndarray, direction: np.ndarray) -> np.ndarray:
        """Depth over the box's part inside ``slab``; returns the rays' entries into the slab."""
        rows = plane_rows(*slab_planes(*slab), np.linalg.inv(self.to_world))
        to_eye = self.view @ self.to_world
        extent = region_extent(rows, self.upper, to_eye)
        if extent is not None:
            self.near, self.far = max(self.near, extent[0]), min(self.far, extent[1])
            self.nearest, self.farthest = max(self.nearest, extent[2]), min(self.farthest, extent[3])
        lo, _ = ray_interval(entry, direction, 0.0, np.inf, rows)
        return entry + np.maximum(lo, 0.0)[:, None] * direction

    def world(self, index: np.ndarray) -> np.ndarray:
        return index @ self.to_world[:3, :3].T + self.to_world[:3, 3]

    def eye(self, index: np.ndarray) -> np.ndarray:
        return self.world(index) @ self.view[:3, :3].T + self.view[:3, 3]

    def window_depth(self, distance: np.ndarray) -> np.ndarray:
        p = self.projection
        near_plane = (p[2, 3] + p[3, 3]) / (p[2, 2] + p[3, 2])
        far_plane = (p[2, 3] - p[3, 3]) / (p[2, 2] - p[3, 2])
        z = -np.clip(distance, near_plane, far_plane)
        return 0.5 * (p[2, 2] * z + p[2, 3]) / (p[3, 2] * z + p[3, 3]) + 0.5

    def depth(self, mode: str, where: np.ndarray, entry: np.ndarray) -> np.ndarray:
        hit_eye, entry_eye = self.eye(where), self.eye(entry)
        extent = self.far - self.near
        if mode == "window":
            near, far = self.window_depth(self.near), self.window_depth(self.far)
            depth = (self.window_depth(-hit_eye[:, 2]) - near) / (far - near)
        elif mode == "steps":
            depth = np.linalg.norm(hit_eye - entry_eye, axis=1) / extent
        elif mode == "entry_plus_length":
            depth = (-entry_eye[:, 2] - self.near + np.linalg.norm(hit_eye - entry_eye, axis=1)) / extent
        elif self.parallel:
            depth = (-hit_eye[:, 2] - self.near) / extent
        else:
            depth = (np.linalg.norm(hit_eye, axis=1) - self.nearest) / (self.farthest - self.nearest)
        return np.clip(depth, 0.0, 1.0)

    def sphere_color(self, where, axis, front, back) -> np.ndarray:
        return sphere_color(self.world(where) - self.centre, axis, front, back)
