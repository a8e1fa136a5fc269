"""A CONTACT whose held push loses its surface (issue 14, "Outcomes that are true"), judged from the log.

``CONTACT DOWN FORCE 8 N SPEED 10 mm/s`` 0.5 mm off the hole's axis touches the hole's chamfer
with the peg's rim (2.0-2.4 N), and the hold starts there; on the realistic plant's seeds 1, 2
and 4 the peg then slides off the chamfer into the bore. What a roboticist expects of force
control (a speed limit in its force-controlled directions): the push runs on no faster than the
statement's SPEED, lands on the bore's steel bottom as the approach lands on a face, and ends
resting there at its FORCE, the CONTACT done by its own measure (force settled).
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest
from run_support import HOLE_DEPTH_M, HOLE_MOUTH_M, write_program

import cosmos
from cosmos.commands.run import run_program
from cosmos.runlog import read_log
from cosmos.runtime.rates import Rates

FORCE_N, SPEED_MPS = 8.0, 0.010
SOURCE = (
    "SPEED 0.2 m/s\n"
    "MOVE TO hole + (0.5 mm, 0, 10 mm)\n"
    f"CONTACT DOWN FORCE {FORCE_N:g} N SPEED {SPEED_MPS * 1e3:g} mm/s\n"
)
LINE = 3
BORE_BOTTOM_M = HOLE_MOUTH_M - np.array((0.0, 0.0, HOLE_DEPTH_M))
"""The centre of the bore's bottom [m] (the scene's documented mouth and depth)."""


@pytest.mark.parametrize("seed", [1, 2])
def test_a_push_off_the_chamfer_lands_in_the_bore_at_its_speed(tmp_path: Path, seed: int) -> None:
    """The peg slid off the chamfer ends done, resting on the bore's bottom at FORCE, never faster than SPEED.

    Catches the held push running away when it loses its surface: with eq. 18's force loop alone
    (its integrals wound by the lost push) the peg fell the 43 mm at up to 82 mm/s and hit the bore's
    steel bottom at 174-201 N (a protective stop over the statement's limit, 2 FORCE + 30 N = 46 N;
    with the push faded out above its speed, 66-72 N). Judged from the run's 1 kHz log against the
    scene's documented geometry and the CONTACT bar of docs/language.md: the speed along the push
    during the hold stays within 10 % of SPEED, the push peaks under max(1.5 FORCE, FORCE + 5 N),
    the tool point ends on the bore's bottom (within 0.5 mm; 1 mm of its axis), and the CONTACT
    is done with its force settled (also catches a hold that reports "done" while still falling).
    """
    program = write_program(tmp_path, "lost", SOURCE)
    log = tmp_path / "lost.mcap"
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        code = run_program(program, log, Rates(state_hz=1000.0), seed)
    record = read_log(log)
    events = [e for e in record.events if e.line == LINE]
    told = "\n".join(f"{e.t:.3f} {e.kind}: {e.reason}" for e in events)
    assert code == 0, told
    assert events[-1].kind == "done" and events[-1].reason == "force settled", told
    state = record.state
    hold = next(s.segment for s in record.segments if s.kind == "contact_hold")
    held = state.segment == hold
    down = np.array((0.0, 0.0, -1.0))
    fastest = float(state.v[held, :3].dot(down).max())
    assert fastest <= 1.1 * SPEED_MPS, f"ran on at {fastest * 1e3:.1f} mm/s along the push\n{told}"
    peak = float(state.wrench[held, :3].dot(down).max())
    assert peak < max(1.5 * FORCE_N, FORCE_N + 5.0), f"the push peaked at {peak:.1f} N\n{told}"
    end = state.x[held][-1]
    assert abs(end[2] - BORE_BOTTOM_M[2]) < 5e-4, f"ended {(end[2] - BORE_BOTTOM_M[2]) * 1e3:.2f} mm off"
    assert np.hypot(*(end[:2] - BORE_BOTTOM_M[:2])) < 1e-3


def test_a_slide_off_an_edge_says_its_surface_is_lost(tmp_path: Path) -> None:
    """A SLIDE that carries the peg off the hole fixture's top fails saying it left its surface.

    Bug: it failed "did not arrive ... 18.3 mm and 0.1 deg from its goal" with the tool at its goal
    across (0.6 mm): the 18 mm were the fall along the force-controlled axis, which is no goal of a
    SLIDE. It now fails where it leaves its surface (cosmos.execution.left_surface: here its push
    lost for 0.25 s over the edge), short of its goal; the slide it names is measured here from the
    log's tool points.
    """
    program = (
        "SPEED 0.2 m/s\nMOVE TO hole + (25 mm, 0, 10 mm)\nCONTACT DOWN FORCE 8 N SPEED 10 mm/s\n"
        "SLIDE +X BY 40 mm SPEED 10 mm/s\n"
    )
    run = cosmos.run(program, log=tmp_path / "edge.mcap")
    assert not run.ok and run.outcome is not None and run.outcome.location.endswith(":4:1")
    reason = run.outcome.reason
    assert "its surface at" in reason, reason
    slid_mm = float(reason.split("after ")[1].split(" mm")[0])
    state = run.record.state
    sliding = state.x[state.line == 4]
    across_mm = 1e3 * float(np.hypot(*(sliding[-1, :2] - sliding[0, :2])))
    assert slid_mm < 40.0  # short of its goal across
    assert abs(slid_mm - across_mm) < 1.5  # the slide it names is the tool's
