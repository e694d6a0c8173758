"""DEMIP of a volume beyond the 3D texture limit, drawn in bricks inside the user's render
(mipcast.mappers.bricked_demip: the two phases of distributed DEMIP over local bricks).

The limit is lowered to 20 points per axis, so the 48^3 fixture is drawn in 3 x 3 x 3 bricks;
the picture is compared with the single-texture DEMIP render, the depth and the maximum with it
and with the float64 reference (mipcast.reference.demip) on the same camera rays.
"""
import numpy as np
import pytest

from mipcast.core.object_state import object_state
from mipcast.mappers.demip import render_depth
from mipcast.mappers.float_readout import render_float
from mipcast.methods import METHODS
from mipcast.reference.demip import render_demip
from test_bricked_mapper import DISTANCE, SIZE, image, lowered, picture, pipeline  # noqa: F401  (fixture)

DEPTH = 0.4
BACKGROUND = np.array([26, 26, 51])


def build(image, name, mode, sphere):
    mapper, renderer, window = pipeline(image, name)
    mapper.SetDepthWeight(DEPTH)
    mapper.SetDepthMode(mode)
    mapper.SetSphereWeight(sphere)
    return mapper, renderer, window


@pytest.mark.parametrize("name, mode, sphere", [("demip", "entry_plus_length", 0.0), ("demip", "eye_distance", 0.5),
                                                ("demip", "steps", 0.0), ("demip", "steps", 0.5),
                                                ("demip_two_pass", "window", 0.5)])
def test_bricked_demip_draws_the_single_texture_picture(image, name, mode, sphere, monkeypatch, tmp_path):
    one_mapper, _, one_window = build(image, name, mode, sphere)
    one_rgb, one_depth = picture(one_window), render_depth(one_window, one_mapper)
    one_values = render_float(one_window, one_mapper)

    lowered(monkeypatch)
    mapper, renderer, window = build(image, name, mode, sphere)
    rgb = picture(window)
    assert mapper.GetNumberOfBricks() == 27 and mapper.GetLastProblem() is None
    if name == "demip_two_pass":  # its own pass 1 (the whole volume in one texture) is never drawn
        assert "first_pass" not in object_state(mapper)
    depth, values = render_depth(window, mapper), render_float(window, mapper)
    low, high = image.GetPointData().GetScalars().GetRange(0)

    # the picture: within 2 grey levels of the single texture's on >= 99.9 % of the pixels, not blank
    assert (np.abs(rgb - BACKGROUND).max(axis=-1) > 10).mean() > 0.3
    difference = np.abs(rgb - one_rgb).max(axis=-1)
    assert (difference <= 2).mean() >= 0.999, (difference.max(), (difference > 2).sum())
    if sphere > 0:  # the sphere tints: the picture is coloured
        assert np.abs(rgb[..., 0] - rgb[..., 2]).max() > 30
    # the same pixels get a DEMIP term, at the same depth (float32 rounding)
    assert (np.isnan(depth) == np.isnan(one_depth)).mean() >= 0.999 and np.isfinite(depth).mean() > 0.2
    both = np.isfinite(depth) & np.isfinite(one_depth)
    assert (np.abs(depth[both] - one_depth[both]) <= 1e-5).mean() >= 0.999
    # against the float64 reference on the same rays: depth, and the value within the table tolerance
    settings = dict(sample_distance=DISTANCE, window=(low, high), depth_weight=DEPTH, depth_mode=mode,
                    sphere_weight=sphere)
    camera = renderer.GetActiveCamera()
    reference = render_demip(image, camera, SIZE, output="depth", **settings)
    assert (np.isnan(depth) == np.isnan(reference)).mean() >= 0.999
    near = np.isfinite(depth) & np.isfinite(reference)
    assert (np.abs(depth[near] - reference[near]) <= 1e-5).mean() >= 0.999
    expected = render_demip(image, camera, SIZE, output="value", **settings)
    assert (np.isnan(values) == np.isnan(expected)).mean() >= 0.999
    both = np.isfinite(values) & np.isfinite(expected)
    assert np.max(np.abs(values[both] - expected[both])) / (high - low) <= METHODS[name].reference_tolerance
    assert np.max(np.abs(values[both] - one_values[both])) / (high - low) <= 1e-4
    if mode == "steps" and sphere > 0:
        from vtk_png import write_png

        write_png(tmp_path / "bricked_demip.png", np.concatenate([one_rgb, rgb], axis=1).astype(np.uint8))
