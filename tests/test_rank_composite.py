"""The render view's reduction route (mipcast.mappers.rank_composite) on one process, without MPI.

With an identity reduction the composed picture must be the single-texture GPU picture: a rank's
phases, the CPU composite and the colour sphere are checked here in a plain VTK pipeline (the ranks
themselves: tests/test_representation_distributed.py).  Before a fix, phase 2's index readout was
mapped to data units: 93 % of the pixels within one level with the sphere, up to 61 levels off.
"""
import numpy as np
import pytest

from mipcast.mappers import rank_composite
from test_bricked_demip import DEPTH
from test_bricked_mapper import image, picture, pipeline  # noqa: F401  (fixture)


def _identity(values, op):
    return values


@pytest.mark.parametrize("name, mode, sphere", [("demip", "eye_distance", 0.5), ("demip", "steps", 0.0),
                                                ("demip_two_pass", "window", 0.5), ("average", None, 0.0),
                                                ("analytic_average", None, 0.0)])
def test_one_process_reduction_draws_the_single_texture_picture(image, name, mode, sphere):
    mapper, renderer, window = pipeline(image, name)
    renderer.SetBackground(0.0, 0.0, 0.0)
    if mode is not None:
        mapper.SetDepthWeight(DEPTH)
        mapper.SetDepthMode(mode)
        mapper.SetSphereWeight(sphere)
    one = picture(window)
    direction = image.GetDirectionMatrix()
    stub = (tuple(image.GetExtent()), image.GetOrigin(), image.GetSpacing(),
            [direction.GetElement(i, j) for i in range(3) for j in range(3)])
    composed = {}

    def start(caller, event):
        composed["rgba"], composed["problem"] = rank_composite.compose(
            mapper, mapper.GetAttachedVolume(), caller, image, stub, _identity,
            "demip" if mode is not None else "mean")

    renderer.AddObserver("StartEvent", start)
    window.Render()
    assert composed["problem"] is None and composed["rgba"] is not None
    rgb = np.clip(composed["rgba"][..., :3] * 255.0 + 0.5, 0.0, 255.0).astype(int)  # premultiplied, over black
    assert (one.max(axis=-1) > 10).mean() > 0.3
    if sphere > 0:
        assert np.abs(one[..., 0] - one[..., 2]).max() > 30  # the sphere tints
    difference = np.abs(rgb - one).max(axis=-1)
    assert (difference <= 1).mean() >= 0.999, (difference.max(), (difference > 1).sum())
