"""Foveated rendering beyond the GPU's 3D texture limit (mipcast.mappers.bricked_foveated).

The limit is lowered to 20 points per axis for a 48^3 volume: level 0 (48^3, 27 bricks) and
the 24^3 pyramid level (8 bricks) are composited over bricks, then masked and blended by the
levels' own pieces; the picture must be the single-texture foveated picture (same gaze,
radius, levels, content tolerance, silhouette band), and inside the fovea the float readout
the float64 reference on the same rays.
"""
import numpy as np
import pytest

from mipcast.core import foveation
from mipcast.core.object_state import object_state
from mipcast.data_fixtures import make_fixture
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView

LIMIT = 20
SIZE = (80, 72)


@pytest.fixture(scope="module")
def image():
    return make_fixture("vessels", size=48)


def foveated(image, method, tolerance=0.0, limit=None):
    view = OffscreenView(image, "foveated", size=SIZE, view="perspective", window="full")
    mapper = view.mapper
    mapper.SetMethod(method)
    mapper.SetGazePoint(0.4, 0.55)
    mapper.SetFovealRadius(0.15)
    mapper.SetFalloff(0.2)
    mapper.SetContentTolerance(tolerance)
    if limit:
        object_state(mapper)["texture_limit"] = limit  # pretend a small GPU
    return view


@pytest.mark.parametrize("method, tolerance", [("mip", 0.0), ("analytic", 8.0)])
def test_bricked_levels_give_the_single_texture_foveated_picture(image, method, tolerance, tmp_path):
    one, bricked = foveated(image, method, tolerance), foveated(image, method, tolerance, LIMIT)
    expected, got = one.screenshot().astype(int), bricked.screenshot().astype(int)
    mapper = bricked.mapper
    assert mapper.GetLastProblem() is None
    assert mapper.GetNumberOfBricks() == 27 + 8 and one.mapper.GetNumberOfBricks() == 0
    assert one.mapper.GetLastPlan().layers == mapper.GetLastPlan().layers
    grey = np.abs(got - expected).max(axis=-1)
    assert got.max() > 200 and (got.max(axis=-1) > 10).mean() > 0.3  # a picture, not a black frame
    assert (grey <= 1).all()
    if method == "analytic":  # bit for bit (cells lie whole in a brick)
        assert np.array_equal(got, expected)
    else:  # sampled: the outline rays no brick samples get their sample on the CPU (mipcast.mappers.outline_rays)
        assert (grey == 0).mean() >= 0.998 and outline_rays(bricked).sum() >= 3

    # the float readout: the same blended values, and the float64 reference inside the fovea
    low, high = image.GetPointData().GetScalars().GetRange(0)
    values, unbricked = bricked.float_image(), one.float_image()
    assert np.array_equal(np.isnan(values), np.isnan(unbricked))
    agree = np.isnan(values) | (np.abs(values - unbricked) <= 1e-4 * (high - low))  # NaN where both are
    assert agree.all()
    plan = mapper.GetLastPlan()
    fovea = foveation.eccentricity(SIZE, plan.gaze, plan.aspect) < plan.start
    reference = METHODS[method].reference(image, bricked.camera, bricked.size,
                                          sample_distance=bricked.sample_distance, window=bricked.window)
    assert fovea.sum() > 500 and np.isfinite(reference[fovea]).all()
    assert np.array_equal(np.isnan(values[fovea]), np.isnan(reference[fovea]))
    assert np.nanmax(np.abs(values[fovea] - reference[fovea])) / (high - low) <= METHODS[method].reference_tolerance

    cost = mapper.GetLastFrameCost()  # the levels cast what one texture casts; the bricks cast their part
    assert cost["rays"] == one.mapper.GetLastFrameCost()["rays"] and cost["brick_rays"] > 0


def outline_rays(view) -> np.ndarray:
    """Pixels whose level-0 ray no brick can sample on the GPU (mipcast.mappers.outline_rays).

    The whole box's chord is shorter than one step and lies in one brick, while its one
    sample (one step past the entry, clamped back onto the box) falls in a cell of the
    neighbouring brick, which that ray never crosses.  (The float64 rays of the view: a
    prediction, which the CPU's sample of these rays must make agree.)
    """
    from mipcast.core.camera_rays import camera_rays
    from mipcast.mappers.bricks import brick_extents

    image = view.image
    dims = np.array(image.GetDimensions())
    rays = camera_rays(image, view.camera, view.size)
    step = view.sample_distance  # t is a world distance
    short = rays.hit & (rays.t_exit - rays.t_enter < step)
    ends = [rays.origin + t[..., None] * rays.direction for t in (rays.t_enter, rays.t_exit)]
    sample = np.clip(ends[0] + step * rays.direction, 0, dims - 1)
    cell = np.minimum(np.floor(sample), dims - 2)
    boxes = [np.array(e).reshape(3, 2) for e in brick_extents(tuple(dims), LIMIT)]
    crossed = np.zeros(short.shape, dtype=bool)
    for box in boxes:
        owns = np.all((cell >= box[:, 0]) & (cell + 1 <= box[:, 1]), axis=-1)
        # the chord's middle in that brick's box: the ray crosses it (its fragment is drawn)
        middle = 0.5 * (ends[0] + ends[1])
        crossed |= owns & np.all((middle >= box[:, 0] - 1e-6) & (middle <= box[:, 1] + 1e-6), axis=-1)
    return short & ~crossed


def test_a_demip_layer_beyond_the_limit_gives_the_single_texture_foveated_picture(image):
    one, bricked = foveated(image, "demip", 8.0), foveated(image, "demip", 8.0, LIMIT)
    expected, got = one.screenshot().astype(int), bricked.screenshot().astype(int)
    mapper = bricked.mapper
    assert mapper.GetLastProblem() is None
    assert mapper.GetNumberOfBricks() == 27 + 8 and one.mapper.GetNumberOfBricks() == 0
    plan = mapper.GetLastPlan()
    assert one.mapper.GetLastPlan().layers == plan.layers
    grey = np.abs(got - expected).max(axis=-1)
    assert got.max() > 200 and (got.max(axis=-1) > 10).mean() > 0.3  # a picture, not a black frame
    mip = foveated(image, "mip", 8.0).screenshot().astype(int)  # DEMIP's depth term shows: not MIP's picture
    assert (np.abs(got - mip).max(axis=-1) > 10).mean() > 0.1
    assert outline_rays(bricked).sum() >= 3  # some rays whose one sample no brick holds: the CPU's (exact)
    # blended after compositing: where two levels mix, the picture is still the single texture's; there each
    # level's colour (the CPU's composite against the GPU's tables) may round its own way, and the two
    # weighted errors add: a rare mixed pixel 2 grey off (gazes (0.5, 0.5), (0.4, 0.6): 1-2 pixels)
    shares = foveation.blend_shares(plan)
    mixed = np.max(np.stack(list(shares.values())), axis=0) < 1.0 - 1e-6
    assert (grey[~mixed] <= 1).all()
    assert mixed.sum() > 1000 and (grey[mixed] <= 1).mean() >= 0.999 and grey[mixed].max() <= 2
    # the blend weight is the level's (foveated_weight after the composited colour), never a brick's
    bricked_levels = [entry for key, entry in object_state(mapper)["levels_drawn"].items()
                      if isinstance(key, tuple) and key[-1] == "bricks"]
    assert len(bricked_levels) == 2
    for entry in bricked_levels:
        pieces = entry["mapper"].GetShaderPieces()
        assert pieces.index("foveated_brick_color") < pieces.index("foveated_weight")
    source = object_state(mapper)["brick_sources"][0]["mapper"]
    for pair in object_state(source)["demip_bricks"]["entries"]:
        for entry in pair:
            assert "foveated_weight" not in entry["mapper"].GetShaderPieces()
            assert "foveated_skip" in entry["mapper"].GetShaderPieces()  # only the level's rays

    # the float readout: the same blended maxima as the single texture's
    low, high = image.GetPointData().GetScalars().GetRange(0)
    values, unbricked = bricked.float_image(), one.float_image()
    agree = (np.isnan(values) & np.isnan(unbricked)) | (np.abs(values - unbricked) <= 1e-4 * (high - low))
    assert agree.all()


def test_a_demip_layer_without_one_brick_is_not_the_single_texture_picture(image, monkeypatch):
    """The agreement above is no accident: a level missing one brick's part is far off."""
    from mipcast.mappers import bricked_demip

    expected = foveated(image, "demip").screenshot().astype(int)
    bricks_of = bricked_demip.bricks_of

    def one_dropped(mapper, limit, kinds=None):
        bricks = bricks_of(mapper, limit, kinds)
        return bricks[:12] + bricks[13:] if len(bricks) == 27 else bricks  # one of level 0's, in the fovea
    monkeypatch.setattr(bricked_demip, "bricks_of", one_dropped)
    dropped = foveated(image, "demip", limit=LIMIT)
    got = dropped.screenshot().astype(int)
    assert dropped.mapper.GetLastProblem() is None and dropped.mapper.GetNumberOfBricks() == 26 + 8
    grey = np.abs(got - expected).max(axis=-1)
    assert (grey > 1).mean() > 0.015 and grey.max() > 100  # (the test above asks 99.9 % within 1 grey)


def test_bricked_levels_follow_the_users_cropping_and_clipping(image):
    from vtkmodules.vtkCommonDataModel import vtkPlane, vtkPlaneCollection

    pictures = []
    for limit in (None, LIMIT):
        view = foveated(image, "mip", 8.0, limit)
        mapper = view.mapper
        mapper.SetCropping(True)
        mapper.SetCroppingRegionPlanes(0, 30, 0, 47, 0, 47)
        mapper.SetCroppingRegionFlagsToSubVolume()
        plane = vtkPlane()
        plane.SetOrigin(0.0, 0.0, 20.0)
        plane.SetNormal(0.2, 0.0, 1.0)
        planes = vtkPlaneCollection()
        planes.AddItem(plane)
        mapper.SetClippingPlanes(planes)
        pictures.append(view.screenshot().astype(int))
        assert mapper.GetLastProblem() is None and mapper.GetNumberOfBricks() == (35 if limit else 0)
    grey = np.abs(pictures[0] - pictures[1]).max(axis=-1)
    assert pictures[1].max() > 200 and (grey <= 1).mean() >= 0.999
    assert mapper.GetCropping()  # the user's settings are left as they were


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_bricked_levels_draw_missing_values_as_the_single_texture_does(image, method):
    """A ray of missing data only draws nothing in a level drawn from bricks, as in one texture.

    A NaN slab through the vessels: the level-0 rays near the box's corners cross the slab only.
    Until 2026-12-04 a level drawn from bricks drew such a ray as a value of -1e30 (black, and
    -1.9e30 in the float readout) instead of leaving the coarser level beneath (18 pixels up to
    22 grey off the single texture's picture for mip, 20 up to 28 for analytic).
    """
    from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
    from vtkmodules.vtkCommonDataModel import vtkImageData

    values = vtk_to_numpy(image.GetPointData().GetScalars()).astype(np.float32).reshape(48, 48, 48)
    values[20:28] = np.nan  # (z, y, x): a slab of 8 slices
    holed = vtkImageData()
    holed.CopyStructure(image)
    array = numpy_to_vtk(values.ravel(), deep=1)
    array.SetName("scalars")
    holed.GetPointData().SetScalars(array)
    one, bricked = foveated(holed, method), foveated(holed, method, limit=LIMIT)
    expected, got = one.screenshot().astype(int), bricked.screenshot().astype(int)
    assert bricked.mapper.GetLastProblem() is None and bricked.mapper.GetNumberOfBricks() == 27 + 8
    assert got.max() > 200 and (got.max(axis=-1) > 10).mean() > 0.3  # a picture, not a black frame
    grey = np.abs(got - expected).max(axis=-1)
    assert (grey <= 1).all()
    low, high = np.nanmin(values), np.nanmax(values)
    readout, unbricked = bricked.float_image(), one.float_image()
    assert np.array_equal(np.isnan(readout), np.isnan(unbricked)) and np.isnan(readout).sum() > 1000
    assert np.nanmin(readout) >= low  # no ray drawn from the bricks' "no value"
    assert np.nanmax(np.abs(readout - unbricked)) <= 1e-4 * (high - low)


@pytest.mark.parametrize("method", ["mip", "demip"])
def test_bricked_levels_follow_the_slab(image, method):
    """A slab following the camera (SetSlabThickness): the bricks a level composites clip to it as one texture
    does. Until 2026-12-04 they drew the whole volume: the bricks' source is itself a private mapper, so it
    handed its bricks no camera for the slab (here 25 % of the pixels more than 1 grey off the single
    texture's picture, demip 35 %; tests/differential_check.py's vessels 24³ at limit 12, front view: 242
    of 400 fovea pixels off the float64 reference, up to 85 % of the range)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from mipcast.core.clipping import slab_planes

    pictures, values = [], []
    for limit in (None, LIMIT):
        view = foveated(image, method, 0.0, limit)
        view.mapper.SetSlabThickness(7.0)
        pictures.append(view.screenshot().astype(int))
        values.append(view.float_image())
        assert view.mapper.GetLastProblem() is None and view.mapper.GetNumberOfBricks() == (35 if limit else 0)
    grey = np.abs(pictures[0] - pictures[1]).max(axis=-1)
    assert pictures[1].max() > 200 and (grey <= 1).mean() >= 0.999
    full = foveated(image, method, 0.0, LIMIT).screenshot().astype(int)  # the slab shows: not the whole volume
    assert (np.abs(full - pictures[1]).max(axis=-1) > 10).mean() > 0.05
    plan, camera = view.mapper.GetLastPlan(), view.camera
    fovea = foveation.eccentricity(SIZE, plan.gaze, plan.aspect) < plan.start
    reference = METHODS[method].reference(image, camera, view.size, sample_distance=view.sample_distance,
                                          window=view.window, clip_planes=slab_planes(
                                              7.0, camera.GetFocalPoint(), camera.GetDirectionOfProjection()))
    span = np.ptp(vtk_to_numpy(image.GetPointData().GetScalars()))
    assert np.array_equal(np.isnan(values[1][fovea]), np.isnan(reference[fovea])) and fovea.sum() > 500
    assert np.nanmax(np.abs(values[1][fovea] - reference[fovea])) / span <= METHODS[method].reference_tolerance
