"""The simulated plant: stepping, encoders, torque limits, contacts and the wrist sensor."""

from __future__ import annotations

from collections.abc import Callable

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from cosmos.errors import CosmosError
from cosmos.plant import Plant
from cosmos.robot_model import GRAVITY, RobotModel, build_robot_model
from cosmos.workcell import ARM_XML, HOME_Q, SCENE_XML, TOOL, fixture_frames
from tests.arm_helpers import solve_ik, tool_jacobian

KP = np.array([400.0, 400.0, 200.0, 20.0, 20.0, 20.0])  # N m/rad
KD = np.array([40.0, 40.0, 20.0, 2.0, 2.0, 2.0])  # N m s/rad


@pytest.fixture(scope="module")
def robot() -> RobotModel:
    return build_robot_model()


def gravity_of(model: pin.Model) -> Callable[[np.ndarray], np.ndarray]:
    data = model.createData()
    return lambda q: pin.computeGeneralizedGravity(model, data, q)


def hold(
    plant: Plant, gravity: Callable[[np.ndarray], np.ndarray], q_target: np.ndarray, seconds: float
) -> None:
    """Gravity compensation from a Pinocchio model plus a joint PD."""
    for _ in range(round(seconds / plant.dt_s)):
        q, qd = plant.read_encoders()
        plant.step(gravity(q) + KP * (q_target - q) - KD * qd)


def sensor_in_world(plant: Plant) -> tuple[np.ndarray, np.ndarray]:
    """The raw sensor force and torque rotated into world axes (test-side, from MuJoCo)."""
    rotation = plant.data.site("ft_sensor").xmat.reshape(3, 3)
    wrench = plant.read_wrench_sensor()
    return rotation @ wrench[:3], rotation @ wrench[3:]


@pytest.mark.parametrize("scene_xml", [ARM_XML, SCENE_XML], ids=["arm", "workcell"])
def test_scene_holds_home_without_warnings(scene_xml, robot):
    # The bare arm is held with Pinocchio's model of the bare arm, the workcell
    # with the controller's model (arm + tool).
    plant = Plant(scene_xml)
    if scene_xml == SCENE_XML:
        model = robot.model
    else:
        model = pin.buildModelFromMJCF(str(ARM_XML))
        model.gravity = pin.Motion(GRAVITY, np.zeros(3))
    hold(plant, gravity_of(model), HOME_Q, seconds=2.0)
    assert plant.time_s == pytest.approx(2.0)
    np.testing.assert_array_equal(plant.data.warning.number, 0)
    q, qd = plant.read_encoders()
    np.testing.assert_allclose(q, HOME_Q, atol=1e-4)
    np.testing.assert_allclose(qd, 0, atol=1e-4)
    assert plant.contacts() == []


def test_gravity_compensation_holds_without_joint_friction(robot):
    # With the drives' Coulomb friction off nothing else can hide a wrong g(q):
    # pure gravity compensation (no PD) must leave the arm where it is.
    plant = Plant()
    plant.model.dof_frictionloss[:] = 0
    plant.reset()
    gravity = gravity_of(robot.model)
    for _ in range(1000):
        q, _ = plant.read_encoders()
        plant.step(gravity(q))
    q, qd = plant.read_encoders()
    np.testing.assert_allclose(q, HOME_Q, atol=1e-9)
    np.testing.assert_allclose(qd, 0, atol=1e-9)


def test_reset_step_and_encoders():
    plant = Plant()
    assert plant.dt_s == 0.001
    q, qd = plant.read_encoders()
    np.testing.assert_array_equal(q, HOME_Q)
    np.testing.assert_array_equal(qd, 0)
    q[0] = 1.0  # a copy: the plant is untouched
    np.testing.assert_array_equal(plant.read_encoders()[0], HOME_Q)
    plant.step(np.zeros(6))
    assert plant.time_s == pytest.approx(0.001)
    target = HOME_Q + 0.1
    plant.reset(target)
    assert plant.time_s == 0.0
    np.testing.assert_array_equal(plant.read_encoders()[0], target)
    np.testing.assert_array_equal(plant.read_encoders()[1], 0)
    plant.reset()
    np.testing.assert_array_equal(plant.read_encoders()[0], HOME_Q)


def test_step_clips_torques_to_the_drive_limits():
    plant = Plant()
    limits = plant.model.actuator_ctrlrange[:, 1]
    plant.step(np.array([1e4, -1e4, 1e4, -1e4, 1e4, -1e4]))
    signs = np.array([1, -1, 1, -1, 1, -1])
    np.testing.assert_array_equal(plant.data.actuator_force, signs * limits)  # what the joints got


def test_scene_without_the_arm_is_refused(tmp_path):
    xml = tmp_path / "box.xml"
    xml.write_text('<mujoco><worldbody><body><joint/><geom size="0.1"/></body></worldbody></mujoco>')
    with pytest.raises(CosmosError, match="joint1"):
        Plant(xml)


def test_bare_arm_has_no_wrist_sensor():
    with pytest.raises(CosmosError, match="wrist sensor"):
        Plant(ARM_XML).read_wrench_sensor()


def test_sensor_reads_the_tool_weight_and_its_moment(robot):
    # Sign convention: the sensor gives the wrench link 6 exerts on the tool.
    # Held still, that force carries the tool's weight: +m g upward; its moment
    # about the sensor origin is (c - o) x (m g up), nonzero when the tool leans.
    weight = TOOL.mass_kg * -GRAVITY  # (0, 0, +m g)
    for q5_offset_deg in (0.0, 40.0):
        plant = Plant()
        q_target = HOME_Q + np.radians([0, 0, 0, 0, q5_offset_deg, 0])
        plant.reset(q_target)
        hold(plant, gravity_of(robot.model), q_target, seconds=0.5)
        assert np.abs(plant.read_encoders()[1]).max() < 1e-6  # still
        force, torque = sensor_in_world(plant)
        np.testing.assert_allclose(force, weight, atol=0.01 * weight[2])
        body = plant.data.body("tool")
        lever = body.xipos - plant.data.site("ft_sensor").xpos  # c - o
        moment = np.cross(lever, weight)
        if q5_offset_deg:
            assert np.linalg.norm(moment) > 0.1
        np.testing.assert_allclose(torque, moment, atol=0.01 * TOOL.mass_kg * 9.81 * 0.1)


def test_after_a_reset_the_sensor_reads_the_held_tool_before_any_step() -> None:
    """Catches a reset leaving the sensors as mj_forward has them with the drives off (the arm
    falling, the tool weightless on the sensor): the first tick's environment force was the
    tool's whole weight, 2.2 N downward, and a program's first CONTACT DOWN took it for a touch
    at t = 0.001 s. Before any step, the reading is the held tool's weight, as after a hold."""
    weight = TOOL.mass_kg * -GRAVITY  # (0, 0, +m g)
    for q5_offset_deg in (0.0, 40.0):
        plant = Plant()
        plant.reset(HOME_Q + np.radians([0, 0, 0, 0, q5_offset_deg, 0]))
        force, _ = sensor_in_world(plant)
        np.testing.assert_allclose(force, weight, atol=0.01 * weight[2])


def contact_force_on_tool(plant: Plant) -> np.ndarray:
    """Sum of the contact forces the environment exerts on the tool, world axes (from MuJoCo)."""
    model, data = plant.model, plant.data
    tool = model.body("tool").id
    total = np.zeros(3)
    for i in range(data.ncon):
        contact = data.contact[i]
        wrench = np.zeros(6)
        mujoco.mj_contactForce(model, data, i, wrench)  # on geom2, in the contact frame
        force = contact.frame.reshape(3, 3).T @ wrench[:3]
        bodies = model.geom_bodyid[contact.geom]
        if bodies[1] == tool:
            total += force
        elif bodies[0] == tool:
            total -= force
    return total


def test_press_on_the_table(robot):
    # Touch the table 5 mm below the start with 2 N, then press with 10 N,
    # commanded through J^T f from the controller's model. The drives' Coulomb
    # friction is switched off here, or it would carry part of the commanded force.
    table = fixture_frames()["table"]
    start = solve_ik(robot, pin.SE3(table.rotation, table.position - 0.005 * table.rotation[:, 2]), HOME_Q)
    plant = Plant()
    plant.model.dof_frictionloss[:] = 0
    plant.reset(start)
    damping = np.array([20.0, 20.0, 10.0, 2.0, 2.0, 2.0])
    gravity = gravity_of(robot.model)
    heights, touching, pushes, sensed = [], [], [], []

    def press(force_down: float, seconds: float) -> None:
        for _ in range(round(seconds / plant.dt_s)):
            q, qd = plant.read_encoders()
            force = np.array([0.0, 0.0, -force_down])
            plant.step(gravity(q) + tool_jacobian(robot, q)[:3].T @ force - damping * qd)
            heights.append(plant.data.site("tool").xpos[2] - table.position[2])
            touching.append(plant.data.ncon > 0)
            pushes.append(contact_force_on_tool(plant))
            sensed.append(sensor_in_world(plant)[0])

    press(2.0, 0.8)
    height_2n = heights[-1]
    press(10.0, 0.5)
    np.testing.assert_array_equal(plant.data.warning.number, 0)

    # No bouncing: once touched, the peg never leaves the table.
    first_touch = touching.index(True)
    assert all(touching[first_touch:])
    after = np.array(heights[first_touch:])
    assert np.max(after - np.minimum.accumulate(after)) < 1e-3
    # Stiff: at 10 N the tool point is less than 1 mm into the table, and moved
    # less than 1 mm from where 2 N held it.
    assert -1e-3 < heights[-1] <= 1e-5
    assert abs(heights[-1] - height_2n) < 1e-3

    # The table pushes back with 10 N: over the last 0.1 s on average, and within 15 % (the slide
    # grid's bar) at every step: the end disc's four steel contact points trade the load in
    # ripples of up to 1.05 N, some 50 ms apart.
    expected = np.array([0.0, 0.0, 10.0])
    last = np.array(pushes[-round(0.1 / plant.dt_s) :])
    np.testing.assert_allclose(last.mean(axis=0), expected, atol=0.2)
    assert np.max(np.linalg.norm(last - expected, axis=1)) < 1.5
    # The sensor: force link 6 exerts on the tool = m a - (contact + weight) (Newton's second
    # law on the tool, its centre of mass's acceleration a from MuJoCo's own RNE: the trembling
    # tool's m a is 1-40 mN); the force the tool applies to the table is then R f + m g, on
    # average (0, 0, -10) N.
    force, _ = sensor_in_world(plant)
    mujoco.mj_rnePostConstraint(plant.model, plant.data)
    acceleration = np.zeros(6)
    tool = plant.model.body("tool").id
    mujoco.mj_objectAcceleration(plant.model, plant.data, mujoco.mjtObj.mjOBJ_BODY, tool, acceleration, 0)
    inertia = TOOL.mass_kg * (acceleration[3:] + GRAVITY)  # MuJoCo's carries -g (accelerometer)
    np.testing.assert_allclose(
        force, inertia - contact_force_on_tool(plant) - TOOL.mass_kg * GRAVITY, atol=1e-6
    )
    np.testing.assert_allclose(
        np.mean(sensed[-len(last) :], axis=0) + TOOL.mass_kg * GRAVITY, -expected, atol=0.2
    )

    contacts = plant.contacts()
    assert {frozenset((c.body1, c.body2)) for c in contacts} == {frozenset(("tool", "table"))}
    assert {frozenset((c.geom1, c.geom2)) for c in contacts} == {
        frozenset(("peg_end", "table_top"))
    }  # the flat end
    assert all(-1e-3 < c.distance_m <= 0 for c in contacts)


def test_wrist_sensor_read_in_force_then_torque_order_whatever_the_scene_order(tmp_path):
    """A scene that declares the torque before the force reads the same wrench. Catches the
    six readings taken in sensordata's order instead of force then torque."""
    swapped = tmp_path / "swapped_sensors.xml"
    text = SCENE_XML.read_text()
    force = '    <force name="ft_force" site="ft_sensor"/>\n'
    torque = '    <torque name="ft_torque" site="ft_sensor"/>\n'
    assert force + torque in text
    swapped.write_text(text.replace(force + torque, torque + force))
    plants = Plant(), Plant(swapped)
    for plant in plants:
        plant.reset(HOME_Q)
        plant.step(np.zeros(6))
    np.testing.assert_array_equal(plants[1].read_wrench_sensor(), plants[0].read_wrench_sensor())
    assert np.abs(plants[0].read_wrench_sensor()).max() > 0.1  # the tool's weight at least


def test_live_signals_are_the_plants_own_buffers() -> None:
    # The servo loop reads the encoders and the sensor from these views and drives the motors
    # through ctrl: after steps they must show the new state (a copy would go stale).
    plant = Plant()
    live = plant.live_signals()
    live.ctrl[:] = (5.0, 0, 0, 0, 0, 0)
    for _ in range(50):
        plant.advance()
    q, qd = plant.read_encoders()
    np.testing.assert_array_equal(live.positions, q)
    np.testing.assert_array_equal(live.velocities, qd)
    np.testing.assert_array_equal(live.wrench_raw, plant.read_wrench_sensor())
    assert qd[0] != 0.0  # the torque written to ctrl moved joint 1
    assert not live.positions.flags.writeable
