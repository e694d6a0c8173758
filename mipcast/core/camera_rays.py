"""Per-pixel camera rays in the continuous index space of an image.

The rays are built the way VTK's OpenGL renderer builds them: each pixel
centre is unprojected through the inverse of the camera's composite
projection matrix (world -> NDC) at the near (NDC z = -1) and far (z = +1)
clipping planes.  This covers orthographic and perspective cameras alike.
"""
from __future__ import annotations

from typing import Any, NamedTuple, Optional, Union

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkCommonMath import vtkMatrix3x3, vtkMatrix4x4

from mipcast.core.validation import check_size

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


def pixel_centres(columns: int, rows: int) -> tuple:
    """NDC x of the column centres (left to right) and y of the row centres (top row first).

    Examples
    --------
    >>> x, y = pixel_centres(4, 2)
    >>> x.tolist(), y.tolist()
    ([-0.75, -0.25, 0.25, 0.75], [0.5, -0.5])
    """
    x = 2.0 * (np.arange(columns) + 0.5) / columns - 1.0
    y = 2.0 * (np.arange(rows)[::-1] + 0.5) / rows - 1.0  # top row first
    return x, y


def unproject(ndc_to_space: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The points under NDC ``(x, y)`` on the near (NDC z = -1) and far (z = +1) planes.

    Parameters
    ----------
    ndc_to_space : numpy.ndarray, shape (4, 4)
        Inverse of the projection into NDC (e.g. of the camera's composite
        projection matrix).
    x, y : numpy.ndarray
        NDC coordinates, broadcast against each other to a shape ``S``.

    Returns
    -------
    numpy.ndarray, shape (2, *S, 3)
        ``[0]`` on the near plane, ``[1]`` on the far plane.

    Examples
    --------
    >>> unproject(np.eye(4), np.array([0.5]), np.array([-0.5])).tolist()
    [[[0.5, -0.5, -1.0]], [[0.5, -0.5, 1.0]]]
    """
    ndc = np.empty((2,) + np.broadcast(x, y).shape + (4,))
    ndc[..., 0] = x
    ndc[..., 1] = y
    ndc[0, ..., 2], ndc[1, ..., 2] = -1.0, 1.0
    ndc[..., 3] = 1.0
    points = ndc @ ndc_to_space.T
    return points[..., :3] / points[..., 3:]


def index_space(image: vtkImageData) -> tuple:
    """The mapping into the image's continuous index space and its box there.

    Returns
    -------
    to_index : numpy.ndarray, shape (4, 4)
        Physical (world) -> index coordinates, point ``(i, j, k)`` counted
        from the first point of the extent.
    upper : numpy.ndarray, shape (3,)
        The far corner of the point-bounds box ``[0, upper]``: dimensions - 1.

    Examples
    --------
    >>> image = vtkImageData()
    >>> image.SetExtent(2, 5, 0, 3, 0, 1)
    >>> image.SetSpacing(0.5, 1.0, 1.0)
    >>> to_index, upper = index_space(image)
    >>> (to_index @ [1.0, 0.0, 0.0, 1.0]).tolist(), upper.tolist()
    ([0.0, 0.0, 0.0, 1.0], [3.0, 3.0, 1.0])
    """
    to_index = matrix_array(image.GetPhysicalToIndexMatrix())
    to_index[:3, 3] -= np.array(image.GetExtent()[0::2], float)
    return to_index, np.array(image.GetDimensions(), float) - 1.0


def first_point(image: vtkImageData) -> tuple:
    """Where the first point of ``image``'s extent lies: its index-to-physical matrix at the extent's start.

    Not ``image.GetPoint(0)``: VTK 9.7 keeps an image's points from before a
    ``DeepCopy`` or ``ShallowCopy`` into it that changed its spacing, origin
    or direction but not its extent (a time step read into the same object).

    Examples
    --------
    >>> image = vtkImageData()
    >>> image.SetExtent(2, 5, 0, 3, 0, 1)
    >>> image.SetSpacing(0.5, 1.0, 1.0)
    >>> first_point(image)
    (1.0, 0.0, 0.0)
    """
    index = np.array([*image.GetExtent()[0::2], 1.0], float)
    return tuple(float(v) for v in (matrix_array(image.GetIndexToPhysicalMatrix()) @ index)[:3])


def placed(image, matrix=None):
    """``image`` as its vtkVolume's ``matrix`` places it in the world: its index-to-physical matrix is index -> world.

    VTK draws a volume's points at ``matrix @ IndexToPhysical`` (the
    volume's ``SetUserMatrix``, position, orientation, scale, origin): the
    copy (scalars shared) folds the matrix into its origin and direction
    matrix (no longer orthonormal under a scale) and keeps the spacing, so
    that world planes and camera rays meet the right points, while a ray's
    length through ``spacing`` (the bricks' ``u_mc_raySpacing``,
    :mod:`mipcast.mappers.outline_rays`, :func:`mipcast.reference.rays.hit_rays`)
    stays in the volume's own units, where VTK measures its sample distance.
    ``image`` itself when ``matrix`` (4x4 array or vtkMatrix4x4) is None or
    the identity.

    Examples
    --------
    >>> image = vtkImageData()
    >>> image.SetDimensions(3, 3, 3)
    >>> placed(image) is image
    True
    >>> turned = np.array([[0.0, -2.0, 0.0, 5.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])
    >>> there = placed(image, turned)
    >>> (matrix_array(there.GetIndexToPhysicalMatrix()) @ [1.0, 1.0, 0.0, 1.0]).tolist(), there.GetSpacing()
    ([3.0, 1.0, 0.0, 1.0], (1.0, 1.0, 1.0))
    """
    if matrix is None:
        return image
    matrix = matrix if isinstance(matrix, np.ndarray) else matrix_array(matrix)
    if np.array_equal(matrix, np.eye(4)):
        return image
    out = type(image)()
    out.ShallowCopy(image)
    out.SetOrigin(matrix[:3, :3] @ np.array(image.GetOrigin()) + matrix[:3, 3])
    out.SetDirectionMatrix((matrix[:3, :3] @ matrix_array(image.GetDirectionMatrix())).ravel())
    return out


def box_interval(origin: np.ndarray, direction: np.ndarray, upper: np.ndarray,
                 margin: float = 0.0) -> tuple:
    """Ray parameters where rays enter/leave the box [-margin, upper + margin].

    ``origin`` and ``direction`` are (..., 3); the returned ``t_near`` and
    ``t_far`` (...) are unclipped (``t_near > t_far`` on a miss).  A zero
    direction component keeps the whole line inside that slab when the
    origin lies in it (bounds inclusive) and excludes it otherwise.

    Examples
    --------
    >>> t_near, t_far = box_interval(np.array([-1.0, 0.5, 0.5]), np.array([1.0, 0.0, 0.0]), np.ones(3))
    >>> float(t_near), float(t_far)
    (1.0, 2.0)
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


def camera_rays(image: vtkImageData, camera: Any, size: tuple, aspect: Optional[float] = None) -> Rays:
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
    aspect : float, optional
        The camera's aspect ratio when it is not ``width / height``: a ray
        grid coarser than the viewport (VTK's reduced framebuffer of an
        image sample distance, whose size it truncates) spans the viewport,
        whose aspect the projection keeps.

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
    aspect = width / height if aspect is None else float(aspect)
    world_to_ndc = matrix_array(camera.GetCompositeProjectionTransformMatrix(aspect, -1, 1))
    ndc_to_world = np.linalg.inv(world_to_ndc)

    x, y = pixel_centres(width, height)
    near, far = unproject(ndc_to_world, x[None, :], y[:, None])
    length = np.linalg.norm(far - near, axis=-1)
    world_dir = (far - near) / length[..., None]

    to_index, upper = index_space(image)
    origin = near @ to_index[:3, :3].T + to_index[:3, 3]
    direction = world_dir @ to_index[:3, :3].T

    t_enter, t_exit = box_interval(origin, direction, upper)
    t_enter, t_exit = np.maximum(t_enter, 0.0), np.minimum(t_exit, length)
    hit = t_enter <= t_exit
    loose_enter, loose_exit = box_interval(origin, direction, upper, TOUCH_TOLERANCE)
    loose_enter, loose_exit = np.maximum(loose_enter, 0.0), np.minimum(loose_exit, length)
    touch = ~hit & (loose_enter <= loose_exit)
    t_enter = np.where(hit, t_enter, np.where(touch, loose_enter, np.nan))
    t_exit = np.where(hit, t_exit, np.where(touch, loose_exit, np.nan))
    return Rays(origin, direction, t_enter, t_exit, hit | touch)
