"""The method table is the one definition of a method.

``test_every_method_matches_its_reference`` is the registry-driven accuracy
test: every method of the table with a float readout against its own float64
reference.  ``test_a_toy_method_registered_in_the_table_only_appears_everywhere``
registers a method with one table entry, one GLSL piece and one reference
function, and finds it in the command line, the pyvista accessor, the
viewer's method cycle, the benchmark's rows, the stability cases and the
accuracy test.
"""
import numpy as np
import pytest
import pyvista as pv

import mipcast
import mipcast.filters  # noqa: F401  (registers grid.mip)
from mipcast.data_fixtures import make_fixture
from mipcast.mappers import shader_pieces
from mipcast.mappers.mip import sampled_projection_mapper
from mipcast.methods import METHODS, Method, register, unregister
from mipcast.offscreen import OffscreenView
from mipcast.reference.rays import hit_rays, scatter, trilinear
from test_shader_pieces import TOY_FIRST_SAMPLE  # the one-piece toy projection

FIRST_SAMPLE_PIECE = TOY_FIRST_SAMPLE.replace("toy_first_sample", "toy_first_sample_only", 1)


def first_sample_reference(image, camera, size, *, sample_distance, window=None):
    """float64: the trilinear value one sample distance inside the box entry (mipcast's first sample,
    clamped to the point bounds as the texture is)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    width, height = size
    nx, ny, nz = image.GetDimensions()
    values = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(nz, ny, nx).astype(np.float64)
    hit, entry, direction, length = hit_rays(image, camera, size)
    return scatter(trilinear(values, entry + sample_distance * direction), hit, height, width)


def accuracy(name: str, view: str):
    """Largest error of ``name``'s float readout against its reference, in fractions of the data range."""
    method = METHODS[name]
    image = make_fixture("vessels", size=32)
    scene = OffscreenView(image, name, size=(48, 40), view=view)
    got = scene.float_image()
    expected = method.reference(image, scene.camera, scene.size, sample_distance=scene.sample_distance,
                                window=scene.window)
    low, high = image.GetPointData().GetScalars().GetRange(0)
    assert np.array_equal(np.isnan(got), np.isnan(expected)), "the method and its reference hit other pixels"
    assert np.isfinite(got).mean() > 0.2, "(nearly) nothing was hit"
    both = np.isfinite(got)
    return float(np.max(np.abs(got[both] - expected[both])) / (high - low))


CHECKED = [name for name, m in METHODS.items() if m.float_readout and m.reference is not None]


@pytest.mark.parametrize("view", ["oblique", "perspective"])
@pytest.mark.parametrize("name", CHECKED)
def test_every_method_matches_its_reference(name, view):
    assert accuracy(name, view) <= METHODS[name].reference_tolerance


def test_every_renderable_method_has_a_reference_or_says_why_not():
    for name, method in METHODS.items():
        assert method.reference is not None or name == "foveated" or not method.float_readout, name


@pytest.fixture
def toy(tmp_path):
    (tmp_path / "toy_first_sample_only.glsl").write_text(FIRST_SAMPLE_PIECE)
    folder = shader_pieces.register_folder(tmp_path)
    register(Method("toy_first", "First sample", "the value of the first sample along the ray",
                    sampled_projection_mapper("toy_first_sample_only"), reference=first_sample_reference,
                    reference_tolerance=1e-4))
    yield "toy_first"
    unregister("toy_first")
    shader_pieces.unregister_folder(folder)


def test_a_toy_method_registered_in_the_table_only_appears_everywhere(toy, tmp_path):
    from mipcast.app.cli import main
    from mipcast.app.viewer import view_methods
    from mipcast.bench.benchmark import default_settings
    from mipcast.bench.stability import cases

    # the registry-driven accuracy test, on the toy: exact against its own reference
    for view in ("oblique", "perspective"):
        assert accuracy(toy, view) <= 1e-4
    # it is a different picture from MIP's (the first sample is not the maximum)
    image = make_fixture("vessels", size=32)
    first = OffscreenView(image, toy, size=(48, 40)).screenshot()
    assert not np.array_equal(first, OffscreenView(image, "mip", size=(48, 40)).screenshot())

    # the command line: a --method choice that renders
    volume = tmp_path / "vessels.vti"
    pv.wrap(image).save(str(volume))
    out = tmp_path / "toy.png"
    assert main(["render", str(volume), "--method", toy, "--out", str(out), "--size", "48", "40"]) == 0
    assert out.stat().st_size > 0
    # pyvista: grid.mip.render
    picture = pv.wrap(image).mip.render(toy, size=(48, 40))
    assert picture.max() > 50
    # the viewer's method cycle, the benchmark's rows, the stability cases
    assert toy in view_methods()
    assert [s.label for s in default_settings() if s.method == toy] == [toy]
    assert toy in {case.method for case in cases()}


def test_registering_a_name_again_replaces_it_and_unregister_removes_it():
    method = Method("toy_again", "Toy", "VTK's own", METHODS["stock"].factory, float_readout=False)
    register(method)
    try:
        assert METHODS["toy_again"] is method and mipcast.create_mapper("toy_again") is not None
    finally:
        unregister("toy_again")
    assert "toy_again" not in METHODS
