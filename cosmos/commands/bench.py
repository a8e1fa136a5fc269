"""``cosmos bench``: what users run and the loop beneath it, beside the floor, as ratios, in one run.

The figures come from :func:`cosmos.bench.suite.measure_all`; this module
prints them (``--json``: one JSON object).
"""

from __future__ import annotations

import json
from collections.abc import Mapping

import click

from cosmos.bench.programs import PROGRAMS_DIR
from cosmos.bench.suite import measure_all


def main(as_json: bool, first: bool = True) -> int:
    """Entry of ``cosmos bench``."""
    figures = measure_all(first)
    if as_json:
        click.echo(json.dumps(figures, indent=2))
        return 0
    for line in report(figures):
        click.echo(line)
    return 0


def _listed(values: object, digits: int = 1) -> str:
    assert isinstance(values, list)
    return ", ".join(f"{value:.{digits}f}" for value in values)


def report(f: Mapping[str, object]) -> list[str]:
    """The figures as lines of text."""
    g = dict(f)
    phases, obstacles, programs = g["phases_us"], g["obstacles"], g["programs"]
    assert isinstance(phases, dict) and isinstance(obstacles, dict) and isinstance(programs, dict)
    lines = [
        f"bench loop: {g['ticks_per_second']:,.0f} ticks/s ({g['tick_us']:.1f} us/tick, real-time factor "
        f"{g['real_time_factor']:.1f} at {g['servo_hz']:g} Hz servo, {g['param_hz']:g} Hz parameters; "
        f"best of {_listed(g['tick_us_runs'])} us/tick)",
        f"  per phase, timed in a second run ({g['timed_tick_us']:.1f} us/tick with clocks):",
        *(f"  {name:<11} {cost:6.2f} us/tick" for name, cost in phases.items()),
        f"floor (mj_step + computeAllTerms + Jacobian): {g['floor_tick_us']:.1f} us/tick "
        f"(best of {_listed(g['floor_tick_us_runs'])}); bench loop / floor = {g['ratio_to_floor']:.2f}",
    ]
    if g["executor_tick_us"] is None:
        lines.append(
            f"executor: not measured, no shipped programs beside this install ({PROGRAMS_DIR}: "
            "an installed package has none); run `cosmos bench` in a clone of the repository"
        )
    else:
        lines.append(
            f"executor (shipped programs, in process): {g['executor_tick_us']:.1f} us/tick; "
            f"/ bench loop = {g['executor_to_bench_loop']:.2f}, / floor = {g['executor_to_floor']:.2f}; "
            f"/ the runtime's tick in the same runs ({g['runtime_tick_us']:.1f} us) = "
            f"{g['executor_to_runtime_tick']:.3f}"
        )
    for name, run in programs.items():
        lines.append(
            f"  {name:<18} {run['ticks']:6d} ticks  {run['executor_tick_us']:5.1f} us/tick  "
            f"(x{run['executor_to_runtime_tick']:.3f} the runtime's)  "
            f"real-time factor {run['real_time_factor']:5.1f}  whole `cosmos run` {run['run_wall_s']:.2f} s "
            f"({run['run_cpu_s']:.2f} s CPU) "
            f"(real-time factor {run['whole_run_real_time_factor']:.1f}){'' if run['ok'] else '  FAILED'}"
        )
    lines.append(
        f"start-up: `cosmos run` of a 10 ms program {g['startup_s']:.2f} s "
        f"({g['startup_cpu_s']:.2f} s CPU), start to exit"
    )
    if "first_run_wall_s" in g:
        lines.append(
            f"first run, empty kernel cache: {g['first_run_wall_s']:.1f} s, "
            f"then {g['first_run_warm_wall_s']:.2f} s warm: compiling costs {g['first_run_compile_s']:.1f} s "
            f"({g['first_run_kernels']} kernels; {g['first_run_reported_compile_s']:.0f} s as reported)"
        )
    counts = sorted(int(key[len("tick_us_") :]) for key in obstacles if key[len("tick_us_") :].isdigit())
    lines.append(
        f"obstacles: bare tick {obstacles['tick_us_bare']:.1f} us (CPU); "
        + ", ".join(
            f"{n} obstacles {obstacles[f'tick_us_{n}']:.1f} us ({obstacles[f'ratio_{n}']:.2f}x)"
            for n in counts
        )
    )
    lines.append(
        f"language: parse + check + compile 10,000 lines in {g['compile_10000_lines_s']:.2f} s "
        f"(best of {_listed(g['compile_10000_lines_runs_s'], 2)} s); `cosmos check` end to end: "
        f"1,000 lines {g['check_1000_lines_s']:.2f} s, 10,000 lines {g['check_10000_lines_s']:.2f} s"
    )
    return lines
