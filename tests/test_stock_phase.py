"""VTK's own GPU MIP / MinIP drawing pieces of a volume on the whole volume's sample positions (issue #18).

In a parallel render view each rank's piece of ``stock`` / ``stock_minip`` is VTK's
``vtkOpenGLGPUVolumeRayCastMapper`` with :mod:`mipcast.mappers.stock_depth`'s pieces; the
``stock_phase`` piece moves the piece's samples from its own ray entry onto the whole volume's
sample positions.  Here, in one process without MPI, each piece (slabs sharing a layer of points)
draws alone with the same camera, opaque grey: the per-pixel maximum (MinIP: minimum, over a white
background) of the pieces' pictures must be the whole volume's stock picture.  Without the phase
piece (each piece sampling from its own entry) it is not (measured below, the control).
The camera inside the volume (``inside``): VTK starts the whole volume's rays at its near-plane cap, and so do
the pieces (``stock_depth.push_cap``); without the cap (samples counted from the whole box's entry, behind the
camera) 51.2 % (stock) and 79.8 % (stock_minip) of the pixels were within 1 grey on 2 pieces along x.
The ranks themselves: tests/test_representation_distributed.py.
"""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkRenderingCore import vtkRenderer, vtkRenderWindow, vtkVolume, vtkWindowToImageFilter
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401
import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401

from mipcast.data_fixtures import make_fixture
from mipcast.distributed import extract_piece, split_extents
from mipcast.mappers import shader_pieces, stock_depth
from mipcast.mappers.brick_rays import global_texture_box
from mipcast.methods import METHODS
from mipcast.offscreen import grey_property

SIZE = (96, 88)
DISTANCE = 0.7  # not a divisor of the spacing: each piece's own entry puts its samples elsewhere


@pytest.fixture(scope="module")
def image():
    image = make_fixture("vessels", size=40)
    image.SetSpacing(1.0, 0.9, 1.1)
    return image


def _draw(image, data, name, camera, op=None, phase=None, background=None):
    """``data`` (the whole ``image`` or a piece of it) drawn by ``name``'s VTK mapper with ``camera``'s view."""
    mapper = METHODS[name].create()
    mapper.SetInputData(data)
    mapper.SetAutoAdjustSampleDistances(False)
    mapper.SetSampleDistance(DISTANCE)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(grey_property(image.GetPointData().GetScalars().GetRange(0)))
    if op is not None:
        uniforms = volume.GetShaderProperty().GetFragmentCustomUniforms()
        uniforms.SetUniformf("u_mc_depthScale", -0.5)  # depth in [0.25, 0.75]: the depth test passes
        uniforms.SetUniformf("u_mc_depthBias", 0.75)
        stock_depth.install(volume, op, phase)
    renderer = vtkRenderer()
    if background is None:
        background = (1.0, 1.0, 1.0) if op == "min" else (0.0, 0.0, 0.0)
    renderer.SetBackground(background)
    renderer.AddVolume(volume)
    window = vtkRenderWindow()
    window.SetOffScreenRendering(True)
    window.SetMultiSamples(0)
    window.AddRenderer(renderer)
    window.SetSize(*SIZE)
    renderer.ResetCamera(image.GetBounds())
    active = renderer.GetActiveCamera()
    active.Azimuth(camera[0])
    active.Elevation(camera[1])
    active.SetParallelProjection(camera[2])
    renderer.ResetCameraClippingRange(image.GetBounds())
    if len(camera) > 3:  # inside the volume: a fraction of the way to the focal point, a wide view, every piece's
        # clipping range the whole volume's (VTK starts the rays at the near-plane cap: stock_phase's u_mc_capTex)
        focal, position = np.array(active.GetFocalPoint()), np.array(active.GetPosition())
        active.SetPosition(*(focal + camera[3] * (position - focal) / np.linalg.norm(position - focal)))
        active.SetViewAngle(60.0)
        active.SetClippingRange(0.1, 150.1)
        if op is not None and phase is not None:
            stock_depth.push_cap(volume, image, active, data.GetExtent(), SIZE[0] / SIZE[1])
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.Update()
    output = grab.GetOutput()
    width, height, _ = output.GetDimensions()
    picture = vtk_to_numpy(output.GetPointData().GetScalars()).reshape(height, width, 3)[::-1].astype(int)
    return picture, shader_pieces.installed_tags(volume.GetShaderProperty())


def _composited(image, name, op, count, axis, camera, phase=True):
    whole = image.GetExtent()
    pictures = []
    for extent in split_extents(whole, count, axis=axis):
        box = global_texture_box(extent, whole) if phase else None
        picture, tags = _draw(image, extract_piece(image, extent), name, camera, op, box)
        assert tags == (["//VTK::DepthPass::Exit", "//VTK::DepthPass::Init"] if phase else ["//VTK::DepthPass::Exit"])
        pictures.append(picture)
    return (np.max if op == "max" else np.min)(pictures, axis=0)


#: (azimuth, elevation, parallel[, distance from the focal point: the camera inside the volume])
CAMERAS = {"oblique": (30.0, 20.0, False), "parallel": (-50.0, 35.0, True), "inside": (30.0, 20.0, False, 12.0)}


@pytest.mark.parametrize("name, op", [("stock", "max"), ("stock_minip", "min")])
@pytest.mark.parametrize("view", sorted(CAMERAS))
def test_pieces_on_the_whole_volumes_samples_draw_the_whole_picture(image, name, op, view):
    camera = CAMERAS[view]
    one, tags = _draw(image, image, name, camera, background=(1.0, 1.0, 1.0) if op == "min" else None)
    assert tags == []  # the whole volume: VTK's own shader
    lit = (one.max(axis=-1) > 10) & (one.min(axis=-1) < 245)
    assert lit.mean() > 0.2, "the whole volume's picture is (nearly) blank"
    blue, _ = _draw(image, image, name, camera, background=(0.0, 0.0, 1.0))
    outside = (blue[..., 2] == 255) & (blue[..., 0] == 0)  # pixels the whole volume's box does not cover
    padded = np.pad(outside, 1)
    outline = np.zeros_like(outside)
    for dr in range(3):
        for dc in range(3):
            outline |= padded[dr:dr + outside.shape[0], dc:dc + outside.shape[1]]
    for count, axis in ((2, 0), (3, 2)):
        grey = np.abs(_composited(image, name, op, count, axis, camera) - one).max(axis=-1)
        # every pixel off is on the volume's outline, where the pieces' boxes and the whole box rasterise
        # a pixel centre on their common silhouette edge differently (measured: 1 pixel of 8448 here)
        off = grey > 1
        assert not (off & ~outline).any(), (count, axis, f"{(~off[~outline]).mean():.4%} of the pixels off the "
                                                         f"outline within 1 grey, max {grey[~outline].max()}")
        assert off.sum() <= 3, (count, axis, f"{off.sum()} outline pixels off")
    control = np.abs(_composited(image, name, op, 2, 0, camera, phase=False) - one).max(axis=-1)
    assert (control <= 1).mean() < 0.999, "without the phase piece the pieces should sample elsewhere"
