"""A CONTACT's approach judged each tick in one compiled call: touched, stopped short, or on its way.

The approach is eq. 20-21's goal motion toward a target 300 mm along its direction, done once
the tool pushes along it more than the touch threshold (2 N, or half the FORCE), the tool's own
inertia taken out (:mod:`cosmos.execution.touch_push`). Its command is a velocity servo without
an integral: met by a surface at a slant (a peg's end on the hole's chamfer, 2.5 mm off the
axis), at the landing's few mm/s it presses only what its damping makes of that speed (1-1.5 N
on the Panda), below the threshold, and stands there: with no TIMEOUT one such CONTACT ran 1124
s of simulated time without an outcome. So an approach that gets no further along its direction
for :data:`~cosmos.execution.closing.STALL_TIME_S` has stopped: pressing at least
:data:`LANDED_N` along it, it has landed (the hold then pushes its FORCE); pressing less,
something else holds it, and it fails.

All of it (the touch, the stall, the statement's TIMEOUT's deadline) is one compiled call a tick
(:func:`approach`, on the arrays a :class:`~cosmos.execution.listing.Listing` lists): in Python
it cost some 1.2 us a tick; the reasons are written in Python, once, when it ends
(:func:`ended`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numba.core import types

from cosmos.execution.closing import STALL_PROGRESS_M, STALL_TIME_S
from cosmos.execution.listing import POSITION, STATE, VELOCITY, WRENCH, listed
from cosmos.execution.touch_push import INERTIA_SIZE, approach_push, inertia, touched
from cosmos.jit import kernel
from cosmos.plan import ContactTouch, Segment, SegmentKind

FloatArray = np.ndarray

LANDED_N = 0.5
"""A stopped approach pressing this much along its direction has landed [N] (the push from which
the approach brakes: docs/language.md, CONTACT, "The landing")."""

DIRECTION, START, THRESHOLD, MAX_TRAVEL, PROGRESS, SINCE, FURTHEST, DEADLINE, PUSH, TRAVEL = (
    INERTIA_SIZE + k for k in (0, 3, 6, 7, 8, 9, 10, 11, 12, 13)
)
"""An approach's state after its inertia's: its unit direction, world (3); the tool point where it
started, world [m] (3); the touch threshold [N]; how far it goes before it fails "found no
contact" [m]; what counts as getting further in :data:`STALL_TIME_S` (0.5 mm, or a quarter of what
its SPEED covers in that time if less: SPEED may be 0.1 mm/s) [m]; when it last got further [s],
and how far along it was then [m]; the statement's TIMEOUT's deadline [s] (inf: none, or judged
elsewhere); the push along it [N] and how far along it the tool is [m] at the last tick judged."""
APPROACH_SIZE = TRAVEL + 1

ON_ITS_WAY, TOUCHED, NO_CONTACT, LANDED, HELD_BACK, DEADLINE_PASSED = 0, 1, 2, 3, 4, 5
"""What :func:`approach` finds at a tick."""


def approach_state(
    segment: Segment, start_xyz: tuple[float, ...], start_s: float, mass_kg: float, deadline_s: float
) -> FloatArray:
    """The state of CONTACT approach ``segment`` started at ``start_xyz`` [m], ``start_s`` [s].

    ``mass_kg`` is the tool's below the wrist sensor; ``deadline_s`` the TIMEOUT's deadline [s] if
    :func:`approach` is to find it passed (inf if not).
    """
    touch = segment.completion
    assert isinstance(touch, ContactTouch)
    speed = segment.speed_limit_mps
    state = np.zeros(APPROACH_SIZE)
    state[:INERTIA_SIZE] = inertia(mass_kg, speed)
    state[DIRECTION : DIRECTION + 3] = touch.direction_world
    state[START : START + 3] = start_xyz
    state[THRESHOLD], state[MAX_TRAVEL] = touch.threshold_n, touch.max_travel_m
    state[PROGRESS] = STALL_PROGRESS_M if not speed else min(STALL_PROGRESS_M, 0.25 * speed * STALL_TIME_S)
    state[SINCE], state[DEADLINE] = start_s, deadline_s
    return state


@kernel(types.int64(types.Array(types.int64, 1, "C"), types.float64))
def approach(table: np.ndarray, t_s: float) -> int:
    """What a CONTACT's approach finds at ``t_s`` [s] (:data:`ON_ITS_WAY` ... :data:`DEADLINE_PASSED`).

    ``table`` lists the snapshot's tool point, twist and wrench and the state
    (:func:`approach_state`); :data:`PUSH` and :data:`TRAVEL` keep what the reasons tell.
    """
    position, velocity = listed(table, POSITION, 3), listed(table, VELOCITY, 6)
    wrench, state = listed(table, WRENCH, 6), listed(table, STATE, APPROACH_SIZE)
    direction = state[DIRECTION : DIRECTION + 3]
    push, met = approach_push(state, wrench, velocity, direction, t_s)
    state[PUSH] = push
    if touched(state, met, state[THRESHOLD], t_s):
        return TOUCHED
    dx, dy, dz = direction[0], direction[1], direction[2]
    travel = (
        (position[0] - state[START]) * dx
        + (position[1] - state[START + 1]) * dy
        + (position[2] - state[START + 2]) * dz
    )
    state[TRAVEL] = travel
    if travel >= state[MAX_TRAVEL] - 1e-3:
        return NO_CONTACT
    if travel > state[FURTHEST] + state[PROGRESS]:
        state[FURTHEST], state[SINCE] = travel, t_s
    elif t_s - state[SINCE] >= STALL_TIME_S:
        return LANDED if push >= LANDED_N else HELD_BACK
    return DEADLINE_PASSED if t_s >= state[DEADLINE] else ON_ITS_WAY


def ended(found: int, state: FloatArray, cause: Callable[[], str]) -> tuple[bool, bool, str] | None:
    """``(done, touched, reason)`` of what :func:`approach` found, None on its way or past its deadline."""
    push, travel = state[PUSH], state[TRAVEL]
    if found == TOUCHED:
        return True, True, f"touched: {push:.2f} N along the approach"
    if found == NO_CONTACT:
        return False, False, f"found no contact within {state[MAX_TRAVEL] * 1e3:.0f} mm"
    if found == LANDED:
        return (
            True,
            True,
            f"touched: stopped against it {push:.2f} N along the approach for {STALL_TIME_S:g} s",
        )
    if found == HELD_BACK:
        return (
            False,
            False,
            (
                f"stopped {max(travel, 0.0) * 1e3:.1f} mm along its approach without touching "
                f"({push:.2f} N along it for {STALL_TIME_S:g} s): {cause()}"
            ),
        )
    return None


def timeout_reason(kind: SegmentKind, timeout_s: float, depth_m: float) -> str:
    """What a segment of ``kind`` that ran out its statement's TIMEOUT [s] says; ``depth_m``: an INSERT's [m].

    A CONTACT's TIMEOUT bounds its search for the surface (docs/language.md).
    """
    if kind is SegmentKind.CONTACT_APPROACH:
        return f"found no contact within {timeout_s:g} s"
    if kind is SegmentKind.INSERT:
        return f"timed out after {timeout_s:g} s at depth {depth_m * 1e3:.1f} mm"
    return f"timed out after {timeout_s:g} s"
