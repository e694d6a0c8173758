"""The GLSL piece loader: headers, tags, slots, no user values in source."""
from importlib import resources

import pytest
from vtkmodules.vtkRenderingCore import vtkVolume

import mipcast
from mipcast.mappers import shader_pieces
from mipcast.mappers.shader_pieces import TEMPLATE_TAGS, install, installed_tags, load_piece, parse_piece, uninstall

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
    for factory in mipcast.METHODS.values():
        names = getattr(factory, "PIECES", ())
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
