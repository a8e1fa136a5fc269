"""One run of a sweep, in whatever process runs it: a pool worker, a Dask worker, or this one.

:func:`run_task` is a plain function of a picklable :class:`RunTask` (the program's text,
the run's index and drawn values), so the local pool and a Dask cluster run the very same
code; a process keeps the compiled plan, the models and the compiled kernels between runs.
The result is what the run's log is given (:class:`cosmos.sweep.tap.LogTap`); the log
itself is dropped, or its bytes returned to be kept.
"""

from __future__ import annotations

import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from cosmos.errors import CosmosError
from cosmos.sweep.tap import LogTap
from cosmos.sweep.variation import WorkcellVariation

if TYPE_CHECKING:
    from cosmos.plan import Plan

TIMING_FIELDS = ("wall_s", "cpu_s", "simulate_s", "overhead_s", "worker")
"""Fields of a result that depend on the machine, not on the run (left out when comparing engines)."""


@dataclass(frozen=True)
class RunTask:
    """One run to make.

    Attributes:
        index: The run's index in the sweep.
        program: The program's name (its path as given).
        source: The program's text.
        values: The run's drawn values, SI, the noise ``seed`` included.
        keep_log: Return the log's bytes: always, or only if the run failed.
        ideal: Run on the ideal plant (``cosmos sweep --ideal``).
    """

    index: int
    program: str
    source: str
    values: dict[str, float]
    keep_log: bool = False
    keep_failed_log: bool = False
    ideal: bool = False


_plans: dict[tuple[str, str], Plan] = {}
"""Plans compiled in this process, by (program, source): a worker compiles a program once."""


def _plan(program: str, source: str) -> Plan:
    plan = _plans.get((program, source))
    if plan is None:
        from cosmos.lang import compile_program
        from cosmos.workcell import fixture_frames

        plan = compile_program(source, program, fixture_frames())
        _plans.clear()
        _plans[program, source] = plan
    return plan


WARM_UP_PROGRAM = "WAIT 20 ms\n"
"""A program so short that running it once costs only the first call of everything a run calls."""


def warm_up() -> None:
    """Load models and compiled kernels and make every first call once, before the first real run."""
    run_task(RunTask(-1, "<warm-up>", WARM_UP_PROGRAM, {"seed": 0.0}))


def run_task(task: RunTask) -> dict[str, Any]:
    """Make one run and return its result (a JSON-able dict; ``log_bytes`` if the log is kept).

    The result's keys: ``index``, ``values``, those of :func:`cosmos.sweep.tap.summarize`,
    and the timings ``wall_s`` (the whole task), ``cpu_s`` (its processor time), ``simulate_s``
    (the executor's run, its logging included) and ``overhead_s`` (their difference: set-up
    and clean-up).
    """
    from cosmos.execution.session import Session
    from cosmos.hand.tool import Tool
    from cosmos.robots import robot_named
    from cosmos.runtime.rates import Rates

    started, cpu_started = time.perf_counter(), time.process_time()
    plan = _plan(task.program, task.source)
    variation = WorkcellVariation.from_values(task.values, ideal=task.ideal)
    handle, name = tempfile.mkstemp(prefix=f"cosmos-sweep-{task.index}-", suffix=".mcap")
    os.close(handle)
    log_path = Path(name)
    try:
        arm = robot_named(plan.robot)
        with Session(
            task.program,
            task.source,
            log_path,
            Rates(),
            variation=variation,
            robot=arm,
            tool=Tool(plan.tool),
            objects=plan.objects,
        ) as session:
            tap = LogTap(session.log)
            simulate_started = time.perf_counter()
            try:
                session.executor.run(plan)
            except CosmosError:
                pass  # the failure is in the events the tap kept, as in the log
            simulate_s = time.perf_counter() - simulate_started
        result = {"index": task.index, "values": dict(task.values)} | tap.summary()
        if task.keep_log or (task.keep_failed_log and not result["ok"]):
            result["log_bytes"] = log_path.read_bytes()
    finally:
        log_path.unlink(missing_ok=True)
    wall_s = time.perf_counter() - started
    result |= {
        "wall_s": wall_s,
        "cpu_s": time.process_time() - cpu_started,
        "simulate_s": simulate_s,
        "overhead_s": wall_s - simulate_s,
        "worker": os.getpid(),
    }
    return result
