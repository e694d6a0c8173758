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


def grazing_sine(image, camera, matrix=None) -> float:
    """The sine of the smallest angle at which ``camera``'s rays meet a face of ``image``'s point box.

    0 for a face seen edge-on (its plane along the rays: a volume whose
    direction matrix turns it about the view axis, seen head-on), 1 for a
    face seen square on. Parallel projection: the faces' normals against
    the direction of projection; perspective: the eye's distance to each
    face's plane over its distance to the face's farthest corner. ``matrix``:
    the volume's (4x4 array or vtkMatrix4x4), folded in as :func:`placed`
    does. Left out: faces exactly edge-on whose normal lies exactly along a
    world axis (an unturned volume seen along an axis: VTK's float32
    projection of such a face is exact, a line that draws no fragment), and
    the faces of a box flat along an axis, which have no plane (1.0 when no
    face is left).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> image = vtkImageData()
    >>> image.SetExtent(0, 10, 0, 10, 0, 10)
    >>> camera = vtkCamera()
    >>> camera.SetFocalPoint(5, 5, 5); camera.SetPosition(5, 5, 40); camera.ParallelProjectionOn()
    >>> grazing_sine(image, camera)   # the side faces run exactly along the view, along world axes
    1.0
    >>> image.SetDirectionMatrix(0.6, -0.8, 0.0, 0.8, 0.6, 0.0, 0.0, 0.0, 1.0)
    >>> grazing_sine(image, camera)   # turned about the view axis: along the view, off the world axes
    0.0
    >>> camera.SetPosition(40, 40, 40)
    >>> image.SetDirectionMatrix(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
    >>> round(grazing_sine(image, camera), 6)   # every face at the same angle
    0.57735
    """
    to_world = matrix_array(image.GetIndexToPhysicalMatrix())
    if matrix is not None:
        to_world = (matrix if isinstance(matrix, np.ndarray) else matrix_array(matrix)) @ to_world
    extent = np.array(image.GetExtent(), dtype=float)
    corners = extent[_CORNER_ENDS] @ to_world[:3, :3].T + to_world[:3, 3]
    normals = np.cross(corners[_EDGES[:, 0]] - corners[0], corners[_EDGES[:, 1]] - corners[0])  # per axis
    lengths = np.linalg.norm(normals, axis=1)
    has_plane = lengths > 0.0
    normals = normals / np.where(has_plane, lengths, 1.0)[:, None]
    if camera.GetParallelProjection():
        direction = np.array(camera.GetDirectionOfProjection())
        sines = np.repeat(np.abs(normals @ direction) / np.linalg.norm(direction), 2)
    else:
        to_eye = np.array(camera.GetPosition()) - corners  # (8, 3)
        reach = np.linalg.norm(to_eye, axis=1)[_FACES].max(axis=1)
        across = np.abs(np.einsum("fk,fk->f", np.repeat(normals, 2, axis=0), to_eye[_FACES[:, 0]]))
        sines = np.where(reach > 0.0, across / np.where(reach > 0.0, reach, 1.0), 0.0)
    exact = (sines == 0.0) & np.repeat(np.count_nonzero(normals, axis=1) == 1, 2)  # along a world axis: no fragment
    counted = np.repeat(has_plane, 2) & ~exact
    return float(sines[counted].min()) if counted.any() else 1.0


#: :func:`grazing_sine`'s box: corner c takes the extent's low or high end per axis by its bits (bit 0 the i
#: end, bit 1 j, bit 2 k), as indices into the extent; per axis the corners one edge away along the other two
#: axes; the faces (axis i low, axis i high, ...) as their four corners.
_CORNER_ENDS = np.array([[2 * axis + ((c >> axis) & 1) for axis in range(3)] for c in range(8)])
_EDGES = np.array([[1 << other for other in range(3) if other != axis] for axis in range(3)])
_FACES = np.array([[c for c in range(8) if (c >> axis) & 1 == side] for axis in range(3) for side in (0, 1)])


#: VTK's least offset of the near-plane cap (vtkOpenGLGPUVolumeRayCastMapper: 1000 float epsilons).
_LEAST_CAP_OFFSET = 1000.0 * float(np.finfo(np.float32).eps)


def near_cap(whole, camera, aspect: float = 1.0) -> Optional[np.ndarray]:
    """The plane where VTK's ray caster starts the rays when ``camera``'s near plane cuts the ``whole`` box, or None.

    VTK's GPU ray caster (``vtkOpenGLGPUVolumeRayCastMapper``,
    ``IsCameraInside`` and ``RenderVolumeGeometry``, the same in VTK 9.2 and
    9.7) tests the box's 8 corners against the camera's near frustum plane
    (``vtkCamera::GetFrustumPlanes``, normalised): where some lie on both
    sides (or one on it) it clips the box with that plane moved ``max(0.001
    (far - near), 1000 float epsilons)`` into the view (in the volume's own
    units: under a volume matrix that scales, that many of them) and caps it, so a
    ray crossing the cap starts there (its first sample one step further),
    not at the box.  ``whole``: the whole volume's image data (the corners
    through its index-to-physical matrix: a volume's own matrix folded in,
    :func:`placed`; :func:`mipcast.mappers.brick_rays.whole_geometry`).

    Returns
    -------
    numpy.ndarray or None
        ``(nx, ny, nz, c)``: the cap is ``n . x = c`` in world coordinates,
        ``n`` the unit view direction; None when the near plane does not
        cut the box (the rays start at the box).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> whole = vtkImageData()
    >>> whole.SetExtent(0, 10, 0, 10, 0, 10)
    >>> camera = vtkCamera()
    >>> camera.SetFocalPoint(5, 5, 5); camera.SetPosition(5, 5, 40); camera.SetClippingRange(1.0, 101.0)
    >>> near_cap(whole, camera) is None
    True
    >>> camera.SetPosition(5, 5, 8); camera.SetClippingRange(1.0, 101.0)
    >>> [round(float(v), 6) for v in near_cap(whole, camera)]   # z = 8 - 1 - 0.1
    [0.0, 0.0, -1.0, -6.9]
    """
    planes = [0.0] * 24
    camera.GetFrustumPlanes(float(aspect), planes)
    plane = np.array(planes[16:20])
    extent = whole.GetExtent()
    corners = np.array([[i, j, k, 1.0] for k in extent[4:6] for j in extent[2:4] for i in extent[0:2]])
    world = corners @ matrix_array(whole.GetIndexToPhysicalMatrix()).T
    side = (world[:, :3] / world[:, 3:]) @ plane[:3] + plane[3]
    if not (np.any(side == 0.0) or (np.any(side < 0.0) and np.any(side > 0.0))):
        return None
    near, far = camera.GetClippingRange()
    offset = max((far - near) * 1.0e-3, _LEAST_CAP_OFFSET)
    # VTK moves the plane by the offset in the volume's own (data) units, along the plane's normal there:
    # in the world by offset * |M^T n| (M the volume's matrix; ``whole``'s direction matrix is M times an
    # orthonormal one, so |D^T n| is the same; 1 without a matrix)
    stretch = float(np.linalg.norm(matrix_array(whole.GetDirectionMatrix()).T @ plane[:3]))
    return np.append(plane[:3], offset * stretch - plane[3])


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
    ray is clipped to ``[0, distance to the far plane]`` as VTK clips it, and
    where the near plane cuts the box (the eye inside the volume) it starts
    at VTK's cap, the near plane moved a little into the view (:func:`near_cap`).
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

    start = np.zeros(length.shape)
    cap = near_cap(image, camera, aspect)
    if cap is not None:  # the near plane cuts the box: VTK starts the rays crossing it at its cap
        with np.errstate(divide="ignore", invalid="ignore"):
            start = np.maximum((cap[3] - near @ cap[:3]) / (world_dir @ cap[:3]), 0.0)
    t_enter, t_exit = box_interval(origin, direction, upper)
    t_enter, t_exit = np.maximum(t_enter, start), np.minimum(t_exit, length)
    hit = t_enter <= t_exit
    loose_enter, loose_exit = box_interval(origin, direction, upper, TOUCH_TOLERANCE)
    loose_enter, loose_exit = np.maximum(loose_enter, start), np.minimum(loose_exit, length)
    touch = ~hit & (loose_enter <= loose_exit)
    t_enter = np.where(hit, t_enter, np.where(touch, loose_enter, np.nan))
    t_exit = np.where(hit, t_exit, np.where(touch, loose_exit, np.nan))
    return Rays(origin, direction, t_enter, t_exit, hit | touch)
