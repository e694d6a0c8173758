"""A brick's view of the whole volume's rays: the uniforms of the ``global_phase`` and ``global_cells`` pieces.

A brick of a volume (a distributed rank's piece, a brick beyond the 3D
texture limit, a ParaView rank's piece) casts the WHOLE volume's rays:
every brick computes them from the same uniforms (the camera's rays in the
whole volume's point-index space, :func:`ray_uniforms`), so that the
bricks together take exactly the single-volume samples and cells.
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np
from vtkmodules.vtkCommonCore import VTK_NEAREST_INTERPOLATION

from mipcast.core.camera_rays import first_point, matrix_array, near_cap, placed


def global_texture_box(piece_extent: Sequence[int], whole: Sequence[int]):
    """The whole volume's point bounds in the brick's texture coordinates (min, max).

    VTK's 3D texture of a brick with ``d`` points along an axis puts point
    ``i`` (of the brick's extent starting at ``e0``) at ``(i - e0 + 0.5) / d``.

    Examples
    --------
    >>> global_texture_box((0, 3, 0, 3, 2, 3), (0, 3, 0, 3, 0, 3))
    ([0.125, 0.125, -0.75], [0.875, 0.875, 0.75])
    """
    low, high = [], []
    for a in range(3):
        e0, e1 = piece_extent[2 * a], piece_extent[2 * a + 1]
        d = e1 - e0 + 1
        low.append((whole[2 * a] - e0 + 0.5) / d)
        high.append((whole[2 * a + 1] - e0 + 0.5) / d)
    return low, high


def texture_plane(plane: Sequence[float], piece_extent: Sequence[int]) -> np.ndarray:
    """A plane ``N . p = w`` of point indices in a piece's texture coordinates (as :func:`global_texture_box`).

    Point ``i`` of the piece's extent ``(e0, e1)`` along an axis lies at
    texture coordinate ``(i - e0 + 0.5) / d``, ``d = e1 - e0 + 1``.

    Examples
    --------
    >>> texture_plane([0.0, 0.0, 1.0, 3.0], (0, 3, 0, 3, 2, 5)).tolist()   # k = 3: the piece's 2nd of 4 points
    [0.0, 0.0, 4.0, 1.5]
    """
    plane = np.asarray(plane, dtype=np.float64)
    first = np.array(piece_extent[0::2], dtype=np.float64)
    points = np.array(piece_extent[1::2], dtype=np.float64) - first + 1.0
    return np.append(plane[:3] * points, plane[3] - plane[:3] @ (first - 0.5))


def set_brick_uniforms(uniforms, whole: Sequence[int], piece: Sequence[int], spacing: Sequence[float],
                       sample_distance: float) -> None:
    """A brick's static ``global_phase`` / ``global_cells`` uniforms on a vtkUniforms.

    The whole volume's and the brick's point-index boxes, the spacing, the
    sample distance; VTK's own normalisation (``u_mc_globalNorm`` (0, 1, 0):
    :class:`DistributedView` then sets the whole range's) and no rays yet
    (:func:`ray_uniforms` each frame, :func:`set_ray_uniforms`).

    Examples
    --------
    >>> from vtkmodules.vtkRenderingCore import vtkVolume
    >>> uniforms = vtkVolume().GetShaderProperty().GetFragmentCustomUniforms()
    >>> set_brick_uniforms(uniforms, (0, 9, 0, 9, 0, 9), (0, 9, 0, 9, 4, 9), (1.0, 1.0, 2.0), 0.5)
    >>> sorted(uniforms.GetNthUniformName(i) for i in range(uniforms.GetNumberOfUniforms()))[:3]
    ['u_mc_brickHi', 'u_mc_brickLo', 'u_mc_globalNorm']
    """
    uniforms.SetUniform3f("u_mc_wholeLo", [float(v) for v in whole[0::2]])
    uniforms.SetUniform3f("u_mc_wholeHi", [float(v) for v in whole[1::2]])
    uniforms.SetUniform3f("u_mc_brickLo", [float(v) for v in piece[0::2]])
    uniforms.SetUniform3f("u_mc_brickHi", [float(v) for v in piece[1::2]])
    uniforms.SetUniform3f("u_mc_raySpacing", [abs(float(v)) for v in spacing])
    uniforms.SetUniformf("u_mc_rayStep", float(sample_distance))
    uniforms.SetUniform3f("u_mc_globalNorm", [0.0, 1.0, 0.0])
    set_ray_uniforms(uniforms, {name: [0.0, 0.0, 0.0] for name in
                                ("u_mc_rayPoint0", "u_mc_rayPointX", "u_mc_rayPointY", "u_mc_rayDirection")})
    uniforms.SetUniform4f("u_mc_rayEye", [0.0, 0.0, 0.0, 0.0])
    uniforms.SetUniform4f("u_mc_rayCap", [0.0, 0.0, 0.0, 0.0])
    uniforms.SetUniformf("u_mc_nearest", 0.0)


def set_ray_uniforms(uniforms, values: dict) -> None:
    """Put :func:`ray_uniforms`' values on a vtkUniforms (vec3 and vec4)."""
    for name, value in values.items():
        (uniforms.SetUniform4f if len(value) == 4 else uniforms.SetUniform3f)(name, value)


def nearest_interpolation(volume) -> bool:
    """Whether ``volume``'s property asks for nearest-neighbour interpolation (``SetInterpolationTypeToNearest``)."""
    prop = volume.GetProperty() if volume is not None else None
    return prop is not None and prop.GetInterpolationType() == VTK_NEAREST_INTERPOLATION


def push_interpolation(volume) -> None:
    """``u_mc_nearest`` on ``volume``'s shader property: 1 when its property asks for nearest-neighbour
    interpolation (``global_phase`` then takes each sample's nearest point, as the GPU's own lookup does)."""
    nearest = nearest_interpolation(volume)
    volume.GetShaderProperty().GetFragmentCustomUniforms().SetUniformf("u_mc_nearest", 1.0 if nearest else 0.0)


def ray_uniforms(image, camera, size) -> dict:
    """The global_phase piece's per-pixel ray, in the absolute point-index space of ``image``.

    ``image``: the whole volume's geometry in the world, its volume's matrix
    folded in (:func:`placed`, :func:`whole_geometry`).

    A pixel at NDC (x, y) casts the ray through ``u_mc_rayPoint0 + x *
    u_mc_rayPointX + y * u_mc_rayPointY`` (the points at the NDC depth of
    the box's centre) along ``u_mc_rayDirection`` (parallel projection,
    ``u_mc_rayEye.w`` 0) or away from the eye ``u_mc_rayEye.xyz``
    (perspective, w 1).  The rays start at the whole box, or at VTK's
    near-plane cap where the camera's near plane cuts the box
    (``u_mc_rayCap``: the plane ``n . p = w`` of :func:`near_cap` in point
    indices, all 0 when there is none).  float64 here, the same float32
    uniforms on every rank, so every rank casts the same rays bit for bit.

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> from vtkmodules.vtkRenderingCore import vtkCamera
    >>> image = vtkImageData()
    >>> image.SetExtent(0, 10, 0, 10, 0, 10)
    >>> camera = vtkCamera()
    >>> camera.SetFocalPoint(5, 5, 5); camera.SetPosition(5, 5, 40); camera.ParallelProjectionOn()
    >>> camera.SetParallelScale(8.0)
    >>> rays = ray_uniforms(image, camera, (16, 16))
    >>> [round(v, 6) for v in rays["u_mc_rayPoint0"]], rays["u_mc_rayEye"][3], rays["u_mc_rayCap"]
    ([5.0, 5.0, 5.0], 0.0, [0.0, 0.0, 0.0, 0.0])
    """
    width, height = size
    to_ndc = matrix_array(camera.GetCompositeProjectionTransformMatrix(width / height, -1, 1))
    from_ndc = np.linalg.inv(to_ndc)
    to_index = matrix_array(image.GetPhysicalToIndexMatrix())
    bounds = image.GetBounds()
    centre = np.array([0.5 * (bounds[0] + bounds[1]), 0.5 * (bounds[2] + bounds[3]), 0.5 * (bounds[4] + bounds[5]),
                       1.0])
    centre_ndc = to_ndc @ centre
    depth = centre_ndc[2] / centre_ndc[3]

    def index_at(x, y, z):
        world = from_ndc @ np.array([x, y, z, 1.0])
        return (to_index @ np.append(world[:3] / world[3], 1.0))[:3]

    point = index_at(0.0, 0.0, depth)
    out = {"u_mc_rayPoint0": point, "u_mc_rayPointX": index_at(1.0, 0.0, depth) - point,
           "u_mc_rayPointY": index_at(0.0, 1.0, depth) - point}
    if camera.GetParallelProjection():
        out["u_mc_rayDirection"] = index_at(0.0, 0.0, 1.0) - index_at(0.0, 0.0, -1.0)
        out["u_mc_rayEye"] = np.zeros(4)
    else:
        out["u_mc_rayDirection"] = np.zeros(3)
        out["u_mc_rayEye"] = np.append((to_index @ np.append(camera.GetPosition(), 1.0))[:3], 1.0)
    cap = near_cap(image, camera, width / height)
    out["u_mc_rayCap"] = np.zeros(4) if cap is None else index_plane(cap, image.GetIndexToPhysicalMatrix())
    return {name: [float(v) for v in value] for name, value in out.items()}


def index_plane(cap: Sequence[float], index_to_world) -> np.ndarray:
    """:func:`near_cap`'s world plane ``n . x = c`` in an index space: ``(N, w)`` with ``N . p = w``.

    ``index_to_world``: the vtkMatrix4x4 (or 4x4 array) from the index
    space's points to world coordinates (an image's
    ``GetIndexToPhysicalMatrix``).

    Examples
    --------
    >>> index_plane([0.0, 0.0, 1.0, 3.0], np.diag([1.0, 1.0, 2.0, 1.0])).tolist()   # z = 3 at index k = 1.5
    [0.0, 0.0, 2.0, 3.0]
    """
    matrix = index_to_world if isinstance(index_to_world, np.ndarray) else matrix_array(index_to_world)
    normal = np.asarray(cap[:3], dtype=np.float64)
    return np.append(matrix[:3, :3].T @ normal, float(cap[3]) - normal @ matrix[:3, 3])


def cap_steps(rays: dict, point: np.ndarray, step: np.ndarray) -> np.ndarray:
    """The parameters ``s`` where the rays ``point + s step`` (point indices, (n, 3)) cross ``rays``' cap.

    ``rays``: :func:`ray_uniforms`' values; -inf where there is no cap (or a
    ray runs along it), as ``shaders/global_phase.glsl`` reads it.

    Examples
    --------
    >>> cap_steps({"u_mc_rayCap": [0.0, 0.0, 1.0, 4.0]}, np.zeros((1, 3)), np.array([[0.0, 0.0, 0.5]])).tolist()
    [8.0]
    """
    cap = np.asarray(rays["u_mc_rayCap"], dtype=np.float64)
    along = step @ cap[:3]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(along > 0.0, (cap[3] - point @ cap[:3]) / np.where(along > 0.0, along, 1.0), -np.inf)


def whole_geometry(whole_stub, matrix=None):
    """A scalar-less vtkImageData with the whole volume's geometry, from ``(extent, origin, spacing, direction)``.

    ``direction``: the 3x3 matrix, row-major, nine numbers (or a vtkMatrix3x3);
    ``matrix``: the volume's own matrix (``vtkVolume.GetMatrix()``), which
    places the geometry in the world (:func:`placed`).

    Examples
    --------
    >>> whole_geometry(((0, 9, 0, 4, 0, 2), (0.0, 0.0, 0.0), (1.0, 2.0, 1.0), [1, 0, 0, 0, 1, 0, 0, 0, 1])).GetBounds()
    (0.0, 9.0, 0.0, 8.0, 0.0, 2.0)
    """
    from vtkmodules.vtkCommonDataModel import vtkImageData

    extent, origin, spacing, direction = whole_stub
    image = vtkImageData()
    image.SetExtent(*extent)
    image.SetOrigin(origin)
    image.SetSpacing(spacing)
    image.SetDirectionMatrix(direction)
    return placed(image, matrix)


def whole_of(image, matrix=None):
    """A scalar-less image with the geometry of ``image``'s points (counted from 0), placed by ``matrix`` (:func:`placed`).

    Examples
    --------
    >>> from vtkmodules.vtkCommonDataModel import vtkImageData
    >>> image = vtkImageData()
    >>> image.SetExtent(2, 5, 0, 3, 0, 1)
    >>> whole_of(image, np.diag([2.0, 1.0, 1.0, 1.0])).GetBounds()
    (4.0, 10.0, 0.0, 3.0, 0.0, 1.0)
    """
    dims = image.GetDimensions()  # counted from 0: the first point of the extent is the origin
    return whole_geometry(((0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1), first_point(image), image.GetSpacing(),
                           image.GetDirectionMatrix()), matrix)


def jitter_problem(mapper) -> Optional[str]:
    """Why ``mapper``'s jittered samples cannot be drawn in bricks now, or None.

    VTK's jittering (``SetUseJittering(True)``) starts each ray a fraction of
    a step in (a 64 x 64 blue-noise pattern read at the fragment's window
    position), while a sampling brick takes the whole volume's samples at
    fixed positions (``shaders/global_phase.glsl``; DEMIP's bricks draw
    unjittered), and the CPU's outline and face rays know no pattern: the
    bricked picture would silently be another one (measured, 48^3 in 27
    bricks: mip 76 %, minip 86 %, average 98.8 %, demip 69 % of the pixels
    within 1 grey of the single texture).  Refused while the input exceeds
    the texture limit and the method (a foveated mapper: its layers) samples;
    the cell walks (analytic, analytic_minip, analytic_average) take no
    samples: jittering changes nothing there, they draw.

    Examples
    --------
    >>> from mipcast.mappers.mip import MIPVolumeMapper
    >>> mapper = MIPVolumeMapper(); mapper.SetUseJittering(True)
    >>> jitter_problem(mapper) is None   # no input, no window: nothing to brick
    True
    """
    if not mapper.GetUseJittering():
        return None
    from mipcast.mappers import bricked_draw

    limit = bricked_draw.exceeds_limit(mapper)
    if not limit:
        return None
    if getattr(type(mapper), "BRICKS", None) == "foveated":
        from mipcast.core.parameter_tables import FOVEATION_LAYERS

        if FOVEATION_LAYERS[mapper.GetMethod()].walks_cells:
            return None
    elif "sampled_loop" not in mapper.GetShaderPieces():
        return None
    return (f"jittering (SetUseJittering(True)) cannot be drawn exactly beyond this GPU's 3D texture limit of {limit} "
            f"points per axis: {type(mapper).__name__}'s bricks take the whole volume's samples at fixed positions, "
            "not the single texture's jittered ones; turn jittering off (mapper.SetUseJittering(False)), use a "
            "method that walks cells (analytic, analytic_minip, analytic_average: no samples to jitter), or "
            f"resample the volume to at most {limit} points per axis (e.g. vtkImageResample)")


def push_whole_rays(volume, sample_distance: float, whole, camera, size) -> None:
    """On ``volume``'s shader property: the rays of ``camera`` through the ``whole`` volume and the step.

    For the ``global_phase`` / ``global_cells`` pieces: ``whole`` is the
    whole volume's geometry (:func:`whole_geometry`), ``size`` the viewport's
    (width, height), ``sample_distance`` the world step of the samples.
    """
    uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
    uniforms.SetUniformf("u_mc_rayStep", float(sample_distance))
    set_ray_uniforms(uniforms, ray_uniforms(whole, camera, tuple(size)))
    push_interpolation(volume)


def push_rays(mapper, entry, camera, shape, size=None) -> None:
    """This frame's whole-volume rays and sample distance on a brick of ``mapper``'s input.

    For the brick ``entry`` (:func:`brick_entry`, its volume following the
    user's, matrix included): the rays of ``camera`` over a viewport of
    ``shape`` (rows, columns) in the whole volume's point indices as the
    volume's matrix places it; ``size`` (width, height) gives the camera's
    aspect ratio when it is not ``shape``'s.
    """
    push_whole_rays(entry["volume"], entry["mapper"].GetSampleDistance(),
                    whole_of(mapper.GetInput(), entry["volume"].GetMatrix()), camera,
                    (shape[1], shape[0]) if size is None else size)


def box_in_view(brick_volume, renderer, shape) -> bool:
    """Whether the brick's box may cover a pixel of the viewport (False only when it surely does not).

    The box's 8 corners (through the volume's matrix) in the camera's clip
    coordinates: a box wholly behind the camera, or wholly beyond one side of
    the viewport (with two pixels to spare), covers no pixel.
    """
    bounds = brick_volume.GetMapper().GetInput().GetBounds()
    corners = np.array([[x, y, z, 1.0] for x in bounds[0:2] for y in bounds[2:4] for z in bounds[4:6]])
    matrix = brick_volume.GetMatrix()
    model = np.array([[matrix.GetElement(r, c) for c in range(4)] for r in range(4)])
    camera = renderer.GetActiveCamera()
    projection = camera.GetCompositeProjectionTransformMatrix(renderer.GetTiledAspectRatio(), -1.0, 1.0)
    view = np.array([[projection.GetElement(r, c) for c in range(4)] for r in range(4)])
    clip = corners @ (view @ model).T
    w = clip[:, 3]
    if np.all(w <= 0.0):
        return False
    if np.any(w <= 0.0):
        return True  # the box reaches behind the camera: its projection is unbounded
    ndc = clip[:, :2] / w[:, None]
    spare = 2.0 * 2.0 / np.array([shape[1], shape[0]], dtype=float)
    return not (np.any(np.all(ndc < -1.0 - spare, axis=0)) or np.any(np.all(ndc > 1.0 + spare, axis=0)))


def brick_entry(kind, piece, extent: Sequence[int], whole: Sequence[int], spacing: Sequence[float],
                sample_distance: float) -> dict:
    """A private mapper of class ``kind`` on its own vtkVolume drawing ``piece``, a brick of ``whole``.

    The mapper's state holds ``global_box`` (the whole volume's samples, the
    ``global_phase`` piece) and the volume's uniforms the brick's boxes
    (:func:`set_brick_uniforms`); :func:`ray_uniforms` come at each draw.
    Returns ``{"mapper", "volume", "matrix", "extent"}``.
    """
    from vtkmodules.vtkCommonMath import vtkMatrix4x4
    from vtkmodules.vtkRenderingCore import vtkVolume

    from mipcast.core.object_state import object_state

    mapper = kind()
    mapper.SetInputData(piece)
    volume = vtkVolume()
    mapper.Attach(volume)
    low, high = global_texture_box(extent, whole)
    object_state(mapper)["global_box"] = (low, high)
    uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
    uniforms.SetUniform3f("u_mc_globalTexMin", low)
    uniforms.SetUniform3f("u_mc_globalTexMax", high)
    set_brick_uniforms(uniforms, whole, extent, spacing, sample_distance)
    return {"mapper": mapper, "volume": volume, "matrix": vtkMatrix4x4(), "extent": tuple(extent)}


def cached_bricks(mapper, limit: int, name: str, make) -> list:
    """The mapper's bricks of its input at ``limit`` points per axis, made again when the input or limit changed.

    ``make(piece, extent, whole)`` builds one brick's entry (e.g. with
    :func:`brick_entry`); the entries are kept in the mapper's state under
    ``name``, keyed by the input, its modification time, the limit and the
    mapper's class.
    """
    from mipcast.core.object_state import object_state
    from mipcast.mappers.bricks import brick_extents, extract_brick

    state = object_state(mapper)
    image = mapper._masked_input()  # your input, a mask's hidden points hidden (MIPVolumeMapper.SetMaskInput)
    key = (image.GetAddressAsString("vtkObjectBase"), image.GetMTime(), int(limit), type(mapper))
    cached = state.get(name)
    if cached is not None and cached["key"] == key:
        return cached["entries"]
    dims = image.GetDimensions()
    whole = (0, dims[0] - 1, 0, dims[1] - 1, 0, dims[2] - 1)
    entries = [make(extract_brick(image, extent), extent, whole) for extent in brick_extents(dims, limit)]
    state[name] = {"key": key, "entries": entries}
    return entries


def visibility_order(extents: Sequence[Sequence[int]], rays: dict) -> list:
    """Indices of ``extents`` (bricks of an axis-aligned grid) in a front-to-back order along every ray.

    ``rays`` are :func:`ray_uniforms`' values (point-index space).  Each
    brick owns the cells ``[e0, e1)`` of its extent along each axis.  Along
    an axis, a ray's brick index only moves one way: with the parallel
    direction's sign (orthographic), or away from the eye's brick
    (perspective: the eye's brick index per axis, -1 or n outside the
    grid).  Sorting by the sum over the axes of that signed index (distance
    from the eye's brick) puts every brick after all bricks a ray can cross
    before it.

    Examples
    --------
    >>> bricks = [(0, 4, 0, 0, 0, 0), (4, 8, 0, 0, 0, 0), (8, 12, 0, 0, 0, 0)]
    >>> parallel = {"u_mc_rayDirection": [-1.0, 0.0, 0.0], "u_mc_rayEye": [0.0, 0.0, 0.0, 0.0]}
    >>> visibility_order(bricks, parallel)
    [2, 1, 0]
    >>> visibility_order(bricks, {"u_mc_rayDirection": [0.0] * 3, "u_mc_rayEye": [5.0, 0.0, 0.0, 1.0]})
    [1, 0, 2]
    """
    extents = [tuple(int(v) for v in e) for e in extents]
    eye = rays["u_mc_rayEye"]
    keys = []
    starts = [sorted({e[2 * a] for e in extents}) for a in range(3)]
    for extent in extents:
        key = 0.0
        for a in range(3):
            index = starts[a].index(extent[2 * a])
            if eye[3] > 0.5:  # perspective: distance from the eye's brick along the axis
                inside = [i for i, s in enumerate(starts[a]) if s <= eye[a]]
                eye_index = inside[-1] if inside else -1
                last = max(e[2 * a + 1] for e in extents)
                if eye[a] >= last:
                    eye_index = len(starts[a])
                key += abs(index - eye_index)
            else:
                key += index * float(np.sign(rays["u_mc_rayDirection"][a]))
        keys.append(key)
    return sorted(range(len(extents)), key=lambda i: keys[i])
