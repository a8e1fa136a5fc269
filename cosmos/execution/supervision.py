"""Protective stops: what the runtime watches every tick besides the statement's own goal.

Like an industrial controller's protective stop (UR), force supervision (ABB's
FCSupv) or reflexes (Franka), every servo tick the executor asks a
:class:`Supervisor` whether the arm is doing something no statement asked for:

- **contact**: a link or the tool touches something the running statement does
  not expect to touch (MuJoCo's contact list, ``data.ncon`` and geom ids against
  geom sets made once). A free motion expects nothing; a statement that holds or
  seeks contact (CONTACT, SLIDE, INSERT, a WAIT or MOVE while a contact is held, a
  COMPLY spring) expects the tool against the fixtures; a guarded motion (UNTIL on
  a force or moment) expects the tool against anything. A link never touches
  anything. A contact the tool already had when the statement began (lifting off
  the table), or that the statement before expected (a peg in its hole), is allowed
  until it has been gone for :data:`CONTACT_GONE_S` with the tool more than
  :data:`INHERITED_REACH_M` from where the statement began (a peg pulled out of a
  0.24 mm clearance hole leaves its bore's walls and grazes them again).
- **force**: the wrist sensor's force above the statement's expected range for
  :data:`FORCE_TICKS` ticks in a row (:func:`force_limit_n`); while the tool is
  still in a contact the statement began with (pulling a peg out of its hole),
  up to the sensor's rating.
- **path**: the measured tool point more than :data:`PATH_DEVIATION_M` off the
  commanded straight line on the motion-controlled axes (not while an obstacle's
  potential field acts: the field pushes the arm off the line on purpose, and not
  on a COMPLY spring's axes).
- **drive**: a joint's torque at its drive's limit for :data:`SATURATION_S`.

Contacts and force are looked at every tick; the path and the drives every
:data:`SLOW_CHECK_EVERY` ticks, which keeps the cost per tick near 2 us.

Each is a :class:`ProtectiveStop` naming what, where and how hard; the executor
ends the statement as failed, logs ``protective_stop`` (and ``collision`` for a
contact) and holds the arm.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from enum import IntEnum
from operator import ge

import mujoco
import numpy as np

from cosmos.execution.contact_kernel import TOOL_FIXTURE, first_unexpected_contact
from cosmos.execution.contact_roles import PAIR_KINDS, ROLES, Role, geom_roles
from cosmos.execution.expected import (
    FREE_MOTION_FORCE_N,
    expects_contact,
    force_limit_n,
    has_force_term,
    off_line,
    spring_press_n,
)
from cosmos.execution.supervision_kernel import LINE_SIZE, slow_look
from cosmos.plan import Segment
from cosmos.plant import Plant
from cosmos.workcell import WRIST_SENSOR

FloatArray = np.ndarray
IntArray = np.ndarray

FORCE_TICKS = 3
"""Ticks in a row above the range before the stop (a one-tick impact spike is not a stop)."""
PATH_DEVIATION_M = 0.05
"""Largest distance of the measured tool point from its commanded line [m]."""
SATURATION_S = 0.05
"""A drive at its torque limit this long is a protective stop [s]."""
SLOW_CHECK_EVERY = 4
"""Ticks between looks at the path and the drives (4 ms: 4 mm at 1 m/s); contacts and force: every tick."""
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


class StopKind(IntEnum):
    """Why the supervisor stopped the arm."""

    CONTACT = 1
    FORCE = 2
    PATH = 3
    DRIVE = 4


@dataclass(frozen=True)
class ProtectiveStop:
    """A hazard the supervisor found.

    Attributes:
        kind: Which supervision tripped.
        message: ``protective stop: link 3 hit obstacle 'ball' at 2.31 s, 14.2 N``.
        collision: For a contact, ``link3 touches ball`` (the ``collision`` event's reason); else "".
    """

    kind: StopKind
    message: str
    collision: str = ""


def _arm_part(owner: str) -> str:
    """``link3`` -> ``link 3``; ``tool`` stays."""
    return f"link {owner.removeprefix('link')}" if owner.startswith("link") else owner


class Supervisor:
    """Watches one arm every tick (module docstring); reset at every segment.

    Args:
        plant: The workcell (its contact list, its drives' limits).
        torque_limits_nm: The drives' symmetric torque limits [N m]. # (6,)
        servo_dt_s: Servo period [s].
    """

    def __init__(self, plant: Plant, torque_limits_nm: FloatArray, servo_dt_s: float):
        self._plant = plant
        self._data = plant.data
        self._free_roles = geom_roles(plant)
        self._set_roles(self._free_roles)
        self._held_body = -1
        self._owners = plant.geom_owners
        self._torque_limits = [float(t) for t in torque_limits_nm]
        self._saturated_at = [SATURATION_FRACTION * t for t in self._torque_limits]
        self._lowest_saturation = min(self._saturated_at)
        self._saturated_ticks = [0] * len(self._torque_limits)
        self._counting = False  # a drive's looks at its limit are being counted
        self._saturation_looks = max(1, math.ceil(SATURATION_S / (SLOW_CHECK_EVERY * servo_dt_s) - 1e-9))
        self._tick = 0
        self._gone_ticks = max(1, round(CONTACT_GONE_S / servo_dt_s))
        self._dt_s = servo_dt_s
        self.free_force_limit_n = FREE_MOTION_FORCE_N
        """The free-motion force limit now in force [N] (``LIMIT FORCE`` sets it)."""
        self.obstacle_names: Mapping[str, str] = {}
        """MuJoCo body name of each occupied obstacle slot -> the obstacle's name."""
        self.field_acting = False
        """Set by the executor while an obstacle's field acts: the path is not supervised."""
        self._last = (-2, -1)  # the last segment's index and statement_index
        self._expect_fixture = False
        self._guarded = False
        self._force_limit2 = FREE_MOTION_FORCE_N**2
        self._force_limit = FREE_MOTION_FORCE_N
        self._over = 0
        self._inherited = False
        self._since_touch = 0
        self._start: tuple[float, ...] = (0.0, 0.0, 0.0)  # the tool point where the segment began
        # The commanded line as floats (the check runs every tick): start, direction, length^2.
        self._line: tuple[tuple[float, ...], tuple[float, ...], float] = ((0.0,) * 3, (0.0,) * 3, 0.0)
        self._path_axes: list[tuple[float, ...]] = []  # the task frame's free translation axes, world
        self._geoms: IntArray = np.zeros((0, 2), dtype=np.int32)  # contact_geoms's view
        self._line_array = np.zeros(LINE_SIZE)  # the line and the axes as slow_look takes them
        self._axes, self._look_at_path = np.zeros((0, 3)), False

    def contact_geoms(self, ncon: int) -> IntArray:
        """MuJoCo's ``ncon`` contacts' geom pairs (``data.contact.geom``), a live view. # (ncon, 2).

        MuJoCo writes its contacts at the start of its arena every step: the view (whose list the
        bindings build on every call, 0.5-1 us) is kept while their count stays the same.
        """
        view = self._geoms
        if view.shape[0] != ncon:
            view = self._geoms = self._data.contact.geom
        return view

    def _set_roles(self, roles: np.ndarray) -> None:
        self._roles = roles
        self._roles_list: list[int] = roles.tolist()
        # Each pair of geoms' kind (geom1, geom2), read by the compiled look at the contacts.
        self._pair_kinds = np.asarray(PAIR_KINDS, dtype=np.int8)[
            roles[:, None].astype(np.int64) * ROLES + roles[None, :]
        ]
        self._tool_fixture_pairs = pairs = np.argwhere(np.triu(self._pair_kinds == TOOL_FIXTURE))  # (k, 2)
        model = self._plant.model
        plane = model.geom_type == mujoco.mjtGeom.mjGEOM_PLANE
        bound = np.where(plane, np.inf, model.geom_rbound)  # a plane's is 0
        self._pair_reach = bound[pairs[:, 0]] + bound[pairs[:, 1]]  # the bounding spheres' radii, summed

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
        worked_in_contact = self._expect_fixture  # the previous statement's: a peg may graze its hole
        self._expect_fixture = expects_contact(segment)
        self._guarded = has_force_term(segment.until)[0]
        press = spring_press_n(segment, position, goal_position)
        self._force_limit = force_limit_n(segment, self.free_force_limit_n, press)
        self._force_limit2 = self._force_limit**2
        self._over = 0
        self._saturated_ticks = [0] * len(self._saturated_at)
        self._counting = False
        self._tick = 0
        # At a fixture, touching or not: a block just grasped off the table may rest 0.1 mm above it.
        if not same:
            self._inherited = worked_in_contact or self._tool_touches_fixture() or self._tool_at_fixture()
        self._touched = False
        self._since_touch = 0
        self._start = tuple(np.asarray(position, dtype=float).tolist())
        self._path_axes = [
            tuple(segment.frame_rotation[:, i].tolist())
            for i in range(3)
            if segment.motion_axes[i] and segment.stiffness[i] is None
        ]
        self._axes = np.array(self._path_axes, dtype=float).reshape(-1, 3)
        self._look_at_path = bool(self._path_axes)
        self.leg(position, goal_position)

    def leg(self, start: FloatArray, end: FloatArray) -> None:
        """The commanded straight line changes (a VIA point passed): from ``start`` to ``end``."""
        line = np.asarray(end, dtype=float) - start
        self._line = (
            tuple(np.asarray(start, dtype=float).tolist()),
            tuple(line.tolist()),
            float(line @ line),
        )
        self._line_array = np.array([*self._line[0], *self._line[1], self._line[2]])  # slow_look's

    def path_deviation_m(self, position: FloatArray) -> float:
        """The tool point's distance from the segment's commanded line (as the PATH stop measures it) [m]."""
        return off_line(position.tolist(), *self._line, self._path_axes)

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
        if ncon := self._data.ncon:
            stop = self._contacts(ncon, t_s, wrench, position)
            if stop is not None:
                return stop
        elif self._inherited:
            self._since_touch += 1
            if self._since_touch >= self._gone_ticks and self._away(position):
                self._inherited = False
        fx, fy, fz, _, _, _ = wrench.tolist()
        if fx * fx + fy * fy + fz * fz > (_RATING2 if self._inherited else self._force_limit2):
            self._over += 1
            if self._over >= FORCE_TICKS:
                push = math.sqrt(fx * fx + fy * fy + fz * fz)
                limit = WRIST_SENSOR.force_n if self._inherited else self._force_limit
                return ProtectiveStop(
                    StopKind.FORCE,
                    f"protective stop: {push:.1f} N at the wrist at {t_s:.2f} s, above this "
                    f"statement's limit of {limit:g} N",
                )
        else:
            self._over = 0
        self._tick += 1
        if self._tick % SLOW_CHECK_EVERY:
            return None
        # Every 4th tick, in one compiled call: a torque as large as the lowest limit (only then
        # is each drive held against its own), and the tool's distance from its line.
        look_at_path = self._look_at_path and not self.field_acting
        at_lowest, off = slow_look(
            torque, self._lowest_saturation, position, self._line_array, self._axes, look_at_path
        )
        if self._counting or (at_lowest and any(map(ge, map(abs, torque.tolist()), self._saturated_at))):
            stop = self._saturation(torque.tolist(), t_s)
            if stop is not None:
                return stop
        if look_at_path and off > PATH_DEVIATION_M:
            return ProtectiveStop(
                StopKind.PATH,
                f"protective stop: the tool is {off * 1e3:.0f} mm off its path at {t_s:.2f} s "
                f"(limit {PATH_DEVIATION_M * 1e3:g} mm)",
            )
        return None

    def _saturation(self, taus: list[float], t_s: float) -> ProtectiveStop | None:
        """The stop for a drive at its torque limit for :data:`SATURATION_S`; counts each one's looks."""
        ticks = self._saturated_ticks
        for joint, (tau, limit) in enumerate(zip(taus, self._saturated_at, strict=True)):
            if tau >= limit or -tau >= limit:
                ticks[joint] += 1
                if ticks[joint] >= self._saturation_looks:
                    held_ms = ticks[joint] * SLOW_CHECK_EVERY * self._dt_s * 1e3
                    return ProtectiveStop(
                        StopKind.DRIVE,
                        f"protective stop: drive {joint + 1} at its torque limit of "
                        f"{self._torque_limits[joint]:g} N m for {held_ms:.0f} ms at {t_s:.2f} s",
                    )
            else:
                ticks[joint] = 0
        self._counting = any(ticks)
        return None

    def tool_touched(self) -> bool:
        """Whether the tool has touched a fixture since the segment started, or is at one now.

        Touched: MuJoCo's contacts. At: within :data:`NEAR_FIXTURE_M` (MuJoCo's distances), as a peg
        that slid into its bore's clearance untouched is.
        """
        return self._touched or self._tool_at_fixture()

    def _tool_at_fixture(self) -> bool:
        """Whether the tool is within :data:`NEAR_FIXTURE_M` of a fixture (MuJoCo's distances)."""
        model, data, fromto = self._plant.model, self._data, np.zeros(6)
        pairs, near = self._tool_fixture_pairs, NEAR_FIXTURE_M
        # Only the pairs whose bounding spheres come that close (a MuJoCo distance costs 10-100 us).
        apart = np.linalg.norm(data.geom_xpos[pairs[:, 0]] - data.geom_xpos[pairs[:, 1]], axis=1)
        close = pairs[apart - self._pair_reach < near].tolist()
        return any(mujoco.mj_geomDistance(model, data, g1, g2, near, fromto) < near for g1, g2 in close)

    def _tool_touches_fixture(self) -> bool:
        ncon = self._data.ncon
        if not ncon:
            return False
        kinds = self._pair_kinds
        return any(kinds[g1, g2] == TOOL_FIXTURE for g1, g2 in self.contact_geoms(ncon).tolist())

    def _away(self, position: FloatArray) -> bool:
        """Whether the tool point is more than :data:`INHERITED_REACH_M` from the statement's start."""
        x, y, z = position[0] - self._start[0], position[1] - self._start[1], position[2] - self._start[2]
        return x * x + y * y + z * z > INHERITED_REACH_M * INHERITED_REACH_M

    def _contacts(
        self, ncon: int, t_s: float, wrench: FloatArray, position: FloatArray
    ) -> ProtectiveStop | None:
        """A stop for the first contact the statement does not expect; tracks inherited ones."""
        geom = self.contact_geoms(ncon)
        index, touching_fixture = first_unexpected_contact(
            geom, self._pair_kinds, self._expect_fixture or self._guarded or self._inherited, self._guarded
        )
        self._touched = self._touched or touching_fixture
        if index >= 0:
            roles = self._roles_list
            g1, g2 = geom[index].tolist()
            arm, other = (g1, g2) if roles[g1] in (Role.LINK, Role.TOOL) else (g2, g1)
            return self._contact_stop(index, arm, other, roles[other], t_s, wrench)
        if self._inherited:
            self._since_touch = 0 if touching_fixture else self._since_touch + 1
            if self._since_touch >= self._gone_ticks and self._away(position):
                self._inherited = False
        return None

    def _contact_stop(
        self, index: int, arm: int, other: int, role: int, t_s: float, wrench: FloatArray
    ) -> ProtectiveStop:
        """The stop for contact ``index``.

        Its force is the contact's normal force, and for the tool at least what the wrist
        sensor reads: the stop comes at the first touch, before much force has built up.
        """
        plant = self._plant
        force = np.zeros(6)
        mujoco.mj_contactForce(plant.model, self._data, index, force)
        push = abs(float(force[0]))
        if self._roles_list[arm] == Role.TOOL:
            push = max(push, float(np.linalg.norm(wrench[:3])))
        owner = self._owners[other]
        if role == Role.OBSTACLE:
            name = self.obstacle_names.get(owner, owner)
            what = f"obstacle '{name}'"
        elif owner == "world":
            name, what = "floor", "the floor"
        elif role == Role.OBJECT:
            name, what = owner, f"object '{owner}'"
        else:  # as programs name it: hole_fixture's frame is `hole`
            name = owner.removesuffix("_fixture")
            what = f"fixture '{name}'"
        arm_owner = self._owners[arm]
        return ProtectiveStop(
            StopKind.CONTACT,
            f"protective stop: {_arm_part(arm_owner)} hit {what} at {t_s:.2f} s, {push:.1f} N",
            collision=f"{arm_owner} touches {name}",
        )
