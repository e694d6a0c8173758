"""TIFF stacks as microscopes and Fiji write them (mipcast.io.tiff): axes, spacing, time points, channels,
placement as Fiji shows them, damaged files."""
import warnings

import numpy as np
import pytest
import tifffile
from vtkmodules.util.numpy_support import vtk_to_numpy

from mipcast.io import read_volume
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView

RNG = np.random.default_rng(7)
STACK = RNG.integers(0, 4000, (4, 6, 2, 20, 16), dtype=np.uint16)  # T Z C Y X


def values_of(image):
    scalars = vtk_to_numpy(image.GetPointData().GetScalars())
    nx, ny, nz = image.GetDimensions()
    return scalars.reshape(nz, ny, nx, -1) if scalars.ndim == 2 else scalars.reshape(nz, ny, nx)


@pytest.fixture(scope="module")
def hyperstack(tmp_path_factory):
    """Fiji's Save As > Tiff of a 2-channel time series, LZW-compressed (Bio-Formats' exporter option)."""
    path = tmp_path_factory.mktemp("tiff") / "hyper.tif"
    tifffile.imwrite(path, STACK, imagej=True, compression="lzw", resolution=(1 / 0.2, 1 / 0.25),
                     metadata={"axes": "TZCYX", "spacing": 1.5, "unit": "micron"})
    return path


def test_an_imagej_hyperstack_reads_its_spacing_channels_and_time_points(hyperstack):
    with pytest.warns(UserWarning, match=r"holds 4 time points \(T\); the first is read: pass volume=K"):
        image = read_volume(hyperstack)
    assert image.GetDimensions() == (16, 20, 6)
    assert np.allclose(image.GetSpacing(), (0.2, 0.25, 1.5))
    assert np.array_equal(values_of(image), np.moveaxis(STACK[0], 1, -1))  # channels as components
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        third = read_volume(hyperstack, volume=2)
    assert np.array_equal(values_of(third), np.moveaxis(STACK[2], 1, -1))
    with pytest.raises(ValueError, match=r"holds 4 time points \(T; volume 0 to 3\); there is no volume 4"):
        read_volume(hyperstack, volume=4)


def test_ome_tiff_sizes_are_converted_to_micrometres(tmp_path):
    path = tmp_path / "cells.ome.tif"
    tifffile.imwrite(path, STACK[0, :, 0], ome=True, compression="zlib",
                     metadata={"axes": "ZYX", "PhysicalSizeX": 150.0, "PhysicalSizeXUnit": "nm",
                               "PhysicalSizeY": 0.15, "PhysicalSizeZ": 0.002, "PhysicalSizeZUnit": "mm"})
    image = read_volume(path)
    assert np.allclose(image.GetSpacing(), (0.15, 0.15, 2.0))
    assert np.array_equal(values_of(image), STACK[0, :, 0])


def test_plain_pages_and_rgb_pages(tmp_path):
    plain, rgb = tmp_path / "plain.tif", tmp_path / "rgb.tif"
    with tifffile.TiffWriter(plain) as writer:  # pages written one by one, no shape metadata
        for page in STACK[0, :, 1]:
            writer.write(page, metadata=None, resolution=(72.0, 72.0))  # a printer's resolution: not a spacing
    colours = RNG.integers(0, 255, (5, 20, 16, 3), dtype=np.uint8)
    tifffile.imwrite(rgb, colours, photometric="rgb")
    image = read_volume(plain)
    assert image.GetSpacing() == (1.0, 1.0, 1.0) and np.array_equal(values_of(image), STACK[0, :, 1])
    assert np.array_equal(values_of(read_volume(rgb)), colours)


def test_the_front_views_analytic_mip_is_fijis_z_projection(tmp_path):
    """Placed as Fiji shows the stack (x right, the first row at the top, the first slice nearest the front
    view's eye): the front view's analytic MIP has a blob of the first slice's top-left at its top-left and
    one of the last slice's bottom-right at its bottom-right, and it is the float64 reference's.  (The sampled
    mip there does not sample the first slice: VTK's first sample lies one step past the box's entry.)"""
    stack = np.zeros((6, 20, 16), np.float32)
    stack[0, 2:6, 2:6] = 1.0  # first slice, top-left
    stack[5, 14:18, 10:14] = 0.6  # last slice, bottom-right
    path = tmp_path / "blobs.tif"
    tifffile.imwrite(path, stack, imagej=True, metadata={"axes": "ZYX"})
    image = read_volume(path)
    scene = OffscreenView(image, "analytic", size=(64, 80), view="front", window=(0.0, 1.0))
    got = scene.float_image()
    expected = METHODS["analytic"].reference(image, scene.camera, scene.size, window=scene.window)
    assert np.array_equal(np.isnan(got), np.isnan(expected))
    assert np.nanmax(np.abs(got - expected)) <= METHODS["analytic"].reference_tolerance
    rows, columns = got.shape
    top_left, bottom_right = got[:rows // 2, :columns // 2], got[rows // 2:, columns // 2:]
    assert np.nanmax(top_left) > 0.99 and np.nanmax(bottom_right) == pytest.approx(0.6, abs=1e-3)
    assert np.nanmax(got[:rows // 2, columns // 2:]) < 0.01 and np.nanmax(got[rows // 2:, :columns // 2]) < 0.01
    nearest, farthest = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]  # the first slice is the one nearest the eye
    image.TransformIndexToPhysicalPoint(0, 0, 0, nearest)
    image.TransformIndexToPhysicalPoint(0, 0, 5, farthest)
    eye = np.array(scene.camera.GetPosition())
    assert np.linalg.norm(eye - np.array(nearest)) < np.linalg.norm(eye - np.array(farthest))


def test_axes_that_cannot_be_placed_and_damaged_files_say_so(tmp_path, hyperstack):
    odd = tmp_path / "rotations.tif"
    tifffile.imwrite(odd, np.zeros((3, 4, 20, 16), np.uint8), photometric="minisblack", metadata={"axes": "ZRYX"})
    with pytest.raises(ValueError, match=r"its axes are ZRYX .*R \(4\) cannot be placed: save one volume per file"):
        read_volume(odd)
    garbage = tmp_path / "garbage.tif"
    garbage.write_bytes(b"II*\x00" + bytes(range(40)))
    with pytest.raises(ValueError, match=r"cannot read '.*garbage.tif' as TIFF"):
        read_volume(garbage)
    cut = tmp_path / "cut.tif"
    data = hyperstack.read_bytes()
    cut.write_bytes(data[:len(data) // 2])  # the first time point whole, the rest gone
    with pytest.warns(UserWarning, match="is damaged .*the volume read is whole"):
        first = read_volume(cut, volume=0)
    assert np.array_equal(values_of(first), np.moveaxis(STACK[0], 1, -1))
    with pytest.raises(ValueError, match="damaged or incomplete"):
        read_volume(cut, volume=3)
    single, planar = tmp_path / "single.tif", tmp_path / "planar.tif"
    tifffile.imwrite(single, STACK[0, 0, 0])
    tifffile.imwrite(planar, STACK[0, :4, 0], photometric="rgb", planarconfig="separate")  # 4 planes of 1 image
    for path, axes in ((single, "YX"), (planar, "SYX")):
        with pytest.raises(ValueError, match=rf"holds one 2D image \(axes {axes}, .*a projection needs at least 2 "
                                             "slices"):
            read_volume(path)


def test_every_pixel_type_a_stack_holds(tmp_path):
    """Half floats (VTK has no such type: float32, every value exact), bits (uint8), and the others as they are."""
    for dtype in (np.float16, np.uint8, np.int8, np.uint32, np.int64, np.float64, bool):
        values = (RNG.random((3, 8, 6)) * 100).astype(dtype)
        path = tmp_path / f"{np.dtype(dtype).name}.tif"
        tifffile.imwrite(path, values, photometric="minisblack")
        image = read_volume(path)
        drawn = values_of(image)
        assert drawn.dtype == {np.float16: np.float32, bool: np.uint8}.get(dtype, np.dtype(dtype)), dtype
        assert np.array_equal(drawn, values.astype(drawn.dtype)), dtype


def test_the_cli_renders_a_time_point_and_channel_of_a_stack(tmp_path, hyperstack):
    from matplotlib import pyplot

    from mipcast.app.cli import main

    shots = {}
    for name, extra in (("t1c0", ["--volume", "1", "--component", "0"]), ("t1c1", ["--volume", "1", "--component", "1"])):
        out = tmp_path / f"{name}.png"
        assert main(["render", str(hyperstack), "--out", str(out), "--size", "48", "40", "--view", "front",
                     "--window", "0", "4000"] + extra) == 0
        shots[name] = pyplot.imread(out)[..., :3]
    assert shots["t1c0"].max() > 0.5 and not np.array_equal(shots["t1c0"], shots["t1c1"])
