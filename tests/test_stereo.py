"""Stereo pairs: per-eye parallax as the camera predicts, anaglyph channels from the right eyes, every method."""
import numpy as np
import pytest

from mipcast import METHODS
from mipcast.data_fixtures import make_fixture
from mipcast.mappers.stereo import eye_projection, predicted_disparity, set_stereo
from mipcast.offscreen import OffscreenView

SIZE = (96, 64)
EYE_ANGLE = 8.0


def _view(image, method="mip", window=None):
    view = OffscreenView(image, method, size=SIZE, view="front", window=window)
    view.camera.SetParallelProjection(False)
    view.renderer.ResetCamera()
    view.camera.Zoom(1.6)
    view.renderer.ResetCameraClippingRange()
    return view


def _eye(view, eye):
    set_stereo(view.render_window, eye, EYE_ANGLE, view.camera)
    return view.screenshot()


def _as_eye(camera, side):
    """Make mono ``camera`` (its EyeAngle set) the camera of one eye, in place: moved sideways to the eye's
    centre of projection, its off-axis (sheared) projection explicit."""
    from vtkmodules.vtkCommonMath import vtkMatrix4x4

    from mipcast.core.camera_rays import matrix_array
    from mipcast.mappers.stereo import eye_position

    projection = eye_projection(camera, SIZE[0] / SIZE[1], side)
    move = eye_position(camera, side) - np.array(camera.GetPosition())
    shift = np.eye(4)
    shift[:3, 3] = matrix_array(camera.GetViewTransformMatrix())[:3, :3] @ move  # the move in eye coordinates
    matrix = vtkMatrix4x4()
    matrix.DeepCopy((projection @ shift).ravel().tolist())
    camera.SetPosition(*(np.array(camera.GetPosition()) + move))
    camera.SetFocalPoint(*(np.array(camera.GetFocalPoint()) + move))
    camera.SetExplicitProjectionTransformMatrix(matrix)
    camera.UseExplicitProjectionTransformMatrixOn()


def _ball_centres(picture):
    """x centroids (pixels, left to right) of the two bright blobs, split at the image's middle gap."""
    grey = picture.max(axis=-1).astype(float)
    grey[grey < 128] = 0
    columns = np.nonzero(grey.sum(axis=0))[0]
    gap = np.argmax(np.diff(columns))
    centres = []
    for part in (columns[:gap + 1], columns[gap + 1:]):
        block = grey[:, part[0]:part[-1] + 1]
        centres.append(part[0] + 0.5 + float((block.sum(axis=0) * np.arange(block.shape[1])).sum() / block.sum()))
    return centres


@pytest.fixture(scope="module")
def frontback():
    return make_fixture("frontback", size=32)


def test_the_eyes_differ_by_the_parallax_the_camera_predicts(frontback):
    view = _view(frontback)
    left, right = _eye(view, "left"), _eye(view, "right")
    n = 32
    centres = [(round(0.35 * n), n // 2, round(0.25 * n)), (round(0.65 * n), n // 2, round(0.75 * n))]
    origin, spacing = np.array(frontback.GetOrigin()), np.array(frontback.GetSpacing())
    world = [origin + spacing * np.array(c) for c in centres]
    predicted = [predicted_disparity(view.camera, SIZE[0] / SIZE[1], p, SIZE) for p in world]
    measured = list(np.subtract(_ball_centres(right), _ball_centres(left)))
    # the low-x ball is left in the image; one ball is nearer than the focal point, one farther
    assert predicted[0] * predicted[1] < 0 and min(abs(d) for d in predicted) > 1.5
    assert np.allclose(measured, predicted, atol=0.6), (measured, predicted)


def test_anaglyph_takes_red_from_the_left_eye_and_cyan_from_the_right(frontback):
    view = _view(frontback)
    left, right = _eye(view, "left"), _eye(view, "right")
    anaglyph = _eye(view, "anaglyph").astype(float)
    assert np.abs(left.astype(int) - right).max() > 100, "the eyes must differ"
    # each anaglyph channel is a function of one eye's grey alone (VTK's colour mapping of a grey)
    for channel, eye in ((anaglyph[..., 0], left[..., 0]), (anaglyph[..., 1], right[..., 1]),
                         (anaglyph[..., 2], right[..., 2])):
        for grey in np.unique(eye):
            values = channel[eye == grey]
            assert values.max() - values.min() <= 1, (grey, values.min(), values.max())
    only_left = (left.max(axis=-1) > 150) & (right.max(axis=-1) == 0)
    only_right = (right.max(axis=-1) > 150) & (left.max(axis=-1) == 0)
    assert only_left.any() and only_right.any()
    assert anaglyph[only_left][:, 0].min() > 100 and anaglyph[only_left][:, 1:].max() == 0
    assert anaglyph[only_right][:, 0].max() == 0 and anaglyph[only_right][:, 1:].min() > 100


def test_side_by_side_puts_each_eye_in_its_half(frontback):
    view = _view(frontback)
    pair = _eye(view, "side-by-side")
    half = SIZE[0] // 2
    assert pair[:, :half].max() > 200 and pair[:, half:].max() > 200
    set_stereo(view.render_window, None)
    assert view.screenshot().max() > 200


# VTK's own mappers (stock, cpu and their blend modes) aim every ray from the centre camera: mipcast's only
@pytest.mark.parametrize("method", [name for name, m in METHODS.items() if m.float_readout])
def test_each_eye_is_the_method_seen_through_that_eye(frontback, method):
    """An eye's image equals a mono render from that eye's centre of projection (the camera moved
    sideways, the off-axis frustum explicit): rays, depth normalisation etc. are per eye."""
    if METHODS[method].projection != "mip":  # MinIP and average: dark balls in a bright box
        from mipcast.data_fixtures import image_from_array
        from vtkmodules.util.numpy_support import vtk_to_numpy

        values = vtk_to_numpy(frontback.GetPointData().GetScalars()).reshape(32, 32, 32)
        frontback = image_from_array(1.0 - values)
    stereo = _view(frontback, method, window=(0.0, 1.0))
    eye = _eye(stereo, "left")
    mono = _view(frontback, method, window=(0.0, 1.0))
    mono.camera.SetEyeAngle(EYE_ANGLE)
    _as_eye(mono.camera, "left")
    reference = mono.screenshot()
    assert reference.max() > 100
    error = np.abs(reference.astype(int) - eye).max(axis=-1)
    assert np.mean(error <= 1) >= 0.995, (np.mean(error <= 1), error.max())


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_an_eye_inside_the_volume_sees_its_rays_against_the_reference(frontback, method):
    """A stereo fly-through: each eye's float readout against the float64 reference on that eye's own rays (the
    eye camera: moved sideways, its off-axis projection explicit). Perspective eyes aim along the pixel's line
    through their sheared frustum (shaders/perspective_ray_direction.glsl) since 2026-12-05; from the eye's
    position (stereo_ray_direction) the near-plane cap's float32 rounding was ~1e-4 of the range off."""
    from vtkmodules.vtkRenderingCore import vtkCamera

    view = _view(frontback, method, window=(0.0, 1.0))
    camera = view.camera
    camera.Dolly(camera.GetDistance() / 6.0)  # the eye 6 units from the centre of a 32-unit box
    view.renderer.ResetCameraClippingRange()
    mono = vtkCamera()
    mono.DeepCopy(camera)
    mono.SetEyeAngle(EYE_ANGLE)
    for side in ("left", "right"):
        set_stereo(view.render_window, side, EYE_ANGLE, camera)
        found = view.float_image()
        eye = vtkCamera()  # the eye's camera, mono
        eye.DeepCopy(mono)
        _as_eye(eye, side)
        settings = {} if METHODS[method].walks_cells else {"sample_distance": view.sample_distance}
        expected = METHODS[method].reference(frontback, eye, SIZE, window=(0.0, 1.0), **settings)
        both = np.isfinite(found) & np.isfinite(expected)
        assert both.sum() > 1000 and np.mean(np.isnan(found) == np.isnan(expected)) >= 0.99
        assert np.abs(found[both] - expected[both]).max() <= 2e-5, (side, np.abs(found[both] - expected[both]).max())
