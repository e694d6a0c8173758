"""The GLSL piece loader: headers, tags, slots, no user values in source; the one sampled loop."""
import re
from importlib import resources

import numpy as np
import pytest
from vtkmodules.vtkRenderingCore import vtkVolume

import mipcast
from mipcast.data_fixtures import make_fixture
from mipcast.mappers import shader_pieces
from mipcast.mappers.demip_two_pass import DEMIPFirstPassMapper
from mipcast.mappers.mip import MIPVolumeMapper, sampled_projection_mapper
from mipcast.mappers.shader_pieces import (CELL_HOOKS, HOOK_TAG, SAMPLED_HOOKS, SAMPLED_LOOP, TEMPLATE_TAGS,
                                           check_hooks, install, installed_tags, load_piece, parse_piece, uninstall)
from mipcast.offscreen import OffscreenView

ALL_PIECES = sorted(p.name[:-5] for p in resources.files("mipcast.shaders").iterdir()
                    if p.name.endswith(".glsl"))
HEADER = "// mipcast piece: p\n// fills: {tag}\n// mode: {mode}\n"


def test_there_are_pieces():
    assert {"sampled_loop", "mip_hooks", "mip_color", "float_readout"} <= set(ALL_PIECES)


@pytest.mark.parametrize("name", ALL_PIECES)
def test_every_piece_loads_and_fills_a_template_tag(name):
    piece = load_piece(name)
    assert piece.tag in TEMPLATE_TAGS
    assert "//VTK::" not in piece.text
    assert load_piece(name) is piece, "pieces are cached"


def test_every_method_uses_existing_pieces_once_per_tag():
    for method in mipcast.METHODS.values():
        names = getattr(method.factory, "PIECES", ())
        tags = [load_piece(n).tag for n in names]
        assert len(tags) == len(set(tags))


def test_augment_keeps_vtk_code_replace_drops_it():
    augment = parse_piece("p", HEADER.format(tag="Base::Dec", mode="augment") + "float a;\n")
    replace = parse_piece("p", HEADER.format(tag="Shading::Init", mode="replace") + "a = 1;\n")
    assert augment.replacement.startswith("//VTK::Base::Dec\n")
    assert "//VTK::" not in replace.replacement


@pytest.mark.parametrize("text, message", [
    ("float a;\n", "header"),
    (HEADER.format(tag="Nope::Dec", mode="replace"), "unknown tag"),
    (HEADER.format(tag="Base::Dec", mode="prepend"), "mode"),
    (HEADER.format(tag="Base::Dec", mode="replace") + "// see //VTK::Base::Dec\n", "substitute"),
    (HEADER.format(tag="Base::Dec", mode="replace").replace(": p", ": q", 1), "declares the name"),
])
def test_bad_pieces_are_refused(text, message):
    with pytest.raises(ValueError, match=message):
        parse_piece("p", text)


def test_missing_piece_is_an_error():
    with pytest.raises(ValueError, match="no shader piece"):
        load_piece("does_not_exist")


def test_two_pieces_for_one_slot_are_refused():
    twin = parse_piece("p", HEADER.format(tag="Shading::Exit", mode="replace"))
    with pytest.raises(ValueError, match="both fill"):
        install(vtkVolume().GetShaderProperty(), [load_piece("mip_color"), twin])


def test_install_keeps_foreign_code_on_other_slots_and_uninstall_leaves_it():
    prop = vtkVolume().GetShaderProperty()
    prop.AddFragmentShaderReplacement("//VTK::Picking::Exit", True, "foreign();", False)
    install(prop, [load_piece("mip_color"), load_piece("mip_globals")])
    assert installed_tags(prop) == ["//VTK::Base::Dec", "//VTK::Shading::Exit"]
    uninstall(prop)
    assert installed_tags(prop) == []
    assert prop.GetNumberOfShaderReplacements() == 1


def test_no_python_module_builds_glsl_from_values():
    # Numbers reach the shader through uniforms only: no module formats GLSL text.
    package = resources.files("mipcast")
    for module in package.iterdir():
        if module.name.endswith(".py"):
            source = module.read_text()
            assert "AddFragmentShaderReplacement(" not in source or module.name == "shader_pieces.py"
    assert shader_pieces.install.__module__ == "mipcast.mappers.shader_pieces"


# -- the one sampled ray loop and its hooks ------------------------------------------

#: Hook pieces of the sampled loop, and of the exact projections' cell walk (amip_*_hooks).
HOOK_PIECES = [name for name in ALL_PIECES if load_piece(name).tag == HOOK_TAG and not name.startswith("amip_")]
CELL_HOOK_PIECES = [name for name in ALL_PIECES if load_piece(name).tag == HOOK_TAG and name.startswith("amip_")]
#: The analytic method walks cells with loops of its own (they share amip_cell).
CELL_WALKS = {"amip_loop", "amip_loop_blocks"}
TOY_FIRST_SAMPLE = """// mipcast piece: toy_first_sample
// fills: Picking::Dec
// mode: augment
// Toy projection: the first sample along the ray.
void mcBeginRay(inout int first, inout int count)
{
  mc_rayMax = -1.0e30;
}

bool mcSample(float value, int i)
{
  mc_rayMax = value;
  return false;
}

void mcEndRay(int count)
{
  mc_rayMax = mcNormalised(mc_rayMax);
}
"""


def _code(piece) -> str:
    """The piece's GLSL without its comments."""
    return re.sub(r"//[^\n]*", "", piece.text)


def _sampled_piece_lists() -> dict:
    """Every sampled method's piece list, by a name for the message."""
    lists = {"mip": MIPVolumeMapper.PIECES, "minip": mipcast.MinIPVolumeMapper.PIECES,
             "average": mipcast.AverageVolumeMapper.PIECES}
    demip = mipcast.DEMIPVolumeMapper()
    demip.SetDepthWeight(0.5)
    for projection in ("mip", "lmip", "attenuated", "mida"):
        demip.SetProjection(projection)
        lists[f"demip {projection}"] = demip.GetShaderPieces()
    first = DEMIPFirstPassMapper()
    lists["two-pass first"] = first.GetShaderPieces()
    lists["two-pass second"] = mipcast.DEMIPTwoPassVolumeMapper().GetShaderPieces()
    return lists


@pytest.mark.parametrize("method, names", sorted(_sampled_piece_lists().items()))
def test_every_sampled_method_runs_the_one_loop_with_one_hook_piece(method, names):
    assert SAMPLED_LOOP in names, method
    hooks = [name for name in names if load_piece(name).tag == HOOK_TAG]
    assert len(hooks) == 1, (method, hooks)
    check_hooks(load_piece(hooks[0]))
    assert not [name for name in names if name in CELL_WALKS or name.endswith("_loop") and name != SAMPLED_LOOP]


@pytest.mark.parametrize("cls, hooks", [("AnalyticMIPVolumeMapper", "amip_max_hooks"),
                                        ("AnalyticMinIPVolumeMapper", "amip_min_hooks"),
                                        ("AnalyticAverageVolumeMapper", "amip_average_hooks")])
def test_the_exact_methods_share_the_cell_walk_with_one_cell_hook_piece(cls, hooks):
    names = getattr(mipcast, cls)().GetShaderPieces()
    assert SAMPLED_LOOP not in names and "amip_cell" in names and "amip_loop" in names
    assert [name for name in names if load_piece(name).tag == HOOK_TAG] == [hooks]


@pytest.mark.parametrize("name", CELL_HOOK_PIECES)
def test_every_cell_hook_piece_defines_every_cell_hook(name):
    assert check_hooks(load_piece(name), CELL_HOOKS) is load_piece(name)
    with pytest.raises(ValueError, match="sampled loop's hook"):
        check_hooks(load_piece(name))


def test_the_cell_walk_is_refused_without_a_cell_hook_piece():
    names = [n for n in mipcast.AnalyticMIPVolumeMapper.PIECES if n != "amip_max_hooks"]
    with pytest.raises(ValueError, match="cell-hook piece"):
        install(vtkVolume().GetShaderProperty(), [load_piece(n) for n in names])


@pytest.mark.parametrize("name", ALL_PIECES)
def test_no_piece_but_the_loops_marches(name):
    # one sampled march (sampled_loop) and analytic MIP's cell walks; every other
    # piece fills hooks or helpers without a loop of its own
    loops = re.findall(r"\b(?:for|while)\s*\(", _code(load_piece(name)))
    if name == SAMPLED_LOOP:
        # the first march, the optional second march, and (cropping regions with block skipping) the
        # visibility test of jumped samples, which reads no texture
        assert len(loops) == 3, "the first march, the optional second march and the jumped samples' visibility"
    elif name == "amip_average_hooks":
        # the bisection of a crossing with the missing-value floor (24 halvings of [0, 1], no texture read):
        # a loop, which llvmpipe skips where no lane of a group needs it; written out, every cell ran it
        # (the exact average of vessels 64³ with every 13th voxel NaN, 256²: 128-131 ms written out, 60-62 a loop)
        code = _code(load_piece(name))
        assert len(loops) == 1 and "for (int k = 0; k < 24; ++k)" in code
        assert "texture" not in code and "texelFetch" not in code
    elif name not in CELL_WALKS:
        assert not loops, f"{name} has a loop of its own; fill sampled_loop's hooks instead"


def test_the_loop_samples_at_entry_plus_i_steps_and_calls_every_hook():
    code = _code(load_piece(SAMPLED_LOOP))
    assert code.count("mc_base + float(mc_") == 2
    assert "vec3 mc_base = g_dataPos;" in code  # moved only by the global_phase piece (distributed bricks)
    for hook in list(SAMPLED_HOOKS) + ["mcBeginSecondMarch", "mcSecondSample", "mcEndSecondMarch"]:
        assert f"{hook}(" in code


@pytest.mark.parametrize("name", HOOK_PIECES)
def test_every_hook_piece_defines_every_hook(name):
    assert check_hooks(load_piece(name)) is load_piece(name)


def test_hook_pieces_exist_for_every_sampled_method():
    assert {"mip_hooks", "demip_hooks", "demip_lmip_hooks", "demip_attenuated_hooks", "demip_mida_hooks",
            "demip_two_pass_first_hooks", "demip_two_pass_second_hooks"} <= set(HOOK_PIECES)


def test_the_refusal_test_is_written_once():
    owners = [name for name in ALL_PIECES if "u_mc_refused" in _code(load_piece(name))]
    assert owners == ["mip_globals"]


@pytest.fixture
def piece_folder(tmp_path):
    folder = shader_pieces.register_folder(tmp_path)
    yield tmp_path
    shader_pieces.unregister_folder(folder)


def test_a_piece_from_a_registered_folder_loads(piece_folder):
    (piece_folder / "toy_first_sample.glsl").write_text(TOY_FIRST_SAMPLE)
    piece = load_piece("toy_first_sample")
    assert piece.tag == HOOK_TAG and check_hooks(piece) is piece
    cls = sampled_projection_mapper("toy_first_sample")
    assert issubclass(cls, MIPVolumeMapper)
    assert "toy_first_sample" in cls.PIECES and "mip_hooks" not in cls.PIECES
    shader_pieces.unregister_folder(piece_folder)
    with pytest.raises(ValueError, match="no shader piece"):
        load_piece("toy_first_sample")


def test_package_pieces_come_before_registered_ones(piece_folder):
    (piece_folder / "mip_hooks.glsl").write_text(TOY_FIRST_SAMPLE.replace("toy_first_sample", "mip_hooks"))
    assert "return false" not in load_piece("mip_hooks").text


def test_a_missing_folder_is_refused(tmp_path):
    with pytest.raises(ValueError, match="no folder"):
        shader_pieces.register_folder(tmp_path / "absent")


@pytest.mark.parametrize("hook", list(SAMPLED_HOOKS))
def test_a_missing_hook_is_a_clear_error(piece_folder, hook):
    text = TOY_FIRST_SAMPLE.replace(hook + "(", "notAHook(")
    (piece_folder / "toy_first_sample.glsl").write_text(text)
    with pytest.raises(ValueError, match=rf"does not define the sampled loop's hook.*{hook}"):
        sampled_projection_mapper("toy_first_sample")
    pieces = [load_piece(name) for name in MIPVolumeMapper.PIECES if name != "mip_hooks"]
    with pytest.raises(ValueError, match=rf"{hook}"):
        install(vtkVolume().GetShaderProperty(), pieces + [load_piece("toy_first_sample")])


def test_the_loop_without_a_hook_piece_is_refused():
    pieces = [load_piece(name) for name in MIPVolumeMapper.PIECES if name != "mip_hooks"]
    with pytest.raises(ValueError, match="needs a hook piece"):
        install(vtkVolume().GetShaderProperty(), pieces)


def test_a_hook_piece_in_another_slot_is_refused(piece_folder):
    (piece_folder / "toy_first_sample.glsl").write_text(TOY_FIRST_SAMPLE.replace("Picking::Dec", "Shading::Dec"))
    with pytest.raises(ValueError, match=HOOK_TAG):
        sampled_projection_mapper("toy_first_sample")


@pytest.fixture
def toy_methods():
    """Register methods for one test; unregistered afterwards."""
    names = []

    def add(name, hooks):
        mipcast.methods.register(mipcast.methods.Method(name, name, "a toy", sampled_projection_mapper(hooks)))
        names.append(name)

    yield add
    for name in names:
        mipcast.methods.unregister(name)


def test_a_one_piece_projection_renders(piece_folder, toy_methods):
    # the toy method "first sample along the ray": one hook piece, nothing else
    (piece_folder / "toy_first_sample.glsl").write_text(TOY_FIRST_SAMPLE)
    (piece_folder / "toy_mip.glsl").write_text(load_piece("mip_hooks").text.replace("mip_hooks", "toy_mip", 1))
    toy_methods("toy_first", "toy_first_sample")
    toy_methods("toy_mip", "toy_mip")
    image = make_fixture("vessels", size=32)
    mip = OffscreenView(image, "mip", size=(48, 40)).float_image()
    first = OffscreenView(image, "toy_first", size=(48, 40)).float_image()
    again = OffscreenView(image, "toy_mip", size=(48, 40)).float_image()
    np.testing.assert_array_equal(again, mip)  # the same hooks under another name: the same picture
    hits = ~np.isnan(mip)
    assert 0.1 < hits.mean() and np.array_equal(np.isnan(first), ~hits)
    assert np.all(first[hits] <= mip[hits]) and np.mean(first[hits] < mip[hits]) > 0.2
