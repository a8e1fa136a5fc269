"""A CONTACT's approach and hold, and an INSERT's touch: compiled judges against their Python (issue 20).

The approach's touch and stall, the hold's lost push, lost contact and settling, and an INSERT's
touch are each one compiled call a tick now (cosmos.execution.approach_stall,
cosmos.execution.lost_push, cosmos.execution.touch_push). Their Python as it was
(contact_judges_before.py) must give the same outcome, reason and all, at every tick of real runs
on both arms and of made-up ticks that reach every ending: the same judgement at every tick is
the same run.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from contact_judges_before import Approach, Hold, InsertTouch
from run_support import run_in_process, write_program

from cosmos.execution.monitor import Outcome, SegmentMonitor, Snapshot, Verdict
from cosmos.lang import compile_program
from cosmos.plan import ContactTouch, DepthReached, ForceSettled
from cosmos.workcell import fixture_frames

Judged = list[tuple[str, float, Outcome | None, Outcome | None]]


def _compared(monkeypatch: pytest.MonkeyPatch) -> Judged:
    """Each tick a CONTACT's approach or hold, or an INSERT's touch, judged: (kind, t, compiled, before)."""
    judged: Judged = []
    completion_judge = SegmentMonitor._completion_judge

    def both(self: SegmentMonitor, completion: object) -> Any:
        compiled = completion_judge(self, completion)
        if isinstance(completion, DepthReached) and completion.touch_n is not None:
            touched, before = self._insert_touched, InsertTouch(self, completion)
            listing = self._insert

            def insert_touched(table: np.ndarray, t_s: float) -> bool:
                found, expected = touched(table, t_s), before(listing.snapshot)
                outcome = Outcome(Verdict.DONE, f"touched: {listing.state[-1]:.2f} N", touched=True)
                judged.append(("insert", t_s, outcome if found else None, expected))
                return bool(found)

            self._insert_touched = insert_touched
            return compiled
        if not isinstance(completion, ContactTouch | ForceSettled):
            return compiled
        kind, before = (
            ("approach", Approach(self, completion))
            if isinstance(completion, ContactTouch)
            else ("hold", Hold(self, completion))
        )

        def judge(snap: Snapshot) -> Outcome | None:
            expected, outcome = before(snap), compiled(snap)
            judged.append((kind, snap.t_s, outcome, expected))
            return outcome

        return judge

    monkeypatch.setattr(SegmentMonitor, "_completion_judge", both)
    return judged


PUMA_CONTACTS = """\
SPEED 0.2 m/s
MOVE TO table + (-20 mm, 0, 20 mm)
CONTACT DOWN FORCE 5 N SPEED 20 mm/s TIMEOUT 5 s
MOVE BY (0, 0, 30 mm)
CONTACT DOWN FORCE 8 N SPEED 60 mm/s
MOVE BY (10 mm, 0, 20 mm)
CONTACT DOWN FORCE 4 N SPEED 10 mm/s UNTIL FORCE > 3 N TIMEOUT 5 s
MOVE BY (0, 0, 40 mm)
CONTACT UP FORCE 5 N SPEED 20 mm/s TIMEOUT 0.6 s
"""
PANDA_CONTACTS = """\
ROBOT panda
MOVE TO hole + (20 mm, 0, 12 mm) SPEED 0.15 m/s
CONTACT DOWN FORCE 6 N SPEED 50 mm/s TIMEOUT 5 s
MOVE BY (0, 0, 10 mm)
CONTACT DOWN FORCE 6 N SPEED 8 mm/s TIMEOUT 20 s
MOVE TO hole + (20 mm, 0, 6 mm)
INSERT DOWN DEPTH 25 mm FORCE 12 N COMPLY X Y RX RY SPEED 40 mm/s TIMEOUT 10 s
"""


@pytest.mark.parametrize("source", [PUMA_CONTACTS, PANDA_CONTACTS], ids=["puma", "panda"])
def test_the_compiled_judges_judge_as_their_python_did_at_every_tick_of_real_contacts(
    source: str, tmp_path: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Catches the compiled judges parting from their Python at any tick: the touch's window of
    speeds or pushes kept a tick too long or short (a fast approach's tool inertia), the travel
    counted from the statement's start, a stall's clock restarted, the TIMEOUT's deadline judged
    under an UNTIL or not at all, the hold's mark or its settling kept when the push ran on, a
    force axis left out, or the snapshot's arrays read at a stale address. Each changes the tick a
    contact ends at, or its reason."""
    judged = _compared(monkeypatch)
    run = run_in_process(write_program(tmp_path, "contacts", source), tmp_path / "contacts.mcap")
    assert [(kind, t) for kind, t, outcome, expected in judged if outcome != expected] == []
    endings = [(kind, outcome.reason) for kind, _, outcome, _ in judged if outcome is not None]
    kinds = {kind for kind, _ in endings}
    assert len(judged) > 1500 and kinds >= {"approach", "hold"}, endings
    if "panda" in source:
        assert "insert" in kinds, run.describe()  # beside the hole: touched, then jammed
    else:  # the last CONTACT finds nothing above: its TIMEOUT
        assert endings[-1] == ("approach", "found no contact within 0.6 s"), endings


def _monitor(source: str, kind: str, mass_kg: float) -> tuple[SegmentMonitor, np.ndarray]:
    plan = compile_program(source, "c.cos", fixture_frames())
    (segment,) = [s for s in plan.segments if s.kind.value == kind]
    start = np.array([0.6, 0.15, 0.2578])
    goal = (start.copy(), np.diag([1.0, -1.0, -1.0]))
    return SegmentMonitor(segment, 0.0, start, 0.0, start, None, goal, lambda: "held", mass_kg), start


@pytest.mark.parametrize(
    ("source", "kind"),
    [
        ("CONTACT DOWN FORCE 6 N SPEED 80 mm/s TIMEOUT 3 s\n", "contact_approach"),
        ("CONTACT DOWN FORCE 6 N SPEED 8 mm/s\n", "contact_approach"),
        ("CONTACT DOWN FORCE 6 N SPEED 20 mm/s UNTIL FORCE > 30 N TIMEOUT 3 s\n", "contact_approach"),
        ("CONTACT DOWN FORCE 8 N\n", "contact_hold"),
        ("CONTACT +Z IN slope FORCE 5 N TIMEOUT 6 s\n", "contact_hold"),
    ],
)
def test_made_up_ticks_reach_every_ending_as_the_python_did(source: str, kind: str) -> None:
    """Seeded random ticks (a tool creeping, stopping, pressing or falling, the wrist ringing),
    through the monitor's judge on a new snapshot each tick (its arrays copied, not listed), must
    end every run at the same tick with the same outcome as the Python did: touched, landed, held
    back, no contact within its travel or its TIMEOUT; settled, held, not settled, lost contact.
    Catches a branch of the compiled judges the real runs do not reach parting from it."""
    rng = np.random.default_rng(11)
    reasons = set()
    for run in range(60):
        monitor, start = _monitor(source, kind, 0.66)
        completion = monitor.segment.completion
        before = Approach(monitor, completion) if kind == "contact_approach" else Hold(monitor, completion)
        position, t = start.copy(), 0.0
        speed = [0.0, 0.0002, 0.01, 0.08, -0.01][run % 5]  # down (z falls), or up
        force = [0.0, 0.2, 1.0, 1.9, 5.0, 8.0][run // 5 % 6]
        for _ in range(8000):
            t += 0.001
            if rng.random() < 0.0005:  # a change of pace or of push
                speed, force = speed * rng.choice([0.0, 0.5, 2.0]), rng.choice([0.0, 0.7, 3.0, 8.0, 20.0])
            position[2] -= speed * 0.001 + rng.normal(0.0, 2e-6)
            velocity = np.array([0.0, 0.0, -speed, 0.0, 0.0, 0.0]) + rng.normal(0.0, 0.002, 6)
            ringing = 0.4 if run // 2 % 2 else 0.05  # the wrist's, or a steady push
            wrench = np.array([0.0, 0.0, -force, 0.0, 0.0, 0.0]) + rng.normal(0.0, ringing, 6)
            if run % 2:  # a strided view: copied to be read
                velocity = np.repeat(velocity, 2)[::2]
            snap = Snapshot(t, position.copy(), np.diag([1.0, -1.0, -1.0]), velocity, wrench)
            outcome, expected = monitor.judge(snap), before(snap)
            if monitor.segment.until is not None and expected is None and t >= monitor._deadline_s:
                expected = monitor._timed_out(snap)
            assert outcome == expected, (run, t)
            if outcome is not None:
                words = outcome.reason.replace(":", "").split()  # the ending, without its figures
                reasons.add(" ".join(word for word in words[:5] if not word[0].isdigit()))
                break
    assert reasons >= ENDINGS[kind], reasons


ENDINGS = {
    "contact_approach": {
        "touched N along the",  # a touch (its figure left out)
        "touched stopped against it",  # landed
        "stopped mm along its",  # held back
        "found no contact within",  # its travel (300 mm), or its TIMEOUT
    },
    "contact_hold": {
        "contact held, force within",
        "force did not settle within",
        "lost contact the tool ran",
    },
}
