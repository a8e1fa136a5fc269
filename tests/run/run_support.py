"""Running programs for the acceptance tests of ``cosmos run``, and reading what their logs show.

Programs are written as text into a temporary directory and run either through
the command line in a subprocess (``python -m cosmos run PROG --log LOG``: exit
status, stdout and stderr exactly as a user sees them) or in-process through
:func:`cosmos.commands.run.run_program` (the same code path without the
interpreter start-up). Every judgement is made on the run's own MCAP log, read
back with :func:`cosmos.runlog.read_log`.

The workcell's geometry used to judge the runs is written out here from the
issue and the scene's documentation (table top, hole mouth, slope tilt), not
taken from the code under test; ``test_run_geometry`` checks that the two agree.
"""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Self

import numpy as np
import pytest

from cosmos.runlog import read_log
from cosmos.runlog.reader import EventRecord, RunRecord, SegmentRecord

REPO = Path(__file__).resolve().parents[2]
PROGRAMS = REPO / "programs"

TABLE_TOP_Z_M = 0.20
"""Height of the table's top face [m]."""
TABLE_POINT_M = np.array([0.60, -0.15, 0.20])
"""The ``table`` fixture frame's origin, a work point on the table top [m]."""
HOLE_MOUTH_M = np.array([0.60, 0.15, 0.26])
"""Centre of the hole's mouth [m]."""
HOLE_DEPTH_M = 0.045
"""Depth of the hole below its mouth [m]."""
SLOPE_CENTRE_M = np.array([0.45, -0.40, 0.26])
"""Centre of the tilted plate's top face [m]."""
SLOPE_TILT_RAD = np.radians(20.0)
"""The plate's outward normal is world z turned by this angle about world y (towards +x)."""
SLOPE_NORMAL_OUT = np.array([np.sin(SLOPE_TILT_RAD), 0.0, np.cos(SLOPE_TILT_RAD)])
"""Outward unit normal of the tilted plate (world)."""

SHIPPED = tuple(sorted(p.name for p in PROGRAMS.glob("*.cos")))
"""The shipped programs, by file name."""

CLI_TIMEOUT_S = 600.0
"""Wall-clock bound on one subprocess run (the machine may be loaded)."""


@dataclass(frozen=True)
class ProgramRun:
    """A finished run: how it exited, what it printed, and its log read back."""

    program: Path
    returncode: int
    stdout: str
    stderr: str
    log: RunRecord

    @property
    def source(self) -> str:
        """The program's text."""
        return self.program.read_text(encoding="utf-8")

    def line_of(self, text: str, start: int = 1) -> int:
        """Source line (1-based) of the first line at or after ``start`` that contains ``text``."""
        for number, line in enumerate(self.source.splitlines(), start=1):
            if number >= start and text in line:
                return number
        raise AssertionError(f"no line containing {text!r} in {self.program}")

    def events(self, kind: str | None = None, line: int | None = None) -> list[EventRecord]:
        """Events of the run, optionally of one kind and/or one source line."""
        return [
            e
            for e in self.log.events
            if (kind is None or e.kind == kind) and (line is None or e.line == line)
        ]

    def segments(self, kind: str | None = None, line: int | None = None) -> list[SegmentRecord]:
        """Segments of the run, optionally of one kind and/or one source line."""
        return [
            s
            for s in self.log.segments
            if (kind is None or s.kind == kind) and (line is None or s.line == line)
        ]

    def describe(self) -> str:
        """Exit status, stderr and the event list: what a failed assertion should show."""
        events = "\n".join(f"  {e.t:7.3f} {e.kind:8s} line {e.line}: {e.reason}" for e in self.log.events)
        return f"{self.program.name}: exit {self.returncode}\nstderr:\n{self.stderr}\nevents:\n{events}"


def read_run(program: Path, log_path: Path, returncode: int, stdout: str, stderr: str) -> ProgramRun:
    """Bundle a finished run with its log."""
    return ProgramRun(program, returncode, stdout, stderr, read_log(log_path))


def cli_command(program: Path, log_path: Path) -> list[str]:
    """``python -m cosmos run PROGRAM --log LOG``, as a user would type it."""
    return [sys.executable, "-m", "cosmos", "run", str(program), "--log", str(log_path)]


def run_cli(program: Path, log_path: Path) -> ProgramRun:
    """Run ``cosmos run PROGRAM --log LOG`` in a subprocess and wait for it."""
    done = subprocess.run(
        cli_command(program, log_path),
        capture_output=True,
        text=True,
        timeout=CLI_TIMEOUT_S,
        cwd=REPO,
        check=False,
    )
    return read_run(program, log_path, done.returncode, done.stdout, done.stderr)


def run_in_process(program: Path, log_path: Path, ideal: bool = False) -> ProgramRun:
    """Run a program through :func:`cosmos.commands.run.run_program` in this process.

    On the realistic plant (the default) or the ideal one (``--ideal``).
    """
    from cosmos.commands.run import run_program
    from cosmos.runtime.rates import Rates

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        returncode = run_program(program, log_path, Rates(), 0, ideal=ideal)
    return read_run(program, log_path, returncode, out.getvalue(), err.getvalue())


def write_program(directory: Path, name: str, source: str) -> Path:
    """Write ``source`` to ``directory/name.cos``."""
    path = directory / f"{name}.cos"
    path.write_text(source, encoding="utf-8")
    return path


class BackgroundRuns:
    """CLI runs in a background thread, one at a time, while tests run in-process.

    The machine has two cores: one runs the in-process simulations of the test
    functions, the other works through this queue of subprocess runs, so the
    directory's wall time is roughly halved without oversubscribing the cores.
    """

    def __init__(self, log_dir: Path):
        self._log_dir = log_dir
        self._programs: dict[str, Path] = {}
        self._results: dict[str, ProgramRun | BaseException] = {}
        self._done: dict[str, threading.Event] = {}
        self._queue: list[str] = []
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._process: subprocess.Popen[str] | None = None
        self._closed = False

    def submit(self, key: str, program: Path) -> None:
        """Queue a CLI run of ``program`` under ``key`` (a second submit of a key is ignored)."""
        with self._lock:
            if key in self._done or self._closed:
                return
            self._programs[key] = program
            self._done[key] = threading.Event()
            self._queue.append(key)
            if self._thread is None:
                self._thread = threading.Thread(target=self._work, name="cosmos-runs", daemon=True)
                self._thread.start()

    def _work(self) -> None:
        while True:
            with self._lock:
                if not self._queue or self._closed:
                    self._thread = None
                    return
                key = self._queue.pop(0)
                program = self._programs[key]
                log_path = self._log_dir / f"{key}.mcap"
                self._process = subprocess.Popen(
                    cli_command(program, log_path),
                    stdout=subprocess.PIPE,
                    stderr=subprocess.PIPE,
                    text=True,
                    cwd=REPO,
                )
            try:
                stdout, stderr = self._process.communicate(timeout=CLI_TIMEOUT_S)
                self._results[key] = read_run(program, log_path, self._process.returncode, stdout, stderr)
            except BaseException as error:  # handed to the test that waits for it
                self._process.kill()
                self._results[key] = error
            self._done[key].set()

    def result(self, key: str) -> ProgramRun:
        """Wait for the run queued under ``key`` and return it."""
        if not self._done[key].wait(timeout=CLI_TIMEOUT_S * max(1, len(self._done))):
            raise TimeoutError(f"the background run of {key} did not finish")
        outcome = self._results[key]
        if isinstance(outcome, BaseException):
            raise outcome
        return outcome

    def close(self) -> None:
        """Drop what is still queued and stop the run in progress (the session is over)."""
        with self._lock:
            self._closed = True
            self._queue.clear()
            process = self._process
        if process is not None and process.poll() is None:
            process.kill()
            process.wait()


def samples_of(run: ProgramRun, segment_indices: list[int]) -> np.ndarray:
    """Boolean mask of the state samples logged while any of the given segments ran."""
    return np.isin(run.log.state.segment, segment_indices)


def tool_axis_world(quat_wxyz: np.ndarray) -> np.ndarray:
    """The tool's z axis in world coordinates from w x y z quaternions. # (n, 4) -> (n, 3)."""
    w, x, y, z = np.asarray(quat_wxyz, dtype=float).T
    return np.stack((2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)), axis=1)


def angle_deg(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle between rows of ``a`` and the vector ``b`` [deg]."""
    a = np.atleast_2d(a)
    cos = a.dot(b) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


BOTH_PLANTS = [pytest.param(False, id="realistic"), pytest.param(True, id="ideal")]
"""``ideal`` parameters: the realistic plant, then the ideal one, both expected to pass."""


class StepProbe:
    """What MuJoCo's data shows after every physics step of the runs made inside ``with``: a
    wrapper on :meth:`cosmos.plant.Plant.advance`; a subclass's :meth:`sample` reads it."""

    def __init__(self) -> None:
        from cosmos.plant import Plant

        self._plant_class = Plant
        self._original = Plant.advance
        self._force = np.zeros(6)  # mujoco.mj_contactForce's output, for the subclasses

    def __enter__(self) -> Self:
        probe, original = self, self._original

        def advance(plant: Any) -> float:
            t = original(plant)
            probe.sample(plant.model, plant.data, t)
            return t

        self._plant_class.advance = advance  # type: ignore[method-assign]
        return self

    def __exit__(self, *_: object) -> None:
        self._plant_class.advance = self._original  # type: ignore[method-assign]

    def sample(self, model: Any, data: Any, t: float) -> None:
        """Read one physics step's ``model`` and ``data`` at simulated time ``t`` [s]."""
        raise NotImplementedError


GRASPED_PEG_INSERT = """TOOL GRIPPER
LET holder = hole + (0, 120 mm, 0)
MOVE TO holder + (0, 0, 50 mm) SPEED 0.3 m/s
MOVE TO holder + (0, 0, 15 mm) SPEED 50 mm/s
GRASP peg FORCE 80 N
MOVE BY (0, 0, 70 mm) SPEED 80 mm/s
MOVE TO hole + (3 mm, -2 mm, 8 mm) SPEED 0.15 m/s
CONTACT DOWN FORCE 6 N SPEED 8 mm/s
INSERT DOWN DEPTH 25 mm FORCE 12 N TIMEOUT 30 s
"""
"""The shipped peg taken from its holder by the gripper (no ROBOT line: either arm), then a CONTACT
and an INSERT from 3.6 mm off the hole's axis, where it lands on the mouth's edge."""
