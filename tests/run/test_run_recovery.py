"""TRY ... ON FAIL ... RETRY n around an INSERT that jams (issue 22, "Must show").

The peg starts 25 mm beside the hole's axis, where its whole face lands on the
fixture's flat top (the flat runs from 11 mm, the chamfer's outer edge, to 45 mm
from the axis; the peg's radius is 9.9 mm): INSERT jams there. The handler lifts,
moves over the hole and retries; the second INSERT goes in. The depth reached is
judged on the logged tool point against the hole's mouth written out in
run_support, not on the executor's own report.
"""

from __future__ import annotations

import re

import pytest
from run_support import HOLE_MOUTH_M, ProgramRun, run_in_process, write_program

from cosmos.run_result import run_from_record

JAMMING_TRY = """\
# a peg 25 mm beside the hole jams on the fixture's top; the handler recentres it
SPEED 0.25 m/s
MOVE TO hole + (25 mm, 0, 40 mm)
MOVE TO hole + (25 mm, 0, 2 mm)
TRY
  INSERT DOWN DEPTH 27 mm FORCE 15 N COMPLY X Y RX RY TIMEOUT 10 s
ON FAIL
  MOVE BY (0, 0, 20 mm)
  MOVE TO hole + ({x}, 0, 2 mm)
  RETRY 1
END
MOVE BY (0, 0, 60 mm)
"""
INSERT_LINE, TRY_LINE, ON_FAIL_LINE, RETRY_LINE = 6, 5, 7, 10


@pytest.fixture(scope="module")
def recovered(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The handler moves over the hole: the retry succeeds."""
    directory = tmp_path_factory.mktemp("recovered")
    program = write_program(directory, "recovered", JAMMING_TRY.format(x="0 mm"))
    return run_in_process(program, directory / "recovered.mcap")


@pytest.fixture(scope="module")
def exhausted(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    """The handler goes back to the same wrong place: the retry jams too, and RETRY 1 is used up."""
    directory = tmp_path_factory.mktemp("exhausted")
    program = write_program(directory, "exhausted", JAMMING_TRY.format(x="25 mm"))
    return run_in_process(program, directory / "exhausted.mcap")


def test_the_jam_is_recovered_and_the_program_succeeds(recovered: ProgramRun) -> None:
    """Exit 0, and the log holds, in order: the INSERT failed, ON FAIL took over, the handler's
    statements, the retry, the INSERT done. Catches a TRY that does not catch, a handler not run,
    a RETRY that does not run the block again, or a run reported failed after its recovery."""
    assert recovered.returncode == 0, recovered.describe()
    kinds = [(e.kind, e.line) for e in recovered.log.events if e.kind not in ("start", "contact")]
    expected = [
        ("done", 3),
        ("done", 4),
        ("failed", INSERT_LINE),
        ("recovery", TRY_LINE),
        ("done", 8),
        ("done", 9),
        ("retry", RETRY_LINE),
        ("done", INSERT_LINE),
        ("done", 12),
    ]
    assert kinds == expected, recovered.describe()
    failed = recovered.events("failed")[0]
    assert "jammed" in failed.reason, recovered.describe()
    recovery = recovered.events("recovery")[0]
    assert f"line {ON_FAIL_LINE}" in recovery.reason and "jammed" in recovery.reason
    assert "retry 1 of 1" in recovered.events("retry")[0].reason
    assert run_from_record(recovered.log).ok, "the Python API reads the recovered run as successful"


def test_the_retry_goes_into_the_hole_and_the_first_try_did_not(recovered: ProgramRun) -> None:
    """On the logged tool point: the first INSERT stopped on the fixture's top (a few mm below
    where it started, beside the hole), the retried one went 25 mm below the mouth on its axis.
    Catches a 'success' the arm did not make."""
    inserts = recovered.segments("insert", INSERT_LINE)
    assert len(inserts) == 2, recovered.describe()
    state = recovered.log.state
    first = state.segment == inserts[0].segment
    # The retried INSERT from the retry on: its approach may reach the depth untouched.
    second = (state.line == INSERT_LINE) & (state.t >= recovered.events("retry")[0].t)
    lowest_first = HOLE_MOUTH_M[2] - state.x[first, 2].min()
    assert lowest_first < 0.005, f"the jammed INSERT went {lowest_first * 1e3:.1f} mm below the mouth"
    assert abs(state.x[first, 0].mean() - (HOLE_MOUTH_M[0] + 0.025)) < 0.003
    deepest = HOLE_MOUTH_M[2] - state.x[second, 2].min()
    assert deepest > 0.024, f"the retried INSERT reached {deepest * 1e3:.1f} mm below the mouth"
    assert abs(state.x[second, 0][-1] - HOLE_MOUTH_M[0]) < 0.002


def test_a_retry_that_fails_again_ends_the_program(exhausted: ProgramRun) -> None:
    """With RETRY 1 used up, the second jam ends the program: exit 1, a failed event at the RETRY
    naming the jam, and no statement after the TRY ran. Catches retries without a bound, and a
    message that reads "RETRY 1 the TRY block ..." (the statement's head run into the reason)."""
    assert exhausted.returncode == 1, exhausted.describe()
    assert len(exhausted.events("failed", INSERT_LINE)) == 2
    assert len(exhausted.events("retry")) == 1
    final = exhausted.events("failed", RETRY_LINE)
    assert final and re.search(r"failed again after 1 retry: .*jammed", final[0].reason), exhausted.describe()
    assert not exhausted.events(line=12), "the MOVE after the TRY must not run"
    assert "jammed" in exhausted.stderr
    assert "RETRY 1 ran out: the TRY block" in exhausted.stderr
    assert not run_from_record(exhausted.log).ok
