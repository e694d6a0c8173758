"""DEMIP's slab and ordered projections (LMIP, attenuated MIP, MIDA) of a volume beyond the 3D texture limit,
drawn in bricks (mipcast.mappers.bricked_demip, mipcast.mappers.demip_ordered_bricks).

The limit is lowered to 20 points per axis (48^3 fixture: 27 bricks). Each bricked picture is compared
with the single-texture render and its values and depths with the float64 reference (mipcast.reference.demip)
on the same camera rays (MIDA's picture with the opaque grey ramp too); the ordered projections' bricks
are drawn front to back
(mipcast.mappers.brick_rays.visibility_order).
"""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData

from mipcast.core.clipping import slab_planes
from mipcast.mappers.brick_rays import visibility_order
from mipcast.mappers.bricks import brick_extents
from mipcast.mappers.demip import render_depth
from mipcast.mappers.float_readout import render_float
from mipcast.reference.demip import render_demip
from test_bricked_mapper import (DISTANCE, SIZE, _wall, image, lowered, missing_image, picture,  # noqa: F401
                                 pipeline)  # (image, missing_image: fixtures)
from vtk_png import write_png

DEPTH = 0.4
LOCAL = 0.15
NORMAL = (0.3, 0.2, 1.0)
BACKGROUND = np.array([26, 26, 51])


def translucent(image):
    """A coloured, translucent property (MIDA's opacity and colour then matter sample by sample)."""
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

    low, high = image.GetPointData().GetScalars().GetRange(0)
    colour = vtkColorTransferFunction()
    colour.AddRGBPoint(low, 0.1, 0.0, 0.3)
    colour.AddRGBPoint(0.5 * (low + high), 1.0, 0.5, 0.0)
    colour.AddRGBPoint(high, 1.0, 1.0, 0.8)
    opacity = vtkPiecewiseFunction()
    opacity.AddPoint(low, 0.02)
    opacity.AddPoint(high, 0.5)
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    return prop


def set_demip(mapper, projection, slab):
    """The cases' DEMIP settings: depth weight, depth mode, projection, local threshold, the slab."""
    mapper.SetDepthWeight(DEPTH)
    mapper.SetDepthMode("entry_plus_length")
    mapper.SetProjection(projection)
    mapper.SetLocalThreshold(LOCAL)
    if slab:
        mapper.SetSlabThickness(slab)
        mapper.SetSlabNormal(*NORMAL)


def build(image, projection, slab, parallel, camera=None, coloured=False):
    mapper, renderer, window = pipeline(image, "demip")
    if coloured:
        mapper.GetAttachedVolume().SetProperty(translucent(image))
    set_demip(mapper, projection, slab)
    if camera is not None:
        renderer.GetActiveCamera().DeepCopy(camera)
    renderer.GetActiveCamera().SetParallelProjection(parallel)
    return mapper, renderer, window


def render_both(image, projection, slab, parallel, monkeypatch, camera=None, coloured=False):
    """(single texture, bricked): each (rgb, depth, values, camera)."""
    out = []
    for bricked in (False, True):
        if bricked:
            lowered(monkeypatch)
        mapper, renderer, window = build(image, projection, slab, parallel, camera, coloured)
        rgb = picture(window)
        if bricked:
            assert mapper.GetNumberOfBricks() == 27 and mapper.GetLastProblem() is None
        out.append((rgb, render_depth(window, mapper), render_float(window, mapper), renderer.GetActiveCamera()))
    return out


def reference(image, camera, projection, slab, output, window=None):
    settings = dict(sample_distance=DISTANCE, window=window or image.GetPointData().GetScalars().GetRange(0), depth_weight=DEPTH, depth_mode="entry_plus_length",
                    projection=projection, local_threshold=LOCAL)
    if slab:
        planes = (slab, camera.GetFocalPoint(), NORMAL)
        settings.update(clip_planes=slab_planes(*planes), slab=planes)
    return render_demip(image, camera, SIZE, output=output, **settings)


def check(image, one, bricked, projection, slab, coloured=False):
    (one_rgb, one_depth, one_values, _), (rgb, depth, values, camera) = one, bricked
    low, high = image.GetPointData().GetScalars().GetRange(0)
    # the picture: within 1 grey level of the single texture's on >= 99.9 % of the pixels, not blank
    assert (np.abs(rgb - BACKGROUND).max(axis=-1) > 10).mean() > 0.2
    difference = np.abs(rgb - one_rgb).max(axis=-1)
    assert (difference <= 1).mean() >= 0.999, (difference.max(), (difference > 1).sum())
    if projection == "mida" and not coloured:  # the picture is MIDA's composite (opaque grey ramp)
        composite = np.rint(255.0 * reference(image, camera, projection, slab, "rgb"))
        hit = np.isfinite(composite).all(axis=-1)
        assert hit.mean() > 0.2 and (np.abs(rgb[hit] - composite[hit]).max(axis=-1) <= 1).mean() >= 0.999
    # the values: the single texture's and the float64 reference's (same hits, float32 rounding)
    expected = reference(image, camera, projection, slab, "value")
    for other in (one_values, expected):
        assert (np.isnan(values) == np.isnan(other)).mean() >= 0.999
        both = np.isfinite(values) & np.isfinite(other)
        assert np.max(np.abs(values[both] - other[both])) / (high - low) <= 3e-5
    # the depths: the same pixels get a DEMIP term (none for attenuated MIP), at the reference's depth
    expected_depth = reference(image, camera, projection, slab, "depth")
    for other in (one_depth, expected_depth):
        assert (np.isnan(depth) == np.isnan(other)).mean() >= 0.999
        both = np.isfinite(depth) & np.isfinite(other)
        assert not both.any() or (np.abs(depth[both] - other[both]) <= 1e-5).mean() >= 0.999
    if projection in ("attenuated", "mida"):
        assert np.isnan(depth).all()
    else:
        assert np.isfinite(depth).mean() > 0.2
    return expected


@pytest.mark.parametrize("projection, slab, parallel, coloured", [
    ("lmip", 0.0, False, False), ("lmip", 8.0, True, False), ("attenuated", 0.0, True, False),
    ("attenuated", 8.0, False, False), ("mip", 8.0, False, False), ("mida", 0.0, False, False),
    ("mida", 8.0, True, True)])
def test_bricked_demip_projection_and_slab(image, projection, slab, parallel, coloured, monkeypatch, tmp_path):
    one, bricked = render_both(image, projection, slab, parallel, monkeypatch, coloured=coloured)
    expected = check(image, one, bricked, projection, slab, coloured)
    if projection in ("lmip", "attenuated"):  # the projection is not MIP on a good share of the rays
        mip = reference(image, bricked[3], "mip", slab, "value")
        low, high = image.GetPointData().GetScalars().GetRange(0)
        both = np.isfinite(mip) & np.isfinite(expected)
        assert (np.abs(mip[both] - expected[both]) > 1e-3 * (high - low)).mean() > 0.02
    if coloured:  # translucent and coloured: the background shows through, the picture has hues
        assert np.abs(bricked[0][..., 0] - bricked[0][..., 2]).max() > 30
    write_png(tmp_path / f"bricked_{projection}_{slab:g}.png", np.concatenate([one[0], bricked[0]], axis=1)
              .astype(np.uint8))


@pytest.mark.parametrize("projection, coloured", [("mip", False), ("mida", True)])
def test_with_msaa_bricked_demip_gets_the_single_texture_silhouette(image, projection, coloured, monkeypatch):
    """8x MSAA: the pixels next to a box face whose centre lies off it get that face's fragment of the single
    texture (mipcast.mappers.bricked_demip.face_picture: its rays from the face's plane, their maximum and
    first same-material sample, depth from the ray's start, Eq. 1; MIDA's composite of the transfer
    functions): every pixel within one level (drawn through the faces without them: 80 pixels off by up to
    80 levels for mip, 3 by 2 for the translucent MIDA; 88 by 19 with the opaque grey ramp)."""
    pictures = []
    for bricked in (False, True):
        if bricked:
            lowered(monkeypatch)
        mapper, _, window = build(image, projection, 0.0, False, coloured=coloured)
        window.SetMultiSamples(8)
        pictures.append(picture(window))
    assert mapper.GetNumberOfBricks() == 27 and mapper.GetLastProblem() is None
    assert (np.abs(pictures[1] - BACKGROUND).max(axis=-1) > 10).mean() > 0.3  # drawn, not blank
    difference = np.abs(pictures[1] - pictures[0]).max(axis=-1)
    assert difference.max() <= 1, [(int(y), int(x), int(difference[y, x])) for y, x in zip(*np.nonzero(difference > 1))]


@pytest.mark.parametrize("projection, scene, samples", [
    ("lmip", "opaque wall", 0), ("attenuated", "opaque wall", 8), ("mida", "opaque wall", 0),
    ("attenuated", "missing values", 0), ("mida", "missing values", 8)])
def test_bricked_ordered_projections_end_at_geometry_and_take_missing_values(image, missing_image, projection, scene,
                                                                            samples, monkeypatch):
    """Opaque geometry: the ordered bricks' rays end where the whole volume's ray ends (the scene depth in their
    state texture's alpha, ``whole_ray_end``); they ended at the far plane (an opaque wall through the centre:
    296-844 pixels off by up to 183 levels).  Missing values: no per-brick missing test on a material
    (attenuated) or on 0 (MIDA), the whole ray's on the CPU (1201-1583 pixels were off by up to 196 levels)."""
    pictures, values = [], []
    for bricked in (False, True):
        if bricked:
            lowered(monkeypatch)
        mapper, renderer, window = build(missing_image if scene == "missing values" else image, projection, 0.0,
                                         False)
        window.SetMultiSamples(samples)
        if scene == "opaque wall":
            _wall(renderer, image)
        pictures.append(picture(window))
        if not samples:
            values.append(render_float(window, mapper))
    assert mapper.GetNumberOfBricks() == 27 and mapper.GetLastProblem() is None
    assert (np.abs(pictures[1] - BACKGROUND).max(axis=-1) > 10).mean() > 0.3  # drawn, not blank
    difference = np.abs(pictures[1] - pictures[0]).max(axis=-1)
    assert difference.max() <= 1, [(int(y), int(x), int(difference[y, x])) for y, x in zip(*np.nonzero(difference > 1))]
    if values:
        one, got = values
        low, high = image.GetPointData().GetScalars().GetRange(0)
        assert (np.isnan(one) == np.isnan(got)).all() and np.isfinite(got).mean() > 0.3
        both = np.isfinite(one) & np.isfinite(got)
        assert np.max(np.abs(got[both] - one[both])) / (high - low) <= 3e-5


def two_peaks(size=48):
    """Along z: a first local maximum (0.6) on the bricks' shared layer z = 16, a higher one (1.0) at z = 38."""
    z = np.arange(size, dtype=float)
    profile = 0.6 * np.clip(1.0 - np.abs(z - 16.0) / 5.0, 0.0, None) + np.clip(1.0 - np.abs(z - 38.0) / 5.0, 0.0, None)
    x = np.arange(size, dtype=float)
    modulation = 0.8 + 0.2 * np.cos(x / 7.0)[None, None, :] * np.cos(x / 9.0)[None, :, None]
    values = (profile[:, None, None] * modulation).astype(np.float32)  # (z, y, x)
    image = vtkImageData()
    image.SetDimensions(size, size, size)
    image.GetPointData().SetScalars(numpy_to_vtk(values.ravel(), deep=True))
    return image


@pytest.mark.parametrize("parallel", [False, True])
def test_bricked_lmip_first_local_maximum_on_a_brick_border(parallel, monkeypatch, tmp_path):
    """The first local maximum lies on the shared layer z = 16: its rise is in the bricks in front, its fall
    in the bricks behind; the running maximum crosses with the float texture, so LMIP ends there (value
    about 0.6 x modulation), not at the global maximum behind (1.0 x modulation)."""
    from vtkmodules.vtkRenderingCore import vtkCamera

    image = two_peaks()
    camera = vtkCamera()
    camera.SetFocalPoint(23.5, 23.5, 23.5)
    camera.SetPosition(30.0, 18.0, -90.0)  # from the low-z side: the z = 16 peak is in front
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetViewAngle(30.0)
    camera.SetParallelScale(30.0)
    one, bricked = render_both(image, "lmip", 0.0, parallel, monkeypatch, camera)
    check(image, one, bricked, "lmip", 0.0)
    values = bricked[2]
    hit = np.isfinite(values)
    assert hit.mean() > 0.3 and (values[hit] < 0.62).mean() > 0.95  # the first peak, not the second (>= 0.6)
    write_png(tmp_path / "bricked_lmip_border.png", np.concatenate([one[0], bricked[0]], axis=1).astype(np.uint8))


@pytest.mark.parametrize("eye", [(-30.0, 10.0, 60.0, 1.0), (20.0, 25.0, 40.0, 1.0), (0.0, 0.0, 0.0, 0.0)])
def test_visibility_order_puts_every_brick_after_the_bricks_a_ray_crosses_first(eye):
    extents = brick_extents((48, 48, 48), 20)
    starts = [sorted({e[2 * a] for e in extents}) for a in range(3)]
    index_of = {tuple(starts[a].index(e[2 * a]) for a in range(3)): i for i, e in enumerate(extents)}
    rng = np.random.default_rng(3)
    for direction in rng.normal(size=(40, 3)):
        rays = {"u_mc_rayEye": list(eye), "u_mc_rayDirection": list(direction)}
        rank = {index: position for position, index in enumerate(visibility_order(extents, rays))}
        start = np.array(eye[:3]) if eye[3] else np.full(3, 23.5) - 60.0 * direction / np.linalg.norm(direction)
        points = start + np.linspace(0.0, 200.0, 4000)[:, None] * direction / np.linalg.norm(direction)
        points = points[np.all((points >= 0) & (points < 47), axis=1)]
        cell = np.stack([np.searchsorted(starts[a], points[:, a], side="right") - 1 for a in range(3)], axis=1)
        owners = [index_of[tuple(c)] for c in cell]
        seen = [o for k, o in enumerate(owners) if k == 0 or owners[k - 1] != o]
        assert [rank[i] for i in seen] == sorted(rank[i] for i in seen), (direction, seen)


def one_side(image, value):
    """``image`` with its points x >= 31 (the last layer of bricks along x, bricks (31, 47, ...)) set to
    ``value`` (float32): air beside a patient (the minimum), or NaN where a mask hides them."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32).reshape(48, 48, 48).copy()
    values[:, :, 31:] = value
    out = vtkImageData()
    out.DeepCopy(image)
    out.GetPointData().SetScalars(numpy_to_vtk(values.ravel(), deep=True))
    return out


@pytest.mark.parametrize("side, projection", [("air", "lmip"), ("mask", "lmip"), ("mask", "attenuated")])
def test_bricked_ordered_projections_carry_their_state_through_a_brick_of_one_value(image, side, projection,
                                                                                   monkeypatch, tmp_path):
    """A brick holding one value (all air, or all points a mask hides, SetMaskInput) normalises over VTK's
    widened range, 1e-6 data units wide (vtkVolumeTexture::GetScaleAndBias), not 1: LMIP's running maximum
    carried into such a brick came back as the brick's value (differential case 1483: 161 of 557 pixels, up
    to 1.57 of the range off; here the rays from the low-x side whose scan had not ended when they reached
    the bricks x >= 31)."""
    from vtkmodules.vtkRenderingCore import vtkCamera

    low, high = image.GetPointData().GetScalars().GetRange(0)
    drawn = one_side(image, low) if side == "air" else image
    seen = one_side(image, np.nan) if side == "mask" else drawn  # what the reference sees: hidden is NaN
    mask = None
    if side == "mask":
        mask = vtkImageData()
        mask.CopyStructure(image)
        keep = np.ones((48, 48, 48), np.uint8)
        keep[:, :, 31:] = 0
        mask.GetPointData().SetScalars(numpy_to_vtk(keep.ravel(), deep=True))
    camera = vtkCamera()
    camera.SetFocalPoint(23.5, 18.8, 28.2)
    camera.SetPosition(-70.0, 35.0, 50.0)  # from the low-x side: the bricks x >= 31 are behind
    camera.SetViewUp(0.0, 1.0, 0.0)
    camera.SetViewAngle(30.0)
    values, rgbs = [], []
    for bricked in (False, True):
        if bricked:
            lowered(monkeypatch)
        mapper, renderer, window = build(drawn, projection, 0.0, False, camera)
        if mask is not None:
            mapper.SetMaskInput(mask)
        rgbs.append(picture(window))
        values.append(render_float(window, mapper))
        assert mapper.GetNumberOfBricks() == (27 if bricked else 0) and mapper.GetLastProblem() is None
    write_png(tmp_path / f"bricked_{projection}_{side}.png", np.concatenate(rgbs, axis=1).astype(np.uint8))
    expected = reference(seen, camera, projection, 0.0, "value", window=(low, high))
    one, got = values
    assert np.isfinite(expected).mean() > 0.3 and (np.isnan(got) == np.isnan(expected)).mean() >= 0.999
    for other in (one, expected):
        both = np.isfinite(got) & np.isfinite(other)
        assert np.max(np.abs(got[both] - other[both])) / (high - low) <= 3e-5
    difference = np.abs(rgbs[1] - rgbs[0]).max(axis=-1)
    assert (difference <= 1).mean() >= 0.999, (difference.max(), (difference > 1).sum())


@pytest.mark.parametrize("projection", ["lmip", "attenuated"])
def test_bricked_ordered_projections_window_the_component_drawn(image, projection, monkeypatch, tmp_path):
    """Three components (x 0.2, x 1, x 0.5 the fixture) drawing component 1 under a window inside its range
    and above component 0's: the bricks' material window and LMIP's threshold come from the values drawn
    (the rendered input's range, as the single texture's), not from component 0's range (until 2026-12-05
    LMIP 0.49 and attenuated MIP 0.71 of the range off here; differential case 3250, the magnitude of
    vectors cropped in bricks, 90 pixels up to 0.58)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from mipcast.offscreen import grey_property

    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32)
    low, high = float(values.min()), float(values.max())
    vectors = vtkImageData()
    vectors.DeepCopy(image)
    vectors.GetPointData().SetScalars(numpy_to_vtk(np.stack([0.2 * values, values, 0.5 * values], axis=1),
                                                   deep=True))
    window = (low + 0.3 * (high - low), low + 0.9 * (high - low))
    assert window[0] > 0.2 * high  # (the window lies above every value of component 0)
    drawn = []
    for bricked in (False, True):
        if bricked:
            lowered(monkeypatch)
        mapper, renderer, render_window = build(vectors, projection, 0.0, False)
        mapper.SetComponent(1)
        mapper.GetAttachedVolume().SetProperty(grey_property(window))
        drawn.append((picture(render_window), render_float(render_window, mapper)))
        assert mapper.GetNumberOfBricks() == (27 if bricked else 0) and mapper.GetLastProblem() is None
    (one_rgb, one), (rgb, got) = drawn
    write_png(tmp_path / f"bricked_{projection}_component.png", np.concatenate([one_rgb, rgb], axis=1).astype(np.uint8))
    camera = renderer.GetActiveCamera()
    settings = dict(sample_distance=DISTANCE, window=window, depth_weight=DEPTH, depth_mode="entry_plus_length",
                    projection=projection, local_threshold=LOCAL, component=1)
    expected = render_demip(vectors, camera, SIZE, output="value", **settings)
    assert np.isfinite(expected).mean() > 0.3 and (np.isnan(got) == np.isnan(expected)).mean() >= 0.999
    for other in (one, expected):
        both = np.isfinite(got) & np.isfinite(other)
        assert np.max(np.abs(got[both] - other[both])) / (high - low) <= 3e-5
    assert (np.abs(rgb - one_rgb).max(axis=-1) <= 1).mean() >= 0.999
