"""GPU limits and memory: texture limit and free memory queries, texture bytes per method,
the packed-corner budget, and bricked analytic MIP beyond one 3D texture (the mapper bricks itself) (issue #13, item 7)."""
import numpy as np
import pytest
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

from mipcast.data_fixtures import make_fixture
from mipcast.mappers import bricks, gpu_limits
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView


def _errors():
    """Capture VTK's error/warning text; returns the string window (read with GetOutput)."""
    captured = vtkStringOutputWindow()
    previous = vtkOutputWindow.GetInstance()
    vtkOutputWindow.SetInstance(captured)
    return captured, previous


def test_the_driver_is_asked_for_its_limits():
    view = OffscreenView(make_fixture("spheres", size=16), "analytic", size=(32, 32))
    view.screenshot()
    limits = gpu_limits.describe(view.render_window)
    assert limits["max_texture_size_3d"] >= 256  # OpenGL 3.2 guarantees 256
    free = limits["free_gpu_memory"]
    extensions = gpu_limits.gl_extensions(view.render_window)
    if {"GL_NVX_gpu_memory_info", "GL_ATI_meminfo"} & extensions:
        assert free is not None and free > 0
    else:  # e.g. llvmpipe: the driver cannot say, and we say unknown
        assert free is None


def test_each_method_reports_its_texture_bytes():
    image = make_fixture("vessels", size=24)  # float32
    volume = 24 ** 3 * 4
    expected = {"mip": volume + 3 ** 3 * 4,  # the default window has a floor: block maxima for skipping
                "demip": volume + 3 ** 3 * 4,  # skipping blocks too (its maximum's march)
                "analytic": 4 * volume + 3 ** 3 * 4,          # packed corners + 3^3 float block maxima
                "demip_two_pass": 2 * volume + 32 * 24 * 8}   # two uploads + pass 1's RGBA8 + float image
    for name, bytes_ in expected.items():
        view = OffscreenView(image, name, size=(32, 24))
        view.screenshot()
        assert view.mapper.GetTextureBytes() == bytes_, name
    view = OffscreenView(image, "analytic", size=(32, 24))
    view.mapper.SetPackedCorners(False)
    assert view.mapper.GetTextureBytes() == volume + 3 ** 3 * 4
    view = OffscreenView(image, "mip", size=(32, 24))
    view.mapper.SetSkipping(False)
    view.screenshot()
    assert view.mapper.GetTextureBytes() == volume
    foveated = OffscreenView(image, "foveated", size=(32, 24)).mapper
    assert foveated.GetTextureBytes() > volume  # the pyramid: the volume and its coarser levels


def test_packed_corners_fall_back_to_unpacked_when_the_budget_is_short():
    image = make_fixture("vessels", size=24)
    view = OffscreenView(image, "analytic", size=(48, 40), window="full")
    packed = view.float_image()
    assert "amip_corners_packed" in view.mapper.GetShaderPieces()
    captured, previous = _errors()
    try:
        view.mapper.SetTextureBudget(view.mapper.GetTextureBytes() - 1)  # one byte short
        first = view.float_image()
        second = view.float_image()
    finally:
        vtkOutputWindow.SetInstance(previous)
    text = captured.GetOutput()
    assert text.count("over the budget") == 1, text  # warned once, not per frame
    assert "amip_corners" in view.mapper.GetShaderPieces()
    assert view.mapper.GetTextureBytes() == 24 ** 3 * 4 + 27 * 4
    assert np.array_equal(np.isnan(first), np.isnan(packed))
    assert np.nanmax(np.abs(first - packed)) <= 1e-6 and np.array_equal(first, second, equal_nan=True)
    with pytest.raises(ValueError, match="bytes"):
        view.mapper.SetTextureBudget(-1)


def test_brick_ranges_share_one_layer_and_cover_every_cell():
    for points in (2, 16, 17, 40, 41):
        for limit in (2, 3, 16):
            ranges = bricks.brick_ranges(points, limit)
            cells = [c for a, b in ranges for c in range(a, b)]
            assert cells == list(range(points - 1)), (points, limit)
            assert all(b - a + 1 <= limit for a, b in ranges)
            assert all(ranges[i][1] == ranges[i + 1][0] for i in range(len(ranges) - 1))


def test_analytic_beyond_the_texture_limit_is_drawn_in_bricks_exactly(monkeypatch):
    image = make_fixture("vessels", size=40)
    image.SetSpacing(1.0, 0.8, 1.2)  # bricks placed in world space, not in index space
    whole = OffscreenView(image, "analytic", size=(64, 56), view="perspective", window="full")
    unbricked = whole.float_image()
    unbricked_rgb = whole.screenshot()

    monkeypatch.setattr(gpu_limits, "max_texture_size_3d", lambda window: 16)
    scene = OffscreenView(image, "analytic", size=(64, 56), view="perspective", window="full")
    got = scene.float_image()
    assert scene.mapper.GetNumberOfBricks() == 27  # the mapper itself bricks (mipcast.mappers.bricked_draw)
    expected = METHODS["analytic"].reference(image, scene.camera, scene.size,
                                              sample_distance=scene.sample_distance, window=scene.window)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    assert np.array_equal(np.isnan(got), np.isnan(expected))
    assert np.isfinite(got).mean() > 0.3
    assert np.nanmax(np.abs(got - expected)) / (high - low) <= 1e-4
    assert np.array_equal(np.isnan(got), np.isnan(unbricked))
    assert np.nanmax(np.abs(got - unbricked)) / (high - low) <= 1e-4
    rgb = scene.screenshot()  # coloured from the composed maxima: within one 8-bit level
    assert rgb.max() > 100 and np.abs(rgb.astype(int) - unbricked_rgb).max() <= 1
    assert scene.mapper.GetLastProblem() is None

    # foveated draws it too: its levels beyond the limit composited over bricks (tests/test_foveated_bricks.py)
    foveated = OffscreenView(image, "foveated", size=(64, 56), view="perspective", window="full")
    assert foveated.screenshot().max() > 100 and foveated.mapper.GetLastProblem() is None
    assert foveated.mapper.GetNumberOfBricks() >= 27
    # and with a DEMIP layer: each level's DEMIP composited over bricks, then blended
    demip_layer = OffscreenView(image, "foveated", size=(64, 56), view="perspective", window="full")
    demip_layer.mapper.SetMethod("demip")
    assert demip_layer.screenshot().max() > 100 and demip_layer.mapper.GetLastProblem() is None
    assert demip_layer.mapper.GetNumberOfBricks() >= 27
    # DEMIP draws it in bricks in two phases (mipcast.mappers.bricked_demip; tests/test_bricked_demip.py)
    demip = OffscreenView(image, "demip", size=(64, 56), view="perspective", window="full")
    assert demip.screenshot().max() > 100 and demip.mapper.GetLastProblem() is None
    assert demip.mapper.GetNumberOfBricks() == 27
