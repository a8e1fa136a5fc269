"""A guarded MOVE stopped on a touch holds where it touched, not pressing on (tester's u13).

docs/language.md's UNTIL example, ``MOVE BY (0, 0, -100 mm) UNTIL FORCE > 5 N`` from 50 mm over
the table, then ``WAIT 1 s``: the UNTIL fired at 6.3-7.5 N, but the arm came to rest pressing
10.1 N (seed 0), 13.9 N (seed 1) and 27.9 N (ideal plant) into the table, MuJoCo's contact forces
as the wrist read them, and the WAIT still pressed 2.4-3.1 N: the brake let go as soon as the tool
was at rest, pressed into the surface by its momentum, and the WAIT's hold took that compressed
pose. Judged on MuJoCo's own contact forces on the tool against the UNTIL's threshold at the
MOVE's end, and against a touch's 2 N (docs/language.md, CONTACT) at the WAIT's.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from tool_contact import ToolContactProbe, run_with_probe

GUARDED = """MOVE TO table + (0, 0, 50 mm)
MOVE BY (0, 0, -100 mm) UNTIL FORCE > 5 N
WAIT 1 s
MOVE BY (0, 0, 50 mm)
"""
THRESHOLD_N = 5.0
"""The UNTIL's."""
TOUCH_N = 2.0
"""What docs/language.md counts as a touch (CONTACT: the force along the approach "exceeds 2 N")."""
CASES = {
    "puma-realistic-0": ("", 0, False),
    "puma-realistic-1": ("", 1, False),
    "puma-ideal": ("", 0, True),
    "panda-realistic-0": ("ROBOT panda\n", 0, False),
    "panda-ideal": ("ROBOT panda\n", 0, True),
}


def _force_at(probe: ToolContactProbe, t_s: float) -> float:
    """The magnitude of MuJoCo's contact force on the tool at the last physics step by ``t_s`` [N]."""
    last = int(np.searchsorted(np.asarray(probe.t), t_s + 1e-9)) - 1
    return float(np.linalg.norm(probe.force[last]))


@pytest.mark.parametrize("case", sorted(CASES))
def test_a_guarded_move_stopped_on_the_table_holds_where_it_touched(tmp_path: Path, case: str) -> None:
    """Catches the hold after a guarded stop pressing on: 10.1-27.9 N of contact force as the MOVE
    ended "stopped, UNTIL FORCE > 5 N", and 2.4-3.1 N still at the end of the WAIT after it."""
    prefix, seed, ideal = CASES[case]
    record, probe = run_with_probe(tmp_path, "guarded", prefix + GUARDED, seed, ideal)
    move_line = 2 + prefix.count("\n")
    ends = {e.line: e for e in record.events if e.kind in ("done", "stopped", "failed")}
    assert ends[move_line].kind == "stopped", ends[move_line].reason
    assert ends[move_line].reason.startswith("UNTIL FORCE > 5 N"), ends[move_line].reason
    moved = _force_at(probe, ends[move_line].t)
    assert moved <= THRESHOLD_N, f"the stopped MOVE ended pressing {moved:.1f} N"
    waited = _force_at(probe, ends[move_line + 1].t)
    assert waited <= TOUCH_N, f"the WAIT after it ended pressing {waited:.1f} N"
