"""What the run log records from the live runtime: the state, the link transforms, each segment's start.

The controller never reads the simulator's internals; the *recorder* may: the
log shows the true tool pose (MuJoCo's tool site) beside the joint state, the
torques applied and the wrench as the wrist sensor reported it.
"""

from __future__ import annotations

from collections.abc import Sequence

import mujoco
import numpy as np

from cosmos.execution.resolve import effective_masses
from cosmos.osc.orientation import matrix_to_quat
from cosmos.plan import Segment
from cosmos.plant import Plant
from cosmos.runlog.foxglove import ARM_FRAMES
from cosmos.runlog.writer import RunLog
from cosmos.runtime.parameters import Evaluation
from cosmos.runtime.setpoint import ServoSetpoint
from cosmos.workcell import TOOL_SITE

TRANSFORM_EVERY = 5
"""Link transforms go to ``/tf`` at every 5th state sample (50 Hz at the default 250 Hz)."""

_mat2quat = mujoco.mju_mat2Quat  # looked up once: recording runs in the servo loop


class LogRecorder:
    """Feeds ``/cosmos/state`` and ``/tf`` from the runtime's samples.

    Attributes:
        segment: Index of the segment running, written with every state.
        line: Source line of its statement.
    """

    def __init__(self, log: RunLog, plant: Plant, frames: Sequence[str] = ARM_FRAMES):
        self.log = log
        self.segment = 0
        self.line = 0
        model, data = plant.model, plant.data
        self._site_xpos = data.site_xpos[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)]
        self._site_xmat = data.site_xmat[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)]
        bodies = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name) for name in frames]
        self._bodies = np.array(bodies, dtype=np.int64)  # (frames,) rows of xpos, xquat
        self._xpos = data.xpos  # (nbody, 3) world [m], a view: read at each /tf sample
        self._xquat = data.xquat  # (nbody, 4) world, w x y z
        self._quat = np.empty(4)
        self._count = 0
        self.last_t_s = -1.0
        """Time of the last state sample recorded [s]."""
        self._pending: tuple[int, int] | None = None

    def start_segment(self, segment: int, line: int, after_s: float | None = None) -> None:
        """Tag the samples from now on with ``segment`` and ``line``.

        Args:
            segment: The segment's index.
            line: Its statement's line.
            after_s: The previous segment ended at this time because its UNTIL held: the
                first sample at or after it still belongs to that segment (it shows what
                fired the condition), so the new tag starts after that sample.
        """
        if after_s is not None and self.last_t_s < after_s - 1e-9:
            self._pending = (segment, line)
        else:
            self.segment, self.line, self._pending = segment, line, None

    def record(
        self,
        t_s: float,
        q: np.ndarray,
        qd: np.ndarray,
        tau: np.ndarray,
        wrench: np.ndarray,
        twist: np.ndarray,
    ) -> None:
        """Record one state sample: the joint state, the tool pose and twist, the wrench; /tf every 5th.

        Args:
            t_s: Simulated time since start [s].
            q: Joint positions [rad]. # (6,)
            qd: Joint velocities [rad/s]. # (6,)
            tau: Joint torques being applied [N m]. # (6,)
            wrench: Wrench the tool applies to the environment, world [N, N m]. # (6,)
            twist: Tool twist ``J qd``, world axes: linear [m/s] then angular [rad/s]. # (6,)
        """
        log = self.log
        _mat2quat(self._quat, self._site_xmat)
        log.state(t_s, q, qd, tau, self._site_xpos, self._quat, twist, wrench, self.segment, self.line)
        self.last_t_s = t_s
        if self._pending is not None:
            self.segment, self.line = self._pending
            self._pending = None
        self._count += 1
        if self._count % TRANSFORM_EVERY == 1:
            log.transforms(t_s, self._xpos, self._xquat, self._bodies)


def log_segment(
    log: RunLog, t_s: float, index: int, segment: Segment, setpoint: ServoSetpoint, evaluation: Evaluation
) -> None:
    """Write segment ``index``'s start on ``/cosmos/segment``: its goal, task frame, stiffness and damping.

    Args:
        log: The run log.
        t_s: Simulated time at its start [s].
        index: The segment's index in order of execution.
        segment: The segment.
        setpoint: Its servo setpoint (unit-mass gains, goal, task frame).
        evaluation: The model's evaluation at its start (the effective masses).
    """
    # The servo's unit-mass gains times the effective masses: physical stiffness and damping.
    masses = effective_masses(evaluation, setpoint.rotation_task_to_world)
    motion = np.array(setpoint.motion_axes, dtype=bool)
    stiffness = np.where(motion, setpoint.kp_task * masses, 0.0)
    damping = setpoint.kv_task * masses
    goal = np.concatenate((setpoint.position, matrix_to_quat(setpoint.rotation_to_world)))
    log.segment(
        t_s,
        segment=index,
        line=segment.line,
        statement=segment.statement,
        kind=segment.kind.value,
        frame=matrix_to_quat(setpoint.rotation_task_to_world),
        motion_axes=[int(a) for a in setpoint.motion_axes],
        force_setpoint=setpoint.force_task,
        stiffness=stiffness,
        damping=damping,
        goal=goal,
        speed_limit=segment.speed_limit_mps,
        timeout=segment.timeout_s,
    )
