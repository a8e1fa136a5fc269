"""GRASP and RELEASE that cannot do what they say: each a located failure, the arm held, the log complete."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.run.run_support import ProgramRun, run_in_process, write_program

HEADER = """TOOL GRIPPER
OBJECT block BOX SIZE (40 mm, 30 mm, 50 mm) MASS 0.5 kg AT table
OBJECT far BOX SIZE (40 mm, 30 mm, 50 mm) MASS 0.5 kg AT table + (200 mm, 0, 0)
SPEED 0.2 m/s
"""
DOWN = "MOVE TO table + (0, 0, 32.5 mm) SPEED 50 mm/s\n"


def _run(tmp_path: Path, body: str, ideal: bool = True) -> ProgramRun:
    program = write_program(tmp_path, "hand", HEADER + body)
    return run_in_process(program, tmp_path / "hand.mcap", ideal=ideal)


def _failed_at(run: ProgramRun, text: str) -> str:
    """The failure's reason, after checking it is the only failure, at the line holding ``text``."""
    assert run.returncode != 0, run.describe()
    line = run.line_of(text, 5)
    failed = run.events("failed")
    assert [e.line for e in failed] == [line], run.describe()
    assert not run.log.truncated
    assert f"hand.cos:{line}:" in run.stderr, run.stderr
    return failed[0].reason


def test_grasp_on_nothing(tmp_path: Path) -> None:
    """Closing in free air fails at the GRASP: "closed to 0 mm: nothing between the fingers".

    Catches a GRASP that reports success with the fingers shut on air (the next MOVE would
    carry nothing) or that hangs waiting for a force that never comes.
    """
    run = _run(tmp_path, "MOVE BY (0, 0, 50 mm)\nGRASP FORCE 30 N\nMOVE BY (0, 0, 10 mm)\n")
    reason = _failed_at(run, "GRASP")
    assert reason.startswith("closed to 0 mm: nothing between the fingers"), reason


def test_grasp_of_an_object_out_of_reach(tmp_path: Path) -> None:
    """GRASP far, with the fingers at the other block... no: in free air above the table, says how far it is.

    Catches a named GRASP that closes on nothing without naming where its object is.
    """
    run = _run(tmp_path, "MOVE BY (0, 0, 50 mm)\nGRASP far\n")
    reason = _failed_at(run, "GRASP far")
    assert "nothing between the fingers ('far' is " in reason and "mm from the tool point)" in reason, reason


def test_grasp_of_the_wrong_object(tmp_path: Path) -> None:
    """GRASP far with the fingers round block fails: "closed on 'block', not on 'far'", and lets go.

    Catches a GRASP that takes whatever is between the fingers for the object it names (the
    program would carry the wrong part and put the wrong mass in the model).
    """
    run = _run(tmp_path, DOWN + "GRASP far\n")
    reason = _failed_at(run, "GRASP far")
    assert reason == "closed on 'block', not on 'far'", reason


def test_release_with_nothing_held(tmp_path: Path) -> None:
    """RELEASE before any GRASP fails at its line. Catches a RELEASE that silently does nothing."""
    run = _run(tmp_path, "MOVE BY (0, 0, 10 mm)\nRELEASE\nMOVE BY (0, 0, 10 mm)\n")
    assert _failed_at(run, "RELEASE") == "the gripper holds nothing"


def test_grasp_width_mismatch(tmp_path: Path) -> None:
    """GRASP block WIDTH 60 mm closes to 40 mm: a located failure. Catches a WIDTH that is not checked."""
    run = _run(tmp_path, DOWN + "GRASP block WIDTH 60 mm\n")
    reason = _failed_at(run, "GRASP block")
    assert reason.startswith("closed to 39.") or reason.startswith("closed to 40."), reason
    assert reason.endswith("WIDTH expects 60.0 mm")


@pytest.mark.parametrize("ideal", [True, False], ids=["ideal", "realistic"])
def test_dragging_a_held_block_into_the_table_is_a_protective_stop(tmp_path: Path, ideal: bool) -> None:
    """A MOVE that pushes the held block 10 mm into the table stops with a protective stop at its line.

    Catches contacts of held objects that the supervision ignores (the block's geoms belong
    to no arm part: only the wrist's force, or the slip it causes, can stop the arm).
    """
    run = _run(
        tmp_path, DOWN + "GRASP block\nMOVE BY (0, 0, 20 mm)\nMOVE TO table + (30 mm, 0, -10 mm)\n", ideal
    )
    reason = _failed_at(run, "MOVE TO table + (30 mm")
    assert reason.startswith("protective stop: "), reason
    assert run.events("protective_stop")


@pytest.mark.parametrize("ideal", [True, False], ids=["ideal", "realistic"])
def test_a_slipping_object_is_a_protective_stop(tmp_path: Path, ideal: bool) -> None:
    """2 kg at FRICTION 0.2 held with 20 N (8 N of friction for 19.6 N of weight) slips: a protective stop.

    Catches a lift that carries on while the object slides out of the fingers (the program
    would place nothing), and an object's FRICTION that the pads' contacts ignore (the
    pads' own 1.0 would hold it).
    """
    body = (
        "OBJECT heavy BOX SIZE (40 mm, 30 mm, 50 mm) MASS 2 kg AT table + (0, 100 mm, 0) FRICTION 0.2\n"
        "MOVE TO table + (0, 100 mm, 32.5 mm) SPEED 50 mm/s\nGRASP heavy FORCE 20 N\n"
        "MOVE BY (0, 0, 50 mm) SPEED 0.1 m/s\n"
    )
    run = _run(tmp_path, body, ideal)
    reason = _failed_at(run, "MOVE BY (0, 0, 50 mm)")
    assert reason.startswith("protective stop: 'heavy' slips: "), reason
    assert run.events("protective_stop")
