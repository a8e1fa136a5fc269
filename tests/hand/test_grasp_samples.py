"""The state samples logged while a GRASP runs are the GRASP's.

Bug: the hand's steps are not segments, so their samples kept the tag of the MOVE before
(its line and segment): a sweep's per-statement peak force for every GRASP read 0.0 N
(``cosmos sweep`` of a pick-up, 8 runs), and a user's per-line plot gave the MOVE the grasp's
second of holding still.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import cosmos
from cosmos.runlog.reader import read_log
from cosmos.sweep.tap import summarize

PROGRAM = """\
TOOL GRIPPER
MOVE TO table + (-160 mm, 250 mm, 100 mm)
MOVE TO table + (-160 mm, 250 mm, 12.5 mm) SPEED 50 mm/s
GRASP block_b FORCE 30 N WIDTH 30 mm
MOVE BY (0, 0, 50 mm)
"""


def test_a_grasps_samples_carry_its_line_and_its_peak_force(tmp_path: Path) -> None:
    run = cosmos.run(PROGRAM, log=tmp_path / "grasp.mcap")
    assert run.ok, run.outcome
    log = read_log(tmp_path / "grasp.mcap")
    start, done = (e.t for e in log.events if e.line == 4 and e.kind in ("start", "done"))
    t, line = log.state.t, log.state.line
    inside = (t > start) & (t < done)
    assert inside.sum() > 100  # about a second at 250 Hz
    assert set(line[inside].tolist()) == {4}
    force = np.linalg.norm(log.state.wrench[:, :3], axis=1)
    grasp = next(s for s in summarize(log.events, t, line, force)["statements"] if s["line"] == 4)
    assert grasp["peak_force_n"] == float(force[inside | ((t == done) & (line == 4))].max())
    assert grasp["peak_force_n"] > 0.0
