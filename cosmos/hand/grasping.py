"""GRASP and RELEASE on the arm: close until both fingers feel the force, hold, let go.

:class:`Hand` runs a program's hand steps (:class:`cosmos.plan.HandStep`) for the
executor, holding the arm where it is while the fingers move:

- **GRASP** commands the drive to close at :data:`DEFAULT_FINGER_SPEED_MPS` with the grip
  force as its force limit, and watches the pad sensors and the opening every tick. It
  has the object when both pads read at least :data:`FELT` of the force and the opening has
  stopped (:data:`SETTLE_S`); it fails when the fingers close to nothing ("GRASP closed
  to 0 mm: nothing between the fingers"), on something else than the named object or not
  on an object at all (the pads' contacts name what they touch: the world model's
  recognition of what is in the hand), or to an opening other than its ``WIDTH``. A held
  object is affixed: :func:`cosmos.hand.payload.holding` moves the tool frame to the
  object's base point and adds its declared mass to the controller's model; the plant's
  ``tool`` site moves with it, so the measured tool (the log's ``/cosmos/state``, arrival
  checks) is that point too.
- **RELEASE** opens the fingers until they are clear of the object and goes back to the
  empty hand's model; with nothing held it fails at its line.

While an object is held, :meth:`Hand.slip` tells the supervision (every few ticks) when
the grip force falls below :data:`SLIP_FORCE_FRACTION` of the setting or the object has
moved in the fingers by :data:`SLIP_M` (MuJoCo's object pose against the hand's, standing
in for a tactile slip sensor): a protective stop.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.hand.fingers import Fingers
from cosmos.hand.gripper_scene import PADS
from cosmos.hand.payload import holding
from cosmos.hand.tool import DEFAULT_FINGER_SPEED_MPS, GRIPPER, GripperDatasheet
from cosmos.hand.work_object import WorkObject
from cosmos.plan import HandAction, HandStep
from cosmos.robot_model import RobotModel
from cosmos.runtime.loop import Runtime
from cosmos.workcell import TOOL_SITE

FELT = 0.9
"""A pad feels the grip when it reads this fraction of the grip force."""
SETTLE_S = 0.05
"""The opening must stay within :data:`SETTLE_M` this long for a grasp to be made [s]."""
SETTLE_M = 2e-4
NOTHING_M = 4e-4
"""Closed below this opening, the fingers hold nothing [m]."""
WIDTH_TOLERANCE_M = 3e-3
"""A GRASP's WIDTH and the opening it closed to may differ by this much [m]."""
RELEASE_CLEARANCE_M = 0.01
"""RELEASE opens until the pads are this far clear of the object, each side [m]."""
SLIP_FORCE_FRACTION = 0.5
SLIP_M = 0.005


@dataclass(frozen=True)
class Held:
    """What the hand holds.

    Attributes:
        item: The object.
        force_n: The grip force it is held with [N].
        opening_m: The opening the fingers closed to [m].
        body: Its MuJoCo body id.
        centre_in_site_m: Its centre in the (affixed) tool site's frame at the grasp [m]. # (3,)
    """

    item: WorkObject
    force_n: float
    opening_m: float
    body: int
    centre_in_site_m: np.ndarray

    @property
    def centre_in_site(self) -> tuple[float, float, float]:
        """:attr:`centre_in_site_m` as floats [m]."""
        x, y, z = self.centre_in_site_m.tolist()
        return x, y, z


class Hand:
    """The gripper as the executor uses it (module docstring).

    Args:
        runtime: The controller and its plant (which must have the gripper).
        objects: The program's objects.
        hold: Holds the arm where it is for a duration [s] (the executor's ``hold``).
        datasheet: The gripper's (its stroke and smallest force).
        declare_payload: Add a held object's mass to the controller's model (tests compare
            without).

    Raises:
        CosmosError: If the plant has no gripper.
    """

    def __init__(
        self,
        runtime: Runtime,
        objects: tuple[WorkObject, ...],
        hold: Callable[[float], None],
        datasheet: GripperDatasheet = GRIPPER,
        declare_payload: bool = True,
    ) -> None:
        plant = runtime.plant
        if plant.fingers is None:
            raise CosmosError("GRASP and RELEASE need the gripper (TOOL GRIPPER)")
        self._runtime, self._fingers, self._hold = runtime, plant.fingers, hold
        self._model, self._data = plant.model, plant.data
        self._objects = {item.name: item for item in objects}
        self._bodies = {mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_BODY, n): n for n in self._objects}
        geom = mujoco.mjtObj.mjOBJ_GEOM
        self._pad_side = {
            mujoco.mj_name2id(self._model, geom, name): side
            for side, pad in enumerate(PADS)
            for name in (pad, f"{pad}_lower")
        }
        self._site = mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)
        self._hand_site = (self._model.site_pos[self._site].copy(), self._model.site_quat[self._site].copy())
        self._hand_model: RobotModel = runtime.robot
        self._datasheet = datasheet
        self.declare_payload = declare_payload
        self.held: Held | None = None

    @property
    def fingers(self) -> Fingers:
        """The gripper's drive and pad sensors."""
        return self._fingers

    def grip_n(self) -> float:
        """FINGER FORCE: the smaller of the pads' forces as their sensors read them now [N]."""
        return self._fingers.read().grip_force_n

    def apply(self, step: HandStep, fail: Callable[[str], None]) -> str:
        """Run a GRASP or RELEASE; returns what it did, for the log's ``done`` event.

        Args:
            step: The hand step.
            fail: Logs the failure at the step's line, holds the arm and raises.
        """
        if step.action is HandAction.GRASP:
            return self._grasp(step, fail)
        return self._release(fail)

    # ----------------------------------------------------------------- grasp

    def _grasp(self, step: HandStep, fail: Callable[[str], None]) -> str:
        if self.held is not None:
            fail(f"the gripper already holds '{self.held.item.name}': RELEASE it first")
        fingers, force = self._fingers, step.force_n
        fingers.command(-DEFAULT_FINGER_SPEED_MPS, force)
        self._hold(0.0)
        dt = self._runtime.plant.dt_s
        settle_ticks, still = math.ceil(SETTLE_S / dt), 0
        last = fingers.opening_m()
        limit_s = self._runtime.time_s + self._datasheet.stroke_m / DEFAULT_FINGER_SPEED_MPS + 1.0
        tick = self._runtime.tick
        while True:
            tick()
            reading = fingers.read()
            still = still + 1 if abs(reading.opening_m - last) < SETTLE_M * dt / SETTLE_S else 0
            last = reading.opening_m
            if reading.opening_m < NOTHING_M:
                fingers.command(DEFAULT_FINGER_SPEED_MPS, self._datasheet.grip_force_min_n)
                where = self._distance_text(step.object_name)
                fail(f"closed to {reading.opening_m * 1e3:.0f} mm: nothing between the fingers{where}")
            if still >= settle_ticks and min(reading.force_left_n, reading.force_right_n) >= FELT * force:
                break
            if self._runtime.time_s > limit_s:
                fingers.command(DEFAULT_FINGER_SPEED_MPS, self._datasheet.grip_force_min_n)
                fail(
                    f"the fingers did not settle on {force:g} N: pads {reading.force_left_n:.1f} N and "
                    f"{reading.force_right_n:.1f} N at {reading.opening_m * 1e3:.1f} mm"
                )
        touched = self._touched()
        if touched is None or (step.object_name is not None and touched != step.object_name):
            fingers.command(DEFAULT_FINGER_SPEED_MPS, self._datasheet.grip_force_min_n)
            self._hold(0.5)
            what = "no object (the pads touch no declared OBJECT)" if touched is None else f"'{touched}'"
            wanted = f", not on '{step.object_name}'" if step.object_name is not None else ""
            fail(f"closed on {what}{wanted}")
            raise AssertionError  # fail() raises
        assert touched is not None
        if step.width_m is not None and abs(last - step.width_m) > WIDTH_TOLERANCE_M:
            fingers.command(DEFAULT_FINGER_SPEED_MPS, self._datasheet.grip_force_min_n)
            self._hold(0.5)
            fail(f"closed to {last * 1e3:.1f} mm; WIDTH expects {step.width_m * 1e3:.1f} mm")
        self._affix(self._objects[touched], force, last)
        reading = fingers.read()
        return (
            f"holds '{touched}' at {reading.force_left_n:.1f} N and {reading.force_right_n:.1f} N, "
            f"opening {reading.opening_m * 1e3:.1f} mm"
        )

    def _touched(self) -> str | None:
        """The declared object both pads touch, if any."""
        data, bodies = self._data, self._bodies
        found: list[set[str]] = [set(), set()]
        sides = self._pad_side
        for g1, g2 in data.contact.geom[: data.ncon].tolist():
            for pad, other in ((g1, g2), (g2, g1)):
                side = sides.get(pad)
                name = None if side is None else bodies.get(int(self._model.geom_bodyid[other]))
                if name is not None:
                    found[side].add(name)  # type: ignore[index]
        both = found[0] & found[1]
        return next(iter(sorted(both)), None)

    def _distance_text(self, name: str | None) -> str:
        if name is None:
            return ""
        body = mujoco.mj_name2id(self._model, mujoco.mjtObj.mjOBJ_BODY, name)
        gap = float(np.linalg.norm(self._data.xpos[body] - self._data.site_xpos[self._site]))
        return f" ('{name}' is {gap * 1e3:.0f} mm from the tool point)"

    def _affix(self, item: WorkObject, force_n: float, opening_m: float) -> None:
        """The object becomes the tool (module docstring)."""
        model, data, site = self._model, self._data, self._site
        body = next(b for b, n in self._bodies.items() if n == item.name)
        tool_to_world = _pose(data.site_xpos[site], data.site_xmat[site])
        object_to_world = _pose(data.xpos[body], data.xmat[body])
        object_in_tool = np.linalg.solve(tool_to_world, object_to_world)
        # In the flange frame: the tool site's pose in it is the controller's (its datasheet).
        spec = self._hand_model.tool
        tool_in_flange = np.eye(4)
        tool_in_flange[:3, :3], tool_in_flange[:3, 3] = (
            spec.tool_rotation_in_flange,
            spec.tool_position_in_flange,
        )
        object_in_flange = tool_in_flange @ object_in_tool
        carried = holding(
            self._hand_model, item, object_in_flange[:3, :3], object_in_flange[:3, 3], self.declare_payload
        )
        self._runtime.carry(carried)
        # The plant's tool site goes to the object's base point (its axes stay the hand's).
        base_in_tool = object_in_tool[:3, 3] + object_in_tool[:3, :3] @ np.asarray(item.base_in_body_m)
        hand_pos, hand_quat = self._hand_site
        hand_rotation = np.empty(9)
        mujoco.mju_quat2Mat(hand_rotation, hand_quat)
        model.site_pos[site] = hand_pos + hand_rotation.reshape(3, 3) @ base_in_tool
        mujoco.mj_kinematics(model, data)
        centre_in_site = data.site_xmat[site].reshape(3, 3).T @ (data.xpos[body] - data.site_xpos[site])
        self.held = Held(item, force_n, opening_m, body, centre_in_site)
        self._hold(0.0)

    # --------------------------------------------------------------- release

    def _release(self, fail: Callable[[str], None]) -> str:
        held = self.held
        if held is None:
            fail("the gripper holds nothing")
            raise AssertionError  # fail() raises
        fingers = self._fingers
        fingers.command(DEFAULT_FINGER_SPEED_MPS, self._datasheet.grip_force_min_n)
        target = min(held.opening_m + 2 * RELEASE_CLEARANCE_M, self._datasheet.stroke_m - 1e-3)
        limit_s = self._runtime.time_s + 2 * RELEASE_CLEARANCE_M / DEFAULT_FINGER_SPEED_MPS + 1.0
        self._hold(0.0)
        while fingers.opening_m() < target and self._runtime.time_s < limit_s:
            self._runtime.tick()
        fingers.command(0.0, self._datasheet.grip_force_min_n)
        self.held = None
        self._runtime.carry(self._hand_model)
        position, quat = self._hand_site
        self._model.site_pos[self._site], self._model.site_quat[self._site] = position, quat
        mujoco.mj_kinematics(self._model, self._data)
        self._hold(0.0)
        return f"let go of '{held.item.name}', opening {fingers.opening_m() * 1e3:.1f} mm"

    # ------------------------------------------------------------------ slip

    def slip(self) -> str | None:
        """Why the held object is slipping, or None (nothing held, or held fast)."""
        held = self.held
        if held is None:
            return None
        reading = self._fingers.read()
        if reading.grip_force_n < SLIP_FORCE_FRACTION * held.force_n:
            return (
                f"'{held.item.name}' slips: grip force {reading.grip_force_n:.1f} N, "
                f"below {SLIP_FORCE_FRACTION:.0%} of {held.force_n:g} N"
            )
        # Where the object's centre is in the tool site's frame, against where it was at the grasp:
        # in floats, a few products (arrays cost 5 us, and this runs every few ticks while held).
        data, site = self._data, self._site
        x, y, z = data.xpos[held.body].tolist()
        sx, sy, sz = data.site_xpos[site].tolist()
        x, y, z = x - sx, y - sy, z - sz
        r = data.site_xmat[site].tolist()  # row-major: the centre in the site's frame is R^T offset
        cx, cy, cz = held.centre_in_site
        dx = r[0] * x + r[3] * y + r[6] * z - cx
        dy = r[1] * x + r[4] * y + r[7] * z - cy
        dz = r[2] * x + r[5] * y + r[8] * z - cz
        moved = math.sqrt(dx * dx + dy * dy + dz * dz)
        if moved > SLIP_M:
            return f"'{held.item.name}' slips: it moved {moved * 1e3:.1f} mm in the fingers"
        return None


def _pose(position: np.ndarray, xmat: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = np.asarray(xmat).reshape(3, 3), position
    return pose
