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
