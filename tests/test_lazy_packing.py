"""Analytic MIP's first frame of a large input is drawn unpacked, exact; the packed copy follows (issue #14).

The packed-corner copy (four times the volume) is made in a background
thread after the first frame and drawn from the first frame that finds it
ready; small inputs (packed copy <= LAZY_PACKING_BYTES) pack at once.
"""
import time

import numpy as np
import pytest
from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLGPUVolumeRayCastMapper

from mipcast import reference
from mipcast.core.object_state import object_state
from mipcast.data_fixtures import image_from_array
from mipcast.mappers.analytic import AnalyticMIPVolumeMapper
from mipcast.offscreen import OffscreenView

SIZE = (72, 64)


def _values():
    rng = np.random.default_rng(14)
    return (rng.random((24, 28, 26)) ** 4 * 3000 - 1000).astype(np.int16)


def _volume(values=None):
    return image_from_array(_values() if values is None else values, spacing=(0.9, 1.0, 1.3))


def _components(view) -> int:
    """Components of what VTK draws: 4 = the packed copy, 1 = the volume itself."""
    return vtkOpenGLGPUVolumeRayCastMapper.GetInput(view.mapper).GetPointData().GetScalars().GetNumberOfComponents()


def _render_until_packed(view, seconds=20.0) -> int:
    """Render until the packed copy is drawn; the number of frames that took."""
    frames, deadline = 0, time.monotonic() + seconds
    while _components(view) != 4 and time.monotonic() < deadline:
        view.render_window.Render()
        frames += 1
        time.sleep(0.01)
    return frames


def test_large_input_first_frame_is_unpacked_exact_and_packing_follows(monkeypatch):
    # the CT's case at test size: the packed copy over the automatic limit
    monkeypatch.setattr(AnalyticMIPVolumeMapper, "LAZY_PACKING_BYTES", 1024)
    image = _volume()
    view = OffscreenView(image, "analytic", size=SIZE, window="full")
    packer = object_state(view.mapper)["packer"]
    assert view.mapper.GetPackingDelay() == -1  # automatic
    first = view.float_image()  # the first frame: drawn unpacked, nothing packed in it
    assert _components(view) == 1
    assert packer.GetOutputDataObject(0).GetNumberOfPoints() == 0  # the packer never ran
    assert "amip_corners_packed" not in view.mapper.GetShaderPieces()
    exact = reference.render(image, view.camera, SIZE, method="analytic")
    low, high = view.window
    hits = ~np.isnan(exact) & ~np.isnan(first)
    assert hits.mean() > 0.1
    assert np.mean(np.abs(first[hits] - exact[hits]) / (high - low) <= 1e-3) >= 0.999
    assert view.mapper.GetTextureBytes() == 4 * 2 * 24 * 28 * 26 + 3 * 4 * 4 * 4  # the steady state: packed
    assert _render_until_packed(view) >= 1  # made in the background, drawn once ready
    assert "amip_corners_packed" in view.mapper.GetShaderPieces()
    packed = view.float_image()
    # the steady state draws what packing at once draws, bit for bit; so does the unpacked first frame
    at_once = OffscreenView(image, "analytic", size=SIZE, window="full")
    at_once.mapper.SetPackingDelay(0)
    reference_float = at_once.float_image()
    assert _components(at_once) == 4
    assert np.array_equal(packed, reference_float, equal_nan=True)
    assert np.array_equal(first, reference_float, equal_nan=True)
    assert np.array_equal(view.screenshot(), at_once.screenshot())
    # a new input starts unpacked again
    view.set_input(_volume(np.ascontiguousarray(_values()[::-1])))
    view.render_window.Render()
    assert _components(view) == 1
    assert _render_until_packed(view) >= 1


def test_small_input_packs_for_the_first_frame_and_delays_are_checked():
    view = OffscreenView(_volume(), "analytic", size=SIZE, window="full")
    view.render_window.Render()
    assert _components(view) == 4  # 24x28x26 int16: 140 KiB packed, under LAZY_PACKING_BYTES
    view.mapper.SetPackingDelay(2)  # the same input: already packed, stays packed
    view.render_window.Render()
    assert _components(view) == 4
    for bad in (-2, 1.5, True, "1"):
        with pytest.raises(ValueError, match="packing delay"):
            view.mapper.SetPackingDelay(bad)


def test_switching_from_one_to_four_components_between_frames():
    # VTK 9.7 crashed drawing the packed copy where it had drawn the one-component volume
    view = OffscreenView(_volume(), "analytic", size=SIZE, window="full")
    view.mapper.SetPackedCorners(False)
    unpacked = view.screenshot()
    view.mapper.SetPackedCorners(True)
    assert np.array_equal(view.screenshot(), unpacked)
    assert _components(view) == 4 and unpacked.max() > 100
