"""A CONTACT's landing: the approach's braking and the held push's landed test (cosmos.osc.contact).

The compiled :func:`cosmos.runtime.kernels.contact.push_landed` against its reference
:func:`cosmos.osc.contact.push_landed` on seeded random inputs and at its edges, and which
gains each kind of motion gets from :func:`cosmos.runtime.servo_gains.touch_damping_for`.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from cosmos.execution.resolve import brakes_at_its_touch
from cosmos.lang import compile_program
from cosmos.osc.contact import LANDED_PUSH, LANDED_SPEED_MPS, TOUCH_BRAKING_N, push_landed, touch_braking
from cosmos.osc.held_push import touch_damping
from cosmos.runtime.kernels import contact as ck
from cosmos.runtime.servo_gains import ServoGains, touch_damping_for
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint

SEEDS = range(12)


@pytest.mark.parametrize("seed", SEEDS)
def test_push_landed_is_its_reference(seed: int) -> None:
    """The kernel against cosmos.osc.contact.push_landed, at rest or not, over the goal or not.

    Catches a kernel that reads the speed off the push (any direction, or the moment rows), or
    that compares the push with the goal's size on a different scale."""
    rng = np.random.default_rng(seed)
    n = rng.normal(size=3)
    n /= np.linalg.norm(n)
    goal = np.concatenate((rng.uniform(1.0, 40.0) * n, rng.normal(0.0, 1.0, 3)))
    push = float(np.linalg.norm(goal[:3]))
    velocity = rng.normal(0.0, 0.05, 6)
    velocity[:3] += (rng.uniform(-2.0, 2.0) * LANDED_SPEED_MPS - float(n @ velocity[:3])) * n
    wrench = rng.normal(0.0, 2.0, 6)
    wrench[:3] += (rng.uniform(0.5, 1.5) * LANDED_PUSH * push - float(n @ wrench[:3])) * n
    expected = (
        abs(float(n @ velocity[:3])) <= LANDED_SPEED_MPS and float(n @ wrench[:3]) <= LANDED_PUSH * push
    )
    assert push_landed(goal, wrench, velocity) == expected
    assert ck.push_landed(goal, wrench, velocity, ck.LANDED) == expected


def test_push_landed_edges() -> None:
    """At the speed and share exactly, just over either, and without a push (always landed).

    Catches a strict comparison where the docstring promises ``<=``, and a division by a zero goal."""
    goal = np.array([0.0, 0.0, -10.0, 0.0, 0.0, 0.0])
    at_rest = np.array([0.0, 0.0, -LANDED_SPEED_MPS, 0.0, 0.0, 0.0])
    pushing = np.array([0.0, 0.0, -LANDED_PUSH * 10.0, 0.0, 0.0, 0.0])
    for landed in (push_landed, lambda g, w, v: ck.push_landed(g, w, v, ck.LANDED)):
        assert landed(goal, pushing, at_rest)
        assert not landed(goal, pushing * 1.01, at_rest)
        assert not landed(goal, pushing, at_rest * 1.01)
        assert landed(goal, pushing, -at_rest)  # moving back out as slowly
        assert landed(np.zeros(6), pushing * 10.0, at_rest * 10.0)


def test_touch_braking_damps_the_motion_into_the_first_push() -> None:
    """A tool moving down at 30 mm/s that feels 0.6 N from below: F*_m gains 300/s x 25 mm/s upward.

    Computed by hand: c = f_s (no commanded acceleration), n = -z, n^T xd - v_l = 0.025 m/s, so
    F*_m gains +7.5 m/s^2 along +z. Catches braking that waits for the 2 N touch threshold, that
    brakes a tool moving away from the push or already at its landing speed, or one whose push
    is under 0.5 N."""
    motion, velocity = np.zeros(6), np.array([0.0, 0.0, -0.03, 0.0, 0.0, 0.0])
    felt = np.array([0.0, 0.0, -0.6, 0.0, 0.0, 0.0])  # the tool pushes down on the table
    braked = touch_braking(motion, felt, velocity, 0.65)
    assert braked == pytest.approx(np.array([0.0, 0.0, 7.5, 0.0, 0.0, 0.0]))
    assert np.array_equal(touch_braking(motion, felt, -velocity, 0.65), motion)  # moving away
    assert np.array_equal(touch_braking(motion, felt * 0.4 / 0.6, velocity, 0.65), motion)  # 0.4 N
    assert np.array_equal(touch_braking(motion, felt, velocity / 6.0, 0.65), motion)  # at 5 mm/s


@pytest.mark.parametrize("seed", SEEDS)
def test_touch_braking_kernel_is_its_reference(seed: int) -> None:
    """The compiled braking against cosmos.osc.contact.touch_braking, the tool's inertia in the push,
    toward the push or away, above the landing speed or under it; with v_l = 0 it is the spring's
    touch damping (cosmos.osc.held_push.touch_damping).

    Catches a kernel that leaves the landing speed out, brakes along the wrong direction, or
    reads the push without the tool's own inertia."""
    rng = np.random.default_rng(seed)
    motion, velocity = rng.normal(0.0, 3.0, 6), rng.normal(0.0, 0.03, 6)
    wrench = rng.normal(0.0, 2.0, 6)
    mass = rng.uniform(0.3, 2.5)  # the peg tool's 0.66 kg to a gripper holding a peg
    params = np.array((rng.uniform(0.1, 1.0), mass, 300.0))
    for landing in (0.0, rng.uniform(0.0, 0.02)):
        expected = touch_braking(motion, wrench, velocity, mass, params[0], 300.0, landing)
        got = motion.copy()
        ck.touch_braking_into(got, wrench, velocity, params, landing)
        assert got == pytest.approx(expected, rel=1e-12, abs=1e-12)
    spring = touch_damping(motion, wrench, velocity, 300.0, params[0], mass)
    assert touch_braking(motion, wrench, velocity, mass, params[0], 300.0, 0.0) == pytest.approx(spring)


def test_touch_braking_threshold_grows_with_the_mass_below_the_sensor() -> None:
    """A 2 kg tool (a gripper holding the peg) brakes from 1.5 N (0.75 N/kg), not from 0.5 N; the
    0.66 kg peg tool still from 0.5 N. Computed by hand: 0.75 x 2 = 1.5 N > 0.5 N.

    Catches the braking reading a heavy tool's inertia as a push: grasp_and_insert.cos's INSERT
    (seed 7 of tests/hand/test_grasp_and_insert.py) braked on the hand's inertia, read its own
    braking as a 2 N touch 1.6 mm above the hole and jammed 8.3 mm in."""
    motion, velocity = np.zeros(6), np.array([0.0, 0.0, -0.03, 0.0, 0.0, 0.0])
    down = np.array([0.0, 0.0, -1.0, 0.0, 0.0, 0.0])
    assert np.array_equal(touch_braking(motion, 1.4 * down, velocity, 2.0), motion)
    assert touch_braking(motion, 1.6 * down, velocity, 2.0)[2] == pytest.approx(7.5)
    assert touch_braking(motion, 0.6 * down, velocity, 0.66)[2] == pytest.approx(7.5)
    for push, braked in ((1.4, False), (1.6, True)):
        got = motion.copy()
        ck.touch_braking_into(got, push * down, velocity, np.array((0.5, 2.0, 300.0)), 0.005)
        assert (got[2] > 0.0) == braked


def _setpoint(**kwargs: object) -> ServoSetpoint:
    return ServoSetpoint(mode=MotionMode.GOAL, position=np.zeros(3), rotation_to_world=np.eye(3), **kwargs)  # type: ignore[arg-type]


def test_insert_approach_brakes_as_a_contact_approach() -> None:
    """An INSERT's approach brakes at its first push as a CONTACT's does; its insertion (a force axis) and
    a MOVE do not. Read from the compiled plan of a program and the setpoints the executor makes.

    Catches the INSERT's approach left unbraked: it landed on the hole's chamfer at its SPEED,
    33.5-45 N for FORCE 15 N (tests/run/test_run_insert_landing.py)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plan = compile_program(
            "MOVE TO (600 mm, 150 mm, 264 mm)\nINSERT DOWN DEPTH 27 mm FORCE 15 N COMPLY X Y RX RY\n"
            "MOVE BY (0, 0, 30 mm)\nCONTACT DOWN FORCE 5 N\n"
        )
    kinds = [(s.kind.value, brakes_at_its_touch(s)) for s in plan.segments]
    assert kinds == [
        ("move", False),
        ("contact_approach", True),
        ("insert", False),
        ("move", False),
        ("contact_approach", True),
        ("contact_hold", False),
    ]


def test_only_a_contact_approach_brakes_at_its_first_push() -> None:
    """A CONTACT's approach looks for 0.5 N and brakes at 300/s (at 1 kHz, scaled at 500 Hz); a
    MOVE with uniform gains looks for no touch; one with gains per axis (a spring) for 8 N.

    Catches the braking leaking into every MOVE (a tool's inertia read as a push would slow
    it), its gain not scaled with the servo period, and the spring's touch damping lost."""
    gains = ServoGains()
    assert touch_damping_for(gains, _setpoint(touch_braking=True), 1e-3) == (TOUCH_BRAKING_N, 300.0, 0.005)
    assert touch_damping_for(gains, _setpoint(touch_braking=True), 2e-3) == (TOUCH_BRAKING_N, 150.0, 0.005)
    free = touch_damping_for(gains, _setpoint(), 1e-3)
    assert math.isinf(free[0])
    sprung = _setpoint(kp_task=np.array([400.0, 400.0, 100.0, 400.0, 400.0, 400.0]))
    assert touch_damping_for(gains, sprung, 1e-3) == (gains.touch_n, gains.touch_damping, 0.0)
