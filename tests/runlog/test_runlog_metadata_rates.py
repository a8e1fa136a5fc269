"""Rates stored in the log's metadata read back exactly (replay --verify re-runs with them)."""

from __future__ import annotations

from pathlib import Path

import pytest

from cosmos.runlog import RunLog, read_log


@pytest.mark.parametrize("servo_hz", [1000.0, 225.0, 333.3333, 1000.0 / 3.0])
def test_rates_round_trip_exactly(tmp_path: Path, servo_hz: float) -> None:
    path = tmp_path / "rates.mcap"
    with RunLog(
        path, program="p.cos", source="", servo_hz=servo_hz, param_hz=100.0, state_hz=250.0, model="m", seed=0
    ):
        pass
    metadata = read_log(path).metadata
    assert float(metadata["servo_hz"]) == servo_hz
    assert metadata["param_hz"] == "100"  # round numbers stay short
