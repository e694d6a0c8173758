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


# A stand-in for a depth-aware method (DEMIP-like): it declares every hook the
# viewer looks for, so the viewer's behaviour is tested before DEMIP lands.
VIEWER_SCRIPT = textwrap.dedent('''
    import sys
    import numpy as np
    import pyvista
    from mipcast import METHODS, MIPVolumeMapper, create_mapper
    from mipcast.data_fixtures import make_fixture
    from mipcast.core.object_state import object_state
    from mipcast.app.viewer import build_viewer, run_viewer


    class FakeDepthMapper(MIPVolumeMapper):
        DEPTH_MODES = ("window", "steps", "entry")

        def _get(self, key, default):
            return object_state(self).get(key, default)

        def SetDepthWeight(self, value): object_state(self)["depth_weight"] = value
        def GetDepthWeight(self): return self._get("depth_weight", 0.15)
        def SetSphereWeight(self, value): object_state(self)["sphere_weight"] = value
        def GetSphereWeight(self): return self._get("sphere_weight", 0.0)
        def SetDepthMode(self, value): object_state(self)["depth_mode"] = value
        def GetDepthMode(self): return self._get("depth_mode", "window")
        def SetGazePoint(self, x, y): object_state(self)["gaze"] = (x, y)
        def GetSphereColors(self): return ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0))


    METHODS["fake_depth"] = FakeDepthMapper
    names = list(METHODS)
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
    assert len(plotter.widgets.slider_widgets) == 1  # sample distance only
    first = plotter.screenshot()
    assert first.max() > 100, "viewer picture is black"

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
    assert np.allclose(object_state(fake)["gaze"], (0.25, 0.25)), object_state(fake).get("gaze")

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
        assert titles == ["depth weight", "material threshold", "sample distance (voxels)",
                          "sphere weight"], titles
        assert demip.GetDepthWeight() == 0.6  # carried over from the stand-in
        modes = list(type(demip).DEPTH_MODES)
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
