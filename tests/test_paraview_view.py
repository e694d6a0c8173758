"""mipcast in ParaView's render view (plugin/render_view.py), run for real in Debian's ParaView.

Runs ``tests/paraview_view_check.py`` in a ``pvpython`` subprocess under
xvfb: a 48^3 vessel phantom read from a .vti is shown with
``mipcast.plugin.render_view.show`` in a 112 x 96 render view (FXAA,
orientation axes, palette background off) and every screenshot is compared
with mipcast's own offscreen render of the same scene (camera copied from
ParaView, transfer functions rebuilt from the proxies' values, the same
flat-coloured geometry).  Skipped when ``pvpython`` or ``xvfb-run`` is not
installed (Debian: ``apt-get install paraview python3-paraview xvfb``).
"""
import os
from pathlib import Path

import pytest
from installed import OUTSIDE, plain_env
from xvfb import pvpython_report

ROOT = Path(__file__).resolve().parents[1]
CHECK = ROOT / "tests" / "paraview_view_check.py"
TIMEOUT = 240
#: Share of pixels within 1 grey level of the offscreen render.
MATCH = 0.99


@pytest.fixture(scope="module")
def report():
    return pvpython_report(CHECK.name, "the ParaView render view test", TIMEOUT)


def test_module_imports_without_paraview_and_says_where_to_run():
    import importlib.util
    import subprocess
    import sys

    if importlib.util.find_spec("paraview") is not None:
        pytest.skip("paraview is importable here")
    code = ("import sys, mipcast.plugin.render_view as rv\n"
            "assert 'paraview' not in sys.modules\n"
            "try:\n    rv.show()\nexcept ImportError as e:\n    print(e)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=plain_env(), cwd=OUTSIDE, timeout=60)
    assert done.returncode == 0, done.stderr
    assert "pvpython" in done.stdout


def _matches(result):
    assert result["within_1_share"] >= MATCH, result
    # a black or empty picture would match a black reference: demand a lit one
    assert result["lit_share"] > 0.25, result


@pytest.mark.parametrize("method", ["mip", "analytic", "demip"])
def test_view_matches_offscreen_render(report, method):
    _matches(report["methods"][method])


def test_every_method_renders_in_the_view(report):
    import mipcast

    assert set(report["methods"]) == set(mipcast.METHODS)
    for method, result in report["methods"].items():
        assert result["within_1_share"] >= MATCH, (method, result)
        assert result["shown_method"] == method


def test_show_again_replaces_the_method(report):
    for method, result in report["methods"].items():
        assert result["volumes_in_renderer"] == 1, (method, result)
        assert result["shown"] == 1, (method, result)
    assert report["methods"]["cpu"]["same_volume"]


def test_outline_coloured_by_the_array_and_functions_rescaled(report):
    result = report["methods"]["mip"]
    assert result["representation"].strip("'") == "Outline"
    assert result["coloured_by"] == ["POINTS", "scalars"]
    assert result["lut_ends"] == pytest.approx(result["data_range"])
    assert result["pwf_ends"] == pytest.approx(result["data_range"])
    assert result["volume_in_clipping_range"]
    assert result["clipping"] == pytest.approx(result["ref_clipping"])


def test_interactive_render_with_lod_draws_the_volume(report):
    _matches(report["interactive"])


def test_hide_removes_the_volume(report):
    hidden = report["hidden"]
    assert hidden["removed"] and not hidden["again"]
    assert hidden["shown"] == 0 and hidden["volumes_in_renderer"] == 0
    assert hidden["changed_share"] > 0.25  # show() had added a visible volume
    assert hidden["lit_share"] < 0.10      # only the outline is left


def test_hide_restores_the_representation(report):
    result = report["restore"]
    assert result["before"] == [1, "Surface", ["POINTS", ""]]
    assert result["shown"] == [1, "Outline", ["POINTS", "RTData"]]
    assert result["hidden"] == result["before"]
    assert result["never_shown_visible_after_hide"] == 0


def test_parallel_projection_without_outline(report):
    _matches(report["parallel"])
    assert report["parallel"]["volume_in_clipping_range"]


@pytest.mark.parametrize("method", ["mip", "analytic", "demip"])
def test_rays_stop_at_opaque_geometry(report, method):
    result = report["sphere"][method]
    _matches(result)
    assert result["sphere_changed_share"] > 0.03  # the sphere hides part of the volume
    assert result["sphere_pixel_share"] > 0.05


def test_colour_map_edits_reach_the_volume(report):
    result = report["colour_map"]
    _matches(result)
    assert result["changed_share"] > 0.25
    assert result["same_object"]


def test_locked_colour_range_is_kept(report):
    result = report["colour_map"]
    assert result["locked_points_kept"]
    assert result["locked_range"] == pytest.approx(result["locked_range_expected"])
    assert result["unlocked_range"] == pytest.approx(result["data_range"])


def test_upstream_changes_flow_through(report):
    result = report["upstream"]
    _matches(result)
    assert result["changed_share"] > 0.10
    assert result["coloured_by"] == ["POINTS", "RTData"]


def test_time_series_follows_the_animation_time(report):
    """A 3-file .vti series animated as the GUI does: each frame is that step's volume."""
    result = report["time"]
    for step in ("0", "1", "2", "0_again"):
        assert result[step]["within_1_share"] >= MATCH, (step, result)
        assert result[step]["lit_share"] > 0.05, (step, result)
    # the steps differ: a volume stuck on step 0 cannot match steps 1 and 2
    assert result["1"]["ref_changed_from_step_0"] > 0.05
    assert result["2"]["ref_changed_from_step_0"] > 0.05


@pytest.mark.parametrize("method", ["mip", "analytic", "demip", "stock", "cpu"])
def test_array_renamed_upstream_hides_the_volume_until_it_is_back(report, method):
    """Was a segfault for "cpu" (VTK's own CPU mapper given no scalars)."""
    result = report["rename"][method]
    assert result["before_lit_share"] > 0.25, result
    renamed = result["renamed"]
    assert renamed["visible"] == 0 and renamed["lit_share"] < 0.10, result  # the outline only
    assert len(renamed["warnings"]) == 1, result
    message = renamed["warnings"][0]
    for word in ("mipcast", method, "hidden", "'inv'", "show(array=", "hide()"):
        assert word in message, message
    assert renamed["warnings_after_second_frame"] == 1, result  # once per change
    assert result["visible_again"] == 1
    assert result["back"]["within_1_share"] >= MATCH, result


def test_volume_follows_the_outline_colouring(report):
    """ColorBy on the outline: the volume renders that array with its (edited) colour map."""
    result = report["recolour"]
    assert result["shown_array"] == "inv"
    assert result["same_lut"]
    _matches(result)
    assert result["changed_share"] > 0.25
    assert result["after_solid_colour"] == "inv"  # solid colour: nothing to follow


def test_deleting_the_source_removes_its_volume(report):
    assert report["upstream"]["after_delete"] == {"shown": 0, "volumes_in_renderer": 0}


def test_deleting_the_view_or_source_lets_go_at_once(report):
    """Was: the entry (and the deleted vtkPVRenderView) stayed until a render of that view."""
    result = report["deletion"]
    assert result["entries_before"] == 1
    assert result["entries_after_delete"] == 0 and not result["observed_after_delete"]
    assert result["view_object_released"]
    assert result["source_entries_after_delete"] == 0
    assert result["volume_in_renderer_after_source_delete"] == 0


def test_paraview_passes(report):
    passes = report["passes"]
    _matches(passes["no_depth_peeling"])
    for setting in (0, 1):  # translucent geometry, volumes peeled or not
        result = passes[f"translucent_peel_volumes_{setting}"]
        _matches(result)
        assert result["glass_changed_share"] > 0.03
    # FXAA smooths edges after the volume is drawn: it is why the test view turns it off
    assert passes["fxaa"]["within_1_share"] < MATCH


def test_macros(report):
    assert report["macros"] == {
        "mipcast_analytic.py": ["analytic"],
        "mipcast_demip.py": ["demip"],
        "mipcast_hide.py": [],
        "mipcast_mip.py": ["mip"],
    }


@pytest.mark.parametrize("case, words", [
    ("polydata", ["TypeError", "vtkImageData", "vtkPolyData", "Resample To Image"]),
    ("component_out_of_range", ["InputError", "component 5", "0 .. 2"]),
    ("nan", ["InputError", "NaN", "nothing to draw"]),
    ("missing_array", ["'nope'", "RTData"]),
    ("unknown_method", ["'best'", "'analytic'"]),
    ("unknown_setting", ["TypeError", "no_such_weight"]),
    ("spreadsheet", ["TypeError", "render view", "SpreadSheetView"]),
])
def test_bad_input_is_refused_with_the_fix(report, case, words):
    message = report["errors"][case]
    for word in words:
        assert word in message, message


@pytest.mark.parametrize("case", ["mip_magnitude", "stock_magnitude", "analytic_1", "stock_2", "cpu_0"])
def test_multi_component_arrays_draw_the_magnitude_or_a_component(report, case):
    """show() draws a three-component array as mipcast does: the magnitude, or the chosen component."""
    result = report["vectors"][case]
    _matches(result)
    assert result["vector_mode"] == ("Magnitude" if case.endswith("magnitude") else "Component"), result
    if not case.endswith("magnitude"):
        assert result["vector_component"] == int(case[-1])


def test_refused_input_adds_nothing(report):
    assert report["errors"]["shown_after_errors"] == [[False, "mip"]]


def test_remote_session_is_refused(report):
    remote = report["remote"]
    if "skipped" in remote:
        pytest.skip(remote["skipped"])
    message = remote["message"]
    assert message.startswith("RuntimeError")
    assert "builtin session" in message and "mipcast MIP Render" in message
