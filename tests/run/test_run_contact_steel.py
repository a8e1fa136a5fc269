"""CONTACT onto steel (issue 14, item 5): the hole fixture's top face, judged from the run's own log at 1 kHz.

The table's 1.5 mm impedance ramp cushions a landing at the SPEED; the hole's top face meets the
steel peg with the tool's 0.3 mm, where the push rises some 3 N per millisecond per 5 mm/s and the
landing's peak is set by the speed at the touch (:mod:`cosmos.osc.landing`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from test_run_contact_impact import DOWN, bar_n, land

SOURCE = (
    "FRAME beside = hole + (16 mm, 0, 10 mm)\n"
    "MOVE TO beside\n"
    "CONTACT DOWN FORCE 8 N SPEED 20 mm/s TIMEOUT 5 s\n"
    "WAIT 0.3 s\n"
)


def test_contact_onto_the_hole_top_lands_near_its_force(tmp_path: Path) -> None:
    """search_insert.cos's CONTACT DOWN FORCE 8 N SPEED 20 mm/s onto the hole's top face peaks under 13 N.

    Realistic plant, seed 0. Catches an approach that meets the steel face at its SPEED: the
    push peaked at 45.7 N logged (53 N in MuJoCo's contact) within 2 ms of the touch, before
    the touch braking or the force loop could act; and a landing that slows too early to touch
    (the approach stalls above the face: "found no contact"). The touch comes within 0.25 s of
    the approach at the SPEED (the face is 10 mm below the start: 0.54 s before, 0.65 s now).
    """
    landing = land(tmp_path, SOURCE, 3, DOWN, False)
    peak = float(landing.push.max())
    assert peak < bar_n(8.0), f"peak {peak:.2f} N for FORCE 8 N\n{landing.describe()}"
    events = [(e.t, e.kind) for e in landing.record.events if e.line == 3]
    start = next(t for t, kind in events if kind == "start")
    touch = next(t for t, kind in events if kind == "contact")
    assert touch - start < 0.010 / 0.020 + 0.25, f"touched {touch - start:.2f} s after the start"
    assert bool(np.isfinite(landing.push).all())
