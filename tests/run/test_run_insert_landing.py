"""An INSERT's landing on the hole's steel chamfer (issue 14, item 5: impacts are the controller's job).

The INSERT's approach brakes from the first push it feels, as a CONTACT's does
(:func:`cosmos.osc.contact.touch_braking`, ``ServoSetpoint.touch_braking``). Judged from the
run's log against the CONTACT's documented bound on a landing's peak (docs/language.md):
``max(1.5 FORCE, FORCE + 5 N)``, 22.5 N for FORCE 15 N.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import cosmos

PROGRAM = """\
SPEED 0.25 m/s
MOVE TO hole + (2 mm, 0, 2 mm)
INSERT DOWN DEPTH 27 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 20 s
"""
INSERT_LINE = 3
FORCE_N = 15.0
WINDOW_S = 0.05
"""The landing is judged over this time after the approach's touch [s]."""


@pytest.mark.parametrize(("ideal", "seed"), [(True, 0), (False, 1)])
def test_insert_landing_peak_within_the_contact_bound(tmp_path: Path, ideal: bool, seed: int) -> None:
    """The wrist's peak within 50 ms of the touch under max(1.5 f, f + 5 N), the depth reached.
    Catches the INSERT's approach left unbraked (it landed on the chamfer at its SPEED, 19 mm/s:
    33.5 N on the ideal plant, 35.5 N on the realistic plant's seed 1, at the default 20 mm/s)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(PROGRAM, log=tmp_path / "insert_landing.mcap", ideal=ideal, seed=seed)
    assert run.ok, run.outcome
    segments = [s for s in run.segments if s.line == INSERT_LINE]
    assert [s.kind for s in segments] == ["contact_approach", "insert"]
    touch = segments[1].t
    state = run.record.state
    window = (state.t >= touch - 0.01) & (state.t <= touch + WINDOW_S)
    peak = float(np.linalg.norm(state.wrench[window, :3], axis=1).max())
    assert peak > 0.5 * FORCE_N, f"no landing seen ({peak:.1f} N)"
    bound = max(1.5 * FORCE_N, FORCE_N + 5.0)
    assert peak <= bound, f"landing peaked at {peak:.1f} N for FORCE {FORCE_N:g} N"
