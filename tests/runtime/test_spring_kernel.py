"""The compiled spring observer (cosmos.runtime.kernels.spring) against its NumPy reference."""

from __future__ import annotations

import numpy as np

from cosmos.osc.integral_action import SPRING_OBSERVER, observe_spring_disturbance, spring_intent
from cosmos.osc.orientation import so3_exp
from cosmos.runtime.kernels import servo as sk
from cosmos.runtime.kernels.cruise import CRUISE
from cosmos.runtime.kernels.joint_speed import JOINT_SPEED_MAX
from cosmos.runtime.kernels.spring import SPRING_LAW, SPRINGS, spring_intent_into, spring_law_into

DT_S = 1e-3


def _blocks(r: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.concatenate((r.dot(v[:3]), r.dot(v[3:])))


def _random_tick(rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    """A task frame's rotation (3 x 3 and its 6 x 6 block), springs on some axes, the kernels' state
    and vectors with a random wrench in them."""
    r = so3_exp(rng.normal(size=3))
    rotation = np.zeros((6, 6))
    rotation[:3, :3] = r
    springs = np.where(rng.random(6) < 0.5, rng.uniform(0.5, 8.0, 6), 0.0)
    state = np.zeros((sk.STATE_ROWS, 6))
    vectors = np.zeros((sk.VECTORS, 6))
    vectors[SPRINGS] = springs
    state[sk.WRENCH] = rng.normal(scale=5.0, size=6)
    return r, rotation, springs, state, vectors


def test_the_spring_kernel_matches_its_reference_on_random_ticks() -> None:
    """Catches a kernel that drifts from the readable law: a wrong frame, sign, bound or axis."""
    rng = np.random.default_rng(14)
    for _ in range(200):
        r, rotation, springs, state, vectors = _random_tick(rng)
        state[sk.VELOCITY] = rng.normal(scale=0.05, size=6)
        state[SPRING_LAW] = rng.normal(scale=0.5, size=6)
        state[SPRING_LAW + 1] = rng.normal(scale=0.05, size=6)
        motion = rng.normal(size=6)
        before = state.copy()
        out = motion.copy()
        spring_law_into(out, state, vectors, rotation, DT_S)
        estimate, predicted, command = observe_spring_disturbance(
            before[SPRING_LAW],
            before[SPRING_LAW + 1],
            springs,
            _blocks(r.T, motion),
            _blocks(r.T, before[sk.VELOCITY]),
            _blocks(r.T, before[sk.WRENCH]),
            DT_S,
        )
        np.testing.assert_allclose(state[SPRING_LAW], estimate, atol=1e-12)
        np.testing.assert_allclose(state[SPRING_LAW + 1], predicted, atol=1e-12)
        np.testing.assert_allclose(out, _blocks(r, command), atol=1e-12)


def test_the_observer_leaves_the_spring_law_at_rest_in_contact() -> None:
    """Catches a spring whose press is not k x shortfall at rest: the unit mass pressed against a
    surface by the command ``s`` (the spring's pull) with a joint's static friction holding part
    of it (a disturbance d) presses ``s`` once the observer has converged."""
    mass, pull = 5.0, -1.0  # a 5 N press down, on 5 kg
    springs = np.array((0.0, 0.0, mass, 0.0, 0.0, 0.0))
    estimate, predicted = np.zeros(6), np.zeros(6)
    friction = 1.6  # N the joints hold back at rest
    for _ in range(2000):
        command = np.array((0.0, 0.0, pull, 0.0, 0.0, 0.0))
        commanded = command - estimate
        # At rest on the surface: it pushes back whatever the command and the friction leave.
        press = mass * commanded[2] + friction
        wrench = np.array((0.0, 0.0, press, 0.0, 0.0, 0.0))
        estimate, predicted, _ = observe_spring_disturbance(
            estimate, predicted, springs, command, np.zeros(6), wrench, DT_S
        )
    assert abs(press - mass * pull) < 1e-3, press
    assert abs(estimate[2] * mass - friction) < 1e-3  # the friction, observed
    assert SPRING_OBSERVER[0] > 0.0


def test_the_spring_intent_kernel_matches_its_reference_on_random_ticks() -> None:
    """Catches the kernel that takes a spring's push off the friction's intent drifting from its
    reference: a wrong frame, sign or axis (it must leave the axes that are no spring alone)."""
    rng = np.random.default_rng(15)
    for _ in range(200):
        r, rotation, springs, state, vectors = _random_tick(rng)
        acceleration = rng.normal(size=6)
        out = acceleration.copy()
        spring_intent_into(out, state, vectors, rotation)
        expected = spring_intent(_blocks(r.T, acceleration), springs, _blocks(r.T, state[sk.WRENCH]))
        np.testing.assert_allclose(out, _blocks(r, expected), atol=1e-12)


def test_a_spring_at_rest_in_balance_asks_no_friction_compensation() -> None:
    """Catches the Coulomb compensation turning the joints toward a spring's pull that a surface
    holds: pressed at its law (f = lambda F*_m), the spring axis's intent is zero; free (f = 0) it
    is the pull, as before."""
    mass, pull = 22.0, -0.7  # the PUMA's 22 kg along z, 15.4 N down
    springs = np.array((0.0, 0.0, mass, 0.0, 0.0, 0.0))
    command = np.array((0.1, 0.0, pull, 0.0, 0.0, 0.0))
    pressed = spring_intent(command, springs, np.array((0.0, 0.0, mass * pull, 0.0, 0.0, 0.0)))
    np.testing.assert_allclose(pressed, (0.1, 0.0, 0.0, 0.0, 0.0, 0.0), atol=1e-15)
    np.testing.assert_allclose(spring_intent(command, springs, np.zeros(6)), command)


def test_the_springs_rows_are_their_own() -> None:
    """Catches a spring row laid over another's: the cruise's state, the null space's intent."""
    assert SPRING_LAW == CRUISE + 1 and sk.FRICTION_ERROR == SPRING_LAW + 2  # then SURFACE, last
    assert sk.SURFACE == sk.FRICTION_ERROR + 1 and sk.STATE_ROWS == sk.SURFACE + 1
    assert (
        SPRINGS == sk.NULL_INTENT + 1 and JOINT_SPEED_MAX == SPRINGS + 1 and sk.VECTORS == JOINT_SPEED_MAX + 1
    )
