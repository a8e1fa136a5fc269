"""/cosmos/state comes at one fixed rate of simulated time for the whole run (interfaces.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from run_support import run_in_process, write_program

from cosmos.runlog.reader import read_log

PROGRAM = "MOVE BY (0, 0, 20 mm)\nWAIT 0.13 s\nMOVE BY (10 mm, 0, 0)\nWAIT 0.07 s\n"


def test_state_samples_are_evenly_spaced_across_segments(tmp_path: Path) -> None:
    run = run_in_process(write_program(tmp_path, "rate", PROGRAM), tmp_path / "rate.mcap")
    assert run.returncode == 0, run.describe()
    record = read_log(tmp_path / "rate.mcap")
    period_s = 1.0 / float(record.metadata["state_hz"])
    steps = np.diff(record.state.t)
    assert len(record.segments) == 4
    assert np.allclose(steps, period_s, atol=1e-6), (steps.min(), steps.max())
