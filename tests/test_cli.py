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
