"""The servo level's gains that hold for every segment (:class:`cosmos.runtime.servo.ServoLevel`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from cosmos.osc.contact import LANDING_SPEED_MPS, TOUCH_BRAKING_N, TOUCH_BRAKING_PER_S
from cosmos.osc.unified import ForceGains

if TYPE_CHECKING:
    from cosmos.runtime.setpoint import ServoSetpoint


@dataclass(frozen=True)
class ServoGains:
    """Gains of the servo level that do not change from segment to segment.

    Attributes:
        force: Force-loop gains on force-controlled axes.
        xi_q: Null-space joint damping of eq. 34, in [1/s].
        contact_threshold_n: Sensed force on the force-controlled axes above which the
            tool counts as touching for the rest of the segment: from then on the force
            error is integrated (in free space it would wind up), [N].
        coulomb_velocity_rad_s: Joint speed over which the Coulomb friction
            compensation ramps from 0 to its full value, in [rad/s].
        coulomb_lookahead_s: How far ahead the commanded joint acceleration counts
            toward the direction of motion, in [s].
        coulomb_filter_s: Time constant of the low-pass on the Coulomb compensation, [s].
        admittance_gain: On force-controlled moment axes, rotation speed per N m of
            moment error, in [rad/s / N m] (admittance control; see kernels.servo).
        admittance_max_speed_rad_s: Bound on that speed, in [rad/s].
        admittance_kv: Velocity gain of the unit-mass servo that tracks it, in [1/s].
        moment_filter_s: Time constant of the low-pass on the sensed moment there, [s].
        force_speed_kv: Velocity gain that holds a force-controlled push to its speed reference
            (:func:`cosmos.osc.unified.speed_limited_push`, :mod:`cosmos.osc.push_speed`), in [1/s].
            At 150 the peg ran under its aim at SPEED 5 mm/s on the ideal plant (the joints turn
            below the Coulomb compensation's ramp there, and the servo leaves the rest as a speed error).
        push_speed_aim: The capped push aims at this fraction of the speed limit: as the
            contact's friction changes (a chamfer, the hole's walls) its speed swings by up to
            a millimetre per second (INSERT at 5-30 mm/s), and the limit is a limit. On the
            steel contact the peg's landing on the chamfers (44 N at 29 mm/s) slows it to
            24 mm/s and the speed loop's catching up overshot: 0.93 peaked at 33.75 mm/s at
            SPEED 30 on the realistic plant (12.5 % over); 0.90 at 30.9 mm/s.
        push_speed_margin_mps: ... and at least this far below it, in [m/s]
            (:func:`cosmos.osc.push_speed.push_aim`): the ripple the encoders' counts leave in
            the true speed is absolute (about 1 mm/s), so SPEED 5 mm/s aims at 4 mm/s.
        approach_speed_margin_mps: An INSERT's approach (eq. 20-21 without integral) runs this far
            under 1.1 times its SPEED, in [m/s] (:func:`cosmos.osc.push_speed.approach_speed`).
        push_speed_rate: The push's speed reference rises to its aim at this many aims per
            second, its rise fed forward (:mod:`cosmos.osc.push_speed`), in [1/s]. At 8 and 30 a
            peg lingered on the chamfer and its compliant wrist tilted until it jammed
            (grasp_and_insert.cos seeds 4 and 6; a Lissajous search, seed 3).
        motion_ki: Integral gain on the motion axes' translation error in contact, once a
            tracked trajectory's reference has stopped
            (:func:`cosmos.osc.integral_action.integrate_motion_error`), in [1/s^3]; below
            ``kp kv`` (16,000 at the defaults), the third-order loop's stability bound.
        motion_integral_limit_ms: Anti-windup bound on that integral, per axis, in [m s]
            (``motion_ki`` times it, 8 m/s^2, is the most it adds to F*).
        goal_integral: A free goal motion's integral action on its translation error
            (:func:`cosmos.osc.integral_action.integrate_goal_error`): ``(k_i [1/s^3], limit [m s],
            band [m], slow [m/s], quiet [N])``; it grows only within ``band`` of the goal, slower
            than ``slow`` and pushing less than ``quiet``. ``k_i = 1000`` keeps the third-order
            loop ``s^3 + kv s^2 + kp s + k_i`` overdamped (roots -26, -10, -3.8 /s at the
            defaults); ``k_i`` times the limit is the most it adds to F*, in [m/s^2].
        cruise_integral: A goal motion's integral action on its cruise speed along its line
            while eq. 21's limit binds (:mod:`cosmos.osc.cruise_speed`): ``(k_c [1/s^2], limit
            [m/s^2], moving [1], quiet [N])``; ``k_c = kv^2 / 4`` (a double root at -20 /s);
            it grows only while the tool moves faster than ``moving`` times the limit and
            pushes less than ``quiet``; ``limit`` is the most it adds to F*.
        held_push: A push held against a surface (no speed cap: CONTACT, SLIDE, WAIT in
            contact; once the touch is felt: in free space it would crawl at 1 mm/s), along
            itself (:func:`cosmos.osc.held_push.held_push`): ``(k_fh, k_ih, k_vh, limit)``,
            the proportional [1] and integral [1/s] gains added to ``force``'s, the damping
            [1/s] and the integral's anti-windup bound [N s] (``k_ih`` times it, 58 N, the
            most it adds). Measured on the slide grid (tests/run/slide_grid.py) with the
            flat-ended peg, realistic plant: 54 of 54 (ideal plant 54). A light fast slide's
            push sags while the tool slows at the slide's end and overshoots as it stops (5 N at
            50 mm/s along -Y: 4.1 N, then 6.6 N within 0.1 s), quicker than the integral
            follows; ``k_fh`` 0.8 takes 96.0 % of its samples within 15 % (0.4: 94.5 %, the
            one miss of 54; 1.0-1.6: 95.1-96.3 %; seeds 1-4 99.1, 96.2, 99.5, 100 % against
            98.2, 96.2, 98.9, 100 %), and ``k_ih`` 400/s instead 95.7 % but 5 N at 50 mm/s
            along +X falls to 47 %. With ``k_fh`` 0.4, 52 of 54 before the goal and slide
            integrals were as they are now; ``k_vh``
            100/s (on a 1 mm ramp) 49: the 5 N slides at 5 mm/s
            keep 87-94 % within 15 %, the damping passing the velocity observer's
            quantisation noise, and 200/s worse; ``k_ih`` 150/s: 5 N at 50 mm/s along -Y
            falls to 70 % on both plants; ``k_fh = k_ih = 0``: the 5 N slides at 50 mm/s
            fall to 61-64 % (but the 30 N ones arrive).
        hold_observer: A free hold's disturbance observer while the null space is driven (a
            POSTURE, the links' field or the joint-limit potential through N^T:
            :func:`cosmos.osc.integral_action.observe_hold_disturbance`): ``(L [1/s], bound
            [m/s^2])``; it moves within the goal integral's band and below its quiet force. The
            joints a null-space motion turns bring their friction error to the held tool as a
            step (joint 1's 10 % of 25 N m: 0.4 m/s^2, a millimetre at kp = 400;
            tests/run/test_run_null_space.py). L = 20/s (the hold's roots all at -20 /s), seeds
            0-4 of the realistic plant, with the friction told the null space's intent
            (:func:`cosmos.osc.null_space.null_space_intent`): POSTURE 0.26-0.36 mm, a ball at the
            forearm 0.24-0.68 mm (the last of it the field on the tool's link, meant to move it),
            from 0.78-1.21 and 0.82-1.45 mm; the intent alone 0.53-1.12 and 0.69-1.34 mm, the
            observer alone 0.37-0.49 and 0.55-0.89 mm. Without the intent, 40/s: POSTURE
            0.25-0.32 mm but a ball 1.37 mm (seed 4); 10/s: POSTURE up to 0.68 mm. In every free
            hold (not only while the null space is driven) it raised the arm's rest after a kick
            of the wrist (eq. 38; MuJoCo's speeds, seed 0 4.7e-4 to 8.2e-4 rad/s, seeds 1 and 3
            over 1e-3), so plain holds go without.
        touch_n: Where every axis is motion-controlled with gains per axis (a COMPLY spring,
            which expects contact), a push above this on what the tool moves toward is a
            touch, and the motion into it gets the held push's damping
            (:func:`cosmos.osc.held_push.touch_damping`), in [N].
        touch_damping: That damping, in [1/s] (a 100 N/m spring landing at 27 mm/s on the
            table: 33 N at 50/s, a protective stop; under 30 N at 200/s), at 1 kHz.
        touch_braking: A CONTACT's approach (:func:`cosmos.osc.contact.touch_braking`): the push
            felt along it that starts the braking, in [N], the braking's damping, in [1/s], at
            1 kHz, and the landing speed it leaves, in [m/s]. Measured on
            ``tests/run/contact_impact_grid.py`` (FORCE 3-30 N, SPEED 5-50 mm/s, the table, the
            tilted plate and a turned task frame, realistic seeds 0-4 and ideal): without it a
            3 N CONTACT landed at 12 N at 30 mm/s and 32 N at 50 mm/s. 0.5 N is ten times the
            sensor's noise and above the free tool's inertia error in a cruise (the approach's
            speed at the touch is unchanged); at 200/s 3 N at 30 mm/s still landed at 7 N; at
            500/s the push fell to 0 after landing on the realistic plant (its velocity
            observer's 8 ms delay makes the braking outlast the motion). Damping the hold after
            the switch at 100-300/s, tried for the same reason, lifted the tool off the table
            for 10-300 ms on the realistic plant: the observer's delay again.
        insert_compliance: An INSERT's compliant axes (:func:`cosmos.osc.tilt_window.insert_compliance`):
            ``theta_w`` [rad], the window its rotations turn freely within short of the mouth;
            ``k_w`` [1/s], the stop's speed per radian beyond it; ``d_in`` [m], the depth along
            the push from which the part is in the mouth; ``theta_in`` [rad] and ``k_in``
            [1/s], the window there and its stop's rate; ``s``, the share of the push felt
            sent across it toward the part's lean short of the mouth, and ``v_s`` [m/s], the
            speed that way at which that push is off. 10 deg: a peg landing 3.2 mm off tips
            into the mouth; at 3 deg it stayed on the top and jammed; with none a tipped peg
            wedged at 21-25 deg (on the Panda's ``panda_search_insert.cos`` too); at 8 deg
            that search met a wall at 218 N. 2 mm: tipping 10.8 deg on the mouth's edge
            lowers the 8.4 mm end's centre at most 1.6 mm. 2 deg: Whitney's ``c / mu`` for
            the 0.24 mm clearance of the 20 mm peg, steel 0.45, is 1.5 deg (a held peg dropped
            in at 10.85 deg jammed at 2.9 mm on the chamfer), and the window is measured in
            the controller's estimate, which on the realistic plant sat 1.5 deg off the
            bore's axis 24 mm in: at 1.5 deg the stop held the peg against the bore and it
            stick-slipped past its SPEED (5.95 mm/s at 5, seed 1 of
            ``tests/run/test_run_insert_speed.py``). 2 1/s: at 20 1/s the peg righted
            from 10.8 deg at 3 rad/s and knocked the bore at 47 N, at 4 1/s that seed ran
            5.85 mm/s. 0.6 and 5 mm/s: the
            Panda's welded peg 3.7-6.2 mm off (friction 0.4-0.8) crept over the edge at
            0.5 mm/s or stayed (4 of 16 failed); pushed, 16 of 16 went in.
        posture_kp: Unit-mass joint stiffness of the POSTURE task in the null space, in
            [1/s^2]: ``xi_q^2 / 4``, critically damped by the null-space damping.
    """

    force: ForceGains = ForceGains(k_f=0.6, k_i=12.0, k_vf=30.0, integral_limit=5.0)
    xi_q: float = 20.0
    contact_threshold_n: float = 1.0
    coulomb_velocity_rad_s: float = 0.01
    coulomb_lookahead_s: float = 0.02
    coulomb_filter_s: float = 0.005
    admittance_gain: float = 30.0
    admittance_max_speed_rad_s: float = 0.3
    admittance_kv: float = 40.0
    moment_filter_s: float = 0.02
    force_speed_kv: float = 300.0
    push_speed_aim: float = 0.90
    push_speed_margin_mps: float = 0.001
    push_speed_rate: float = 60.0
    approach_speed_margin_mps: float = 0.003
    motion_ki: float = 2000.0
    motion_integral_limit_ms: float = 0.004
    held_push: tuple[float, float, float, float] = (0.8, 288.0, 50.0, 0.2)
    goal_integral: tuple[float, float, float, float, float] = (1000.0, 0.003, 0.003, 0.005, 2.0)
    hold_observer: tuple[float, float] = (20.0, 3.0)
    cruise_integral: tuple[float, float, float, float] = (400.0, 2.0, 0.25, 2.0)
    touch_n: float = 8.0
    touch_damping: float = 200.0
    touch_braking: tuple[float, float, float] = (TOUCH_BRAKING_N, TOUCH_BRAKING_PER_S, LANDING_SPEED_MPS)
    insert_compliance: tuple[float, ...] = (0.1745, 20.0, 0.002, 0.035, 2.0, 0.6, 0.005)
    posture_kp: float = 100.0


HELD_PUSH_RATE_S = 0.001
"""The servo period the held push's gains are given for; a slower servo scales them down."""


def held_push_at(gains: tuple[float, float, float, float], servo_dt_s: float) -> tuple[float, ...]:
    """The held push's ``(k_fh, k_ih, k_vh, limit)`` for a servo period.

    Its damping is near ``1 / dt`` at 1 kHz (a touch stopped within a tick or two) and its
    integral fast: each gain scaled by ``min(1, HELD_PUSH_RATE_S / dt)`` keeps ``k_vh dt``,
    ``k_ih dt`` and the contact's loop gain what they are at 1 kHz (at 225 Hz unscaled, the
    loop rang up to 160 N on a 10 N CONTACT). The bound on the integral stays.
    """
    scale = min(1.0, HELD_PUSH_RATE_S / servo_dt_s)
    k_fh, k_ih, k_vh, limit = gains
    return (k_fh * scale, k_ih * scale, k_vh * scale, limit)


def touch_damping_for(
    gains: ServoGains, setpoint: ServoSetpoint, servo_dt_s: float
) -> tuple[float, float, float]:
    """The touch a free motion looks for, the damping of the motion into it and the speed it leaves.

    ``(touch_n [N], k [1/s], v_l [m/s])``: a CONTACT's approach brakes from the first push it
    feels down to its landing speed (:func:`cosmos.osc.contact.touch_braking`, ``touch_braking``); a
    motion with gains per axis (a COMPLY spring, which expects contact) is damped into a touch
    above ``touch_n`` (:func:`cosmos.osc.held_push.touch_damping`); other motions look for none
    (an infinite threshold). The damping is scaled by ``min(1, HELD_PUSH_RATE_S / dt)`` as the
    held push's is (:func:`held_push_at`).
    """
    scale = min(1.0, HELD_PUSH_RATE_S / servo_dt_s)
    if setpoint.touch_braking:
        touch_n, gain, landing_speed = gains.touch_braking
        return touch_n, gain * scale, landing_speed
    return (math.inf if setpoint.uniform_gains else gains.touch_n), gains.touch_damping * scale, 0.0


LIMIT_PROJECTION_MARGIN_RAD = 0.30
"""Distance from a joint limit at which the task starts giving up what needs that joint [rad]."""
LIMIT_PROJECTION_WHOLE_RAD = 0.15
"""... and wholly gives it up [rad]: where the joint-limit field begins
(cosmos.runtime.parameters.JointLimitField.rho_0_rad), so the task never pushes a joint
against the field (the fight ran the tool 50 mm off its line)."""
