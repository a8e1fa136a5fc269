"""Protective stops: what the runtime watches every tick besides the statement's own goal.

Like an industrial controller's protective stop (UR), force supervision (ABB's FCSupv) or
reflexes (Franka), every servo tick the executor asks a :class:`Supervisor` whether the arm is
doing something no statement asked for:

- **contact**: a link or the tool touches something the running statement does not expect to
  touch (MuJoCo's contact list against geom sets made once). A free motion expects nothing; a
  statement that holds or seeks contact (CONTACT, SLIDE, INSERT, a WAIT or MOVE while a contact
  is held, a COMPLY spring) expects the tool against the fixtures; a guarded motion (UNTIL on a
  force or moment) against anything. A link never touches anything. A contact the tool had when
  the statement began (lifting off the table), or that the statement before expected (a peg in
  its hole), is allowed until it has been gone for :data:`CONTACT_GONE_S` with the tool more
  than :data:`INHERITED_REACH_M` from where the statement began.
- **force**: the wrist's force above the statement's range (:func:`force_limit_n`) for
  :data:`~cosmos.execution.supervision_kernel.FORCE_TICKS` ticks in a row; while the tool is
  still in a contact the statement began with, up to the sensor's rating.
- **path**: the tool point more than :data:`PATH_DEVIATION_M` off the commanded straight line on
  the motion-controlled axes (not while an obstacle's field acts, nor on a COMPLY spring's axes).
- **drive**: a joint's torque at its drive's limit for :data:`SATURATION_S`.
- **speed**: a joint beyond its speed limit (:mod:`cosmos.execution.joint_speed_watch`).

Contacts and force are looked at every tick, the path and the drives every
:data:`SLOW_CHECK_EVERY` ticks, in one compiled call a tick
(:mod:`cosmos.execution.supervision_kernel`), under 1 us. Each is a :class:`ProtectiveStop`
naming what, where and how hard; the executor ends the statement as failed, logs
``protective_stop`` (and ``collision`` for a contact) and holds the arm.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from numba import typeof

from cosmos.execution.contact_kernel import TOOL_FIXTURE
from cosmos.execution.contact_pairs import ContactPairs
from cosmos.execution.contact_roles import PAIR_KINDS, ROLES, Role, geom_roles
from cosmos.execution.expected import (
    FREE_MOTION_FORCE_N,
    expects_contact,
    force_limit_n,
    has_force_term,
    off_line,
    spring_press_n,
)
from cosmos.execution.fixture_reach import FixtureReach
from cosmos.execution.joint_speed_watch import JointSpeedWatch
from cosmos.execution.protective_stop import (
    ProtectiveStop,
    StopKind,
    contact_stop,
    drive_stop,
    force_stop,
    path_stop,
)
from cosmos.execution.supervision_kernel import (
    ALLOW_FIXTURE,
    AXES,
    COUNTING,
    DEVIATION_KEPT,
    DEVIATION_MOST,
    FIELD_ACTING,
    FORCE_LIMIT2,
    GONE_TICKS,
    GUARDED,
    INHERITED,
    KINDS,
    LINE,
    LINE_SIZE,
    LIVE_VECTOR,
    LOOK_AT_PATH,
    LOOKS,
    LOWEST,
    OVER,
    POSITION,
    QD,
    RATING2,
    REACH2,
    SATURATED_AT,
    SINCE_TOUCH,
    SLOW_CHECK_EVERY,
    START,
    STATE,
    STOP_VALUE,
    STOP_WHICH,
    TABLE_SIZE,
    TICK,
    TORQUE,
    TOUCHED,
    WATCH,
    WRENCH,
    path_deviation_listed,
    state_size,
    supervise_listed,
    supervise_tick,
)
from cosmos.plan import Segment
from cosmos.plant import Plant
from cosmos.workcell import WRIST_SENSOR

FloatArray = np.ndarray
IntArray = np.ndarray

SATURATION_S = 0.05
"""A drive at its torque limit this long is a protective stop [s]."""
SATURATION_FRACTION = 0.999
"""A torque at or above this fraction of its limit counts as at the limit."""
CONTACT_GONE_S = 0.05
"""A contact the tool had at a statement's start stays allowed until gone this long [s]..."""
NEAR_FIXTURE_M = 0.0005
"""A tool this close to a fixture is at it, touching or not: a peg in its hole's bore is within
its 0.12 mm radial clearance of the wall [m]."""
INHERITED_REACH_M = 0.05
"""... and the tool this far from where the statement began [m]: longer than the hole is deep
(45 mm), so a peg pulled out grazes its bore freely; a lift off the table is clear of it
long before."""
_RATING2 = WRIST_SENSOR.force_n**2


class Supervisor:
    """Watches one arm every tick (module docstring); reset at every segment.

    A tick is one compiled call (:func:`cosmos.execution.supervision_kernel.supervise_tick`) on
    the state the segment's start set up; this class words the stop it finds.

    Args:
        plant: The workcell (its contact list, its drives' limits).
        torque_limits_nm: The drives' symmetric torque limits [N m]. # (6,)
        servo_dt_s: Servo period [s].
    """

    def __init__(self, plant: Plant, torque_limits_nm: FloatArray, servo_dt_s: float):
        self._plant = plant
        self._data = plant.data
        self._table = np.zeros(TABLE_SIZE, dtype=np.int64)  # the tick's arrays by address (_list)
        self._free_roles = geom_roles(plant)
        self._set_roles(self._free_roles)
        self._held_body = -1
        self._owners = plant.geom_owners
        self._torque_limits = [float(t) for t in torque_limits_nm]
        joints = len(self._torque_limits)
        saturated_at = [SATURATION_FRACTION * t for t in self._torque_limits]
        self._dt_s = servo_dt_s
        # The tick's state (supervision_kernel's layout): what lasts, then what each segment sets.
        self._state = state = np.zeros(state_size(joints))
        state[GONE_TICKS] = max(1, round(CONTACT_GONE_S / servo_dt_s))
        state[REACH2] = INHERITED_REACH_M * INHERITED_REACH_M
        state[RATING2] = _RATING2
        state[FORCE_LIMIT2] = FREE_MOTION_FORCE_N**2
        state[LOWEST] = min(saturated_at)
        state[LOOKS] = max(1, math.ceil(SATURATION_S / (SLOW_CHECK_EVERY * servo_dt_s) - 1e-9))
        state[SATURATED_AT : SATURATED_AT + joints] = saturated_at
        self._counts = slice(SATURATED_AT + joints, SATURATED_AT + 2 * joints)  # each drive's looks
        self.deviation_kept = state[DEVIATION_KEPT : DEVIATION_MOST + 1]
        """``(keeping, largest)``: while ``keeping`` is 1.0 each tick keeps the tool's largest distance from
        its path in ``largest`` [m] (as the PATH stop measures it: the field on the tool's watch)."""
        self._list(STATE, state)
        self.free_force_limit_n = FREE_MOTION_FORCE_N
        """The free-motion force limit now in force [N] (``LIMIT FORCE`` sets it)."""
        self.obstacle_names: Mapping[str, str] = {}
        """MuJoCo body name of each occupied obstacle slot -> the obstacle's name."""
        self._last = (-2, -1)  # the last segment's index and statement_index
        self._expect_fixture = False
        self._force_limit = FREE_MOTION_FORCE_N
        # The commanded line as floats (for path_deviation_m): start, direction, length^2.
        self._line: tuple[tuple[float, ...], tuple[float, ...], float] = ((0.0,) * 3, (0.0,) * 3, 0.0)
        self._path_axes: list[tuple[float, ...]] = []  # the task frame's free translation axes, world
        self._pairs = ContactPairs(self._data, self._table)  # the contacts' geom pairs, their views
        self._pairs.update(self._data.ncon)
        self._axes = np.zeros((0, 3))
        self._list(AXES, self._axes)
        self.watch_joint_speeds([0.0] * joints)  # none until the arm's are known
        # The compiled tick without numba's dispatch (it types every argument: 0.5 us a tick) on the live
        # views seen to be of the plain tick's declared types (the executor's, the same every tick).
        supervise_listed.compile_declared()
        (declared,) = supervise_listed.signatures
        self._listed_tick = supervise_listed.overloads[declared].entry_point
        self._listed_deviation: Any = None  # path_deviation_listed's, loaded at its first call
        self._live_types = (LIVE_VECTOR,) * 3  # wrench, torque, position as supervise_tick declares them
        self._wrench: object = None  # the live views listed (_check_unlisted)
        self._torque: object = None
        self._position: object = None

    def _list(self, at: int, array: np.ndarray) -> None:
        """List ``array`` (C-contiguous, of the dtype its view is made with) at ``at`` in the tick's table."""
        rows, columns = array.shape if array.ndim == 2 else (1, array.shape[0])
        self._table[at : at + 3] = (array.ctypes.data, rows, columns)

    def watch_joint_speeds(self, limits_rad_s: Sequence[float]) -> None:
        """Stop a joint beyond its speed limit [rad/s] (:mod:`cosmos.execution.joint_speed_watch`)."""
        qd = self._data.qvel[: len(self._torque_limits)]  # the plant's joint speeds, a live view
        self._speeds = JointSpeedWatch(qd, np.asarray(limits_rad_s, dtype=float), self._dt_s)
        self._list(QD, qd)
        self._list(WATCH, self._speeds.watch)

    @property
    def field_acting(self) -> bool:
        """Set by the executor while an obstacle's field acts: the path is not supervised."""
        return bool(self._state[FIELD_ACTING])

    @field_acting.setter
    def field_acting(self, acting: bool) -> None:
        self._state[FIELD_ACTING] = acting

    def _set_roles(self, roles: np.ndarray) -> None:
        self._roles = roles
        self._roles_list: list[int] = roles.tolist()
        # Each pair of geoms' kind (geom1, geom2), read by the compiled look at the contacts.
        self._pair_kinds = np.asarray(PAIR_KINDS, dtype=np.int8)[
            roles[:, None].astype(np.int64) * ROLES + roles[None, :]
        ]
        self._list(KINDS, self._pair_kinds)
        self._near_fixture = FixtureReach(self._plant, roles == Role.TOOL, self._pair_kinds == TOOL_FIXTURE)

    def holding(self, body: int) -> None:
        """The object of MuJoCo body ``body`` is held (-1: none): part of the tool until let go.

        Its contacts with the fingers are the arm's own; its contacts with the fixtures and
        other objects are the tool's (docs/language.md: while held, the object is part of the arm).
        """
        if body == self._held_body:
            return
        self._held_body = body
        roles = self._free_roles.copy()
        if body >= 0:
            roles[self._plant.model.geom_bodyid == body] = Role.TOOL
        roles.setflags(write=False)
        self._set_roles(roles)

    # --------------------------------------------------------------- segments

    def start(self, segment: Segment, position: FloatArray, goal_position: FloatArray) -> None:
        """A segment starts at the measured tool point ``position`` toward ``goal_position``."""
        same = self._last == (segment.index - 1, segment.statement_index)  # a CONTACT's hold: not inherited
        self._last = (segment.index, segment.statement_index)
        state = self._state
        worked_in_contact = self._expect_fixture  # the previous statement's: a peg may graze its hole
        self._expect_fixture = expects_contact(segment)
        guarded = has_force_term(segment.until)[0]
        state[ALLOW_FIXTURE], state[GUARDED] = self._expect_fixture or guarded, guarded
        press = spring_press_n(segment, position, goal_position)
        self._force_limit = force_limit_n(segment, self.free_force_limit_n, press)
        state[FORCE_LIMIT2] = self._force_limit**2
        state[OVER] = state[TICK] = state[COUNTING] = 0.0
        state[self._counts] = 0.0
        # At a fixture, touching or not: a block just grasped off the table may rest 0.1 mm above it.
        if not same:  # a CONTACT's hold keeps what its approach had
            state[INHERITED] = worked_in_contact or self._tool_touches_fixture() or self._tool_at_fixture()
        state[TOUCHED] = state[SINCE_TOUCH] = 0.0
        state[START : START + 3] = position
        self._path_axes = [
            tuple(segment.frame_rotation[:, i].tolist())
            for i in range(3)
            if segment.motion_axes[i] and segment.stiffness[i] is None
        ]
        self._axes = np.array(self._path_axes, dtype=float).reshape(-1, 3)
        self._list(AXES, self._axes)
        state[LOOK_AT_PATH] = bool(self._path_axes)
        self.leg(position, goal_position)

    def leg(self, start: FloatArray, end: FloatArray) -> None:
        """The commanded straight line changes (a VIA point passed): from ``start`` to ``end``."""
        line = np.asarray(end, dtype=float) - start
        self._line = (
            tuple(np.asarray(start, dtype=float).tolist()),
            tuple(line.tolist()),
            float(line @ line),
        )
        self._state[LINE : LINE + LINE_SIZE] = [*self._line[0], *self._line[1], self._line[2]]

    def path_deviation_m(self, position: FloatArray) -> float:
        """The tool point's distance from the segment's commanded line (as the PATH stop measures it) [m].

        For the live tool point the ticks look at, one compiled call (1 us less than in Python).
        """
        if position is not self._position:
            return off_line(position.tolist(), *self._line, self._path_axes)
        if self._listed_deviation is None:  # among obstacles only (the field's watch): loaded then
            path_deviation_listed.compile_declared()
            (declared,) = path_deviation_listed.signatures
            self._listed_deviation = path_deviation_listed.overloads[declared].entry_point
        return float(self._listed_deviation(self._table))

    # ------------------------------------------------------------------ ticks

    def check(
        self, t_s: float, wrench: FloatArray, torque: FloatArray, position: FloatArray
    ) -> ProtectiveStop | None:
        """The hazard found at this tick, if any.

        Args:
            t_s: Simulated time [s].
            wrench: The wrench the tool applies, as the wrist sensor gave it, world [N, N m]. # (6,)
            torque: The torques the drives apply [N m]. # (6,)
            position: The measured tool point, world [m]. # (3,)
        """
        ncon = self._data.ncon
        if self._pairs.count != ncon:
            self._pairs.update(ncon)
        if wrench is not self._wrench or torque is not self._torque or position is not self._position:
            return self._check_unlisted(ncon, t_s, wrench, torque, position)
        kind = self._listed_tick(ncon, self._table)
        return None if not kind else self._found(kind, t_s, wrench)

    def checker(
        self, wrench: FloatArray, torque: FloatArray, position: FloatArray
    ) -> Callable[[float], ProtectiveStop | None]:
        """:meth:`check` on these live views for a segment's ticks: ``check(t_s)``, one argument a tick.

        The views are listed here, once (a :meth:`check` on others lists those instead): a tick reads
        MuJoCo's contact count and makes the compiled call.
        """
        if type(self).check is not Supervisor.check or not self._listable(wrench, torque, position):
            check = self.check  # a subclass's own, or views of other types: as the tick declares them
            return lambda t_s: check(t_s, wrench, torque, position)
        data, pairs, listed, table, found = (
            self._data,
            self._pairs,
            self._listed_tick,
            self._table,
            self._found,
        )

        def tick_check(t_s: float) -> ProtectiveStop | None:
            ncon = data.ncon
            if pairs.count != ncon:
                pairs.update(ncon)
            kind = listed(ncon, table)
            return None if not kind else found(kind, t_s, wrench)

        return tick_check

    def _listable(self, wrench: FloatArray, torque: FloatArray, position: FloatArray) -> bool:
        """List the three live views if they are of the types the compiled tick declares (True), else not."""
        if tuple(typeof(array) for array in (wrench, torque, position)) != self._live_types:
            return False
        self._wrench, self._torque, self._position = wrench, torque, position  # kept alive: listed
        self._list(WRENCH, wrench)
        self._list(TORQUE, torque)
        self._list(POSITION, position)
        return True

    def _check_unlisted(
        self, ncon: int, t_s: float, wrench: FloatArray, torque: FloatArray, position: FloatArray
    ) -> ProtectiveStop | None:
        """:meth:`check` on arrays not listed: listed if of the tick's types, else by numba's dispatch."""
        if self._listable(wrench, torque, position):
            kind = self._listed_tick(ncon, self._table)
            return None if not kind else self._found(kind, t_s, wrench)
        speeds, state = self._speeds, self._state
        supervise_tick.compile_declared()  # closed to other types: numba refuses them, converts the rest
        kind, state[STOP_WHICH], state[STOP_VALUE] = supervise_tick(  # numba's dispatch converts them
            ncon, self._pairs.kernel_view, self._pair_kinds, wrench, torque, position, state, self._axes,
            speeds.qd, speeds.watch,
        )  # fmt: skip
        return None if not kind else self._found(kind, t_s, wrench)

    def _found(self, kind: int, t_s: float, wrench: FloatArray) -> ProtectiveStop:
        """The stop the tick found, in words: its ``which`` and ``value`` (supervise_tick's) in the state."""
        which, value = int(self._state[STOP_WHICH]), float(self._state[STOP_VALUE])
        if kind == StopKind.CONTACT:
            roles = self._roles_list
            g1, g2 = self._pairs.view[which].tolist()
            arm, other = (g1, g2) if roles[g1] in (Role.LINK, Role.TOOL) else (g2, g1)
            owners, arm_roles = (self._owners[arm], self._owners[other]), (roles[arm], roles[other])
            return contact_stop(
                self._plant.model, self._data, which, owners, arm_roles, self.obstacle_names, t_s, wrench
            )
        if kind == StopKind.FORCE:
            limit = WRIST_SENSOR.force_n if self._state[INHERITED] else self._force_limit
            return force_stop(value, limit, t_s)
        if kind == StopKind.DRIVE:
            held_s = value * SLOW_CHECK_EVERY * self._dt_s
            return drive_stop(which, self._torque_limits[which], held_s, t_s)
        if kind == StopKind.SPEED:
            return ProtectiveStop(StopKind.SPEED, self._speeds.stop_text(which, t_s))
        return path_stop(value, t_s)

    def tool_touched(self) -> bool:
        """Whether the tool has touched a fixture since the segment started, or is at one now.

        Touched: MuJoCo's contacts. At: within :data:`NEAR_FIXTURE_M` (MuJoCo's distances), as a peg
        that slid into its bore's clearance untouched is.
        """
        return bool(self._state[TOUCHED]) or self._tool_at_fixture()

    def _tool_at_fixture(self) -> bool:
        """Whether the tool is within :data:`NEAR_FIXTURE_M` of a fixture (MuJoCo's distances)."""
        return self._near_fixture.within(NEAR_FIXTURE_M)

    def _tool_touches_fixture(self) -> bool:
        ncon = self._data.ncon
        if not ncon:
            return False
        kinds = self._pair_kinds
        return any(kinds[g1, g2] == TOOL_FIXTURE for g1, g2 in self._pairs.update(ncon).tolist())
