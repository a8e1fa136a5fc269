"""The protective stops' tick, compiled (numba): one call a tick (contacts, force, drives, path).

:func:`supervise_tick` is the whole of a tick's supervision (:mod:`cosmos.execution.supervision`
says what each stop is) on a state array the supervisor sets up at each segment's start; Python
only words the stop it finds. Its slower looks (every 4th tick: the drives and the path,
:func:`slow_look`) and its look at the contacts (:func:`first_unexpected_contact`) are compiled
into it. In Python the looks cost 2 to 3 us a tick, and the three separate calls 1.5 to 3 us; the
arithmetic is the same, in the same order.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba.core import types

from cosmos.execution.contact_kernel import first_unexpected_contact
from cosmos.execution.joint_speed_watch import first_over_speed
from cosmos.jit import kernel
from cosmos.obstacles.kernels.arrays import _pointer

FloatArray = np.ndarray
IntArray = np.ndarray

LINE_START, LINE_DIRECTION, LINE_LENGTH2, LINE_SIZE = 0, 3, 6, 7
"""The commanded line's layout in its array: its start, its direction (end - start), the
direction's squared length."""


_VECTOR = types.Array(types.float64, 1, "A", readonly=True)


@kernel(
    types.Tuple((types.boolean, types.float64))(
        _VECTOR,
        types.float64,
        _VECTOR,
        _VECTOR,
        types.Array(types.float64, 2, "A", readonly=True),
        types.boolean,
    )
)
def slow_look(
    torque: FloatArray,
    lowest_limit: float,
    position: FloatArray,
    line: FloatArray,
    axes: FloatArray,
    look_at_path: bool,
) -> tuple[bool, float]:
    """Whether a drive's torque is as large as ``lowest_limit``, and the tool's distance from its line.

    Args:
        torque: The drives' torques [N m]. # (n,)
        lowest_limit: The lowest of the drives' limits (at the saturation fraction) [N m].
        position: The measured tool point, world [m]. # (3,)
        line: The commanded line (:data:`LINE_START` ...). # (7,)
        axes: The world directions the distance is measured along, one a row. # (k, 3)
        look_at_path: Whether to measure it (else the distance is 0).

    Returns:
        ``(at_lowest, off_m)``: some ``|tau| >= lowest_limit``; the distance from the line
        on ``axes`` as :func:`cosmos.execution.expected.off_line` computes it [m].
    """
    at_lowest = False
    for i in range(torque.shape[0]):
        tau = torque[i]
        if tau >= lowest_limit or -tau >= lowest_limit:
            at_lowest = True
            break
    if not look_at_path:
        return at_lowest, 0.0
    dx, dy, dz = line[LINE_DIRECTION], line[LINE_DIRECTION + 1], line[LINE_DIRECTION + 2]
    rx = position[0] - line[LINE_START]
    ry = position[1] - line[LINE_START + 1]
    rz = position[2] - line[LINE_START + 2]
    length2 = line[LINE_LENGTH2]
    if length2 > 1e-12:
        along = (rx * dx + ry * dy + rz * dz) / length2
        along = 0.0 if along < 0.0 else along  # max(0.0, along), as Python's max takes it
        along = along if along < 1.0 else 1.0  # min(1.0, along)
        rx, ry, rz = rx - along * dx, ry - along * dy, rz - along * dz
    total = 0.0
    for k in range(axes.shape[0]):
        component = rx * axes[k, 0] + ry * axes[k, 1] + rz * axes[k, 2]
        total += component * component
    return at_lowest, math.sqrt(total)


FORCE_TICKS = 3
"""Ticks in a row above the range before the stop (a one-tick impact spike is not a stop)."""
PATH_DEVIATION_M = 0.05
"""Largest distance of the measured tool point from its commanded line [m]."""
SLOW_CHECK_EVERY = 4
"""The path and the drives are looked at every this many ticks (4 ms: 4 mm at 1 m/s);
contacts and force every tick."""

NO_STOP, CONTACT_STOP, FORCE_STOP, PATH_STOP, DRIVE_STOP, SPEED_STOP = 0, 1, 2, 3, 4, 5
"""What :func:`supervise_tick` found (:class:`cosmos.execution.supervision.StopKind`'s values)."""

# The supervision's state, one array of floats: its layout.
ALLOW_FIXTURE = 0  # the statement expects the tool on the fixtures (or is guarded): 1.0, else 0.0
GUARDED = 1  # a guarded motion: the tool may touch obstacles
INHERITED = 2  # a contact the statement began with is still allowed
SINCE_TOUCH = 3  # ticks since the tool last touched a fixture (while INHERITED)
GONE_TICKS = 4  # ... after which, away from the start, the inherited contact is over
START = 5  # the tool point where the segment began (3)
REACH2 = 8  # the squared distance from START beyond which the tool is away [m^2]
FORCE_LIMIT2 = 9  # the statement's force limit, squared [N^2]
RATING2 = 10  # the wrist sensor's rating, squared [N^2]: the limit while INHERITED
OVER = 11  # ticks in a row above the limit
TICK = 12  # ticks since the segment began (the slow looks every SLOW_CHECK_EVERY)
LOWEST = 13  # the lowest of the drives' limits at the saturation fraction [N m]
LOOK_AT_PATH = 14  # the segment's path is supervised (it has free translation axes)
FIELD_ACTING = 15  # an obstacle's field acts: the path is not supervised
TOUCHED = 16  # the tool has touched a fixture since the segment began
COUNTING = 17  # a drive's looks at its limit are being counted
LOOKS = 18  # looks at its limit that make a drive's stop
LINE = 19  # the commanded line (LINE_SIZE)
STOP_WHICH = LINE + LINE_SIZE  # the stop supervise_listed found: which (a contact, a drive, a joint) ...
STOP_VALUE = STOP_WHICH + 1  # ... and its value (supervise_tick's Returns)
DEVIATION_KEPT = STOP_VALUE + 1  # 1.0: every tick keeps the tool's largest distance from its line ...
DEVIATION_MOST = DEVIATION_KEPT + 1  # ... here [m] (the field on the tool's watch, in an episode)
SATURATED_AT = DEVIATION_MOST + 1
"""Then each drive's limit at the saturation fraction [N m] (n), then its looks at it so far (n)."""


def state_size(joints: int) -> int:
    """The length of the supervision's state for an arm of ``joints`` drives."""
    return SATURATED_AT + 2 * joints


@kernel
def _speed_look(qd: FloatArray, watch: FloatArray) -> tuple[int, int, float]:
    """The joints' speeds (:func:`first_over_speed`): a joint over its limit long enough, and its speed."""
    joint = first_over_speed(qd, watch)
    if joint < 0:
        return NO_STOP, 0, 0.0
    return SPEED_STOP, joint, abs(qd[joint])


@kernel
def _away(position: FloatArray, state: FloatArray) -> bool:
    """Whether the tool point is farther than REACH2's root from where the segment began."""
    x = position[0] - state[START]
    y = position[1] - state[START + 1]
    z = position[2] - state[START + 2]
    return x * x + y * y + z * z > state[REACH2]


@kernel
def _at_a_limit(torque: FloatArray, state: FloatArray) -> bool:
    """Whether some drive's torque is as large as its own limit (either sign)."""
    for joint in range(torque.shape[0]):
        tau, limit = torque[joint], state[SATURATED_AT + joint]
        if tau >= limit or -tau >= limit:
            return True
    return False


@kernel
def _count_saturation(torque: FloatArray, state: FloatArray) -> int:
    """Count each drive's looks at its limit (a drive below it starts again): the drive stopped, or -1."""
    counts, counting = SATURATED_AT + torque.shape[0], False
    for joint in range(torque.shape[0]):
        tau, limit = torque[joint], state[SATURATED_AT + joint]
        if tau >= limit or -tau >= limit:
            state[counts + joint] += 1.0
            if state[counts + joint] >= state[LOOKS]:
                return joint
        else:
            state[counts + joint] = 0.0
        counting = counting or state[counts + joint] != 0.0
    state[COUNTING] = 1.0 if counting else 0.0
    return -1


LIVE_VECTOR = types.Array(types.float64, 1, "C")
"""A live buffer as the executor passes it (an exact match: numba converts any other type in Python,
1 us a call)."""


@kernel(
    types.Tuple((types.int64, types.int64, types.float64))(
        types.int64,
        types.Array(types.int32, 2, "A"),  # MuJoCo's contacts as a strided view: always this type
        types.Array(types.int8, 2, "C"),
        LIVE_VECTOR,
        LIVE_VECTOR,
        LIVE_VECTOR,
        LIVE_VECTOR,
        types.Array(types.float64, 2, "C"),
        LIVE_VECTOR,
        LIVE_VECTOR,
    )
)
def supervise_tick(
    ncon: int,
    geom: IntArray,
    kinds: IntArray,
    wrench: FloatArray,
    torque: FloatArray,
    position: FloatArray,
    state: FloatArray,
    axes: FloatArray,
    qd: FloatArray,
    watch: FloatArray,
) -> tuple[int, int, float]:
    """One tick of the protective stops (:class:`cosmos.execution.supervision.Supervisor`), in one call.

    The contacts (:func:`first_unexpected_contact`) and the wrist's force every tick; the drives
    and the path (:func:`slow_look`) every :data:`SLOW_CHECK_EVERY` ticks; then, if none of them
    stops the arm, the joints' speeds (:func:`first_over_speed`); ``state`` (the layout above) and
    ``watch`` are read and brought up to date; while ``state[DEVIATION_KEPT]`` is set, first the
    tool's distance from its line (:func:`slow_look`'s) is kept in ``state[DEVIATION_MOST]`` if larger.

    Args:
        ncon: How many contacts MuJoCo found.
        geom: The contacts' geom pairs (MuJoCo's ``data.contact.geom``), ``ncon`` rows or more. # (m, 2)
        kinds: Each pair of geoms' kind. # (ngeom, ngeom)
        wrench: The wrench the tool applies, as the wrist sensor gave it, world [N, N m]. # (6,)
        torque: The torques the drives apply [N m]. # (n,)
        position: The measured tool point, world [m]. # (3,)
        state: The supervision's state. # (state_size(n),)
        axes: The world directions the path's distance is measured along, one a row. # (k, 3)
        qd: The joints' speeds [rad/s]. # (n,)
        watch: The speed watch (:func:`first_over_speed`'s ``watch``). # (1 + 2 n,)

    Returns:
        ``(kind, which, value)``: ``NO_STOP``, or the stop found: a contact's index in ``geom``; the
        force at the wrist [N]; the distance off the path [m]; a drive's index and its looks; a
        joint's index and its speed [rad/s].
    """
    if state[DEVIATION_KEPT] != 0.0:  # as slow_look measures it for the PATH stop
        deviated = slow_look(torque[:0], 0.0, position, state[LINE : LINE + LINE_SIZE], axes, True)[1]
        if deviated > state[DEVIATION_MOST]:  # max(most, deviated), as Python's max takes it
            state[DEVIATION_MOST] = deviated
    inherited = state[INHERITED] != 0.0
    if ncon:
        allow_fixture = state[ALLOW_FIXTURE] != 0.0 or inherited
        index, touching = first_unexpected_contact(geom[:ncon], kinds, allow_fixture, state[GUARDED] != 0.0)
        if touching:
            state[TOUCHED] = 1.0
        if index >= 0:
            return CONTACT_STOP, index, 0.0
        if inherited:
            state[SINCE_TOUCH] = 0.0 if touching else state[SINCE_TOUCH] + 1.0
    elif inherited:
        state[SINCE_TOUCH] += 1.0
    if inherited and state[SINCE_TOUCH] >= state[GONE_TICKS] and _away(position, state):
        state[INHERITED] = 0.0
        inherited = False
    fx, fy, fz = wrench[0], wrench[1], wrench[2]
    push2 = fx * fx + fy * fy + fz * fz
    if push2 > (state[RATING2] if inherited else state[FORCE_LIMIT2]):
        state[OVER] += 1.0
        if state[OVER] >= FORCE_TICKS:
            return FORCE_STOP, 0, math.sqrt(push2)
    else:
        state[OVER] = 0.0
    state[TICK] += 1.0
    if state[TICK] % SLOW_CHECK_EVERY:
        return _speed_look(qd, watch)
    # A torque as large as the lowest limit (only then is each drive held against its own), and
    # the tool's distance from its line.
    look_at_path = state[LOOK_AT_PATH] != 0.0 and state[FIELD_ACTING] == 0.0
    line = state[LINE : LINE + LINE_SIZE]
    at_lowest, off = slow_look(torque, state[LOWEST], position, line, axes, look_at_path)
    if state[COUNTING] != 0.0 or (at_lowest and _at_a_limit(torque, state)):
        joint = _count_saturation(torque, state)
        if joint >= 0:
            return DRIVE_STOP, joint, state[SATURATED_AT + torque.shape[0] + joint]
    if look_at_path and off > PATH_DEVIATION_M:
        return PATH_STOP, 0, off
    return _speed_look(qd, watch)


# The arrays of a tick listed by address (supervise_listed's table, int64): per array its address, rows
# and columns; MuJoCo's contacts' geom pairs as the rows of their records, read as int32 (their first two).
GEOMS, KINDS, WRENCH, TORQUE, POSITION, STATE, AXES, QD, WATCH = range(0, 27, 3)
TABLE_SIZE = WATCH + 3


@kernel(types.int64(types.int64, types.Array(types.int64, 1, "C")))
def supervise_listed(ncon: int, table: IntArray) -> int:
    """:func:`supervise_tick` on the arrays ``table`` lists (their views made here): one argument for ten.

    numba converts each array argument of a call from Python (50-100 ns each); the supervisor lists its
    live buffers once (:class:`cosmos.execution.supervision.Supervisor`) and calls this every tick.

    Args:
        ncon: How many contacts MuJoCo found.
        table: Per array (``GEOMS`` ... ``WATCH``) its address, rows and columns; the contacts'
            rows are ``ncon`` records of as many int32 as the columns say. # (TABLE_SIZE,)

    Returns:
        The stop's kind (``NO_STOP`` ...); its ``which`` and ``value`` are written to the state's
        ``STOP_WHICH`` and ``STOP_VALUE``.
    """
    records = numba.carray(_pointer(table[GEOMS]), (ncon, table[GEOMS + 2]), np.int32)
    kinds = numba.carray(_pointer(table[KINDS]), (table[KINDS + 1], table[KINDS + 2]), np.int8)
    state = numba.carray(_pointer(table[STATE]), table[STATE + 2], np.float64)
    kind, which, value = supervise_tick(
        ncon,
        records[:, :2],
        kinds,
        numba.carray(_pointer(table[WRENCH]), table[WRENCH + 2], np.float64),
        numba.carray(_pointer(table[TORQUE]), table[TORQUE + 2], np.float64),
        numba.carray(_pointer(table[POSITION]), table[POSITION + 2], np.float64),
        state,
        numba.carray(_pointer(table[AXES]), (table[AXES + 1], table[AXES + 2]), np.float64),
        numba.carray(_pointer(table[QD]), table[QD + 2], np.float64),
        numba.carray(_pointer(table[WATCH]), table[WATCH + 2], np.float64),
    )
    state[STOP_WHICH] = which
    state[STOP_VALUE] = value
    return kind


@kernel(types.float64(types.Array(types.int64, 1, "C")))
def path_deviation_listed(table: IntArray) -> float:
    """The tool point's distance from its commanded line on the path's axes (:func:`slow_look`'s) [m].

    On the arrays ``table`` lists (:func:`supervise_listed`'s): the tool point, the state's line,
    the axes; what :func:`cosmos.execution.expected.off_line` computes, in one compiled call.
    """
    position = numba.carray(_pointer(table[POSITION]), table[POSITION + 2], np.float64)
    state = numba.carray(_pointer(table[STATE]), table[STATE + 2], np.float64)
    axes = numba.carray(_pointer(table[AXES]), (table[AXES + 1], table[AXES + 2]), np.float64)
    _, off = slow_look(position[:0], 0.0, position, state[LINE : LINE + LINE_SIZE], axes, True)
    return off
