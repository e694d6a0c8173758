"""Gaze streams: eye-tracker samples to the gaze a foveated frame uses.

mipcast depends on no tracker: a tracker's Python API pushes samples
``(t, x, y)`` (seconds, normalised viewport coordinates, (0, 0)
bottom-left) into a :class:`GazeStream` -- directly, or through
:meth:`mipcast.mappers.foveated.FoveatedVolumeMapper.PushGaze` or a source
callable (:meth:`~mipcast.mappers.foveated.FoveatedVolumeMapper.SetGazeCallable`).
The stream classifies each sample by its velocity over the last
``VELOCITY_WINDOW`` seconds (I-VT, Salvucci & Goldberg 2000; the window
keeps tracker noise from passing for saccades):

- *fixation* (slower than ``saccade_velocity``): the rendered gaze moves
  only when the eye has left a disc of ``fixation_radius`` around it, so
  tracker jitter and microsaccades cause no re-render; a drift or a smooth
  pursuit that leaves the disc moves it (to the sample, or to the position
  predicted ``prediction`` seconds ahead from the recent velocity, to hide
  the render latency);
- *saccade* (faster): the last fixation is kept (vision is suppressed
  during a saccade, Matin 1974); the first slow sample after it lands the
  gaze there at once.

Pure Python; :func:`synthetic_trace` makes a recorded-style trace
(fixations with tremor, a smooth pursuit, saccades) for tests and the
benchmark.

Examples
--------
>>> stream = GazeStream(fixation_radius=0.02, saccade_velocity=2.0)
>>> stream.push(0.00, 0.50, 0.50), stream.push(0.03, 0.501, 0.499)  # first sample, then jitter
(True, False)
>>> stream.push(0.06, 0.80, 0.50), stream.state                     # 10 heights/s: a saccade
(False, 'saccade')
>>> stream.push(0.09, 0.801, 0.50), stream.gaze                     # landed
(True, (0.801, 0.5))
"""
from __future__ import annotations

import math
from typing import List, NamedTuple, Optional, Tuple

import numpy as np

#: Defaults: jitter below 0.02 viewport heights (about 0.6 degrees on the
#: default display) re-renders nothing; 2 viewport heights per second
#: (about 60 degrees/s) separates saccades from pursuit and drift.
DEFAULT_FIXATION_RADIUS = 0.02
DEFAULT_SACCADE_VELOCITY = 2.0
#: Seconds over which a sample's velocity is measured.
VELOCITY_WINDOW = 0.02


class GazeSample(NamedTuple):
    """One tracker sample: time (s), position (normalised viewport coordinates) and, in traces, its kind."""

    t: float
    x: float
    y: float
    kind: str = ""


class GazeStream:
    """Samples in, the gaze to render with out (see the module docstring).

    Parameters
    ----------
    fixation_radius : float, default: 0.02
        Viewport heights the eye may wander from the rendered gaze without a re-render.
    saccade_velocity : float, default: 2.0
        Viewport heights per second above which a sample belongs to a saccade.
    prediction : float, default: 0.0
        Seconds to extrapolate a moving gaze ahead (0: off).
    aspect : float, default: 1.0
        Viewport width / height (distances are in viewport heights).
    """

    def __init__(self, fixation_radius: float = DEFAULT_FIXATION_RADIUS,
                 saccade_velocity: float = DEFAULT_SACCADE_VELOCITY, prediction: float = 0.0,
                 aspect: float = 1.0) -> None:
        for name, value in (("fixation_radius", fixation_radius), ("saccade_velocity", saccade_velocity),
                            ("prediction", prediction), ("aspect", aspect)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be a finite number >= 0, got {value!r}")
        if saccade_velocity <= 0 or aspect <= 0:
            raise ValueError("saccade_velocity and aspect must be > 0")
        self.fixation_radius = float(fixation_radius)
        self.saccade_velocity = float(saccade_velocity)
        self.prediction = float(prediction)
        self.aspect = float(aspect)
        #: The gaze frames should use now (None before the first sample).
        self.gaze: Optional[Tuple[float, float]] = None
        #: ``"fixation"`` or ``"saccade"``: the last sample's class.
        self.state = "fixation"
        #: Time of the sample the current gaze came from.
        self.gaze_time: Optional[float] = None
        self.re_renders = 0
        self._last: Optional[GazeSample] = None
        self._history: List[GazeSample] = []
        self._velocity = (0.0, 0.0)

    @property
    def last_time(self) -> Optional[float]:
        """Time of the last sample taken (None before the first)."""
        return None if self._last is None else self._last.t

    def _distance(self, a, b) -> float:
        return math.hypot((a[0] - b[0]) * self.aspect, a[1] - b[1])

    def push(self, t: float, x: float, y: float) -> bool:
        """Take one sample; True when the gaze to render with changed (a re-render is due).

        Samples must come in time order; a repeated or older time stamp is refused.
        """
        t, x, y = float(t), float(x), float(y)
        if not all(math.isfinite(v) for v in (t, x, y)):
            raise ValueError(f"gaze sample must be finite numbers, got {(t, x, y)!r}")
        previous = self._last
        if previous is not None and t <= previous.t:
            raise ValueError(f"gaze samples must come in time order: t={t} after t={previous.t}")
        self._last = GazeSample(t, x, y)
        self._history.append(self._last)
        while len(self._history) > 2 and t - self._history[1].t >= VELOCITY_WINDOW:
            self._history.pop(0)
        if previous is None:
            return self._move((x, y), t)
        first = self._history[0]
        dt = t - first.t
        velocity = ((x - first.x) / dt, (y - first.y) / dt)
        speed = math.hypot(velocity[0] * self.aspect, velocity[1])
        if speed > self.saccade_velocity:
            self.state = "saccade"
            return False  # keep the last fixation until the eye lands
        landed = self.state == "saccade"
        self.state = "fixation"
        # smoothed velocity (exponential, a few samples) for the prediction
        self._velocity = velocity if landed else tuple(0.5 * a + 0.5 * b for a, b in zip(self._velocity, velocity))
        if landed or self._distance((x, y), self.gaze) > self.fixation_radius:
            target = (x, y)
            if self.prediction > 0 and not landed:
                target = (x + self._velocity[0] * self.prediction, y + self._velocity[1] * self.prediction)
            return self._move(target, t)
        return False

    def _move(self, gaze, t) -> bool:
        self.gaze = (float(gaze[0]), float(gaze[1]))
        self.gaze_time = t
        self.re_renders += 1
        return True


def synthetic_trace(seed: int = 0, rate: float = 250.0) -> List[GazeSample]:
    """A recorded-style gaze trace: fixations with tremor, a smooth pursuit, saccades.

    At ``rate`` Hz: a 400 ms fixation at (0.3, 0.6), a saccade to (0.7, 0.4)
    (40 ms, peak about 20 viewport heights/s), a 300 ms fixation, a 500 ms
    smooth pursuit to (0.5, 0.5) at about 0.5 heights/s, a saccade to
    (0.2, 0.2), a 300 ms fixation.  Fixations have Gaussian tremor of
    0.002 heights (a tracker's noise); ``kind`` labels every sample.

    Examples
    --------
    >>> trace = synthetic_trace()
    >>> len(trace), sorted({s.kind for s in trace})
    (395, ['fixation', 'pursuit', 'saccade'])
    """
    rng = np.random.default_rng(seed)
    step = 1.0 / rate
    samples: List[GazeSample] = []

    def add(kind, points):
        for x, y in points:
            samples.append(GazeSample(len(samples) * step, float(x), float(y), kind))

    def fixation(at, seconds):
        n = int(round(seconds * rate))
        add("fixation", np.asarray(at) + rng.normal(0.0, 0.002, (n, 2)))

    def saccade(a, b, seconds=0.04):
        n = int(round(seconds * rate))
        s = (1 - np.cos(np.pi * (np.arange(1, n + 1) / n))) / 2  # smooth start and landing
        add("saccade", np.asarray(a) + s[:, None] * (np.asarray(b) - np.asarray(a)))

    def pursuit(a, b, seconds):
        n = int(round(seconds * rate))
        s = np.arange(1, n + 1) / n
        add("pursuit", np.asarray(a) + s[:, None] * (np.asarray(b) - np.asarray(a))
            + rng.normal(0.0, 0.001, (n, 2)))

    fixation((0.3, 0.6), 0.4)
    saccade((0.3, 0.6), (0.7, 0.4))
    fixation((0.7, 0.4), 0.3)
    pursuit((0.7, 0.4), (0.5, 0.5), 0.5)
    saccade((0.5, 0.5), (0.2, 0.2))
    fixation((0.2, 0.2), 0.3)
    return samples
