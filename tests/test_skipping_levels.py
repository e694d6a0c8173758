"""The exact-skipping helpers of analytic MIP: block maxima and transfer-function floors."""
import numpy as np
import pytest
from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
from vtkmodules.vtkRenderingCore import vtkColorTransferFunction, vtkVolumeProperty

from mipcast.mappers.max_blocks import block_maxima
from mipcast.core.transfer_bounds import constant_ends


@pytest.mark.parametrize("shape", [(2, 2, 2), (9, 9, 9), (10, 13, 7), (2, 30, 5)])
@pytest.mark.parametrize("block", [1, 2, 3, 4, 8])
def test_block_maxima_bound_every_cell_of_the_block(shape, block):
    values = np.random.default_rng(sum(shape) + block).random(shape)
    maxima = block_maxima(values, block)
    assert maxima.shape == tuple(-(-(n - 1) // block) for n in shape)
    for index in np.ndindex(*maxima.shape):
        region = tuple(slice(b * block, min(b * block + block, n - 1) + 1) for b, n in zip(index, shape))
        assert maxima[index] == values[region].max()


def _property(colour_points, opacity_points, colour_class=vtkColorTransferFunction):
    colour, opacity = colour_class(), vtkPiecewiseFunction()
    for x, r, g, b in colour_points:
        colour.AddRGBPoint(x, r, g, b)
    for x, a in opacity_points:
        opacity.AddPoint(x, a)
    prop = vtkVolumeProperty()
    prop.SetColor(colour)
    prop.SetScalarOpacity(opacity)
    return prop


def test_floor_and_ceiling_of_a_hot_map_with_transparent_background():
    prop = _property([(0, 0, 0, 0), (300, 1, 0, 0), (600, 1, 1, 0), (900, 1, 1, 1)],
                     [(-1000, 0), (150, 0), (400, 1), (3000, 1)])
    # premultiplied colour is 0 up to 150 (opacity 0), white from 900 on
    assert constant_ends(prop, -1000.0, 3000.0) == (150.0, 900.0)


def test_no_floor_when_colour_changes_from_the_minimum():
    prop = _property([(0, 0, 0, 0), (1, 1, 1, 1)], [(0, 1), (1, 1)])
    assert constant_ends(prop, 0.0, 1.0) == (0.0, 1.0)


def test_window_outside_the_data_range():
    prop = _property([(2, 0, 0, 0), (3, 1, 1, 1)], [(2, 1), (3, 1)])
    floor, ceiling = constant_ends(prop, 0.0, 1.0)  # all data below the window: one colour
    assert floor == 1.0 and ceiling == 0.0


def test_discretizable_colour_maps_work_too():
    # ParaView's colour maps are vtkDiscretizableColorTransferFunction subclasses, whose
    # GetColor override hides the one-argument form in Python
    from vtkmodules.vtkRenderingCore import vtkDiscretizableColorTransferFunction

    points = ([(0, 0, 0, 0), (300, 1, 0, 0), (600, 1, 1, 0), (900, 1, 1, 1)],
              [(-1000, 0), (150, 0), (400, 1), (3000, 1)])
    prop = _property(*points, colour_class=vtkDiscretizableColorTransferFunction)
    assert constant_ends(prop, -1000.0, 3000.0) == constant_ends(_property(*points), -1000.0, 3000.0)
