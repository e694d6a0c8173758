"""Two-pass DEMIP: the one-pass picture from two GPU passes, pass 2 really reading pass 1, refusals."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPlane, vtkPlaneCollection
from vtkmodules.vtkFiltersSources import vtkPlaneSource, vtkSphereSource
from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkVolume

import mipcast
from mipcast.data_fixtures import image_from_array, make_fixture
from mipcast.mappers.demip import render_depth
from mipcast.mappers.demip_two_pass import INDEX_BASE, DEMIPFirstPassMapper, DEMIPTwoPassVolumeMapper
from mipcast.mappers.foveated import layer_methods
from mipcast.offscreen import OffscreenView
from mipcast.mappers.shader_pieces import load_piece

SIZE = (96, 80)


def _views(image, view="oblique", size=SIZE, window=None, setup=None, **settings):
    """(one-pass, two-pass) views of one scene with the same DEMIP settings (snake_case)."""
    views = []
    for method in ("demip", "demip_two_pass"):
        scene = OffscreenView(image, method, size=size, view=view, window=window)
        for name, value in settings.items():
            getattr(scene.mapper, "Set" + "".join(p.title() for p in name.split("_")))(value)
        if setup is not None:
            setup(scene)
        views.append(scene)
    return views


def _agreement(one, two):
    """Share of pixels within 1 grey level, and the share of lit pixels."""
    a, b = one.screenshot().astype(int), two.screenshot().astype(int)
    error = np.abs(a - b).max(axis=-1)
    return float(np.mean(error <= 1)), float(np.mean(a.max(axis=-1) > 0))


def _assert_same_picture(one, two, lit=0.02):
    within, lit_share = _agreement(one, two)
    assert lit_share > lit, "the volume is (nearly) off screen"
    assert within >= 0.995, within


def _first_pass_codes(scene):
    """Pass 1's float image as written (top row first): see shaders/demip_two_pass_globals.glsl."""
    image = vtkImageData()
    scene.mapper.GetFirstPassMapper().GetDepthImage(image)
    width, height, _ = image.GetDimensions()
    return vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width)[::-1].astype(np.float64)


# -- the same picture as the one-pass mapper ----------------------------------------
@pytest.mark.parametrize("settings", [
    dict(),
    dict(depth_mode="window", depth_weight=0.3),
    dict(depth_mode="eye_distance", depth_weight=0.3),
    dict(depth_mode="steps"),
    dict(sphere_weight=0.5, sphere_colors=((1.0, 0.6, 0.0), (0.0, 0.4, 1.0)),
         sphere_orientation=(20.0, -35.0, 10.0)),
], ids=["default", "window", "eye_distance", "steps", "sphere"])
@pytest.mark.parametrize("view", ["oblique", "perspective"])
@pytest.mark.parametrize("fixture", ["vessels", "frontback"])
def test_two_passes_draw_the_one_pass_picture(fixture, view, settings):
    one, two = _views(make_fixture(fixture, size=40), view, **settings)
    _assert_same_picture(one, two)


def test_readouts_equal_the_one_pass_readouts():
    image = make_fixture("vessels", size=40)
    one, two = _views(image, "perspective", window=(0.2, 1.0), depth_weight=0.3)
    for read in (lambda v: v.float_image(), lambda v: render_depth(v.render_window, v.mapper)):
        a, b = read(one), read(two)
        assert np.array_equal(np.isnan(a), np.isnan(b))
        assert (~np.isnan(a)).mean() > 0.05
        assert np.nanmax(np.abs(a - b)) <= 1e-6 * max(1.0, np.nanmax(np.abs(a)))


@pytest.mark.parametrize("case", ["image_sample_distance_2", "image_sample_distance_3", "jittering",
                                  "viewport_offset", "viewport_offset_jittering", "volume_matrix"])
def test_other_mapper_and_scene_settings(case):
    def setup(scene):
        if case.startswith("image_sample_distance"):  # 3: the reduced grid is truncated
            scene.mapper.SetImageSampleDistance(float(case[-1]))
        if "jittering" in case:
            scene.mapper.SetUseJittering(True)
        if "viewport" in case:  # pass 1's buffer starts at the viewport, the window does not
            scene.renderer.SetViewport(0.4, 0.3, 1.0, 1.0)
        if case == "volume_matrix":
            scene.volume.RotateZ(25.0)
            scene.volume.SetPosition(3.0, -2.0, 1.0)
            scene.renderer.ResetCamera()

    one, two = _views(make_fixture("vessels", size=40), "perspective", size=(112, 96), setup=setup)
    _assert_same_picture(one, two)


def test_clipping_planes_and_cropping():
    def clip(scene):
        plane = vtkPlane()
        plane.SetOrigin(20.0, 20.0, 20.0)
        plane.SetNormal(0.3, 0.2, 1.0)
        planes = vtkPlaneCollection()
        planes.AddItem(plane)
        scene.mapper.SetClippingPlanes(planes)

    def crop(scene):
        scene.mapper.SetCropping(True)
        scene.mapper.SetCroppingRegionPlanes(5, 34, 0, 25, 8, 39)
        scene.mapper.SetCroppingRegionFlagsToSubVolume()

    image = make_fixture("vessels", size=40)
    for setup in (clip, crop):
        _assert_same_picture(*_views(image, "perspective", setup=setup))


def test_opaque_geometry_ends_rays_as_in_one_pass():
    def geometry(scene):  # a ball inside the volume, a square hiding part of it
        ball = vtkSphereSource()
        ball.SetCenter(16.0, 20.0, 26.0)
        ball.SetRadius(8.0)
        square = vtkPlaneSource()
        square.SetOrigin(-8.0, -8.0, 50.0)
        square.SetPoint1(24.0, -8.0, 50.0)
        square.SetPoint2(-8.0, 24.0, 50.0)
        for source in (ball, square):
            mapper = vtkPolyDataMapper()
            mapper.SetInputConnection(source.GetOutputPort())
            actor = vtkActor()
            actor.SetMapper(mapper)
            actor.GetProperty().SetColor(0.9, 0.3, 0.3)
            scene.renderer.AddActor(actor)
        scene.renderer.ResetCameraClippingRange()

    image = make_fixture("vessels", size=40)
    bare = OffscreenView(image, "demip_two_pass", size=SIZE, view="perspective").screenshot()
    one, two = _views(image, "perspective", setup=geometry)
    _assert_same_picture(one, two)
    picture = two.screenshot().astype(int)
    red = (picture[..., 0] > 150) & (picture[..., 1] < 120)
    assert red.mean() > 0.05 and np.abs(picture - bare).max() > 100, "the geometry shows"


def test_window_resizes_between_frames():
    one, two = _views(make_fixture("vessels", size=32))
    for size in ((96, 80), (64, 100), (128, 128)):
        for scene in (one, two):
            scene.render_window.SetSize(*size)
        _assert_same_picture(one, two)


def test_long_rays_march_from_the_ray_start():
    # more than INDEX_BASE samples per ray: the start index is not packed
    image = make_fixture("vessels", size=24)
    one, two = _views(image, setup=lambda scene: scene.mapper.SetSampleDistance(0.005))
    _assert_same_picture(one, two)
    codes = _first_pass_codes(two)
    long_rays = codes >= 2.0
    assert long_rays.mean() > 0.1, "most rays are longer than INDEX_BASE samples"
    assert np.all(codes[long_rays] == np.round(codes[long_rays]))


# -- pass 2 really uses pass 1 -----------------------------------------------------------
def test_the_depth_term_comes_through_pass_one():
    # where DEMIP differs from MIP, the two-pass picture differs from MIP the same way
    image = make_fixture("frontback", size=40)
    one, two = _views(image, "front", size=(96, 96), depth_weight=0.3)
    mip = OffscreenView(image, "mip", size=(96, 96), view="front").screenshot().astype(int)
    a, b = one.screenshot().astype(int), two.screenshot().astype(int)
    demip_differs = np.abs(a - mip).max(axis=-1) > 1
    assert demip_differs.mean() > 0.02
    assert np.all(np.abs(b - mip).max(axis=-1)[demip_differs] > 1)
    assert np.abs(a - b).max() <= 1


def test_pass_one_writes_sample_indices_where_rays_hit():
    image = make_fixture("vessels", size=40)
    _, two = _views(image, "perspective")
    two.screenshot()
    codes = _first_pass_codes(two)
    misses = np.isnan(OffscreenView(image, "mip", size=SIZE, view="perspective").float_image())
    no_ray = (codes > 0.5) & (codes < 1.5)
    assert np.array_equal(no_ray, misses), "pass 1 casts a ray exactly where MIP does"
    packed = -1.0 - codes[~no_ray]
    assert np.all(packed >= 0) and np.all(packed == np.round(packed))
    start, at_max = np.divmod(packed, INDEX_BASE)
    assert np.all(start <= at_max) and at_max.max() > 10


def test_nothing_is_drawn_where_pass_one_casts_no_ray():
    _, two = _views(make_fixture("vessels", size=32))
    assert two.screenshot().max() > 200
    first = two.mapper.GetFirstPassMapper()
    assert isinstance(first, DEMIPFirstPassMapper)

    def refuse(mapper, event):  # after the mapper's own check: pass 1 casts no ray
        mapper.GetAttachedVolume().GetShaderProperty().GetFragmentCustomUniforms().SetUniformf(
            "u_mc_refused", 1.0)

    tag = first.AddObserver(vtkCommand.VolumeMapperRenderStartEvent, refuse, -5.0)
    assert two.screenshot().max() == 0
    first.RemoveObserver(tag)
    assert two.screenshot().max() > 200


# -- rules and refusals --------------------------------------------------------------------
def test_registered_as_a_method_but_not_a_foveation_layer():
    assert isinstance(mipcast.create_mapper("demip_two_pass"), DEMIPTwoPassVolumeMapper)
    assert mipcast.DEMIPTwoPassVolumeMapper is DEMIPTwoPassVolumeMapper
    assert "demip_two_pass" not in layer_methods()


def test_pieces_fill_each_tag_once():
    mapper, first = DEMIPTwoPassVolumeMapper(), DEMIPFirstPassMapper()
    first.SetUseJittering(True)
    for names in (mapper.PIECES + ("demip_readout",), first.GetShaderPieces()):
        tags = [load_piece(name).tag for name in names]
        assert len(tags) == len(set(tags)), names
    assert "demip_two_pass_first_jitter" in first.GetShaderPieces()


def test_bad_input_is_refused_at_render_not_drawn():
    image = make_fixture("vessels", size=32)
    scene = OffscreenView(image, "demip_two_pass", size=(48, 48))
    assert scene.screenshot().max() > 100
    values = np.full((8, 8, 8), np.nan, np.float32)  # every value missing: nothing to draw
    scene.mapper.SetInputData(image_from_array(values))
    messages = []
    scene.mapper.AddObserver(vtkCommand.ErrorEvent, lambda *args: messages.append(args))
    assert "NaN" in scene.mapper.GetRenderProblem()
    assert scene.screenshot().max() == 0 and messages
    scene.mapper.SetInputData(image)
    assert scene.screenshot().max() > 100


@pytest.mark.parametrize("break_it, words", [
    (lambda m: m.SetAutoAdjustSampleDistances(True), ["AutoAdjustSampleDistances", "SetSampleDistance"]),
    (lambda m: m.SetPartitions(2, 1, 1), ["SetPartitions(1, 1, 1)"]),
])
def test_settings_that_cannot_work_are_refused_at_render(break_it, words):
    scene = OffscreenView(make_fixture("vessels", size=32), "demip_two_pass", size=(48, 48))
    assert scene.mapper.GetAutoAdjustSampleDistances() == 0, "off from the start"
    assert scene.screenshot().max() > 100
    break_it(scene.mapper)
    messages = []
    scene.mapper.AddObserver(vtkCommand.ErrorEvent, lambda *args: messages.append(args))
    problem = scene.mapper.GetRenderProblem()
    for word in words:
        assert word in problem, problem
    assert scene.screenshot().max() == 0 and messages


def test_a_volume_in_no_renderer_is_refused():
    scene = OffscreenView(make_fixture("vessels", size=32), "demip_two_pass", size=(48, 48))
    assert scene.screenshot().max() > 100
    scene.renderer.RemoveVolume(scene.volume)
    messages = []
    scene.mapper.AddObserver(vtkCommand.ErrorEvent, lambda *args: messages.append(args))
    scene.renderer.GetRenderWindow().Render()
    scene.volume.RenderVolumetricGeometry(scene.renderer)  # drawn by hand, as a helper volume
    assert messages
    scene.renderer.AddVolume(scene.volume)
    assert scene.screenshot().max() > 100


def test_unattached_mapper_is_refused():
    mapper = DEMIPTwoPassVolumeMapper()
    mapper.SetInputData(make_fixture("vessels", size=16))
    volume = vtkVolume()
    volume.SetMapper(mapper)
    assert "Attach" in mapper.GetRenderProblem()


@pytest.mark.parametrize("setter, args, error, words", [
    ("SetProjection", ("lmip",), ValueError, ["'lmip'", "'mip'", "DEMIPVolumeMapper"]),
    ("SetProjection", ("mida",), ValueError, ["'mida'", "'mip'"]),
    ("SetDepthMode", ("exact",), ValueError, ["depth_mode", "'eye_distance'"]),
    ("SetDepthWeight", (1.5,), ValueError, ["depth_weight", "[0, 1]"]),
    ("SetSphereWeight", ("half",), TypeError, ["sphere_weight", "number"]),
])
def test_bad_parameters_name_the_parameter(setter, args, error, words):
    mapper = DEMIPTwoPassVolumeMapper()
    with pytest.raises(error) as raised:
        getattr(mapper, setter)(*args)
    for word in words:
        assert word in str(raised.value), str(raised.value)
    mapper.SetProjection("mip")
    assert mapper.GetProjection() == "mip"
