"""INSERT honours its SPEED along the insertion axis (issue 14, item 4), judged from the run's log.

The peg starts 2 mm above the mouth and 2 mm off the hole's axis; the INSERT approaches
with every axis held, lands on the chamfers, then pushes 15 N down with the lateral axes
compliant: where the chamfers give way the push alone would drive the peg in at 55-80
mm/s. The speed along the insertion axis must peak within 10 % of its limit: SPEED's,
or the documented default of 20 mm/s.

The speed is the tool point's travel over five samples of the log's state (20 ms at its
250 Hz). In the bore the peg's steel grazes the walls: each graze is an impulse that shows
in a single 1 ms sample of the velocity (6.1 mm/s once at SPEED 5 while the tool moves
0.001 mm more than at 5 mm/s); the limit is on the tool's motion, which the travel measures.
At SPEED 5 mm/s the joints stick and slip below the friction compensation's ramp: an
integral on the push's speed error wound up meanwhile and overshot by 12 %; it is gone.
Landing 2 mm off the axis, the peg slides down the chamfer: the compliant axes' force loop
carried it down the slope past the cap (5.25-5.65 mm/s at SPEED 5 on the ideal plant, seeds
0-4) until it was dropped while the cap binds (cosmos.osc.unified.speed_limited_push).
While the cap binds, the joints' friction is compensated toward the commanded speed alone
along the push (cosmos.osc.unified.push_commanded_speed): toward the commanded plus the
sensed speed, the friction torque followed the realistic plant's velocity observer's lag
and noise, and the peg rang on the chamfer (SPEED 10 mm/s: 11.65 and 12.4 mm/s, seeds 0, 2).
On the realistic plant the push's cap tracks a speed reference that rises to its aim and
follows the tool while the push is at its force, and the approach runs 3 mm/s under 1.1
SPEED (cosmos.osc.push_speed); seed 1 is the drawn arm that ran the approach fast. It peaked
at 5.80 mm/s at SPEED 5 (a strict xfail) until the scenes' ccd_tolerance went to 1e-8: the
collider's false contact depths on the chamfer were part of the ringing; now 5.30 mm/s.
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
INSERT DOWN DEPTH 27 mm FORCE 15 N COMPLY X Y RX RY{speed} TIMEOUT 20 s
"""
INSERT_LINE = 3
DEFAULT_INSERT_SPEED_MPS = 0.020
"""docs/language.md: the insertion axis "is limited to 20 mm/s unless SPEED says otherwise"."""
WINDOW_TICKS = 5
"""The speed is the travel over this many samples of the log's state divided by their time."""


@pytest.mark.parametrize(
    ("speed_mmps", "ideal", "seed"),
    [
        (None, True, 0),
        (10.0, True, 0),
        (30.0, True, 0),
        (5.0, True, 0),
        (5.0, True, 1),
        (5.0, False, 1),
        (10.0, False, 0),
        (10.0, False, 1),
        (20.0, False, 1),
        (30.0, False, 1),
    ],
)
def test_insert_peaks_within_ten_percent_of_its_speed(
    tmp_path: Path, speed_mmps: float | None, ideal: bool, seed: int
) -> None:
    """The peak downward speed of the INSERT (approach and insertion) within 10 % of the limit,
    the depth reached. Catches the push left uncapped on its force axis (55.6 mm/s at SPEED 10
    mm/s, 80 mm/s in peg_in_hole.cos), an approach at the MOVE's speed, a cap so tight or so stuck
    in joint friction that the peg crawls or jams, the compliant axes carrying the peg down the
    chamfer past the cap (5.65 mm/s at SPEED 5 on the ideal plant, seed 1), and on the realistic
    plant the approach at its SPEED (seed 1's drawn arm ran its eq. 20-21 2.7 mm/s fast: 12.7,
    22.85 and 32.8 mm/s at SPEED 10, 20 and 30; cosmos.osc.push_speed.approach_speed) and the
    push's cap stepped back to its aim after the landing's dip (11.55 mm/s at SPEED 10, seed 0,
    once the approach was slowed; cosmos.osc.push_speed)."""
    clause = "" if speed_mmps is None else f" SPEED {speed_mmps:g} mm/s"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        log = tmp_path / "insert_speed.mcap"
        run = cosmos.run(PROGRAM.format(speed=clause), log=log, ideal=ideal, seed=seed)
    assert run.ok, run.outcome
    limit = DEFAULT_INSERT_SPEED_MPS if speed_mmps is None else speed_mmps * 1e-3
    segments = [s for s in run.segments if s.line == INSERT_LINE]
    assert [s.kind for s in segments] == ["contact_approach", "insert"]
    assert all(s.speed_limit == pytest.approx(limit) for s in segments)
    state = run.record.state
    inserting = state.line == INSERT_LINE
    t, z = state.t[inserting], state.x[inserting, 2]
    down = -(z[WINDOW_TICKS:] - z[:-WINDOW_TICKS]) / (t[WINDOW_TICKS:] - t[:-WINDOW_TICKS])
    assert down.max() <= 1.10 * limit, f"peak {down.max() * 1e3:.2f} mm/s, limit {limit * 1e3:g} mm/s"
    assert np.mean(down > 0.5 * limit) > 0.5, "the peg should travel near its speed, not crawl"
