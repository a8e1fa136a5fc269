"""A REPL session on the Panda (``cosmos repl --robot panda``): it moves, touches, logs seven joints.

Catches a session that drives the PUMA whatever it was asked, a ROBOT input that switches the
arm mid-session, or a log of the wrong arm.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from cosmos.robots import PANDA
from cosmos.workcell import fixture_frames
from tests.repl.repl_drive import CTRL_D, ENTER, Driven, drive

TABLE = fixture_frames(PANDA)["table"].position

KEYS = (
    "MOVE BY (0, 0, -20 mm)" + ENTER
    + "ROBOT puma560" + ENTER
    + "MOVE TO table + (0, 0, 30 mm) SPEED 0.25 m/s" + ENTER
    + "CONTACT DOWN FORCE 5 N SPEED 40 mm/s" + ENTER
    + "WAIT 0.3 s" + ENTER
    + CTRL_D
)  # fmt: skip


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> Driven:
    return drive(tmp_path_factory.mktemp("repl_panda"), KEYS, robot=PANDA)


def test_the_session_drives_the_panda(session: Driven) -> None:
    assert session.status == 0
    assert "a simulated Franka Emika Panda in its workcell" in session.output
    assert session.log.metadata["robot"] == "panda"
    assert session.log.state.q.shape[1] == 7
    assert session.app.engine.session.runtime.q.shape == (7,)


def test_a_robot_input_naming_another_arm_is_refused(session: Driven) -> None:
    assert "ROBOT puma560: this run is on the panda" in session.output


def test_move_and_contact_on_the_panda(session: Driven) -> None:
    moved = session.position_at(session.done_time("MOVE BY (0, 0, -20 mm)"))
    start = session.log.state.x[0]
    assert np.linalg.norm(moved - start - (0.0, 0.0, -0.02)) < 1e-3
    pressed = session.position_at(session.done_time("WAIT 0.3 s"))
    assert abs(pressed[2] - (TABLE[2] + 0.0)) < 2e-3  # the tip on the table top
    assert -session.log.state.wrench[-1, 2] == pytest.approx(5.0, abs=0.5)


def test_session_log_is_complete(session: Driven, tmp_path: Path) -> None:
    assert not session.log.truncated
