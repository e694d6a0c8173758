"""VTK's reduced buffer (image sample distance above 1) in a viewport away from the window's corner.

VTK clears the buffer, whose texels count from its own corner, under the
renderer's scissor box, which starts at the viewport's corner: the texels
below and left of it kept the last frame's rays (255 grey off a fresh view
after a camera turn, stock VTK too). mipcast's mappers draw in a box from
the window's origin (``private_draw.scissor_from_origin``).
"""
import numpy as np
import pytest
from vtkmodules.vtkRenderingCore import vtkRenderer

from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView


def _subplot(image, method):
    view = OffscreenView(image, method, size=(120, 64))
    view.renderer.SetViewport(0.4, 0.2, 1.0, 1.0)
    other = vtkRenderer()
    other.SetViewport(0.0, 0.0, 0.4, 1.0)
    other.SetBackground(0.2, 0.3, 0.4)
    view.render_window.AddRenderer(other)
    view.mapper.SetAutoAdjustSampleDistances(False)
    view.mapper.SetImageSampleDistance(2.0)
    return view


@pytest.mark.parametrize("method", ["mip", "analytic"])
def test_a_turned_subplot_keeps_no_rays_of_the_last_frame(method):
    image = make_fixture("vessels", size=32)
    turned = _subplot(image, method)
    turned.screenshot()
    turned.camera.Azimuth(40.0)
    picture = turned.screenshot()
    fresh = _subplot(image, method)
    fresh.camera.Azimuth(40.0)
    expected = fresh.screenshot()
    assert expected.max() > 100 and np.array_equal(picture, expected)
    # the other renderer's pixels are its background, untouched
    assert np.array_equal(np.unique(picture[:, :40].reshape(-1, 3), axis=0), [[51, 76, 102]])
