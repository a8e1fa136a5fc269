"""All of ``cosmos bench`` in one run: one dictionary of figures, times in [us] or [s] as named.

Ratios are reported, not asserted. Each time is the best of its runs unless
named otherwise (on a shared machine the slower runs measure the neighbours);
the runs are in the figures too.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

from cosmos.bench.language import bench_compile, check_end_to_end_s
from cosmos.bench.obstacles import bench_obstacles
from cosmos.bench.programs import executor_run, first_run, program_run, shipped_programs, startup_run
from cosmos.bench.servo import REPEATS, measure

PROGRAM_REPEATS = 1
"""Runs of each shipped program as a ``cosmos run`` process (the best is kept)."""

IN_PROCESS_REPEATS = 2
"""Runs of each shipped program in process (the best is kept). One was not enough: the first
program of a kind paid what the process loads once, at first use (the obstacles' kernels at the
first ``OBSTACLE``: ``null_space.cos`` run first spent 0.16 s more of its own than run again),
which is start-up, not the executor's loop."""

STARTUP_REPEATS = 3
"""Runs of the start-up program (the best is kept)."""

CHECK_REPEATS = {1_000: 3, 10_000: 1}
"""Runs of ``cosmos check`` per program length (the 10,000-line one takes seconds)."""


def programs_figures(
    repeats: int = PROGRAM_REPEATS, in_process: int = IN_PROCESS_REPEATS
) -> dict[str, object]:
    """The shipped programs through the executor (in process) and as ``cosmos run`` processes."""
    per_program: dict[str, dict[str, float | bool]] = {}
    walls: dict[str, float] = {}
    total_s = total_ticks = total_runtime_s = total_setup_s = 0.0
    with tempfile.TemporaryDirectory(prefix="cosmos-bench-") as tmp:
        startup_run(Path(tmp))  # untimed: writes any bytecode missing, as an install has it
        for path in shipped_programs():
            runs = [executor_run(path) for _ in range(in_process)]
            best = min(runs, key=lambda run: run.wall_s)
            whole = min((program_run(path, Path(tmp)) for _ in range(repeats)), key=lambda run: run.wall_s)
            walls[path.name] = whole.wall_s
            per_program[path.name] = {
                "ok": best.ok,
                "simulated_s": best.simulated_s,
                "ticks": best.ticks,
                "executor_tick_us": best.tick_us,
                "executor_tick_us_runs": [run.tick_us for run in runs],  # type: ignore[dict-item]
                "runtime_tick_us": best.runtime_tick_us,
                "runtime_setup_ms": best.setup_s * 1e3,
                "executor_to_runtime_tick": best.to_runtime_tick,
                "executor_to_runtime_tick_alone": best.to_runtime_tick_alone,
                "real_time_factor": best.real_time_factor,
                "session_s": best.session_s,
                "run_wall_s": walls[path.name],
                "run_cpu_s": whole.cpu_s,
                "whole_run_real_time_factor": best.simulated_s / walls[path.name],
            }
            total_s += best.wall_s
            total_ticks += best.ticks
            total_runtime_s += best.runtime_s
            total_setup_s += best.setup_s
        startup = min((startup_run(Path(tmp)) for _ in range(STARTUP_REPEATS)), key=lambda run: run.wall_s)
    ran = total_ticks > 0  # an installed package has no shipped programs: nothing measured is null
    return {
        "programs": per_program,
        "run_wall_s": walls,
        "executor_tick_us": total_s / total_ticks * 1e6 if ran else None,
        "runtime_tick_us": total_runtime_s / total_ticks * 1e6 if ran else None,
        # The gap that is the executor's own: its loop against the runtime's work in the same runs, its
        # ticks and its set-up of each segment (the bench loop's workload is free space and one setpoint;
        # the programs' contacts cost physics time); "_alone": against the ticks alone.
        "executor_to_runtime_tick": total_s / (total_runtime_s + total_setup_s) if ran else None,
        "executor_to_runtime_tick_alone": total_s / total_runtime_s if ran else None,
        "startup_s": startup.wall_s,
        "startup_cpu_s": startup.cpu_s,
    }


def measure_all(first: bool = True) -> dict[str, object]:
    """Every figure of ``cosmos bench``; ``first=False`` skips the first run in a fresh cache (30 s+)."""
    figures = measure()
    figures.update(programs_figures())
    executor_us = figures["executor_tick_us"]
    ran = isinstance(executor_us, float)
    figures["executor_to_bench_loop"] = executor_us / float(figures["tick_us"]) if ran else None  # type: ignore
    figures["executor_to_floor"] = executor_us / float(figures["floor_tick_us"]) if ran else None  # type: ignore
    if first:
        with tempfile.TemporaryDirectory(prefix="cosmos-bench-") as tmp:
            run = first_run(Path(tmp))
        figures["first_run_wall_s"] = run.wall_s
        figures["first_run_warm_wall_s"] = run.warm_wall_s
        figures["first_run_compile_s"] = run.wall_s - run.warm_wall_s
        figures["first_run_kernels"] = run.kernels
        figures["first_run_reported_compile_s"] = run.compile_s
    figures["obstacles"] = bench_obstacles()
    figures["compile_10000_lines_runs_s"] = runs_s = [bench_compile(10_000) for _ in range(REPEATS)]
    figures["compile_10000_lines_s"] = min(runs_s)
    for lines, repeats in CHECK_REPEATS.items():
        figures[f"check_{lines}_lines_runs_s"] = runs_s = check_end_to_end_s(lines, repeats)
        figures[f"check_{lines}_lines_s"] = min(runs_s)
    return figures
