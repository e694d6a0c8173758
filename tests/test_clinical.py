"""Clinical projections (issue #16, items 4-6): default window, patient views, turntable."""
import numpy as np
import pytest
from PIL import Image, ImageSequence
from vtkmodules.vtkCommonCore import vtkStringArray
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter

from mipcast import reference
from mipcast.app.cli import main
from mipcast.core.patient_views import PATIENT_VIEWS, orientation_code, view_basis
from mipcast.core.windowing import PRESETS, default_window, looks_like_ct, resolve_window, window_and_reason
from mipcast.data_fixtures import head_ct_path, load_head_ct, make_fixture
from mipcast.data_fixtures.synthetic import image_from_array
from mipcast.offscreen import OffscreenView


def _write_vti(image, path):
    writer = vtkXMLImageDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(image)
    writer.Write()
    return path


def _rgb(path):
    return np.asarray(Image.open(path).convert("RGB"))


# ------------------------------------------------------------ default window

def test_vessels_default_window_leaves_the_noisy_background_black():
    image = make_fixture("vessels", size=48)
    low, high = default_window(image)
    assert 0.17 < low < 0.3 and 0.9 < high <= 1.0  # background noise reaches 0.15 + 0.02
    auto, full = (OffscreenView(image, "mip", size=(64, 64), window=w) for w in (None, "full"))
    assert auto.window == (low, high) and full.window == image.GetPointData().GetScalars().GetRange(0)
    exact = reference.render(image, auto.camera, (64, 64), method="analytic")
    background = exact < 0.18
    picture, before = auto.screenshot()[..., 0], full.screenshot()[..., 0]
    assert picture[background].max() == 0  # black, not a grey box
    assert before[background].mean() > 20  # what the data range showed
    assert np.median(picture[exact > 0.8]) > 200  # vessels bright


def test_demip_shades_the_vessels_not_the_background():
    image = make_fixture("vessels", size=48)
    scene = OffscreenView(image, "demip", size=(64, 64))
    exact = reference.render(image, scene.camera, (64, 64), method="analytic")
    picture = scene.screenshot().astype(int)
    assert picture[exact < 0.18].max() == 0
    vessels = picture[exact > 0.5].max(axis=-1)
    assert vessels.std() > 10  # depth shading varies along the vessels


def test_flat_background_fixtures_keep_it_black():
    for name, low in (("spheres", 0.0), ("frontback", 0.05)):
        window, reason = window_and_reason(make_fixture(name, size=32))
        assert window[0] == pytest.approx(low) and window[1] == pytest.approx(1.0) and reason == "histogram percentiles"


def test_ct_is_recognised_by_units_name_or_air_and_gets_the_preset():
    rng = np.random.default_rng(1)
    ct = rng.normal(-1000, 10, (24, 24, 24)).astype(np.int16)
    ct[6:18, 6:18, 6:18] = 40
    ct[10:12, 10:12, :] = 1200
    assert looks_like_ct(image_from_array(ct)) and default_window(image_from_array(ct)) == (150.0, 1200.0)
    as_float = image_from_array(ct.astype(np.float32))
    assert not looks_like_ct(as_float)
    units = vtkStringArray()
    units.SetName("units")
    units.InsertNextValue("HU")
    as_float.GetFieldData().AddArray(units)  # what the DICOM reader records for CT
    assert looks_like_ct(as_float) and default_window(as_float) == (150.0, 1200.0)
    assert looks_like_ct(image_from_array(ct.astype(np.float32), name="HU"))
    shifted = image_from_array((ct.astype(np.int32) + 1024).astype(np.uint16))  # stored values, no rescale
    assert not looks_like_ct(shifted)


def test_window_words_and_explicit_windows():
    image = make_fixture("spheres", size=16)
    assert resolve_window(image, "full") == (0.0, 1.0)
    assert resolve_window(image, "auto") == default_window(image)
    assert resolve_window(image, (0.2, 0.4)) == (0.2, 0.4)
    assert resolve_window(image, "ct-bone") == PRESETS["ct-bone"]
    with pytest.raises(ValueError, match="'full'"):
        resolve_window(image, "wide")
    with pytest.raises(ValueError, match="high > low"):
        OffscreenView(image, window=(1.0, 0.0))
    # an infinite end drew black with a traceback from the render observer (the transfer bounds' IndexError)
    for window in ((float("-inf"), 1.0), (0.0, float("inf"))):
        with pytest.raises(ValueError, match="two finite numbers.*'full' is the data range"):
            resolve_window(image, window)
        with pytest.raises(ValueError, match="finite"):
            OffscreenView(image, window=window)


def test_a_dicom_ct_series_gets_the_ct_preset():
    import os
    from pydicom.data import get_testdata_file
    from mipcast.io import read_volume

    folder = os.path.dirname(get_testdata_file("dicomdirtests/98892001/CT5N/2062"))
    image = read_volume(folder)  # the reader records units "HU" (Modality CT)
    assert looks_like_ct(image)
    # its 16 x 16 x 5 crop holds -888..85 HU: nothing reaches the preset's 150 HU, so the histogram rule
    window, reason = window_and_reason(image)
    assert reason == "histogram percentiles" and -888 <= window[0] < window[1] <= 85
    scalars = image.GetPointData().GetScalars()
    scalars.SetValue(0, 700)  # a bone voxel
    scalars.Modified()
    assert window_and_reason(image) == ((150.0, 700.0), "CT preset ct-mip (HU)")


@pytest.mark.skipif(head_ct_path() is None, reason="head CT absent (apt-get install invesalius-examples)")
def test_head_ct_gets_the_ct_preset():
    window, reason = window_and_reason(load_head_ct())
    assert window == (150.0, 1800.0) and reason.startswith("CT preset")


def test_cli_render_default_window_and_full(tmp_path, capsys):
    source = _write_vti(make_fixture("vessels", size=32), tmp_path / "vessels.vti")
    outs = {}
    for name, extra in (("auto", []), ("full", ["--window", "full"]), ("range", None)):
        if extra is None:
            low, high = make_fixture("vessels", size=32).GetPointData().GetScalars().GetRange(0)
            extra = ["--window", repr(low), repr(high)]
        outs[name] = tmp_path / f"{name}.png"
        assert main(["render", str(source), "--out", str(outs[name]), "--size", "48", "48"] + extra) == 0
    said = capsys.readouterr().out
    assert "histogram percentiles; --window full for the data range" in said
    assert np.array_equal(_rgb(outs["full"]), _rgb(outs["range"]))
    assert _rgb(outs["auto"]).mean() < _rgb(outs["full"]).mean()  # background black
    assert main(["render", str(source), "--out", str(tmp_path / "x.png"), "--window", "wide"]) == 2
    assert "--window takes LOW HIGH" in capsys.readouterr().err


def test_pyvista_and_viewer_use_the_default_window():
    pyvista = pytest.importorskip("pyvista")
    import mipcast.filters  # noqa: F401
    from mipcast.app.viewer import build_viewer

    grid = pyvista.wrap(make_fixture("vessels", size=24))
    window = default_window(grid)
    scene = OffscreenView(grid, "mip", size=(32, 32))
    assert np.array_equal(grid.mip.render("mip", size=(32, 32)), scene.screenshot())
    volume = mipcast.filters.add_volume(pyvista.Plotter(off_screen=True, window_size=(32, 32)), grid)
    assert volume.GetProperty().GetRGBTransferFunction().GetRange() == pytest.approx(window)
    full = mipcast.filters.add_volume(pyvista.Plotter(off_screen=True, window_size=(32, 32)), grid, clim="full")
    assert full.GetProperty().GetRGBTransferFunction().GetRange() == pytest.approx(
        grid.GetPointData().GetScalars().GetRange(0))
    plotter = build_viewer(grid, "mip", window_size=(32, 32), off_screen=True, view="anterior")
    try:
        shown = plotter.mip.volumes[0].GetProperty().GetRGBTransferFunction().GetRange()
        assert shown == pytest.approx(window)
        assert plotter.camera.GetDirectionOfProjection() == pytest.approx((0.0, 1.0, 0.0))
    finally:
        plotter.close()


# ------------------------------------------------------------ patient views

N = 40


def _face(x, y, z):
    """A head in LPS world coordinates (mm, centre 0): skull, face on the anterior (-y) side.

    Nose (1.0) at the front centre, eyes (0.8) above it, a left ear marker
    (0.6, patient's left, +x) and a vertex marker (0.5, superior, +z).
    """
    def ball(cx, cy, cz, r):  # flat: the MIP of a feature is its value
        return ((x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2) < r * r

    head = 0.25 * (((x / 14) ** 2 + (y / 16) ** 2 + (z / 17) ** 2) < 1.0)
    parts = [head, 1.0 * ball(0, -14, 0, 3), 0.8 * ball(-6, -11, 7, 3), 0.8 * ball(6, -11, 7, 3),
             0.6 * ball(13, 0, 0, 3), 0.5 * ball(0, 0, 15, 3)]
    return np.maximum.reduce(parts).astype(np.float32)


def _face_image(direction):
    """The head sampled on an N^3 grid whose index axes point along ``direction``'s columns."""
    direction = np.asarray(direction, dtype=float)
    spacing = 1.0
    centre = (N - 1) / 2 * spacing
    k, j, i = np.meshgrid(*(np.arange(N) * spacing - centre,) * 3, indexing="ij")
    world = np.einsum("rc,c...->r...", direction, np.stack([i, j, k]))
    values = _face(*world)
    origin = -direction @ np.full(3, centre)
    return image_from_array(values, spacing=(spacing,) * 3, origin=origin, direction=direction)


CORONAL = np.column_stack([(1, 0, 0), (0, 0, -1), (0, 1, 0)])  # i: left, j: inferior, k: posterior


def _oblique():
    angle = np.radians(30.0)
    c, s = np.cos(angle), np.sin(angle)
    about_z = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    about_x = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    return about_z @ about_x @ CORONAL


def _where(values, low, high):
    """(row, column) centre of the pixels with values in [low, high], as fractions of the image (0.5: centre)."""
    rows, cols = np.nonzero((values >= low) & (values <= high))
    assert rows.size, f"no pixels in [{low}, {high}]"
    return rows.mean() / values.shape[0], cols.mean() / values.shape[1]


@pytest.mark.parametrize("direction", [np.eye(3), CORONAL, _oblique()], ids=["axial", "coronal", "oblique"])
def test_anterior_view_shows_the_face_upright_with_the_left_on_the_right(direction):
    image = _face_image(direction)
    scene = OffscreenView(image, "analytic", size=(96, 96), view="anterior", window=(0.0, 1.0))
    values = scene.float_image()
    nose_row, nose_col = _where(values, 0.999, 1.001)
    eyes_row, _ = _where(values, 0.799, 0.801)
    ear_row, ear_col = _where(values, 0.599, 0.601)
    vertex_row, vertex_col = _where(values, 0.499, 0.501)
    assert abs(nose_col - 0.5) < 0.03 and abs(nose_row - 0.5) < 0.03  # the nose faces the camera
    assert vertex_row < eyes_row - 0.05 < nose_row - 0.1  # superior is up
    assert abs(vertex_col - 0.5) < 0.03 and abs(ear_row - 0.5) < 0.03
    assert ear_col > 0.6  # the patient's left on the viewer's right
    camera = np.array(scene.camera.GetPosition())
    assert np.linalg.norm(camera - (0, -15, 0)) < np.linalg.norm(camera - (0, 15, 0))  # in front of the face


def test_rotated_series_looks_like_the_axial_one_in_every_patient_view():
    axial, coronal = _face_image(np.eye(3)), _face_image(CORONAL)
    assert (orientation_code(axial), orientation_code(coronal)) == ("LPS", "LIP")
    for view in PATIENT_VIEWS:
        a, b = (OffscreenView(im, "analytic", size=(64, 64), view=view, window=(0.0, 1.0)).screenshot()
                for im in (axial, coronal))
        assert np.abs(a.astype(int) - b.astype(int)).mean() < 1.0, view


def test_superior_view_puts_the_face_at_the_top_and_left_and_right_views_mirror():
    image = _face_image(_oblique())
    top = OffscreenView(image, "analytic", size=(96, 96), view="superior", window=(0.0, 1.0)).float_image()
    assert _where(top, 0.999, 1.001)[0] < 0.4  # nose: anterior is up
    assert _where(top, 0.599, 0.601)[1] < 0.4  # seen from above, the patient's left is on the viewer's left
    left = OffscreenView(image, "analytic", size=(96, 96), view="left", window=(0.0, 1.0)).float_image()
    right = OffscreenView(image, "analytic", size=(96, 96), view="right", window=(0.0, 1.0)).float_image()
    assert _where(left, 0.999, 1.001)[1] < 0.4 and _where(right, 0.999, 1.001)[1] > 0.6  # face left / right
    for name in PATIENT_VIEWS:
        forward, up, right_axis = view_basis(name)
        assert np.dot(forward, up) == 0 and np.linalg.det(np.stack([right_axis, up, -forward])) == pytest.approx(1)


def test_cli_and_pyvista_take_patient_views(tmp_path):
    pyvista = pytest.importorskip("pyvista")
    import mipcast.filters  # noqa: F401

    image = _face_image(CORONAL)
    source = _write_vti(image, tmp_path / "face.vti")
    out = tmp_path / "anterior.png"
    assert main(["render", str(source), "--view", "anterior", "--out", str(out), "--size", "48", "48",
                 "--method", "analytic", "--window", "0", "1"]) == 0
    expected = OffscreenView(image, "analytic", size=(48, 48), view="anterior", window=(0.0, 1.0)).screenshot()
    assert np.array_equal(_rgb(out), expected)
    grid = pyvista.wrap(image)
    assert np.array_equal(grid.mip.render("analytic", size=(48, 48), view="anterior", window=(0, 1)), expected)
    shot = grid.mip.plot("analytic", off_screen=True, window_size=(48, 48), screenshot=True, view="superior",
                         clim=(0, 1))
    assert shot.shape == (48, 48, 3) and shot.max() > 200


@pytest.mark.skipif(head_ct_path() is None, reason="head CT absent (apt-get install invesalius-examples)")
def test_head_ct_anterior_and_superior_views():
    # Cranium.inv3 records no orientation: its rows run posterior -> anterior (face at high y) and its
    # slices inferior -> superior (teeth at k = 0); left/right is not recorded.  Turned into LPS by
    # flipping x and y (a rotation; which side is the patient's left stays unknown).
    image = load_head_ct()
    image.SetDirectionMatrix(-1, 0, 0, 0, -1, 0, 0, 0, 1)
    front = OffscreenView(image, "analytic", size=(96, 96), view="anterior").float_image()
    metal_row, _ = _where(front, 2500, 4000)  # dental fillings
    assert metal_row > 0.55  # the teeth at the bottom: superior is up
    top = OffscreenView(image, "analytic", size=(96, 96), view="superior").float_image()
    assert _where(top, 2500, 4000)[0] < 0.4  # seen from above, the face (teeth) is at the top
    camera = np.array(OffscreenView(image, "mip", size=(32, 32), view="anterior").camera.GetPosition())
    bounds = image.GetBounds()
    assert camera[1] < bounds[2]  # on the anterior (-y) side, where the face now is


# ------------------------------------------------------------ turntable

def test_turntable_gif_has_n_distinct_frames_and_starts_with_the_render(tmp_path, capsys):
    source = _write_vti(make_fixture("vessels", size=32), tmp_path / "vessels.vti")
    still, spin = tmp_path / "still.png", tmp_path / "spin.gif"
    common = [str(source), "--size", "48", "40", "--view", "anterior"]
    assert main(["render"] + common + ["--out", str(still)]) == 0
    assert main(["render"] + common + ["--out", str(spin), "--turntable", "6"]) == 0
    captured = capsys.readouterr()
    assert "turntable: frame 6/6" in captured.err and f"wrote {spin} (6 frames)" in captured.out
    gif = Image.open(spin)
    frames = [np.asarray(frame.convert("RGB")) for frame in ImageSequence.Iterator(gif)]
    assert gif.n_frames == 6 and len(frames) == 6 and frames[0].shape == (40, 48, 3)
    assert np.array_equal(frames[0], _rgb(still))
    for a, b in zip(frames, frames[1:]):
        assert np.abs(a.astype(int) - b.astype(int)).mean() > 1.0


def test_turntable_frames_turn_about_view_up():
    from mipcast.app.turntable import turntable_frames

    scene = OffscreenView(_face_image(np.eye(3)), "analytic", size=(48, 48), view="anterior", window=(0.0, 1.0))
    seen = []
    frames = turntable_frames(scene, 4, progress=lambda done, total: seen.append((done, total)))
    assert seen[-1] == (4, 4) and len(frames) == 4
    assert scene.camera.GetViewUp() == pytest.approx((0.0, 0.0, 1.0))  # turned about superior
    # 3 x 90 degrees: the camera went right (to the patient's left) and on round to the patient's right
    assert scene.camera.GetDirectionOfProjection() == pytest.approx((1.0, 0.0, 0.0), abs=1e-9)


def test_turntable_errors(tmp_path, capsys):
    source = _write_vti(make_fixture("spheres", size=16), tmp_path / "s.vti")
    assert main(["render", str(source), "--out", str(tmp_path / "x.png"), "--turntable", "4"]) == 2
    assert "--out must end in .gif or .mp4" in capsys.readouterr().err
    assert main(["render", str(source), "--out", str(tmp_path / "x.gif"), "--turntable", "1"]) == 2
    assert "at least 2 frames" in capsys.readouterr().err
    assert main(["render", str(source), "--out", str(tmp_path / "x.gif"), "--slab-sweep", "4"]) == 2
    assert "--slab-sweep needs --slab" in capsys.readouterr().err
