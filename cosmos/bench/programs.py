"""What users run: the shipped programs through the executor, whole ``cosmos run`` processes, a first run.

* :func:`executor_run`: one program in process, as ``cosmos run`` runs it (plan
  compiled, a session with its log, the executor's loop); the per-tick cost of
  that loop is the executor's own path, monitor, obstacles and log included.
* :func:`process_run`: ``cosmos run`` as a new process, start to exit, as a user
  starts it (the installed ``cosmos`` command, Python's bytecode kept), wall and CPU.
* :func:`first_run`: ``cosmos run`` with an empty kernel cache (``COSMOS_CACHE_DIR``
  set to a new directory): what a fresh install's first run costs.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import cosmos

PROGRAMS_DIR = Path(cosmos.__file__).resolve().parents[1] / "programs"
"""The shipped programs (in a source tree; an installed wheel has none)."""

TINY_PROGRAM = "WAIT 10 ms\n"
"""A program that does almost nothing: its ``cosmos run`` is start-up and shut-down."""

FIRST_RUN_PROGRAM = """\
# Every kernel a run can need: the controller, the log's writer, the obstacle field.
OBSTACLE post CYLINDER AT (0.3, -0.5, 0.5) RADIUS 40 mm HEIGHT 1 m
MOVE BY (0, 0, 20 mm) SPEED 0.1 m/s
"""

_COMPILED = re.compile(r"compiled (\d+) kernels? in (\d+) s")


def shipped_programs() -> list[Path]:
    """The shipped programs, by name (empty outside a source tree)."""
    return sorted(PROGRAMS_DIR.glob("*.cos")) if PROGRAMS_DIR.is_dir() else []


@dataclass(frozen=True)
class ExecutorRun:
    """One program run in process through the executor.

    Attributes:
        program: The program's file name.
        ok: Whether every statement succeeded.
        simulated_s: Simulated time of the run [s].
        ticks: Servo ticks run.
        wall_s: Wall time of the executor's run of the plan [s] (no start-up, no compile).
        session_s: Wall time to open the session (plant, models, log) [s].
        runtime_s: Of ``wall_s``, the time inside the runtime's ticks (sense, parameters,
            servo, physics, record) [s].
        setup_s: Of ``wall_s``, the time inside the runtime's own set-up of each segment [s]:
            the fresh evaluation at the measured state (``Runtime.reset_clocks``) and the servo's
            new setpoint with its rotation plan (``Runtime.set_setpoint``). The rest of ``wall_s``
            is the executor's own: its judgement of each tick (monitor, protective stops,
            obstacles) and the rest of each segment's start (goals, monitor, log).

    Both ``wall_s`` and ``runtime_s`` leave out what the clock around each tick costs
    (:func:`tick_clock_cost_ns`): the executor runs without it.
    """

    program: str
    ok: bool
    simulated_s: float
    ticks: int
    wall_s: float
    session_s: float
    runtime_s: float = 0.0
    setup_s: float = 0.0

    @property
    def tick_us(self) -> float:
        """Wall time per servo tick of the executor's loop [us]."""
        return self.wall_s / max(1, self.ticks) * 1e6

    @property
    def runtime_tick_us(self) -> float:
        """Wall time per servo tick inside the runtime's tick, in the same run [us]."""
        return self.runtime_s / max(1, self.ticks) * 1e6

    @property
    def to_runtime_tick(self) -> float:
        """The executor's loop over the runtime's ticks and set-up in it: 1.0 is no cost of its own.

        Same run. The runtime's set-up of a segment is counted as the runtime's, as its ticks are: the bench
        loop it is compared with runs one setpoint, and the set-up is the runtime's evaluation and
        servo, not the executor's judgement (counted as the executor's, the executor was charged
        0.2-0.6 ms a segment of the runtime's work).
        """
        runtime_s = self.runtime_s + self.setup_s
        return self.wall_s / runtime_s if runtime_s > 0 else 0.0

    @property
    def to_runtime_tick_alone(self) -> float:
        """The executor's loop over the runtime's ticks alone (the set-up counted as the executor's)."""
        return self.wall_s / self.runtime_s if self.runtime_s > 0 else 0.0

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall second of the executor's loop."""
        return self.simulated_s / self.wall_s if self.wall_s > 0 else 0.0


CLOCK_CALLS = 20_000
"""Calls of the tick's clock around a tick that does nothing, per look at what it costs."""


class _Idle:
    def tick(self) -> float:
        """A runtime's tick that does nothing."""
        return 0.0


def _timed(tick: Callable[[], float], inside: list[int]) -> Callable[[], float]:
    """``tick`` with a clock around it: its nanoseconds are added to ``inside[0]``."""
    clock = time.perf_counter_ns

    def timed_tick() -> float:
        start = clock()
        now = tick()
        inside[0] += clock() - start
        return now

    return timed_tick


def _timed_call(call: Callable[..., None], inside: list[int]) -> Callable[..., None]:
    """``call`` with a clock around it: its nanoseconds are added to ``inside[0]``."""
    clock = time.perf_counter_ns

    def timed_call(*args: object) -> None:
        start = clock()
        call(*args)
        inside[0] += clock() - start

    return timed_call


def tick_clock_cost_ns(calls: int = CLOCK_CALLS, looks: int = 5) -> tuple[float, float]:
    """What the clock around each tick adds, per tick: to the executor's loop, and inside the tick [ns].

    Timed around a tick that does nothing, best of ``looks``: the loop's extra cost is the
    timed call's minus the bare call's (the wrapper's call, two clock reads, the sum); of it,
    the clock reads' share falls between them, inside the time counted as the runtime's.
    Without the correction the executor was charged 0.1-0.3 us a tick (1-2 % of a 15 us tick)
    that ``cosmos run`` never pays.
    """
    bare = _Idle().tick
    best_bare = best_timed = best_inside = float("inf")
    for _ in range(looks):
        start = time.perf_counter_ns()
        for _ in range(calls):
            bare()
        best_bare = min(best_bare, (time.perf_counter_ns() - start) / calls)
        inside = [0]
        timed = _timed(bare, inside)
        start = time.perf_counter_ns()
        for _ in range(calls):
            timed()
        best_timed = min(best_timed, (time.perf_counter_ns() - start) / calls)
        best_inside = min(best_inside, inside[0] / calls)
    extra = max(0.0, best_timed - best_bare)
    clocks = min(extra, max(0.0, best_inside - best_bare))
    return extra, clocks


def executor_run(path: Path) -> ExecutorRun:
    """Run ``path`` in process as ``cosmos run`` does (its log in a temporary directory)."""
    from cosmos.commands.run import compile_file
    from cosmos.errors import CosmosError
    from cosmos.execution.session import Session
    from cosmos.hand.tool import Tool
    from cosmos.robots import robot_named
    from cosmos.runtime.rates import Rates

    plan = compile_file(path)
    rates = Rates()
    with tempfile.TemporaryDirectory(prefix="cosmos-bench-") as tmp:
        opened = time.perf_counter()
        arm = robot_named(plan.robot)
        with Session(
            str(path),
            plan.source,
            Path(tmp) / "run.mcap",
            rates,
            robot=arm,
            tool=Tool(plan.tool),
            objects=plan.objects,
        ) as session:
            runtime = session.runtime
            inside, setup = [0], [0]
            # The executor looks the tick up at each segment's start, and the set-up at each call.
            runtime.tick = _timed(runtime.tick, inside)  # type: ignore[method-assign]
            runtime.reset_clocks = _timed_call(runtime.reset_clocks, setup)  # type: ignore[method-assign]
            runtime.set_setpoint = _timed_call(runtime.set_setpoint, setup)  # type: ignore[method-assign]
            start_s, ok = runtime.time_s, True
            started = time.perf_counter()
            try:
                session.executor.run(plan)
            except CosmosError:
                ok = False
            wall_s = time.perf_counter() - started
            simulated_s = runtime.time_s - start_s
    ticks = round(simulated_s * rates.servo_hz)
    extra_ns, clocks_ns = tick_clock_cost_ns()
    return ExecutorRun(
        path.name,
        ok,
        simulated_s,
        ticks,
        wall_s - ticks * extra_ns / 1e9,
        started - opened,
        inside[0] / 1e9 - ticks * clocks_ns / 1e9,
        setup[0] / 1e9,
    )


def command() -> list[str]:
    """How a user starts cosmos: the ``cosmos`` command installed beside this interpreter.

    ``python -m cosmos`` where there is none (a source tree without an install).
    """
    script = Path(sys.executable).with_name("cosmos")
    return [str(script)] if script.is_file() else [sys.executable, "-m", "cosmos"]


def user_environment(env: dict[str, str] | None = None) -> dict[str, str]:
    """``env`` (default: this process's) as a user's run has it: Python's bytecode kept.

    An install compiles every module's bytecode once; with ``PYTHONDONTWRITEBYTECODE`` set
    (some development machines) each process compiles every module again (0.15 s), which
    no user's run pays.
    """
    out = dict(os.environ if env is None else env)
    out.pop("PYTHONDONTWRITEBYTECODE", None)
    return out


@dataclass(frozen=True)
class ProcessRun:
    """One whole ``cosmos`` process: wall and CPU seconds, start to exit, and its stderr."""

    wall_s: float
    cpu_s: float  # user and system, the process and its children
    stderr: str


def process_run(args: list[str], env: dict[str, str] | None = None) -> ProcessRun:
    """``cosmos ARGS`` as a new process, as a user starts it (:func:`command`, :func:`user_environment`)."""
    before = os.times()
    start = time.perf_counter()
    done = subprocess.run(
        [*command(), *args], capture_output=True, text=True, env=user_environment(env), check=False
    )
    wall = time.perf_counter() - start
    after = os.times()
    if done.returncode not in (0, 1):  # 1: the program failed, and ran whole (the figures say `ok`)
        from cosmos.errors import CosmosError

        said = done.stderr.strip().splitlines()[-1:] or ["no message"]
        raise CosmosError(f"cosmos {' '.join(args)} exited with status {done.returncode}: {said[0]}")
    cpu = after.children_user + after.children_system - before.children_user - before.children_system
    return ProcessRun(wall, cpu, done.stderr)


def process_wall_s(args: list[str], env: dict[str, str] | None = None) -> tuple[float, str]:
    """Wall seconds of ``cosmos ARGS`` (:func:`process_run`) from start to exit, and its stderr."""
    run = process_run(args, env)
    return run.wall_s, run.stderr


def program_run(path: Path, log_dir: Path) -> ProcessRun:
    """``cosmos run PATH`` as a new process (warm kernel cache)."""
    return process_run(["run", str(path), "--force", "--log", str(log_dir / f"{path.stem}.mcap")])


def run_wall_s(path: Path, log_dir: Path) -> float:
    """Wall seconds of ``cosmos run PATH`` as a new process (warm kernel cache)."""
    return program_run(path, log_dir).wall_s


def startup_run(log_dir: Path) -> ProcessRun:
    """``cosmos run`` on :data:`TINY_PROGRAM`: interpreter, imports, models, log, as a new process."""
    program = log_dir / "tiny.cos"
    program.write_text(TINY_PROGRAM, encoding="utf-8")
    return process_run(["run", str(program), "--force", "--log", str(log_dir / "tiny.mcap")])


def startup_s(log_dir: Path) -> float:
    """Wall seconds of :func:`startup_run`."""
    return startup_run(log_dir).wall_s


@dataclass(frozen=True)
class FirstRun:
    """``cosmos run`` of :data:`FIRST_RUN_PROGRAM` with an empty kernel cache, then again warm.

    Attributes:
        wall_s: The first run, start to exit [s].
        warm_wall_s: The same run again, its kernels cached [s].
        kernels: Kernels the first run compiled (as it reported).
        compile_s: Seconds it reported compiling.
    """

    wall_s: float
    warm_wall_s: float
    kernels: int
    compile_s: float


def first_run(log_dir: Path) -> FirstRun:
    """A first run on this machine, in a fresh cache directory (deleted afterwards)."""
    program = log_dir / "first.cos"
    program.write_text(FIRST_RUN_PROGRAM, encoding="utf-8")
    args = ["run", str(program), "--force", "--log", str(log_dir / "first.mcap")]
    with tempfile.TemporaryDirectory(prefix="cosmos-fresh-cache-") as cache:
        env = dict(os.environ, COSMOS_CACHE_DIR=cache)
        wall, stderr = process_wall_s(args, env)
        warm, _ = process_wall_s(args, env)
    match = _COMPILED.search(stderr)
    kernels, compile_s = (int(match.group(1)), float(match.group(2))) if match else (0, 0.0)
    return FirstRun(wall, warm, kernels, compile_s)
