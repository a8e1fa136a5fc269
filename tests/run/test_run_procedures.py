"""A grid of touches: a procedure with parameters against the LET workaround (issue 22, "Must show").

Before procedures took arguments, a user wrote the spot to touch into a LET
before each call. The parameterised procedure must compile to the same plan,
segment for segment, and, run, give the same log's segments; and the touches
must land where the program says (judged on the logged tool point against the
table top written out in run_support).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from run_support import BOTH_PLANTS, TABLE_TOP_Z_M, ProgramRun, run_in_process, write_program

from cosmos import plan
from cosmos.commands.check import load_fixtures
from cosmos.lang import compile_program

SPOTS_MM = ((0.0, 0.0), (30.0, 20.0))
"""The touched spots, from the table frame's origin [mm]."""

BODY = "  MOVE TO table + spot\n  CONTACT DOWN FORCE f\n  MOVE BY (0, 0, 15 mm)\nEND\n"
WITH_LET = (
    "SPEED 0.25 m/s\nPROC touch\n"
    + BODY
    + ("".join(f"LET spot = ({x} mm, {y} mm, 15 mm)\nLET f = 6 N\ntouch\n" for x, y in SPOTS_MM))
)
WITH_PARAMETERS = (
    "SPEED 0.25 m/s\nPROC touch(spot, f)\n"
    + BODY
    + ("".join(f"touch(({x} mm, {y} mm, 15 mm), 6 N)\n" for x, y in SPOTS_MM))
)


def _without_place(segment: plan.Segment) -> dict[str, object]:
    """A segment's JSON fields but where it was written (its line, column and call context)."""
    fields = plan.segment_to_json(segment)
    for key in ("line", "column", "context"):
        fields.pop(key)
    return fields


def test_the_plans_are_the_same() -> None:
    """Every segment field (targets, setpoints, axes, completions) equal, in order. Catches an
    argument bound to the wrong parameter, or evaluated in the wrong units."""
    fixtures = load_fixtures()
    with_let = compile_program(WITH_LET, "let.cos", fixtures)
    with_parameters = compile_program(WITH_PARAMETERS, "parameters.cos", fixtures)
    assert len(with_let.segments) == len(with_parameters.segments) == 4 * len(SPOTS_MM)
    for a, b in zip(with_let.segments, with_parameters.segments, strict=True):
        assert _without_place(a) == _without_place(b)


def run_both(directory: Path, ideal: bool) -> tuple[ProgramRun, ProgramRun]:
    """Both programs, run on the realistic plant or the ideal one."""
    done = []
    for name, source in (("with_let", WITH_LET), ("with_parameters", WITH_PARAMETERS)):
        done.append(run_in_process(write_program(directory, name, source), directory / f"{name}.mcap", ideal))
    return done[0], done[1]


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> tuple[ProgramRun, ProgramRun]:
    """Both programs, run on the realistic plant."""
    return run_both(tmp_path_factory.mktemp("grid"), ideal=False)


@pytest.fixture(scope="module")
def ideal_runs(tmp_path_factory: pytest.TempPathFactory) -> tuple[ProgramRun, ProgramRun]:
    """Both programs, run on the ideal plant."""
    return run_both(tmp_path_factory.mktemp("grid_ideal"), ideal=True)


def test_the_logs_segments_are_the_same(runs: tuple[ProgramRun, ProgramRun]) -> None:
    """Both runs succeed and log the same segments (kind, goal, force setpoint, axes, gains)
    at the same times. Catches a run-time difference the plan comparison cannot see."""
    with_let, with_parameters = runs
    assert with_let.returncode == 0, with_let.describe()
    assert with_parameters.returncode == 0, with_parameters.describe()
    a, b = with_let.log.segments, with_parameters.log.segments
    assert len(a) == len(b) == 4 * len(SPOTS_MM)
    for x, y in zip(a, b, strict=True):
        assert (x.kind, x.statement, x.motion_axes) == (y.kind, y.statement, y.motion_axes)
        np.testing.assert_allclose(x.goal, y.goal, atol=1e-9)
        np.testing.assert_allclose(x.force_setpoint, y.force_setpoint, atol=1e-9)
        np.testing.assert_allclose(x.stiffness, y.stiffness, rtol=1e-9)
        assert x.t == pytest.approx(y.t, abs=1e-9)


@pytest.mark.parametrize(
    "ideal",
    BOTH_PLANTS,
)
def test_the_touches_land_on_the_spots(ideal: bool, request: pytest.FixtureRequest) -> None:
    """Each CONTACT hold of the parameterised run presses the table top at its spot with 6 N."""
    run = request.getfixturevalue("ideal_runs" if ideal else "runs")[1]
    state = run.log.state
    table_origin = np.array([0.60, -0.15])
    holds = run.segments("contact_hold")
    assert len(holds) == len(SPOTS_MM), run.describe()
    for hold, (x_mm, y_mm) in zip(holds, SPOTS_MM, strict=True):
        mask = state.segment == hold.segment
        tip = state.x[mask][-1]
        np.testing.assert_allclose(tip[:2], table_origin + np.array([x_mm, y_mm]) / 1e3, atol=2e-3)
        assert abs(tip[2] - TABLE_TOP_Z_M) < 2e-3
        assert state.wrench[mask][-20:, 2].mean() == pytest.approx(-6.0, abs=1.0)
