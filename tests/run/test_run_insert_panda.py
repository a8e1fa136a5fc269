"""The PUMA's insertions from 2 mm off (tests/run/test_run_insert.py) on the Panda: ten of ten.

The same program (ten directions of a 2 mm lateral error, each INSERT from 2 mm above the
mouth with X Y RX RY compliant at zero force), the Panda chosen by ``ROBOT panda``; every
INSERT must end ``done`` with the tip 25 mm into the hole, judged from the log as for the
PUMA. Catches the force loop, the admittance on the compliant axes or the peg's geometry
failing on the arm with seven joints (and a lighter effective mass: Lambda's translation
5-11 kg, the PUMA's 12-18).
"""

from __future__ import annotations

from pathlib import Path

from test_run_insert import GOAL_TOLERANCE_M, INSERTED_M, OFFSET_M, directions, insert, report

from cosmos.robots import PANDA


def test_ten_of_ten_insertions_succeed_on_the_panda(tmp_path: Path) -> None:
    results = [
        insert(tmp_path, OFFSET_M, a, "X Y RX RY", seed, PANDA.name) for seed, a in enumerate(directions())
    ]
    summary = report(results)
    for result in results:
        assert result.outcome == "done" and "reached" in result.reason, summary
        assert result.deepest_m >= INSERTED_M - GOAL_TOLERANCE_M, summary
