import subprocess
import sys


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "cosmos", *args], capture_output=True, text=True, timeout=120
    )


def test_help_lists_every_subcommand() -> None:
    result = run_cli("--help")
    assert result.returncode == 0
    for name in ("run", "check", "repl", "replay", "bench"):
        assert name in result.stdout


def test_missing_program_is_a_usage_error() -> None:
    result = run_cli("check", "no/such/file.cos")
    assert result.returncode == 2
    assert "Traceback" not in result.stderr


def test_a_negative_seed_is_a_usage_error() -> None:
    """Catches `cosmos run --seed -1` ending in numpy's traceback ("expected non-negative
    integer") after the program had been checked and the log opened."""
    from click.testing import CliRunner

    from cosmos.cli import cli

    for command in ("run", "sweep"):
        result = CliRunner().invoke(cli, [command, "programs/hello.cos", "--seed", "-1"])
        assert result.exit_code == 2, result.output
        assert "'--seed': -1 is not in the range x>=0" in result.output
        assert "Traceback" not in result.output


def test_a_file_the_user_cannot_read_is_one_line_naming_it(tmp_path, monkeypatch) -> None:
    """A program the user may not read gave click's three lines ("Usage: ... Error: Invalid
    value for 'PROGRAM': Path ... is not readable.") where a missing one gives one line: every
    command must say it the same way, one line naming the path and the operating system's reason.
    The permission is denied through ``os.access`` and ``os.open`` (the tests may run as root)."""
    import errno
    import os

    from tests.cli_in_process import cosmos_in_process

    program = tmp_path / "locked.cos"
    program.write_text("WAIT 1 s\n")
    locked = {str(program)}
    real_access, real_open = os.access, os.open
    monkeypatch.setattr(
        os, "access", lambda path, mode, **kw: str(path) not in locked and real_access(path, mode)
    )

    def denied_open(path, flags, *args, **kwargs):
        if str(path) in locked:
            raise PermissionError(errno.EACCES, "Permission denied", str(path))
        return real_open(path, flags, *args, **kwargs)

    monkeypatch.setattr(os, "open", denied_open)
    for command in ("check", "run", "sweep"):
        result = cosmos_in_process(command, str(program))
        assert result.returncode == 2, result.stderr
        assert result.stderr == f"cannot read {program}: Permission denied\n", result.stderr
