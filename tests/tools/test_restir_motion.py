"""The equal-CPU RIS of tools/experiments/restir_motion.py (RIS's relMSE at another method's own CPU time, from the
RIS rows of the same run), against values worked out by hand."""

from __future__ import annotations

import pytest

from tools.experiments import restir_motion as tool


def row(method: str, cpu_ms: float, mean: float, k: int = 1, median: float | None = None) -> dict:
    return {"method": method, "cpu_ms": cpu_ms, "k": k, "mean_rel_mse_after_0": mean,
            "median_rel_mse_after_0": mean if median is None else median}


def test_only_plain_ris_counts_are_the_ladder():
    assert tool.ris_candidates_of("ris+candidates=16") == 16
    assert tool.ris_candidates_of("ris") is None
    assert tool.ris_candidates_of("restir+candidates=16") is None
    assert tool.ris_candidates_of("ris+candidates=16+taa_filter=catmull_rom") is None


def test_a_method_between_two_counts():
    # RIS costs 5 + 1 N ms (10 -> 15 ms, 20 -> 25 ms) and its relMSE is 0.2 at 10 and 0.1 at 20 (N^-1).
    # A method of 19.142... ms sits at N = 14.142... = 10 sqrt(2), half-way in log N: relMSE 0.2 / sqrt(2).
    n = 10 * 2**0.5
    rows = [row("ris+candidates=10", 15.0, 0.2), row("ris+candidates=20", 25.0, 0.1), row("restir", 5.0 + n, 0.05)]
    (got_n, got_e), = tool.equal_time_ris(rows).values()
    assert got_n == pytest.approx(n)
    assert got_e == pytest.approx(0.2 / 2**0.5)


def test_beyond_the_ladder_the_end_segment_goes_on():
    # the same RIS, a method of 45 ms: N = 40, two doublings past 10 along N^-1: 0.05
    rows = [row("ris+candidates=10", 15.0, 0.2), row("ris+candidates=20", 25.0, 0.1), row("restir", 45.0, 0.01)]
    assert tool.equal_time_ris(rows)["restir"] == pytest.approx((40.0, 0.05))


def test_the_median_is_read_when_asked():
    rows = [row("ris+candidates=10", 15.0, 0.2, median=0.4), row("ris+candidates=20", 25.0, 0.1, median=0.1),
            row("restir", 25.0, 0.05)]
    # N = 20, an end of the ladder: its own median
    assert tool.equal_time_ris(rows, "median_rel_mse_after_0")["restir"] == pytest.approx((20.0, 0.1))


def test_rows_of_several_frames_and_a_single_count_make_no_ladder():
    rows = [row("ris+candidates=10", 15.0, 0.2, k=2), row("ris+candidates=20", 25.0, 0.1), row("restir", 20.0, 0.1)]
    assert tool.equal_time_ris(rows) is None
