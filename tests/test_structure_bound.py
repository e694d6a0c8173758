"""The data's bound on where a full-quality ray may meet structure above the floor: no pixel above it left out.

Checked against the float64 reference renderer on the same camera rays: every pixel whose exact maximum
lies above the floor must have its nearest deciding texel in the bound (mipcast.core.structure_bound).
"""
import numpy as np
import pytest
from vtkmodules.vtkCommonMath import vtkMatrix4x4
from vtkmodules.vtkCommonTransforms import vtkTransform

from mipcast import reference
from mipcast.core.foveation import coarse_texels
from mipcast.core.structure_bound import blocks_above, halved_cells, ndc_from_index, splat_texels
from mipcast.mappers.max_blocks import block_maxima
from mipcast.data_fixtures import image_from_array
from mipcast.offscreen import OffscreenView

SIZE = (64, 48)
GRID = (16, 12)   # a texel every 4 pixels: acuity's coarsest level
FLOOR = 0.8


def _specks(seed: int):
    rng = np.random.default_rng(seed)
    values = np.zeros((10, 12, 14))
    points = rng.integers(0, (10, 12, 14), size=(40, 3))
    values[points[:, 0], points[:, 1], points[:, 2]] = rng.uniform(0.9, 2.0, 40)   # from just above the floor
    return image_from_array(values.astype(np.float32), spacing=(1.0, 1.5, 0.7))


def _placed_view(image, view: str):
    scene = OffscreenView(image, "mip", size=SIZE, view=view)
    transform = vtkTransform()
    transform.Translate(4.0, -3.0, 2.0)
    transform.RotateWXYZ(35.0, 0.3, 1.0, 0.2)
    transform.Scale(1.2, 0.9, 1.4)
    matrix = vtkMatrix4x4()
    matrix.DeepCopy(transform.GetMatrix())
    scene.volume.SetUserMatrix(matrix)
    scene.renderer.ResetCamera()
    scene.camera.Zoom(1.3)
    scene.renderer.ResetCameraClippingRange()
    return scene


@pytest.mark.parametrize("view", ["oblique", "perspective"])
@pytest.mark.parametrize("block", [1, 2])
@pytest.mark.parametrize("seed", [0, 1])
def test_every_pixel_above_the_floor_has_its_texel_in_the_bound(view, block, seed):
    image = _specks(seed)
    scene = _placed_view(image, view)
    matrix = scene.volume.GetMatrix()
    exact = reference.render(image, scene.camera, SIZE, method="analytic", matrix=matrix)
    above = np.nan_to_num(exact, nan=-1.0) > FLOOR
    values = np.asarray(scene.image.GetPointData().GetScalars()).reshape(10, 12, 14)
    boxes = blocks_above(block_maxima(values, block), FLOOR, block, image.GetDimensions())
    to_ndc = ndc_from_index(image, scene.camera, SIZE[0] / SIZE[1], matrix)
    bound = splat_texels(boxes, to_ndc, GRID, np.ones(GRID[::-1], bool))
    assert above.sum() >= 10   # the specks are seen
    assert np.all(coarse_texels(bound, SIZE)[above])   # the nearest texel of every such pixel is in the bound
    assert bound.mean() < 0.9   # and it is a bound, not the whole view
    if block == 1:  # the half cells above the floor: a tighter bound, still holding every such pixel
        halves = splat_texels(halved_cells(values, boxes, FLOOR), to_ndc, SIZE, np.ones(SIZE[::-1], bool))
        assert np.all(halves[above]) and halves.sum() < splat_texels(boxes, to_ndc, SIZE, halves | True).sum()


def test_only_the_texels_asked_for_and_all_of_them_when_the_volume_reaches_behind_the_eye():
    image = _specks(0)
    scene = _placed_view(image, "perspective")
    values = np.asarray(scene.image.GetPointData().GetScalars()).reshape(10, 12, 14)
    boxes = blocks_above(block_maxima(values, 1), FLOOR, 1, image.GetDimensions())
    some = np.zeros(GRID[::-1], bool)
    some[4:8, 5:9] = True
    to_ndc = ndc_from_index(image, scene.camera, SIZE[0] / SIZE[1], scene.volume.GetMatrix())
    assert not np.any(splat_texels(boxes, to_ndc, GRID, some) & ~some)
    scene.camera.SetPosition(*scene.volume.GetCenter())   # the eye inside the volume
    inside = ndc_from_index(image, scene.camera, SIZE[0] / SIZE[1], scene.volume.GetMatrix())
    assert np.array_equal(splat_texels(boxes, inside, GRID, some), some)


@pytest.mark.parametrize("cells", [False, True], ids=["point scalars", "cell scalars"])
def test_the_foveated_mappers_blocks_bound_what_its_rays_draw(cells):
    """The mapper's blocks (its drawn values over its transfer functions' floor), for point and cell scalars: cell
    values are drawn on the cell centres, half a cell in from the points, VTK filling the outer half cell."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    from mipcast.mappers import foveated_masks

    rng = np.random.default_rng(3)
    values = np.zeros((9, 11, 13), np.float32)   # (z, y, x): the cells' or the points' values
    points = rng.integers(0, values.shape, size=(40, 3))
    values[points[:, 0], points[:, 1], points[:, 2]] = rng.uniform(0.9, 2.0, 40)
    values[-1, -1, -1] = values[0, 0, 0] = values[-1, 0, 5] = values[4, -1, 0] = 2.0   # at the box's faces
    image = vtkImageData()
    image.SetDimensions(*(np.array(values.shape[::-1]) + (1 if cells else 0)))
    image.SetSpacing(1.0, 1.5, 0.7)
    array = numpy_to_vtk(values.ravel(), deep=True)
    array.SetName("v")
    (image.GetCellData() if cells else image.GetPointData()).SetScalars(array)
    scene = _placed_view(image, "oblique")
    scene.set_window((FLOOR, 2.0))
    matrix = scene.volume.GetMatrix()
    exact = reference.render(image, scene.camera, SIZE, method="analytic", matrix=matrix)
    above = np.nan_to_num(exact, nan=-1.0) > FLOOR
    boxes = foveated_masks.above_floor_boxes({}, image, scene.volume)
    # a texel per pixel: the boxes' own placement, not the slack of coarse texels, decides
    bound = splat_texels(boxes, ndc_from_index(image, scene.camera, SIZE[0] / SIZE[1], matrix), SIZE,
                         np.ones(SIZE[::-1], bool))
    assert above.sum() >= 10
    assert np.all(bound[above])
    assert bound.mean() < 0.9


def test_the_kept_projections_follow_the_view_and_the_gaze():
    """foveated_masks.structure_texels keeps the boxes' projections while the view stands still: a moved gaze, a
    turned camera and a moved volume give what a fresh splat gives."""
    from types import SimpleNamespace

    from mipcast.core.foveation import eccentricity
    from mipcast.mappers import foveated_masks

    image = _specks(2)
    scene = _placed_view(image, "perspective")
    scene.set_window((FLOOR, 2.0))
    boxes = foveated_masks.above_floor_boxes({}, image, scene.volume)
    state, viewport = {}, (0, 0) + SIZE

    def fresh(plan):
        near = eccentricity(GRID, plan.gaze, plan.aspect) < plan.start + 0.5 * np.hypot(
            plan.aspect / GRID[0], 1.0 / GRID[1])
        to_ndc = ndc_from_index(image, scene.camera, SIZE[0] / SIZE[1], scene.volume.GetMatrix())
        return splat_texels(boxes, to_ndc, GRID, near)

    seen = []
    for step in range(5):
        plan = SimpleNamespace(layers=[SimpleNamespace(grid=GRID)], aspect=SIZE[0] / SIZE[1], start=0.2,
                               gaze=(0.3 + 0.1 * step, 0.5))
        if step == 3:
            scene.camera.Azimuth(20.0)
        if step == 4:
            scene.volume.AddPosition(1.5, 0.0, 0.0)
        kept = foveated_masks.structure_texels(state, plan, 0, image, scene.volume, scene.camera, viewport, boxes)
        assert np.array_equal(kept, fresh(plan)), step
        seen.append(kept)
    assert all(seen[k].any() for k in range(5)) and not np.array_equal(seen[0], seen[1])
