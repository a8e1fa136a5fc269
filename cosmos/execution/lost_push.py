"""A held push that loses its surface: a CONTACT's hold whose tool runs on along the push.

A peg held on the hole's chamfer may slide off it into the bore; the held push then runs on
at its SPEED (:func:`cosmos.osc.held_push.held_push_cap`) until it lands on the bore's bottom. Its
force is not settled meanwhile, whatever the wrist reads (the bore's wall rubbing the peg reads
3-6 N of an 8 N push), and its settling is bounded from where it lands again, not from the touch.

A CONTACT's hold is judged each tick in one compiled call (:func:`hold`, on the arrays a
:class:`~cosmos.execution.listing.Listing` lists): its push run on, its contact lost, its force
settled (the force axes of the wrench in the task frame against their setpoints), its bound. In
Python it cost some 1.9 us a tick; the reasons are written in Python, once, when it ends
(:func:`hold_ended`).
"""

from __future__ import annotations

import math

import numpy as np
from numba.core import types

from cosmos.execution.listing import POSITION, STATE, WRENCH, listed
from cosmos.jit import kernel
from cosmos.plan import TOUCH_THRESHOLD_N, ForceSettled, Segment, SegmentKind

FloatArray = np.ndarray

LOST_PUSH_TRAVEL_M = 0.001
"""A held push that runs on this far along itself has lost its surface [m]. Pressing a surface
it moves under 0.1 mm (the table's 1.5 mm contact ramp, sensed through the encoders' noise)."""

PUSH, AT, SINCE, PRESSED_AT, TOUCHING, CONTACT, SETTLED_SINCE = 0, 3, 6, 7, 10, 11, 12
TOLERANCE, SETTLE_TIME, MAX_TIME, DEADLINE, WORST, FREE, TERMS_COUNT, TERMS = 13, 14, 15, 16, 17, 18, 19, 20
"""A hold's state: its push's unit direction, world (3); the tool point where it last had its
surface, world [m] (3), and since when [s]; the tool point where it last touched something, world
[m] (3); the least force that touches something [N] (the touch's,
:data:`~cosmos.plan.TOUCH_THRESHOLD_N`, or half the push if less); whether it is a CONTACT's hold
(1.0: one running on touching nothing fails); since when its force has been settled [s] (NaN: it is
not); the force's tolerance [N], its settling time [s], its bound from the last landing [s]; the
statement's TIMEOUT's deadline [s] (inf: none, or judged elsewhere); the worst force axis's error
[N] and how far the tool ran touching nothing [m] at the last tick judged; then the force axes:
how many, and for each where its half of the wrench starts (force 0, moment 3), its row of R^T,
its setpoint."""
TERM = 5
HOLD_SIZE = TERMS + 6 * TERM

ON_ITS_WAY, LOST_CONTACT, SETTLED, BOUND_REACHED, DEADLINE_PASSED = 0, 1, 2, 3, 4
"""What :func:`hold` finds at a tick."""


def hold_state(
    segment: Segment, force_axes: FloatArray, start: tuple[float, ...], start_s: float, deadline_s: float
) -> FloatArray:
    """The state of held push ``segment`` (a force-settled ending) from ``start`` [m], ``start_s`` [s].

    ``force_axes`` are the task frame's axes under force control (bool, (6,)); ``deadline_s`` is
    the TIMEOUT's deadline [s] if :func:`hold` is to find it passed (inf if not).
    """
    settled = segment.completion
    assert isinstance(settled, ForceSettled)
    unit, size = segment_push(segment)
    state = np.zeros(HOLD_SIZE)
    state[PUSH : PUSH + 3], state[AT : AT + 3], state[PRESSED_AT : PRESSED_AT + 3] = unit, start, start
    state[SINCE], state[TOUCHING] = start_s, min(TOUCH_THRESHOLD_N, 0.5 * size)
    state[CONTACT] = segment.kind is SegmentKind.CONTACT_HOLD
    state[SETTLED_SINCE] = math.nan
    state[TOLERANCE], state[SETTLE_TIME], state[MAX_TIME] = (
        settled.tolerance_n, settled.settle_time_s, settled.max_time_s,
    )  # fmt: skip
    state[DEADLINE] = deadline_s
    rows_t = np.asarray(segment.frame_rotation, dtype=float).T.tolist()
    setpoints = np.asarray(segment.force_setpoint, dtype=float).tolist()
    axes = [i for i in range(6) if force_axes[i]]
    state[TERMS_COUNT] = len(axes)
    for k, i in enumerate(axes):
        state[TERMS + TERM * k : TERMS + TERM * (k + 1)] = (3 * (i // 3), *rows_t[i % 3], setpoints[i])
    return state


@kernel(types.int64(types.Array(types.int64, 1, "C"), types.float64))
def hold(table: np.ndarray, t_s: float) -> int:
    """What a held push finds at ``t_s`` [s] (:data:`ON_ITS_WAY` ... :data:`DEADLINE_PASSED`).

    ``table`` lists the snapshot's tool point and wrench and the state (:func:`hold_state`);
    :data:`WORST` and :data:`FREE` keep what the reasons tell.
    """
    position, wrench = listed(table, POSITION, 3), listed(table, WRENCH, 6)
    state = listed(table, STATE, HOLD_SIZE)
    x, y, z = position[0], position[1], position[2]
    nx, ny, nz = state[PUSH], state[PUSH + 1], state[PUSH + 2]
    if (x - state[AT]) * nx + (y - state[AT + 1]) * ny + (z - state[AT + 2]) * nz > LOST_PUSH_TRAVEL_M:
        state[AT], state[AT + 1], state[AT + 2], state[SINCE] = x, y, z, t_s  # ran on: its new mark
        state[SETTLED_SINCE] = math.nan
    if state[CONTACT]:  # a CONTACT's hold that runs on touching nothing (any force's direction) fails
        fx, fy, fz = wrench[0], wrench[1], wrench[2]
        if math.sqrt(fx * fx + fy * fy + fz * fz) >= state[TOUCHING]:
            state[PRESSED_AT], state[PRESSED_AT + 1], state[PRESSED_AT + 2] = x, y, z
            free = 0.0
        else:
            free = (
                (x - state[PRESSED_AT]) * nx
                + (y - state[PRESSED_AT + 1]) * ny
                + (z - state[PRESSED_AT + 2]) * nz
            )
        state[FREE] = free
        if free > LOST_CONTACT_M:
            return LOST_CONTACT
    elapsed, worst = t_s - state[SINCE], 0.0
    for k in range(int(state[TERMS_COUNT])):  # the rows of diag(R^T, R^T) it needs
        at = TERMS + TERM * k
        half = int(state[at])
        error = abs(
            state[at + 1] * wrench[half]
            + state[at + 2] * wrench[half + 1]
            + state[at + 3] * wrench[half + 2]
            - state[at + 4]
        )
        if error > worst:  # Python's max(worst, error)
            worst = error
    state[WORST] = worst
    if worst <= state[TOLERANCE]:
        if math.isnan(state[SETTLED_SINCE]):
            state[SETTLED_SINCE] = t_s
        if t_s - state[SETTLED_SINCE] >= state[SETTLE_TIME]:
            return SETTLED
    else:
        state[SETTLED_SINCE] = math.nan
    if elapsed >= state[MAX_TIME]:
        return BOUND_REACHED
    return DEADLINE_PASSED if t_s >= state[DEADLINE] else ON_ITS_WAY


def hold_ended(
    found: int, state: FloatArray, segment: Segment, force_axes: FloatArray, t_s: float
) -> tuple[bool, str] | None:
    """``(done, reason)`` of what :func:`hold` found at ``t_s`` [s]; None on its way or past its deadline.

    ``force_axes`` as :func:`hold_state`'s.
    """
    settled = segment.completion
    assert isinstance(settled, ForceSettled)
    if found == LOST_CONTACT:
        return False, (
            f"lost contact: the tool ran on {state[FREE] * 1e3:.1f} mm along its push touching nothing "
            f"(under {state[TOUCHING]:g} N) at {t_s:.2f} s"
        )
    if found == SETTLED:
        return True, "force settled"
    if found != BOUND_REACHED:
        return None
    # Still pressing, but not steadily (a peg sliding down a chamfer, say): the
    # contact is held, so the statement succeeds and says so; lost, it fails.
    worst = float(state[WORST])
    setpoint = float(np.max(np.abs(segment.force_setpoint[force_axes])))
    if worst <= 0.5 * setpoint:
        return True, (
            f"contact held, force within {worst:.1f} N of its setpoint but not settled "
            f"to {settled.tolerance_n:g} N in {settled.max_time_s:g} s"
        )
    return False, f"force did not settle within {settled.max_time_s:g} s"


LOST_CONTACT_M = 0.015
"""A CONTACT's hold whose tool runs on this far along its push touching nothing has lost its
contact and fails [m]. A peg sliding off the hole's chamfer falls into the bore rubbing its wall
(4-7 N sensed all the 43 mm down, realistic seed 1); a hold whose touch was the tool's own
inertia (issue 14: SPEED 100 mm/s, before the touch was judged without it) pushed the tool 606
mm through free air, 7.2 s, until the path deviation stopped it."""

LOST_SURFACE_M = 0.005
"""A motion statement's held push that ran on this far along itself has lost its surface, as its
failure says [m]: more than a tilted table's rise over a slide (2 deg over 100 mm is 3.5 mm)."""


def segment_push(segment: Segment) -> tuple[tuple[float, float, float], float]:
    """The segment's push, its force setpoint's translation in the world: unit direction, size [N].

    ``((0, 0, 0), 0)`` for a segment that pushes nothing.
    """
    push = np.asarray(segment.frame_rotation, dtype=float).dot(np.asarray(segment.force_setpoint[:3]))
    size = float(np.linalg.norm(push))
    if not size > 0.0:
        return (0.0, 0.0, 0.0), 0.0
    nx, ny, nz = (push / size).tolist()
    return (nx, ny, nz), size


def lost_surface(segment: Segment, start: tuple[float, ...], position: FloatArray) -> str:
    """What a failure adds when the segment's held push ran on along itself: its surface is gone.

    A SLIDE off a fixture's edge: the push follows the tool down at its SPEED
    (:func:`cosmos.osc.held_push.held_push_cap`) while the motion axes reach their goal, and the
    statement does not arrive; "18.3 mm from its goal" said nothing of why (17.7 mm of it was the
    fall along the push). Empty when the push is held, or the segment holds none.
    """
    push, _ = segment_push(segment)
    ran = sum((p - s) * n for p, s, n in zip(position.tolist(), start, push, strict=True))
    if not any(push) or ran <= LOST_SURFACE_M:
        return ""
    return f"; it lost its surface: the tool ran on {ran * 1e3:.1f} mm along its push"
