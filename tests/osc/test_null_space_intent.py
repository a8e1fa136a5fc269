"""What the null space's torques tell the friction compensation and the hold observer
(cosmos.osc.null_space.null_space_intent, cosmos.runtime.null_space.NullSpaceTerms), against
Pinocchio's forward dynamics (ABA) on the PUMA's position task."""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from cosmos.osc.null_space import DEFAULT_ABSORPTION, null_space_intent
from cosmos.robot_model import build_robot_model
from cosmos.runtime.null_space import LinkField, NullSpaceTerms
from cosmos.runtime.parameters import ParameterLevel

ROBOT = build_robot_model()
Q = np.array((0.1, 0.7, -2.9, 0.3, -0.8, 2.8))
POSTURE = Q + np.radians((0.0, 0.0, 0.0, 30.0, 0.0, -30.0))
LOOKAHEAD_S = 0.02


def test_the_intent_is_the_look_ahead_of_the_acceleration_the_torque_asks() -> None:
    """``L A^-1 Gamma_0`` equals L times the joint acceleration Pinocchio's ABA gives the torque at
    rest (gravity held). Catches the intent taken from the torque itself (N m read as rad/s) or
    from A instead of its inverse."""
    torque = np.random.default_rng(3).normal(0.0, 5.0, 6)
    model, data = ROBOT.model, ROBOT.model.createData()
    zero = np.zeros(6)
    gravity = pin.rnea(model, data, Q, zero, zero)
    expected = LOOKAHEAD_S * pin.aba(model, data, Q, zero, torque + gravity)
    evaluation = ParameterLevel(ROBOT).evaluate(Q, zero)
    np.testing.assert_allclose(
        null_space_intent(evaluation.inertia_inv, torque, LOOKAHEAD_S), expected, rtol=1e-7
    )


def test_a_posture_drives_the_observer_and_the_intent_and_nothing_is_expected_of_it() -> None:
    """With a POSTURE on the position task the terms switch the hold observer on, ask the friction
    for the posture's joint motion (which leaves the tool point still: ``J intent = 0``), and expect
    no acceleration of the tool from it; with nothing driving the null space, or no null space,
    all three are off. Catches the observer left on in plain holds (where it only adds a dither at
    rest), the intent missing, and the posture counted as a field meant to move the tool."""
    zero = np.zeros(6)
    evaluation = ParameterLevel(ROBOT).evaluate(Q, zero)
    jacobian = evaluation.jacobian[:3]
    inertia = evaluation.inertia
    null_space_t = np.eye(6) - jacobian.T @ np.linalg.solve(
        jacobian @ np.linalg.solve(inertia, jacobian.T), jacobian @ np.linalg.inv(inertia)
    )
    terms = NullSpaceTerms(100.0, DEFAULT_ABSORPTION, (20.0, 3.0, 3e-3, 2.0), LOOKAHEAD_S)
    field = LinkField(zero, zero)
    terms.correction(null_space_t, evaluation, 1.0, field, zero, POSTURE)
    assert terms.observer_gain == 20.0
    assert np.abs(terms.intent).max() > 1e-3
    np.testing.assert_allclose(jacobian @ terms.intent, 0.0, atol=1e-9 * np.abs(terms.intent).max())
    np.testing.assert_allclose(terms.known_acceleration, 0.0, atol=1e-9)
    for nst, posture in ((null_space_t, None), (np.zeros((6, 6)), POSTURE)):
        terms.correction(nst, evaluation, 1.0, field, zero, posture)
        assert terms.observer_gain == 0.0 and not terms.intent.any() and not terms.known_acceleration.any()
