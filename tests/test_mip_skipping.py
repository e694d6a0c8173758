"""Sampled MIP's block skipping: the same picture and the same float readout as reading every sample.

With a window above the background (a transfer-function floor above the data
minimum) sampled MIP starts each ray at the floor, jumps over blocks of cells
whose maximum (block maxima one point wider than the block) is not above the
running maximum, and stops at the ceiling (shaders/mip_hooks_blocks.glsl,
the block section of shaders/sampled_loop.glsl).  Every test compares
``Skipping`` on with ``Skipping`` off (every sample read) pixel for pixel, in
settings that move the samples (perspective, jittering, reduced images,
clipping, slabs, cropping, scaled and rotated volumes).
"""
import numpy as np
import pytest
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPlane
from vtkmodules.util.numpy_support import numpy_to_vtk

from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

SIZE = (96, 80)


def _face_specks(shape=(33, 41, 49), block: int = 8) -> vtkImageData:
    """Dim noise with bright single voxels on and next to the faces of the skipping blocks.

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
    image = vtkImageData()
    image.SetDimensions(shape[2], shape[1], shape[0])
    image.SetSpacing(1.0, 0.9, 1.3)
    image.SetOrigin(-3.0, 2.0, 1.0)
    array = numpy_to_vtk(values.ravel(), deep=True)
    array.SetName("specks")
    image.GetPointData().SetScalars(array)
    return image


@pytest.fixture(scope="module")
def specks():
    return _face_specks()


@pytest.fixture(scope="module")
def vessels():
    return make_fixture("vessels", size=48)


def _pair(image, window, view="oblique", configure=None, readout=False):
    """(skipping on, skipping off): screenshots, or float readouts."""
    out = []
    for skipping in (True, False):
        scene = OffscreenView(image, "mip", size=SIZE, view=view, window=window)
        scene.mapper.SetSkipping(skipping)
        if configure is not None:
            configure(scene)
        out.append(scene.float_image() if readout else scene.screenshot())
        if not readout:
            assert ("mip_hooks_blocks" in scene.mapper.GetShaderPieces()) == skipping
    return out


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
    "rotated volume": lambda s: (s.volume.RotateZ(33.0), s.volume.RotateX(-20.0), s.volume.SetScale(1.0, 1.7, 0.6)),
}


@pytest.mark.parametrize("view", ["oblique", "perspective"])
@pytest.mark.parametrize("name", sorted(CONFIGURATIONS))
def test_specks_on_block_faces_are_never_jumped(specks, view, name):
    on, off = _pair(specks, (0.3, 1.0), view, CONFIGURATIONS[name])
    drawn = off.max(axis=2) > 0
    assert drawn.mean() > 0.005, "the scene must show specks"
    assert np.array_equal(on, off), (np.abs(on.astype(int) - off).max(), np.sum(np.any(on != off, axis=2)))


@pytest.mark.parametrize("window", [(0.25, 1.0), (0.5, 0.7), (0.1, 0.3)])
def test_vessels_picture_is_unchanged(vessels, window):
    on, off = _pair(vessels, window, "perspective")
    assert off.max() > 0
    assert np.array_equal(on, off)


@pytest.mark.parametrize("name", ["plain", "clipping plane", "cropping regions"])
def test_float_readout_is_unchanged(specks, name):
    # the readout turns floor and ceiling off (exact data units) and still jumps blocks below the running maximum
    on, off = _pair(specks, (0.3, 1.0), "oblique", CONFIGURATIONS[name], readout=True)
    assert np.isfinite(off).mean() > 0.2
    assert np.array_equal(on, off, equal_nan=True)


def test_skipping_needs_a_floor(vessels):
    low, high = vessels.GetPointData().GetScalars().GetRange(0)
    full = OffscreenView(vessels, "mip", size=(32, 32), window=(low, high))
    full.screenshot()
    assert "mip_hooks_blocks" not in full.mapper.GetShaderPieces()  # no floor: nothing to jump from the start
    windowed = OffscreenView(vessels, "mip", size=(32, 32), window=(0.25, 1.0))
    windowed.screenshot()
    assert "mip_hooks_blocks" in windowed.mapper.GetShaderPieces()
    assert windowed.mapper.GetMaskInput() is not None


def test_missing_values_keep_their_picture(vessels):
    values = vessels.GetPointData().GetScalars()
    image = vtkImageData()
    image.DeepCopy(vessels)
    array = np.array([values.GetValue(i) for i in range(values.GetNumberOfTuples())], dtype=np.float32)
    array[: array.size // 5] = np.nan
    image.GetPointData().SetScalars(numpy_to_vtk(array, deep=True))
    on, off = _pair(image, (0.25, 1.0), "oblique")
    assert np.array_equal(on, off)
