"""Depth-enhanced MIP: GPU against the float64 reference, depth order, stability, parameters."""
import numpy as np
import pytest
from vtkmodules.vtkRenderingCore import vtkCoordinate

import mipcast
from mipcast import reference
from mipcast.data_fixtures import image_from_array, make_fixture
from mipcast.mappers.demip import DEPTH_MODES, SPHERE_PRESETS, render_depth
from mipcast.core.metrics import silhouette
from mipcast.offscreen import OffscreenView

SIZE = (96, 80)


def _image(values):
    return image_from_array(np.asarray(values, np.float32))


def _scene(image, view="oblique", size=SIZE, window=None, camera=None, **settings):
    """An offscreen DEMIP view with ``settings`` (snake_case names of the mapper's setters)."""
    scene = OffscreenView(image, "demip", size=size, view=view, window=window)
    for name, value in settings.items():
        getattr(scene.mapper, "Set" + "".join(p.title() for p in name.split("_")))(value)
    if camera is not None:
        camera(scene.camera)
        scene.renderer.ResetCameraClippingRange()
    return scene


def _reference(scene, output, **settings):
    return reference.render(scene.image, scene.camera, scene.size, method="demip",
                            sample_distance=scene.sample_distance, window=scene.window,
                            output=output, **settings)


def _compare(image, view="oblique", size=SIZE, window=None, camera=None, **settings):
    """GPU picture and float depth against the reference: shares of agreeing pixels."""
    scene = _scene(image, view, size, window, camera, **settings)
    picture = scene.screenshot().astype(float)
    depth = render_depth(scene.render_window, scene.mapper)
    expected_depth = _reference(scene, "depth", **settings)
    expected_rgb = _reference(scene, "rgb", **settings)
    hits = ~np.isnan(expected_rgb[..., 0])
    outline = silhouette(np.where(hits, 0.0, np.nan))
    assert hits.mean() > 0.02, "the volume is (nearly) off screen"
    grey_error = np.abs(picture - np.round(255 * np.nan_to_num(expected_rgb))).max(axis=-1)
    disagree = np.isnan(depth) != np.isnan(expected_depth)
    both = ~np.isnan(depth) & ~np.isnan(expected_depth)
    depth_error = np.abs(depth[both] - expected_depth[both])
    return {"grey_within_2": float(np.mean(grey_error[hits] <= 2)),
            "depth_within_1e-4": float(np.mean(depth_error <= 1e-4)) if both.any() else 1.0,
            "depth_max_error": float(depth_error.max(initial=0.0)),
            "term_masks_disagree": int(np.count_nonzero(disagree & ~outline)),
            "with_term": float(both.mean()), "picture": picture, "depth": depth,
            "expected_depth": expected_depth}


def _assert_matches(result):
    summary = {k: v for k, v in result.items() if not isinstance(v, np.ndarray)}
    assert result["grey_within_2"] >= 0.99, summary
    assert result["depth_within_1e-4"] >= 0.999, summary
    assert result["term_masks_disagree"] == 0, summary


# -- parity and accuracy -------------------------------------------------------
@pytest.mark.parametrize("view", ["oblique", "perspective"])
def test_zero_weights_are_bit_identical_to_mip(view):
    image = make_fixture("vessels", size=48)
    demip = _scene(image, view, depth_weight=0.0, sphere_weight=0.0).screenshot()
    mip = OffscreenView(image, "mip", size=SIZE, view=view).screenshot()
    assert mip.max() > 200
    assert np.array_equal(demip, mip)


@pytest.mark.parametrize("mode", DEPTH_MODES)
@pytest.mark.parametrize("view", ["oblique", "perspective"])
def test_each_depth_mode_matches_reference(mode, view):
    result = _compare(make_fixture("vessels", size=48), view, window=(0.2, 1.0), depth_mode=mode,
                      depth_weight=0.3)
    _assert_matches(result)
    assert result["depth_max_error"] < 1e-5
    assert 0.05 < result["with_term"] < 0.5


@pytest.mark.parametrize("fixture", ["noise", "frontback"])
def test_full_range_window_and_sphere_match_reference(fixture):
    _assert_matches(_compare(make_fixture(fixture, size=40), "perspective", sphere_weight=0.5,
                             sphere_colors=((1.0, 0.6, 0.0), (0.0, 0.4, 1.0)),
                             sphere_orientation=(20.0, -35.0, 10.0)))


def test_depth_modes_differ_as_defined():
    # parallel projection: window, entry_plus_length and eye_distance all measure
    # the hit's view distance; steps measures from the ray's entry instead
    image = make_fixture("vessels", size=40)
    depth = {mode: render_depth(*_window_and_mapper(_scene(image, "oblique", window=(0.2, 1.0),
                                                           depth_mode=mode))) for mode in DEPTH_MODES}
    for mode in ("window", "eye_distance"):
        assert np.nanmax(np.abs(depth[mode] - depth["entry_plus_length"])) < 1e-5
    assert np.nanmax(np.abs(depth["steps"] - depth["entry_plus_length"])) > 0.2
    # perspective: the window depth is non-linear, entry_plus_length over-estimates off axis
    depth = {mode: render_depth(*_window_and_mapper(_scene(image, "perspective", window=(0.2, 1.0),
                                                           depth_mode=mode))) for mode in DEPTH_MODES}
    assert 1e-3 < np.nanmax(np.abs(depth["eye_distance"] - depth["entry_plus_length"])) < 0.1
    assert np.nanmax(np.abs(depth["window"] - depth["eye_distance"])) > 0.05


def _window_and_mapper(scene):
    return scene.render_window, scene.mapper


def test_value_readout_is_the_maximum_and_depth_readout_restores_the_setting():
    image = make_fixture("vessels", size=40)
    scene = _scene(image, depth_weight=0.4)
    mip = OffscreenView(image, "mip", size=SIZE).float_image()
    values = scene.float_image()
    assert np.array_equal(np.isnan(values), np.isnan(mip))
    # DEMIP places sample k at entry + k * step (MIP adds the step k times): same samples
    expected = reference.render(image, scene.camera, SIZE, method="mip",
                                sample_distance=scene.sample_distance)
    assert np.nanmax(np.abs(values - mip)) < 1e-4
    assert np.nanmax(np.abs(values - expected)) < 1e-4
    render_depth(scene.render_window, scene.mapper)
    assert scene.mapper.GetReadout() == "value"
    scene.mapper.SetReadout("depth")
    low, high = image.GetPointData().GetScalars().GetRange(0)
    as_values = scene.float_image()
    depth = (as_values.astype(float) - low) / (high - low)
    assert np.nanmin(depth) >= 0 and np.nanmax(depth) <= 1


def test_background_keeps_the_mip_colour():
    # the DEMIP term applies only where the maximum is above the window's low end
    image = make_fixture("vessels", size=40)
    window = (0.3, 1.0)
    scene = _scene(image, window=window, depth_weight=0.5, sphere_weight=0.5)
    picture = scene.screenshot()
    depth = render_depth(scene.render_window, scene.mapper)
    mip = OffscreenView(image, "mip", size=SIZE, window=window)
    mip_picture, values = mip.screenshot(), mip.float_image()
    background = values <= window[0]
    assert background.mean() > 0.2
    assert np.all(np.isnan(depth[background]))
    assert np.array_equal(picture[background], mip_picture[background])
    assert np.all(~np.isnan(depth[values > window[0] + 0.01]))


# -- depth order -----------------------------------------------------------------
def _disc_means(scene, picture):
    """Mean colour of the two frontback balls' discs: (low-z ball, high-z ball)."""
    n = scene.image.GetDimensions()[0]
    means = []
    for centre in ((round(0.35 * n), n // 2, round(0.25 * n)), (round(0.65 * n), n // 2, round(0.75 * n))):
        coordinate = vtkCoordinate()
        coordinate.SetCoordinateSystemToWorld()
        coordinate.SetValue(*map(float, centre))
        x, y = coordinate.GetComputedDoubleDisplayValue(scene.renderer)
        rows, columns = np.mgrid[0:picture.shape[0], 0:picture.shape[1]]
        inside = np.hypot(columns + 0.5 - x, picture.shape[0] - rows - 0.5 - y) < 3.0
        assert inside.sum() >= 9
        means.append(picture[inside].reshape(-1, 3).mean(axis=0))
    return means


@pytest.mark.parametrize("mode", DEPTH_MODES)
def test_nearer_ball_is_brighter_and_order_flips_with_the_camera(mode):
    image = make_fixture("frontback", size=40)
    brighter = {}
    for view in ("front", "back"):  # camera on +z (high-z ball near), then on -z
        mip = _disc_means(_scene(image, view, size=(96, 96), depth_weight=0.0),
                          OffscreenView(image, "mip", size=(96, 96), view=view).screenshot())
        assert abs(mip[0][0] - mip[1][0]) < 1.0, "MIP shows both balls alike"
        scene = _scene(image, view, size=(96, 96), depth_mode=mode, depth_weight=0.3)
        low_z, high_z = _disc_means(scene, scene.screenshot())
        assert abs(low_z[0] - high_z[0]) > 20, (view, low_z, high_z)
        brighter[view] = "high-z" if high_z[0] > low_z[0] else "low-z"
    assert brighter == {"front": "high-z", "back": "low-z"}


def test_colour_sphere_is_fixed_in_the_world_and_rotates_on_its_own():
    image = make_fixture("frontback", size=40)

    def colours(view, **settings):
        scene = _scene(image, view, size=(96, 96), depth_weight=0.0, sphere_weight=0.6, **settings)
        return _disc_means(scene, scene.screenshot())  # (low-z ball, high-z ball) mean RGB

    def redness(view, **settings):
        return [float(m[0] - m[2]) for m in colours(view, **settings)]  # red - blue

    low_z, high_z = redness("front")  # default: front pole on world +z, facing the camera
    assert high_z > 50 and low_z < -50, "the nearer (high-z) ball is redder"
    low_z, high_z = redness("back")   # the camera moved round: the colours stay in the world
    assert high_z > 50 and low_z < -50
    low_z, high_z = redness("back", sphere_orientation=(0.0, 180.0, 0.0))
    assert low_z > 50 and high_z < -50, "the turned sphere puts red on the (now near) low-z ball"
    low_z, high_z = colours("front", sphere_colors="green-blue")
    assert high_z[1] - high_z[2] > 50 and low_z[2] - low_z[1] > 50  # green front, blue back


# -- stability ---------------------------------------------------------------------
def _slab_and_ball(faint=0.1):
    """A faint slab near the +z side, a bright ball behind it (seen from +z)."""
    k, j, i = np.mgrid[0:32, 0:32, 0:32].astype(float)
    values = np.where((k >= 22) & (k <= 24), faint, 0.0)
    distance = np.sqrt((i - 15.5) ** 2 + (j - 15.5) ** 2 + (k - 9.0) ** 2)
    values = np.maximum(values, np.clip(6.5 - distance, 0.0, 1.0))
    return _image(values)


@pytest.mark.parametrize("eps, finds", [(0.1, "ball"), (0.85, "ball"), (0.95, "slab"), (1.0, "slab")])
def test_large_threshold_finds_the_first_faint_tissue(eps, finds):
    # seen from +z the slab (material 0.1) lies in front of the ball (material 1):
    # eps > 0.9 makes the slab "the same material" as the ball's maximum
    image = _slab_and_ball()
    scene = _scene(image, "front", size=(64, 64), window=(0.0, 1.0), material_threshold=eps)
    depth = render_depth(scene.render_window, scene.mapper)
    centre = depth[30:34, 30:34]
    expected = _reference(scene, "depth", material_threshold=eps)[30:34, 30:34]
    assert np.allclose(centre, expected, atol=1e-5)
    slab, ball = 7.0 / 31.0, 16.0 / 31.0  # depth of the slab's and the ball's front (z = 24, 15)
    assert np.allclose(centre, slab if finds == "slab" else ball, atol=1.5 / 31.0), centre


def test_tiny_threshold_gives_the_depth_of_the_maximum_itself():
    # eps -> 0: "same material" is the maximum's own sample, so the depth follows
    # the position of the maximum, which on noise jumps from pixel to pixel
    image = make_fixture("noise", size=40)
    tiny = _compare(image, "oblique", window="full", material_threshold=1e-9)  # the noise's whole range
    assert tiny["term_masks_disagree"] == 0 and tiny["depth_within_1e-4"] >= 0.995
    assert not np.any(np.isnan(tiny["depth"]) & ~np.isnan(tiny["expected_depth"])), \
        "a match always exists: the maximum's own sample"
    moderate = _compare(image, "oblique", window="full", material_threshold=0.3)
    roughness = {name: np.nanmean(np.abs(np.diff(result["depth"], axis=1)))
                 for name, result in (("tiny", tiny), ("moderate", moderate))}
    assert roughness["tiny"] > 1.5 * roughness["moderate"], roughness


def test_grazing_rays_at_the_box_edges():
    rng = np.random.default_rng(8)
    image = _image(rng.random((9, 9, 9)))

    def edge_on(camera):  # a box edge runs through the middle of the image
        camera.SetFocalPoint(8.0, 8.0, 4.0)
        camera.SetPosition(48.0, 48.0, 4.0)
        camera.SetViewUp(0.0, 0.0, 1.0)
        camera.SetParallelProjection(True)
        camera.SetParallelScale(6.0)

    for mode in DEPTH_MODES:
        _assert_matches(_compare(image, size=(64, 64), camera=edge_on, depth_mode=mode))


def test_flat_background_at_the_floor_stays_background():
    # axis-aligned rays through voxel planes: float rounding of sample positions
    # must not lift the exact-floor background into "tissue"
    for view in ("front", "back"):
        _assert_matches(_compare(make_fixture("frontback", size=48), view, depth_weight=0.3))


@pytest.mark.parametrize("eps", [1e-4, 0.02, 0.07, 0.3, 1.0])
def test_threshold_sweep_equals_a_second_march_from_the_ray_start(eps):
    # the reference marches from the ray start; the shader starts at the level
    # below the maximum's: the depths must agree for every threshold
    _assert_matches(_compare(make_fixture("noise", size=40), "perspective", window=(0.1, 0.9),
                             material_threshold=eps))


# -- related cues: pseudo-chromadepth, LMIP, attenuated MIP, MIDA --------------------
@pytest.mark.parametrize("settings", [
    dict(chroma_depth_weight=0.7),                                          # on DEMIP
    dict(depth_weight=0.0, depth_of="maximum", chroma_depth_weight=0.7),    # on plain MIP
    dict(projection="lmip", local_threshold=0.3),
    dict(projection="attenuated", attenuation=0.2),
    dict(projection="mida"),
], ids=["chroma-demip", "chroma-mip", "lmip", "attenuated", "mida"])
@pytest.mark.parametrize("fixture", ["vessels", "noise"])
def test_related_cues_match_reference(fixture, settings):
    scene = _scene(make_fixture(fixture, size=40), "perspective", window=(0.1, 1.0), **settings)
    result = _compare(scene.image, "perspective", window=(0.1, 1.0), **settings)
    _assert_matches(result)
    values = scene.float_image()
    expected = _reference(scene, "value", **settings)
    assert np.nanmax(np.abs(values - expected)) < 1e-3
    if settings.get("projection") in ("attenuated", "mida"):
        assert np.all(np.isnan(result["depth"])), "no DEMIP term"


@pytest.mark.parametrize("view, nearer", [("front", "high-z"), ("back", "low-z")])
def test_chromadepth_colours_the_nearer_ball_red_and_the_farther_blue(view, nearer):
    image = make_fixture("frontback", size=40)
    for settings in (dict(chroma_depth_weight=1.0), dict(depth_weight=0.0, depth_of="maximum",
                                                         chroma_depth_weight=1.0)):
        scene = _scene(image, view, size=(96, 96), **settings)
        low_z, high_z = _disc_means(scene, scene.screenshot())
        near, far = (high_z, low_z) if nearer == "high-z" else (low_z, high_z)
        assert near[0] > far[0] + 50 and far[2] > near[2] + 50, (near, far)


def test_lmip_shows_the_first_local_maximum_above_its_threshold():
    # seen from +z the faint slab (0.1) comes first: LMIP with a threshold below
    # it shows the slab where MIP shows the ball behind it
    image = _slab_and_ball()
    values = {}
    for threshold in (0.05, 0.2):
        scene = _scene(image, "front", size=(64, 64), window=(0.0, 1.0), depth_weight=0.0,
                       projection="lmip", local_threshold=threshold)
        values[threshold] = scene.float_image()[30:34, 30:34]
        assert np.allclose(values[threshold], _reference(scene, "value", projection="lmip",
                                                         local_threshold=threshold)[30:34, 30:34], atol=1e-5)
    assert np.allclose(values[0.05], 0.1, atol=1e-3)
    assert np.allclose(values[0.2], 1.0, atol=1e-3)


def test_attenuated_mip_without_attenuation_is_mip_and_darkens_with_it():
    image = _slab_and_ball(faint=0.3)
    window = (0.0, 1.0)
    mip = OffscreenView(image, "mip", size=(64, 64), view="oblique", window=window).screenshot()
    greys = []
    for attenuation in (0.0, 0.05, 0.3):
        scene = _scene(image, "oblique", size=(64, 64), window=window, projection="attenuated",
                       attenuation=attenuation)
        greys.append(scene.screenshot()[..., 0].astype(int))
    assert np.abs(greys[0] - mip[..., 0]).max() <= 1
    assert greys[0].sum() > greys[1].sum() > greys[2].sum()


# -- parameters --------------------------------------------------------------------
def test_defaults_and_getters():
    mapper = mipcast.DEMIPVolumeMapper()
    assert mapper.GetDepthWeight() == 0.15 and mapper.GetSphereWeight() == 0.0
    assert mapper.GetDepthMode() == "entry_plus_length" and mapper.GetMaterialThreshold() == 0.1
    assert mapper.GetSphereColors() == SPHERE_PRESETS["red-blue"]
    mapper.SetSphereColors("green-red")
    assert mapper.GetSphereColors() == ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0))
    mapper.SetSphereColors((1, 0.5, 0), (0, 0.6, 1))
    assert mapper.GetSphereColors() == ((1.0, 0.5, 0.0), (0.0, 0.6, 1.0))
    mapper.SetSphereColors(0, 1, 0, 1, 0, 0)  # six numbers, as the command line passes them
    assert mapper.GetSphereColors() == ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0))
    mapper.SetSphereOrientation(0, 90, 0)
    assert np.allclose(mapper.GetSphereOrientation(), [[0, 0, 1], [0, 1, 0], [-1, 0, 0]])
    mapper.SetSphereOrientation(np.eye(3)[[1, 0, 2]] * [[1], [-1], [1]])
    assert np.allclose(np.array(mapper.GetSphereOrientation())[:, 2], [0, 0, 1])


@pytest.mark.parametrize("setter, args, error, words", [
    ("SetDepthWeight", (1.5,), ValueError, ["depth_weight", "[0, 1]"]),
    ("SetDepthWeight", (-0.1,), ValueError, ["depth_weight", "[0, 1]"]),
    ("SetDepthWeight", ("0.2",), TypeError, ["depth_weight", "number"]),
    ("SetDepthWeight", (True,), TypeError, ["depth_weight"]),
    ("SetSphereWeight", (float("nan"),), ValueError, ["sphere_weight", "[0, 1]"]),
    ("SetMaterialThreshold", (0.0,), ValueError, ["material_threshold", "(0, 1]"]),
    ("SetMaterialThreshold", (2.0,), ValueError, ["material_threshold", "(0, 1]"]),
    ("SetDepthMode", ("exact",), ValueError, ["depth_mode", "'entry_plus_length'", "'eye_distance'"]),
    ("SetReadout", ("grey",), ValueError, ["readout", "'depth'"]),
    ("SetSphereColors", ("red-green",), ValueError, ["sphere_colors", "'green-red'"]),
    ("SetSphereColors", ((1, 0, 0),), TypeError, ["sphere_colors", "two RGB"]),
    ("SetSphereColors", ((1, 0, 0), (0, 0, 2)), ValueError, ["back colour", "[0, 1]"]),
    ("SetSphereColors", ((1, 0), (0, 0, 1)), TypeError, ["front colour", "RGB triplet"]),
    ("SetSphereOrientation", ([[1, 0, 0], [0, 1, 0], [0, 0, -1]],), ValueError,
     ["sphere_orientation", "rotation"]),
    ("SetSphereOrientation", ((1, 2),), TypeError, ["sphere_orientation", "3 angles"]),
    ("SetSphereOrientation", ("xyz",), TypeError, ["sphere_orientation"]),
    ("SetChromaDepthWeight", (2,), ValueError, ["chroma_depth_weight", "[0, 1]"]),
    ("SetDepthOf", ("max",), ValueError, ["depth_of", "'maximum'", "'same_material'"]),
    ("SetProjection", ("minip",), ValueError, ["projection", "'lmip'", "'mida'"]),
    ("SetLocalThreshold", (-1,), ValueError, ["local_threshold", "[0, 1]"]),
    ("SetAttenuation", (-0.1,), ValueError, ["attenuation", ">= 0"]),
    ("SetAttenuation", (None,), TypeError, ["attenuation", "number"]),
])
def test_bad_parameters_name_the_parameter_and_range(setter, args, error, words):
    mapper = mipcast.DEMIPVolumeMapper()
    with pytest.raises(error) as raised:
        getattr(mapper, setter)(*args)
    for word in words:
        assert word in str(raised.value), str(raised.value)


def test_reference_checks_its_parameters():
    image = make_fixture("frontback", size=16)
    scene = OffscreenView(image, "mip", size=(16, 16))
    with pytest.raises(TypeError, match="requires parameter.*window"):
        reference.render(image, scene.camera, (16, 16), method="demip", sample_distance=1.0)
    with pytest.raises(TypeError, match="unknown parameter.*depth_wieght"):
        reference.render(image, scene.camera, (16, 16), method="demip", sample_distance=1.0,
                         window=(0, 1), depth_wieght=0.2)
    with pytest.raises(ValueError, match="output"):
        reference.render(image, scene.camera, (16, 16), method="demip", sample_distance=1.0,
                         window=(0, 1), output="grey")
    with pytest.raises(ValueError, match="window"):
        reference.render(image, scene.camera, (16, 16), method="demip", sample_distance=1.0,
                         window=(1, 0))


def test_pieces_follow_the_settings():
    mapper = mipcast.DEMIPVolumeMapper()
    mapper.SetDepthWeight(0.0)
    assert mapper.GetShaderPieces() == mipcast.MIPVolumeMapper.PIECES, "nothing to draw: MIP's pieces"
    mapper.SetChromaDepthWeight(0.5)
    assert "demip_hooks" in mapper.GetShaderPieces()
    mapper.SetProjection("lmip")
    assert "demip_lmip_hooks" in mapper.GetShaderPieces()
    mapper.SetProjection("mida")
    assert {"demip_mida_hooks", "demip_mida_color"} <= set(mapper.GetShaderPieces())
    mapper.SetProjection("attenuated")
    assert "demip_attenuated_hooks" in mapper.GetShaderPieces()


def test_partitioned_rendering_is_refused():
    scene = _scene(make_fixture("frontback", size=24), "front", size=(48, 48))
    assert scene.screenshot().max() > 100
    scene.mapper.SetPartitions(2, 1, 1)
    assert "SetPartitions" in scene.mapper.GetRenderProblem()
    assert scene.screenshot().max() == 0
    scene.mapper.SetPartitions(1, 1, 1)
    assert scene.screenshot().max() > 100


def test_settings_change_uniforms_not_shaders():
    scene = _scene(make_fixture("frontback", size=24), "front", size=(48, 48))
    first = scene.screenshot()
    pieces = scene.mapper.GetShaderPieces()
    scene.mapper.SetDepthWeight(0.6)
    scene.mapper.SetDepthMode("window")
    second = scene.screenshot()
    assert scene.mapper.GetShaderPieces() == pieces
    assert np.abs(first.astype(int) - second.astype(int)).max() > 20


@pytest.mark.slow
@pytest.mark.skipif(__import__("mipcast.data_fixtures", fromlist=["head_ct_path"]).head_ct_path() is None,
                    reason="head CT absent: apt-get install invesalius-examples")
def test_head_ct_face_and_occiput_swap_brightness_with_the_camera():
    # y runs from the occiput (low y) to the face (high y): look along y from
    # the face side, then from the back; a pixel's found point is in the face
    # half when its depth says it is in the near (face view) or far half
    from mipcast.data_fixtures import load_head_ct

    head = load_head_ct()
    x0, x1, y0, y1, z0, z1 = head.GetBounds()
    centre = ((x0 + x1) / 2, (y0 + y1) / 2, (z0 + z1) / 2)
    gain = {}
    for side, sign in (("face", 1.0), ("occiput", -1.0)):
        def aim(camera):
            camera.SetFocalPoint(*centre)
            camera.SetPosition(centre[0], centre[1] + sign * 1000.0, centre[2])
            camera.SetViewUp(0.0, 0.0, 1.0)
            camera.SetParallelProjection(True)
            camera.SetParallelScale(0.55 * (z1 - z0) + 0.3 * (x1 - x0))
        shots = {}
        for weight in (0.0, 0.3):
            scene = _scene(head, "front", size=(96, 96), window=(300.0, 1500.0), depth_weight=weight)
            aim(scene.camera)
            scene.renderer.ResetCameraClippingRange()
            shots[weight] = scene.screenshot()[..., 0].astype(float)
            if weight:
                depth = render_depth(scene.render_window, scene.mapper)
        near = depth < 0.5
        in_face = near if side == "face" else (depth >= 0.5)
        brightening = shots[0.3] - shots[0.0]
        found = ~np.isnan(depth)
        assert found.sum() > 500 and (found & in_face).sum() > 50 and (found & ~in_face).sum() > 50
        gain[side] = (brightening[found & in_face].mean(), brightening[found & ~in_face].mean())
    face_view, occiput_view = gain["face"], gain["occiput"]
    assert face_view[0] > face_view[1] + 10, "seen from the face, the face is brighter"
    assert occiput_view[1] > occiput_view[0] + 10, "seen from the back, the occiput is brighter"


def test_depth_readout_of_8_bit_data_matches_the_same_data_as_float():
    # the depth is read as the shader writes it: no data-unit conversion (nor
    # 8-bit texture factor) may touch it
    values = (np.random.default_rng(4).random((20, 24, 28)) * 200).astype(np.uint8)
    depths = []
    for data in (values, values.astype(np.float32)):
        scene = OffscreenView(image_from_array(data), "demip", size=(48, 48), window=(40.0, 180.0))
        depths.append(render_depth(scene.render_window, scene.mapper))
    both = ~np.isnan(depths[0]) & ~np.isnan(depths[1])
    assert both.mean() > 0.2
    assert np.median(np.abs(depths[0][both] - depths[1][both])) < 1e-4


def test_the_reference_colours_demip_by_a_colour_map():
    """``colour=``: DEMIP's base colour from a function of the values (a colour map); the grey ramp written
    as such a function gives the default picture, a red map only red, and anything else is refused."""
    image = make_fixture("frontback", size=16)
    view = OffscreenView(image, "demip", size=(24, 24))
    low, high = view.window
    settings = dict(sample_distance=view.sample_distance, window=view.window, output="rgb", depth_weight=0.5)
    grey = reference.render(image, view.camera, view.size, "demip", **settings)
    ramp = reference.render(image, view.camera, view.size, "demip", **settings,
                            colour=lambda v: np.repeat(np.clip((v - low) / (high - low), 0, 1)[:, None], 3, axis=1))
    assert np.isfinite(grey).any() and np.array_equal(np.isnan(grey), np.isnan(ramp))
    assert np.nanmax(np.abs(grey - ramp)) < 1e-12
    red = reference.render(image, view.camera, view.size, "demip", **settings,
                           colour=lambda v: np.tile([1.0, 0.0, 0.0], (len(v), 1)))
    hit = np.isfinite(red[..., 0])
    assert np.all(red[hit][:, 0] >= red[hit][:, 1]) and np.nanmax(np.abs(red - grey)) > 0.1
    with pytest.raises(TypeError, match="colour"):
        reference.render(image, view.camera, view.size, "demip", **settings, colour="bone")
