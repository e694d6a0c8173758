"""Gaze streams: a replayed recorded-style trace re-renders nothing during fixations; latency is one frame."""
import numpy as np
import pytest

from mipcast.core.gaze import GazeStream, synthetic_trace
from mipcast.data_fixtures import make_fixture
from mipcast.offscreen import OffscreenView


def _replay(stream, trace):
    return [stream.push(s.t, s.x, s.y) for s in trace]


def test_no_re_render_during_fixations_below_the_threshold():
    trace = synthetic_trace(seed=3)
    changed = _replay(GazeStream(), trace)
    kinds = [s.kind for s in trace]
    starts = {0} | {i for i in range(1, len(trace)) if kinds[i] != kinds[i - 1]}
    for i, (kind, moved) in enumerate(zip(kinds, changed)):
        if kind == "fixation" and moved:
            # only the landing of a saccade (within the velocity window after it) moves a fixation
            start = max(j for j in starts if j <= i)
            assert i == 0 or (kinds[start - 1] == "saccade" and trace[i].t - trace[start].t <= 0.03), i
    fixations = sum(1 for i in starts if kinds[i] == "fixation")
    assert sum(m for m, k in zip(changed, kinds) if k == "fixation") == fixations  # one per fixation
    assert sum(m for m, k in zip(changed, kinds) if k == "saccade") <= 2  # at most a saccade's slow onset
    assert sum(m for m, k in zip(changed, kinds) if k == "pursuit") >= 5  # the pursuit is followed


def test_saccade_keeps_the_last_fixation_then_lands():
    stream = GazeStream()
    trace = synthetic_trace()
    gazes = []
    for sample in trace:
        stream.push(sample.t, sample.x, sample.y)
        gazes.append((sample.kind, stream.gaze))
    first_saccade = next(i for i, s in enumerate(trace) if s.kind == "saccade")
    held = [g for k, g in gazes[first_saccade:first_saccade + 8] if k == "saccade"]
    assert all(np.hypot(g[0] - 0.3, g[1] - 0.6) < 0.02 for g in held)
    after = next(g for (k, g), s in zip(gazes[first_saccade:], trace[first_saccade:]) if k == "fixation"
                 and s.t > trace[first_saccade].t + 0.08)
    assert np.hypot(after[0] - 0.7, after[1] - 0.4) < 0.02


def test_prediction_leads_a_pursuit():
    trace = [s for s in synthetic_trace() if s.kind == "pursuit"]
    lead = int(0.05 * 250)  # samples in 50 ms

    def error(stream):
        errors = []
        for i, sample in enumerate(trace[:-lead]):
            if stream.push(sample.t, sample.x, sample.y) and i > 5:
                later = trace[i + lead]
                errors.append(np.hypot(stream.gaze[0] - later.x, stream.gaze[1] - later.y))
        return np.mean(errors)

    assert error(GazeStream(prediction=0.05)) < 0.5 * error(GazeStream())


def test_bad_samples_are_refused():
    stream = GazeStream()
    stream.push(1.0, 0.5, 0.5)
    with pytest.raises(ValueError, match="time order"):
        stream.push(0.5, 0.5, 0.5)
    with pytest.raises(ValueError, match="finite"):
        stream.push(2.0, float("nan"), 0.5)


def test_mapper_renders_only_when_the_stream_moves_and_uses_the_sample_in_the_next_frame():
    view = OffscreenView(make_fixture("vessels", size=24), "foveated", size=(48, 48))
    mapper = view.mapper
    trace = synthetic_trace()[:130]  # a fixation, a saccade, the landing
    renders = 0
    for sample in trace:
        if mapper.PushGaze(sample.t, sample.x, sample.y):
            view.render_window.Render()
            renders += 1
            assert mapper.GetLastPlan().gaze == mapper.GetGazeStream().gaze  # this frame used it
            assert 0 < mapper.GetLastGazeLatency() < 10
    assert renders == 2 and mapper.GetGazeSource() == "stream"
    polled = iter([(10.0, 0.8, 0.2), None])
    mapper.SetGazeCallable(lambda: next(polled, None))
    view.render_window.Render()
    assert mapper.GetLastPlan().gaze == (0.8, 0.2)
    with pytest.raises(TypeError, match="callable"):
        mapper.SetGazeCallable(3)
