"""Tests of the float64 reference renderer and its camera rays."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.ndimage import map_coordinates
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkRenderingCore import vtkCamera

from mipcast.core.camera_rays import box_interval, camera_rays, index_space, matrix_array
from mipcast.reference import render


# ---------------------------------------------------------------- helpers

def make_image(values, spacing=(1, 1, 1), origin=(0, 0, 0), direction=None,
               extent_start=(0, 0, 0)):
    """Image data with point scalars ``values`` indexed [k, j, i]."""
    values = np.asarray(values)
    nz, ny, nx = values.shape
    image = vtkImageData()
    i0, j0, k0 = extent_start
    image.SetExtent(i0, i0 + nx - 1, j0, j0 + ny - 1, k0, k0 + nz - 1)
    image.SetSpacing(*spacing)
    image.SetOrigin(*origin)
    if direction is not None:
        image.SetDirectionMatrix(*np.asarray(direction, float).ravel())
    image.GetPointData().SetScalars(numpy_to_vtk(values.ravel(), deep=True))
    return image


def make_camera(focal, position, up, parallel, angle=30.0, scale=1.0, clip=(0.5, 500.0)):
    camera = vtkCamera()
    camera.SetFocalPoint(*focal)
    camera.SetPosition(*position)
    camera.SetViewUp(*up)
    camera.SetParallelProjection(parallel)
    camera.SetViewAngle(angle)
    camera.SetParallelScale(scale)
    camera.SetClippingRange(*clip)
    return camera


def ray_camera(point, direction, scale=1.0):
    """Orthographic camera whose centre pixel ray runs through ``point`` along ``direction``."""
    direction = np.asarray(direction, float) / np.linalg.norm(direction)
    up = np.eye(3)[np.argmin(np.abs(direction))]
    position = np.asarray(point, float) - 40.0 * direction
    return make_camera(point, position, up, True, scale=scale, clip=(1.0, 100.0))


def matrix(vtk_matrix):
    return np.array([[vtk_matrix.GetElement(r, c) for c in range(4)] for r in range(4)])


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else -q


def random_camera(rng, image, parallel):
    """A camera looking at the volume from a random direction, volume in view."""
    to_world = matrix(image.GetIndexToPhysicalMatrix())
    dims = np.array(image.GetDimensions(), float)
    centre = (to_world @ np.append((dims - 1) / 2, 1.0))[:3]
    radius = 0.5 * np.linalg.norm(to_world[:3, :3] @ (dims - 1))
    view = rng.normal(size=3)
    view /= np.linalg.norm(view)
    focal = centre + rng.normal(scale=0.1 * radius, size=3)
    angle = rng.uniform(25, 45)
    distance = radius / math.tan(math.radians(angle / 2)) * rng.uniform(0.75, 1.0)
    up = np.cross(view, rng.normal(size=3))
    return make_camera(focal, focal - distance * view, up, parallel,
                       angle=angle, scale=radius * rng.uniform(0.5, 0.8),
                       clip=(distance - 1.5 * radius, distance + 1.5 * radius))


def interpolate(volume, position):
    """Independent trilinear interpolation (scipy) at index positions (..., 3)."""
    coords = np.moveaxis(position, -1, 0)[::-1].reshape(3, -1)
    return map_coordinates(volume, coords, order=1, mode="nearest").reshape(position.shape[:-1])


def golden_max(func, a, b, iterations=100):
    """Vectorised golden-section search; returns the best value evaluated."""
    g = (math.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = func(c), func(d)
    best = np.maximum(fc, fd)
    for _ in range(iterations):
        left = fc >= fd
        a, b = np.where(left, a, c), np.where(left, d, b)
        kept, f_kept = np.where(left, c, d), np.where(left, fc, fd)
        new = np.where(left, b - g * (b - a), a + g * (b - a))
        f_new = func(new)
        best = np.maximum(best, f_new)
        c, fc = np.where(left, new, kept), np.where(left, f_new, f_kept)
        d, fd = np.where(left, kept, new), np.where(left, f_kept, f_new)
    return best


def brute_force(volume, rays, density=200):
    """Dense sampling (>= ``density`` samples per voxel of L1 ray length) plus a
    golden-section refinement around every discrete local maximum.

    Returns the per-pixel maximum (NaN on misses) and all dense samples of hit rays.
    """
    hit = rays.hit
    origin, direction = rays.origin[hit], rays.direction[hit]
    t_in, t_out = rays.t_enter[hit], rays.t_exit[hit]
    cells = np.abs(direction).sum(axis=1) * (t_out - t_in)
    count = int(density * (cells.max() + 1)) + 1
    t = t_in[:, None] + (t_out - t_in)[:, None] * np.linspace(0.0, 1.0, count)
    samples = interpolate(volume, origin[:, None] + t[..., None] * direction[:, None])
    padded = np.pad(samples, ((0, 0), (1, 1)), constant_values=-np.inf)
    ray, col = np.nonzero((samples >= padded[:, :-2]) & (samples >= padded[:, 2:]))
    low, high = t[ray, np.maximum(col - 1, 0)], t[ray, np.minimum(col + 1, count - 1)]
    refined = golden_max(lambda s: interpolate(volume, origin[ray] + s[:, None] * direction[ray]),
                         low, high)
    best = samples.max(axis=1)
    np.maximum.at(best, ray, refined)
    out = np.full(hit.shape, np.nan)
    out[hit] = best
    return out, samples


def volume_of(image):
    dims = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(dims[::-1]).astype(float)


RNG_VOLUME = np.random.default_rng(7).random((8, 7, 6))   # nz, ny, nx
PLAIN = make_image(RNG_VOLUME)


# ---------------------------------------------------------------- exact vs brute force

@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("parallel", [True, False])
def test_exact_matches_brute_force(seed, parallel):
    rng = np.random.default_rng(seed)
    shape = tuple(rng.integers(5, 10, size=3))
    values = rng.random(shape)
    image = make_image(values, spacing=rng.uniform(0.5, 2.0, size=3),
                       origin=rng.uniform(-20, 20, size=3),
                       direction=random_rotation(rng) if seed else None)
    camera = random_camera(rng, image, parallel)
    size = (20, 16)
    exact = render(image, camera, size, method="analytic")
    brute, samples = brute_force(values, camera_rays(image, camera, size))
    hit = np.isfinite(brute)
    assert hit.sum() > 100
    assert np.array_equal(np.isfinite(exact), hit)
    data_range = np.ptp(values)
    assert np.max(np.abs(exact[hit] - brute[hit])) <= 1e-9 * data_range
    assert np.all(exact[hit][:, None] >= samples - 1e-12 * data_range)


# ---------------------------------------------------------------- special rays

def exact_centre(image, point, direction):
    camera = ray_camera(point, direction)
    rays = camera_rays(image, camera, (1, 1))
    value = render(image, camera, (1, 1), method="analytic")[0, 0]
    return value, rays


def assert_brute(image, point, direction):
    value, rays = exact_centre(image, point, direction)
    brute, samples = brute_force(volume_of(image), rays)
    assert abs(value - brute[0, 0]) <= 1e-9
    assert value >= samples.max() - 1e-12
    return value, rays


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_axis_parallel_ray(axis):
    point = np.array([2.5, 3.25, 4.5])
    direction = np.eye(3)[axis]
    value, rays = assert_brute(PLAIN, point, direction)
    assert np.abs(rays.direction[0, 0])[np.arange(3) != axis].max() < 1e-12
    # the interpolant is linear between grid planes: the maximum is on a plane
    on_planes = np.tile(point, (PLAIN.GetDimensions()[axis], 1))
    on_planes[:, axis] = np.arange(len(on_planes))
    assert value == pytest.approx(interpolate(RNG_VOLUME, on_planes).max(), abs=1e-12)


@pytest.mark.parametrize("x", [0.0, 3.0, 5.0])
def test_ray_along_cell_face(x):
    point, direction = (x, 2.3, 4.1), (0.0, 0.6, 0.8)
    value, _ = assert_brute(PLAIN, point, direction)
    # only the face's own values matter: change every other slice
    changed = RNG_VOLUME.copy()
    others = np.arange(6) != int(x)
    changed[:, :, others] = np.random.default_rng(3).random(changed[:, :, others].shape)
    other_value, _ = exact_centre(make_image(changed), point, direction)
    assert other_value == pytest.approx(value, abs=1e-12)


def test_ray_along_cell_edge():
    value, _ = assert_brute(PLAIN, (3.0, 4.0, 2.7), (0.0, 0.0, 1.0))
    assert value == pytest.approx(RNG_VOLUME[:, 4, 3].max(), abs=1e-12)


def test_ray_through_grid_lines():
    # in the face x = 3, diagonal in y/z: crosses grid lines at the points (3, k, k)
    value, _ = assert_brute(PLAIN, (3.0, 0.0, 0.0), (0.0, 1.0, 1.0))
    assert value >= max(RNG_VOLUME[k, k, 3] for k in range(7)) - 1e-12


def test_ray_through_grid_corners():
    value, rays = assert_brute(PLAIN, (0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    assert value >= max(RNG_VOLUME[k, k, k] for k in range(6)) - 1e-12
    assert rays.t_exit[0, 0] - rays.t_enter[0, 0] == pytest.approx(5 * math.sqrt(3))


def test_ray_grazing_along_an_edge():
    value, rays = assert_brute(PLAIN, (2.5, 6 - 1e-7, 7 - 1e-7), (1.0, 0.0, 0.0))
    assert rays.hit[0, 0]
    assert value == pytest.approx(RNG_VOLUME[7, 6, :].max(), abs=1e-6)


def test_ray_grazing_across_an_edge():
    # crosses the corner column x = 5, y = 6 a hair inside: a segment ~3e-6 long
    value, rays = assert_brute(PLAIN, (5 - 1e-6, 6 - 1e-6, 3.3), (1.0, -1.0, 0.0))
    assert rays.hit[0, 0]
    assert 0 < rays.t_exit[0, 0] - rays.t_enter[0, 0] < 1e-5
    edge = 0.7 * RNG_VOLUME[3, 6, 5] + 0.3 * RNG_VOLUME[4, 6, 5]
    assert value == pytest.approx(edge, abs=1e-5)


@pytest.mark.parametrize("point, direction", [
    ((-1.0, 3.0, 4.0), (0.0, 0.0, 1.0)),        # parallel, outside
    ((5 + 1e-3, 6.5, 3.0), (0.0, -1.0, 0.0)),   # parallel, just outside a face
    ((7.0, 7.0, 3.0), (1.0, -1.0, 0.2)),        # oblique, past a corner
])
def test_ray_missing_the_box(point, direction):
    value, rays = exact_centre(PLAIN, point, direction)
    assert not rays.hit[0, 0]
    assert np.isnan(value) and np.isnan(rays.t_enter[0, 0]) and np.isnan(rays.t_exit[0, 0])
    assert np.isnan(render(PLAIN, ray_camera(point, direction), (1, 1), sample_distance=0.5)[0, 0])


@pytest.mark.parametrize("miss", [0.0, 1e-11])
def test_ray_touching_one_corner(miss):
    # 1e-11 voxel outside is float64 rounding of the camera matrices: still a touch
    value, rays = exact_centre(PLAIN, (5.0 + miss, 6.0 + miss, 7.0), (1.0, -1.0, 0.5))
    assert rays.hit[0, 0]
    assert abs(rays.t_exit[0, 0] - rays.t_enter[0, 0]) < 1e-6
    assert value == pytest.approx(RNG_VOLUME[7, 6, 5], abs=1e-9)
    value, rays = exact_centre(PLAIN, (5.0 + 1e-6, 6.0 + 1e-6, 7.0), (1.0, -1.0, 0.5))
    assert not rays.hit[0, 0] and np.isnan(value)


# ---------------------------------------------------------------- known answers

@pytest.mark.parametrize("parallel", [True, False])
def test_linear_field_maximum_at_an_end(parallel):
    rng = np.random.default_rng(11)
    coef = np.array([0.7, -1.3, 0.4])
    k, j, i = np.mgrid[0:7, 0:6, 0:9].astype(float)
    values = coef[0] * i + coef[1] * j + coef[2] * k + 5.0
    image = make_image(values, spacing=(0.8, 1.2, 1.5), origin=(3, -2, 1),
                       direction=random_rotation(rng))
    camera = random_camera(rng, image, parallel)
    rays = camera_rays(image, camera, (17, 13))
    ends = [rays.origin + t[..., None] * rays.direction for t in (rays.t_enter, rays.t_exit)]
    expected = np.maximum(*(e @ coef + 5.0 for e in ends))
    exact = render(image, camera, (17, 13), method="analytic")
    assert np.isfinite(exact).sum() > 50
    np.testing.assert_allclose(exact, expected, rtol=0, atol=1e-12 * np.ptp(values))


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.float32])
def test_single_bright_voxel(dtype):
    values = np.zeros((7, 7, 7), dtype=dtype)
    values[3, 4, 2] = 100
    image = make_image(values)
    # rays along z on a grid of 0.25 voxel around the bright point (2, 4)
    camera = make_camera((2, 4, 3), (2, 4, 30), (0, 1, 0), True, scale=0.75 * 7 / 6)
    exact = render(image, camera, (7, 7), method="analytic")
    offset = np.linspace(-0.75, 0.75, 7)
    dx, dy = np.meshgrid(offset, offset[::-1])
    expected = 100 * np.clip(1 - np.abs(dx), 0, 1) * np.clip(1 - np.abs(dy), 0, 1)
    np.testing.assert_allclose(exact, expected, atol=1e-12)
    assert exact[3, 3] == pytest.approx(100.0, abs=1e-12)
    # an oblique ray through the point also reaches the voxel value exactly
    value, _ = exact_centre(image, (2.0, 4.0, 3.0), (1.0, 2.0, 3.0))
    assert value == pytest.approx(100.0, abs=1e-12)


# ---------------------------------------------------------------- sampled MIP

def slow_mip(volume, rays, step):
    """Per-ray Python loop: VTK's sample positions, clamp, explicit trilinear."""
    nz, ny, nx = volume.shape
    top = np.array([nx - 1, ny - 1, nz - 1], float)
    out = np.full(rays.hit.shape, np.nan)
    for r, c in zip(*np.nonzero(rays.hit)):
        t_in, t_out = rays.t_enter[r, c], rays.t_exit[r, c]
        best = -math.inf
        for n in range(1, max(1, math.floor((t_out - t_in) / step + 1e-9)) + 1):
            position = rays.origin[r, c] + (t_in + n * step) * rays.direction[r, c]
            x, y, z = np.minimum(np.maximum(position, 0), top)
            i, j, k = min(int(x), nx - 2), min(int(y), ny - 2), min(int(z), nz - 2)
            fx, fy, fz = x - i, y - j, z - k
            value = sum(volume[k + b, j + a, i + e] * (fx if e else 1 - fx) * (fy if a else 1 - fy)
                        * (fz if b else 1 - fz) for e in (0, 1) for a in (0, 1) for b in (0, 1))
            best = max(best, value)
        out[r, c] = best
    return out


@pytest.mark.parametrize("parallel", [True, False])
def test_mip_matches_slow_loop(parallel):
    rng = np.random.default_rng(5)
    values = rng.random((6, 5, 7)) * 300 - 100
    image = make_image(values, spacing=(1.3, 0.8, 1.1), origin=(-4, 2, 9),
                       direction=random_rotation(rng))
    camera = random_camera(rng, image, parallel)
    for step in (0.7, 0.23):
        mip = render(image, camera, (9, 8), method="mip", sample_distance=step)
        slow = slow_mip(values, camera_rays(image, camera, (9, 8)), step)
        assert np.isfinite(slow).sum() > 20
        np.testing.assert_allclose(mip, slow, rtol=0, atol=1e-12 * np.ptp(values))


def test_mip_last_sample_on_exit_face():
    values = np.zeros((8, 5, 5))
    values[-1] = 1.0                       # bright only at the exit face z = 7 * 0.1
    image = make_image(values, spacing=(1, 1, 0.1))
    camera = ray_camera((2.0, 2.0, 0.35), (0, 0, 1))
    rays = camera_rays(image, camera, (1, 1))
    length = rays.t_exit[0, 0] - rays.t_enter[0, 0]
    assert length == pytest.approx(0.7)
    for count in range(3, 30):             # length / step is count up to rounding
        mip = render(image, camera, (1, 1), sample_distance=length / count)
        assert mip[0, 0] == pytest.approx(1.0, abs=1e-9)
    assert render(image, camera, (1, 1), sample_distance=length / 3.5)[0, 0] < 0.6


@pytest.mark.parametrize("parallel", [True, False])
def test_mip_below_exact_and_converging(parallel):
    rng = np.random.default_rng(9)
    values = rng.random((9, 8, 10))
    image = make_image(values, spacing=(1.0, 1.4, 0.7), origin=(1, 2, 3),
                       direction=random_rotation(rng))
    camera = random_camera(rng, image, parallel)
    exact = render(image, camera, (24, 20), method="analytic")
    rays = camera_rays(image, camera, (24, 20))
    hit = np.isfinite(exact)
    errors = []
    for step in (0.8, 0.08, 0.008):
        mip = render(image, camera, (24, 20), method="mip", sample_distance=step)
        assert np.array_equal(np.isfinite(mip), hit)
        # VTK always takes one sample; on a ray shorter than a step it lies
        # beyond the exit and is clamped to the box, i.e. off the ray
        on_ray = hit & (rays.t_exit - rays.t_enter >= step)
        assert np.all(mip[on_ray] <= exact[on_ray] + 1e-12)
        errors.append(np.max(np.abs(exact[hit] - mip[hit])))
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 0.02


# ---------------------------------------------------------------- camera rays

def test_orthographic_rays_by_hand():
    image = make_image(np.zeros((7, 6, 5)), spacing=(2, 1, 0.5), origin=(10, 20, 30))
    camera = make_camera((14, 22.5, 31.5), (14, 22.5, 131.5), (0, 1, 0), True,
                         scale=4.5, clip=(50, 150))
    rays = camera_rays(image, camera, (4, 3))
    world_x = np.array([9.5, 12.5, 15.5, 18.5])
    world_y = np.array([25.5, 22.5, 19.5])                      # top row first
    np.testing.assert_allclose(rays.origin[..., 0], np.tile((world_x - 10) / 2, (3, 1)), atol=1e-12)
    np.testing.assert_allclose(rays.origin[..., 1], np.tile(world_y[:, None] - 20, (1, 4)),
                               atol=1e-12)
    np.testing.assert_allclose(rays.origin[..., 2], (81.5 - 30) / 0.5, atol=1e-10)
    np.testing.assert_allclose(rays.direction, np.broadcast_to([0, 0, -2.0], (3, 4, 3)), atol=1e-14)
    expected_hit = np.zeros((3, 4), bool)
    expected_hit[1, 1:3] = True
    assert np.array_equal(rays.hit, expected_hit)
    np.testing.assert_allclose(rays.t_enter[expected_hit], 48.5, atol=1e-10)
    np.testing.assert_allclose(rays.t_exit[expected_hit], 51.5, atol=1e-10)
    assert np.isnan(rays.t_enter[~expected_hit]).all()


def test_perspective_rays():
    rng = np.random.default_rng(4)
    image = make_image(np.zeros((4, 4, 4)), spacing=(0.5, 2, 1), origin=(1, 2, 3),
                       direction=random_rotation(rng))
    position, focal = np.array([3.0, 4.0, 40.0]), np.array([3.5, 2.0, 5.0])
    camera = make_camera(focal, position, (0, 1, 0), False, angle=40, clip=(10, 100))
    rays = camera_rays(image, camera, (5, 5))
    to_world = matrix(image.GetIndexToPhysicalMatrix())[:3, :3]
    world_dir = rays.direction @ to_world.T
    np.testing.assert_allclose(np.linalg.norm(world_dir, axis=-1), 1.0, atol=1e-12)
    axis = (focal - position) / np.linalg.norm(focal - position)
    np.testing.assert_allclose(world_dir[2, 2], axis, atol=1e-12)
    world_origin = matrix(image.GetIndexToPhysicalMatrix()) @ np.append(rays.origin[2, 2], 1)
    np.testing.assert_allclose(world_origin[:3], position + 10 * axis, atol=1e-10)
    # top-centre pixel: NDC y = 0.8, so tan(angle off axis) = 0.8 tan(20 deg)
    angle = math.acos(np.clip(world_dir[0, 2] @ axis, -1, 1))
    assert math.tan(angle) == pytest.approx(0.8 * math.tan(math.radians(20)), rel=1e-9)


def test_rays_clipped_by_near_and_far_planes():
    camera = ray_camera((2.5, 3.0, 3.5), (0, 0, -1))
    camera.SetClippingRange(40.0, 42.0)          # near plane through the focal point
    rays = camera_rays(PLAIN, camera, (1, 1))
    # the near plane cuts the box: VTK starts the ray at its cap, 0.001 of the clipping range further
    assert rays.t_enter[0, 0] == pytest.approx(0.002, abs=1e-12)
    np.testing.assert_allclose(rays.origin[0, 0], (2.5, 3.0, 3.5), atol=1e-12)
    assert rays.t_exit[0, 0] == pytest.approx(2.0)
    value = render(PLAIN, camera, (1, 1), method="analytic")[0, 0]
    # z runs from the cap, 3.498, down to 1.5 only: candidates are both ends and the planes between
    candidates = [(2.5, 3.0, z) for z in (1.5, 2.0, 3.0, 3.498)]
    assert value == pytest.approx(interpolate(RNG_VOLUME, np.array(candidates)).max(), abs=1e-12)


def test_rows_top_first_columns_left_to_right():
    values = np.zeros((12, 12, 12))
    values[5:7, 9:11, 8:11] = 1.0             # high y (world up), high x (world right)
    image = make_image(values)
    camera = make_camera((5.5, 5.5, 5.5), (5.5, 5.5, 40), (0, 1, 0), True, scale=6.0)
    exact = render(image, camera, (12, 12), method="analytic")
    rows, cols = np.nonzero(exact > 0.5)
    assert rows.max() < 6 and cols.min() > 6


def test_extent_start_does_not_move_the_volume():
    spacing, origin, start = np.array([1.2, 0.7, 1.0]), np.array([3.0, -1.0, 2.0]), (2, 5, 1)
    shifted = make_image(RNG_VOLUME, spacing=spacing, origin=origin - spacing * start,
                         extent_start=start)
    camera = random_camera(np.random.default_rng(2), PLAIN, False)
    plain = make_image(RNG_VOLUME, spacing=spacing, origin=origin)
    np.testing.assert_allclose(render(shifted, camera, (10, 10), method="analytic"),
                               render(plain, camera, (10, 10), method="analytic"), atol=1e-12)


def test_matrix_array_rows_and_columns():
    from vtkmodules.vtkCommonMath import vtkMatrix3x3, vtkMatrix4x4

    for vtk_class, size in ((vtkMatrix4x4, 4), (vtkMatrix3x3, 3)):
        vtk_matrix = vtk_class()
        expected = np.arange(size * size, dtype=float).reshape(size, size) / 7.0
        for r in range(size):
            for c in range(size):
                vtk_matrix.SetElement(r, c, expected[r, c])
        array = matrix_array(vtk_matrix)
        assert array.dtype == np.float64 and np.array_equal(array, expected)
        array[0, 0] = -1.0  # a copy
        assert vtk_matrix.GetElement(0, 0) == 0.0
    with pytest.raises(TypeError, match="vtkMatrix4x4 or vtkMatrix3x3"):
        matrix_array(np.eye(4))


def test_index_space_counts_from_the_extent_start():
    rotation = random_rotation(np.random.default_rng(4))
    image = make_image(RNG_VOLUME, spacing=(1.2, 0.7, 1.5), origin=(3.0, -1.0, 2.0), direction=rotation,
                       extent_start=(2, 5, 1))
    to_index, upper = index_space(image)
    point = [0.0, 0.0, 0.0]
    image.TransformContinuousIndexToPhysicalPoint(3.25, 6.5, 2.0, point)
    np.testing.assert_allclose(to_index @ np.append(point, 1.0), [1.25, 1.5, 1.0, 1.0], atol=1e-12)
    assert upper.tolist() == [float(n - 1) for n in image.GetDimensions()]


def test_box_interval_parallel_rays_inside_or_outside():
    origin = np.array([[0.5, 0.0, 0.5], [0.5, 1.0, 0.5], [0.5, 1.5, 0.5]])
    t_near, t_far = box_interval(origin, np.array([1.0, 0.0, 0.0]), np.ones(3))
    assert t_near.tolist() == [-0.5, -0.5, np.inf] and t_far.tolist() == [0.5, 0.5, -np.inf]
    t_near, t_far = box_interval(origin[2:], np.array([1.0, 0.0, 0.0]), np.ones(3), margin=0.5)
    assert (t_near.tolist(), t_far.tolist()) == ([-1.0], [1.0])


# ---------------------------------------------------------------- bad input

def test_bad_input_raises():
    camera = ray_camera((2.0, 3.0, 4.0), (0, 0, 1))
    with pytest.raises(TypeError):
        render("not an image", camera, (4, 4), method="analytic")
    two = make_image(RNG_VOLUME)
    two.GetPointData().SetScalars(numpy_to_vtk(np.zeros((RNG_VOLUME.size, 2)), deep=True))
    with pytest.raises(ValueError, match="component 2"):
        render(two, camera, (4, 4), method="analytic", component=2)
    nan = np.full_like(RNG_VOLUME, np.nan)
    with pytest.raises(ValueError, match="NaN"):
        render(make_image(nan), camera, (4, 4), method="analytic")
    with pytest.raises(ValueError, match="at least 2 points"):
        render(make_image(RNG_VOLUME[:1]), camera, (4, 4), method="analytic")
    with pytest.raises(ValueError, match="'analytic'"):
        render(PLAIN, camera, (4, 4), method="cubic")
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match="sample_distance"):
            render(PLAIN, camera, (4, 4), method="mip", sample_distance=bad)
    with pytest.raises(TypeError, match="sample_distance"):
        render(PLAIN, camera, (4, 4), method="mip")
    with pytest.raises(TypeError, match="sample_distance"):
        render(PLAIN, camera, (4, 4), method="analytic", sample_distance=1.0)
    with pytest.raises(TypeError, match="jitter"):
        render(PLAIN, camera, (4, 4), sample_distance=1.0, jitter=True)
    for size in ((0, 4), (4, -1), (2.5, 4)):
        with pytest.raises(ValueError, match="size"):
            render(PLAIN, camera, size, method="analytic")
    for size in ("ab", 4, (1, 2, 3)):
        with pytest.raises(TypeError, match="size"):
            render(PLAIN, camera, size, method="analytic")


def test_inputs_unchanged():
    image = make_image(RNG_VOLUME, spacing=(1, 2, 0.5), origin=(1, 2, 3))
    scalars = vtk_to_numpy(image.GetPointData().GetScalars()).copy()
    camera = random_camera(np.random.default_rng(8), image, False)
    state = [camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
             camera.GetClippingRange(), camera.GetViewAngle(), camera.GetParallelProjection()]
    geometry = [image.GetOrigin(), image.GetSpacing(), image.GetExtent()]
    render(image, camera, (8, 8), method="analytic")
    render(image, camera, (8, 8), method="mip", sample_distance=0.5)
    assert np.array_equal(vtk_to_numpy(image.GetPointData().GetScalars()), scalars)
    assert state == [camera.GetPosition(), camera.GetFocalPoint(), camera.GetViewUp(),
                     camera.GetClippingRange(), camera.GetViewAngle(),
                     camera.GetParallelProjection()]
    assert geometry == [image.GetOrigin(), image.GetSpacing(), image.GetExtent()]
