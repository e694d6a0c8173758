"""The base mapper: parity with stock VTK MIP, Attach rules, refusals, float readout."""
import json
import shutil
from pathlib import Path

import numpy as np
import pytest
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkRenderingCore import vtkVolume

import mipcast
from mipcast.data_fixtures import image_from_array
from mipcast import reference
from mipcast.core.metrics import grey_diff
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView
from mipcast.mappers.shader_pieces import installed_tags
from installed import pvpython_env
from xvfb import run_under_xvfb

HERE = Path(__file__).resolve().parent


def _parity(image, size=(96, 80), configure=None, **kwargs):
    shots = {}
    for method in ("stock", "mip"):
        view = OffscreenView(image, method, size=size, **kwargs)
        if configure is not None:
            configure(view)
        shots[method] = view.screenshot()
    return grey_diff(shots["stock"], shots["mip"]), shots["mip"]


def test_parity_with_stock_vtk_in_process():
    from parity_check import parity  # tests/ is on sys.path (conftest)
    result = parity()
    for view in ("oblique", "perspective"):
        assert result[view]["lit"] > 0.3, "the picture is (nearly) black"
        assert result[view]["within_1"] >= 0.999, result


@pytest.mark.skipif(not (shutil.which("pvpython") and shutil.which("xvfb-run")),
                    reason="ParaView's pvpython (VTK 9.2) not installed: apt-get install paraview xvfb")
def test_parity_with_stock_vtk_92_in_paraview():
    run = run_under_xvfb(["pvpython", str(HERE / "parity_check.py")], timeout=300, env=pvpython_env())
    assert run.returncode == 0, run.stderr[-2000:]
    result = json.loads(run.stdout.strip().splitlines()[-1])
    assert result["vtk"].startswith("9.2"), result
    for view in ("oblique", "perspective"):
        assert result[view]["lit"] > 0.3
        assert result[view]["within_1"] >= 0.999, result
        assert result[view]["masks_agree"], result
        assert result[view]["float_max_error"] <= 1e-3, result
    for case, entry in result["projections"].items():  # MinIP and average (tests/test_projections.py)
        assert entry["lit"] > 0.3 and entry["within_1"] >= 0.999, (case, entry)
        for key, value in entry.items():
            if key.endswith("_masks_agree"):
                assert value, (case, key, entry)
            if key.endswith("_max_error"):
                assert value <= 1e-3, (case, key, entry)


@pytest.mark.parametrize("name, configure", [
    ("half-voxel steps", lambda v: v.mapper.SetSampleDistance(0.5)),
    ("image sample distance 2", lambda v: v.mapper.SetImageSampleDistance(2.0)),
    ("nearest interpolation", lambda v: v.volume.GetProperty().SetInterpolationTypeToNearest()),
    ("colour and opacity ramp", lambda v: _hot_property(v)),
])
def test_vtk_settings_behave_as_in_stock(vessels48, name, configure):
    diff, shot = _parity(vessels48, configure=configure)
    assert shot.max() > 100, f"{name}: picture is dark"
    assert diff["within_1"] >= 0.999, (name, diff)


def _hot_property(view):
    prop = view.volume.GetProperty()
    colour = prop.GetRGBTransferFunction()
    colour.RemoveAllPoints()
    colour.AddRGBPoint(0.0, 0.0, 0.0, 0.3)
    colour.AddRGBPoint(0.5, 1.0, 0.2, 0.0)
    colour.AddRGBPoint(1.0, 1.0, 1.0, 0.6)
    opacity = prop.GetScalarOpacity()
    opacity.RemoveAllPoints()
    opacity.AddPoint(0.1, 0.0)
    opacity.AddPoint(0.8, 1.0)


def _image(values, spacing=(1.0, 1.0, 1.0), origin=(0.0, 0.0, 0.0), direction=None):
    return image_from_array(values, spacing=spacing, origin=origin, direction=direction)


def _rotation(axis, degrees):
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    x, y, z = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.array([[c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
                     [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
                     [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)]])


@pytest.mark.parametrize("view", ["oblique", "perspective"])
@pytest.mark.parametrize("geometry", ["unit", "anisotropic rotated int16", "dense sampling"])
def test_float_readout_matches_sampled_reference(view, geometry):
    rng = np.random.default_rng(3)
    if geometry == "unit":
        image = mipcast.data_fixtures.make_fixture("vessels", size=40)
    else:
        values = (rng.random((24, 36, 30)) ** 6 * 3000 - 1000).astype(np.int16)
        image = _image(values, spacing=(0.8, 0.8, 2.0), origin=(-10.0, 5.0, 3.0),
                       direction=_rotation((1, 2, 0.5), 35))
    distance = 0.7
    if geometry == "dense sampling":  # thousands of steps per ray: positions must not drift
        image = image_from_array(rng.random((64, 64, 64)).astype(np.float32))
        distance = 1.0 / 32.0
    low, high = image.GetPointData().GetScalars().GetRange(0)
    gpu = OffscreenView(image, "mip", size=(80, 64), view=view, sample_distance=distance)
    values = gpu.float_image()
    expected = reference.render(image, gpu.camera, (80, 64), method="mip", sample_distance=distance)
    assert np.array_equal(np.isnan(values), np.isnan(expected)), "hit masks differ"
    hits = ~np.isnan(expected)
    assert 0.1 < hits.mean() < 0.95
    error = np.abs(values[hits] - expected[hits]) / (high - low)
    assert np.percentile(error, 99.9) <= 1e-3
    assert error.max() <= 5e-3


def test_unattached_mapper_refuses_to_draw(vessels48):
    view = OffscreenView(vessels48, "mip", size=(64, 64))
    messages = []
    view.mapper.AddObserver(vtkCommand.ErrorEvent, lambda *args: messages.append(args))
    assert view.screenshot().max() > 100
    view.volume.SetMapper(None)
    view.volume.SetMapper(view.mapper)
    view.volume.GetShaderProperty().ClearAllFragmentShaderReplacements()
    assert not view.mapper.IsAttached()
    assert "Attach(volume)" in view.mapper.GetRenderProblem()
    assert view.screenshot().max() == 0, "an unattached mipcast mapper must not draw stock MIP"
    assert messages, "no VTK error was reported"
    view.mapper.Attach(view.volume)
    assert view.screenshot().max() > 100


def test_set_mapper_without_attach_is_refused(vessels48):
    mapper = mipcast.MIPVolumeMapper()
    mapper.SetInputData(vessels48)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    assert "Attach" in mapper.GetRenderProblem()


def test_attach_moves_pieces_and_refuses_foreign_code(vessels48):
    mapper = mipcast.MIPVolumeMapper()
    mapper.SetInputData(vessels48)
    first, second = vtkVolume(), vtkVolume()
    mapper.Attach(first)
    assert installed_tags(first.GetShaderProperty())
    mapper.Attach(second)
    assert installed_tags(first.GetShaderProperty()) == []
    assert mapper.GetAttachedVolume() is second and second.GetMapper() is mapper
    foreign = vtkVolume()
    foreign.GetShaderProperty().AddFragmentShaderReplacement("//VTK::Shading::Init", True, "x", False)
    with pytest.raises(ValueError, match="did not install"):
        mapper.Attach(foreign)
    with pytest.raises(TypeError, match="vtkVolume"):
        mapper.Attach(vessels48)


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_bad_input_is_refused_at_render_not_drawn(vessels48, method):
    view = OffscreenView(vessels48, method, size=(48, 48))
    assert view.screenshot().max() > 100
    values = np.full((8, 8, 8), np.nan, np.float32)  # every value missing: nothing to draw
    view.mapper.SetInputData(_image(values))  # after the view checked its input
    messages = []
    view.mapper.AddObserver(vtkCommand.ErrorEvent, lambda *args: messages.append(args))
    problem = view.mapper.GetRenderProblem()
    assert "NaN" in problem and "nothing to draw" in problem
    assert view.screenshot().max() == 0 and messages and view.mapper.GetLastProblem() == problem
    view.mapper.SetInputData(vessels48)
    assert view.screenshot().max() > 100


def test_input_connection_works(vessels48):
    from vtkmodules.vtkImagingCore import vtkImageShiftScale

    view = OffscreenView(vessels48, "mip", size=(64, 64))
    scale = vtkImageShiftScale()
    scale.SetInputData(vessels48)
    scale.SetScale(1.0)
    scale.SetOutputScalarTypeToFloat()
    view.mapper.SetInputConnection(scale.GetOutputPort())
    assert view.mapper.GetRenderProblem() is None
    assert view.screenshot().max() > 100


def test_attachment_survives_python_wrapper_loss(vessels48):
    import gc

    def build():
        view = OffscreenView(vessels48, "mip", size=(48, 48))
        return view.render_window, view.renderer.GetVolumes().GetLastProp().GetAddressAsString("vtkObjectBase")

    window, address = build()  # the Python wrappers of the volume and mapper die here
    gc.collect()
    volume = window.GetRenderers().GetFirstRenderer().GetVolumes().GetLastProp()
    assert volume.GetAddressAsString("vtkObjectBase") == address
    assert volume.GetMapper().IsAttached()
    assert volume.GetMapper().GetRenderProblem() is None


@pytest.mark.parametrize("method", ["mip", "analytic", "demip"])
def test_float_readout_in_a_subplot_with_opaque_geometry(method):
    # VTK's render-to-image keeps the viewport's window offset in its pixel
    # uniforms: in a renderer that does not start at the window's corner the
    # rays would end at the scene depth of other pixels
    from vtkmodules.vtkFiltersSources import vtkPlaneSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow

    from mipcast.mappers.float_readout import render_float
    from mipcast.offscreen import grey_property, set_view

    image = mipcast.data_fixtures.make_fixture("vessels", size=32)

    def readout(window_width, viewport):
        window = vtkRenderWindow()
        window.SetOffScreenRendering(1)
        window.SetSize(window_width, 96)
        window.SetMultiSamples(0)
        if viewport[0] > 0:
            left = vtkRenderer()
            left.SetViewport(0.0, 0.0, viewport[0], 1.0)
            window.AddRenderer(left)
        renderer = vtkRenderer()
        renderer.SetViewport(*viewport)
        window.AddRenderer(renderer)
        mapper = mipcast.methods.create_mapper(method)
        mapper.SetInputData(image)
        mapper.SetAutoAdjustSampleDistances(False)
        volume = vtkVolume()
        mapper.Attach(volume)
        volume.SetProperty(grey_property((0.2, 0.9)))
        renderer.AddVolume(volume)
        plane = vtkPlaneSource()  # an opaque plane through the middle of the volume, over its left part
        plane.SetOrigin(-5.0, -5.0, 16.0)
        plane.SetPoint1(16.0, -5.0, 16.0)
        plane.SetPoint2(-5.0, 40.0, 16.0)
        plane_mapper = vtkPolyDataMapper()
        plane_mapper.SetInputConnection(plane.GetOutputPort())
        actor = vtkActor()
        actor.SetMapper(plane_mapper)
        renderer.AddActor(actor)
        set_view(renderer, image, "front")
        renderer.GetActiveCamera().Azimuth(20)
        renderer.ResetCameraClippingRange()
        return render_float(window, mapper)

    alone = readout(128, (0.0, 0.0, 1.0, 1.0))
    beside = readout(256, (0.5, 0.0, 1.0, 1.0))
    assert alone.shape == beside.shape == (96, 128)
    assert np.array_equal(np.isnan(alone), np.isnan(beside)) and np.isnan(alone).mean() < 0.9
    assert np.nanmax(np.abs(alone - beside)) < 1e-5


@pytest.mark.parametrize("dtype", [np.uint8, np.int8])
@pytest.mark.parametrize("method", ["mip", "analytic", "foveated"])
def test_float_readout_of_8_bit_data_is_in_data_units(dtype, method):
    # VTK normalises 8-bit texels by 256 (128) where they hold value / 255 (127)
    base = np.random.default_rng(2).random((20, 24, 28))
    values = (-100 + 150 * base if dtype == np.int8 else 50 + 150 * base).astype(dtype)
    image = image_from_array(values)
    view = OffscreenView(image, method, size=(64, 64))
    if method == "foveated":
        view.mapper.SetFoveation(False)  # full quality: comparable with the reference
    found = view.float_image()
    kind = {"method": "analytic"} if method == "analytic" else {"method": "mip", "sample_distance": view.sample_distance}
    expected = reference.render(image, view.camera, (64, 64), **kind)
    hits = ~np.isnan(found) & ~np.isnan(expected)
    assert hits.mean() > 0.2
    error = found[hits] - expected[hits]
    if method == "analytic":  # texelFetch: exact texels
        assert np.max(np.abs(error)) <= 1e-3 * np.ptp(values.astype(float))
    else:  # the texture unit filters 8-bit texels in 8-bit steps: unbiased, within ~1 unit
        assert abs(error.mean()) < 0.1 and np.max(np.abs(error)) < 2.0


def _mask_of(image, keep):
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    mask = vtkImageData()
    mask.CopyStructure(image)
    mask.GetPointData().SetScalars(numpy_to_vtk(keep.astype(np.uint8).ravel(), deep=True))
    return mask


@pytest.mark.parametrize("method", ["mip", "analytic", "minip", "analytic_minip", "demip", "demip_two_pass",
                                    "average", "analytic_average", "foveated"])
def test_a_mask_hides_its_points_as_missing_data(vessels48, method):
    """SetMaskInput (VTK's binary mask: CT angiography's bone removal) was silently ignored by every mipcast
    method until 2026-12-04 (VTK's mask slot carries the block level, and mipcast's loops read no mask): now
    points where the mask is 0 are missing data, the picture and floats those of the volume with NaN there,
    the user's image and mask unchanged, and a mask modified in place is read again."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    values = vtk_to_numpy(vessels48.GetPointData().GetScalars()).reshape(vessels48.GetDimensions()[::-1])
    keep = np.ones(values.shape, bool)
    keep[:, :, :20] = False  # the low-x part hidden
    mask = _mask_of(vessels48, keep)
    before = values.copy()
    window = (0.0, 0.5) if "minip" in method else (0.2, 1.0)
    masked = OffscreenView(vessels48, method, size=(64, 48), window=window)
    masked.mapper.SetMaskInput(mask)
    assert masked.mapper.GetMaskInput() is mask and masked.mapper.GetRenderProblem() is None
    holes = values.astype(np.float32)
    holes[~keep] = np.nan
    expected = OffscreenView(_image(holes), method, size=(64, 48), window=window)
    picture = masked.screenshot()
    assert np.array_equal(picture, expected.screenshot())
    assert np.array_equal(masked.float_image(), expected.float_image(), equal_nan=True)
    plain = OffscreenView(vessels48, method, size=(64, 48), window=window).screenshot()
    assert not np.array_equal(picture, plain) and picture.max() > 100
    assert np.array_equal(values, before)  # the user's image is not modified
    # the mask edited in place and marked modified: read again (all kept: the plain picture)
    vtk_to_numpy(mask.GetPointData().GetScalars())[:] = 1
    mask.Modified()
    assert np.array_equal(masked.screenshot(), plain)
    masked.mapper.SetMaskInput(None)
    assert masked.mapper.GetMaskInput() is None and np.array_equal(masked.screenshot(), plain)


@pytest.mark.parametrize("method", ["mip", "analytic", "demip", "average", "foveated"])
def test_masks_and_hidden_points_stay_missing_in_bricks(vessels48, method):
    """A volume beyond the 3D texture limit is drawn in bricks cut from the input: until 2026-12-04 the cut
    kept the scalars only, so points hidden by a ghost array or a vtkValidPointMask were drawn as values in
    bricks (and a mask was refused there). Now the bricks carry the arrays that hide points: the masked and
    the ghost-hidden volumes draw the NaN twin's bricked picture (limit 20: 27 bricks of the 48^3)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes

    from mipcast.core.object_state import object_state

    values = vtk_to_numpy(vessels48.GetPointData().GetScalars()).reshape(vessels48.GetDimensions()[::-1])
    keep = np.ones(values.shape, bool)
    keep[:, :, :20] = False
    keep[::5, ::3] = False
    holes = values.astype(np.float32)
    holes[~keep] = np.nan
    ghosted = _image(values.astype(np.float32))
    ghosts = numpy_to_vtk(np.where(keep, 0, vtkDataSetAttributes.HIDDENPOINT).astype(np.uint8).ravel(), deep=True)
    ghosts.SetName(vtkDataSetAttributes.GhostArrayName())
    ghosted.GetPointData().AddArray(ghosts)
    pictures = {}
    for name, image in (("nan", _image(holes)), ("mask", vessels48), ("ghosts", ghosted)):
        view = OffscreenView(image, method, size=(48, 40), window=(0.2, 1.0))
        object_state(view.mapper)["texture_limit"] = 20  # a smaller GPU: the 48^3 in bricks
        if name == "mask":
            view.mapper.SetMaskInput(_mask_of(vessels48, keep))
        pictures[name] = view.screenshot()
        assert view.mapper.GetNumberOfBricks() > 1 or method == "foveated", name
    assert pictures["nan"].max() > 100
    assert np.array_equal(pictures["mask"], pictures["nan"])
    assert np.array_equal(pictures["ghosts"], pictures["nan"])


def test_a_mask_that_cannot_be_drawn_is_refused_naming_why(vessels48):
    """A mask of other dimensions and a label-map mask are refused with the reason (no picture drawn from
    half the settings)."""
    from vtkmodules.vtkCommonDataModel import vtkImageData

    view = OffscreenView(vessels48, "mip", size=(48, 48))
    small = vtkImageData()
    small.SetDimensions(8, 8, 8)
    small.AllocateScalars(3, 1)  # unsigned char
    view.mapper.SetMaskInput(small)
    assert "has dimensions (8, 8, 8), the volume (48, 48, 48)" in view.mapper.GetRenderProblem()
    assert view.screenshot().max() == 0
    with pytest.raises(TypeError, match="binary masks only"):
        view.mapper.SetMaskTypeToLabelMap()


@pytest.mark.parametrize("method", ["mip", "analytic", "minip", "average", "demip", "foveated"])
def test_blend_modes_other_than_the_methods_own_are_refused(vessels48, method):
    """Every mipcast method puts its ray loop in VTK's maximum-intensity template. Until 2026-12-04 another
    blend mode was taken silently: composite, isosurface and minimum drew the method's picture anyway,
    additive the whole box lit. Now the setters refuse naming what to use, and a mode set past them (from
    C++: VTK's own class method) is a render problem, drawn as nothing, not as a wrong picture."""
    from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper as Base

    view = OffscreenView(vessels48, method, size=(48, 48))  # the projection's default window
    plain = view.screenshot()
    assert plain.max() > 100
    for setter in ("SetBlendModeToComposite", "SetBlendModeToAdditive", "SetBlendModeToIsoSurface",
                   "SetBlendModeToMinimumIntensity", "SetBlendModeToAverageIntensity"):
        with pytest.raises(ValueError, match="vtkGPUVolumeRayCastMapper"):
            getattr(view.mapper, setter)()
    view.mapper.SetBlendModeToMaximumIntensity()  # its own: accepted
    assert np.array_equal(view.screenshot(), plain)
    Base.SetBlendMode(view.mapper, Base.ADDITIVE_BLEND)  # past the Python setters
    assert "blend mode 'additive' is not one of its settings" in view.mapper.GetRenderProblem()
    assert view.screenshot().max() == 0


@pytest.mark.parametrize("method", ["mip", "analytic", "minip", "analytic_minip", "stock"])
def test_int8_minus_128_is_drawn_as_minus_128(method):
    """VTK's signed 8-bit texture holds -128 as -127 (signed normalised texels clamp at -1): until 2026-12-05 an
    int8 volume's -128 was read back and drawn as -127 (1 unit of its range, 0.4 % of -128 .. 100), stock VTK's
    too. Such data now goes to the GPU as an int16 copy (mipcast.core.prepare). Half the volume -128, half
    -127: the front view's rays see each half's value."""
    values = np.full((8, 8, 8), -127, np.int8)
    values[:, :, :4] = -128
    values[0, 0, 0] = 100  # (z, y, x): a range beyond the two values
    image = image_from_array(values)
    view = OffscreenView(image, method, size=(32, 32), view="front", window=(-130.0, -125.0))
    picture = view.screenshot()[..., 0].astype(float)
    reference_name = {"stock": "mip"}.get(method, method)
    settings = {} if METHODS[reference_name].walks_cells else {"sample_distance": view.sample_distance}
    expected = METHODS[reference_name].reference(image, view.camera, view.size, window=view.window, **settings)
    row = expected[16]
    assert np.sum(row == -128.0) >= 8 and np.sum(row == -127.0) >= 8  # both halves in view
    grey = np.where(np.isfinite(expected), np.round(255 * np.clip((expected + 130.0) / 5.0, 0, 1)), 0.0)
    # -128 is 102 grey, -127 153; stock reads VTK's colour table half a table step off (docs/methods.md,
    # "Reading VTK's tables where they hold the value"): 1024 entries over 228 units, 5.7 grey here
    allowed = 2.0 if method != "stock" else 1.0 + 0.5 * 228.0 / 1023.0 / 5.0 * 255.0
    assert np.abs(picture - grey)[16].max() <= allowed, np.abs(picture - grey)[16].max()
    if METHODS[method].float_readout:
        found = view.float_image()
        both = np.isfinite(found) & np.isfinite(expected)
        assert np.abs(found[both] - expected[both]).max() < 0.01


@pytest.mark.parametrize("dtype, values", [(np.int16, (-1024, -1023, 0, 1, 1000, 3071)),
                                           (np.uint16, (0, 1, 2, 40000, 65534, 65535))])
@pytest.mark.parametrize("method", ["analytic", "mip"])
def test_float_readout_of_16_bit_data_is_in_data_units(method, dtype, values):
    """VTK normalises 16-bit texels by 32768 (65536) where they hold value / 32767 (65535), as 8-bit ones by
    128 (256): until 2026-12-05 the readout took 16-bit values as they were, 3e-5 of the value off (a CT's
    3071 HU read back as 3071.09, uint16's 65535 as 65536). Slabs of single values along x, seen from the
    front: every ray's value is its slab's."""
    slabs = np.repeat(np.array(values, dtype), 4)
    volume = np.ascontiguousarray(np.broadcast_to(slabs, (4, 4, slabs.size)))
    image = image_from_array(volume)
    view = OffscreenView(image, method, size=(8 * slabs.size, 16), view="front")
    camera = view.camera
    camera.SetParallelScale(2.0)  # the slabs across the picture
    camera.SetFocalPoint((slabs.size - 1) / 2.0, 1.5, 1.5)
    camera.SetPosition((slabs.size - 1) / 2.0, 1.5, 40.0)
    view.renderer.ResetCameraClippingRange()
    found = view.float_image()
    settings = {} if METHODS[method].walks_cells else {"sample_distance": view.sample_distance}
    expected = METHODS[method].reference(image, camera, view.size, window=view.window, **settings)
    inside = np.isfinite(found) & np.isin(expected, np.array(values, float))  # (not the cells between slabs)
    assert {float(v) for v in values} <= set(expected[inside].tolist())
    assert np.abs(found[inside] - expected[inside]).max() <= 2e-6 * np.ptp(np.array(values, float))
