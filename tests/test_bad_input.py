"""The bad-input catalogue: every case x every method of the table (docs/reliability.md).

Each case is either drawn (a correct picture: the float readout against the
method's float64 reference on the same rays, or, for methods without one, a
defined picture: no NaN, values inside the data's finite range, uniform where
every ray sees one value) or refused with a clear error: ``mipcast.InputError``
before rendering (the pyvista/CLI paths) and, inside a VTK pipeline, a VTK
error event, a reason in ``GetLastProblem()`` and nothing drawn.  One view per
method is shared by all cases, so the input also changes size, type and
component count between frames.
"""
from __future__ import annotations

import numpy as np
import pytest
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkCommand
from vtkmodules.vtkCommonDataModel import vtkDataSetAttributes, vtkImageData

import mipcast
from mipcast.core.prepare import prepare_scalars
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView, set_view

SIZE = (32, 32)
N = 10
RNG = np.random.default_rng(13)
BASE = np.asarray(make_fixture("vessels", size=N).GetPointData().GetScalars()).reshape(N, N, N)


def image_of(values, components=1, spacing=(1.0, 1.0, 1.0), direction=None, shape=None) -> vtkImageData:
    values = np.asarray(values)
    shape = shape or values.shape[:3]
    image = vtkImageData()
    image.SetDimensions(shape[2], shape[1], shape[0])
    image.SetSpacing(spacing)
    if direction is not None:
        image.SetDirectionMatrix(np.asarray(direction, dtype=float).ravel().tolist())
    array = numpy_to_vtk(np.ascontiguousarray(values).reshape(-1, components), deep=True,
                         array_type=None)
    array.SetName("values")
    image.GetPointData().SetScalars(array)
    return image


def scaled(dtype, low, high):
    """BASE (0..1) mapped onto [low, high] in ``dtype``."""
    return (low + BASE.astype(np.float64) * (high - low)).astype(dtype)


def holes(values, every=7, fill=np.nan):
    out = np.array(values, dtype=values.dtype if values.dtype.kind == "f" else np.float32)
    out.ravel()[::every] = fill
    return out


def nan_half():
    out = BASE.astype(np.float32).copy()
    out[:, :, : N // 2] = np.nan  # a land mask: half the volume has no data
    return out


def nan_slab():
    out = BASE.astype(np.float64).copy()
    out[3:6] = np.nan
    return out


def one_finite():
    out = np.full((N, N, N), np.nan, np.float32)
    out[5, 5, 5] = 2.0
    out[5, 5, 4] = 1.0
    return out


def vectors(dtype, components):
    stack = [BASE * (k + 1) for k in range(components)]
    return (np.stack(stack, axis=-1) * (100 if np.dtype(dtype).kind in "iu" else 1)).astype(dtype)


def nan_vector():
    out = vectors(np.float32, 3)
    out[::3, 2, 2, 1] = np.nan
    return out


def rotation():
    c, s = np.cos(0.4), np.sin(0.4)
    return [[c, -s, 0], [s, c, 0], [0, 0, 1]]


def no_scalars():
    image = vtkImageData()
    image.SetDimensions(4, 4, 4)
    return image


def cell_scalars(cells=(N, N, N)):
    """Cell scalars only (BASE's values on ``cells`` cells): drawn on the image of the cell centres."""
    image = vtkImageData()
    image.SetDimensions(cells[2] + 1, cells[1] + 1, cells[0] + 1)
    image.SetSpacing(1.0, 0.8, 1.25)
    values = BASE[:cells[0], :cells[1], :cells[2]].astype(np.float32)
    image.GetCellData().SetScalars(numpy_to_vtk(values.ravel(), deep=True))
    return image


def hidden(values, cells=False):
    """``values`` with every 7th point (cell) and a half-slab blanked in VTK's ghost array (HIDDENPOINT /
    HIDDENCELL, as vtkImageData.BlankPoint/BlankCell and simulations' blanking write them)."""
    image = cell_scalars() if cells else image_of(values)
    count = image.GetNumberOfCells() if cells else image.GetNumberOfPoints()
    bit = vtkDataSetAttributes.HIDDENCELL if cells else vtkDataSetAttributes.HIDDENPOINT
    flags = np.zeros(count, np.uint8)
    flags[::7] = bit
    flags[: count // 3] = bit
    ghosts = numpy_to_vtk(flags, deep=True)
    ghosts.SetName(vtkDataSetAttributes.GhostArrayName())
    (image.GetCellData() if cells else image.GetPointData()).AddArray(ghosts)
    return image


I32, U32 = np.iinfo(np.int32), np.iinfo(np.uint32)
#: name -> (make image, component, expected: "picture" or words of the error)
CASES = {
    # -- missing values
    "nan_sparse_f32": (lambda: image_of(holes(BASE.astype(np.float32))), None, "picture"),
    "nan_sparse_f64": (lambda: image_of(holes(BASE.astype(np.float64), 5)), None, "picture"),
    "nan_half_land_mask": (lambda: image_of(nan_half()), None, "picture"),
    "nan_slab": (lambda: image_of(nan_slab()), None, "picture"),
    "pos_inf": (lambda: image_of(holes(BASE.astype(np.float32), 9, np.inf)), None, "picture"),
    "neg_inf": (lambda: image_of(holes(BASE.astype(np.float32), 9, -np.inf)), None, "picture"),
    "nan_and_inf": (lambda: image_of(holes(holes(BASE.astype(np.float32), 11, np.inf), 7)), None, "picture"),
    "one_finite_pair": (lambda: image_of(one_finite()), None, "picture"),
    "nan_constant": (lambda: image_of(holes(np.full((N, N, N), 3.0, np.float32))), None, "picture"),
    "all_nan": (lambda: image_of(np.full((6, 6, 6), np.nan, np.float32)), None, ["NaN", "nothing to draw"]),
    "all_inf": (lambda: image_of(np.full((6, 6, 6), -np.inf)), None, ["NaN/Inf", "nothing to draw"]),
    "hidden_points_int16": (lambda: hidden(scaled(np.int16, -1000, 3000)), None, "picture"),
    "hidden_cells": (lambda: hidden(None, cells=True), None, "picture"),
    # -- scalar types
    "int8": (lambda: image_of(scaled(np.int8, -100, 120)), None, "picture"),
    "uint8": (lambda: image_of(scaled(np.uint8, 3, 250)), None, "picture"),
    "int16": (lambda: image_of(scaled(np.int16, -1000, 3000)), None, "picture"),
    "uint16": (lambda: image_of(scaled(np.uint16, 0, 60000)), None, "picture"),
    "int32": (lambda: image_of(scaled(np.int32, -200000, 900000)), None, "picture"),
    "uint32_full_range": (lambda: image_of(scaled(np.uint32, 0, U32.max)), None, "picture"),
    "int32_full_range": (lambda: image_of(scaled(np.int32, I32.min + 1, I32.max)), None, "picture"),
    "int64": (lambda: image_of(scaled(np.int64, -5000, 70000)), None, "picture"),
    "uint64": (lambda: image_of(scaled(np.uint64, 10, 2 ** 40)), None, "picture"),
    "float32": (lambda: image_of(scaled(np.float32, -1.5, 2.5)), None, "picture"),
    "float64": (lambda: image_of(scaled(np.float64, 1e-3, 5e-3)), None, "picture"),
    "int64_offset": (lambda: image_of(scaled(np.int64, 2 ** 40, 2 ** 40 + 100)), None, ["offset"]),
    # -- components
    "vec3_magnitude": (lambda: image_of(vectors(np.float32, 3), 3), None, "picture"),
    "vec3_component_1": (lambda: image_of(vectors(np.float32, 3), 3), 1, "picture"),
    "vec2_int16_magnitude": (lambda: image_of(vectors(np.int16, 2), 2), "magnitude", "picture"),
    "vec4_uint8_component_3": (lambda: image_of(vectors(np.uint8, 4), 4), 3, "picture"),
    "vec3_nan_magnitude": (lambda: image_of(nan_vector(), 3), None, "picture"),
    "one_component_component_0": (lambda: image_of(BASE.astype(np.float32)), 0, "picture"),
    "component_out_of_range": (lambda: image_of(vectors(np.float32, 3), 3), 5, ["component 5", "0 .. 2"]),
    # -- degenerate geometry and values
    "constant_zero": (lambda: image_of(np.zeros((N, N, N), np.float32)), None, "picture"),
    "constant_float": (lambda: image_of(np.full((N, N, N), 7.25)), None, "picture"),
    "constant_uint8": (lambda: image_of(np.full((N, N, N), 200, np.uint8)), None, "picture"),
    "two_points_each_axis": (lambda: image_of(RNG.random((2, 2, 2)).astype(np.float32)), None, "picture"),
    "thin_2x2x16": (lambda: image_of(RNG.random((16, 2, 2)).astype(np.float32)), None, "picture"),
    "anisotropic_spacing": (lambda: image_of(BASE.astype(np.float32), spacing=(0.5, 1.0, 2.5)), None, "picture"),
    "rotated_direction": (lambda: image_of(BASE.astype(np.float32), direction=rotation()), None, "picture"),
    "line_1x1x8": (lambda: image_of(np.ones((8, 1, 1), np.float32)), None, ["at least 2 points"]),
    "one_voxel": (lambda: image_of(np.ones((1, 1, 1), np.float32)), None, ["at least 2 points"]),
    "single_slice": (lambda: image_of(np.ones((1, 8, 8), np.float32)), None, ["at least 2 points", "pad"]),
    "zero_spacing": (lambda: image_of(BASE.astype(np.float32), spacing=(1.0, 0.0, 1.0)), None, ["spacing", "zero"]),
    "negative_spacing": (lambda: image_of(BASE.astype(np.float32), spacing=(1.0, -1.0, 1.0)),
                         None, ["negative", "direction matrix"]),
    "nan_spacing": (lambda: image_of(BASE.astype(np.float32), spacing=(np.nan, 1.0, 1.0)), None, ["spacing"]),
    "sheared_direction": (lambda: image_of(BASE.astype(np.float32), direction=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]),
                          None, ["orthonormal", "vtkImageReslice"]),
    # VTK's GPU ray caster draws a reflection nearly blank (rays enter through the far faces): refused with the fix
    # (the pyvista filters and readers draw it right-handed: tests/test_pyvista_api.py)
    "mirrored_direction": (lambda: image_of(BASE.astype(np.float32), direction=np.diag([1.0, -1.0, 1.0])),
                           None, ["reflection", "mipcast.io.right_handed"]),
    "no_scalars": (no_scalars, None, ["no active point scalars"]),
    "cell_scalars_only": (cell_scalars, None, "picture"),
    "cell_scalars_one_cell_thick": (lambda: cell_scalars((N, 1, N)), None, ["at least 2 cells", "vtkCellDataToPointData"]),
    "empty": (lambda: vtkImageData(), None, ["empty"]),
}


@pytest.fixture(scope="module")
def views():
    """One view per method, reused by every case (the input changes between frames)."""
    start = make_fixture("spheres", size=8)
    return {name: OffscreenView(start, name, size=SIZE, view="oblique", window=(0.0, 1.0))
            for name in mipcast.METHODS}


def _show(view, image, component):
    """Put ``image`` into the shared view: window over its finite range, camera on its bounds."""
    prepared = prepare_scalars(image, component)
    low, high = prepared.low, prepared.high
    if not high > low:
        low, high = low - 1.0, high + 1.0
    view.set_input(image, component)
    view.set_window((low, high))
    distance = min(abs(s) for s in image.GetSpacing())
    view.mapper.SetSampleDistance(distance)
    view.sample_distance = distance
    set_view(view.renderer, image, "oblique")
    return prepared


def _reference(view, image, component):
    method = view.method
    return method.reference(image, view.camera, view.size, sample_distance=view.sample_distance,
                            window=view.window, component=component)


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize("method", list(mipcast.METHODS))
def test_bad_input_catalogue(views, method, case):
    make, component, expected = CASES[case]
    view = views[method]
    if method == "stock_average" and case.startswith("constant"):
        return _constant_stock_average(view, make)
    if expected != "picture":
        with pytest.raises(mipcast.InputError) as raised:  # the pyvista / CLI paths: before rendering
            mipcast.core.validation.check_image(make(), component)
        for word in expected:
            assert word in str(raised.value), str(raised.value)
        return _refused_in_a_pipeline(view, make, component, expected[0])

    image = make()
    prepared = _show(view, image, component)
    shot = view.screenshot()
    assert shot.max() > 0, "nothing drawn"
    if not view.method.float_readout:
        return _check_stock_picture(view, image, component, shot, prepared)
    found = view.float_image()
    if view.method.reference is not None:
        exact = _reference(view, image, component)
        hits = ~np.isnan(found) & ~np.isnan(exact)
        span = max(prepared.high - prepared.low, abs(prepared.high), 1e-30)
        assert hits.sum() > 0
        mismatch = np.mean(np.isnan(found) != np.isnan(exact))
        assert mismatch < 0.03, f"{mismatch:.3f} of the pixels disagree on hit / miss"
        tolerance = _tolerance(view.method, prepared, image)
        error = np.max(np.abs(found[hits] - exact[hits])) / span
        assert error <= tolerance, f"error {error:.3g} of the range > {tolerance:.3g}"
        if view.method.projection == "average" and (prepared.missing or not prepared.high > prepared.low):
            _check_stock_picture(view, image, component, shot, prepared)  # the grey over the finite range
    values = found[~np.isnan(found)]
    assert values.size, "no ray hit"
    slack = 1e-4 * max(prepared.high - prepared.low, abs(prepared.high), abs(prepared.low), 1e-30)
    assert values.min() >= prepared.low - slack and values.max() <= prepared.high + slack, (values.min(), values.max())
    if case.startswith("constant"):
        lit = shot.reshape(-1, 3)[~np.isnan(found.ravel())]
        assert np.ptp(lit) <= 1, f"a constant volume must give a uniform picture, got greys {np.unique(lit)}"


def _constant_stock_average(view, make):
    """VTK's own average draws a constant volume black (its samples normalise to 0): the caller is told why."""
    with pytest.warns(mipcast.InputWarning, match="constant.*stock_average.*black.*'average'"):
        _show(view, make(), None)
    shot = view.screenshot()
    assert shot.max() == 0, "VTK's AVERAGE_INTENSITY blend drew a constant volume: drop the warning"


def _tolerance(method, prepared, image) -> float:
    """The method's tolerance; float32 textures resolve 32/64-bit integers to 2**-24 of their magnitude."""
    tolerance = method.reference_tolerance
    if prepared.values.dtype.itemsize == 1 and not method.walks_cells:
        # the texture unit filters 8-bit texels in 8-bit steps (tests/test_mip_mapper.py): within 2 units
        tolerance = max(tolerance, 2.0 / max(prepared.high - prepared.low, 1e-30))
    if prepared.values.dtype.itemsize >= 4 and prepared.values.dtype != np.float32:
        magnitude = max(abs(prepared.low), abs(prepared.high))
        tolerance = max(tolerance, 4 * 2.0 ** -24 * magnitude / max(prepared.high - prepared.low, 1e-30))
    return tolerance


def _check_stock_picture(view, image, component, shot, prepared):
    """VTK's own mappers: a defined picture; stock's greys follow its sampled reference.

    Also the average's grey with missing values or a constant volume: the mean normalised over
    the finite range (a constant's widened by 1: ``view.window`` here).
    """
    if view.method.reference is None:
        return
    exact = _reference(view, image, component)
    low, high = view.window
    grey = np.clip((exact - low) / (high - low), 0.0, 1.0) * 255.0
    hits = ~np.isnan(exact)
    close = np.abs(shot[..., 0].astype(float)[hits] - grey[hits]) <= 3.0
    assert close.mean() > 0.97, f"only {close.mean():.3f} of the pixels within 3 greys of the reference"


def test_catalogue_is_large_enough():
    assert len(CASES) >= 40 and len(CASES) * len(mipcast.METHODS) >= 280


def test_inf_warns_once_per_volume():
    import warnings

    image = image_of(holes(BASE.astype(np.float32), 9, np.inf))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        view = OffscreenView(image, "mip", size=(16, 16), window=(0.0, 1.0))
        for _ in range(3):
            view.screenshot()
    assert sum(issubclass(w.category, mipcast.InputWarning) for w in caught) == 1


def test_user_image_is_not_modified_and_get_input_returns_it():
    values = holes(BASE.astype(np.float32))
    image = image_of(values)
    before = np.asarray(image.GetPointData().GetScalars()).copy()
    view = OffscreenView(image, "analytic", size=(16, 16), window=(0.0, 1.0))
    view.screenshot()
    assert view.mapper.GetInput() is image
    after = np.asarray(image.GetPointData().GetScalars())
    assert np.array_equal(np.isnan(before), np.isnan(after)) and np.array_equal(before[~np.isnan(before)],
                                                                              after[~np.isnan(after)])


def test_dicom_error_is_an_input_error():
    from mipcast.io.dicom import DicomError

    assert issubclass(DicomError, mipcast.InputError) and issubclass(mipcast.InputError, ValueError)


def test_bit_arrays_are_refused_with_the_cast():
    from vtkmodules.vtkCommonCore import vtkBitArray

    image = vtkImageData()
    image.SetDimensions(2, 2, 2)
    bits = vtkBitArray()
    bits.SetNumberOfTuples(8)
    image.GetPointData().SetScalars(bits)
    with pytest.raises(TypeError, match="vtkImageCast"):
        mipcast.core.validation.check_image(image)


def test_component_in_pyvista_and_cli(tmp_path):
    """``component=`` (pyvista) and ``--component`` (CLI) draw the chosen component; bad ones fail first."""
    import pyvista

    from mipcast.app.cli import main
    from mipcast.filters import render

    image = image_of(vectors(np.float32, 3), 3)
    grid = pyvista.wrap(image)
    second = render(grid, "mip", size=(24, 24), window=(0.0, 2.0), component=1, as_float=True)
    alone = render(pyvista.wrap(image_of(np.ascontiguousarray(vectors(np.float32, 3)[..., 1]))), "mip",
                   size=(24, 24), window=(0.0, 2.0), as_float=True)
    assert np.nanmax(second) > 1.0 and np.allclose(second, alone, equal_nan=True)
    import mipcast.filters  # noqa: F401  (registers grid.mip)
    accessor = grid.mip.render("mip", size=(24, 24), window=(0.0, 2.0), component=1, as_float=True)
    assert np.allclose(accessor, alone, equal_nan=True)
    with pytest.raises(mipcast.InputError, match="component 3"):
        render(grid, "analytic", size=(24, 24), component=3)
    path = tmp_path / "vectors.vti"
    grid.save(str(path))
    out = tmp_path / "component.png"
    assert main(["render", str(path), "--method", "analytic", "--component", "2", "--size", "24", "24",
                 "--out", str(out)]) == 0 and out.stat().st_size > 0
    assert main(["render", str(path), "--component", "7", "--size", "24", "24", "--out", str(out)]) == 2
    from mipcast.app.viewer import build_viewer

    plotter = build_viewer(image, "analytic", off_screen=True, window_size=(48, 48), component=0)
    try:
        assert plotter.screenshot().max() > 0
    finally:
        plotter.close()


def test_inf_warns_once_even_for_foveated_levels():
    import warnings

    image = image_of(holes(BASE.astype(np.float32), 8, -np.inf))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        view = OffscreenView(image, "foveated", size=(32, 32), window=(0.0, 1.0))
        view.screenshot()
        view.screenshot()
    assert sum(issubclass(w.category, mipcast.InputWarning) for w in caught) == 1


@pytest.mark.parametrize("method", list(mipcast.METHODS))
def test_rays_without_finite_data_show_the_background(method):
    """A land mask: where rays cross only NaN the picture shows the background, in the display path too.

    Every method: mipcast's discard such rays (NaN in the float readout); VTK's own (stock, cpu) draw
    them through a property that is transparent on the fill's side of the data.
    """
    image = image_of(nan_half())
    prepared = prepare_scalars(image)
    view = OffscreenView(image, method, size=(32, 32), view="front", window=(prepared.low, prepared.high))
    view.renderer.SetBackground(0.0, 0.0, 1.0)
    shot = view.screenshot().astype(int)
    background = (shot[..., 2] == 255) & (shot[..., 0] == 0)
    left, right = background[:, 2:14], background[8:24, 17:23]  # the NaN half and the finite half, from the front
    assert left.mean() > 0.9, f"{left.mean():.2f} of the all-missing rays show the background"
    assert right.mean() < 0.1, "the finite half must be drawn"
    if view.method.float_readout:
        missing = np.isnan(view.float_image())
        assert missing[:, 2:14].mean() > 0.9 and not missing[8:24, 17:23].any()
        if view.method.reference is not None:
            assert np.mean(missing != np.isnan(_reference(view, image, None))) < 0.03


def test_a_whole_nan_column_is_background_in_every_method():
    """A 2x2 column of voxels (all z) is NaN: seen along it, its rays show the background, the rest is drawn."""
    from scipy.ndimage import binary_dilation

    values = BASE.astype(np.float32).copy()
    values[:, 4:6, 4:6] = np.nan  # (z, y, x): the column runs along z, the front view looks along it
    image = image_of(values)
    prepared = prepare_scalars(image)
    first = OffscreenView(image, "mip", size=(40, 40), view="front", window=(prepared.low, prepared.high))
    hole = np.isnan(_reference(first, image, None))
    inside = ~np.isnan(_reference(first, image_of(BASE.astype(np.float32)), None))
    hole &= inside
    solid = inside & ~binary_dilation(hole, iterations=2)  # rays near the column are pulled, not missing
    assert 4 <= hole.sum() <= 200 and solid.sum() > 400
    for method in mipcast.METHODS:
        view = OffscreenView(image, method, size=(40, 40), view="front", window=(prepared.low, prepared.high))
        view.renderer.SetBackground(0.0, 0.0, 1.0)
        shot = view.screenshot().astype(int)
        background = (shot[..., 2] == 255) & (shot[..., 0] == 0) & (shot[..., 1] == 0)
        assert background[hole].mean() > 0.9, f"{method}: {background[hole].mean():.2f} of the column's rays"
        assert background[solid].mean() < 0.01, f"{method}: {background[solid].mean():.2f} of the finite rays"


@pytest.mark.parametrize("cells", [False, True])
def test_hidden_points_and_cells_are_drawn_as_missing_data_in_every_method(cells):
    """Points (cells) VTK's ghost array marks hidden are missing data, drawn exactly as NaN there is; before
    2026-12-04 mipcast drew their values, and VTK's own mappers, given mipcast's copy with the ghost array,
    hid them their own way (56 % of stock's pixels off the NaN picture)."""
    image = hidden(scaled(np.float32, 0.0, 1.0), cells=cells)
    data = image.GetCellData() if cells else image.GetPointData()
    values = vtk_to_numpy(data.GetScalars()).copy()
    values[vtk_to_numpy(data.GetArray("vtkGhostType")) > 0] = np.nan
    twin = vtkImageData()
    twin.CopyStructure(image)
    (twin.GetCellData() if cells else twin.GetPointData()).SetScalars(numpy_to_vtk(values, deep=True))
    assert np.isnan(values).mean() > 0.3
    window = (0.0, 1.0)
    for method in mipcast.METHODS:
        shots = [OffscreenView(data_set, method, size=SIZE, view="oblique", window=window).screenshot()
                 for data_set in (image, twin)]
        assert shots[1].max() > 60, method
        assert np.abs(shots[0].astype(int) - shots[1]).max() <= 1, method


@pytest.mark.parametrize("resampler", ["vtkResampleToImage", "vtkProbeFilter"])
def test_resample_to_image_draws_the_mesh_not_its_bounding_box(resampler):
    """ParaView's "Resample To Image" (vtkResampleToImage) of an unstructured mesh marks the points outside
    the mesh HIDDENPOINT, vtkProbeFilter 0 in vtkValidPointMask (value 0 there): the projections draw the
    mesh, and its average is not pulled towards 0 by the box around it (before 2026-12-04 the box was drawn:
    every ray through it hit)."""
    from vtkmodules.vtkFiltersCore import vtkDelaunay3D, vtkElevationFilter, vtkProbeFilter, vtkResampleToImage
    from vtkmodules.vtkFiltersSources import vtkSphereSource

    sphere = vtkSphereSource()
    sphere.SetThetaResolution(24)
    sphere.SetPhiResolution(24)
    elevation = vtkElevationFilter()
    elevation.SetInputConnection(sphere.GetOutputPort())
    mesh = vtkDelaunay3D()
    mesh.SetInputConnection(elevation.GetOutputPort())
    if resampler == "vtkResampleToImage":
        resample = vtkResampleToImage()
        resample.SetInputConnection(mesh.GetOutputPort())
        resample.SetSamplingDimensions(24, 24, 24)
    else:
        grid = vtkImageData()
        grid.SetDimensions(24, 24, 24)
        grid.SetOrigin(-0.5, -0.5, -0.5)
        grid.SetSpacing(1.0 / 23, 1.0 / 23, 1.0 / 23)
        resample = vtkProbeFilter()
        resample.SetInputData(grid)
        resample.SetSourceConnection(mesh.GetOutputPort())
    resample.Update()
    image = resample.GetOutput()
    image.GetPointData().SetActiveScalars("Elevation")
    assert prepare_scalars(image).missing > 0.4 * image.GetNumberOfPoints()  # the box's corners, hidden
    for method in ("analytic", "analytic_average"):
        view = OffscreenView(image, method, size=(64, 64), view="front", window="full")
        found = view.float_image()
        disc = ~np.isnan(found)
        assert 0.15 < disc.mean() < 0.35, (method, disc.mean())  # the sphere's disc, not the box's square
        exact = _reference(view, image, None)
        assert np.array_equal(disc, ~np.isnan(exact)), method
        assert np.nanmax(np.abs(found - exact)) <= 1e-3, method


def _refused_in_a_pipeline(view, make, component, word):
    """VTK's own mappers: refused before (prepared copy); mipcast's: a VTK error event, the reason, nothing drawn."""
    if not view.method.float_readout:
        with pytest.raises(mipcast.InputError, match=word):
            view.set_input(make(), component)
        return
    view.mapper.SetComponent(component if component is not None and component >= 0 else -1)
    view.mapper.SetInputData(make())
    events = []
    tag = view.mapper.AddObserver(vtkCommand.ErrorEvent, lambda *args: events.append(args))
    try:
        shot = view.screenshot()
    finally:
        view.mapper.RemoveObserver(tag)
    assert events, "no VTK error event"
    problem = view.mapper.GetLastProblem()
    assert problem is not None and word in problem, problem
    assert shot.max() == 0, "a refused input must draw nothing (nothing stale)"


@pytest.mark.parametrize("method", ["mip", "stock", "foveated", "analytic"])
def test_a_volume_far_from_the_origin_warns_once_with_the_fix(method):
    """UTM-like coordinates: the GPU's float32 rays misplace some (docs/reliability.md, *Coordinates far from the
    origin*: 34 % of a phantom's pixels off at 1e6 spacings, against the float64 reference on the same rays).  One
    InputWarning per origin naming the fix; none at 1e4 spacings (within float32 rounding of the reference)."""
    import warnings

    from vtkmodules.vtkCommonDataModel import vtkImageData

    from mipcast.data_fixtures import make_fixture

    far = 1.0e6 + 17.0 * ["mip", "stock", "foveated", "analytic"].index(method)  # the warning is once per origin
    for origin, expected in ((1.0e4, 0), (far, 1)):
        image = vtkImageData()
        image.DeepCopy(make_fixture("vessels", size=16))
        image.SetOrigin(origin, -origin, 0.5 * origin)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            view = OffscreenView(image, method, size=(16, 16), window=(0.2, 1.0))
            view.screenshot()
            view.screenshot()
        said = [w for w in caught if issubclass(w.category, mipcast.InputWarning) and "origin" in str(w.message)]
        assert len(said) == expected, [str(w.message) for w in caught]
        if expected:
            assert "voxel spacings from the origin" in str(said[0].message)
            assert "SetOrigin(0, 0, 0)" in str(said[0].message)
