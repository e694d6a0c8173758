"""Analytic MIP's work counters: what the walk visits, solves and skips."""
import numpy as np
from mipcast.mappers.amip_stats import work_per_ray
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView


def test_full_range_walks_every_crossed_cell():
    scene = OffscreenView(make_fixture("vessels", size=48), "analytic", size=(64, 64), window="full")
    work = work_per_ray(scene)
    assert abs(work["cells_walked"] - work["cells_crossed"]) < 0.02 * work["cells_crossed"]
    assert work["blocks_jumped"] == 0.0 and work["texel_fetches"] == 2 * work["cells_walked"]  # packed corners
    assert 0.1 < work["skipped_cubics"] < 0.9  # the corner bound spares some root solves


def test_a_window_above_the_background_skips_most_cells():
    scene = OffscreenView(make_fixture("vessels", size=48), "analytic", size=(64, 64), window=(0.3, 0.9))
    work = work_per_ray(scene)
    assert work["blocks_jumped"] > 1.0
    assert work["skipped_cells"] > 0.5
    # fetches: 2 per walked cell + 1 block maximum per step, against 2 per crossed cell without skipping
    assert work["texel_fetches"] < 0.7 * 2 * work["cells_crossed"]


def test_skipping_off_walks_and_solves_every_cell_with_the_same_answer():
    window = (0.3, 0.9)
    views = {}
    for skipping in (True, False):
        views[skipping] = OffscreenView(make_fixture("vessels", size=48), "analytic", size=(64, 64), window=window)
        views[skipping].mapper.SetSkipping(skipping)
    on, off = (work_per_ray(views[s]) for s in (True, False))
    assert off["blocks_jumped"] == 0.0 and off["skipped_cubics"] == 0.0
    assert abs(off["cells_walked"] - off["cells_crossed"]) < 0.02 * off["cells_crossed"]
    assert on["skipped_cells"] > 0.5 and on["texel_fetches"] < 0.7 * off["texel_fetches"]
    assert "amip_loop_blocks" not in views[False].mapper.GetShaderPieces()
    assert np.array_equal(views[True].screenshot(), views[False].screenshot())
    # both exact: they differ by float32 rounding only (block jumps restart the walk at other t values)
    assert np.allclose(views[True].float_image(), views[False].float_image(), equal_nan=True, atol=1e-6, rtol=0)
