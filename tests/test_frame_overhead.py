"""mipcast.bench.frame_overhead: its kinds of frame do what their names say."""
import numpy as np

from mipcast.bench import frame_overhead
from mipcast.bench.foveation_bench import framed_view
from mipcast.data_fixtures import make_fixture


def test_a_turning_camera_turns_and_a_moving_gaze_visits_the_path():
    view = framed_view(make_fixture("spheres", size=16), "foveated", 32, "fill")
    camera = view.renderer.GetActiveCamera()
    before = np.array(camera.GetDirectionOfProjection())
    frame_overhead._move(view, "camera turning", 0)
    after = np.array(camera.GetDirectionOfProjection())
    angle = np.degrees(np.arccos(np.clip(before @ after, -1.0, 1.0)))
    assert abs(angle - frame_overhead.TURN) < 1e-6
    for index in range(5):
        frame_overhead._move(view, "gaze moving", index)
        expected = frame_overhead.GAZE_PATH[index % len(frame_overhead.GAZE_PATH)]
        assert view.mapper.GetGazePoint() == expected
    gaze, direction = view.mapper.GetGazePoint(), np.array(camera.GetDirectionOfProjection())
    frame_overhead._move(view, "still", 7)
    assert view.mapper.GetGazePoint() == gaze and np.array_equal(camera.GetDirectionOfProjection(), direction)
    view.render_window.Finalize()


def test_rows_time_every_setting_and_kind_of_frame_against_full_quality():
    rows = frame_overhead.measure_frame_overhead(make_fixture("spheres", size=16), "spheres", sizes=[32], frames=2,
                                                 warmup=1)
    kinds = {(row["setting"], row["move"]) for row in rows}
    assert kinds == {(setting, move) for setting in frame_overhead.SETTINGS for move in frame_overhead.MOVES
                     if not (setting == "full quality" and move == "gaze moving")}
    full = next(row for row in rows if row["setting"] == "full quality" and row["move"] == "still")
    assert full["wall_over_full"] == 1.0
    assert all(row["wall_ms"] > 0 and row["cpu_ms"] > 0 and row["frames"] == 2 for row in rows)
    table = frame_overhead.overhead_table(rows)
    assert table.count("\n") == 1 + len(frame_overhead.SETTINGS)  # header, rule, a line per setting
