"""Known-answer tests of mipcast.core.metrics on tiny hand-made images."""
import doctest

import numpy as np
import pytest

from mipcast.core import metrics
from mipcast.core.metrics import error_map, grey_diff, summary

NAN = np.nan


def test_docstring_examples():
    assert doctest.testmod(metrics).failed == 0


def test_error_map_values_and_misses():
    reference = np.array([[1.0, NAN], [3.0, 4.0]])
    rendered = np.array([[1.5, 7.0], [2.0, 4.0]], dtype=np.float32)
    errors = error_map(rendered, reference)
    assert errors.dtype == np.float64
    np.testing.assert_array_equal(errors, [[0.5, NAN], [1.0, 0.0]])


def test_error_map_shape_mismatch_names_both():
    with pytest.raises(ValueError, match=r"\(2, 3\).*\(3, 2\)"):
        error_map(np.zeros((2, 3)), np.zeros((3, 2)))


def test_error_map_gpu_miss_raises_with_count():
    reference = np.zeros((2, 2))
    rendered = np.array([[0.0, NAN], [NAN, 0.0]])
    with pytest.raises(ValueError, match=r"missed 2 hit pixels.*\(0, 1\)"):
        error_map(rendered, reference)


def test_misses_the_renderings_rule_allows_are_counted_not_raised():
    reference = np.zeros((5, 5))
    rendered = np.zeros((5, 5))
    rendered[2, 2] = rendered[2, 3] = NAN
    may_miss = np.zeros((5, 5), dtype=bool)
    may_miss[2, 2] = True
    with pytest.raises(ValueError, match=r"missed 1 hit pixels.*\(2, 3\)"):
        error_map(rendered, reference, may_miss=may_miss)
    may_miss[2, 3] = True
    assert np.isnan(error_map(rendered, reference, may_miss=may_miss)).sum() == 2
    stats = summary(rendered, reference, 1.0, may_miss=may_miss)
    assert stats["missing_data_misses"] == 2 and stats["silhouette_misses"] == 0 and stats["hit_pixels"] == 23


def test_summary_known_answer():
    reference = np.array([[10.0, 100.0], [200.0, 250.0], [NAN, NAN]])
    rendered = np.array([[10.0, 101.0], [202.5, 250.0], [5.0, NAN]])
    stats = summary(rendered, reference, 200.0, window=(0.0, 255.0))
    assert stats["grey_level"] == 1.0
    assert stats["hit_pixels"] == 4
    assert stats["mean"] == 0.875 and stats["max"] == 2.5
    assert stats["p99"] == pytest.approx(1.0 + 0.97 * 1.5)
    assert stats["mean_pct"] == 0.4375 and stats["max_pct"] == 1.25
    assert stats["over_1_grey"] == 0.25 and stats["within_1_grey"] == 0.75
    # default foreground: reference > 0 + 0.25 * 255 -> 100, 200, 250
    assert stats["fg_hit_pixels"] == 3
    assert stats["fg_mean"] == pytest.approx(3.5 / 3) and stats["fg_max"] == 2.5
    assert stats["fg_over_1_grey"] == pytest.approx(1 / 3)


def test_summary_grey_level_from_data_range_and_default_foreground():
    reference = np.array([[0.0, 100.0, 200.0, 400.0]])
    rendered = reference + np.array([[0.0, 0.0, 2.0, 2.5]])
    stats = summary(rendered, reference, 510.0)
    assert stats["grey_level"] == 2.0
    assert stats["over_1_grey"] == 0.25  # an error of exactly one grey level is within
    # no window: threshold 0 + 0.25 * (400 - 0) = 100, so 200 and 400 are foreground
    assert stats["fg_hit_pixels"] == 2 and stats["fg_over_1_grey"] == 0.5


def test_summary_explicit_and_empty_foreground():
    reference = np.array([[0.0, 1.0], [2.0, 3.0]])
    rendered = reference + np.array([[1.0, 0.0], [0.0, 0.0]])
    stats = summary(rendered, reference, 3.0, foreground=[[True, False], [False, False]])
    assert stats["fg_hit_pixels"] == 1 and stats["fg_max"] == 1.0
    empty = summary(rendered, reference, 3.0, foreground=np.zeros((2, 2), bool))
    assert empty["fg_hit_pixels"] == 0
    assert np.isnan(empty["fg_mean"]) and np.isnan(empty["fg_over_1_grey"])


@pytest.mark.parametrize("kwargs, message", [
    ({"data_range": 0.0}, "data_range"),
    ({"data_range": 1.0, "window": (2.0, 2.0)}, "window"),
    ({"data_range": 1.0, "foreground": np.ones((3, 3), bool)}, r"\(3, 3\)"),
])
def test_summary_rejects_bad_arguments(kwargs, message):
    with pytest.raises(ValueError, match=message):
        summary(np.zeros((2, 2)), np.zeros((2, 2)), **kwargs)


def test_grey_diff_known_answer():
    a = np.zeros((2, 2, 4), np.uint8)
    b = a.copy()
    b[0, 0, 3] = 1
    b[1, 1, 0] = 255  # no uint8 wrap-around
    assert grey_diff(a, b) == {"within_1": 0.75, "max": 255}
    assert grey_diff(a[..., 0], b[..., 0]) == {"within_1": 0.75, "max": 255}


def test_grey_diff_rejects_bad_input():
    with pytest.raises(TypeError, match="uint8"):
        grey_diff(np.zeros((2, 2)), np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"\(2, 2, 3\).*\(2, 2, 4\)"):
        grey_diff(np.zeros((2, 2, 3), np.uint8), np.zeros((2, 2, 4), np.uint8))
