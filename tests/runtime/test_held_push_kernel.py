"""The servo's compiled held push (cosmos.runtime.kernels.held_push) against cosmos.osc.held_push.

Each kernel is run on seeded random inputs and compared with the readable NumPy function it mirrors;
the stiff surface's gain and damping are also checked against what they are derived from.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.osc.contact import LANDED_SPEED_MPS
from cosmos.osc.held_push import (
    STIFF_HELD_K_FH,
    held_gains,
    held_on_steel,
    held_push,
    held_push_cap,
    ramp_over,
    steel_damping,
)
from cosmos.osc.landing import landing_limit
from cosmos.runtime.kernels import held_push as hk
from cosmos.runtime.kernels.cruise import LANDING
from cosmos.runtime.servo_gains import ServoGains
from tests.runtime.kernel_references import close
from tests.runtime.kernel_references import omega_bar as random_omega_bar

SEEDS = range(20)


@pytest.mark.parametrize("seed", SEEDS)
def test_held_push_is_its_reference(seed: int) -> None:
    """The held push's terms against cosmos.osc.held_push.held_push, integrating on even seeds.

    Catches the terms added off the push's direction, the damping not scaled by the mass along
    it, the integral growing when the gate is shut or escaping its clamp."""
    rng = np.random.default_rng(seed)
    goal = np.concatenate((rng.normal(0.0, 10.0, 3), rng.normal(0.0, 0.5, 3)))
    m = rng.normal(size=(6, 6))
    force_to_acceleration = np.linalg.inv(m @ m.T + 3.0 * np.eye(6)) @ random_omega_bar(rng)
    force_to_acceleration[:3, :3] = np.eye(3) * rng.uniform(0.02, 1.0)  # a push the arm can make
    setpoint, sensed = rng.uniform(0.2, 1.0) * goal, rng.normal(0.0, 5.0, 6)
    velocity, feedback = rng.normal(0.0, 0.02, 6), rng.normal(0.0, 5.0, 6)
    gains = (float(rng.uniform(0.0, 1.0)), 288.0, 1000.0, 0.2)
    integral, integrate = float(rng.uniform(-0.19, 0.19)), seed % 2 == 0
    args = (goal, setpoint, sensed, velocity, force_to_acceleration)
    expected, expected_integral = held_push(feedback, *args, gains, integral, integrate, 1e-3)
    got = feedback.copy()
    got_integral = hk.held_push_into(got, *args, np.array(gains), integral, integrate, 1e-3)
    close(got, expected)
    assert got_integral == pytest.approx(expected_integral, rel=1e-12, abs=1e-15)
    assert (got_integral != integral) == integrate and abs(got_integral) <= gains[3]
    n = goal[:3] / np.linalg.norm(goal[:3])
    assert np.allclose(np.cross(got[:3] - feedback[:3], n), 0.0, atol=1e-9)  # along the push only
    assert np.array_equal(got[3:], feedback[3:])


def test_held_push_without_a_push_leaves_the_feedback() -> None:
    """No translation in F_d (a pure moment setpoint): nothing added, nothing integrated."""
    feedback, goal = np.arange(6.0), np.array((0.0, 0.0, 0.0, 0.3, 0.0, 0.0))
    args = (goal, goal, np.ones(6), np.ones(6), np.eye(6))
    got = feedback.copy()
    assert hk.held_push_into(got, *args, np.array((0.4, 288.0, 1000.0, 0.2)), 0.1, True, 1e-3) == 0.1
    assert np.array_equal(got, feedback)
    expected, integral = held_push(feedback, *args, (0.4, 288.0, 1000.0, 0.2), 0.1, True, 1e-3)
    assert integral == 0.1 and np.array_equal(expected, feedback)


@pytest.mark.parametrize("seed", SEEDS)
def test_held_push_capped_is_its_reference(seed: int) -> None:
    """The held push with its speed limit against cosmos.osc.held_push.held_push then held_push_cap
    (on steel, where a landing is set, with held_gains and steel_damping first), binding on odd
    seeds, on a landing's profile (braking, past its point, far off) or at the SPEED; on seeds 2,
    6, 10, ... the push asks more than the limit allows but does not move along itself.

    Catches the limit read off the push's direction or off the landing's slots, its braking not
    fed forward, the held integral kept while the limit binds, and a limit that binds at rest."""
    rng = np.random.default_rng(seed)
    goal = np.concatenate((rng.normal(0.0, 10.0, 3), rng.normal(0.0, 0.5, 3)))
    n = goal[:3] / np.linalg.norm(goal[:3])
    force_to_acceleration = np.eye(6) * rng.uniform(0.05, 1.0)  # a push the arm can make
    setpoint, sensed = rng.uniform(0.2, 1.0) * goal, rng.normal(0.0, 5.0, 6)
    velocity, error = rng.normal(0.0, 0.02, 6), rng.normal(0.0, 0.002, 6)
    landing = (float(-n @ error[:3]) - (0.001, -0.001, 0.01)[seed % 3], 0.004 * (seed % 4 != 0), 0.1)
    gains, dt_s, max_speed, speeds = (0.4, 288.0, 50.0, 0.2), 1e-3, 0.02, np.array((30.0, 300.0))
    feedback = rng.normal(0.0, 5.0, 6)
    to_go = float(-n @ error[:3]) - landing[0]
    limit, brake = landing_limit(max_speed, to_go, landing[1], landing[2])
    # Along the push at 0.6-1.4 times the limit (odd seeds), or back from it, at 0-1 times (even).
    share = rng.uniform(0.6, 1.4) if seed % 2 else -rng.uniform(0.0, 1.0)
    velocity[:3] += (share * limit - float(n @ velocity[:3])) * n
    # The asked push 50 N above (odd seeds, and 2, 6, ...) or below (0, 4, ...) what the limit allows.
    along, inverse_mass = float(n @ velocity[:3]), float(n @ force_to_acceleration[:3, :3] @ n)
    allowed = float(n @ sensed[:3]) + (-brake + 300.0 * (limit - along) + 30.0 * along) / inverse_mass
    if seed % 5 == 0:  # the ramp over on these seeds (and 3, 7, 11, ...)
        setpoint = goal.copy()
    elif seed % 4 == 3:
        setpoint = goal * 0.5 + goal * 0.5
    steel = landing[1] > 0.0  # landed (integrating) on steel: held_gains

    def reference(feedback: np.ndarray) -> tuple[np.ndarray, float]:
        on_steel, damped = feedback, velocity
        if held_on_steel(landing[1], True, goal, setpoint):
            on_steel, damped = steel_damping(feedback, goal, velocity, force_to_acceleration, 30.0)
        args = (goal, setpoint, sensed, damped, force_to_acceleration, held_gains(gains, steel))
        return held_push(on_steel, *args, 0.1, True, dt_s)

    held, _ = reference(feedback)
    feedback[:3] += (allowed - float(n @ held[:3]) + (50.0 if seed % 4 else -50.0)) * n
    expected, expected_integral = reference(feedback)
    expected, limited = held_push_cap(
        expected, goal, sensed, velocity, force_to_acceleration, error, max_speed, landing, 300.0, 30.0
    )
    got, integral, scalars = feedback.copy(), np.array((0.1,)), np.zeros(LANDING + 3)
    scalars[LANDING : LANDING + 3] = landing
    args = (goal, setpoint, sensed, velocity, error, force_to_acceleration, np.array(gains), True, dt_s)
    assert hk.held_push_capped_into(got, integral, *args, max_speed, speeds, scalars) == limited
    assert limited == bool(seed % 2)
    close(got, expected)
    assert integral[0] == (0.0 if limited else pytest.approx(expected_integral, rel=1e-12))


@pytest.mark.parametrize("seed", SEEDS)
def test_steel_damping_is_its_reference(seed: int) -> None:
    """The landed push's damping on steel against cosmos.osc.held_push.steel_damping, and its law.

    Along the push, speeds within the band (even seeds) are all given back to eq. 18's damping
    (``k_vf m_n v_n``) and leave the held push's none; beyond it (odd seeds) only the band's share.
    Catches the band applied across the push, its sign lost, or eq. 18's share not given back."""
    rng = np.random.default_rng(seed)
    goal = np.concatenate((rng.normal(0.0, 10.0, 3), rng.normal(0.0, 0.5, 3)))
    n = goal[:3] / np.linalg.norm(goal[:3])
    force_to_acceleration = np.eye(6) * rng.uniform(0.05, 1.0)
    velocity, feedback = rng.normal(0.0, 0.02, 6), rng.normal(0.0, 5.0, 6)
    along = float(rng.uniform(-1.0, 1.0)) * LANDED_SPEED_MPS * (3.0 if seed % 2 else 1.0)
    velocity[:3] += (along - float(n @ velocity[:3])) * n
    expected, damped = steel_damping(feedback, goal, velocity, force_to_acceleration, 30.0)
    got = feedback.copy()
    got_damped = hk.steel_damping_into(got, goal, velocity, force_to_acceleration, 30.0, LANDED_SPEED_MPS)
    close(got, expected)
    close(got_damped, damped)
    beyond = math.copysign(max(abs(along) - LANDED_SPEED_MPS, 0.0), along)
    mass = 1.0 / float(n @ force_to_acceleration[:3, :3] @ n)
    close(got[:3] - feedback[:3], 30.0 * mass * (along - beyond) * n)
    assert float(n @ got_damped[:3]) == pytest.approx(beyond, abs=1e-15)
    close(got_damped - (n @ got_damped[:3]) * np.r_[n, 0, 0, 0], velocity - along * np.r_[n, 0, 0, 0])


def test_the_stiff_push_loop_gain_is_under_one() -> None:
    """On steel the sensed push follows the command within a tick: ``F(k+1) = (1 + k) F_d - k F(k)``.

    With eq. 18's ``k_f`` and the held push's ``k_fh`` that loop (independent of the code: the
    sequence itself) converges to ``F_d`` only if ``k = k_f + k_fh < 1``. Catches the stiff gain
    raised back to the table's 0.8 (``k`` = 1.4: the Panda's 30 N CONTACT on the hole's top rang
    into bounces of 0-62 N), or eq. 18's ``k_f`` raised past what the stiff gain leaves."""
    gains = ServoGains()
    table = held_gains(gains.held_push, stiff=False)
    steel = held_gains(gains.held_push, stiff=True)
    assert table == gains.held_push and steel[1:] == table[1:] and steel[0] == STIFF_HELD_K_FH

    def last_error(k: float) -> float:
        push, goal = 0.0, 10.0
        for _ in range(200):
            push = (1.0 + k) * goal - k * push
        return abs(push - goal)

    assert last_error(gains.force.k_f + steel[0]) < 1e-6
    assert last_error(gains.force.k_f + table[0]) > 1.0


def test_held_on_steel_waits_for_the_ramp() -> None:
    """The gate of steel_damping, compiled and readable: a landing, landed, the ramp over.

    Catches the gate opened while the force setpoint still ramps (the impact's rise passes the goal
    latch: FORCE 8 N at 5 mm/s then peaked 1 N higher) or without a landing (the table's holds)."""
    goal = np.array((0.0, 0.0, -8.0, 0.0, 0.0, 0.0))
    for setpoint, over in ((goal, True), (0.99 * goal, False), (goal * 0.3 + goal * 0.7, True)):
        assert hk.ramp_over(goal, setpoint) == over == ramp_over(goal, setpoint)
        assert held_on_steel(0.004, True, goal, setpoint) == over
    assert not held_on_steel(0.0, True, goal, goal) and not held_on_steel(0.004, False, goal, goal)
