"""From a compiled segment to the servo's setpoint, resolved against the measured state.

A segment's relative or absent target, its per-axis stiffness and damping and
its force ramp only become numbers when the segment starts: the target is the
measured pose plus the offset, a physical stiffness K on a motion axis becomes
the unit-mass gain ``kp = K / lambda`` with ``lambda = n^T Lambda n`` the
end effector's effective mass along that task axis (eq. 18 makes the
decoupled end effector a unit mass, so the physical spring is ``Lambda kp``).

An axis that COMPLY ... STIFFNESS makes a spring is impedance control about an anchor: a
MOVE moves the anchor along its line at its SPEED, a trajectory tracked with eq. 19 (as a
SLIDE's), and the tool follows on the spring, pressing ``k`` times its shortfall where
something stops it; a hold keeps the anchor where the statement before left it
(:func:`spring_anchor`); the servo holds the spring to its law with the axes' effective
masses (``ServoSetpoint.spring_masses``, :mod:`cosmos.runtime.kernels.spring`), and no
integral of the position error acts on it.

A free MOVE at a low SPEED (at most :data:`TRACKED_SPEED_MPS`) tracks a reference moving
along its line at the SPEED, with eq. 19's position feedback, in place of eq. 20-21's
velocity servo (:func:`tracks_a_reference`).
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.capabilities import ARM_CAPABILITY
from cosmos.osc.motion import PoseTrajectory, goal_ramp_acceleration
from cosmos.osc.orientation import so3_exp, so3_log
from cosmos.plan import ContactTouch, DepthReached, Posture, RelativeTarget, Segment, SegmentKind, Target
from cosmos.runtime.parameters import Evaluation
from cosmos.runtime.setpoint import (
    DEFAULT_KP,
    DEFAULT_KV,
    DEFAULT_MAX_ANGULAR_SPEED,
    MotionMode,
    ServoSetpoint,
)

FloatArray = np.ndarray

FORCE_RAMP_S = 0.25
"""Force setpoints ramp from the sensed force to the new value over this time [s]."""

HOLD_SPEED_MPS = 0.25
"""Speed limit when a segment holds or only moves its force axes [m/s]."""


def goal_pose(
    target: Target | None, position: FloatArray, rotation: FloatArray
) -> tuple[FloatArray, FloatArray]:
    """The goal pose of a target, given the measured tool pose at segment start."""
    if target is None:
        return position.copy(), rotation.copy()
    if isinstance(target, RelativeTarget):
        return position + target.offset_world, rotation.copy()
    goal_rotation = rotation.copy() if target.rotation_world is None else target.rotation_world
    return np.array(target.position_world), np.array(goal_rotation)


def segment_goals(
    segment: Segment,
    position: FloatArray,
    rotation: FloatArray,
    previous: ServoSetpoint | None,
    now_s: float,
) -> list[tuple[FloatArray, FloatArray]]:
    """The goal poses of a segment starting now: its VIA points' then its target's (:func:`goal_pose`).

    A hold keeps its springs' anchors where the segment before left them (:func:`spring_anchor`).

    Args:
        segment: The segment about to start.
        position: The measured tool point, in [m]. # (3,)
        rotation: The measured tool orientation, tool to world. # (3, 3)
        previous: The servo's setpoint until now (None: none yet).
        now_s: Simulated time, in [s].
    """
    goals = [goal_pose(via, position, rotation) for via in segment.via]
    goals.append(spring_anchor(segment, goal_pose(segment.target, position, rotation), previous, now_s))
    return goals


def spring_axes(segment: Segment) -> tuple[bool, ...]:
    """Per task axis, whether COMPLY ... STIFFNESS made it a spring (motion-controlled, stiffness > 0)."""
    return tuple(
        bool(moving) and stiffness is not None and stiffness > 0.0
        for moving, stiffness in zip(segment.motion_axes, segment.stiffness, strict=True)
    )


def moves_its_anchor(segment: Segment) -> bool:
    """A MOVE with a target and a SPEED, through no VIA point: its springs' anchor cruises to the goal."""
    return (
        segment.kind is SegmentKind.MOVE
        and segment.target is not None
        and not segment.via
        and bool(segment.speed_limit_mps)
    )


def spring_anchor(
    segment: Segment,
    goal: tuple[FloatArray, FloatArray],
    previous: ServoSetpoint | None,
    now_s: float,
) -> tuple[FloatArray, FloatArray]:
    """A hold's goal pose, its springs' anchors kept where the previous segment commanded them.

    A spring (COMPLY ... STIFFNESS) renders ``F = k (x_anchor - x)``: a MOVE that presses the
    tool onto something through its spring leaves the anchor beyond the tool, and the press is
    ``k`` times that shortfall. A hold (WAIT; a statement's hold on its other axes) re-anchored
    at the measured pose would let it go. So a segment without a target keeps, on each axis
    that is a spring both in it and in the segment before (same task frame), the anchor the
    servo last commanded there (a tracked trajectory's sample now, else its goal); its other
    axes hold the measured pose as before. A MOVE moves the anchor from the measured pose (it
    starts where the tool is), and ``COMPLY NONE`` or a failure's hold ends the press.

    Args:
        segment: The segment about to start.
        goal: Its goal pose from :func:`goal_pose`: the measured pose for a hold.
        previous: The servo's setpoint until now (None: none yet).
        now_s: Simulated time, in [s].

    Returns:
        The goal pose, position [m] and rotation (tool to world). # (3,), (3, 3)
    """
    springs = spring_axes(segment)
    if segment.target is not None or previous is None or not any(springs):
        return goal
    frame = np.asarray(segment.frame_rotation, dtype=float)
    if not np.allclose(frame, previous.rotation_task_to_world):
        return goal
    kept = [springs[i] and previous.spring_masses[i] > 0.0 for i in range(6)]
    if not any(kept):
        return goal
    anchor, anchor_rotation = previous.position, previous.rotation_to_world
    if previous.mode is MotionMode.TRAJECTORY and isinstance(previous.trajectory, PoseTrajectory):
        sample = previous.trajectory.sample(now_s - previous.start_s)
        anchor, anchor_rotation = sample.position, sample.rotation_to_world
    position, rotation = goal
    # The anchor's offset from the measured pose, in the task frame, kept on the spring axes only.
    offset = frame.T.dot(np.asarray(anchor) - position) * np.array(kept[:3], dtype=float)
    turn = frame.T.dot(so3_log(np.asarray(anchor_rotation).dot(rotation.T))) * np.array(kept[3:], dtype=float)
    return position + frame.dot(offset), so3_exp(frame.dot(turn)).dot(rotation)


TRACKED_SPEED_MPS = 0.0100001
"""At or below this SPEED a free MOVE tracks a reference along its line (:func:`tracks_a_reference`) [m/s]."""

TRACKED_TURN_RAD = math.radians(30.0)
"""A slower MOVE that turns the tool more than this keeps eq. 20-21 and its rotation plan [rad]."""


def tracks_a_reference(segment: Segment, rotation: FloatArray, goal_rotation: FloatArray) -> bool:
    """Whether a MOVE is a reference tracked along its line at its SPEED (eq. 19), not eq. 20-21.

    Eq. 20-21 hold the cruise to the SPEED with a velocity servo, and their integral
    (:mod:`cosmos.osc.cruise_speed`) with the sensed speed along the line. At a few mm/s that
    speed is mostly the encoders' quantisation (30-50 um of tool travel per count, through a
    40 Hz observer), and the whole motion lies within the goal integral's band
    (:func:`cosmos.osc.integral_action.integrate_goal_error`), which drives it toward the goal:
    a MOVE of 2-5 mm at SPEED 1 mm/s ran at 2.4-4.7 mm/s (medians), at 0.5 mm/s at 2.0-3.8 mm/s,
    and at 2 mm/s down it stuck and slipped between 0.2 and 3.5 times its SPEED (seeds 0-4 and
    the ideal plant). The position is measured far better than the speed there, so the tool tracks
    a reference that cruises along the line at the SPEED between short ramps
    (:func:`cosmos.osc.motion.cruise`), with eq. 19, as a SLIDE and a COMPLY spring's anchor
    do: a steady model error leaves a steady lag behind the reference, not a speed error.

    Only a free MOVE (every axis motion-controlled, no spring, no VIA point, no free
    orientation or POSTURE for the null space) with a target, turning the tool at most
    :data:`TRACKED_TURN_RAD`. From 3 mm/s on the friction's intent reads the reference
    (:func:`cosmos.osc.cruise_speed.tracked_intent`): with a trajectory's, a joint turning
    within the Coulomb compensation's ramp hunted (5 mm/s along +Y: 0.73-1.23 times the
    SPEED). At 2 mm/s straight down the shoulder still sticks and slips (0.5-2.2 times the
    SPEED, where eq. 20-21 gave 0.2-3.5). Up to 10 mm/s tracking did better than eq. 20-21
    and their cruise integral (:mod:`cosmos.osc.cruise_speed`), at 10 mm/s within a few per
    cent both, eq. 20-21 running 55 % over in the first 0.25 s, tracking 23 %. Among obstacles
    the reference would not give way to the field as eq. 20-21's goal motion does
    (:func:`cosmos.runtime.goal_line.kept_line`): :func:`setpoint_for` does not track there.

    Args:
        segment: The segment about to start.
        rotation: The measured tool orientation, tool to world. # (3, 3)
        goal_rotation: The goal's. # (3, 3)
    """
    speed = segment.speed_limit_mps
    if segment.kind is not SegmentKind.MOVE or segment.target is None or segment.via or not speed:
        return False
    if speed > TRACKED_SPEED_MPS or not all(segment.motion_axes) or any(spring_axes(segment)):
        return False
    if segment.orientation_free or segment.posture is not None:
        return False
    turn = float(np.linalg.norm(so3_log(np.asarray(goal_rotation).dot(np.asarray(rotation).T))))
    return turn <= TRACKED_TURN_RAD


def posture_joints(
    posture: Posture | None, home_q: FloatArray, q_lower: FloatArray, q_upper: FloatArray
) -> tuple[FloatArray | None, str]:
    """A POSTURE's joint angles for this arm, or the reason the arm cannot take it.

    Args:
        posture: The segment's POSTURE, or None.
        home_q: The arm's ``home`` configuration, in [rad]. # (n,)
        q_lower: Lower joint limits, in [rad]. # (n,)
        q_upper: Upper joint limits, in [rad]. # (n,)

    Returns:
        ``(angles, "")``; ``(None, "")`` without a posture; ``(None, reason)`` when the
        arm cannot take it (the number of joints, a joint beyond its limit).
    """
    if posture is None:
        return None, ""
    q = np.array(home_q if posture.joints_rad is None else posture.joints_rad, dtype=float)
    if q.shape != home_q.shape:
        return (
            None,
            f"the POSTURE of line {posture.span.line} gives {q.size} joint angles; the arm has {home_q.size}",
        )
    for j in range(q.size):
        if not q_lower[j] <= q[j] <= q_upper[j]:
            return None, (
                f"the POSTURE of line {posture.span.line} puts joint {j + 1} at "
                f"{math.degrees(q[j]):.1f} deg, beyond its range "
                f"{math.degrees(q_lower[j]):.0f}..{math.degrees(q_upper[j]):.0f} deg"
            )
    return q, ""


def effective_masses(evaluation: Evaluation, rotation_task_to_world: FloatArray) -> FloatArray:
    """``n^T Lambda n`` for each task axis n: translation [kg], rotation [kg m^2]. # (6,)."""
    lam = evaluation.lambda_
    masses = np.empty(6)
    for i in range(3):
        axis = rotation_task_to_world[:, i]
        masses[i] = axis.dot(lam[:3, :3]).dot(axis)
        masses[i + 3] = axis.dot(lam[3:, 3:]).dot(axis)
    return masses


def spring_masses(segment: Segment, evaluation: Evaluation) -> FloatArray:
    """Each task axis's effective mass where the segment makes it a spring, else 0, [kg, kg m^2]. # (6,)."""
    springs = np.array(spring_axes(segment))
    if not springs.any():
        return np.zeros(6)
    return np.where(springs, effective_masses(evaluation, segment.frame_rotation), 0.0)


def axis_gains(segment: Segment, evaluation: Evaluation) -> tuple[FloatArray, FloatArray]:
    """Unit-mass gains ``(kp, kv)`` per task axis from the segment's stiffness and damping."""
    kp = np.full(6, DEFAULT_KP)
    kv = np.full(6, DEFAULT_KV)
    custom = [
        i
        for i in range(6)
        if segment.motion_axes[i] and (segment.stiffness[i] is not None or segment.damping[i] is not None)
    ]
    if not custom:
        return kp, kv
    masses = effective_masses(evaluation, segment.frame_rotation)
    for i in custom:
        stiffness, damping = segment.stiffness[i], segment.damping[i]
        if stiffness is not None:
            kp[i] = stiffness / masses[i]
        if damping is not None:
            kv[i] = damping / masses[i]
        else:
            kv[i] = 2.0 * math.sqrt(kp[i])  # critically damped
    return kp, kv


def setpoint_for(
    segment: Segment,
    goal_position: FloatArray,
    goal_rotation: FloatArray,
    evaluation: Evaluation,
    wrench_world: FloatArray,
    start_s: float,
    posture_rad: FloatArray | None = None,
    among_obstacles: bool = False,
    next_leg: bool = False,
) -> ServoSetpoint:
    """The servo setpoint that executes ``segment`` toward the given goal pose (and POSTURE, if any).

    Among obstacles (``among_obstacles``) a free MOVE keeps eq. 20-21's goal motion at any SPEED:
    it gives way to their field (seed section 6), where a tracked reference would pull against it.
    ``next_leg``: the goal is a MOVE ... VIA's next one, after a VIA point passed.
    """
    kp, kv = axis_gains(segment, evaluation)
    trajectory = None
    duration_s = segment.duration_s
    cruise_speed = None
    if duration_s is None and segment.kind is SegmentKind.SLIDE and segment.speed_limit_mps:
        # Along a surface, friction opposes the motion: a trajectory tracked with eq. 19
        # (and its integral, cosmos.runtime.kernels.servo) pushes through it, where eq. 20's
        # velocity servo would crawl. It cruises at the SPEED between short ramps.
        cruise_speed, duration_s = segment.speed_limit_mps, 1.0  # the cruise sets the duration
    sprung = any(spring_axes(segment))
    if duration_s is None and sprung and moves_its_anchor(segment):
        # A spring's anchor moves: eq. 19 tracks it along the line at the SPEED, and the tool
        # follows on the spring (the module's docstring). Eq. 20-21 on a spring axis would give the
        # velocity servo only kv = 2 sqrt(k / lambda): 2 N at 20 mm/s for 500 N/m, less than
        # the joints' friction error, and a 20 mm MOVE crawled for 22 s.
        cruise_speed, duration_s = segment.speed_limit_mps, 1.0
    rotation = evaluation.rotation_tool_to_world
    tracked = (
        duration_s is None and not among_obstacles and tracks_a_reference(segment, rotation, goal_rotation)
    )
    if tracked:  # a low SPEED: a reference along the line, tracked (tracks_a_reference)
        cruise_speed, duration_s = segment.speed_limit_mps, 1.0
    if duration_s is not None:
        mode = MotionMode.TRAJECTORY
        trajectory = PoseTrajectory.between(
            evaluation.position,
            rotation,
            goal_position,
            goal_rotation,
            duration_s,
            cruise_speed,
            DEFAULT_MAX_ANGULAR_SPEED if sprung or tracked else None,
        )
    elif segment.target is None and segment.kind is not SegmentKind.CONTACT_APPROACH:
        mode = MotionMode.HOLD
    else:
        mode = MotionMode.GOAL
    speed = segment.speed_limit_mps or HOLD_SPEED_MPS
    acceleration = ARM_CAPABILITY.tool_acceleration_mps2
    if segment.kind is SegmentKind.MOVE:  # its SPEED once the cruise's integral has learnt the arm
        acceleration = goal_ramp_acceleration(speed, acceleration)
    return ServoSetpoint(
        mode=mode,
        position=goal_position,
        rotation_to_world=goal_rotation,
        rotation_task_to_world=np.array(segment.frame_rotation),
        motion_axes=tuple(bool(a) for a in segment.motion_axes),
        force_task=np.array(segment.force_setpoint),
        force_start_world=wrench_world.copy(),
        ramp_s=FORCE_RAMP_S,
        start_s=start_s,
        max_speed=speed,
        acceleration=acceleration,
        kp_task=kp,
        kv_task=kv,
        trajectory=trajectory,
        limit_push_speed=segment.kind is SegmentKind.INSERT,
        orientation_free=segment.orientation_free,
        posture_rad=posture_rad,
        spring_masses=spring_masses(segment, evaluation),
        # An INSERT's approach lands on the chamfer at the speed eq. 20-21 alone gives it: at its
        # SPEED (the cruise integral) the insertion rang past its cap (11.05 mm/s at 10, seed 0);
        # one landing on a flat steel face has it, as a CONTACT's (cosmos.runtime.landing_zone).
        # A spring renders k (x_anchor - x): no integral may turn it into a stiff servo.
        cruise_integral=not isinstance(segment.completion, DepthReached) and not sprung,
        touch_braking=brakes_at_its_touch(segment),  # cosmos.osc.contact.touch_braking
        leg=mode is MotionMode.GOAL and next_leg,
    )


def brakes_at_its_touch(segment: Segment) -> bool:
    """A CONTACT's or an INSERT's approach: every axis held until the tool touches.

    Both brake from the first push they feel (:func:`cosmos.osc.contact.touch_braking`). An
    INSERT's approach landing unbraked on the hole's chamfer or top face at 15-25 mm/s peaked
    within 1-8 ms of its touch: in the shipped peg sweep (60 runs) 34.7 N at the 95th percentile
    and 45.1 N at most for FORCE 15 N; braked 19.5 N and 37.4 N (the steel contact's force rises
    from 0.5 N to 6-9 N within a tick, so braking takes part of the impact, not all of it).
    """
    return isinstance(segment.completion, ContactTouch) or _insert_approach(segment)


def _insert_approach(segment: Segment) -> bool:
    """An INSERT's approach: done at its DEPTH or on a touch (:class:`cosmos.plan.DepthReached`)."""
    return isinstance(segment.completion, DepthReached) and segment.completion.touch_n is not None
