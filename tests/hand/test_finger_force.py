"""FINGER FORCE in UNTIL, IF and WHILE: the grip the pads feel (the smaller of the two)."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from cosmos.errors import ProgramError
from cosmos.lang import compile_program
from cosmos.workcell import fixture_frames
from tests.hand.gripper_support import hand_samples
from tests.run.run_support import run_in_process, write_program

GRIP_N = 40.0
PROGRAM = """TOOL GRIPPER
OBJECT block BOX SIZE (40 mm, 30 mm, 50 mm) MASS 0.5 kg AT table
MOVE TO table + (0, 0, 32.5 mm) SPEED 0.2 m/s
WAIT 0.3 s UNTIL FINGER FORCE > 10 N
GRASP block FORCE 40 N WIDTH 40 mm
MOVE BY (0, 0, 30 mm) SPEED 0.1 m/s UNTIL FINGER FORCE > 10 N
IF FINGER FORCE > 30 N
  WAIT 0.1 s
END
"""


@pytest.mark.parametrize("text", ["WAIT 1 s UNTIL FINGER FORCE > 10 N\n", "IF FINGER FORCE < 5 N\nEND\n"])
def test_finger_force_needs_the_gripper(text: str) -> None:
    """FINGER FORCE in a program whose tool is the peg is a check error at its column.

    Catches: a peg program that compiles a condition on pads it does not have (it would
    never fire, reading 0 N, and the statement would run to its end silently).
    """
    with pytest.raises(ProgramError) as raised:
        compile_program(text, "t.cos", fixture_frames())
    error = raised.value
    assert "TOOL GRIPPER" in str(error)
    line = text.splitlines()[0]
    assert error.span is not None and error.span.column == line.index("FINGER") + 1


def test_finger_force_compiles_with_the_gripper() -> None:
    """Catches: TOOL GRIPPER not carried to the conditions' check (every FINGER FORCE refused)."""
    compile_program(PROGRAM, "t.cos", fixture_frames())


@pytest.mark.parametrize("ideal", [False, True], ids=["realistic", "ideal"])
def test_until_finger_force_stops_with_the_grip_that_fired_it(tmp_path: Path, ideal: bool) -> None:
    """Before GRASP the pads feel nothing and the WAIT runs out; once the block is gripped at
    40 N, the lift's UNTIL FINGER FORCE > 10 N stops it at once, and its reason gives the grip
    read, within 10 % of the GRASP's 40 N and within 1 N of the pads on /cosmos/hand then.

    Catches: FINGER FORCE read from the wrist sensor (the block's 4.9 N never passes 10 N, so
    the lift would run to its end), a condition that fires on the open fingers, a reason
    whose value is not the reading that fired it, a decision that cannot read the grip.
    """
    log = tmp_path / "ff.mcap"
    run = run_in_process(write_program(tmp_path, "ff", PROGRAM), log, ideal=ideal)
    assert run.returncode == 0, run.describe()
    assert not run.events("stopped", 4), run.describe()  # the open fingers: the WAIT ran out
    stopped = run.events("stopped", 6)
    assert len(stopped) == 1, run.describe()
    match = re.fullmatch(r"UNTIL FINGER FORCE > 10 N: ([0-9.]+) N at ([0-9.]+) s", stopped[0].reason)
    assert match is not None, stopped[0].reason
    fired_n, fired_s = float(match.group(1)), float(match.group(2))
    assert abs(fired_n - GRIP_N) <= 0.1 * GRIP_N
    started = run.events("start", 6)[0].t
    assert fired_s - started < 0.02  # at once: the grip was there when the lift started
    pads = [s for s in hand_samples(log) if 0 <= float(s["t"]) - fired_s < 0.05]  # type: ignore[arg-type]
    grips = np.array([min(float(s["force_left"]), float(s["force_right"])) for s in pads])  # type: ignore[arg-type]
    assert len(grips) > 0 and np.all(np.abs(grips - fired_n) < 1.0), (grips, fired_n)
    decided = [e for e in run.events(line=7) if "FINGER FORCE > 30 N: read" in e.reason]
    assert decided, run.describe()
    read_n = float(re.search(r"read ([0-9.]+) N", decided[0].reason).group(1))  # type: ignore[union-attr]
    assert abs(read_n - GRIP_N) <= 0.1 * GRIP_N
    assert run.events("done", 8), run.describe()  # the IF's branch ran
