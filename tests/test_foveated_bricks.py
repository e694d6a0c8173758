"""Foveated rendering beyond the GPU's 3D texture limit (mipcast.mappers.bricked_foveated).

The limit is lowered to 20 points per axis for a 48^3 volume: level 0 (48^3, 27 bricks) and
the 24^3 pyramid level (8 bricks) are composited over bricks, then masked and blended by the
levels' own pieces; the picture must be the single-texture foveated picture (same gaze,
radius, levels, content tolerance, silhouette band), and inside the fovea the float readout
the float64 reference on the same rays.
"""
import numpy as np
import pytest
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

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
    assert (grey <= 1).mean() >= 0.999
    if method == "analytic":  # bit for bit (cells lie whole in a brick)
        assert np.array_equal(got, expected)
    else:  # sampled: a few silhouette rays the bricked draw misses (mipcast.mappers.bricked_draw)
        assert (grey == 0).mean() >= 0.998

    # the float readout: the same blended values, and the float64 reference inside the fovea
    low, high = image.GetPointData().GetScalars().GetRange(0)
    values, unbricked = bricked.float_image(), one.float_image()
    assert np.array_equal(np.isnan(values), np.isnan(unbricked))
    agree = np.isnan(values) | (np.abs(values - unbricked) <= 1e-4 * (high - low))  # NaN where both are
    assert agree.mean() >= 0.999 and (method == "mip" or agree.all())
    plan = mapper.GetLastPlan()
    fovea = foveation.eccentricity(SIZE, plan.gaze, plan.aspect) < plan.start
    reference = METHODS[method].reference(image, bricked.camera, bricked.size,
                                          sample_distance=bricked.sample_distance, window=bricked.window)
    assert fovea.sum() > 500 and np.isfinite(reference[fovea]).all()
    assert np.array_equal(np.isnan(values[fovea]), np.isnan(reference[fovea]))
    assert np.nanmax(np.abs(values[fovea] - reference[fovea])) / (high - low) <= METHODS[method].reference_tolerance

    cost = mapper.GetLastFrameCost()  # the levels cast what one texture casts; the bricks cast their part
    assert cost["rays"] == one.mapper.GetLastFrameCost()["rays"] and cost["brick_rays"] > 0


def test_a_demip_layer_beyond_the_limit_refuses_naming_the_limit_and_the_fix(image):
    refused = foveated(image, "demip", limit=LIMIT)
    captured, previous = vtkStringOutputWindow(), vtkOutputWindow.GetInstance()
    vtkOutputWindow.SetInstance(captured)
    try:
        assert refused.screenshot().max() == 0
    finally:
        vtkOutputWindow.SetInstance(previous)
    problem = refused.mapper.GetLastProblem()
    assert "3D texture limit of 20" in problem and problem in captured.GetOutput()
    assert "'demip'" in problem and "SetMethod" in problem and "resample" in problem
    assert foveated(image, "demip").screenshot().max() > 100  # within one texture it draws


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
