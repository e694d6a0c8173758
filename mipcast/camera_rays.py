"""Per-pixel camera rays in the continuous index space of an image.

The rays are built the way VTK's OpenGL renderer builds them: each pixel
centre is unprojected through the inverse of the camera's composite
projection matrix (world -> NDC) at the near (NDC z = -1) and far (z = +1)
clipping planes.  This covers orthographic and perspective cameras alike.
"""
from __future__ import annotations

from typing import Any, NamedTuple, Union

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkCommonMath import vtkMatrix3x3, vtkMatrix4x4

from .validation import check_size

#: Rays that miss the box by less than this many voxels (float64 rounding
#: of the camera and image matrices) are treated as touching it.
TOUCH_TOLERANCE = 1e-9


class Rays(NamedTuple):
    """Camera rays in index space; arrays have rows top-first.

    Attributes
    ----------
    origin : numpy.ndarray, shape (H, W, 3)
        Ray start (on the near clipping plane) in index coordinates (i, j, k).
    direction : numpy.ndarray, shape (H, W, 3)
        Index-space displacement per unit of world length along the ray.
    t_enter, t_exit : numpy.ndarray, shape (H, W)
        World distances from ``origin`` where the ray enters / leaves the
        point-bounds box, clipped to the near and far planes; NaN on a miss.
    hit : numpy.ndarray of bool, shape (H, W)
        Whether the ray meets the box (touching an edge or corner counts).
    """

    origin: np.ndarray
    direction: np.ndarray
    t_enter: np.ndarray
    t_exit: np.ndarray
    hit: np.ndarray


def matrix_array(vtk_matrix: Union[vtkMatrix4x4, vtkMatrix3x3]) -> np.ndarray:
    """Return a VTK matrix as a float64 numpy array (a copy).

    Parameters
    ----------
    vtk_matrix : vtkMatrix4x4 or vtkMatrix3x3
        The matrix (read only).

    Returns
    -------
    numpy.ndarray, shape (4, 4) or (3, 3), float64
        ``out[r, c] == vtk_matrix.GetElement(r, c)``.

    Raises
    ------
    TypeError
        If ``vtk_matrix`` is neither a vtkMatrix4x4 nor a vtkMatrix3x3.

    Examples
    --------
    >>> from vtkmodules.vtkCommonMath import vtkMatrix3x3, vtkMatrix4x4
    >>> shift = vtkMatrix4x4()
    >>> shift.SetElement(0, 3, 2.5)
    >>> matrix_array(shift)[0]
    array([1. , 0. , 0. , 2.5])
    >>> matrix_array(vtkMatrix3x3()).shape, matrix_array(vtkMatrix3x3()).dtype
    ((3, 3), dtype('float64'))
    """
    if isinstance(vtk_matrix, vtkMatrix4x4):
        size = 4
    elif isinstance(vtk_matrix, vtkMatrix3x3):
        size = 3
    else:
        raise TypeError(f"expected vtkMatrix4x4 or vtkMatrix3x3, got {type(vtk_matrix).__name__}")
    return np.array([[vtk_matrix.GetElement(r, c) for c in range(size)] for r in range(size)],
                    dtype=np.float64)


def _slab(origin: np.ndarray, direction: np.ndarray, upper: np.ndarray,
          margin: float) -> tuple:
    """Ray parameters where rays enter/leave the box [-margin, upper + margin].

    A zero direction component keeps the whole line inside that slab when
    the origin lies in it (bounds inclusive) and excludes it otherwise.
    """
    lo_box, hi_box = -margin, upper + margin
    with np.errstate(divide="ignore", invalid="ignore"):
        t_lo = (lo_box - origin) / direction
        t_hi = (hi_box - origin) / direction
    parallel = direction == 0
    inside = (origin >= lo_box) & (origin <= hi_box)
    t_near = np.where(parallel, np.where(inside, -np.inf, np.inf), np.minimum(t_lo, t_hi))
    t_far = np.where(parallel, np.where(inside, np.inf, -np.inf), np.maximum(t_lo, t_hi))
    return t_near.max(axis=-1), t_far.min(axis=-1)


def camera_rays(image: vtkImageData, camera: Any, size: tuple) -> Rays:
    """Cast one ray per pixel centre, as VTK's GPU ray caster does.

    Parameters
    ----------
    image : vtkImageData or pyvista.ImageData
        The volume; its origin, spacing, direction matrix and extent define
        the world -> index mapping.  Point ``(i, j, k)`` (counted from the
        first point of the extent) sits at index coordinate ``(i, j, k)``,
        so the box is ``[0, nx-1] x [0, ny-1] x [0, nz-1]``.
    camera : vtkCamera
        The camera (read only).
    size : tuple of int
        Window size ``(width, height)`` in pixels.

    Returns
    -------
    Rays
        ``origin``, ``direction`` (H, W, 3), ``t_enter``, ``t_exit``,
        ``hit`` (H, W); all float64 except ``hit``.  Row 0 is the top row
        of the window (as in ``pyvista.Plotter.screenshot()``).

    Notes
    -----
    ``t`` is a world distance measured from the near clipping plane; the
    ray is clipped to ``[0, distance to the far plane]`` as VTK clips it.
    A ray that misses the box by less than ``TOUCH_TOLERANCE`` voxels is
    reported as touching it (hit, with the parameters of that slightly
    larger box), so rays meant to run along a face or through a corner do
    not flicker with float64 rounding.

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> image = vtkImageData()
    >>> image.SetDimensions(4, 4, 4)
    >>> camera = vtkCamera()
    >>> camera.SetPosition(1.5, 1.5, 10.0)
    >>> camera.SetFocalPoint(1.5, 1.5, 0.0)
    >>> rays = camera_rays(image, camera, (3, 3))
    >>> bool(rays.hit[1, 1]), round(float(rays.t_exit[1, 1] - rays.t_enter[1, 1]), 6)
    (True, 3.0)
    """
    if not isinstance(image, vtkImageData):
        raise TypeError(f"expected vtkImageData or pyvista.ImageData, got {type(image).__name__}")
    width, height = check_size(size)
    world_to_ndc = matrix_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
    ndc_to_world = np.linalg.inv(world_to_ndc)

    x = 2.0 * (np.arange(width) + 0.5) / width - 1.0
    y = 2.0 * (np.arange(height)[::-1] + 0.5) / height - 1.0  # top row first
    ndc = np.empty((2, height, width, 4))
    ndc[..., 0] = x[None, None, :]
    ndc[..., 1] = y[None, :, None]
    ndc[0, ..., 2], ndc[1, ..., 2] = -1.0, 1.0
    ndc[..., 3] = 1.0
    world = ndc @ ndc_to_world.T
    world = world[..., :3] / world[..., 3:]
    near, far = world[0], world[1]
    length = np.linalg.norm(far - near, axis=-1)
    world_dir = (far - near) / length[..., None]

    extent = image.GetExtent()
    to_index = matrix_array(image.GetPhysicalToIndexMatrix())
    origin = near @ to_index[:3, :3].T + to_index[:3, 3] - np.array(extent[0::2], float)
    direction = world_dir @ to_index[:3, :3].T
    upper = np.array(image.GetDimensions(), float) - 1.0

    t_enter, t_exit = _slab(origin, direction, upper, 0.0)
    t_enter, t_exit = np.maximum(t_enter, 0.0), np.minimum(t_exit, length)
    hit = t_enter <= t_exit
    loose_enter, loose_exit = _slab(origin, direction, upper, TOUCH_TOLERANCE)
    loose_enter, loose_exit = np.maximum(loose_enter, 0.0), np.minimum(loose_exit, length)
    touch = ~hit & (loose_enter <= loose_exit)
    t_enter = np.where(hit, t_enter, np.where(touch, loose_enter, np.nan))
    t_exit = np.where(hit, t_exit, np.where(touch, loose_exit, np.nan))
    return Rays(origin, direction, t_enter, t_exit, hit | touch)
