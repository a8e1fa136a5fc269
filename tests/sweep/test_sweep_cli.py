"""cosmos sweep on the command line: its mistakes (the whole command: test_sweep_resume.py)."""

from __future__ import annotations

from pathlib import Path

from sweep_support import TOUCH_TABLE

from tests.cli_in_process import cosmos_in_process as cosmos_cli


def test_a_bad_vary_is_a_usage_error_without_traceback(tmp_path: Path) -> None:
    """Catches a mistyped parameter starting worker processes or ending in a traceback."""
    result = cosmos_cli(
        "sweep", str(TOUCH_TABLE), "--runs", "2", "--vary", "hole.w=1mm", "--out", str(tmp_path)
    )
    assert result.returncode == 2
    assert "unknown parameter 'hole.w'" in result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "results.jsonl").exists()


def test_cosmos_run_takes_values_not_distributions() -> None:
    """Catches cosmos run --vary drawing a value of its own (the run would not be reproducible)."""
    result = cosmos_cli("run", str(TOUCH_TABLE), "--vary", "table.z=normal(0,1mm)")
    assert result.returncode == 2
    assert "--vary table.z=normal(0,1mm): cosmos run takes one value, not a distribution" in result.stderr
    assert "Traceback" not in result.stderr
