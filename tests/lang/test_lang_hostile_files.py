"""Program files a user (or an attacker) hands to ``check``, ``run`` and ``:load``.

One reader (``cosmos.lang.read_program``) serves all three. Every hostile case
ends in one line naming the file (or one located ``file:line:col`` error), exit
status 1 or 2, no traceback, and in bounded time.
"""

from __future__ import annotations

import dataclasses
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner
from lang_support import FIXTURES

from cosmos.cli import cli
from cosmos.commands import check as check_command
from cosmos.commands import run as run_command
from cosmos.errors import CosmosError, ProgramError, UsageError
from cosmos.lang import compile_program, read_program
from cosmos.lang.compile.blocks import MAX_EXPANSION_DEPTH
from cosmos.lang.parse.nesting import MAX_BLOCK_DEPTH
from cosmos.lang.parse.source_file import MAX_PROGRAM_BYTES
from cosmos.plan import plan_to_json
from cosmos.repl.engine import read_program_file

PROGRAM = "SPEED 0.2 m/s\nMOVE TO hole + (0, 0, 50 mm)\nCONTACT DOWN FORCE 8 N\nWAIT 1 s\n"


@pytest.fixture(autouse=True)
def test_fixtures(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(check_command, "load_fixtures", lambda: FIXTURES)
    monkeypatch.setattr(run_command, "fixture_frames", lambda: FIXTURES)


def _check_in_process(path: Path, *args: str) -> tuple[int, str, str]:
    """(exit status, stdout, stderr) of ``cosmos check``, errors rendered as ``main`` renders them."""
    result = CliRunner().invoke(cli, ["check", str(path), *args], catch_exceptions=True)
    if isinstance(result.exception, CosmosError):
        status = 2 if isinstance(result.exception, UsageError) else 1
        return status, result.stdout, result.exception.render()
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    return result.exit_code, result.stdout, result.stderr


def _check_process(path: Path) -> subprocess.CompletedProcess[str]:
    """``cosmos check PATH`` in its own process, killed after 60 s (a hang fails the test)."""
    return subprocess.run(
        [sys.executable, "-m", "cosmos", "check", str(path)],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, "PYTHONWARNINGS": "ignore"},
    )


def _special_file(kind: str, tmp_path: Path) -> Path:
    if kind == "fifo":
        path = tmp_path / "pipe.cos"
        os.mkfifo(path)
        return path
    if kind == "directory":
        return tmp_path
    if kind == "missing":
        return tmp_path / "missing.cos"
    return Path("/dev/zero")


@pytest.mark.parametrize(
    ("kind", "reason"),
    [
        ("fifo", "a pipe (FIFO), not a program file"),
        ("dev_zero", "a device, not a program file"),
        ("directory", "a directory, not a program file"),
        ("missing", "No such file or directory"),
    ],
)
def test_a_file_that_is_not_a_regular_file_is_one_line_not_a_hang(
    kind: str, reason: str, tmp_path: Path
) -> None:
    """Catches the reader blocking on a FIFO, reading /dev/zero until memory runs out, or a
    directory or missing file ending in a traceback or click's three-line usage error."""
    if kind == "dev_zero" and not Path("/dev/zero").exists():
        pytest.skip("no /dev/zero here")
    path = _special_file(kind, tmp_path)
    result = _check_process(path)
    assert result.returncode == 2
    assert result.stdout == ""
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and str(path) in lines[0] and reason in lines[0], result.stderr


def test_a_file_over_the_size_cap_is_refused_before_it_is_parsed(tmp_path: Path) -> None:
    """Catches a 50 MB file being read and parsed for minutes: over 1 MB is one line, exit 2."""
    path = tmp_path / "huge.cos"
    path.write_bytes(b"# comment\n" * (MAX_PROGRAM_BYTES // 10 + 1))
    status, out, err = _check_in_process(path)
    assert (status, out) == (2, "")
    assert err == f"{path}: the file is larger than 1 MB; a program is smaller"


def test_binary_data_is_not_read_as_a_program(tmp_path: Path) -> None:
    """Catches /proc/self/environ-like bytes (NULs) reaching the parser, whose error shows the line."""
    path = tmp_path / "environ.cos"
    path.write_bytes(b"SECRET=hunter2\x00HOME=/root\x00")
    with pytest.raises(UsageError) as caught:
        read_program(path)
    assert caught.value.render() == f"{path}: binary data (control characters), not a program file"


@pytest.mark.parametrize("layout", ["lf", "bom", "crlf", "bom_crlf", "cr"])
def test_check_run_and_load_read_bom_and_crlf_alike(layout: str, tmp_path: Path) -> None:
    """Catches a byte-order mark that passes ``check`` and fails ``run``, and CRLF read
    differently by the three commands: each reads the same text and makes the same plan."""
    text = PROGRAM.replace("\n", {"crlf": "\r\n", "bom_crlf": "\r\n", "cr": "\r"}.get(layout, "\n"))
    data = text.encode("utf-8")
    if layout.startswith("bom"):
        data = b"\xef\xbb\xbf" + data
    path = tmp_path / "prog.cos"
    path.write_bytes(data)
    assert read_program(path) == PROGRAM
    assert read_program_file(path) == PROGRAM  # the REPL's :load
    ran = run_command.compile_file(path)  # what `cosmos run` compiles
    status, out, _ = _check_in_process(path, "--json")
    assert status == 0
    expected = json.loads(json.dumps(plan_to_json(compile_program(PROGRAM, str(path), FIXTURES))))
    assert json.loads(out) == expected
    assert json.loads(json.dumps(plan_to_json(ran))) == expected


def test_a_crlf_program_reports_an_error_where_an_lf_one_does(tmp_path: Path) -> None:
    """Catches line numbers shifted by CR LF (a lone CR counted as a line by one reader only)."""
    path = tmp_path / "bad.cos"
    path.write_bytes(b"WAIT 1 s\r\nMOVE TO hoel\r\n")
    status, _, err = _check_in_process(path)
    assert status == 1
    assert err.splitlines()[0].startswith(f"{path}:2:9: unknown name 'hoel'")


def _nested_repeats(depth: int) -> str:
    return "REPEAT 1\n" * depth + "WAIT 1 s\n" + "END\n" * depth


@pytest.mark.parametrize("depth", [330, 360, 400, 500, 5000])
def test_deeply_nested_blocks_are_a_located_error_before_any_recursion(depth: int) -> None:
    """Catches 500 nested REPEATs ending in a RecursionError traceback, and depths 330-400
    blaming 'expressions' that are not there: the error names the block past the limit."""
    with pytest.raises(ProgramError) as caught:
        compile_program(_nested_repeats(depth), "deep.cos", FIXTURES)
    error = caught.value
    assert error.span is not None and (error.span.line, error.span.column) == (MAX_BLOCK_DEPTH + 1, 1)
    assert error.message.startswith(f"blocks nested more than {MAX_BLOCK_DEPTH} deep")
    assert error.render().splitlines()[0].startswith(f"deep.cos:{MAX_BLOCK_DEPTH + 1}:1: blocks nested")


def test_blocks_at_the_nesting_limit_compile() -> None:
    """Catches a limit that refuses what it says it accepts."""
    compiled = compile_program(_nested_repeats(MAX_BLOCK_DEPTH), "deep.cos", FIXTURES)
    assert len(compiled.segments) == 1


def test_nested_repeats_on_one_line_are_counted_too() -> None:
    """Catches the nesting count missing blocks opened after ';'."""
    depth = MAX_BLOCK_DEPTH + 20
    source = "REPEAT 1; " * depth + "WAIT 1 s; " + "END; " * depth
    with pytest.raises(ProgramError, match="blocks nested more than"):
        compile_program(source, "one_line.cos", FIXTURES)


def _chain(length: int) -> str:
    """PROC p1 calls p2 ... calls p{length}, which waits; then p1 is called."""
    procs = [f"PROC p{i}\n  p{i + 1}\nEND\n" for i in range(1, length)]
    return f"PROC p{length}\n  WAIT 1 s\nEND\n" + "".join(reversed(procs)) + "p1\n"


def test_a_chain_of_40_distinct_procedures_is_not_recursion() -> None:
    """Catches a call-depth limit of 32 reported as 'procedures call each other without end'."""
    compiled = compile_program(_chain(40), "chain.cos", FIXTURES)
    assert len(compiled.segments) == 1
    assert "p40 called at line" in compiled.segments[0].context


def test_a_procedure_calling_itself_is_still_recursion() -> None:
    """Catches the recursion check lost when the depth limit was raised."""
    with pytest.raises(ProgramError, match="procedures call each other without end: a -> b -> a"):
        compile_program("PROC a\n  b\nEND\nPROC b\n  a\nEND\na\n", "loop.cos", FIXTURES)


def test_a_chain_longer_than_the_expansion_limit_is_a_located_error() -> None:
    """Catches a long chain of distinct procedures recursing until a RecursionError."""
    length = MAX_EXPANSION_DEPTH + 50
    with pytest.raises(ProgramError) as caught:
        compile_program(_chain(length), "long_chain.cos", FIXTURES)
    message = caught.value.message
    assert f"nest more than {MAX_EXPANSION_DEPTH} deep here" in message
    assert caught.value.span is not None
    # One line of 7 kB named all 150 calls, twice; now the outermost and innermost two.
    rendered = caught.value.render()
    assert len(rendered.splitlines()[0]) < 400 and "... 146 more ..." in rendered, rendered


@pytest.mark.parametrize("digits", ["\uff11\uff12", "\u0661\u0662", "1\uff12"])
def test_digits_outside_ascii_are_an_error_not_a_number(digits: str) -> None:
    """Catches full-width digits read as a number (Python's \\d and float() accept them)."""
    with pytest.raises(ProgramError) as caught:
        compile_program(f"WAIT {digits} s\n", "digits.cos", FIXTURES)
    assert "a digit outside ASCII" in caught.value.message
    assert caught.value.span is not None and caught.value.span.line == 1


@pytest.mark.parametrize("name", ["passwd", "environ.txt"])
def test_load_of_a_file_that_is_not_a_program_shows_none_of_it(name: str, tmp_path: Path) -> None:
    """Catches ``:load /etc/passwd`` printing the file's first line under a caret and
    ``:load /proc/self/environ`` printing the environment."""
    path = tmp_path / name
    if name == "passwd":
        path.write_text("root:x:0:0:root:/root:/bin/bash\nsecret-user:x:1000:1000::/home/s:/bin/sh\n")
    else:
        path.write_bytes(b"API_TOKEN=hunter2\x00HOME=/root\x00")
    with pytest.raises(UsageError) as caught:
        read_program_file(path)
    shown = caught.value.render()
    assert len(shown.splitlines()) == 1 and str(path) in shown and "not a" in shown
    for secret in ("root", "secret-user", "hunter2", "API_TOKEN"):
        assert secret not in shown.replace(str(path), "")


@pytest.mark.parametrize("real", ["/etc/passwd", "/proc/self/environ"])
def test_load_of_system_files_shows_none_of_them(real: str) -> None:
    """The same on the machine's own files, where they exist."""
    path = Path(real)
    if not path.exists():
        pytest.skip(f"no {real} here")
    with pytest.raises(UsageError) as caught:
        read_program_file(path)
    assert caught.value.render().startswith(f"{real}: ")
    assert len(caught.value.render().splitlines()) == 1


def test_load_of_a_cos_file_with_an_error_shows_the_error(tmp_path: Path) -> None:
    """Catches the 'not a program' rule hiding a real program's syntax error."""
    path = tmp_path / "mine.cos"
    path.write_text("MOVE (0.5, 0.1, 0.3)\n")
    with pytest.raises(ProgramError) as caught:
        compile_program(read_program_file(path), str(path), FIXTURES)
    assert caught.value.render().startswith(f"{path}:1:6: expected TO or BY after MOVE")


def _nested_calls(levels: int) -> str:
    """Procedures ``p0`` .. ``p<levels>``, each calling the one below ten times; ``p0`` two MOVEs."""
    text = "PROC p0\n  MOVE BY (0, 0, 1 mm)\n  MOVE BY (0, 0, -1 mm)\nEND\n"
    for level in range(1, levels + 1):
        text += f"PROC p{level}\n" + f"  CALL p{level - 1}\n" * 10 + "END\n"
    return text + f"CALL p{levels}\n"


def test_a_program_past_the_step_limit_is_refused_before_it_is_expanded(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Catches a program of six nested procedures (200000 MOVEs) compiled MOVE by MOVE up to the
    limit before it was refused (17 s on a loaded machine), with a message that said "use fewer
    REPEATs" to a program that has none. The refusal is at the outermost CALL."""
    from cosmos.lang.compile.motion.builder import MotionBuilder

    built = []
    original = MotionBuilder.move
    monkeypatch.setattr(MotionBuilder, "move", lambda self, s: built.append(s) or original(self, s))
    source = _nested_calls(5)
    with pytest.raises(ProgramError) as caught:
        compile_program(source, "expand.cos", FIXTURES)
    assert "expands to more than 100000 steps" in caught.value.message
    assert "procedure calls" in caught.value.message
    assert caught.value.span is not None and caught.value.span.line == len(source.splitlines())
    assert built == []


@pytest.mark.parametrize(
    "source",
    [
        _nested_calls(2),
        "REPEAT 3\n  WAIT 1 ms\n  REPEAT 2\n    MOVE BY (0, 0, 1 mm)\n  END\nEND\n",
        "LET n = 4\nREPEAT n\n  WAIT 1 ms\nEND\n",
        "IF FORCE > 2 N\n  WAIT 1 ms\nELSE\n  WAIT 2 ms\nEND\nWAIT 1 ms\n",
        "PROC a\n  WAIT 1 ms\n  IF FORCE > 2 N\n    a2\n  END\nEND\n"
        "PROC a2\n  WAIT 1 ms\nEND\nREPEAT 5\n  a\nEND\n",
    ],
)
def test_the_step_count_known_before_expanding_never_exceeds_what_is_emitted(source: str) -> None:
    """Catches the early refusal counting more steps than the compiler emits (it would refuse
    a program within the limit): the bound against the compiled plan's own steps, blocks unrolled."""
    from cosmos.lang import ast
    from cosmos.lang.compile.blocks import least_steps
    from cosmos.lang.compile.state import ProcEntry
    from cosmos.lang.parse.parser import parse_program

    compiled = compile_program(source, "count.cos", FIXTURES)
    program = parse_program(source, "count.cos")
    procedures = {s.name.key: ProcEntry(s, source) for s in program.statements if isinstance(s, ast.ProcDef)}

    def emitted(steps: tuple[object, ...]) -> int:
        inner = (
            getattr(step, f.name) for step in steps for f in dataclasses.fields(step) if f.name != "span"
        )
        return len(steps) + sum(
            emitted(v) for v in inner if isinstance(v, tuple) and v and hasattr(v[0], "span")
        )

    least = least_steps(program.statements, procedures)
    assert least <= emitted(compiled.steps)


@pytest.mark.parametrize("before, after", [(10_000, 0), (0, 10_000), (300, 300)])
def test_an_error_on_a_long_line_shows_a_window_with_the_caret_under_the_error(
    before: int, after: int
) -> None:
    """A 10,000-character line was echoed whole in its error (20 kB on the terminal): the error
    must show a window of the line, its cut ends marked, with the caret still under the word."""
    source = f"MOVE BY (0, 0, {'1' * before} mm) FOO # {'x' * after}\n"
    with pytest.raises(ProgramError) as raised:
        compile_program(source, "long.cos")
    head, shown, caret = str(raised.value).split("\n")
    assert head.startswith(f"long.cos:1:{source.index('FOO') + 1}: unexpected 'FOO'")
    assert len(shown) <= 4 + 100 + 6 and len(caret) <= len(shown)
    assert shown[caret.index("^") : caret.index("^") + 3] == "FOO" and caret.strip() == "^^^"
    assert shown.startswith("    ...") == (before > 0) and shown.endswith("...") == (after > 0)
