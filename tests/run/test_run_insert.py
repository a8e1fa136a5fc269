"""Force control inserts where position control jams (issue 19, item 2: the seed's point).

The fit is realistic (cosmos/models/puma560/README.md, "Hole"): a 20 mm H11/c11
clearance fit, 0.24 mm diametral clearance, the hole's mouth chamfered 1 mm x 45 deg
and the peg's flat end 1.5 mm x 45 deg. The chamfers lead the peg in while its end's
flat lands inside the mouth: from up to 0.12 + 1 + 1.5 = 2.62 mm off the hole's axis.

Each run is one short program through :func:`cosmos.run` with its own noise seed: from
2 mm above the mouth, ``INSERT DOWN DEPTH 27 mm`` (25 mm into the hole), the start 2 mm
off the axis in a seeded direction. Judged on the run's log against the hole's mouth as
documented (run_support):

* ``COMPLY X Y RX RY`` (zero force across the hole): ten of ten reach 25 mm, the tip
  on the hole's axis;
* ``COMPLY NONE`` (position control across it): at least nine of ten jam at the mouth;
* 8 mm off, beyond the chamfers, both jam on the fixture's flat top (what SEARCH is for:
  tests/run/test_run_search.py).

Measured (15 N push, 20 mm/s): the compliant peg reaches its depth in 1.3-1.6 s; the
stiff one stops 0.7-1.5 mm below the mouth, its chamfer wedged on the hole's.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from run_support import HOLE_MOUTH_M

import cosmos

SEED = 20261124
RUNS = 10
OFFSET_M = 0.002
"""Lateral error of the start, within the chamfers' reach [m]."""
BEYOND_M = 0.008
"""Lateral error beyond the chamfers: the peg's flat end lands on the fixture's top [m]."""
INSERTED_M = 0.025
"""How far into the hole (below the mouth) the tip must get [m]."""
GOAL_TOLERANCE_M = 1e-3
"""The MOVE before the INSERT arrives within 1 mm of its goal (docs/language.md, Defaults)."""
ON_AXIS_M = 0.5e-3
"""Inserted, the tip is this close to the hole's axis: the radial clearance is 0.12 mm, the
polygon's corners 0.2 mm further; more means the peg is not in the bore [m]."""
AT_MOUTH_M = 0.005
"""A jammed peg has not gone deeper than this below the mouth [m] (its chamfer is 1.5 mm)."""
INSERT_LINE = 4
"""The INSERT's line in :func:`program`."""
HELD_M = 0.3e-3
"""While the INSERT approaches (every axis held) the tool stays this close to its start
across the insertion, on the ideal plant [m]: measured under 0.06 mm; free, 1.6 mm."""


@dataclass(frozen=True)
class Insertion:
    """What one INSERT statement did, read from the run's log."""

    outcome: str  # "done" or "failed" (the INSERT's closing event)
    reason: str
    deepest_m: float  # deepest tip position below the mouth
    off_axis_m: float  # the tip's distance from the hole's axis at the end
    approach_drift_m: float  # lateral motion of the tip while the INSERT approached

    def line(self) -> str:
        return (
            f"{self.outcome} ({self.reason}); deepest {self.deepest_m * 1e3:.1f} mm, "
            f"{self.off_axis_m * 1e3:.2f} mm off the axis, "
            f"approach drift {self.approach_drift_m * 1e3:.2f} mm"
        )


def directions() -> np.ndarray:
    """Ten seeded directions of the lateral error, world x-y [rad]."""
    return np.random.default_rng(SEED).uniform(0.0, 2.0 * np.pi, RUNS)


def program(offset_m: float, angle: float, comply: str, robot: str = "") -> str:
    """From home to 2 mm above the mouth, ``offset_m`` off the axis towards ``angle``, and INSERT
    (its line is :data:`INSERT_LINE`, after a ``ROBOT robot`` line if one is given)."""
    dx, dy = 1e3 * offset_m * np.cos(angle), 1e3 * offset_m * np.sin(angle)
    return (
        (f"ROBOT {robot}\n" if robot else "# the default arm\n") + "SPEED 0.25 m/s\n"
        f"MOVE TO hole + ({dx:.3f} mm, {dy:.3f} mm, 2 mm)\n"
        f"INSERT DOWN DEPTH 27 mm FORCE 15 N COMPLY {comply} TIMEOUT 10 s\n"
    )


def insert(
    tmp_path: Path,
    offset_m: float,
    angle: float,
    comply: str,
    seed: int,
    robot: str = "",
    ideal: bool = False,
) -> Insertion:
    """Run one insertion (noise seed ``seed``) and judge it from the log."""
    source = program(offset_m, angle, comply, robot)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(source, seed=seed, log=tmp_path / f"insert-{seed}.mcap", ideal=ideal)
    closing = [e for e in run.events if e.line == INSERT_LINE and e.kind in ("done", "failed")]
    state = run.record.state
    inserting = state.line == INSERT_LINE
    tip = state.x[inserting]
    approach = [s.segment for s in run.segments if s.line == INSERT_LINE and s.kind == "contact_approach"]
    held = tip[np.isin(state.segment[inserting], approach)]
    return Insertion(
        outcome=closing[0].kind if closing else "missing",
        reason=closing[0].reason if closing else "",
        deepest_m=float(HOLE_MOUTH_M[2] - tip[:, 2].min()),
        off_axis_m=float(np.linalg.norm(tip[-1, :2] - HOLE_MOUTH_M[:2])),
        approach_drift_m=float(np.linalg.norm(held[:, :2] - held[0, :2], axis=1).max()),
    )


def report(insertions: list[Insertion]) -> str:
    return "\n".join(f"  insertion {i}: {r.line()}" for i, r in enumerate(insertions))


@pytest.fixture(scope="module")
def compliant(tmp_path_factory: pytest.TempPathFactory) -> list[Insertion]:
    directory = tmp_path_factory.mktemp("compliant")
    return [insert(directory, OFFSET_M, a, "X Y RX RY", seed) for seed, a in enumerate(directions())]


@pytest.fixture(scope="module")
def stiff(tmp_path_factory: pytest.TempPathFactory) -> list[Insertion]:
    directory = tmp_path_factory.mktemp("stiff")
    return [insert(directory, OFFSET_M, a, "NONE", seed) for seed, a in enumerate(directions())]


def test_directions_go_round_the_hole() -> None:
    """The ten errors point all round the hole: every quadrant has one. Catches a test that
    only tries the side where the arm's own drift would help the peg in."""
    quadrants = {int(a // (np.pi / 2)) for a in directions()}
    assert quadrants == {0, 1, 2, 3}


def test_compliant_insertion_from_2_mm_succeeds_ten_of_ten(compliant: list[Insertion]) -> None:
    """Each compliant INSERT ends done with the tip 25 mm into the hole and on its axis.
    Catches a hole or peg that stops a compliant part (a chamfer too small for 2 mm, a
    contact that locks it), and an INSERT that reports done short of its depth."""
    summary = report(compliant)
    for r in compliant:
        assert r.outcome == "done" and "reached" in r.reason, summary
        assert r.deepest_m >= INSERTED_M - GOAL_TOLERANCE_M, summary
        assert r.off_axis_m <= ON_AXIS_M, summary


def test_insert_holds_its_axes_until_it_touches(tmp_path: Path) -> None:
    """Without a held contact the INSERT approaches with every axis held: the tip moves
    straight down to the chamfer (on the ideal plant; the realistic one's friction error moves
    a held tool up to 1.5 mm there). Catches zero-force axes left free in free space (the
    joints' friction pushed the tip 1.6 mm sideways in the 2 mm above the mouth, off the
    chamfer, and 7 of 10 of these insertions jammed)."""
    held = [
        insert(tmp_path, OFFSET_M, a, "X Y RX RY", seed, ideal=True)
        for seed, a in enumerate(directions()[:3])
    ]
    assert max(r.approach_drift_m for r in held) <= HELD_M, report(held)


def test_stiff_insertion_from_2_mm_jams_nine_of_ten(stiff: list[Insertion]) -> None:
    """COMPLY NONE: the lateral axes hold the start, 2 mm off, so the chamfers wedge: at
    least nine of ten jam at the mouth. Catches a fit so loose (or a contact so soft) that
    position control inserts too: then the test above would not show the seed's point."""
    jammed = [r for r in stiff if r.outcome == "failed" and "jammed" in r.reason and r.deepest_m < AT_MOUTH_M]
    assert len(jammed) >= 9, report(stiff)


@pytest.mark.parametrize("comply", ["X Y RX RY", "NONE"])
def test_both_jam_beyond_the_chamfers(tmp_path: Path, comply: str) -> None:
    """8 mm off, the peg's flat end lands on the fixture's top: compliant or not, the INSERT
    jams there (a search finds the hole: tests/run/test_run_search.py). Catches an INSERT
    that reports success off the hole, and a top face that lets the peg sink in."""
    r = insert(tmp_path, BEYOND_M, float(directions()[0]), comply, 0)
    assert r.outcome == "failed" and "jammed" in r.reason, r.line()
    assert r.deepest_m < AT_MOUTH_M, r.line()


def test_an_insert_that_meets_nothing_fails_at_its_depth(tmp_path: Path) -> None:
    """In free space the approach goes the whole DEPTH, at its speed, and the INSERT fails there:
    nothing was inserted (tests/run/test_run_insert_air.py). Catches an approach aimed exactly at
    DEPTH, which the position servo nears and never quite reaches (then it timed out, "found no
    contact within 10 s"), and a free-space INSERT reported "depth 20.0 mm reached"."""
    source = (
        "SPEED 0.25 m/s\nMOVE TO hole + (80 mm, 0, 40 mm)\nINSERT DOWN DEPTH 20 mm FORCE 10 N TIMEOUT 5 s\n"
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", cosmos.CosmosWarning)
        run = cosmos.run(source, log=tmp_path / "free.mcap")
    assert not run.ok and run.outcome is not None
    assert "went its DEPTH of 20.0 mm touching nothing" in run.outcome.reason, run.outcome.reason
    state = run.record.state
    inserting = state.line == 3
    travelled = state.x[inserting][0, 2] - state.x[inserting][-1, 2]
    assert travelled == pytest.approx(0.020, abs=0.5e-3)
    assert state.t[inserting][-1] - state.t[inserting][0] < 2.0  # 20 mm at 20 mm/s, and its ramps
