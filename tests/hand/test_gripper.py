"""The gripper on the PUMA: its mass on the wrist sensor, its drive's grip force, its pad sensors."""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np
import pytest

from cosmos.hand.tool import Tool
from cosmos.robots import PANDA, PUMA560
from cosmos.workcell import scene_spec, tool_spec
from tests.hand.gripper_support import (
    BLOCK,
    DOWN_TO_BLOCK,
    GRASP_BLOCK,
    HAND_MASS_KG,
    G,
    body_position,
    gripper_session,
    run_text,
)
from tests.run.run_support import BOTH_PLANTS


@pytest.mark.parametrize(
    ("robot", "hand_kg", "tcp_z_m"),
    [
        (PUMA560, HAND_MASS_KG, 0.1875),  # 12.5 mm short of the peg's tip, 200 mm out
        # The Panda's own hand (its URDF: hand 0.73 kg, fingers 0.015 kg each, TCP 103.4 mm from
        # the hand) below the 35 mm sensor housing (0.25 kg) on the flange.
        (PANDA, 0.73 + 0.03 + 0.25, 0.035 + 0.1034),
    ],
    ids=["puma560", "panda"],
)
def test_controller_knows_the_hand_as_mujoco_builds_it(robot, hand_kg: float, tcp_z_m: float) -> None:
    """The controller's tool mass, centre and inertia are the whole hand's, fingers included.

    Catches a tool spec read from the ``tool`` body alone (the fingers are bodies of their own):
    the controller would be 0.2 kg light and its gravity wrong. Compared with MuJoCo's own
    subtree mass and centre, and with the datasheet's mass.
    """
    spec = tool_spec(robot, Tool.GRIPPER)
    model = scene_spec(robot.scene_xml, Tool.GRIPPER, robot.name).compile()
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    tool = model.body("tool").id
    flange = model.site("flange").id
    assert spec.mass_kg == pytest.approx(hand_kg, abs=1e-9)
    assert spec.mass_kg == pytest.approx(model.body_subtreemass[tool], abs=1e-12)
    rotation = data.site_xmat[flange].reshape(3, 3)
    com_in_flange = rotation.T @ (data.subtree_com[tool] - data.site_xpos[flange])
    np.testing.assert_allclose(spec.com_in_flange, com_in_flange, atol=1e-12)
    assert np.all(np.linalg.eigvalsh(spec.inertia_in_flange) > 0)
    np.testing.assert_allclose(spec.tool_position_in_flange, (0.0, 0.0, tcp_z_m), atol=1e-12)


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_grasp_lift_weighs_and_grips(tmp_path: Path, ideal: bool) -> None:
    """Down to a 0.5 kg block, close at 40 N, lift 100 mm: it rises, gripped, and weighs on the wrist.

    Catches: a hand mounted above the wrist sensor (its weight missing from the reading), a
    drive whose force is not limited to the setting (pads far over 40 N), pad sensors that
    read the wrong contacts or none (compared with MuJoCo's contact forces on the pads), a
    grip that lets the block slip. Read from MuJoCo's body pose and the sensors as read.
    """
    with gripper_session(tmp_path, ideal) as session:
        plant, fingers = session.plant, session.plant.fingers
        assert fingers is not None
        session.executor.hold(0.5)
        free = plant.read_wrench_sensor()
        assert free[2] == pytest.approx(-HAND_MASS_KG * G, abs=0.3)  # sensor z up at home: the hand's weight
        run_text(session, DOWN_TO_BLOCK)
        assert fingers.read().opening_m == pytest.approx(0.085, abs=1e-4)
        run_text(session, GRASP_BLOCK)
        session.executor.hold(0.2)
        grip = fingers.read()
        assert grip.opening_m == pytest.approx(2 * BLOCK.half_extents_m[0], abs=1e-3)
        assert grip.force_left_n == pytest.approx(40.0, rel=0.05)
        assert grip.force_right_n == pytest.approx(40.0, rel=0.05)
        assert _pad_normal_force(plant.model, plant.data) == pytest.approx(40.0, rel=0.05)
        start = body_position(session, "block")
        run_text(session, "MOVE BY (0, 0, 100 mm) SPEED 0.1 m/s\n")
        session.executor.hold(0.5)
        lifted = body_position(session, "block")
        assert lifted[2] - start[2] == pytest.approx(0.100, abs=0.002)
        assert plant.read_wrench_sensor()[2] == pytest.approx(-(HAND_MASS_KG + BLOCK.mass_kg) * G, abs=0.3)
        assert fingers.read().grip_force_n == pytest.approx(40.0, rel=0.1)


def test_closing_on_nothing_closes_to_zero(tmp_path: Path) -> None:
    """Closed in free air the fingers meet (opening 0) and the pads feel nothing.

    Catches fingers that collide with each other or pad sensors that read the drive's
    force instead of a contact (they would read 40 N with nothing held).
    """
    with gripper_session(tmp_path, True, objects=()) as session:
        fingers = session.plant.fingers
        assert fingers is not None
        fingers.command(-0.15, 40.0)
        session.executor.hold(1.0)
        reading = fingers.read()
        assert reading.opening_m < 1e-4
        assert abs(reading.force_left_n) < 0.3 and abs(reading.force_right_n) < 0.3


def _pad_normal_force(model: mujoco.MjModel, data: mujoco.MjData) -> float:
    """Mean over the two pads of MuJoCo's contact normal forces on each (both strips) [N]."""
    sides = {
        model.geom(f"{pad}{part}").id: pad for pad in ("pad_left", "pad_right") for part in ("", "_lower")
    }
    pads = {"pad_left": 0.0, "pad_right": 0.0}
    force = np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        for geom in (int(contact.geom1), int(contact.geom2)):
            if geom in sides:
                mujoco.mj_contactForce(model, data, i, force)
                pads[sides[geom]] += force[0]
    return float(np.mean(list(pads.values())))
