"""Ctrl-C stops a motion and the arm holds; failures, :load and :reset keep the session going."""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from cosmos.repl.app import ReplApp
from cosmos.workcell import fixture_frames
from tests.repl.repl_drive import CTRL_C, CTRL_D, ENTER, Driven, drive

TABLE = fixture_frames()["table"].position  # (3,) m
LONG_MOVE = "MOVE BY (0, 0, -150 mm) SPEED 0.05 m/s"  # 3 s of motion
PROGRAM = "FRAME p = table + (0, 0, 80 mm)\nMOVE TO p SPEED 0.25 m/s\n"
FAILING = "WAIT 0.05 s\nCONTACT UP FORCE 5 N TIMEOUT 0.2 s\n"


def _press_ctrl_c_mid_motion(app: ReplApp) -> None:
    """Send this process a real SIGINT once the long move has run 0.5 s of simulated time."""
    runtime = app.engine.session.runtime

    def wait_then_interrupt() -> None:
        deadline = time.monotonic() + 30.0
        while runtime.time_s < 0.5 and time.monotonic() < deadline:
            time.sleep(0.01)
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=wait_then_interrupt, daemon=True).start()


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> Driven:
    folder = tmp_path_factory.mktemp("repl_interrupt")
    program = folder / "approach.cos"
    program.write_text(PROGRAM)
    failing = folder / "failing.cos"
    failing.write_text(FAILING)
    keys = (
        "MOVE BY (0, 0, -5 mm)" + CTRL_C  # cleared at the prompt, never runs
        + LONG_MOVE + ENTER  # interrupted by SIGINT
        + "WAIT 0.3 s" + ENTER
        + "CONTACT UP FORCE 5 N TIMEOUT 0.3 s" + ENTER  # nothing above: fails
        + "SLIDE +X BY 10 mm" + ENTER  # no contact held after the failure
        + f":load {program}" + ENTER
        + "MOVE TO p + (0, 0, 10 mm)" + ENTER
        + f":load {failing}" + ENTER
        + ":reset" + ENTER
        + ":frames" + ENTER
        + CTRL_D
    )  # fmt: skip
    return drive(folder, keys, _press_ctrl_c_mid_motion)


def test_ctrl_c_at_the_prompt_clears_the_line(session: Driven) -> None:
    assert "MOVE BY (0, 0, -5 mm)" not in session.output
    assert session.status == 0


def test_ctrl_c_mid_motion_stops_the_arm_and_returns_to_the_prompt(session: Driven) -> None:
    out = session.output
    assert "<repl>:1:1: MOVE BY interrupted\n    " + LONG_MOVE + "\n    " + "^" * len(LONG_MOVE) in out
    assert "the arm holds its pose" in out
    stopped = next(e for e in session.log.events if e.kind == "interrupted")
    travelled = session.position_at(0.0)[2] - session.position_at(stopped.t)[2]
    assert 0.01 < travelled < 0.14, travelled


def test_the_arm_holds_where_it_stopped(session: Driven) -> None:
    stopped = next(e for e in session.log.events if e.kind == "interrupted")
    after_wait = session.position_at(session.done_time("WAIT 0.3 s"))
    assert np.linalg.norm(after_wait - session.position_at(stopped.t)) < 5e-3


def test_a_failed_statement_is_reported_and_releases_nothing_held(session: Driven) -> None:
    out = session.output
    assert "<repl>:3:1: CONTACT UP" in out
    assert "SLIDE needs a held contact" in out
    assert "Traceback" not in out


def test_load_runs_a_file_into_the_session_and_keeps_its_names(session: Driven) -> None:
    end = session.position_at(session.done_time("MOVE TO p + (0, 0, 10 mm)"))
    np.testing.assert_allclose(end, TABLE + [0.0, 0.0, 0.090], atol=2e-3)


def test_a_failure_in_a_loaded_file_points_into_the_file(session: Driven) -> None:
    failing = Path(session.app.log_path).parent / "failing.cos"
    expected = (
        f"{failing}:2:1: CONTACT UP found no contact within 0.2 s\n    CONTACT UP FORCE 5 N TIMEOUT 0.2 s\n"
    )
    assert expected in session.output


def test_logged_lines_are_transcript_lines_loaded_files_included(session: Driven) -> None:
    lines = (session.log.source or "").splitlines()
    assert "MOVE TO p SPEED 0.25 m/s" in lines
    for segment in session.log.segments:
        assert lines[segment.line - 1].strip() in (segment.statement, "# " + segment.statement)


def test_reset_puts_the_arm_home_and_forgets_names(session: Driven) -> None:
    np.testing.assert_allclose(session.tool_position, session.position_at(0.0), atol=1e-3)
    frames = session.output.rsplit("the arm is home", 1)[-1]
    assert "\ntable " in frames and "\np " not in frames
    assert "the arm is home" in session.output
    transcript = session.log.source or ""
    assert "# :reset" in transcript and f"# :load {Path(session.app.log_path).parent}" in transcript
    times = session.log.state.t
    assert np.all(np.diff(times) > 0)  # the clock went on through the reset
