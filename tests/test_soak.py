"""Soak (issue #13, item 8): 500 frames changing camera, method, parameters, grey window,
window size and input, in one window: memory stays flat after warm-up and nothing but a
method change binds another shader program; nothing compiles after warm-up.
The 10,000-frame run: ``python tests/soak.py --frames 10000`` (docs/reliability.md, "Soak")."""
from soak import KINDS, run


def test_500_frames_keep_memory_flat_and_compile_nothing_after_warm_up():
    figures = run(frames=500, size=48, warmup=250)
    after = figures["after_warmup"]
    assert all(after[kind]["frames"] > 0 for kind in KINDS), after
    assert figures["rss_growth_mb"] <= 5.0, figures["rss_mb"]
    assert all(after[kind]["compiles"] == 0 for kind in KINDS), after
    assert all(after[kind]["switches"] == 0 for kind in KINDS), after
    assert figures["compiles_in_warmup"] >= len(figures["methods"]) - 2  # counted: each GPU method compiled


def test_the_counter_sees_a_pieces_change_compile():
    """Control: a change that installs other pieces binds a new program, which the soak's counter sees."""
    from mipcast.data_fixtures import make_fixture
    from mipcast.offscreen import OffscreenView

    view = OffscreenView(make_fixture("vessels", size=16), "analytic", size=(24, 24))

    def bound():
        view.render_window.Render()
        return view.render_window.GetShaderCache().GetLastShaderBound().GetAddressAsString("vtkObjectBase")

    first = bound()
    view.camera.Azimuth(30.0)
    assert bound() == first
    view.mapper.SetPackedCorners(False)
    unpacked = bound()
    assert unpacked != first
    view.mapper.SetPackedCorners(True)
    assert bound() == first  # back to the cached program: a switch, no compile
