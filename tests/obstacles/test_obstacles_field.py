"""The FIRAS field's joint torques against finite differences of its own potential and of the kinematics."""

from __future__ import annotations

import dataclasses

import numpy as np
import pinocchio as pin
import pytest

from cosmos.errors import CosmosError
from cosmos.obstacles import FieldParameters, ObstacleField, arm_capsules
from cosmos.obstacles.obstacle import Obstacle, box, cylinder, sphere
from cosmos.obstacles.proximity import capsule_proximity
from cosmos.osc.firas import firas_potential
from cosmos.workcell import HOME_Q
from tests.obstacles.obstacle_scenes import robot

EVERY_CALL = FieldParameters(period_s=0.0, geometry_every=1)  # measured at each call
UNCAPPED = dataclasses.replace(EVERY_CALL, damping_ns_per_m=0.0, force_cap_n=1e9)


def _potential(q: np.ndarray, obstacles: list[Obstacle], parameters: FieldParameters) -> float:
    """Sum over links and obstacles of U(rho) at the link's closest capsule, from scratch."""
    model = robot().model
    data = model.createData()
    pin.forwardKinematics(model, data, q)
    caps = arm_capsules(robot())
    total = 0.0
    for obstacle in obstacles:
        nearest: dict[int, float] = {}
        for i in range(len(caps)):
            joint = data.oMi[int(caps.joint[i]) + 1]
            a, b = joint.act(caps.a_in_joint[i]), joint.act(caps.b_in_joint[i])
            rho = capsule_proximity(a, b, float(caps.radius_m[i]), obstacle, obstacle.position_world).distance
            k = int(caps.joint[i])
            nearest[k] = min(nearest.get(k, np.inf), rho)
        total += sum(
            float(firas_potential(rho, parameters.influence_m, parameters.eta)) for rho in nearest.values()
        )
    return total


SCENES = {
    "sphere_at_tool": [sphere("ball", (0.68, -0.15, 0.52), 0.05)],
    "box_by_wrist": [box("wall", (0.60, -0.03, 0.62), (0.3, 0.02, 0.2))],
    "post_over_forearm": [cylinder("post", (0.43, -0.13, 1.22), 0.04, 0.5)],
    "two": [sphere("ball", (0.68, -0.15, 0.52), 0.05), box("wall", (0.60, -0.03, 0.62), (0.3, 0.02, 0.2))],
}


@pytest.mark.parametrize("name", list(SCENES))
def test_torque_is_minus_the_gradient_of_the_potential(name: str) -> None:
    """Gamma = J_c^T F with F = -dU/dx makes Gamma = -dU/dq (central differences)."""
    field = ObstacleField(robot(), UNCAPPED)
    for obstacle in SCENES[name]:
        field.add(obstacle)
    q = HOME_Q + np.array([0.02, -0.01, 0.02, 0.1, -0.05, 0.2])
    torque = field.torque(q, np.zeros(6), 0.0)
    assert np.linalg.norm(torque) > 0.1  # the scene is within reach of the field
    assert all(0.01 < i.distance_m < 0.1 for i in field.influences)
    step = 1e-6
    gradient = np.array(
        [
            (
                _potential(q + step * e, SCENES[name], UNCAPPED)
                - _potential(q - step * e, SCENES[name], UNCAPPED)
            )
            / (2 * step)
            for e in np.eye(6)
        ]
    )
    np.testing.assert_allclose(torque, -gradient, rtol=1e-4, atol=1e-4 * np.abs(gradient).max())


def test_nothing_acts_beyond_the_influence_distance_or_when_switched_off() -> None:
    field = ObstacleField(robot(), EVERY_CALL)
    field.add(sphere("far", (0.0, 1.5, 0.5), 0.1))
    assert not np.any(field.torque(HOME_Q, np.zeros(6), 0.0))
    assert field.influences == ()
    field.add(sphere("near", (0.64, -0.15, 0.52), 0.05))
    assert np.any(field.torque(HOME_Q, np.zeros(6), 0.0))
    field.enabled = False
    assert not np.any(field.torque(HOME_Q, np.zeros(6), 0.0))
    assert [i.obstacle for i in field.influences] == ["near"]  # still reported
    assert field.influences[0].link == "link6"


def test_damping_resists_the_approach_only() -> None:
    """A velocity toward the obstacle adds a force that opposes it; moving away adds none."""
    ball = sphere("ball", (0.66, -0.15, 0.52), 0.05)
    plain = ObstacleField(robot(), dataclasses.replace(EVERY_CALL, damping_ns_per_m=0.0))
    damped = ObstacleField(robot(), EVERY_CALL)
    plain.add(ball)
    damped.add(ball)
    # Joint 2 turning positively moves the tool outward (+x), toward the ball.
    jac = pin.computeFrameJacobian(
        robot().model, robot().model.createData(), HOME_Q, robot().tool_frame, pin.LOCAL_WORLD_ALIGNED
    )
    qd = np.linalg.solve(jac, np.array([0.2, 0, 0, 0, 0, 0]))  # tool at 0.2 m/s toward +x
    extra_in = damped.torque(HOME_Q, qd, 0.0) - plain.torque(HOME_Q, qd, 0.0)
    extra_out = damped.torque(HOME_Q, -qd, 0.0) - plain.torque(HOME_Q, -qd, 0.0)
    assert extra_in.dot(qd) < 0.0  # dissipates energy of the approach
    assert not np.any(extra_out)


def test_a_moving_obstacle_is_taken_where_it_is_now_and_its_approach_is_damped() -> None:
    ball = sphere("ball", (0.94, -0.15, 0.52), 0.05, velocity_mps=(-0.1, 0.0, 0.0))
    every_time = EVERY_CALL
    field = ObstacleField(robot(), every_time)
    field.add(ball)
    assert not np.any(field.torque(HOME_Q, np.zeros(6), 0.0))  # 0.24 m away at t = 0
    at_2s = field.torque(HOME_Q, np.zeros(6), 2.4)  # now at x = 0.70, 44 mm from the peg
    still = ObstacleField(robot(), every_time)
    still.add(sphere("ball", (0.70, -0.15, 0.52), 0.05))
    at_rest = still.torque(HOME_Q, np.zeros(6), 0.0)
    assert np.any(at_rest)
    # The same place; the ball closing in at 0.1 m/s pushes harder than a still one.
    jac = pin.computeFrameJacobian(
        robot().model, robot().model.createData(), HOME_Q, robot().tool_frame, pin.LOCAL_WORLD_ALIGNED
    )
    push_tool = np.linalg.solve(jac.T, at_2s)[:3]
    push_rest = np.linalg.solve(jac.T, at_rest)[:3]
    assert push_tool[0] < push_rest[0] < 0.0


def test_gain_scale_and_influence_per_obstacle() -> None:
    base = sphere("ball", (0.70, -0.15, 0.52), 0.05)
    torques = {}
    for label, obstacle in {
        "default": base,
        "double": dataclasses.replace(base, gain_scale=2.0),
        "short": dataclasses.replace(base, influence_m=0.02),
    }.items():
        field = ObstacleField(robot(), UNCAPPED)
        field.add(obstacle)
        torques[label] = field.torque(HOME_Q, np.zeros(6), 0.0)
    np.testing.assert_allclose(torques["double"], 2.0 * torques["default"])
    assert not np.any(torques["short"])  # the peg is ~40 mm away


def test_within_its_period_the_field_holds_its_torque() -> None:
    field = ObstacleField(robot())  # period 8 ms
    field.add(sphere("ball", (0.70, -0.15, 0.52), 0.05))
    first = field.torque(HOME_Q, np.zeros(6), 0.0).copy()
    moved = HOME_Q + np.array([0.0, 0.05, 0.0, 0.0, 0.0, 0.0])
    np.testing.assert_array_equal(field.torque(moved, np.zeros(6), 0.004), first)  # held
    assert not np.array_equal(field.torque(moved, np.zeros(6), 0.008), first)  # evaluated


def test_names_are_unique() -> None:
    field = ObstacleField(robot())
    field.add(sphere("ball", (0.0, 1.0, 0.5), 0.1))
    with pytest.raises(CosmosError, match="already"):
        field.add(sphere("ball", (0.0, 1.0, 0.5), 0.1))
    field.remove("ball")
    with pytest.raises(CosmosError, match="no obstacle 'ball'"):
        field.remove("ball")


def test_between_measurements_the_approach_is_estimated_to_first_order() -> None:
    """With geometry measured every other evaluation, the estimate is close to a measurement."""
    ball = sphere("ball", (0.70, -0.15, 0.52), 0.05)
    estimating = ObstacleField(robot(), dataclasses.replace(EVERY_CALL, geometry_every=2))
    measuring = ObstacleField(robot(), EVERY_CALL)
    estimating.add(ball)
    measuring.add(ball)
    qd = np.array([0.3, 1.0, -0.5, 0.0, 0.2, 0.0])  # rad/s: the tool moves a few mm in 4 ms
    estimating.torque(HOME_Q, qd, 0.0)  # measured
    q = HOME_Q + 0.004 * qd
    estimated = estimating.torque(q, qd, 0.004)
    measured = measuring.torque(q, qd, 0.004)
    assert estimating.influences[0].distance_m == pytest.approx(measuring.influences[0].distance_m, abs=2e-5)
    np.testing.assert_allclose(estimated, measured, rtol=0.05, atol=0.01 * np.abs(measured).max())


def test_parameters_are_checked() -> None:
    with pytest.raises(CosmosError, match="geometry_every"):
        FieldParameters(geometry_every=0)
    with pytest.raises(CosmosError, match="rho_0"):
        FieldParameters(influence_m=-0.1)
