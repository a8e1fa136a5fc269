"""Slip as a protective stop: the supervision of a held object (:meth:`cosmos.hand.grasping.Hand.slip`)."""

from __future__ import annotations

import numpy as np

from cosmos.execution.supervision import ProtectiveStop, StopKind, Supervisor
from cosmos.hand.grasping import Hand
from cosmos.plan import Segment
from cosmos.plant import Plant

SLIP_CHECK_EVERY = 4
"""A held object is looked at every this many ticks (as the path and the drives)."""


class GraspSupervisor(Supervisor):
    """The arm's supervision plus the held object's slip (every :data:`SLIP_CHECK_EVERY` ticks).

    Args:
        plant: The workcell.
        torque_limits_nm: The drives' symmetric torque limits [N m]. # (n,)
        servo_dt_s: Servo period [s].
        hand: The gripper.
    """

    def __init__(self, plant: Plant, torque_limits_nm: np.ndarray, servo_dt_s: float, hand: Hand):
        super().__init__(plant, torque_limits_nm, servo_dt_s)
        self._hand = hand
        self._hand_tick = 0

    def start(self, segment: Segment, position: np.ndarray, goal_position: np.ndarray) -> None:
        """A segment starts: the object the hand holds now is part of the tool."""
        held = self._hand.held
        self.holding(-1 if held is None else held.body)
        super().start(segment, position, goal_position)

    def check(
        self, t_s: float, wrench: np.ndarray, torque: np.ndarray, position: np.ndarray
    ) -> ProtectiveStop | None:
        """The arm's hazard at this tick, else a slipping held object's."""
        stop = super().check(t_s, wrench, torque, position)
        if stop is not None or self._hand.held is None:
            return stop
        self._hand_tick += 1
        if self._hand_tick % SLIP_CHECK_EVERY:
            return None
        why = self._hand.slip()
        return (
            None if why is None else ProtectiveStop(StopKind.FORCE, f"protective stop: {why} at {t_s:.2f} s")
        )
