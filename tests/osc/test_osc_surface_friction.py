"""A held contact's sliding friction, learnt and compensated (cosmos.osc.surface_friction), and its kernel.

The readable reference against the update worked by hand (a tool sliding on a surface whose
friction opposes its motion), and the compiled kernel (cosmos.runtime.kernels.surface_friction)
against the reference on seeded random inputs.
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.surface_friction import (
    SURFACE_FRICTION,
    learn_surface_friction,
    surface_friction_force,
    surface_intent,
)
from cosmos.runtime.kernels.surface_friction import COEFFICIENT, FORCE, SLID, SURFACE, surface_friction_into

DT_S, LOOKAHEAD_S, BLEND = 0.001, 0.02, 0.2
OMEGA_BAR_Z = np.diag([0.0, 0.0, 1.0, 0.0, 0.0, 0.0])  # the push along world z, the rest motion axes


def test_a_sliding_tool_learns_the_friction_and_is_pushed_through_it() -> None:
    """A tool sliding along +x at 30 mm/s on a table whose friction (0.8 x 20 N) opposes it, sensed as
    the wrench it applies (+16 N along x; 25 N into the table at that moment, for a 20 N setpoint): the
    coefficient learnt is 0.8 and F_s is the share c of the friction beyond the floor, along the slide,
    nothing across or into the table. Catches the friction taken against the sensed push instead of
    the setpoint, its direction from the wrench instead of the motion, the normal leaking into the
    tangent plane, and the floor or share lost."""
    wrench = np.array([16.0, 0.0, -25.0, 0.0, 0.0, 0.0])  # the push sensed above its 20 N setpoint
    velocity = np.array([0.03, 0.0, 0.0, 0.0, 0.0, 0.0])
    motion = np.array([0.0, 0.0, -3.0, 0.0, 0.0, 0.0])  # a command into the table: not an intent
    intent = surface_intent(velocity, motion, np.zeros(6), OMEGA_BAR_Z, LOOKAHEAD_S)
    assert intent == pytest.approx([0.03, 0.0, 0.0])
    coefficient, slid, force = 0.0, False, np.zeros(3)
    for _ in range(3000):
        coefficient, slid = learn_surface_friction(
            coefficient, slid, wrench, velocity, intent, OMEGA_BAR_Z, 20.0, DT_S, SURFACE_FRICTION
        )
        force = surface_friction_force(force, coefficient, 20.0, intent, BLEND, SURFACE_FRICTION)
    assert slid
    assert coefficient == pytest.approx(0.8, rel=1e-4)
    expected = SURFACE_FRICTION.share * (16.0 - SURFACE_FRICTION.floor_n)
    assert force == pytest.approx([expected, 0.0, 0.0], rel=1e-4)


def test_before_its_first_slide_a_still_tool_takes_what_it_holds_as_a_lower_bound() -> None:
    """Static friction holds any smaller force: a tool still on the surface, told to move, takes the
    tangential force it holds (12 N against 20 N: 0.6) as the coefficient at least, keeps a larger one
    learnt, and once it has slid no longer ratchets (a still tool's force is then no measure of the
    friction). Catches the ratchet lowering the coefficient, acting after the first slide, or acting
    where nothing asks the tool to move."""
    wrench = np.array([0.0, -12.0, -20.0, 0.0, 0.0, 0.0])
    still, told = np.zeros(6), np.array([0.0, -0.01, 0.0])
    learn = learn_surface_friction
    assert learn(0.2, False, wrench, still, told, OMEGA_BAR_Z, 20.0, DT_S, SURFACE_FRICTION) == (0.6, False)
    assert learn(0.9, False, wrench, still, told, OMEGA_BAR_Z, 20.0, DT_S, SURFACE_FRICTION) == (0.9, False)
    assert learn(0.2, True, wrench, still, told, OMEGA_BAR_Z, 20.0, DT_S, SURFACE_FRICTION) == (0.2, True)
    quiet = np.array([0.0, -0.001, 0.0])  # under v_c: nothing asks it to move
    assert learn(0.2, False, wrench, still, quiet, OMEGA_BAR_Z, 20.0, DT_S, SURFACE_FRICTION) == (0.2, False)
    huge = np.array([0.0, -80.0, -20.0, 0.0, 0.0, 0.0])  # a wall, not friction: bounded
    bound = SURFACE_FRICTION.max_coefficient
    assert learn(0.2, False, huge, still, told, OMEGA_BAR_Z, 20.0, DT_S, SURFACE_FRICTION) == (bound, False)


def test_the_compensation_ramps_in_with_the_intent() -> None:
    """Near rest the compensation is the share ``|s| / v_c`` of the friction, toward s (the tool held
    within ``v_c / (L kp)`` of its goal by static friction stays there). Catches the ramp lost (a
    full push at any intent: the tool would hunt about its goal) or its direction."""
    intent = np.array([0.0, 0.4, 0.3]) * SURFACE_FRICTION.full_speed_mps * 0.5  # |s| = v_c / 4
    force = surface_friction_force(np.zeros(3), 0.5, 20.0, intent, 1.0, SURFACE_FRICTION)
    level = SURFACE_FRICTION.share * (10.0 - SURFACE_FRICTION.floor_n) * 0.25
    assert force == pytest.approx(level * np.array([0.0, 0.8, 0.6]))


def _random_omega_bar(rng: np.random.Generator) -> np.ndarray:
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    omega_bar = np.zeros((6, 6))
    omega_bar[:3, :3] = np.outer(q[:, 2], q[:, 2])  # a push along a random axis
    return omega_bar


@pytest.mark.parametrize(
    ("held", "slide", "speed", "slid"),
    [
        (True, True, 0.03, 0.0),  # sliding: learns at its rate
        (True, True, 0.001, 0.0),  # still, before its first slide: the ratchet
        (True, True, 0.001, 1.0),  # still, after: kept
        (True, False, 0.03, 1.0),  # a hold on the contact: F_s restarts, mu_s kept
        (False, False, 0.03, 1.0),  # no contact: forgotten
    ],
)
def test_the_kernel_matches_the_reference(held: bool, slide: bool, speed: float, slid: float) -> None:
    """Catches the compiled kernel drifting from cosmos.osc.surface_friction: the projection onto the
    surface, the ratio to the setpoint, the two ways of learning and their gates, the ramp, the
    low-pass, ``J^T F_s`` added to the torque, and the resets."""
    for seed in range(5):
        rng = np.random.default_rng(seed)
        n = 6
        omega_bar = _random_omega_bar(rng)
        jacobian = rng.normal(size=(6, n))
        state = np.full((SURFACE + 1, 7), np.nan)
        state[0, :6] = rng.normal(0.0, 5.0, 6)  # the wrench
        direction = rng.normal(size=6)
        direction[:3] -= omega_bar[:3, :3] @ direction[:3]
        state[2, :6] = speed * direction / np.linalg.norm(direction[:3])  # the twist, on the surface
        state[SURFACE, :5] = (rng.uniform(0.1, 0.5), slid, *rng.normal(0.0, 2.0, 3))
        motion, commanded = rng.normal(0.0, 1.0, 6), rng.normal(0.0, 0.01, 6)
        goal = np.concatenate((omega_bar[:3, :3] @ rng.normal(0.0, 10.0, 3), rng.normal(0.0, 1.0, 3)))
        torque = rng.normal(0.0, 1.0, n)
        adaption = np.array((40.0, LOOKAHEAD_S, 100.0, DT_S))
        row = state[SURFACE].copy()
        out_torque, out_state = torque.copy(), state.copy()
        surface_friction_into(
            out_torque, out_state, jacobian, omega_bar, motion, commanded, goal, held, slide, adaption, BLEND
        )
        expected_row, expected_torque = row.copy(), torque.copy()
        if not held:
            expected_row[:] = 0.0
        elif not slide:
            expected_row[FORCE : FORCE + 3] = 0.0
        else:
            push = float(np.linalg.norm(goal[:3]))
            intent = surface_intent(state[2, :6], motion, commanded, omega_bar, LOOKAHEAD_S)
            coefficient, was = learn_surface_friction(
                row[COEFFICIENT], row[SLID] != 0.0, state[0, :6], state[2, :6], intent, omega_bar, push, DT_S,
                SURFACE_FRICTION,
            )  # fmt: skip
            force = surface_friction_force(
                row[FORCE : FORCE + 3], coefficient, push, intent, BLEND, SURFACE_FRICTION
            )
            expected_row[:5] = (coefficient, float(was), *force)
            expected_torque = torque + jacobian[:3].T @ force
        np.testing.assert_allclose(out_state[SURFACE, :5], expected_row[:5], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(out_torque, expected_torque, rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(out_state[:SURFACE], state[:SURFACE])  # only its row is written
