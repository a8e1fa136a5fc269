"""The gripper in the run log: its fields of ``/cosmos/state``, and ``/cosmos/hand``.

Every state sample of a gripper's log has ``fingers`` (each pad's distance from the
gripper's centre plane [m]) and ``finger_force`` (the pads' forces as their sensors read
them [N]); a log without the gripper has neither (metadata ``fingers`` absent), so its state
is that of every log before the gripper. ``/cosmos/hand`` stays: it alone says what the hand
holds, and replay poses the fingers from it. Written with every 5th state sample, as
``/tf`` is (50 Hz at the default 250 Hz state rate), from the same reading as that sample's
state. Fields (SI units): ``t`` [s], ``opening`` between the pads [m], ``force_left`` and
``force_right`` as the pad sensors read them [N], ``held``: the held object's name or "".
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, Final

import numpy as np

from cosmos.execution.recording import TRANSFORM_EVERY, LogRecorder
from cosmos.hand.fingers import Fingers
from cosmos.plant import Plant
from cosmos.runlog.messages import log_time_ns
from cosmos.runlog.schemas import JSON_SCHEMA_DIALECT
from cosmos.runlog.writer import RunLog

HAND_TOPIC: Final = "/cosmos/hand"
HAND_SCHEMA_NAME: Final = "cosmos.Hand"
HAND_SCHEMA: Final[dict[str, Any]] = {
    "$schema": JSON_SCHEMA_DIALECT,
    "title": HAND_SCHEMA_NAME,
    "type": "object",
    "properties": {
        "t": {"type": "number", "minimum": 0},
        "opening": {"type": "number"},
        "force_left": {"type": "number"},
        "force_right": {"type": "number"},
        "held": {"type": "string"},
    },
    "required": ["t", "opening", "force_left", "force_right", "held"],
    "additionalProperties": False,
}


class HandRunLog(RunLog):
    """A run log with the gripper's state fields and its channel, ``/cosmos/hand`` (module docstring)."""

    def __init__(self, path: Path | str, **options: Any) -> None:
        super().__init__(path, fingers=True, **options)

    def hand_channel(self) -> Callable[[float, bytes], None]:
        """The channel: returns ``write(t_s, message_bytes)``."""
        channel = self._json_channel(HAND_TOPIC, HAND_SCHEMA_NAME, HAND_SCHEMA)
        return lambda t_s, data: self._write(channel, log_time_ns(t_s), data)


class HandRecorder(LogRecorder):
    """The state and ``/tf`` (:class:`LogRecorder`), and the gripper on ``/cosmos/hand``.

    Args:
        log: The run log, with the hand's channel.
        plant: The workcell with the gripper.
        frames: The ``/tf`` frames.
        held: Returns the held object's name, or "".
    """

    def __init__(self, log: HandRunLog, plant: Plant, frames: Sequence[str], held: Callable[[], str]) -> None:
        super().__init__(log, plant, frames)
        fingers = plant.fingers
        assert fingers is not None, "HandRecorder needs the gripper"
        self._fingers: Fingers = fingers
        self._held = held
        self._write = log.hand_channel()
        self._samples = 0

    def record(
        self,
        t_s: float,
        q: np.ndarray,
        qd: np.ndarray,
        tau: np.ndarray,
        wrench: np.ndarray,
        twist: np.ndarray,
    ) -> None:
        """One state sample (:meth:`LogRecorder.record`) with the fingers; the hand with every 5th."""
        fingers = self._fingers
        reading = fingers.read()
        left_m, right_m = fingers.positions_m()
        self.log.fingers(left_m, right_m, reading.force_left_n, reading.force_right_n)
        super().record(t_s, q, qd, tau, wrench, twist)
        self._samples += 1
        if self._samples % TRANSFORM_EVERY == 1:
            message = {
                "t": round(t_s, 9),
                "opening": round(reading.opening_m, 6),
                "force_left": round(reading.force_left_n, 4),
                "force_right": round(reading.force_right_n, 4),
                "held": self._held(),
            }
            self._write(t_s, json.dumps(message, separators=(",", ":")).encode())
