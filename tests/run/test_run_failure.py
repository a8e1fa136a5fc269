"""A failing CONTACT through the command line (issue 5, "Must show").

``CONTACT UP FORCE 5 N TIMEOUT 1.5 s`` in free space: exit status 1, the error
as ``file:4:1: CONTACT UP found no contact within 1.5 s`` with the source line
and a caret under the statement, no Python traceback, the log's path printed,
and a complete log (summary and footer) that reads with a ``failed`` event.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from run_support import ProgramRun, run_cli, write_program

FAILING_PROGRAM = """\
# touch: a CONTACT upward in free space finds nothing
SPEED 0.25 m/s
MOVE BY (0, 0, 50 mm)
CONTACT UP FORCE 5 N TIMEOUT 1.5 s
MOVE BY (0, 0, -50 mm)
"""
FAILING_LINE = 4


@pytest.fixture(scope="module")
def failing_run(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The program above through ``python -m cosmos run PROG --log LOG``."""
    directory = tmp_path_factory.mktemp("failing")
    program = write_program(directory, "touch", FAILING_PROGRAM)
    return run_cli(program, directory / "touch.mcap")


def test_exit_status_is_1(failing_run: ProgramRun) -> None:
    """A statement that fails at run time: exit status 1."""
    assert failing_run.returncode == 1, failing_run.describe()


def test_error_names_file_line_statement_and_reason(failing_run: ProgramRun) -> None:
    """``PROG:4:1: CONTACT UP found no contact within 1.5 s``, the source line, a caret under it."""
    lines = failing_run.stderr.splitlines()
    expected = f"{failing_run.program}:{FAILING_LINE}:1: CONTACT UP found no contact within 1.5 s"
    assert expected in lines, failing_run.stderr
    at = lines.index(expected)
    source_line = FAILING_PROGRAM.splitlines()[FAILING_LINE - 1]
    assert lines[at + 1].strip() == source_line, failing_run.stderr
    caret = lines[at + 2]
    column = caret.index("^")
    assert column == lines[at + 1].index(source_line[0]), "the caret starts under column 1"
    assert set(caret.strip()) == {"^"}, failing_run.stderr


def test_no_traceback(failing_run: ProgramRun) -> None:
    """A user-facing failure never shows a Python traceback."""
    assert "Traceback" not in failing_run.stderr + failing_run.stdout


def test_log_path_is_printed(failing_run: ProgramRun) -> None:
    """The log's path is printed at the end, failure or not."""
    assert f"log: {failing_run.log.path}" in failing_run.stdout.splitlines(), failing_run.stdout


def test_log_is_complete(failing_run: ProgramRun) -> None:
    """The MCAP file has its summary (read with the mcap library itself), and cosmos reads it whole."""
    assert not failing_run.log.truncated
    with Path(failing_run.log.path).open("rb") as stream:
        summary = make_reader(stream).get_summary()
    assert summary is not None and summary.statistics is not None
    topics = {channel.topic for channel in summary.channels.values()}
    assert {"/cosmos/state", "/cosmos/segment", "/cosmos/event"} <= topics
    assert summary.statistics.message_count == sum(failing_run.log.message_counts.values())


def test_log_has_the_failed_event(failing_run: ProgramRun) -> None:
    """One ``failed`` event, on line 4, with the reason; the statement after it never starts."""
    failed = failing_run.events("failed")
    assert [(e.line, e.reason) for e in failed] == [(FAILING_LINE, "found no contact within 1.5 s")]
    contact_start = failing_run.events("start", FAILING_LINE)
    assert len(contact_start) == 1
    # The statement fails when its 1.5 s are up; the executor then holds the arm for a
    # moment before it logs the event (HOLD_AFTER_FAILURE_S, 0.3 s today).
    assert 1.5 - 0.01 <= failed[0].t - contact_start[0].t <= 1.5 + 0.5
    assert not failing_run.events(line=FAILING_LINE + 1), "the program stops at the failure"


def test_arm_holds_after_the_failure(failing_run: ProgramRun) -> None:
    """After the failure the arm holds a safe pose: it does not move on, nor fall.

    The speed is the tool's travel over 50 ms: the logged velocity on the realistic plant
    is the encoders' observer's, which answers a single count (0.1 mm at the tool) with a
    flicker of up to 8 mm/s."""
    timed_out_t = failing_run.events("start", FAILING_LINE)[0].t + 1.5
    state = failing_run.log.state
    after = state.t >= timed_out_t + 0.1  # 0.1 s to stop from the 20 mm/s approach
    assert np.any(after), "the log ends before the failure"
    t, x = state.t[after], state.x[after, :3]
    window = int(np.searchsorted(t, t[0] + 0.05))
    speed_mps = np.linalg.norm(x[window:] - x[:-window], axis=1) / (t[window:] - t[:-window])
    assert float(speed_mps.max()) < 0.005
    assert float(np.ptp(state.x[after], axis=0).max()) < 1e-3


def test_replay_summary_shows_the_failure(failing_run: ProgramRun) -> None:
    """``cosmos replay LOG`` reads the log (exit 0) and its timeline ends with the failed CONTACT."""
    done = subprocess.run(
        [sys.executable, "-m", "cosmos", "replay", str(failing_run.log.path)],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 0, done.stderr
    rows = [line for line in done.stdout.splitlines() if line.strip().startswith(f"{FAILING_LINE} ")]
    assert len(rows) == 1, done.stdout
    assert "CONTACT UP" in rows[0] and "failed" in rows[0], done.stdout
    assert "found no contact within 1.5 s" in rows[0], done.stdout
