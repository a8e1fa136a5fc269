"""``cosmos check``: the plan as a table or JSON, exit status, errors and warnings."""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner
from lang_support import FIXTURES

from cosmos.cli import cli
from cosmos.commands import check as check_command
from cosmos.lang import compile_program
from cosmos.plan import plan_to_json

PEG = """\
FRAME above = hole + (2 mm, 0, 80 mm)
SPEED 0.25 m/s
MOVE TO above
CONTACT DOWN FORCE 8 N SPEED 20 mm/s TIMEOUT 5 s
INSERT DOWN DEPTH 25 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 10 s
MOVE BY (0, 0, 100 mm) UNTIL FORCE > 5 N
OBSTACLE post CYLINDER AT (0.4, -0.2, 0) RADIUS 40 mm HEIGHT 0.6 m
"""


@pytest.fixture(autouse=True)
def test_fixtures(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(check_command, "load_fixtures", lambda: FIXTURES)


def run(tmp_path: Path, source: str | bytes, *args: str) -> tuple[int, str, str]:
    path = tmp_path / "prog.cos"
    if isinstance(source, bytes):
        path.write_bytes(source)
    else:
        path.write_text(source)
    result = CliRunner().invoke(cli, ["check", str(path), *args], catch_exceptions=True)
    if result.exception is not None and not isinstance(result.exception, SystemExit):
        # the console script's main() renders CosmosErrors; CliRunner sees them raw
        from cosmos.errors import CosmosError

        assert isinstance(result.exception, CosmosError), repr(result.exception)
        return 1, result.stdout, result.exception.render()
    return result.exit_code, result.stdout, result.stderr


def test_json_plan_has_the_segment_topic_fields(tmp_path: Path) -> None:
    status, out, _ = run(tmp_path, PEG, "--json")
    assert status == 0
    data = json.loads(out)
    segments = [s for s in data["steps"] if s["step"] == "segment"]
    assert [s["kind"] for s in segments] == ["move", "contact_approach", "contact_hold", "insert", "move"]
    fields = {
        "kind",
        "frame",
        "motion_axes",
        "force_setpoint",
        "stiffness",
        "damping",
        "goal",
        "speed_limit",
        "timeout",
        "line",
        "statement",
    }
    for segment in segments:
        assert fields <= set(segment)
        assert len(segment["frame"]) == 4 and all(
            len(segment[f]) == 6 for f in ("motion_axes", "force_setpoint", "stiffness", "damping")
        )
    hold = segments[2]
    assert hold["motion_axes"] == [1, 1, 0, 1, 1, 1]
    assert hold["force_setpoint"] == [0, 0, -8, 0, 0, 0]
    assert hold["line"] == 4 and hold["statement"] == "CONTACT DOWN FORCE 8 N SPEED 20 mm/s TIMEOUT 5 s"
    assert segments[0]["goal"]["type"] == "absolute" and segments[0]["goal"]["orientation"] == [0, 1, 0, 0]
    assert segments[4]["until"] == {
        "quantity": "force",
        "direction": None,
        "op": ">",
        "value": 5.0,
        "text": "FORCE > 5 N",
    }
    assert data["steps"][-1]["step"] == "add_obstacle" and data["steps"][-1]["position"] == [0.4, -0.2, 0.3]


def test_table_lists_every_statement(tmp_path: Path) -> None:
    status, out, _ = run(tmp_path, PEG)
    assert status == 0
    for word in ("MOVE TO above", "contact_hold", "Fz -8 N", "insert", "add cylinder", "X Y RX RY"):
        assert word in out


def test_error_exits_1_with_a_rendered_message(tmp_path: Path) -> None:
    status, _, err = run(tmp_path, "MOVE TO hole\nCONTACT DOWN FORCE 10 mm\n")
    assert status == 1
    assert err.startswith(f"{tmp_path / 'prog.cos'}:2:20: FORCE needs a force")
    assert "^^^^^" in err


def test_warnings_are_printed_and_exit_0(tmp_path: Path) -> None:
    status, _, err = run(tmp_path, "INSERT -Z IN hole DEPTH 5 mm FORCE 5 N\n")
    assert status == 0
    assert "1:8: warning: fixture frames point +Z into their surface" in err


def test_console_script_end_to_end(tmp_path: Path) -> None:
    # The real command line with the real workcell: no traceback, exit 1 on error.
    bad = tmp_path / "bad.cos"
    bad.write_bytes(b"MOVE TO hole\n\xff\xfe garbage\n")
    result = subprocess.run(
        [sys.executable, "-m", "cosmos", "check", str(bad)], capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 1
    assert "Traceback" not in result.stderr
    assert f"{bad}:2:1: the program is not UTF-8 text" in result.stderr
    good = tmp_path / "good.cos"
    good.write_text(PEG)
    result = subprocess.run(
        [sys.executable, "-m", "cosmos", "check", str(good), "--json"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["steps"][0]["kind"] == "move"


LONG = "SPEED 0.2 m/s\n" + "MOVE TO hole + (0, 0, 50 mm)\nWAIT 0.5 s\n" * 60  # 120 steps


def test_a_plan_longer_than_a_screen_prints_a_summary_in_plain_lines(tmp_path: Path) -> None:
    """Catches a long plan drawn as a rich table row by row (31 of 33 s of a 10,000-line check)."""
    status, out, _ = run(tmp_path, LONG)
    assert status == 0
    lines = out.splitlines()
    assert lines[0] == f"{tmp_path / 'prog.cos'}: 120 segments, 120 steps (move 60, wait 60)"
    assert len(lines) == 1 + check_command.SUMMARY_STEPS + 1
    assert lines[-1] == "... 100 more steps; cosmos check --full prints every one"
    assert "│" not in out  # no table
    assert lines[1].split()[:4] == ["0", "2", "move", "MOVE"]


def test_full_prints_one_plain_line_per_step(tmp_path: Path) -> None:
    """Catches --full dropping steps or a step spread over several lines."""
    status, out, _ = run(tmp_path, LONG, "--full")
    assert status == 0
    lines = out.splitlines()
    assert len(lines) == 1 + 120
    assert [line.split()[0] for line in lines[1:]] == [str(i) for i in range(120)]
    assert all(" wait " in line for line in lines[2::2])


def test_json_written_step_by_step_is_the_plan_as_json(tmp_path: Path) -> None:
    """Catches the streamed JSON drifting from plan_to_json (a key lost, a step out of order)."""
    status, out, _ = run(tmp_path, LONG + "OBSTACLE ball SPHERE AT (0.4, 0.2, 0.5) RADIUS 50 mm\n", "--json")
    assert status == 0
    compiled = check_command.compile_program(
        LONG + "OBSTACLE ball SPHERE AT (0.4, 0.2, 0.5) RADIUS 50 mm\n", str(tmp_path / "prog.cos"), FIXTURES
    )
    assert json.loads(out) == json.loads(json.dumps(plan_to_json(compiled)))


def test_warnings_past_twenty_are_counted_not_printed_unless_full(tmp_path: Path) -> None:
    """Catches 10,000 warnings each rendered from the whole source (quadratic: seconds of printing)."""
    source = "MOVE BY (0, 0, 0)\n" * 30
    status, _, err = run(tmp_path, source)
    assert status == 0
    assert err.count("warning: MOVE BY (0, 0, 0) goes nowhere") == check_command.SUMMARY_WARNINGS
    assert err.splitlines()[-1] == "... 10 more warnings; cosmos check --full prints every one"
    status, _, err = run(tmp_path, source, "--full")
    assert err.count("warning: MOVE BY (0, 0, 0) goes nowhere") == 30
    assert "more warnings" not in err


BRANCHES = """\
MOVE TO table + (0, 0, 50 mm)
IF FORCE Z < -5 N
  MOVE BY (0, 0, 20 mm)
ELSE
  TRY
    INSERT DOWN DEPTH 5 mm FORCE 5 N
  ON FAIL
    MOVE BY (0, 0, 10 mm)
    RETRY 2
  END
END
"""


def test_check_prints_every_branch_indented_under_its_decision(tmp_path: Path) -> None:
    """The listing shows each branch's steps under their IF, ELSE, TRY and ON FAIL, one level
    deeper each; the table has a row for each; the JSON nests them. Catches a branch left out."""
    buffer = io.StringIO()
    check_command.write_plan_lines(compile_program(BRANCHES, "b.cos", FIXTURES), buffer, True)
    listing = buffer.getvalue().splitlines()[1:]
    statements = [line[33:].split("  |")[0] for line in listing]  # after index, line and kind
    assert statements == [
        "MOVE TO table + (0, 0, 50 mm)",
        "IF FORCE Z < -5 N",
        "  MOVE BY (0, 0, 20 mm)",
        "ELSE",
        "  TRY",
        "    INSERT DOWN DEPTH 5 mm FORCE 5 N",  # its approach (no contact is held) ...
        "    INSERT DOWN DEPTH 5 mm FORCE 5 N",  # ... and the insertion
        "  ON FAIL",
        "    MOVE BY (0, 0, 10 mm)",
        "    RETRY 2",
    ], listing
    status, out, _ = run(tmp_path, BRANCHES)
    assert status == 0
    # (the table wraps its statement column: "IF FORCE Z < -5" then "N" below it)
    for word in ("IF FORCE Z < -5", "ELSE", "TRY", "ON FAIL", "RETRY 2", "if", "else", "try", "retry"):
        assert word in out
    status, out, _ = run(tmp_path, BRANCHES, "--json")
    step = json.loads(out)["steps"][1]
    assert step["step"] == "if" and step["else"][0]["step"] == "try"
    assert step["else"][0]["on_fail"][1] == {
        "step": "retry",
        "line": 9,
        "statement": "RETRY 2",
        "context": "",
        "times": 2,
    }
