"""Nothing from the user reaches GLSL text (issue #13, item 10).

Every public setter of every mipcast mapper (the parameter tables' ``SetX``,
``choice`` and ``value`` kinds included, and the hand-written ones) is given
hostile text; the value must be refused with a TypeError/ValueError, or
accepted without any change to the fragment shader VTK really compiled (read
back from the render window's shader cache after a render) or to the shader
replacements on the volume.
"""
import numpy as np
import pytest

from mipcast.core import parameter_tables
from mipcast.core.parameters import parameter_table
from mipcast.data_fixtures import make_fixture
from mipcast.mappers import shader_pieces
from mipcast.mappers.mip import sampled_projection_mapper
from mipcast.methods import METHODS
from mipcast.offscreen import OffscreenView

HOSTILE = (
    "mip\n}\nvoid main(){ gl_FragColor = vec4(1); }",
    "//VTK::Base::Dec",
    "'; DROP TABLE shaders; --",
    "m\u00efp \u2620 \u202e\u0000 \U0001f480",
    "mc_hostile_" * 20000,  # 220,000 characters
)
#: Strings that cannot appear in any legitimate shader (the tag one can: VTK keeps some tags as comments).
DISTINCTIVE = ("void main(){ gl_FragColor", "DROP TABLE", "\u2620", "mc_hostile_mc_hostile_")


def _compiled(view):
    """The fragment source VTK compiled for the last draw, and the volume's shader replacements."""
    view.screenshot()
    program = view.render_window.GetShaderCache().GetLastShaderBound()
    source = program.GetFragmentShader().GetSource()
    replacements = tuple(text for _, text in shader_pieces._fragment_replacements(view.volume.GetShaderProperty()))
    return source, replacements


def _public_setters(mapper):
    """``Set*`` methods mipcast defines on the mapper's class (VTK's own setters take no strings to GLSL)."""
    return sorted({name for cls in type(mapper).__mro__ if cls.__module__.startswith("mipcast")
                   for name in vars(cls) if name.startswith("Set")})


def _get(mapper, getter):
    """The getter's value, or None where there is no argument-free getter."""
    try:
        return getattr(mapper, getter)()
    except (AttributeError, TypeError):
        return None


MAPPED = [name for name, method in METHODS.items() if parameter_table(method.create()) or
          type(method.create()).__module__.startswith("mipcast")]


def test_the_string_parameters_of_every_table_are_covered():
    setters = {setter for name in MAPPED for setter in _public_setters(METHODS[name].create())}
    tables = [t for t in vars(parameter_tables).values() if isinstance(t, tuple) and t and
              all(hasattr(p, "kind") for p in t)]
    strings = {p.setter for table in tables for p in table if p.kind in ("choice", "value")}
    assert strings and strings <= setters, strings - setters


@pytest.mark.parametrize("name", MAPPED)
def test_hostile_text_is_refused_or_changes_no_shader(name):
    view = OffscreenView(make_fixture("vessels", size=12), name, size=(24, 24))
    mapper = view.mapper
    base = _compiled(view)
    assert "mipcast piece" in base[0]  # the program read back is the volume's, with mipcast's pieces
    accepted = []
    for setter in _public_setters(mapper):
        getter = "Get" + setter[3:]
        before = _get(mapper, getter)
        for text in HOSTILE:
            try:
                getattr(mapper, setter)(text)
            except (TypeError, ValueError):
                pass
            else:
                accepted.append(setter)
            source, replacements = _compiled(view)
            for marker in DISTINCTIVE:
                assert marker not in source and not any(marker in r for r in replacements), (setter, marker)
            assert source == base[0] and replacements == base[1], (setter, text[:20])
            if before is not None and setter not in accepted:
                after = _get(mapper, getter)
                assert after is before or np.array_equal(np.asarray(after, dtype=object),
                                                          np.asarray(before, dtype=object)), setter
        if before is not None and setter in accepted:
            getattr(mapper, setter)(before)  # put the (default) value back for the next setter
    # accepted: only booleans, which take any object's truth value and install no text (see docs)
    kinds = {p.setter: p.kind for p in parameter_table(mapper)}
    assert all(kinds.get(s) == "bool" for s in accepted), accepted
    assert np.isfinite(view.float_image()).any() if METHODS[name].float_readout else True


def test_piece_names_and_folders_from_the_user_are_refused():
    for text in HOSTILE:
        with pytest.raises(ValueError):
            shader_pieces.load_piece(text)
        with pytest.raises(ValueError):
            sampled_projection_mapper(text)
        with pytest.raises((ValueError, OSError)):
            shader_pieces.register_folder(text)
    for text in HOSTILE:
        for keyword in ("method", "view", "window"):
            with pytest.raises((TypeError, ValueError)):
                OffscreenView(make_fixture("spheres", size=8), **{keyword: text}, size=(8, 8))


def test_the_check_reads_the_source_vtk_compiled():
    """Control: text that does reach the shader (a replacement put on the volume) is seen by the check."""
    view = OffscreenView(make_fixture("vessels", size=12), "analytic", size=(24, 24))
    base, _ = _compiled(view)
    view.volume.GetShaderProperty().AddFragmentShaderReplacement(
        "//VTK::Termination::Dec", True, "//VTK::Termination::Dec\n// DROP TABLE (control)\n", False)
    source, _ = _compiled(view)
    assert "DROP TABLE (control)" in source and "DROP TABLE" not in base
