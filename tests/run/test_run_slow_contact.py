"""A slow CONTACT starts from rest and cruises at its SPEED on the realistic plant (issue 14, item 4).

On the realistic PUMA the gripper's ``CONTACT DOWN FORCE 5 N SPEED 5 mm/s`` from 20 mm above the
table never moved on seeds 0, 2-5 ("found no contact within 8 s"; at 3 mm/s on seeds 0-5), the
ideal plant touching at its SPEED: eq. 20's proportional pull at a few mm/s (``kv V``, 8 N at 5
mm/s along the approach) is below the joints' static friction the controller's model does not
hold, and the cruise's integral grew only once the tool moved (cosmos.osc.cruise_speed). Judged
from the run's own log: the approach's median speed over 100 ms windows, from 0.5 s after it
starts to the touch, within 10 % of SPEED; the tool touches, the landing's logged push in the
first 0.3 s after the touch under docs/language.md's bar ``max(1.5 f, f + 5 N)``, and the hold
settles at its FORCE (the run succeeds).
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

import cosmos

PROGRAM = """\
TOOL GRIPPER
MOVE TO table + (0, 0, 20 mm)
CONTACT DOWN FORCE {force} N SPEED {speed} mm/s TIMEOUT 8 s
"""
CONTACT_LINE = 3
WINDOW_TICKS = 25
"""The speed is the travel over this many samples of the log's state (100 ms at 250 Hz)."""
TOUCH_N = 2.0
"""docs/language.md: the approach is done once the push along it exceeds 2 N (FORCE 5 N)."""


@pytest.mark.parametrize(("speed_mmps", "seed"), [(5.0, 0), (3.0, 2)])
def test_a_slow_gripper_contact_starts_from_rest_and_lands(
    tmp_path: Path, speed_mmps: float, seed: int
) -> None:
    """Catches the slow CONTACT that stood still on the realistic plant (seed 0 at 5 mm/s, seed 2
    at 3 mm/s: "found no contact within 8 s", the tool 0.00 mm/s), and one that starts but lands
    harder than the documented bar."""
    force_n = 5.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(
            PROGRAM.format(force=force_n, speed=speed_mmps), log=tmp_path / "slow.mcap", seed=seed
        )
    assert run.ok, run.outcome
    state = run.record.state
    approach = [s.segment for s in run.segments if s.line == CONTACT_LINE and s.kind == "contact_approach"]
    assert approach, "no contact_approach segment on the CONTACT's line"
    on = np.isin(state.segment, approach) & (state.line == CONTACT_LINE)
    t, x = state.t[on], state.x[on]
    assert t[-1] - t[0] > 1.0, f"the approach lasted {t[-1] - t[0]:.2f} s: nothing to judge"
    travel = np.linalg.norm(x[WINDOW_TICKS:] - x[:-WINDOW_TICKS], axis=1)
    speeds = travel / (t[WINDOW_TICKS:] - t[:-WINDOW_TICKS])
    judged = t[WINDOW_TICKS:] - t[0] > 0.5
    median = float(np.median(speeds[judged])) * 1e3
    assert abs(median - speed_mmps) <= 0.1 * speed_mmps, f"approach median {median:.2f} mm/s at {speed_mmps}"
    line = state.line == CONTACT_LINE
    push = -state.wrench[line, 2]  # the push along DOWN, world z
    tt = state.t[line]
    touch = int(np.argmax(push > TOUCH_N))
    assert push[touch] > TOUCH_N, "the tool never touched"
    window = (tt >= tt[touch]) & (tt <= tt[touch] + 0.3)
    peak = float(push[window].max())
    assert peak < max(1.5 * force_n, force_n + 5.0), f"landed at {peak:.2f} N"
