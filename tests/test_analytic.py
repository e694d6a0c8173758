"""Analytic MIP on the GPU against the float64 exact reference, on the same rays."""
import numpy as np
import pytest

from mipcast import reference
from mipcast.data_fixtures import head_ct_path, image_from_array, load_head_ct, make_fixture
from mipcast.core.metrics import silhouette
from mipcast.offscreen import OffscreenView

SIZE = (96, 80)


def _image(values, spacing=(1.0, 1.0, 1.0), direction=None):
    return image_from_array(np.asarray(values, np.float32), spacing=spacing, direction=direction)


def _compare(image, view="oblique", size=SIZE, camera=None):
    """GPU float readout and 8-bit picture vs the exact reference: error shares."""
    gpu = OffscreenView(image, "analytic", size=size, view=view, window="full")
    if camera is not None:
        camera(gpu.camera)
        gpu.renderer.ResetCameraClippingRange()
    values = gpu.float_image()
    picture = gpu.screenshot()
    exact = reference.render(image, gpu.camera, size, method="analytic")
    low, high = gpu.window
    misses = np.isnan(exact)
    # Hit masks agree except where a pixel centre lies on the box outline
    # (rasterisation rules and rounding decide there).
    disagree = np.isnan(values) != misses
    outline = silhouette(exact) | silhouette(values)
    assert not np.any(disagree & ~outline), "hit masks differ inside the silhouette"
    hits = ~misses & ~np.isnan(values)
    assert hits.mean() > 0.02, "the volume is (nearly) off screen"
    error = np.abs(values[hits] - exact[hits]) / (high - low)
    expected8 = np.round(255 * np.clip((exact[hits] - low) / (high - low), 0, 1))
    grey_error = np.abs(picture[..., 0][hits].astype(float) - expected8)
    return {"float_ok": float(np.mean(error <= 1e-3)), "float_max": float(error.max()),
            "grey_ok": float(np.mean(grey_error <= 1)), "brightest": int(picture.max()),
            "silhouette_disagreement": int(disagree.sum())}


def _assert_exact(result):
    assert result["float_ok"] >= 0.999, result
    assert result["grey_ok"] >= 0.995, result


@pytest.mark.parametrize("fixture", ["vessels", "spheres", "noise"])
@pytest.mark.parametrize("view", ["oblique", "perspective"])
def test_fixtures_match_exact_reference(fixture, view):
    result = _compare(make_fixture(fixture, size=48), view)
    _assert_exact(result)
    assert result["brightest"] > 200 and result["silhouette_disagreement"] == 0


def test_sampled_mip_is_not_exact_on_vessels():
    # the point of the method: the same check fails for stock-equivalent sampling
    image = make_fixture("vessels", size=48)
    gpu = OffscreenView(image, "mip", size=SIZE)
    values = gpu.float_image()
    exact = reference.render(image, gpu.camera, SIZE, method="analytic")
    hits = ~np.isnan(exact)
    assert np.mean(np.abs(values[hits] - exact[hits]) <= 1e-3) < 0.9


def test_linear_data_has_its_maximum_at_an_end():
    k, j, i = np.mgrid[0:12, 0:10, 0:14].astype(float)
    _assert_exact(_compare(_image(0.5 * i + 0.2 * j - 0.3 * k), "perspective"))


def test_rays_along_voxel_planes_and_through_grid_corners():
    rng = np.random.default_rng(7)
    image = _image(rng.random((17, 17, 17)))

    def on_grid_lines(camera):  # pixel centres exactly on integer and half-integer x, y
        camera.SetFocalPoint(8.0, 8.0, 8.0)
        camera.SetPosition(8.0, 8.0, 60.0)
        camera.SetViewUp(0.0, 1.0, 0.0)
        camera.SetParallelProjection(True)
        camera.SetParallelScale(33 * 0.5 / 2)

    _assert_exact(_compare(image, size=(33, 33), camera=on_grid_lines))

    def diagonal(camera):  # along (1, 1, 1): rays cross cells through edges and corners
        camera.SetFocalPoint(8.0, 8.0, 8.0)
        camera.SetPosition(48.0, 48.0, 48.0)
        camera.SetViewUp(0.0, 0.0, 1.0)
        camera.SetParallelProjection(True)
        camera.SetParallelScale(14.0)

    _assert_exact(_compare(image, size=(64, 64), camera=diagonal))


def test_grazing_rays_at_the_silhouette():
    rng = np.random.default_rng(8)
    image = _image(rng.random((9, 9, 9)))

    def edge_on(camera):  # the box edge runs through the middle of the image
        camera.SetFocalPoint(8.0, 8.0, 4.0)
        camera.SetPosition(8.0 + 40.0, 8.0 + 40.0, 4.0)
        camera.SetViewUp(0.0, 0.0, 1.0)
        camera.SetParallelProjection(True)
        camera.SetParallelScale(6.0)

    _assert_exact(_compare(image, size=(64, 64), camera=edge_on))


@pytest.mark.parametrize("spacing", [(1.0, 1.0, 20.0), (0.1, 2.0, 1.0)])
def test_anisotropic_spacing_up_to_1_to_20(spacing):
    rng = np.random.default_rng(9)
    _assert_exact(_compare(_image(rng.random((10, 12, 14)) ** 4, spacing=spacing), "perspective"))


def test_rotated_direction_matrix():
    c, s = np.cos(0.6), np.sin(0.6)
    rotation = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]) @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    values = np.random.default_rng(1).random((20, 16, 24))
    _assert_exact(_compare(_image(values, direction=rotation), "oblique"))


@pytest.mark.parametrize("shape", [(2, 24, 24), (2, 2, 2), (24, 2, 2)])
def test_thin_and_tiny_volumes(shape):
    rng = np.random.default_rng(10)
    _assert_exact(_compare(_image(rng.random(shape)), "perspective"))


@pytest.mark.slow
@pytest.mark.skipif(head_ct_path() is None, reason="head CT absent: apt-get install invesalius-examples")
@pytest.mark.parametrize("view", ["oblique", "perspective"])
def test_head_ct_matches_exact_reference(view):
    _assert_exact(_compare(load_head_ct(), view, size=(128, 128)))


@pytest.mark.parametrize("window, background_black", [((0.3, 0.9), True), ((0.05, 0.5), False)])
def test_windowed_display_skips_blocks_and_stays_exact(window, background_black):
    # a window above the background turns on block skipping and the floor and
    # ceiling shortcuts; the float readout (exact) and the picture must both hold
    image = make_fixture("vessels", size=48)
    gpu = OffscreenView(image, "analytic", size=SIZE, window=window)
    assert "amip_loop_blocks" in gpu.mapper.GetShaderPieces()
    values = gpu.float_image()
    picture = gpu.screenshot()
    exact = reference.render(image, gpu.camera, SIZE, method="analytic")
    hits = ~np.isnan(exact)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    assert np.mean(np.abs(values[hits] - exact[hits]) <= 1e-3 * (high - low)) >= 0.999
    expected8 = np.round(255 * np.clip((exact[hits] - window[0]) / (window[1] - window[0]), 0, 1))
    grey_error = np.abs(picture[..., 0][hits].astype(float) - expected8)
    assert picture.max() == 255
    assert (np.mean(picture[..., 0][hits] == 0) > 0.3) == background_black
    assert np.mean(grey_error <= 1) >= 0.995


def test_volumes_beyond_one_texture_are_drawn_in_bricks_and_partitions_refused():
    from mipcast.core.object_state import object_state

    view = OffscreenView(make_fixture("spheres", size=40), "analytic", size=(48, 48))
    one = view.screenshot()
    assert one.max() > 100
    assert view.mapper._texture_limit() >= 256  # queried from the real GL context
    object_state(view.mapper)["texture_limit"] = 32  # pretend a small GPU: 2 x 2 x 2 bricks
    assert view.mapper.GetRenderProblem() is None
    bricked = view.screenshot()
    assert view.mapper.GetNumberOfBricks() == 8
    assert np.abs(bricked.astype(int) - one).max() <= 1
    object_state(view.mapper)["texture_limit"] = 2048
    view.mapper.SetPartitions(2, 1, 1)
    assert "SetPartitions" in view.mapper.GetRenderProblem()
    assert view.screenshot().max() == 0
    view.mapper.SetPartitions(1, 1, 1)
    assert view.screenshot().max() > 100
    assert view.mapper.GetNumberOfBricks() == 0
    for bad in ((0, 1, 1), (float("inf"), 1, 1), (1.5, 1, 1), (True, 1, 1)):  # inf was an OverflowError, 0 wrapped
        with pytest.raises(ValueError, match="three integers >= 1"):
            view.mapper.SetPartitions(*bad)
    assert view.screenshot().max() > 100  # the refused call changed nothing


@pytest.mark.parametrize("window", [None, (0.3, 0.9)])
def test_packed_corners_draw_the_same_pixels_as_eight_fetches(window):
    # packing only changes where the corner values come from: pixels and
    # float readout are identical, the user's image is untouched
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

    from mipcast.mappers.amip_stats import work_per_ray

    rng = np.random.default_rng(5)
    values = (rng.random((20, 28, 24)) ** 4 * 3000 - 1000).astype(np.int16)
    image = image_from_array(values, spacing=(0.8, 1.0, 2.0))
    before = vtk_to_numpy(image.GetPointData().GetScalars()).copy()
    stamp = image.GetMTime()
    low, high = image.GetPointData().GetScalars().GetRange(0)
    shown = None if window is None else (low + window[0] * (high - low), low + window[1] * (high - low))
    results = {}
    for packed in (True, False):
        view = OffscreenView(image, "analytic", size=SIZE, window=shown)
        view.mapper.SetPackedCorners(packed)
        results[packed] = (view.screenshot(), view.float_image(), work_per_ray(view)["texel_fetches"])
        assert view.mapper.GetInput() is image
        drawn = vtkOpenGLGPUVolumeRayCastMapper.GetInput(view.mapper)  # what VTK uploads
        assert drawn.GetPointData().GetScalars().GetNumberOfComponents() == (4 if packed else 1)
        assert drawn.GetDimensions() == image.GetDimensions()
    assert np.array_equal(results[True][0], results[False][0])
    assert np.array_equal(results[True][1], results[False][1], equal_nan=True)
    assert results[True][2] < 0.5 * results[False][2]  # 2 fetches per cell instead of 8
    assert np.array_equal(vtk_to_numpy(image.GetPointData().GetScalars()), before)
    assert image.GetMTime() == stamp


def test_packed_corners_of_a_non_standard_array_layout():
    """VTK's one-buffer-per-component (SOA) arrays pack like plain ones (the packed copy is a standard array)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkSOADataArrayTemplate

    plain = make_fixture("vessels", size=24)
    values = (vtk_to_numpy(plain.GetPointData().GetScalars()) * 1000).astype(np.int16)
    soa = vtkSOADataArrayTemplate["int16"]()
    soa.SetNumberOfComponents(1)
    soa.SetNumberOfTuples(values.size)
    for index, value in enumerate(values.tolist()):
        soa.SetValue(index, value)
    soa.SetName("values")
    pictures = []
    for array in (soa, None):
        image = image_from_array(values.reshape(24, 24, 24))  # int16, standard layout
        if array is not None:
            image.GetPointData().SetScalars(array)
        pictures.append(OffscreenView(image, "analytic", size=(48, 48)).float_image())
    assert np.nanmax(pictures[1]) > 500
    assert np.array_equal(np.isnan(pictures[0]), np.isnan(pictures[1]))
    assert np.nanmax(np.abs(pictures[0] - pictures[1])) == 0.0


def test_packed_corners_follow_a_pipeline_and_dependent_components():
    from vtkmodules.vtkImagingCore import vtkImageShiftScale

    image = make_fixture("vessels", size=32)
    view = OffscreenView(image, "analytic", size=(64, 64))
    scale = vtkImageShiftScale()
    scale.SetInputData(image)
    scale.SetScale(2.0)
    view.mapper.SetInputConnection(scale.GetOutputPort())
    view.volume.GetProperty().GetRGBTransferFunction(0).AddRGBPoint(2.0 * image.GetScalarRange()[1], 1, 1, 1)
    assert view.screenshot().max() > 100
    assert view.mapper.GetInput().GetScalarRange()[1] == pytest.approx(2.0 * image.GetScalarRange()[1])
    # dependent components: the one-component volume goes to VTK, which
    # refuses it in that mode exactly as for stock MIP (no shader is built)
    from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

    log = vtkStringOutputWindow()
    previous = vtkOutputWindow.GetInstance()
    vtkOutputWindow.SetInstance(log)
    try:
        view.volume.GetProperty().IndependentComponentsOff()
        assert view.screenshot().max() == 0
        assert "amip_corners_packed" not in view.mapper.GetShaderPieces()
        view.volume.GetProperty().IndependentComponentsOn()
        assert view.screenshot().max() > 100
    finally:
        vtkOutputWindow.SetInstance(previous)
    assert "IndependentComponents is Off" in log.GetOutput()
    assert "compile" not in log.GetOutput()


@pytest.mark.parametrize("method", ["analytic", "analytic_minip"])
def test_packed_corners_with_a_gradient_opacity_function(method):
    """A gradient-opacity function on component 0 (a user's, or the one VTK's CPU ray caster and
    ``GetGradientOpacity()`` create) applies as on the one-component volume: the packed picture
    equals the unpacked one, and VTK's samplers of the corner components are not in the program
    (VTK gave them texture unit -1: GL_INVALID_VALUE at every frame)."""
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction

    image = make_fixture("vessels", size=24)
    low, high = image.GetScalarRange()
    pictures = {}
    for packed in (True, False):
        view = OffscreenView(image, method, size=(48, 48))
        view.mapper.SetPackedCorners(packed)
        plain = view.screenshot()
        function = vtkPiecewiseFunction()
        function.AddPoint(0.0, 0.1)
        function.AddPoint(0.5 * (high - low), 1.0)
        view.volume.GetProperty().SetGradientOpacity(0, function)
        pictures[packed] = view.screenshot()
        assert np.mean(np.abs(plain.astype(int) - pictures[packed]).max(axis=-1) > 1) > 0.1  # it applies
        program = view.render_window.GetShaderCache().GetLastShaderBound()
        used = [program.IsUniformUsed(f"in_gradientTransferFunc_0[{i}]") for i in range(4)]
        assert used == [True, False, False, False], (packed, used)
    assert np.array_equal(pictures[True], pictures[False])
