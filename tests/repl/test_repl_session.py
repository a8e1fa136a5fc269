"""A whole typed session on the live arm: motion, contact held, frames, errors, commands, blocks."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from cosmos.workcell import fixture_frames
from tests.repl.repl_drive import CTRL_D, ENTER, Driven, drive

TABLE = fixture_frames()["table"].position  # (3,) m, the table top's work point

KEYS = (
    "MOVE BY (0, 0, -20 mm)" + ENTER
    + "FRAME above = table + (0, 0, 30 mm)" + ENTER
    + "MOVE TO above SPEED 0.25 m/s" + ENTER
    + "CONTACT DOWN FORCE 5 N SPEED 40 mm/s" + ENTER
    + "WAIT 0.3 s" + ENTER
    + ":state" + ENTER
    + "MOVE BY (0, 0, 1 mx)" + ENTER
    + ":frames" + ENTER
    + "PROC up" + ENTER
    + "MOVE BY (0, 0, 15 mm)" + ENTER
    + "END" + ENTER
    + "up" + ENTER
    + "IF FORCE < 3 N" + ENTER
    + "WAIT 0.1 s" + ENTER
    + "END" + ENTER
    + "help" + ENTER
    + CTRL_D
)  # fmt: skip


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> Driven:
    return drive(tmp_path_factory.mktemp("repl"), KEYS)


def test_session_ends_cleanly_and_prints_its_log(session: Driven) -> None:
    assert session.status == 0
    assert f"log: {session.app.log_path}" in session.output
    assert Path(session.app.log_path).is_file()
    assert not session.log.truncated


def test_move_by_moves_the_tool_down(session: Driven) -> None:
    start = session.position_at(0.0)
    end = session.position_at(session.done_time("MOVE BY (0, 0, -20 mm)"))
    np.testing.assert_allclose(end - start, [0.0, 0.0, -0.020], atol=1.5e-3)


def test_move_to_a_frame_defined_in_the_session(session: Driven) -> None:
    assert "above = (600, -150, 230) mm RPY (180, 0, 0) deg" in session.output
    end = session.position_at(session.done_time("MOVE TO above SPEED 0.25 m/s"))
    np.testing.assert_allclose(end, TABLE + [0.0, 0.0, 0.030], atol=1.5e-3)


def test_contact_is_held_through_wait(session: Driven) -> None:
    log = session.log
    end = session.done_time("WAIT 0.3 s")
    during = (log.state.t > end - 0.25) & (log.state.t <= end)
    force_z = log.state.wrench[during, 2]  # force the tool applies, world z
    assert np.all(np.abs(force_z + 5.0) < 1.0), force_z
    assert np.all(np.abs(log.state.x[during, 2] - TABLE[2]) < 3e-3)


def test_state_reports_the_force_controlled_axis(session: Driven) -> None:
    out = session.output
    assert "mode     force Z" in out
    assert "contact  5 N along (0, 0, -1)" in out
    assert "joints   (" in out and "tool     (" in out and "force    (" in out


def test_syntax_error_is_shown_with_a_caret_and_the_session_goes_on(session: Driven) -> None:
    out = session.output
    assert "<repl>:7:18: 'mx' is not a unit" in out
    assert "    MOVE BY (0, 0, 1 mx)\n                     ^^\n" in out
    assert "Traceback" not in out
    assert "ok  MOVE BY (0, 0, 15 mm) (PROC up called at line 12)" in out


def test_a_block_decided_on_the_arm_says_what_it_read_and_ran(session: Driven) -> None:
    """Catches an IF typed at the prompt that ran its branch and printed nothing: neither the
    force it read nor the WAIT it ran (statements inside IF, WHILE and TRY were silent)."""
    read = re.search(r"^IF FORCE < 3 N: read (\d+\.\d\d) N; holds: runs the IF branch", session.output, re.M)
    assert read, session.output
    assert float(read[1]) < 1.0  # the tool in free air, lifted by PROC up
    assert re.search(r"^ok  WAIT 0\.1 s$", session.output, re.M), session.output


def test_help_typed_without_its_colon_is_the_help(session: Driven) -> None:
    """Catches 'help' typed bare (as in a shell or Python) answered "unknown procedure 'help'"
    with a caret under it: it prints :help's list of commands."""
    assert "unknown procedure 'help'" not in session.output
    assert ":help" in session.output and ":quit" in session.output and ":frames" in session.output


def test_a_procedure_named_help_is_called_not_the_command(tmp_path: Path) -> None:
    """Catches the bare word taken from a program that defines it: ``PROC help`` then ``help``
    runs the procedure (it moves the tool up 10 mm)."""
    keys = "PROC help" + ENTER + "MOVE BY (0, 0, 10 mm)" + ENTER + "END" + ENTER + "help" + ENTER + CTRL_D
    driven = drive(tmp_path, keys)
    assert "ok  MOVE BY (0, 0, 10 mm)" in driven.output
    assert "PROC help defined (1 statement)" in driven.output


def test_frames_lists_fixtures_and_session_frames(session: Driven) -> None:
    out = session.output
    for name in ("world", "table", "hole", "slope"):
        assert re.search(rf"^{name} +\(.*\[fixture\]$", out, re.MULTILINE), name
    assert "above  (600, -150, 230) mm RPY (180, 0, 0) deg  [FRAME at <repl>:2]" in out


def test_multi_line_proc_is_defined_then_called(session: Driven) -> None:
    assert "PROC up defined (1 statement)" in session.output
    np.testing.assert_allclose(session.tool_position[2], TABLE[2] + 0.015, atol=2e-3)


def test_log_holds_the_transcript_with_matching_lines(session: Driven) -> None:
    source = session.log.source
    assert source is not None
    lines = source.splitlines()
    assert lines[0] == "MOVE BY (0, 0, -20 mm)"
    assert lines[5] == "# :state"
    assert lines[6] == "# ! MOVE BY (0, 0, 1 mx)"
    for segment in session.log.segments:  # each logged line number points at its statement
        assert lines[segment.line - 1].strip() == segment.statement
