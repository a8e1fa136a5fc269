"""COMPLY on the slope on the Panda: programs/comply_slope.cos run with ``--robot panda``.

The PUMA's figure (tests/run/test_run_slope.py) on the arm with seven joints: the tool meets
the plate 20 deg off its normal, RX RY comply at zero moment, and at the end of the WAIT its
axis is within 2 deg of the plate's normal, pressing 5 N. Catches the admittance on the
moment axes failing through the redundant arm's Jbar, or ``--robot`` not reaching the run.
"""

from __future__ import annotations

import contextlib
import io

import numpy as np
import pytest
from run_support import PROGRAMS, SLOPE_TILT_RAD, ProgramRun, read_run
from test_run_slope import TOLERANCE_DEG, axis_to_normal_deg, settled_index


@pytest.fixture(scope="module")
def slope_run(tmp_path_factory: pytest.TempPathFactory) -> ProgramRun:
    from cosmos.commands.run import run_program
    from cosmos.runtime.rates import Rates

    program, log = PROGRAMS / "comply_slope.cos", tmp_path_factory.mktemp("slope_panda") / "slope.mcap"
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = run_program(program, log, Rates(), 0, robot="panda")
    run = read_run(program, log, status, out.getvalue(), err.getvalue())
    assert run.returncode == 0, run.describe()
    return run


def test_the_slope_on_the_panda(slope_run: ProgramRun) -> None:
    assert slope_run.log.metadata["robot"] == "panda"
    touch = slope_run.events("contact", slope_run.line_of("CONTACT"))
    at_touch = int(np.searchsorted(slope_run.log.state.t, touch[0].t))
    assert float(axis_to_normal_deg(slope_run)[at_touch]) == pytest.approx(
        np.degrees(SLOPE_TILT_RAD), abs=0.5
    )
    end = settled_index(slope_run)
    angle = float(axis_to_normal_deg(slope_run)[end])
    assert angle <= TOLERANCE_DEG, f"tool axis {angle:.2f} deg off the plate's normal"
    state = slope_run.log.state
    last = (state.t > state.t[end] - 0.5) & (state.t <= state.t[end])
    assert float(-state.wrench[last, 2].mean()) == pytest.approx(5.0, rel=0.1)
