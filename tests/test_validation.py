"""Bad input: each case a clear error naming the problem; inputs never modified."""
import numpy as np
import pytest
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData, vtkPolyData

from mipcast import reference
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView
from mipcast.core.validation import (check_choice, check_finite, check_image, check_non_negative, check_positive,
                                check_size, check_unit)
from installed import OUTSIDE


def _image(values, components=1):
    image = vtkImageData()
    shape = values.shape[:3]
    image.SetDimensions(shape[2], shape[1], shape[0])
    array = numpy_to_vtk(values.reshape(-1, components), deep=True)
    array.SetName("v")
    image.GetPointData().SetScalars(array)
    return image


@pytest.mark.parametrize("make, error, words", [
    (lambda: vtkPolyData(), TypeError, "vtkImageData"),
    (lambda: vtkImageData(), ValueError, "empty"),
    (lambda: _image(np.ones((1, 1, 1), np.float32)), ValueError, "at least 2 points"),
    (lambda: _image(np.ones((4, 4, 1), np.float32)), ValueError, "at least 2 points"),
    (lambda: _image(np.full((4, 4, 4), np.inf, np.float32)), ValueError, "NaN/Inf"),
    (lambda: _image(1.0e9 + np.random.default_rng(0).random((4, 4, 4))), ValueError, "subtract the offset"),
    (lambda: _image(1.0e40 * np.random.default_rng(0).random((4, 4, 4))), ValueError,
     r"beyond 3.4e\+38.*float64.*values / 1e\+36"),
    (lambda: _image(1.0e-40 * np.random.default_rng(0).random((4, 4, 4))), ValueError,
     r"range below 7.52e-37.*float64.*values \* 1e\+40"),
    (lambda: _image((1.0e38 * np.random.default_rng(0).random((4, 4, 4))).astype(np.float32)), ValueError,
     r"beyond 1.06e\+37.*float32"),
    (lambda: _image((1.0e-35 * np.random.default_rng(0).random((4, 4, 4))).astype(np.float32)), ValueError,
     r"range below 7.7e-34.*float32.*values \* 1e\+35"),
])
def test_bad_volumes(make, error, words):
    with pytest.raises(error, match=words):
        check_image(make())


def _cell_image(dims, values):
    image = vtkImageData()
    image.SetDimensions(*dims)
    array = numpy_to_vtk(np.asarray(values, np.float32).ravel(), deep=True)
    array.SetName("c")
    image.GetCellData().SetScalars(array)
    return image


def test_cell_scalars_are_drawn_at_the_cell_centres():
    """Known answer: 2 x 2 x 2 cells valued 1..8 (x fastest), seen along z in parallel projection: the
    interpolant between the cell centres (0.5 and 1.5 on each axis), so the maximum along a ray is the
    upper layer's bilinear value 5 + (x - 0.5) + 2 (y - 0.5), and rays outside the centres' box miss."""
    from vtkmodules.vtkRenderingCore import vtkCamera

    from mipcast.core.prepare import cell_centres

    image = _cell_image((3, 3, 3), np.arange(1.0, 9.0))
    camera = vtkCamera()
    camera.ParallelProjectionOn()
    camera.SetFocalPoint(1.0, 1.0, 1.0)
    camera.SetPosition(1.0, 1.0, 10.0)
    camera.SetParallelScale(1.0)  # 4 x 4 pixels over [0, 2]^2: centres at 0.25, 0.75, 1.25, 1.75
    centre = np.array([0.25, 0.75, 1.25, 1.75])
    x, y = np.meshgrid(centre, centre[::-1])  # row 0 is the top row
    expected = np.where((x > 0.5) & (x < 1.5) & (y > 0.5) & (y < 1.5), 5.0 + (x - 0.5) + 2.0 * (y - 0.5), np.nan)
    found = reference.render(image, camera, (4, 4), method="analytic")
    assert np.allclose(found, expected, equal_nan=True), found
    drawn = cell_centres(image)  # the definition: no value copied, the image given untouched
    assert drawn.GetPointData().GetScalars().GetAddressAsString("vtkObjectBase") == \
        image.GetCellData().GetScalars().GetAddressAsString("vtkObjectBase")
    assert image.GetPointData().GetNumberOfArrays() == 0 and image.GetDimensions() == (3, 3, 3)
    # the GPU draws the same values: exact methods stay exact against the reference
    view = OffscreenView(image, "analytic", size=(4, 4))
    view.renderer.GetActiveCamera().DeepCopy(camera)
    assert np.allclose(view.float_image(), expected, atol=1e-5, equal_nan=True), view.float_image()
    assert view.mapper.GetInput().GetDimensions() == (2, 2, 2)


def test_cell_scalars_with_one_cell_along_an_axis_name_the_fix():
    with pytest.raises(ValueError, match="at least 2 cells.*vtkCellDataToPointData"):
        check_image(_cell_image((2, 3, 3), np.ones(4)))
    with pytest.raises(ValueError, match="at least 2 cells"):
        check_image(_cell_image((4, 4, 1), np.ones(9)))


@pytest.mark.parametrize("dtype", [np.uint8, np.int16, np.uint16, np.float32, np.float64])
def test_good_volumes_pass_read_only(dtype):
    values = np.arange(64).reshape(4, 4, 4).astype(dtype)
    view = check_image(_image(values))
    assert view.shape == (4, 4, 4) and not view.flags.writeable
    assert view[1, 2, 3] == values[1, 2, 3]


@pytest.mark.parametrize("value", [0, -1.0, float("nan"), float("inf")])
def test_positive_parameters(value):
    with pytest.raises(ValueError, match="sample_distance"):
        check_positive("sample_distance", value)
    with pytest.raises(TypeError, match="sample_distance"):
        check_positive("sample_distance", "far")


def test_choices_and_sizes():
    with pytest.raises(ValueError, match="'mip', 'exact'"):
        check_choice("method", "best", ("mip", "exact"))
    for bad in [(0, 5), (5.5, 5), (1, 2, 3), "big"]:
        with pytest.raises((TypeError, ValueError)):
            check_size(bad)



@pytest.mark.parametrize("check, value, error, message", [
    (check_finite, "far", TypeError, "x must be a number, got 'far'"),
    (check_finite, float("inf"), ValueError, "x must be finite, got inf"),
    (check_non_negative, None, TypeError, "x must be a number, got None"),
    (check_non_negative, float("nan"), ValueError, "x must be finite, got nan"),
    (check_non_negative, -1, ValueError, "x must be >= 0, got -1"),
    (lambda n, v: check_non_negative(n, v, numbers_only=True), True, TypeError, "x must be a number >= 0, got True"),
    (lambda n, v: check_non_negative(n, v, numbers_only=True), "1", TypeError, "x must be a number >= 0, got '1'"),
    (lambda n, v: check_non_negative(n, v, numbers_only=True), -0.5, ValueError,
     "x must be a finite number >= 0, got -0.5"),
    (lambda n, v: check_non_negative(n, v, numbers_only=True), float("inf"), ValueError,
     "x must be a finite number >= 0, got inf"),
    (check_unit, "0.5", TypeError, "x must be a number in [0, 1], got '0.5'"),
    (check_unit, False, TypeError, "x must be a number in [0, 1], got False"),
    (check_unit, 1.5, ValueError, "x must be in [0, 1], got 1.5"),
    (check_unit, float("nan"), ValueError, "x must be in [0, 1], got nan"),
    (lambda n, v: check_unit(n, v, open_low=True), 0, ValueError, "x must be in (0, 1], got 0"),
    (lambda n, v: check_unit(n, v, open_low=True), None, TypeError, "x must be a number in (0, 1], got None"),
])
def test_number_checks_name_the_parameter(check, value, error, message):
    with pytest.raises(error) as caught:
        check("x", value)
    assert str(caught.value) == message


def test_number_checks_return_floats():
    assert check_finite("x", "-2.5") == -2.5 and check_finite("x", True) == 1.0
    assert check_non_negative("x", "0") == 0.0 and check_non_negative("x", 3) == 3.0
    assert check_non_negative("x", np.float32(0.5), numbers_only=True) == 0.5
    assert check_unit("x", np.int64(1)) == 1.0 and check_unit("x", 0) == 0.0
    assert check_unit("x", 1e-9, open_low=True) == 1e-9
    assert all(type(v) is float for v in (check_finite("x", np.float32(1)), check_unit("x", np.float64(0.5)),
                                           check_non_negative("x", 2, numbers_only=True)))

def test_entry_points_refuse_and_leave_input_untouched():
    values = np.random.default_rng(0).random((6, 6, 6)).astype(np.float32)
    image = _image(values)
    before = vtk_to_numpy(image.GetPointData().GetScalars()).copy()
    with pytest.raises(ValueError, match="unknown method"):
        OffscreenView(image, "best")
    with pytest.raises(ValueError, match="sample_distance"):
        OffscreenView(image, "mip", sample_distance=-1)
    with pytest.raises(ValueError, match="view"):
        OffscreenView(image, "mip", view="sideways")
    view = OffscreenView(image, "mip", size=(16, 16))
    view.screenshot()
    view.float_image()
    reference.render(image, view.camera, (16, 16), method="analytic")
    assert np.array_equal(vtk_to_numpy(image.GetPointData().GetScalars()), before)
    assert image.GetDimensions() == (6, 6, 6) and image.GetSpacing() == (1.0, 1.0, 1.0)


def test_32_and_64_bit_data_render_exactly_unpacked():
    # VTK rescales 32/64-bit data per component: analytic MIP draws them unpacked
    base = np.random.default_rng(1).random((12, 14, 16))
    for values in (1.0e4 + 10.0 * base, (base * 5000).astype(np.int32)):
        image = _image(values)
        check_image(image)
        view = OffscreenView(image, "analytic", size=(48, 48))
        assert "amip_corners_packed" not in view.mapper.GetShaderPieces()
        found = view.float_image()
        exact = reference.render(image, view.camera, (48, 48), method="analytic")
        hits = ~np.isnan(exact) & ~np.isnan(found)
        assert hits.mean() > 0.2 and np.mean(np.isnan(found) != np.isnan(exact)) < 0.02  # silhouette only
        assert np.max(np.abs(found[hits] - exact[hits])) <= 1e-4 * np.ptp(values)


@pytest.mark.parametrize("dtype", ["longlong", "ulonglong", "int64", "uint64"])
def test_64_bit_integers_of_either_numpy_spelling_are_drawn(dtype):
    """numpy has two 64-bit integer types on Linux (long, "l", and longlong, "q": tifffile's, h5py's for
    some files), equal as dtypes but not as type objects; VTK wraps "q" as vtkTypeInt64Array.  Both are
    drawn (as float64), the float readout the float64 reference's; until 2026-12-05 "q" was refused as
    an unsupported scalar type."""
    base = np.random.default_rng(3).random((12, 14, 16))
    image = _image((base * 5000).astype(dtype))
    assert vtk_to_numpy(image.GetPointData().GetScalars()).dtype.char in "qQlL"
    check_image(image)
    view = OffscreenView(image, "mip", size=(48, 48))
    found = view.float_image()
    expected = reference.render(image, view.camera, (48, 48), method="mip", sample_distance=view.sample_distance)
    hits = ~np.isnan(expected) & ~np.isnan(found)
    assert hits.mean() > 0.2 and np.mean(np.isnan(found) != np.isnan(expected)) < 0.02
    assert np.max(np.abs(found[hits] - expected[hits])) <= METHODS["mip"].reference_tolerance * 5000


_SCALARS_VANISH = r"""
import sys
import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

image = make_fixture("vessels", size=24)
view = OffscreenView(image, sys.argv[1], size=(48, 48))
before = view.screenshot()
name = image.GetPointData().GetScalars().GetName()
values = image.GetPointData().GetScalars()
image.GetPointData().RemoveArray(name)          # upstream: the array is renamed or dropped
image.Modified()
gone = view.screenshot()
three = numpy_to_vtk(np.repeat(np.zeros(image.GetNumberOfPoints(), np.float32)[:, None], 3, axis=1), deep=True)
three.SetName("rgb")
image.GetPointData().SetScalars(three)          # then several components
image.Modified()
several = view.screenshot()
image.GetPointData().SetScalars(values)         # and back
image.Modified()
again = view.screenshot()
print(int(before.max()), int(gone.max()), int(several.max()), int(np.abs(again.astype(int) - before).max()))
"""


@pytest.mark.parametrize("method", [name for name, m in METHODS.items() if m.float_readout])
def test_scalars_that_vanish_after_a_render_are_refused_not_a_crash(method):
    """The input passes at first, then loses its scalars (an upstream rename): an error, nothing drawn, no segfault."""
    import subprocess
    import sys

    completed = subprocess.run([sys.executable, "-c", _SCALARS_VANISH, method], capture_output=True, text=True, cwd=OUTSIDE,
                               timeout=120)
    assert completed.returncode == 0, completed.stderr[-2000:]  # was SIGSEGV (139) for analytic
    before, gone, several, again = map(int, completed.stdout.split()[-4:])
    assert before > 100 and gone == 0 and several == 0 and again == 0
    # three components draw their magnitude (zero here: black), as in ParaView
    assert "no active point scalars" in completed.stderr


SCALED_METHODS = ("mip", "analytic", "minip", "analytic_minip", "average", "analytic_average", "demip", "stock",
                  "stock_minip", "stock_average")


@pytest.mark.parametrize("dtype, scale", [(np.float32, 1e-33), (np.float32, 1e-20), (np.float32, 1e20),
                                          (np.float32, 1e37), (np.float32, -1e37), (np.float64, 1e-36),
                                          (np.float64, 1e38)])
def test_float_values_far_from_one_draw_as_the_same_values_near_one(dtype, scale):
    """Within the limits check_image keeps (mipcast.core.prepare.FLOAT_LIMITS) every method draws values times
    1e-36 .. 1e38 as it draws the values themselves, missing ones included. Before the limits, values past
    them were drawn as garbage (up to 255 grey off); before the exact methods scaled the cubic's derivative,
    analytic MIP was 18 grey off on 23-42 pixels at 1e20 and 1e-20 (float32: qb * qb overflowed, the 1e-20
    guards dropped the roots)."""
    from mipcast.data_fixtures import make_fixture

    values = vtk_to_numpy(make_fixture("vessels", size=24).GetPointData().GetScalars()).astype(np.float64)
    values = values.reshape(24, 24, 24)
    values[::7, ::5, ::3] = np.nan
    for method in SCALED_METHODS:
        expected = OffscreenView(_image(np.sign(scale) * values), method, size=(32, 32)).screenshot().astype(int)
        drawn = OffscreenView(_image((values * scale).astype(dtype)), method, size=(32, 32)).screenshot()
        assert np.abs(drawn.astype(int) - expected).max() <= 1, (method, np.abs(drawn.astype(int) - expected).max())


def test_a_mapper_in_a_vtk_pipeline_refuses_values_beyond_float32():
    """The mappers' own input preparer applies the float limits too (a VTK pipeline has no front end)."""
    from vtkmodules.vtkRenderingCore import vtkVolume

    from mipcast import create_mapper

    mapper = create_mapper("analytic")
    volume = vtkVolume()
    mapper.Attach(volume)
    mapper.SetInputData(_image(1.0e45 * np.random.default_rng(0).random((4, 4, 4))))
    assert "beyond 3.4e+38" in mapper.GetRenderProblem()
    mapper.SetInputData(_image(np.random.default_rng(0).random((4, 4, 4))))
    assert mapper.GetRenderProblem() is None


def test_implicit_and_structure_of_arrays_scalars():
    """VTK's implicit arrays (computed, not stored) and structure-of-arrays arrays (Catalyst's zero-copy
    adaptors) are drawn as the same values in a plain array. The typed implicit classes VTK 9.6 deprecated
    (vtkAffineDoubleArray, ...) made VTK's own vtk_to_numpy fail with a NameError deep inside mipcast; now a
    TypeError names the array and the copy to make."""
    import re
    import warnings

    import vtkmodules.vtkCommonCore as core

    def affine(array_type):
        array = array_type()
        array.SetNumberOfComponents(1)
        array.SetNumberOfTuples(8 ** 3)
        array.ConstructBackend(0.01, 0.0)
        array.SetName("ramp")
        return array

    def image_of(array):
        image = _image(np.zeros((8, 8, 8)))
        image.GetPointData().SetScalars(array)
        return image

    plain = image_of(numpy_to_vtk(0.01 * np.arange(8.0 ** 3), deep=True))
    soa = core.vtkSOADataArrayTemplate_IdE()
    soa.SetNumberOfComponents(1)
    soa.SetNumberOfTuples(8 ** 3)
    for index in range(8 ** 3):
        soa.SetValue(index, 0.01 * index)
    for array in (affine(core.vtkAffineArray_IdE), soa):
        for method in ("mip", "analytic", "stock"):
            assert np.array_equal(OffscreenView(image_of(array), method, size=(24, 24)).screenshot(),
                                  OffscreenView(plain, method, size=(24, 24)).screenshot()), (array, method)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        typed = getattr(core, "vtkAffineDoubleArray", None)
        if typed is not None:  # VTK's numpy_support reads it where pyvista has been imported, else fails
            try:
                values = check_image(image_of(affine(typed)))
            except TypeError as error:
                assert re.search(r"'ramp' are a vtkAffineDoubleArray.*copy.DeepCopy\(array\)", str(error))
            else:
                assert np.allclose(values.ravel(), 0.01 * np.arange(8.0 ** 3))


_TYPED_IMPLICIT = """
import warnings
warnings.simplefilter("ignore", DeprecationWarning)
import vtkmodules.vtkCommonCore as core
from vtkmodules.vtkCommonDataModel import vtkImageData
from mipcast.core.validation import check_image
array = core.vtkAffineDoubleArray()
array.SetNumberOfComponents(1)
array.SetNumberOfTuples(64)
array.ConstructBackend(0.01, 0.0)
array.SetName("ramp")
image = vtkImageData()
image.SetDimensions(4, 4, 4)
image.GetPointData().SetScalars(array)
try:
    check_image(image)
except TypeError as error:
    print(error)
"""


def test_a_typed_implicit_array_names_the_copy_where_numpy_cannot_read_it():
    """Without pyvista imported, VTK 9.7's vtk_to_numpy fails on vtkAffineDoubleArray with a NameError of its
    own; check_image turns that into a TypeError naming the array and the fix."""
    import subprocess
    import sys

    import vtkmodules.vtkCommonCore as core

    if not hasattr(core, "vtkAffineDoubleArray"):
        pytest.skip("this VTK has no typed implicit arrays")
    completed = subprocess.run([sys.executable, "-c", _TYPED_IMPLICIT], capture_output=True, text=True,
                               cwd=OUTSIDE, timeout=120)
    assert completed.returncode == 0, completed.stderr[-2000:]
    out = completed.stdout.strip()
    assert out == "" or ("'ramp' are a vtkAffineDoubleArray" in out and "copy.DeepCopy(array)" in out), out


def test_a_picture_larger_than_the_driver_draws_is_refused_not_drawn_black():
    """VTK draws a window wider than GL_MAX_TEXTURE_SIZE black, silently (llvmpipe: 16384 pixels a side; a
    17000 x 300 screenshot of the vessels came back all zeros until 2026-12-04): OffscreenView refuses it,
    naming the limit; at the limit it draws."""
    from mipcast.data_fixtures import make_fixture
    from mipcast.mappers.gpu_limits import max_picture_size

    image = make_fixture("vessels", size=16)
    probe = OffscreenView(image, "mip", size=(8, 8), view="front")
    probe.screenshot()
    limit = max_picture_size(probe.render_window)
    assert limit >= 1024
    for get in ("screenshot", "float_image"):
        view = OffscreenView(image, "mip", size=(limit + 1, 4), view="front")
        with pytest.raises(ValueError, match=rf"{limit + 1} x 4 pixels is larger than this OpenGL driver draws "
                                             rf"\({limit} pixels a side"):
            getattr(view, get)()
    drawn = OffscreenView(image, "mip", size=(limit, 4), view="front").screenshot()
    assert drawn.shape == (4, limit, 3) and drawn.max() > 100


@pytest.mark.parametrize("method", ["mip", "stock", "demip", "foveated"])
def test_a_sample_distance_beyond_the_loop_limit_is_refused_not_cut_short(method):
    """llvmpipe ends a shader loop after 65536 iterations: the vessels 32³ sampled at 2500 samples a voxel drew
    66 % of the range off the float64 reference (stock VTK's MIP 63 %; tests/loop_limit_check.py), silently, until 2026-12-04. OffscreenView refuses a
    sample distance that takes more samples along the volume's diagonal, naming the finest allowed, and a
    mipcast mapper in a VTK pipeline refuses to draw it; the exact methods take no sample distance."""
    from mipcast.core.validation import MAX_SAMPLES_PER_RAY
    from mipcast.data_fixtures import make_fixture

    image = make_fixture("vessels", size=32)
    diagonal = 31.0 * 3 ** 0.5
    fine = diagonal / (2 * MAX_SAMPLES_PER_RAY)
    with pytest.raises(ValueError, match=r"takes 131072 samples along the volume's diagonal .* at least 0\.000819"):
        OffscreenView(image, method, size=(16, 16), sample_distance=fine)
    assert OffscreenView(image, method, size=(16, 16), sample_distance=diagonal / MAX_SAMPLES_PER_RAY)
    if method != "stock":
        view = OffscreenView(image, method, size=(16, 16))
        view.mapper.SetSampleDistance(fine)
        assert "samples along the volume's diagonal" in view.mapper.GetRenderProblem()
        assert view.screenshot().max() == 0
    exact = OffscreenView(image, "analytic", size=(16, 16))
    exact.mapper.SetSampleDistance(fine)  # ignored by the cell walk
    assert exact.mapper.GetRenderProblem() is None and exact.screenshot().max() > 100
