"""CONTACT's landing on steel (issue 14, item 5), judged from the run's own log at 1 kHz.

The bar (docs/language.md, CONTACT): in the first 0.3 s after the touch the push along the
approach peaks under ``max(1.5 FORCE, FORCE + 5 N)`` at SPEEDs up to 30 mm/s, the tool
stays on the surface, and the approach still lands at its SPEED (the impact is the
controller's to absorb, not a slower approach's). The push is the logged wrench (the
force the tool applies, the wrist sensor's reading, world) projected on the approach
direction, logged at every servo tick: at the default 250 Hz a 5 ms spike can fall between
two samples. The touch is the first push above 0.25 N (five times the sensor's noise) in
the 20 ms before the approach's touch event: the time the tool met the surface, within a
tick or two. While the arm brakes, the sensor also carries the tool's inertia (a 0.65 kg tool
braked at 9 m/s^2 reads 6 N less): the push is judged for a bounce only after its peak.
"""

from __future__ import annotations

import contextlib
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from run_support import BOTH_PLANTS, TABLE_POINT_M, write_program

from cosmos.commands.run import run_program
from cosmos.runlog import read_log
from cosmos.runlog.reader import RunRecord
from cosmos.runtime.rates import Rates

WINDOW_S = 0.3
"""The landing is judged over this time after the touch [s]."""
TOUCH_N = 0.25
"""A logged push above this along the approach is the touch [N]."""
RISE_S = 0.02
"""... looked for over this time before the approach's touch event (at its start the tool's
own inertia may read as much on the sensor) [s]."""
DOWN = np.array([0.0, 0.0, -1.0])


def bar_n(force_n: float) -> float:
    """The documented bound on the landing's peak [N]."""
    return max(1.5 * force_n, force_n + 5.0)


@dataclass(frozen=True)
class Landing:
    """What the log shows of one CONTACT's landing."""

    record: RunRecord
    t: np.ndarray  # (n,) [s], from the touch on, within the window
    push: np.ndarray  # (n,) [N] along the approach
    touch_speed_mps: float  # along the approach, the sample before the touch

    def describe(self) -> str:
        """The first 20 ms of the landing, for a failed assertion."""
        pairs = zip(self.t[:20], self.push[:20], strict=True)
        rows = [f"{(t - self.t[0]) * 1e3:5.1f} ms {p:7.2f} N" for t, p in pairs]
        return "\n".join(rows)


def land(
    tmp_path: Path, source: str, line: int, direction: np.ndarray, ideal: bool, seed: int = 0
) -> Landing:
    """Run ``source`` in-process with the state logged at 1 kHz; the landing of the CONTACT on ``line``."""
    program = write_program(tmp_path, "landing", source)
    log = tmp_path / "landing.mcap"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        code = run_program(program, log, Rates(state_hz=1000.0), seed, ideal=ideal)
    record = read_log(log)
    events = "\n".join(f"{e.t:.3f} {e.kind} line {e.line}: {e.reason}" for e in record.events)
    assert code == 0, events
    state = record.state
    on = state.line == line
    push = state.wrench[:, :3].dot(direction)
    contact = [e.t for e in record.events if e.kind == "contact" and e.line == line]
    assert contact, f"line {line} never touched\n{events}"
    # The first push above TOUCH_N in the last RISE_S before the touch event.
    rising = np.flatnonzero(on & (state.t >= contact[0] - RISE_S) & (push > TOUCH_N))
    first = int(rising[0])
    t0 = state.t[first]
    window = (state.t >= t0) & (state.t <= t0 + WINDOW_S)
    speed = float(state.v[first - 1, :3].dot(direction))
    return Landing(record, state.t[window], push[window], speed)


def table_program(force_n: float, speed_mmps: float) -> str:
    """To 15 mm above the table's work point, then CONTACT DOWN."""
    x, y, z = TABLE_POINT_M * 1e3
    return (
        f"MOVE TO ({x:g} mm, {y:g} mm, {z + 15:g} mm)\n"
        f"CONTACT DOWN FORCE {force_n:g} N SPEED {speed_mmps:g} mm/s TIMEOUT 5 s\n"
        "WAIT 0.3 s\n"
    )


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_light_contact_lands_without_a_spike(tmp_path: Path, ideal: bool) -> None:
    """CONTACT DOWN FORCE 3 N SPEED 30 mm/s: the landing peaks under 8 N, and at its SPEED.

    Catches an approach that runs into the table at full speed and lets the 2 N threshold
    (1.5 N here) switch to force control only after the contact has taken the arm's
    momentum: 10-11 N logged (12 N in MuJoCo's contact) for a 3 N setpoint. Also catches a
    "fix" that lands slower than the program's SPEED: the speed along the approach just
    before the touch is within 10 % of 30 mm/s.
    """
    landing = land(tmp_path, table_program(3.0, 30.0), 2, DOWN, ideal)
    peak = float(landing.push.max())
    assert peak < bar_n(3.0), f"peak {peak:.2f} N for FORCE 3 N\n{landing.describe()}"
    assert landing.touch_speed_mps == pytest.approx(0.030, rel=0.10)


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_landing_keeps_the_tool_on_the_surface(tmp_path: Path, ideal: bool) -> None:
    """After the landing's peak (3 N CONTACT, 30 mm/s) the push never falls to 0 within 0.3 s.

    Catches braking that outlasts the motion and throws the tool back off the table: damping
    the hold at 100-300/s (the realistic plant's velocity observer lags 8 ms) lifted it off for
    10-300 ms, a bounce, and the hold's force loop then landed it a second time.
    """
    landing = land(tmp_path, table_program(3.0, 30.0), 2, DOWN, ideal)
    peak = int(landing.push.argmax())
    lowest = peak + int(landing.push[peak:].argmin())
    assert landing.push[lowest] > 0.0, (
        f"the push fell to {landing.push[lowest]:.2f} N {(landing.t[lowest] - landing.t[0]) * 1e3:.0f} ms "
        f"after the touch\n{landing.describe()}"
    )


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_contact_in_a_turned_task_frame_lands_without_a_spike(tmp_path: Path, ideal: bool) -> None:
    """CONTACT +Z IN a frame turned 45 deg about the downward z, FORCE 5 N SPEED 30 mm/s: under 10 N.

    The approach's axis is the task frame's z (world down) with its x and y turned: catches
    braking or a landing worked out in world axes only (11-13 N logged before the approach
    braked). The hold then settles its force (the contact_hold ends "force settled") within 1 s.
    """
    x, y, z = TABLE_POINT_M * 1e3
    source = (
        f"FRAME turned = ({x:g} mm, {y:g} mm, {z:g} mm) RPY (180 deg, 0, 45 deg)\n"
        f"MOVE TO ({x:g} mm, {y:g} mm, {z + 15:g} mm)\n"
        "CONTACT +Z IN turned FORCE 5 N SPEED 30 mm/s TIMEOUT 5 s\n"
        "WAIT 0.3 s\n"
    )
    landing = land(tmp_path, source, 3, DOWN, ideal)
    peak = float(landing.push.max())
    assert peak < bar_n(5.0), f"peak {peak:.2f} N for FORCE 5 N\n{landing.describe()}"
    assert_settles(landing.record, 3, 1.0)


def assert_settles(record: RunRecord, line: int, within_s: float) -> None:
    """The CONTACT on ``line`` ended "force settled", its contact_hold within ``within_s``."""
    hold = next(s for s in record.segments if s.line == line and s.kind == "contact_hold")
    after = next(s for s in record.segments if s.segment == hold.segment + 1)
    done = [e.reason for e in record.events if e.line == line and e.kind == "done"]
    assert done == ["force settled"], done
    assert after.t - hold.t < within_s, f"the hold took {after.t - hold.t:.2f} s to settle"


def test_light_contact_settles_where_friction_holds_it_short(tmp_path: Path) -> None:
    """Realistic plant, seed 2: CONTACT DOWN FORCE 3 N SPEED 10 mm/s settles within 1 s.

    On that seed's drawn arm the joints' friction holds the 3 N push under 90 % of its goal
    once the ramp is over, and the force integral used to wait for 90 %: the hold ended after
    its 3 s "contact held, force within 0.9 N of its setpoint but not settled". Catches an
    integral that waits for a share of the goal the proportional loop alone cannot reach."""
    landing = land(tmp_path, table_program(3.0, 10.0), 2, DOWN, False, seed=2)
    assert_settles(landing.record, 2, 1.0)
