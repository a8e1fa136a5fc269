"""`cosmos check --json` prints JSON on error too, with the error's location."""

import io
import json
from pathlib import Path

from cosmos.commands.check import check_program


def test_check_json_prints_a_program_error_as_json(tmp_path: Path) -> None:
    """Catches --json printing a text diagnostic (or a traceback) that a tool cannot parse,
    or a location that is not where the error is."""
    line = "MOVE TO (0.5, 0, 0.3"
    program = tmp_path / "bad.cos"
    program.write_text(f"WAIT 0.1 s\n{line}\n")
    out = io.StringIO()
    assert check_program(program, as_json=True, fixtures={}, out=out) == 1
    report = json.loads(out.getvalue())
    assert report["ok"] is False
    error = report["error"]
    assert (error["kind"], error["file"], error["line"]) == ("program", str(program), 2)
    assert error["column"] == len(line) + 1  # the end of the line, where ')' is missing
    assert "expected" in error["message"] and line in error["text"]


def test_check_json_prints_an_unreadable_file_as_json(tmp_path: Path) -> None:
    """Catches --json on a missing file printing text, or with the program-error status."""
    out = io.StringIO()
    assert check_program(tmp_path / "missing.cos", as_json=True, out=out) == 2
    report = json.loads(out.getvalue())
    assert report["error"]["kind"] == "usage" and "missing.cos" in report["error"]["message"]
