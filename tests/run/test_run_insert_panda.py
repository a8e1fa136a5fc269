"""The PUMA's ten seeded insertions (tests/run/test_run_insert.py) on the Panda: ten of ten.

The same program (ten lateral errors up to 2 mm, each INSERT from 2 mm above the mouth with
X Y RX RY compliant at zero force), the Panda chosen by ``ROBOT panda``; every INSERT must end
``done`` with the tip 25 mm into the hole, judged from the log as for the PUMA. Catches the
force loop, the admittance on the compliant axes or the peg's geometry failing on the arm
with seven joints (and a lighter effective mass: Lambda's translation 5-11 kg, the PUMA's 12-18).
"""

from __future__ import annotations

import pytest
from run_support import ProgramRun, run_in_process, write_program
from test_run_insert import (
    GOAL_TOLERANCE_M,
    INSERTED_M,
    Offset,
    insert_results,
    insertion,
    report,
    seeded_offsets,
)

from cosmos.robots import PANDA


@pytest.fixture(scope="module")
def panda_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[ProgramRun, list[Offset]]:
    directory = tmp_path_factory.mktemp("insert_panda")
    offsets = seeded_offsets()
    source = f"ROBOT {PANDA.name}\n# ten seeded insertions, X Y RX RY compliant\nSPEED 0.25 m/s\n"
    source += "".join(insertion(o, "X Y RX RY") for o in offsets)
    program = write_program(directory, "insert_panda", source)
    return run_in_process(program, directory / "insert_panda.mcap"), offsets


def test_ten_of_ten_insertions_succeed_on_the_panda(panda_run: tuple[ProgramRun, list[Offset]]) -> None:
    run, offsets = panda_run
    assert run.log.metadata["robot"] == "panda"
    results = insert_results(run)
    summary = report(results)
    assert run.returncode == 0, run.describe() + "\n" + summary
    assert len(results) == len(offsets), summary
    for result in results:
        assert result.outcome == "done" and "reached" in result.reason, summary
        assert result.deepest_m >= INSERTED_M - GOAL_TOLERANCE_M, summary
