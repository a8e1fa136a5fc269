"""The servo's compiled contact laws (cosmos.runtime.kernels.contact) against their cosmos.osc references.

Each kernel is run on seeded random inputs and at its edges (a push at the
threshold, a speed at its bound, an intent at the clip) and compared with the
readable NumPy function it mirrors (cosmos.osc.contact, .admittance, .friction, .unified).
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.osc.admittance import admittance_command, admittance_speed, low_pass
from cosmos.osc.contact import contact_latched, touch_latched
from cosmos.osc.force import selection
from cosmos.osc.friction import coulomb_compensation, friction_intent
from cosmos.osc.held_push import touch_damping
from cosmos.osc.orientation import so3_exp
from cosmos.osc.tilt_window import insert_compliance, integrated_force_error, tilt_window
from cosmos.osc.unified import REACH_FRACTION, force_goal_reached, speed_limited_push
from cosmos.runtime.kernels import contact as ck
from tests.runtime.kernel_references import close
from tests.runtime.kernel_references import omega_bar as random_omega_bar

SEEDS = range(20)


@pytest.mark.parametrize("seed", SEEDS)
def test_the_latches_are_their_references(seed: int) -> None:
    """Catches a latch that reads the wrong part of the wrench (moments for forces, world for
    selected axes), that resets once set, or that compares with >= where the reference has >."""
    rng = np.random.default_rng(seed)
    omega_bar = random_omega_bar(rng)
    wrench = rng.normal(0.0, 2.0, 6)
    threshold = float(rng.uniform(0.5, 3.0))
    for before in (False, True):
        assert ck.touch_latched(before, omega_bar, wrench, threshold) == touch_latched(
            before, omega_bar, wrench, threshold
        )
        assert ck.contact_latched(before, wrench, threshold) == contact_latched(before, wrench, threshold)


def test_the_latches_at_their_threshold() -> None:
    """A push exactly at the threshold does not latch, one just above does, a set latch stays set.

    Catches >= for >, the moment part counted as a contact force, and a latch that drops."""
    threshold = 2.0
    at = np.array((0.0, 0.0, 2.0, 50.0, -50.0, 50.0))  # big moments, force exactly at the threshold
    above = at * np.array((1.0, 1.0, 1.0 + 1e-12, 1.0, 1.0, 1.0))
    z_force = selection((True, True, False, True, True, True), np.eye(3)).omega_bar
    for wrench, expected in ((at, False), (above, True)):
        assert ck.contact_latched(False, wrench, threshold) is contact_latched(False, wrench, threshold)
        assert contact_latched(False, wrench, threshold) is expected
        assert ck.touch_latched(False, z_force, wrench, threshold) is expected
        assert touch_latched(False, z_force, wrench, threshold) is expected
    assert ck.contact_latched(True, np.zeros(6), threshold) and ck.touch_latched(
        True, z_force, np.zeros(6), 1.0
    )
    # A force on a motion axis only: the touch latch stays open, the contact latch closes.
    sideways = np.array((5.0, 0.0, 0.0, 0.0, 0.0, 0.0))
    assert not ck.touch_latched(False, z_force, sideways, threshold)
    assert ck.contact_latched(False, sideways, threshold)


@pytest.mark.parametrize("seed", SEEDS)
def test_goal_reached_is_its_reference(seed: int) -> None:
    """The force integral's gate (push along the goal >= 90 % of it) against
    cosmos.osc.unified.force_goal_reached, around the boundary and latched.

    Catches a gate on the push's size rather than along the goal, a wrong fraction, or a latch that drops."""
    rng = np.random.default_rng(seed)
    goal = np.concatenate((rng.normal(0.0, 10.0, 3), np.zeros(3)))
    for share in (0.5, REACH_FRACTION - 1e-6, REACH_FRACTION + 1e-6, 1.3):
        sideways = np.cross(goal[:3], rng.normal(0.0, 1.0, 3))  # orthogonal to the goal: no share
        wrench = np.concatenate((share * goal[:3] + sideways, rng.normal(0.0, 5.0, 3)))
        expected = force_goal_reached(goal, wrench)
        assert expected is (share >= REACH_FRACTION)
        assert ck.goal_reached(False, goal, wrench, REACH_FRACTION) is expected
        assert ck.goal_reached(True, goal, wrench, REACH_FRACTION)


@pytest.mark.parametrize("seed", SEEDS)
def test_low_pass_is_its_reference(seed: int) -> None:
    """Catches the blend applied to the wrong side (``sample + b (previous - sample)``)."""
    rng = np.random.default_rng(seed)
    previous, sample, blend = rng.normal(size=6), rng.normal(size=6), float(rng.uniform(0.0, 1.0))
    filtered = previous.copy()
    ck.low_pass_into(filtered, sample, blend)
    close(filtered, low_pass(previous, sample, blend))


def _admittance_axes(rng: np.random.Generator) -> np.ndarray:
    """Omega_a: RX and RY of a random task frame (force axes of the plan, motion axes of the servo)."""
    rotation = so3_exp(rng.uniform(-3.0, 3.0, 3))
    plan = selection((True, True, False, False, False, True), rotation)
    servo = selection((True, True, False, True, True, True), rotation)
    return plan.omega_bar - servo.omega_bar


@pytest.mark.parametrize("seed", SEEDS)
def test_admittance_is_its_reference(seed: int) -> None:
    """Speed and command against cosmos.osc.admittance, with the bound binding on odd seeds.

    Catches the bound taken on the whole twist (or the linear part), the error's sign
    (M_f - F_d), the servo on every axis instead of Omega_a's, or the held motion dropped."""
    rng = np.random.default_rng(seed)
    omega_a = _admittance_axes(rng)
    setpoint, moment = rng.normal(0.0, 1.0, 6), rng.normal(0.0, 1.0, 6)
    gain = float(rng.uniform(1.0, 30.0))
    unbounded = np.linalg.norm((gain * omega_a @ (setpoint - moment))[3:])
    bound = 0.5 * unbounded if seed % 2 else 2.0 * unbounded
    speed = ck.admittance_speed(omega_a, setpoint, moment, gain, bound)
    expected = admittance_speed(omega_a, setpoint, moment, gain, bound)
    close(speed, expected)
    assert np.linalg.norm(speed[3:]) == pytest.approx(min(bound, unbounded), rel=1e-12)
    motion, velocity, kv = rng.normal(0.0, 5.0, 6), rng.normal(0.0, 0.3, 6), float(rng.uniform(10.0, 60.0))
    close(
        ck.admittance_command(omega_a, motion, speed, velocity, kv),
        admittance_command(omega_a, motion, expected, velocity, kv),
    )


def test_admittance_speed_at_its_bound_and_at_rest() -> None:
    """At the bound exactly the speed is left alone; no moment error, no speed (no 0/0).

    Catches a bound that scales at equality, and a norm divided through when it is zero."""
    omega_a = _admittance_axes(np.random.default_rng(3))
    setpoint = np.array((0.0, 0.0, -10.0, 0.4, -0.3, 0.0))
    moment = np.zeros(6)
    speed = admittance_speed(omega_a, setpoint, moment, 2.0, 1.0)
    at_bound = float(np.linalg.norm(speed[3:]))
    close(ck.admittance_speed(omega_a, setpoint, moment, 2.0, at_bound), speed)
    still = ck.admittance_speed(omega_a, setpoint, setpoint, 2.0, 0.0)
    assert np.array_equal(still, np.zeros(6)) and np.array_equal(
        admittance_speed(omega_a, setpoint, setpoint, 2.0, 0.0), np.zeros(6)
    )


def _friction_inputs(rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    jbar = np.eye(6) + rng.normal(0.0, 0.5, (6, 6))
    return (
        rng.normal(0.0, 0.02, 6),  # qd, [rad/s]
        jbar,
        rng.normal(0.0, 0.5, 6),  # commanded acceleration
        rng.normal(0.0, 0.02, 6),  # commanded speed
        rng.uniform(0.5, 25.0, 6),  # Gamma_c(+), [N m]
        rng.uniform(0.5, 25.0, 6),  # Gamma_c(-), [N m]
        rng.uniform(-5.0, 5.0, 6),  # previous Gamma_f
    )


@pytest.mark.parametrize("seed", SEEDS)
def test_coulomb_compensation_is_its_reference(seed: int) -> None:
    """The kernel's ``(dz(qd) + L Jbar (a + xd_c / L)) / v_c`` equals the reference's
    ``dz(qd) + Jbar (L a + xd_c)``, with a dead band ``d`` per joint (some joints' speeds
    inside it, some beyond it on either side).

    Catches the look-ahead applied to the commanded speed too, the clip on the torque instead
    of the intent, the low-pass's blend reversed, the torque not receiving the result, and the
    dead band clipping the speed instead of shifting it (or ignoring its sign)."""
    rng = np.random.default_rng(seed)
    qd, jbar, acceleration, speed, positive_nm, negative_nm, previous = _friction_inputs(rng)
    lookahead_s, full_speed, blend = 0.02, float(rng.uniform(0.005, 0.05)), float(rng.uniform(0.01, 1.0))
    dead_band = rng.uniform(0.0, 0.03, 6)
    intent = friction_intent(qd, jbar, acceleration, speed, lookahead_s, full_speed, dead_band)
    expected = coulomb_compensation(previous, positive_nm, negative_nm, intent, blend)
    torque, coulomb = rng.normal(0.0, 10.0, 6), previous.copy()
    torque_before = torque.copy()
    kernel_acceleration = acceleration + speed / lookahead_s  # as servo_tick passes it
    ck.coulomb_compensation_into(
        torque, coulomb, qd, lookahead_s * jbar, kernel_acceleration, positive_nm, negative_nm,
        dead_band, False, 1.0 / full_speed, blend,
    )  # fmt: skip
    close(coulomb, expected)
    close(torque, torque_before + expected)


def test_coulomb_compensation_at_the_clip_by_direction() -> None:
    """An intent far beyond +-1 asks for exactly Gamma_c(+) turning positively and -Gamma_c(-)
    negatively; with blend 1 that is the torque; at rest with no command it decays toward zero.

    Catches a clip missing (torque growing with speed), a sign flipped on a joint, or the two
    directions' levels swapped or averaged (the PUMA's joint 2: 13.6 N m up, 7.7 N m down)."""
    positive_nm, negative_nm = np.arange(1.0, 7.0), np.arange(11.0, 17.0)
    qd = np.array((1.0, -1.0, 1.0, -1.0, 1.0, -1.0))  # 100 x v_c
    zero = np.zeros(6)
    coulomb, torque = zero.copy(), zero.copy()
    levels = (positive_nm, negative_nm)
    ck.coulomb_compensation_into(torque, coulomb, qd, np.eye(6), zero, *levels, zero, False, 100.0, 1.0)
    intent = friction_intent(qd, np.eye(6), zero, zero, 1.0, 0.01)
    close(coulomb, coulomb_compensation(zero, positive_nm, negative_nm, intent, 1.0))
    close(coulomb, np.where(qd > 0, positive_nm, -negative_nm))
    previous = coulomb.copy()
    ck.coulomb_compensation_into(torque, coulomb, zero, np.eye(6), zero, *levels, zero, False, 100.0, 0.25)
    close(coulomb, 0.75 * previous)
    close(coulomb, coulomb_compensation(previous, positive_nm, negative_nm, zero, 0.25))


@pytest.mark.parametrize("seed", SEEDS)
def test_speed_limited_push_is_its_reference(seed: int) -> None:
    """The push's speed cap against cosmos.osc.unified.speed_limited_push, binding on odd seeds.

    Catches the cap applied off the push's direction, the sensed force left out of the allowance."""
    rng = np.random.default_rng(seed)
    goal = np.concatenate((rng.normal(0.0, 10.0, 3), rng.normal(0.0, 0.5, 3)))
    n = goal[:3] / np.linalg.norm(goal[:3])
    m = rng.normal(size=(6, 6))
    force_to_acceleration = np.linalg.inv(m @ m.T + 3.0 * np.eye(6)) @ random_omega_bar(rng)
    force_to_acceleration[:3, :3] = np.eye(3) * rng.uniform(0.1, 1.0)  # a push the arm can make
    sensed, velocity = rng.normal(0.0, 5.0, 6), rng.normal(0.0, 0.05, 6)
    max_speed, kv, k_vf = float(rng.uniform(0.005, 0.05)), 40.0, 30.0
    feedback = rng.normal(0.0, 5.0, 6)
    # Put the asked push 50 N above (odd seeds) or below (even) the reference's allowance.
    inverse_mass = float(n @ force_to_acceleration[:3, :3] @ n)
    along = float(n @ velocity[:3])
    allowed = float(n @ sensed[:3]) + (kv * (max_speed - along) + k_vf * along) / inverse_mass
    rise = float(rng.uniform(0.0, 0.3))  # the speed reference's own acceleration (osc.push_speed)
    allowed += rise / inverse_mass
    feedback[:3] += (allowed - float(n @ feedback[:3]) + (50.0 if seed % 2 else -50.0)) * n
    args = (goal, sensed, velocity, force_to_acceleration, max_speed, kv, k_vf, rise)
    expected, limited = speed_limited_push(feedback, *args)
    got = feedback.copy()
    got_limited, got_along = ck.speed_limited_push_into(got, *args)
    assert got_limited == limited == bool(seed % 2)
    close(got, expected)
    assert got_along == pytest.approx(along, rel=1e-12, abs=1e-15)


def test_speed_limited_push_without_a_push_leaves_the_feedback() -> None:
    """No translation in F_d (a pure moment setpoint): nothing to cap."""
    feedback = np.arange(6.0)
    goal = np.array((0.0, 0.0, 0.0, 0.3, 0.0, 0.0))
    args = (goal, np.zeros(6), np.zeros(6), np.eye(6), 0.01, 40.0, 30.0, 0.1)
    got = feedback.copy()
    assert ck.speed_limited_push_into(got, *args) == (False, 0.0)
    assert np.array_equal(got, feedback)
    expected, limited = speed_limited_push(feedback, *args)
    assert not limited and np.array_equal(expected, feedback)


@pytest.mark.parametrize("seed", SEEDS)
def test_touch_damping_is_its_reference(seed: int) -> None:
    """The touch's damping against cosmos.osc.held_push.touch_damping: a push above the touch's
    force on what the tool moves toward (even seeds), one below it or moving away (odd seeds),
    the tool's own inertia at the commanded acceleration added to the sensed push.

    Catches damping applied to a motion away from the push (a sphere pushing the tool aside
    would be resisted), below the touch's force, to the tool's own inertia (a 5 cm step ran
    37 mm off its unit-mass response), or off its line."""
    rng = np.random.default_rng(seed)
    velocity, motion = rng.normal(0.0, 0.05, 6), rng.normal(0.0, 3.0, 6)
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    toward = seed % 2 == 0
    velocity[:3] += (0.03 if toward else -0.03) * n - n * float(n @ velocity[:3])
    wrench = np.concatenate((rng.uniform(9.0, 40.0) * n, rng.normal(0.0, 0.5, 3)))
    touch_n = 8.0 if seed % 4 != 1 else float(np.linalg.norm(wrench[:3])) + 1.0  # before the inertia
    mass = 0.65
    wrench[:3] += mass * motion[:3]  # the tool's own inertia at the commanded acceleration
    expected = touch_damping(motion, wrench, velocity, 1000.0, touch_n, mass)
    got = motion.copy()
    ck.touch_braking_into(got, wrench, velocity, np.array((touch_n, mass, 1000.0)), 0.0)  # as a spring's
    close(got, expected)
    damped = not np.array_equal(got, motion)
    assert damped == toward
    if damped:
        assert np.allclose(got[:3] - motion[:3], -1000.0 * 0.03 * n) and np.array_equal(got[3:], motion[3:])


@pytest.mark.parametrize("seed", SEEDS)
def test_tilt_window_is_its_reference(seed: int) -> None:
    """The tilt window's stop against cosmos.osc.tilt_window.tilt_window: a tilt beyond the
    window (even seeds) or within it (odd seeds).

    Catches the stop acting inside the window (an INSERT's peg could not tip into the mouth),
    pushing the tilt further out instead of back, or touching the speed's translation."""
    rng = np.random.default_rng(seed)
    speed, tilt = rng.normal(0.0, 0.2, 6), rng.normal(0.0, 1.0, 6)
    window = 0.1745
    size = rng.uniform(1.2, 3.0) * window if seed % 2 == 0 else rng.uniform(0.0, 0.95) * window
    tilt[3:] *= size / np.linalg.norm(tilt[3:])
    expected = tilt_window(speed, tilt, window, 20.0)
    got = speed.copy()
    ck.tilt_window_into(got, tilt, window, 20.0)
    close(got, expected)
    assert np.array_equal(got[:3], speed[:3])
    turned_back = float(np.dot(got[3:] - speed[3:], tilt[3:]))
    if seed % 2 == 0:
        assert turned_back == pytest.approx(-20.0 * (size - window) * size, rel=1e-9)
    else:
        assert np.array_equal(got, speed)


@pytest.mark.parametrize("seed", SEEDS)
def test_insert_compliance_is_its_reference(seed: int) -> None:
    """The INSERT's window by depth and its push across against
    cosmos.osc.tilt_window.insert_compliance: a push in a random direction, the tool short of
    the mouth (seeds 0, 3, ...), in it (1, 4, ...) or just past ``d_in`` (2, 5, ...), a random
    Omega_bar.

    Catches the kernel's depth read along another axis, its push's cross product turned round,
    the push fed where Omega_bar has no force axis, or ``setpoint`` or ``speed`` written beyond
    what the reference changes."""
    rng = np.random.default_rng(seed)
    speed, tilt, setpoint = rng.normal(0.0, 0.2, 6), rng.normal(0.0, 0.2, 6), rng.normal(0.0, 3.0, 6)
    goal = rng.normal(0.0, 8.0, 6)
    n = goal[:3] / np.linalg.norm(goal[:3])
    params = np.array((0.1745, 20.0, 0.002, 0.026, 4.0, 0.6, 0.005))
    velocity = rng.normal(0.0, 0.004, 6)
    depth = (0.0005, 0.004, 0.00201)[seed % 3]
    error = rng.normal(0.0, 0.003, 6)
    error[:3] += (depth - float(n @ error[:3])) * n
    omega_bar = random_omega_bar(rng)
    wrench = goal * rng.uniform(0.5, 1.5) + rng.normal(0.0, 2.0, 6)  # pressing, more or less
    expected_speed, pushed = insert_compliance(speed, tilt, error, velocity, goal, wrench, omega_bar, params)
    got_speed, got_setpoint = speed.copy(), setpoint.copy()
    ck.insert_compliance_into(got_speed, got_setpoint, tilt, error, velocity, goal, wrench, omega_bar, params)
    close(got_speed, expected_speed)
    close(got_setpoint, setpoint + pushed)  # added to what the row holds
    if seed % 3:
        assert not pushed.any()


@pytest.mark.parametrize("seed", SEEDS)
def test_integrated_force_error_is_its_reference(seed: int) -> None:
    """The force integral's error while an INSERT pushes across against
    cosmos.osc.tilt_window.integrated_force_error, and, computed apart, Omega_bar (F_d - F_s)
    itself where nothing is pushed across (odd seeds) and none of it along the push (even).

    Catches the error's part along the push kept (the integral would wind up or fight it),
    the part across it dropped, or a push's moment rows read as its direction."""
    rng = np.random.default_rng(seed)
    omega_bar = random_omega_bar(rng)
    setpoint, wrench = rng.normal(0.0, 5.0, 6), rng.normal(0.0, 5.0, 6)
    slide = np.zeros(6) if seed % 2 else np.concatenate((rng.normal(0.0, 3.0, 3), rng.normal(0.0, 1.0, 3)))
    expected = integrated_force_error(omega_bar, setpoint, wrench, slide)
    close(ck.integrated_force_error(omega_bar, setpoint, wrench, slide), expected)
    plain = omega_bar @ (setpoint - wrench)
    if seed % 2:
        close(expected, plain)
    else:
        assert float(expected[:3] @ slide[:3]) == pytest.approx(0.0, abs=1e-9)
        close(expected[3:], plain[3:])


def test_coulomb_compensation_ignores_the_encoders_noise() -> None:
    """In a hold a sensed speed within the dead band asks for no friction torque; beyond it, for
    what the excess asks (a joint at d + v_c/2 gets half its level; at -(d + 2 v_c) all of
    -Gamma_c(-)); in a segment that moves or pushes the whole sensed speed counts (a dither).

    Catches the encoders' one-count noise (the velocity observer's 1.6e-2 rad/s on the PUMA's
    joint 6, above the 1e-2 rad/s ramp) asking for the full friction torque at rest: the arm
    dithered within one count after eq. 38 had stopped it; and the band applied under force
    control, where the stuck joints made a held 10 N push ring between 6.5 and 13.3 N."""
    positive_nm, negative_nm = np.full(6, 2.0), np.full(6, 4.0)
    dead_band, full_speed = np.full(6, 0.016), 0.01
    qd = np.array((0.015, -0.015, 0.016 + 0.005, -(0.016 + 0.02), 0.0, 0.03))
    zero = np.zeros(6)
    coulomb, torque = zero.copy(), zero.copy()
    levels = (positive_nm, negative_nm)
    ck.coulomb_compensation_into(torque, coulomb, qd, np.eye(6), zero, *levels, dead_band, False, 100.0, 1.0)
    close(coulomb, np.array((0.0, 0.0, 1.0, -4.0, 0.0, 2.0)))
    intent = friction_intent(qd, np.eye(6), zero, zero, 1.0, full_speed, dead_band)
    close(intent, np.array((0.0, 0.0, 0.5, -2.0, 0.0, 1.4)))
    ck.coulomb_compensation_into(torque, coulomb, qd, np.eye(6), zero, *levels, dead_band, True, 100.0, 1.0)
    close(coulomb, np.array((2.0, -4.0, 2.0, -4.0, 0.0, 2.0)))
