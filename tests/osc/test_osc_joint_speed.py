"""The goal motion within the joints' speed limits, and each joint's speed brake (cosmos.osc.joint_speed).

Checked against hand-worked cases (a Jacobian inverse whose joint speeds are known) and the
compiled servo arithmetic against the readable reference on seeded random inputs.
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.joint_speed import (
    BRAKE_FRACTION,
    FULL_BRAKE_FRACTION,
    JOINT_SPEED_FRACTION,
    joint_speed_limits,
    joint_speed_ratio,
    speed_brake,
)
from cosmos.runtime.kernels.joint_speed import joint_speed_limited, speed_brake_into

KP, KV = np.full(6, 400.0), np.full(6, 40.0)


def test_a_fast_joint_slows_the_whole_goal_motion_to_its_share_of_the_limit() -> None:
    """Eq. 21 bounded the tool only: a roll at 1 rad/s asked a joint for 10 rad/s (its limit 2).

    Far from the goal eq. 21 gives the rotation W_max = 1 rad/s about z; with joint 0 turning
    10 rad per radian of it (``Jbar``'s entry), its speed is 10 rad/s. Scaled to f = 0.8 of its
    2 rad/s limit the rotation may be 0.16 rad/s, and the translation (0.1 m/s along x, joint 1
    turning 3 rad per metre: 0.3 rad/s) is scaled by the same factor, 16 times down.
    """
    jbar = np.zeros((2, 6))
    jbar[0, 5], jbar[1, 0] = 10.0, 3.0
    error = np.array([-1.0, 0.0, 0.0, 0.0, 0.0, -2.0])  # goal 1 m along x, turned 2 rad about z
    speed, angular = joint_speed_limits(error, KP, KV, (0.1, 1.0), jbar, np.array([2.0, 2.0]))
    assert JOINT_SPEED_FRACTION == 0.8
    assert angular == pytest.approx(0.16)
    assert speed == pytest.approx(0.1 * 0.16)


def test_joints_within_their_share_leave_eq_21_as_it_was() -> None:
    """A limit that does not bind must not slow the motion (nor a joint without a limit, 0)."""
    jbar = np.zeros((2, 6))
    jbar[0, 5], jbar[1, 0] = 1.0, 3.0
    error = np.array([-1.0, 0.0, 0.0, 0.0, 0.0, -2.0])
    assert joint_speed_limits(error, KP, KV, (0.1, 1.0), jbar, np.array([2.0, 0.0])) == (0.1, 1.0)
    assert joint_speed_ratio(np.array([100.0, 1.0]), np.array([0.0, 2.0]), 0.5) == pytest.approx(1.0)


def test_the_brake_is_zero_below_its_share_and_the_drives_whole_torque_at_the_limit() -> None:
    """The brake ramps from f_b to the drive's torque at f_s of the limit, against the motion."""
    limits, torque = np.array([2.0, 2.0, 0.0]), np.array([80.0, 10.0, 10.0])
    qd = np.array([BRAKE_FRACTION * 2.0, -FULL_BRAKE_FRACTION * 2.0, 50.0])
    assert speed_brake(qd, limits, torque) == pytest.approx([0.0, 10.0, 0.0])
    half = 0.5 * (BRAKE_FRACTION + FULL_BRAKE_FRACTION) * 2.0
    assert speed_brake(np.array([half, 0.0, 0.0]), limits, torque)[0] == pytest.approx(-40.0)


@pytest.mark.parametrize("uniform", [True, False])
def test_the_compiled_limit_is_the_reference(uniform: bool) -> None:
    """kernels.joint_speed.joint_speed_limited against osc.joint_speed.joint_speed_limits (seeded)."""
    rng = np.random.default_rng(3)
    for _ in range(200):
        n = int(rng.integers(6, 8))
        jbar, limits = rng.normal(size=(n, 6)), rng.uniform(0.5, 3.0, n)
        error, lookahead = rng.normal(size=6) * rng.uniform(0.001, 1.0), 0.02
        kp, kv = (KP, KV) if uniform else (rng.uniform(100, 900, 6), rng.uniform(20, 60, 6))
        rotation = np.eye(6)
        if not uniform:  # the per-axis gains act along a turned task frame
            q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
            rotation[:3, :3] = q
        speeds = (float(rng.uniform(0.01, 1.0)), float(rng.uniform(0.1, 3.0)))
        got = joint_speed_limited(
            *speeds, error, kp, kv, rotation, uniform, lookahead * jbar, lookahead, limits
        )
        turned = np.concatenate((q.T @ error[:3], q.T @ error[3:])) if not uniform else error
        in_task = jbar if uniform else jbar @ np.kron(np.eye(2), q)
        want = joint_speed_limits(turned, kp, kv, speeds, in_task, limits)
        assert got == pytest.approx(want, rel=1e-9, abs=1e-12)


def test_the_compiled_brake_is_the_reference_within_the_drives() -> None:
    """kernels.joint_speed.speed_brake_into adds osc.joint_speed.speed_brake, clipped to the drives."""
    rng = np.random.default_rng(5)
    for _ in range(200):
        limits, torque_max = rng.uniform(1.0, 3.0, 7), rng.uniform(10.0, 90.0, 7)
        qd, torque = rng.normal(size=7) * 3.0, rng.uniform(-1.0, 1.0, 7) * torque_max
        got = torque.copy()
        speed_brake_into(got, qd, limits, torque_max)
        want = np.clip(torque + speed_brake(qd, limits, torque_max), -torque_max, torque_max)
        assert got == pytest.approx(want, rel=1e-12, abs=1e-12)
