"""The sweep's figures: the Wilson interval against published values, failures grouped, bins."""

import pytest

from cosmos.sweep.report import success_by_value, summarize, wilson_interval


@pytest.mark.parametrize(
    ("succeeded", "runs", "low", "high"),
    [
        # Newcombe, Statistics in Medicine 17 (1998) 857-872, Table I, method 3 (Wilson score).
        (81, 263, 0.2553, 0.3662),
        (15, 148, 0.0624, 0.1605),
        (0, 20, 0.0, 0.1611),
        (1, 29, 0.0061, 0.1718),
    ],
)
def test_wilson_interval_matches_published_values(succeeded: int, runs: int, low: float, high: float) -> None:
    """Catches a wrong z, the normal approximation in its place, or a missing continuity-free form."""
    assert wilson_interval(succeeded, runs) == pytest.approx((low, high), abs=1e-4)


def _result(index: int, ok: bool, line: int | None = None, reason: str | None = None, x: float = 0.0) -> dict:
    return {
        "index": index,
        "ok": ok,
        "outcome": "ok" if ok else "failed",
        "line": line,
        "statement": None if ok else "INSERT DOWN",
        "reason": reason,
        "values": {"hole.x": x, "seed": 1.0},
        "duration_s": 1.0 + index,
        "peak_force_n": 10.0 - index,
        "statements": [{"line": 3, "statement": "MOVE TO", "duration_s": 1.0 + index, "peak_force_n": 2.0}],
    }


def test_failures_group_by_statement_and_reason_whatever_the_numbers() -> None:
    """Catches one group per run (numbers in the reason) or groups mixing statements."""
    results = [
        _result(0, True),
        _result(1, False, 6, "jammed at depth 0.1 mm: no progress for 1 s while pushing 14.3 N"),
        _result(2, False, 6, "jammed at depth 2.5 mm: no progress for 1 s while pushing 15.0 N"),
        _result(3, False, 5, "found no contact within 1.5 s"),
    ]
    summary = summarize(results, ["hole.x", "seed"])
    assert (summary["runs"], summary["succeeded"], summary["success_rate"]) == (4, 1, 0.25)
    assert [(g["line"], g["count"], g["runs"]) for g in summary["failures"]] == [(6, 2, [1, 2]), (5, 1, [3])]
    assert summary["slowest"][0]["index"] == 3 and summary["worst"][0]["index"] == 0
    assert summary["statements"][0]["duration_s"]["max"] == 4.0
    assert list(summary["parameters"]) == ["hole.x"]  # the noise seed is no parameter to plot


def test_success_by_value_counts_every_run_once_in_order() -> None:
    """Catches runs lost or counted twice between bins, or bins out of order."""
    results = [_result(i, i % 3 != 0, 1, "r", x=(i * 7 % 11) / 1000) for i in range(11)]
    bins = success_by_value(results, "hole.x")
    assert sum(b["runs"] for b in bins) == 11
    assert sum(b["succeeded"] for b in bins) == sum(1 for r in results if r["ok"])
    assert all(a["high"] <= b["low"] for a, b in zip(bins, bins[1:], strict=False))
