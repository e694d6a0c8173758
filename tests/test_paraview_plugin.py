"""The ParaView plugin, run for real in Debian's ParaView (pvpython under xvfb).

Runs ``tests/paraview_plugin_check.py`` in a ``pvpython`` subprocess: it loads
``plugin/mipcast_paraview.py`` with ``LoadPlugin``, applies the
"mipcast MIP Render" filter to a 32^3 vessel phantom at 96 x 80 pixels for
every method of ``mipcast.METHODS``, compares the output with a direct
``OffscreenView`` render, and feeds it bad inputs.  Skipped when ``pvpython``
or ``xvfb-run`` is not installed (Debian: ``apt-get install paraview
python3-paraview xvfb``).
"""
from pathlib import Path

import pytest
from xvfb import pvpython_report

ROOT = Path(__file__).resolve().parents[1]
CHECK = ROOT / "tests" / "paraview_plugin_check.py"
WIDTH, HEIGHT = 96, 80
TIMEOUT = 240


@pytest.fixture(scope="module")
def report():
    return pvpython_report(CHECK.name, "the ParaView plugin test", TIMEOUT)


def test_output_is_an_image_of_the_requested_size(report):
    assert report["dims"] == [WIDTH, HEIGHT, 1]
    assert report["active_scalars"] == "mip_rgb"
    assert report["rgb_dtype"] == "uint8"
    assert report["value_dtype"] == "float32"


def test_output_is_a_lit_picture_with_misses(report):
    assert report["lit_pixels"] > 0.10 * report["pixels"]
    assert 0.05 < report["nan_share"] < 0.95


def test_every_method_matches_direct_rendering(report):
    import mipcast

    assert set(report["methods"]) == set(mipcast.METHODS)
    for method, result in report["methods"].items():
        assert result["dims"] == [WIDTH, HEIGHT, 1], method
        assert result["rgb_within_1_share"] >= 0.999, (method, result)


def test_float_readout_matches_direct_rendering(report):
    assert report["has_values"]
    assert report["nan_mismatch"] == 0
    assert report["max_value_diff"] <= 1e-6 * report["value_range"]
    for method, result in report["methods"].items():
        if "max_value_diff" in result:
            assert result["nan_mismatch"] == 0, method
            assert result["max_value_diff"] <= 1e-6 * result["value_range"], method


@pytest.mark.parametrize("case, words", [
    ("nan", ["NaN", "nothing to draw"]),
    ("polydata", ["vtkImageData", "vtkPolyData"]),
    ("bad_window", ["Window", "high > low"]),
])
def test_bad_input_reports_the_problem(report, case, words):
    message = report["errors"][case]
    assert message.startswith("mipcast MIP Render:"), message
    for word in words:
        assert word in message, message


def test_a_multiblock_of_image_pieces_is_drawn_as_the_whole_volume(report):
    """A .vtm of a volume's pieces (ParaView's multiblock readers): the filter joins them
    (mipcast.io.composite); until 2026-12-04 it refused anything but vtkImageData."""
    pieces = report["pieces"]
    assert pieces["log"] == ""
    assert pieces["dims"] == [WIDTH, HEIGHT, 1] and pieces["lit_pixels"] > 0.10 * pieces["pixels"]
    assert pieces["max_rgb_diff"] == 0 and pieces["nan_mismatch"] == 0
    assert pieces["max_value_diff"] <= 1e-6 * pieces["value_range"]


@pytest.mark.parametrize("form", ["rectilinear", "left_handed"])
def test_an_even_rectilinear_grid_and_a_left_handed_image_are_drawn_as_the_volume(report, form):
    """netCDF CF's rectilinear grids (evenly spaced, an axis decreasing) and a left-handed direction matrix:
    drawn as the same volume as image data (mipcast.io.as_image_data), the float readout the float64
    reference's; until 2026-12-05 the filter refused both (not image data; a reflection)."""
    import mipcast

    drawn = report["forms"][form]
    assert drawn["log"] == ""
    assert drawn["max_rgb_diff"] == 0 and drawn["nan_mismatch"] == 0 and drawn["lit_pixels"] > 0.10 * drawn["pixels"]
    assert drawn["reference_nan_mismatch"] == 0
    assert drawn["max_reference_diff"] <= mipcast.METHODS["analytic"].reference_tolerance * drawn["value_range"]


def test_an_uneven_rectilinear_grid_is_refused_naming_paraviews_resample_filter(report):
    message = report["forms"]["uneven"]
    assert message.startswith("mipcast MIP Render:") and "not evenly spaced" in message, message
    assert "Filters > Resample To Image" in message, message


def test_filter_recovers_after_an_error(report):
    recovery = report["recovery"]
    assert recovery["failed_reported"]
    assert recovery["dims"] == [WIDTH // 2, HEIGHT // 2, 1]
    assert recovery["value_tuples"] == (WIDTH // 2) * (HEIGHT // 2)
    assert recovery["log"] == ""
