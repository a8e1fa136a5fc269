"""A held peg does not turn in the hand's pads under a moment below their friction limit.

Judged against Coulomb's law, from the run's own log: the moment the grip has to hold about
its axis (the line between the pads), from the wrench the tool applied (``/cosmos/state``)
and the pads' centre (the fingers on ``/tf``), against what two rubber pads' friction holds
(numbers written here from the hands' descriptions and the peg's); the peg's turn
in the fingers from MuJoCo's poses of the peg and the hand on ``/tf``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from tests.hand.gripper_support import tf_poses
from tests.run.run_support import GRASPED_PEG_INSERT, run_in_process, write_program

PROGRAM = GRASPED_PEG_INSERT
"""A grasped peg inserted from 3.6 mm off the hole's axis: it lands on the mouth's edge and the
INSERT's compliant rotations tip it (docs/language.md, INSERT), so the grip holds a moment."""

STEEL_FRICTION = 0.45
"""The shipped peg's FRICTION (docs/language.md: a steel peg; an object's FRICTION is the
coefficient of its contacts with the pads)."""
HANDS = {
    "panda": (0.0185, 0.1034 - 0.0584),
    "puma560": (0.025, 0.1875 - 0.145),
}
"""Per arm, its hand's pad height along the fingers and the pads' centre from the fingers'
joint origin along the hand's z [m]: the Franka hand's rubber fingertip, 18.5 mm
(``panda.urdf``, the ``panda_leftfinger`` collision box "rubber tip with which to grasp"), its
centre the URDF's ``panda_hand_tcp_joint`` 103.4 mm below the hand, ``panda_finger_joint1``
58.4 mm; the PUMA's 2F-85, pads 25 mm tall centred on the tool point at 187.5 mm, fingers from
145 mm (``cosmos/models/puma560/README.md``, "Gripper")."""
STATIC_TURN_DEG = 0.5
"""A grip below its friction limit holds the peg but for the pads' elastic give: a fraction of
a degree (the hand's tilt window alone is 10 deg)."""


def _turn_in_fingers_deg(tool_quat: np.ndarray, peg_quat: np.ndarray) -> np.ndarray:
    """The peg's turn about the hand's x (the pads' normal) since the first sample [deg]. # (n,)"""
    tool, peg = _matrices(tool_quat), _matrices(peg_quat)
    in_hand = np.einsum("nji,njk->nik", tool, peg)  # peg in the hand's axes
    change = np.einsum("nij,kj->nik", in_hand, in_hand[0])  # R_rel R_rel0^T, hand axes
    return np.degrees(np.arctan2(change[:, 2, 1] - change[:, 1, 2], change[:, 1, 1] + change[:, 2, 2]))


def _matrices(quat_wxyz: np.ndarray) -> np.ndarray:
    w, x, y, z = np.asarray(quat_wxyz).T
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
        ],
        axis=-2,
    )


@pytest.mark.parametrize("robot", sorted(HANDS))
def test_a_peg_held_below_the_pads_friction_limit_does_not_turn_in_them(tmp_path: Path, robot: str) -> None:
    """An 80 N grasp holds the peg through the INSERT: it turns under 0.5 deg in the pads.

    The moment about the grip's axis stays below two pads' Coulomb limit (uniform pressure on
    a line contact: mu N L / 4 each, 0.33 N m on the Panda with the peg's steel 0.45, the pads'
    logged force and the URDF's 18.5 mm), so static friction holds the peg. Before, the peg's
    contacts with the pads were point contacts without torsional friction (the peg's geom
    had no ``condim``, and an object's contacts take its own): MuJoCo's soft friction let
    the peg creep about the grip's axis under at most 0.15 N m, under half the limit, 10.8 deg
    in 3 s, until the slip stop ended 7 of 8 runs of this program ("'peg' slips: it moved
    5.0 mm in the fingers"); on the PUMA's 2F-85 it turned 2.7 deg and jammed.
    """
    pad_height_m, pads_from_finger_joint_m = HANDS[robot]
    log = tmp_path / "grasp.mcap"
    run = run_in_process(write_program(tmp_path, "grasp", f"ROBOT {robot}\n{PROGRAM}"), log)
    insert = run.line_of("INSERT")
    start = run.events("start", insert)[0].t
    end = max(e.t for e in run.events(line=insert))
    state = run.log.state
    assert state.finger_force is not None
    inside = (state.t >= start) & (state.t <= end)
    grip_n = float(state.finger_force[inside].min())

    times, poses = tf_poses(log, ("tool", "peg", "finger_left", "finger_right"))
    during = (times >= start) & (times <= end)
    turn = _turn_in_fingers_deg(poses["tool"][1][during], poses["peg"][1][during])

    # The moment the pads must hold: the environment's wrench on the peg about the pads' centre.
    nearest = np.searchsorted(times, state.t[inside]).clip(0, len(times) - 1)
    hand = _matrices(poses["tool"][1][nearest])
    fingers = 0.5 * (poses["finger_left"][0][nearest] + poses["finger_right"][0][nearest])
    pads_centre = fingers + hand[:, :, 2] * pads_from_finger_joint_m
    force, moment = state.wrench[inside, :3], state.wrench[inside, 3:]
    about_pads = -(moment + np.cross(state.x[inside] - pads_centre, force))
    held = np.abs(np.einsum("ni,ni->n", about_pads, hand[:, :, 0]))
    coulomb = 2 * STEEL_FRICTION * grip_n * pad_height_m / 4

    assert held.max() < coulomb, f"the grip held {held.max():.3f} N m; Coulomb's limit {coulomb:.3f} N m"
    turned = float(np.abs(turn).max())
    assert turned < STATIC_TURN_DEG, f"the peg turned {turned:.2f} deg in the fingers\n{run.describe()}"
    assert run.returncode == 0, run.describe()
