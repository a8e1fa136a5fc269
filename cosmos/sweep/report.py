"""What a sweep reports, from its runs' results.

Its success rate with a Wilson interval, failures by statement and reason, per-statement
durations and peak forces, success against each varied parameter, the slowest and the worst
runs, and what the runs cost.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from typing import Any

import numpy as np

from cosmos.sweep.parameters import PARAMETERS, SEED

Z95 = 1.959963984540054
"""The standard normal's 97.5 % quantile: a two-sided 95 % interval."""
QUANTILES = (0.05, 0.5, 0.95)
BINS = 5
"""Bins (of equal counts) of each varied parameter's values for success against it."""
SHOWN = 3
"""Slowest and worst runs listed."""


def wilson_interval(succeeded: int, runs: int, z: float = Z95) -> tuple[float, float]:
    """The Wilson score interval of a success rate (Wilson 1927), 95 % by default.

    ``(p + z^2/2n -+ z sqrt(p(1-p)/n + z^2/4n^2)) / (1 + z^2/n)`` with ``p = succeeded/runs``;
    unlike the normal approximation it stays inside [0, 1] and is not empty at 0 or n successes.

    Returns:
        ``(low, high)``; ``(0, 1)`` for no runs.
    """
    if runs == 0:
        return 0.0, 1.0
    p = succeeded / runs
    z2 = z * z
    centre = (p + z2 / (2 * runs)) / (1 + z2 / runs)
    half = z * math.sqrt(p * (1 - p) / runs + z2 / (4 * runs * runs)) / (1 + z2 / runs)
    return max(0.0, centre - half), min(1.0, centre + half)


def _reason_kind(reason: str) -> str:
    """A failure's reason with its numbers blanked: runs that failed alike are grouped."""
    return re.sub(r"[-+]?\d+(?:\.\d+)?", "#", reason)


def _quantiles(values: Sequence[float]) -> dict[str, float]:
    array = np.asarray(values, dtype=float)
    out = {f"p{round(q * 100):02d}": float(np.quantile(array, q)) for q in QUANTILES}
    out["max"] = float(array.max())
    return out


def summarize(results: Sequence[dict[str, Any]], varied: Sequence[str]) -> dict[str, Any]:
    """A sweep's figures from its runs' results (:func:`cosmos.sweep.worker.run_task`).

    Returns:
        ``runs``, ``succeeded``, ``success_rate``, ``ci95`` ``[low, high]``, ``failures`` (groups
        of ``line``, ``statement``, ``reason`` (the first run's), ``count``, ``runs``),
        ``statements`` (per statement: ``line``, ``statement``, ``runs`` and quantiles of
        ``duration_s`` and ``peak_force_n``), ``parameters`` (per varied parameter, bins
        with ``low``, ``high``, ``runs``, ``succeeded``), ``slowest`` and ``worst`` (peak force)
        runs, and ``cost`` (seconds per run: ``simulate_s``, ``overhead_s``, their ``overhead_ratio``,
        and ``cpu_s``, the processor time of a run: what it costs on an idle core).
    """
    runs = len(results)
    succeeded = sum(1 for r in results if r["ok"])
    low, high = wilson_interval(succeeded, runs)
    groups: dict[tuple[Any, Any, str], dict[str, Any]] = {}
    for r in results:
        if r["ok"]:
            continue
        key = (r["line"], r["statement"], _reason_kind(r["reason"] or r["outcome"]))
        group = groups.setdefault(
            key,
            {"line": r["line"], "statement": r["statement"], "reason": r["reason"], "count": 0, "runs": []},
        )
        group["count"] += 1
        group.setdefault("runs", []).append(r["index"])
    per_statement: dict[tuple[int, str], dict[str, list[float]]] = {}
    for r in results:
        for s in r["statements"]:
            entry = per_statement.setdefault(
                (s["line"], s["statement"]), {"duration_s": [], "peak_force_n": []}
            )
            entry["duration_s"].append(s["duration_s"])
            entry["peak_force_n"].append(s["peak_force_n"])
    statements = [
        {
            "line": line,
            "statement": statement,
            "runs": len(entry["duration_s"]),
            "duration_s": _quantiles(entry["duration_s"]),
            "peak_force_n": _quantiles(entry["peak_force_n"]),
        }
        for (line, statement), entry in sorted(per_statement.items())
    ]
    by_time = sorted(results, key=lambda r: -r["duration_s"])[:SHOWN]
    by_force = sorted(results, key=lambda r: -r["peak_force_n"])[:SHOWN]
    simulate = sum(r.get("simulate_s", 0.0) for r in results)
    cpu = sum(r.get("cpu_s", 0.0) for r in results)
    overhead = sum(r.get("overhead_s", 0.0) for r in results)
    return {
        "runs": runs,
        "succeeded": succeeded,
        "success_rate": succeeded / runs if runs else 0.0,
        "ci95": [low, high],
        "failures": sorted(groups.values(), key=lambda g: -g["count"]),
        "statements": statements,
        "parameters": {name: success_by_value(results, name) for name in varied if name != SEED},
        "slowest": [_brief(r) for r in by_time],
        "worst": [_brief(r) for r in by_force],
        "cost": {
            "simulate_s": simulate / runs if runs else 0.0,
            "overhead_s": overhead / runs if runs else 0.0,
            "overhead_ratio": overhead / simulate if simulate else 0.0,
            "cpu_s": cpu / runs if runs else 0.0,
        },
    }


def _brief(r: dict[str, Any]) -> dict[str, Any]:
    return {k: r[k] for k in ("index", "ok", "duration_s", "peak_force_n", "line", "reason")}


def success_by_value(results: Sequence[dict[str, Any]], name: str) -> list[dict[str, Any]]:
    """Runs and successes in bins of equal counts of one parameter's values [SI]."""
    pairs = sorted((r["values"][name], r["ok"]) for r in results if name in r["values"])
    if not pairs:
        return []
    bins = []
    for chunk in np.array_split(np.arange(len(pairs)), min(BINS, len(pairs))):
        if not len(chunk):
            continue
        members = [pairs[i] for i in chunk]
        bins.append(
            {
                "low": members[0][0],
                "high": members[-1][0],
                "runs": len(members),
                "succeeded": sum(1 for _, ok in members if ok),
            }
        )
    return bins


def _percent(x: float) -> str:
    return f"{100 * x:.1f} %"


def render(summary: dict[str, Any], program: str, results_path: str) -> list[str]:
    """The report for people, line by line."""
    low, high = summary["ci95"]
    lines = [
        f"{program}: {summary['runs']} runs, {summary['succeeded']} succeeded: "
        f"{_percent(summary['success_rate'])} (95 % interval {_percent(low)} .. {_percent(high)}, Wilson)"
    ]
    if summary["failures"]:
        lines.append("failures:")
        for g in summary["failures"]:
            shown = ", ".join(str(i) for i in g["runs"][:8]) + (" ..." if len(g["runs"]) > 8 else "")
            where = f"line {g['line']} {g['statement']}" if g["line"] is not None else "(no statement)"
            lines.append(f"  {g['count']:4d}  {where}: {g['reason']}  (runs {shown})")
    if summary["statements"]:
        lines.append("statements (5 % / median / 95 % / max over runs):")
        for s in summary["statements"]:
            d, f = s["duration_s"], s["peak_force_n"]
            lines.append(
                f"  line {s['line']:<3d} {s['statement']:<14s} "
                f"duration {d['p05']:.2f} / {d['p50']:.2f} / {d['p95']:.2f} / {d['max']:.2f} s   "
                f"peak force {f['p05']:.1f} / {f['p50']:.1f} / {f['p95']:.1f} / {f['max']:.1f} N"
            )
    for name, bins in summary["parameters"].items():
        parameter = PARAMETERS[name]
        scale, unit = parameter.shown_scale, parameter.shown_unit
        cells = [
            f"{b['low'] * scale:.3g}..{b['high'] * scale:.3g}: {b['succeeded']}/{b['runs']}" for b in bins
        ]
        lines.append(f"success by {name}{f' [{unit}]' if unit else ''}: " + "   ".join(cells))
    for title, key, field, unit in (
        ("slowest", "slowest", "duration_s", "s"),
        ("worst (peak force)", "worst", "peak_force_n", "N"),
    ):
        cells = [f"#{r['index']} {r[field]:.2f} {unit}{'' if r['ok'] else ' (failed)'}" for r in summary[key]]
        lines.append(f"{title} runs: " + ", ".join(cells))
    cost = summary["cost"]
    lines.append(
        f"per run in a worker: {cost['simulate_s']:.3f} s running the program, "
        f"{cost['overhead_s']:.3f} s around it ({_percent(cost['overhead_ratio'])}); "
        f"{cost['cpu_s']:.3f} s of processor time"
    )
    lines.append(f"results: {results_path} (one run again: cosmos run PROGRAM --sample {results_path}:N)")
    return lines
