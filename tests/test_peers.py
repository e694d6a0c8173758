"""Peers (``mipcast bench --peers``): vispy's volume visual on VTK's views, against the same reference rays."""
import json

import numpy as np
import pytest

from mipcast import reference
from mipcast.app.cli import main
from mipcast.bench import peers
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView

needs_vispy = pytest.mark.skipif(not peers.vispy_available(), reason="vispy/PyOpenGL not installed (bench extra)")
SIZE = (96, 96)


@pytest.fixture(scope="module")
def noise48():
    return make_fixture("noise", size=48)


def test_vtk_rows_without_vispy(monkeypatch):
    monkeypatch.setattr(peers, "vispy_available", lambda: False)
    rows = peers.measure_peers(make_fixture("vessels", size=24), "vessels", 48, rounds=1, frames=1, warmup=1)
    assert [row["row"] for row in rows] == ["stock", "mip", "analytic"]
    assert rows[0]["ratio_to_stock"] == 1.0 and rows[1]["pixels_hit_vs_stock"] == 1.0
    assert rows[2]["within_1_grey"] == 1.0


@needs_vispy
@pytest.mark.parametrize("view", ["oblique", "perspective"])
def test_vispy_hits_the_same_pixels_with_the_same_samples_per_ray(noise48, view):
    stock = OffscreenView(noise48, "stock", size=SIZE, view=view)
    stock.renderer.SetBackground(*(c / 255 for c in peers.BACKGROUND))
    step = peers.matched_step(noise48, stock.camera, SIZE, stock.sample_distance)
    vispy_view = peers.VispyView(noise48, stock.camera, SIZE, "mip", (0.0, 1.0), step)
    vtk_hit = peers.hit_mask(stock.screenshot())
    vispy_hit = peers.hit_mask(vispy_view.screenshot())
    assert vtk_hit.mean() > 0.2
    assert abs(vispy_hit.sum() / vtk_hit.sum() - 1.0) <= 0.02
    assert np.mean(vtk_hit == vispy_hit) >= 0.98  # the same pixels, not only as many
    vtk_count = peers.vtk_samples(stock)
    count = peers.vispy_samples(noise48, stock.camera, SIZE, step, "average")
    assert abs(count["fetches"] / vtk_count["samples"] - 1.0) <= 0.03
    vispy_view.close()


@needs_vispy
def test_vispy_error_is_computed_on_the_reference_rays(noise48):
    """On a smooth volume a misaligned camera would be many grey levels off; the same rays are not."""
    stock = OffscreenView(noise48, "stock", size=SIZE, view="oblique")
    step = peers.matched_step(noise48, stock.camera, SIZE, stock.sample_distance)
    picture = peers.VispyView(noise48, stock.camera, SIZE, "mip", (0.0, 1.0), step).screenshot()
    exact = reference.render(noise48, stock.camera, SIZE, method="analytic")
    errors = peers.grey_errors(picture, exact, (0.0, 1.0))
    stock.renderer.SetBackground(*(c / 255 for c in peers.BACKGROUND))
    stock_errors = peers.grey_errors(stock.screenshot(), exact, (0.0, 1.0))  # same samples per ray
    assert errors["within_1_grey"] >= stock_errors["within_1_grey"] - 0.05 and errors["p99_grey"] <= stock_errors["p99_grey"] + 1.0
    shifted = peers.grey_errors(np.roll(picture, 3, axis=1), exact, (0.0, 1.0))  # 3 pixels off: far worse
    assert shifted["within_1_grey"] < errors["within_1_grey"] - 0.2, (errors, stock_errors, shifted)


@needs_vispy
def test_measure_peers_rows_have_pixels_samples_and_errors():
    rows = peers.measure_peers(make_fixture("vessels", size=48), "vessels", 96, rounds=1, frames=1, warmup=1)
    by_row = {row["row"]: row for row in rows}
    assert set(by_row) == {"stock", "mip", "analytic", peers.UNCLIPPED} | {f"vispy {m}" for m in peers.VISPY_METHODS}
    for method in peers.VISPY_METHODS:
        row = by_row[f"vispy {method}"]
        assert abs(row["pixels_hit_vs_stock"] - 1.0) <= 0.02 and row["ratio_to_stock"] > 0
        assert abs(row["steps_per_ray"] / by_row["stock"]["samples_per_ray"] - 1.0) < 0.25
    assert by_row[peers.UNCLIPPED]["pixels_hit_vs_stock"] > 1.0  # vispy's own box is half a voxel larger
    assert 0.0 < by_row["vispy mip"]["within_1_grey"] <= 1.0 and "within_1_grey" not in by_row["vispy minip"]


def test_bench_peers_quick_writes_markdown_and_strict_json(tmp_path, capsys):
    assert main(["bench", "--peers", "--quick", "--scenes", "vessels", "--views", "oblique", "--size", "48",
                 "--rounds", "1", "--out", str(tmp_path)]) == 0
    report = json.loads((tmp_path / "peers.json").read_text(), parse_constant=pytest.fail)
    assert {"renderer", "rows", "cost_model", "elapsed_s"} <= set(report)
    assert (tmp_path / "peers.md").read_text().startswith("OpenGL renderer: ")
    assert "OpenGL renderer" in capsys.readouterr().out
