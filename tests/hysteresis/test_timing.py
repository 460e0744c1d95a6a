"""musclesim.hysteresis.timing: what `musclesim bench` reports of the Preisach core's speed —
its figures' relations and text, and the chunked median it takes (no speed is asserted: that is
the benchmarks' business)."""
import pytest

from musclesim.hysteresis import timing


def test_a_run_too_short_for_one_chunk_is_refused():
    with pytest.raises(ValueError, match="n must be at least 1000 and repeat at least 1"):
        timing.preisach(n=999)
    with pytest.raises(ValueError, match=r"\(got 2000, 0\)"):
        timing.preisach(n=2000, repeat=0)


def test_the_report_holds_each_figure_and_its_ratio_to_a_plain_call():
    report = timing.preisach(n=timing.CHUNK, repeat=1)
    assert report["forward_ratio"] == report["forward_us"] / report["call_us"]
    assert report["inverse_ratio"] == report["inverse_us"] / report["call_us"]
    assert min(report["forward_us"], report["inverse_us"], report["call_us"]) > 0
    assert (report["n"], report["repeat"]) == (timing.CHUNK, 1)
    assert (report["goal_forward_us"], report["goal_inverse_us"]) == (2.0, 3.0)


def test_the_text_says_whether_each_figure_meets_its_goal():
    report = {"forward_us": 1.5, "inverse_us": 4.0, "call_us": 0.05, "forward_ratio": 30.0,
              "inverse_ratio": 80.0, "goal_forward_us": 2.0, "goal_inverse_us": 3.0,
              "n": 20000, "repeat": 5, "python": "3.11.7"}
    lines = timing.format_preisach(report).splitlines()
    assert lines[0] == "forward   1.500 us/step  =  30.0 calls  (meets the goal of 2 us)"
    assert lines[1] == "inverse   4.000 us/step  =  80.0 calls  (misses the goal of 3 us)"
    assert lines[3] == "median over chunks of 1000 steps; 5 runs of 20000 steps; Python 3.11.7"


def test_the_median_is_over_every_chunk_of_every_run_each_reset_first():
    calls, resets = [], []
    xs = list(range(2 * timing.CHUNK + 10))  # two whole chunks; the rest is not timed
    median = timing._median_us(lambda x, y: calls.append((x, y)), xs, xs, 3,
                               lambda: resets.append(len(calls)))
    assert resets == [0, 2 * timing.CHUNK, 4 * timing.CHUNK]
    assert len(calls) == 3 * 2 * timing.CHUNK and calls[0] == (0, 0)
    assert median > 0
