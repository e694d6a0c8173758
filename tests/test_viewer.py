"""mipcast view: the headless message, and the viewer driven by simulated events under xvfb."""
import os
import shutil
import sys
import textwrap
from pathlib import Path

import pytest

from mipcast.app.cli import main
from mipcast.app.viewer import has_display
from installed import plain_env
from xvfb import run_under_xvfb

ROOT = Path(__file__).resolve().parents[1]


def test_view_without_display_says_so_and_suggests_render(tmp_path, monkeypatch, capsys):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.setattr(sys, "platform", "linux")
    assert not has_display()
    assert main(["view", str(tmp_path / "head.nii.gz")]) == 2
    message = capsys.readouterr().err
    assert "no display" in message
    assert f"mipcast render {tmp_path / 'head.nii.gz'} --out" in message


def test_view_rejects_unknown_method():
    with pytest.raises(SystemExit):
        main(["view", "x.vti", "--method", "best"])


# A stand-in for a depth-aware method (DEMIP-like), registered in the method
# table with a parameter table that has every kind of entry the viewer uses.
VIEWER_SCRIPT = textwrap.dedent('''
    import sys
    import numpy as np
    import pyvista
    from mipcast import METHODS, MIPVolumeMapper, create_mapper
    from mipcast.data_fixtures import make_fixture
    from mipcast.app.viewer import build_viewer, run_viewer, slider_range, view_methods
    from mipcast.core.parameter_tables import DEMIP
    from mipcast.core.parameters import Parameter, parameter_accessors
    from mipcast.core.shading import IDENTITY
    from mipcast.methods import Method, register

    FAKE = (
        Parameter("depth_weight", "float", 0.15, "Depth.", low=0.0, high=1.0),
        Parameter("sphere_weight", "float", 0.0, "Sphere.", low=0.0, high=1.0),
        Parameter("depth_mode", "choice", "window", "Mode.", choices=("window", "steps", "entry")),
        Parameter("gaze_point", "value", (0.5, 0.5), "Gaze.", convert=lambda *xy: tuple(xy), variadic=True),
        Parameter("sphere_colors", "value", ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)), "Colours.",
                  convert=lambda *c: tuple(c), variadic=True),
        Parameter("sphere_orientation", "value", IDENTITY, "Orientation.", convert=lambda *r: r, variadic=True),
    )


    @parameter_accessors
    class FakeDepthMapper(MIPVolumeMapper):
        PARAMETERS = FAKE


    register(Method("fake_depth", "Fake depth", "a stand-in", FakeDepthMapper, parameters=FAKE))
    names = list(view_methods())
    plotter = build_viewer(make_fixture("vessels", size=32), "mip", window_size=(200, 160))
    plotter.show(interactive=False, auto_close=False)
    iren = plotter.iren.interactor

    def press(key):
        iren.SetKeySym(key)
        iren.InvokeEvent("KeyPressEvent")

    def mapper():
        (volume,) = plotter.mip.volumes
        return volume.GetMapper()

    assert type(mapper()).__name__ == "MIPVolumeMapper"
    assert len(plotter.widgets.slider_widgets) == 2  # sample distance, slab thickness
    first = plotter.screenshot()
    assert first.max() > 100, "viewer picture is black"
    press("bracketright")  # no slab yet: a note, nothing moves
    assert mapper().GetSlabCentre() is None
    slab_slider = plotter.widgets.slider_widgets[1]
    slab_slider.GetRepresentation().SetValue(8.0)
    slab_slider.InvokeEvent("EndInteractionEvent")
    assert mapper().GetSlabThickness() == 8.0
    press("bracketright")
    assert mapper().GetSlabCentre() is not None
    assert plotter.screenshot().max() > 100
    mapper().SetSlabThickness(0.0)
    mapper().SetSlabCentre(None)

    press("m")
    following = names[(names.index("mip") + 1) % len(names)]
    assert type(mapper()) is type(create_mapper(following)), (type(mapper()), following)
    while type(mapper()).__name__ != "FakeDepthMapper":
        press("m")
    fake = mapper()
    assert len(plotter.widgets.slider_widgets) == 3  # sample distance, depth weight, sphere weight
    press("d")
    assert fake.GetDepthMode() == "steps"
    press("d"); press("d")
    assert fake.GetDepthMode() == "window"

    iren.SetEventPosition(50, 40)
    iren.InvokeEvent("MouseMoveEvent")
    assert np.allclose(fake.GetGazePoint(), (0.25, 0.25)), fake.GetGazePoint()

    depth_slider = plotter.widgets.slider_widgets[1]
    depth_slider.GetRepresentation().SetValue(0.6)
    depth_slider.InvokeEvent("EndInteractionEvent")
    assert fake.GetDepthWeight() == 0.6
    shot = plotter.screenshot()
    legend = shot[-30:, -40:].astype(int)  # lower right corner: the colour sphere
    assert (legend[..., 0] - legend[..., 2]).max() > 100 and (legend[..., 2] - legend[..., 0]).max() > 20, \\
        "no red-to-blue colour sphere in the legend corner"

    for _ in names:  # once round: the weight carries over to the next FakeDepthMapper
        press("m")
    assert type(mapper()).__name__ == "FakeDepthMapper" and mapper().GetDepthWeight() == 0.6
    assert mapper().GetDepthMode() == "window"
    press("d"); press("d")
    assert mapper().GetDepthMode() == "entry"  # a mode DEMIP does not have: not carried to it

    if "demip" in METHODS:  # the real depth-enhanced method, when registered
        while type(mapper()).__name__ != "DEMIPVolumeMapper":
            press("m")
        demip = mapper()
        titles = sorted(w.GetRepresentation().GetTitleText() for w in plotter.widgets.slider_widgets)
        assert titles == sorted([p.name.replace("_", " ") for p in DEMIP if slider_range(p)]
                                + ["sample distance (voxels)"]), titles
        assert "depth weight" in titles and "material threshold" in titles
        assert demip.GetDepthWeight() == 0.6  # carried over from the stand-in
        modes = list(next(p for p in DEMIP if p.name == "depth_mode").choices)
        before = demip.GetDepthMode()
        assert before in modes
        press("d")
        assert demip.GetDepthMode() == modes[(modes.index(before) + 1) % len(modes)]
        assert plotter.screenshot().max() > 100

    if "foveated" in METHODS:  # the real gaze-directed method, when registered
        while type(mapper()).__name__ != "FoveatedVolumeMapper":
            press("m")
        iren.SetEventPosition(150, 120)
        iren.InvokeEvent("MouseMoveEvent")
        assert np.allclose(mapper().GetGazePoint(), (0.75, 0.75)), mapper().GetGazePoint()

    old_volume = plotter.mip.volumes[0]
    plotter.close()
    assert plotter.mip.volumes == () and not old_volume.GetMapper().IsAttached()

    # run_viewer: the same window, show() made non-blocking
    shown = []
    original_show = pyvista.Plotter.show

    def show(self, **kwargs):
        shown.append(kwargs["title"])
        original_show(self, interactive=False, auto_close=False)
        assert self.screenshot().max() > 100
        kwargs["before_close_callback"](self)
        self.close()

    pyvista.Plotter.show = show
    run_viewer(make_fixture("spheres", size=24), "analytic", window_size=(96, 96))
    assert shown == ["mipcast view (analytic)"], shown
    print("viewer ok")
''')


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="needs xvfb-run")
def test_viewer_under_xvfb(tmp_path):
    script = tmp_path / "viewer_check.py"
    script.write_text(VIEWER_SCRIPT)
    result = run_under_xvfb([sys.executable, str(script)], cwd=tmp_path, env=plain_env(), timeout=240)
    assert result.returncode == 0 and "viewer ok" in result.stdout, result.stdout + result.stderr
    assert "Encountered issue in callback" not in result.stderr, result.stderr


def test_viewer_params_reach_the_mapper_and_bad_ones_are_refused():
    from mipcast.data_fixtures import make_fixture
    from mipcast.app.viewer import build_viewer

    image = make_fixture("vessels", size=16)
    plotter = build_viewer(image, "demip", off_screen=True, window_size=(48, 48),
                           params={"depth_weight": 0.5, "gaze_point": (0.2, 0.8)})  # a foveated one, kept for later
    assert plotter.mip.volumes[0].GetMapper().GetDepthWeight() == 0.5
    plotter.close()
    with pytest.raises(TypeError, match="depth_wieght"):
        build_viewer(image, "demip", off_screen=True, window_size=(48, 48), params={"depth_wieght": 0.5})
    with pytest.raises(ValueError):
        build_viewer(image, "demip", off_screen=True, window_size=(48, 48), params={"depth_weight": 5.0})
