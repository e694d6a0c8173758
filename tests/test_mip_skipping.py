"""Block skipping of sampled MIP and MinIP (and the exact MinIP): the same picture and the same float
readout as reading every sample.

With a window above the background (a transfer-function floor above the data
minimum) sampled MIP starts each ray at the floor, jumps over blocks of cells
whose maximum (block maxima one point wider than the block) is not above the
running maximum, and stops at the ceiling (shaders/mip_hooks_blocks.glsl,
the block section of shaders/sampled_loop.glsl).  MinIP mirrors it: with a
ceiling below the data maximum, block minima, the ray starting at the ceiling
and stopping at the floor (shaders/minip_hooks_blocks.glsl; the exact MinIP's
cell walk, shaders/amip_loop_blocks.glsl).  Every test compares ``Skipping``
on with ``Skipping`` off (every sample read) pixel for pixel, in settings
that move the samples (perspective, jittering, reduced images, clipping,
slabs, cropping and cropping regions, scaled and rotated volumes), on a
volume and on its mirror image (dark specks in bright noise) for the minimum.
"""
import numpy as np
import pytest
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPlane
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast.data_fixtures import make_fixture
from mipcast.mappers.max_blocks import block_minima
from mipcast.offscreen import OffscreenView

SIZE = (96, 80)


def _face_specks(shape=(33, 41, 49), block: int = 8, mirrored: bool = False) -> vtkImageData:
    """Dim noise with bright single voxels on and next to the faces of the skipping blocks
    (``mirrored``: 1 minus that, dark specks in bright noise, for the minimum).

    A sample near a block's face may be read from the neighbouring block's
    cell; block maxima that covered the block's own points only would let a
    jump step over such a speck.
    """
    rng = np.random.default_rng(7)
    values = rng.random(shape).astype(np.float32) * 0.2  # (z, y, x)
    for _ in range(400):
        face = rng.integers(3)
        point = [rng.choice([k for k in range(n) if k % block in (0, 1, 2, block - 2, block - 1)])
                 if axis == face else rng.integers(n) for axis, n in enumerate(shape)]
        values[tuple(point)] = 0.5 + 0.5 * rng.random()
    if mirrored:
        values = 1.0 - values
    image = vtkImageData()
    image.SetDimensions(shape[2], shape[1], shape[0])
    image.SetSpacing(1.0, 0.9, 1.3)
    image.SetOrigin(-3.0, 2.0, 1.0)
    array = numpy_to_vtk(values.ravel(), deep=True)
    array.SetName("specks")
    image.GetPointData().SetScalars(array)
    return image


#: method: (the volume mirrored, the specks' window, the skipping piece)
METHODS = {"mip": (False, (0.3, 1.0), "mip_hooks_blocks"),
           "minip": (True, (0.0, 0.7), "minip_hooks_blocks"),
           "analytic_minip": (True, (0.0, 0.7), "amip_loop_blocks"),
           "demip": (False, (0.3, 1.0), "demip_hooks_blocks")}


@pytest.fixture(scope="module")
def specks():
    return {mirrored: _face_specks(mirrored=mirrored) for mirrored in (False, True)}


@pytest.fixture(scope="module")
def vessels():
    return make_fixture("vessels", size=48)


def _pair(image, window, view="oblique", configure=None, readout=False, method="mip"):
    """(skipping on, skipping off): screenshots, or float readouts."""
    out = []
    for skipping in (True, False):
        scene = OffscreenView(image, method, size=SIZE, view=view, window=window)
        scene.mapper.SetSkipping(skipping)
        if configure is not None:
            configure(scene)
        out.append(scene.float_image() if readout else scene.screenshot())
        if not readout:
            assert (METHODS[method][2] in scene.mapper.GetShaderPieces()) == skipping
    return out


def _specks_pair(specks, method, **kwargs):
    mirrored, window, _ = METHODS[method]
    return _pair(specks[mirrored], window, method=method, **kwargs)


def _specks_shown(picture) -> float:
    """Share of the pixels drawn apart from the background and the noise: the specks."""
    grey = picture.astype(int).sum(axis=2)
    background = np.bincount(grey.ravel()).argmax()  # the noise's colour (at the window's floor or ceiling)
    return float(np.mean(grey != background))


def _clip(scene):
    plane = vtkPlane()
    centre = scene.image.GetCenter()
    plane.SetOrigin(centre)
    plane.SetNormal(0.3, -0.5, 0.8)
    scene.mapper.AddClippingPlane(plane)


def _crop(scene, fence=False):
    x0, x1, y0, y1, z0, z1 = scene.image.GetBounds()
    scene.mapper.SetCropping(True)
    scene.mapper.SetCroppingRegionPlanes(x0 + 0.2 * (x1 - x0), x1 - 0.3 * (x1 - x0), y0 + 0.25 * (y1 - y0),
                                         y1 - 0.1 * (y1 - y0), z0 + 0.3 * (z1 - z0), z1 - 0.2 * (z1 - z0))
    if fence:
        scene.mapper.SetCroppingRegionFlagsToFence()


CONFIGURATIONS = {
    "plain": None,
    "jittering": lambda s: s.mapper.SetUseJittering(True),
    "half samples": lambda s: s.mapper.SetSampleDistance(2.0 * s.mapper.GetSampleDistance()),
    "dense samples": lambda s: s.mapper.SetSampleDistance(0.3 * s.mapper.GetSampleDistance()),
    "image sample distance 2": lambda s: s.mapper.SetImageSampleDistance(2.0),
    "clipping plane": _clip,
    "slab": lambda s: s.mapper.SetSlabThickness(6.0),
    "cropping": _crop,
    "cropping regions": lambda s: _crop(s, fence=True),
    # a ray whose visible samples all lie in jumped blocks is drawn at the floor (opaque black), not as nothing
    "cropping regions, background": lambda s: (_crop(s, fence=True), s.renderer.SetBackground(0.1, 0.2, 0.3)),
    "rotated volume": lambda s: (s.volume.RotateZ(33.0), s.volume.RotateX(-20.0), s.volume.SetScale(1.0, 1.7, 0.6)),
}


@pytest.mark.parametrize("view", ["oblique", "perspective"])
@pytest.mark.parametrize("name", sorted(CONFIGURATIONS))
@pytest.mark.parametrize("method", ["mip", "minip", "demip"])
def test_specks_on_block_faces_are_never_jumped(specks, method, view, name):
    on, off = _specks_pair(specks, method, view=view, configure=CONFIGURATIONS[name])
    assert _specks_shown(off) > 0.005, "the scene must show specks"
    assert np.array_equal(on, off), (np.abs(on.astype(int) - off).max(), np.sum(np.any(on != off, axis=2)))


@pytest.mark.parametrize("name", ["plain", "clipping plane", "slab", "rotated volume"])
def test_exact_minip_jumps_blocks_without_losing_a_speck(specks, name):
    on, off = _specks_pair(specks, "analytic_minip", view="perspective", configure=CONFIGURATIONS[name])
    assert _specks_shown(off) > 0.005, "the scene must show specks"
    assert np.array_equal(on, off), (np.abs(on.astype(int) - off).max(), np.sum(np.any(on != off, axis=2)))


@pytest.mark.parametrize("window", [(0.25, 1.0), (0.5, 0.7), (0.1, 0.3)])
def test_vessels_picture_is_unchanged(vessels, window):
    on, off = _pair(vessels, window, "perspective")
    assert off.max() > 0
    assert np.array_equal(on, off)


@pytest.mark.parametrize("name", ["plain", "clipping plane", "cropping regions"])
@pytest.mark.parametrize("method", sorted(METHODS))
def test_float_readout_is_unchanged(specks, method, name):
    # the readout turns floor and ceiling off (exact data units) and still jumps blocks that cannot change the
    # running value
    on, off = _specks_pair(specks, method, configure=CONFIGURATIONS[name], readout=True)
    assert np.isfinite(off).mean() > 0.2
    assert np.array_equal(on, off, equal_nan=True)


@pytest.mark.parametrize("method", sorted(METHODS))
def test_skipping_needs_a_bound(specks, method):
    mirrored, window, piece = METHODS[method]
    image = specks[mirrored]
    low, high = image.GetPointData().GetScalars().GetRange(0)
    full = OffscreenView(image, method, size=(32, 32), window=(low, high))
    full.screenshot()
    assert piece not in full.mapper.GetShaderPieces()  # no floor (ceiling): nothing to jump from the start
    windowed = OffscreenView(image, method, size=(32, 32), window=window)
    windowed.screenshot()
    assert piece in windowed.mapper.GetShaderPieces()
    assert vtkOpenGLGPUVolumeRayCastMapper.GetMaskInput(windowed.mapper) is not None  # VTK's slot: the block level


@pytest.mark.parametrize("method", ["minip", "analytic_minip"])
def test_minimum_projections_hold_block_minima(specks, method):
    windowed = OffscreenView(specks[True], method, size=(32, 32), window=METHODS[method][1])
    windowed.screenshot()
    level = vtkOpenGLGPUVolumeRayCastMapper.GetMaskInput(windowed.mapper)  # VTK's slot (GetMaskInput: the user's)
    assert level.GetPointData().GetScalars().GetName() == "block_min"
    scalars = specks[True].GetPointData().GetScalars()
    values = vtk_to_numpy(scalars).reshape(specks[True].GetDimensions()[::-1])
    low, high = scalars.GetRange(0)
    minima = (block_minima(values, windowed.mapper.BLOCK, windowed.mapper.BLOCK_MARGIN) - low) / (high - low)
    assert np.allclose(vtk_to_numpy(level.GetPointData().GetScalars()).reshape(minima.shape), minima, atol=1e-6)


def _ramp(window, minimum=False):
    """Opacity 0 at the window's floor (a MinIP: its ceiling), as pyvista's and ParaView's transfer functions."""
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction

    def configure(scene):
        opacity = vtkPiecewiseFunction()
        opacity.AddPoint(window[0], 1.0 if minimum else 0.0)
        opacity.AddPoint(window[1], 0.0 if minimum else 1.0)
        scene.volume.GetProperty().SetScalarOpacity(opacity)
    return configure


def test_missing_values_keep_their_picture(vessels):
    values = vessels.GetPointData().GetScalars()
    image = vtkImageData()
    image.DeepCopy(vessels)
    array = np.array([values.GetValue(i) for i in range(values.GetNumberOfTuples())], dtype=np.float32)
    array[: array.size // 5] = np.nan
    image.GetPointData().SetScalars(numpy_to_vtk(array, deep=True))
    on, off = _pair(image, (0.25, 1.0), "oblique", _ramp((0.25, 1.0)))
    assert np.array_equal(on, off)
    # opaque at the floor (OffscreenView's grey): blocks are jumped there too (the hooks tell a ray of
    # missing data only by itself), with the same picture
    opaque = [OffscreenView(image, "mip", size=SIZE, view="oblique", window=(0.25, 1.0)) for _ in range(2)]
    opaque[1].mapper.SetSkipping(False)
    assert np.array_equal(opaque[0].screenshot(), opaque[1].screenshot())
    assert "mip_hooks_blocks" in opaque[0].mapper.GetShaderPieces()


DEMIP_SETTINGS = {
    "default": {},
    "sphere, eye distance": {"sphere_weight": 0.6, "depth_mode": "eye_distance", "depth_weight": 0.3},
    "narrow material": {"material_threshold": 0.02, "depth_mode": "window"},
    "depth of the maximum": {"depth_of": "maximum", "chroma_depth_weight": 0.5},
}


def _demip(settings):
    def configure(scene):
        for name, value in settings.items():
            getattr(scene.mapper, "Set" + "".join(part.title() for part in name.split("_")))(value)
    return configure


@pytest.mark.parametrize("view", ["oblique", "perspective"])
@pytest.mark.parametrize("settings", sorted(DEMIP_SETTINGS))
@pytest.mark.parametrize("window", [(0.25, 1.0), (0.5, 0.7)])
def test_demip_picture_and_depth_are_unchanged(vessels, window, settings, view):
    # the depth cue comes from the first sample of the maximum's material: the jumps must neither move it nor
    # lose it (the ceiling stop keeps the sample that reached it)
    configure = _demip(DEMIP_SETTINGS[settings])
    on, off = _pair(vessels, window, view, configure, method="demip")
    assert off.max() > 0
    assert np.array_equal(on, off), (np.abs(on.astype(int) - off).max(), np.sum(np.any(on != off, axis=2)))

    def depth(scene):
        configure(scene)
        scene.mapper.SetReadout("depth")

    on, off = _pair(vessels, window, view, depth, readout=True, method="demip")
    assert np.isfinite(off).mean() > 0.03  # the vessels' pixels (a depth where the maximum is above the floor)
    assert np.array_equal(on, off, equal_nan=True)


@pytest.mark.parametrize("projection", ["lmip", "attenuated", "mida"])
def test_other_demip_projections_read_every_sample(vessels, projection):
    scene = OffscreenView(vessels, "demip", size=(32, 32), window=(0.25, 1.0))
    scene.mapper.SetProjection(projection)
    scene.screenshot()
    assert not any(n.endswith("_blocks") for n in scene.mapper.GetShaderPieces())


def test_demip_without_depth_skips_as_mip(vessels):
    scene = OffscreenView(vessels, "demip", size=(32, 32), window=(0.25, 1.0))
    scene.mapper.SetDepthWeight(0.0)
    scene.screenshot()
    assert "mip_hooks_blocks" in scene.mapper.GetShaderPieces()
    assert np.array_equal(scene.screenshot(), OffscreenView(vessels, "mip", size=(32, 32), window=(0.25, 1.0))
                          .screenshot())


@pytest.mark.parametrize("method", ["mip", "demip"])
def test_cropped_rays_through_jumped_blocks_are_drawn_at_the_floor(vessels, method):
    # fence regions over the vessels: many visible rays meet only blocks below the floor, every one jumped;
    # such a ray is drawn at the floor (opaque black), a ray with no visible sample not at all (the background)
    def configure(scene):
        _crop(scene, fence=True)
        scene.renderer.SetBackground(0.1, 0.2, 0.3)

    on, off = _pair(vessels, (0.25, 1.0), "oblique", configure, method=method)
    black = np.all(off == 0, axis=2).mean()
    background = np.all(np.abs(off.astype(int) - [26, 51, 76]) <= 1, axis=2).mean()
    assert black > 0.05 and background > 0.05, (black, background)
    assert np.array_equal(on, off), (np.abs(on.astype(int) - off).max(), np.sum(np.any(on != off, axis=2)))


#: The bad-input catalogue's drawn cases (tests/test_bad_input.py) the skipping loops must draw as reading every
#: sample does: missing values, every scalar type, components, geometry, cell scalars.
CATALOGUE_CASES = ("nan_sparse_f32", "nan_half_land_mask", "pos_inf", "int8", "uint16", "int64", "uint64",
                   "uint32_full_range", "float64", "vec3_magnitude", "vec3_component_1", "vec4_uint8_component_3",
                   "anisotropic_spacing", "rotated_direction", "thin_2x2x16", "cell_scalars_only")


@pytest.mark.parametrize("case", CATALOGUE_CASES)
@pytest.mark.parametrize("method", ["mip", "minip", "demip", "analytic", "analytic_minip"])
def test_real_inputs_draw_the_same_with_skipping(method, case):
    # the catalogue's own test windows over the whole finite range (no floor: nothing skipped); here a window
    # whose floor (maximum projections) or ceiling (minimum) leaves blocks to jump
    from test_bad_input import CASES

    from mipcast.core.prepare import prepare_scalars

    make, component, _ = CASES[case]
    image = make()
    prepared = prepare_scalars(image, component)
    low, high = prepared.low, prepared.high
    minimum = method.endswith("minip")
    window = (low, low + 0.6 * (high - low)) if minimum else (low + 0.3 * (high - low), high)
    pictures, readouts = [], []
    for skipping in (True, False):
        scene = OffscreenView(image, method, size=(40, 40), view="oblique", window=window, component=component)
        scene.mapper.SetSkipping(skipping)
        if prepared.missing:  # transparent at the fill side's bound, where rays may start with missing values
            _ramp(window, minimum)(scene)
        pictures.append(scene.screenshot().astype(int))
        if skipping:
            assert any(n.endswith("_blocks") for n in scene.mapper.GetShaderPieces()), "nothing skipped"
        readouts.append(scene.float_image())
    assert len(np.unique(pictures[1])) > 2, "a flat picture tests nothing"
    if method.startswith("analytic"):  # floor and ceiling off without skipping, and the walk restarted
        assert np.abs(pictures[0] - pictures[1]).max() <= 1
        span = high - low
        assert np.array_equal(np.isnan(readouts[0]), np.isnan(readouts[1]))
        assert np.nanmax(np.abs(readouts[0] - readouts[1])) <= 1e-4 * span
    else:
        assert np.array_equal(pictures[0], pictures[1]), (np.abs(pictures[0] - pictures[1]).max(),)
        assert np.array_equal(readouts[0], readouts[1], equal_nan=True)


def _uniform(scene, name: str) -> float:
    from vtkmodules.vtkCommonCore import reference

    value = reference(0.0)
    assert scene.volume.GetShaderProperty().GetFragmentCustomUniforms().GetUniformf(name, value)
    return float(value)


@pytest.mark.parametrize("method", ["mip", "analytic", "minip", "analytic_minip", "demip"])
def test_missing_values_keep_skipping_and_their_picture_under_any_bound(vessels, method):
    """With missing values a ray started beyond the bound on the fill's side (a MIP's floor, a MinIP's
    ceiling), so that a ray through missing data only drew the background: blocks below the floor were
    then read, a padded CT (21 % missing) drew 1.6x (mip) / 1.8x (analytic) slower than without its padding.
    Until 2026-12-04 the bound was kept only where the transfer functions are transparent there (pyvista's
    and ParaView's ramps); under an opaque bound (OffscreenView's grey, pyvista's constant opacity) the plain
    loop was drawn. Now the hooks tell a ray that met missing data only themselves, so the bound is kept and
    blocks are jumped under both, with the picture of reading every sample, over a coloured background and
    opaque geometry behind the volume: rays through missing data only show them, under the opaque bound too."""
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkFiltersSources import vtkPlaneSource
    from vtkmodules.vtkRenderingCore import vtkActor, vtkPolyDataMapper

    minimum = "minip" in method
    values = vtk_to_numpy(vessels.GetPointData().GetScalars()).astype(np.float32).reshape(vessels.GetDimensions()[::-1])
    values = 1.0 - values if minimum else values.copy()
    values[:, :, :10] = np.nan  # rays through missing data only
    values[::9, ::7, ::5] = np.nan
    image = vtkImageData()
    image.CopyStructure(vessels)
    image.GetPointData().SetScalars(numpy_to_vtk(values.ravel(), deep=True))
    window = (0.0, 0.75) if minimum else (0.25, 1.0)
    pictures, bounds = {}, {}
    for transparent in (True, False):
        for skipping in (True, False):
            scene = OffscreenView(image, method, size=SIZE, view="oblique", window=window)
            scene.mapper.SetSkipping(skipping)
            if transparent:
                opacity = vtkPiecewiseFunction()
                opacity.AddPoint(window[0], 1.0 if minimum else 0.0)
                opacity.AddPoint(window[1], 0.0 if minimum else 1.0)
                scene.volume.GetProperty().SetScalarOpacity(opacity)
            scene.renderer.SetBackground(0.2, 0.4, 0.7)
            plane = vtkPlaneSource()
            plane.SetCenter(*(c - 0.6 * s for c, s in zip(image.GetCenter(), (0, 0, 48))))
            plane.SetNormal(0.0, 0.0, 1.0)
            plane.SetOrigin(-40, -40, -30)
            plane.SetPoint1(90, -40, -30)
            plane.SetPoint2(-40, 90, -30)
            actor = vtkActor()
            actor.SetMapper(vtkPolyDataMapper())
            actor.GetMapper().SetInputConnection(plane.GetOutputPort())
            actor.GetProperty().SetColor(1.0, 0.6, 0.1)
            scene.renderer.AddActor(actor)
            pictures[transparent, skipping] = scene.screenshot().astype(int)
            if skipping:
                blocks = any(n.endswith("_blocks") for n in scene.mapper.GetShaderPieces())
                bounds[transparent] = _uniform(scene, "u_mc_skipCeiling" if minimum else "u_mc_skipFloor") \
                    if blocks else None
    for transparent in (True, False):
        assert np.array_equal(pictures[transparent, True], pictures[transparent, False]), transparent
        # the bound is kept: blocks beyond it are jumped
        assert bounds[transparent] is not None and abs(bounds[transparent]) < 1.0e29, transparent
        shown = pictures[transparent, True]
        assert (np.abs(shown - [255 * 0.2, 255 * 0.4, 255 * 0.7]).max(-1) < 2).any()   # the background shows
        assert ((shown[..., 0] > 120) & (shown[..., 2] < 50)).any()                        # and the (lit) plane behind
