"""What the run log records from the live runtime: state, link transforms and the scene.

The controller never reads the simulator's internals; the *recorder* may: the
log shows the true tool pose (MuJoCo's tool site) beside the joint state, the
torques applied and the wrench as the wrist sensor reported it.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.plant import Plant
from cosmos.runlog.foxglove import ARM_FRAMES
from cosmos.runlog.scene import FIXTURE_COLOR, Box, Cylinder, Primitive, Sphere
from cosmos.runlog.writer import RunLog
from cosmos.runtime.loop import Sample
from cosmos.runtime.parameters import Evaluation
from cosmos.workcell import TOOL_SITE

TRANSFORM_EVERY = 5
"""Link transforms go to ``/tf`` at every 5th state sample (50 Hz at the default 250 Hz)."""

FIXTURE_BODIES = ("table", "hole_fixture", "slope_fixture")

_mat2quat = mujoco.mju_mat2Quat  # looked up once: recording runs in the servo loop


class LogRecorder:
    """Feeds ``/cosmos/state`` and ``/tf`` from the runtime's samples.

    Attributes:
        segment: Index of the segment running, written with every state.
        line: Source line of its statement.
    """

    def __init__(self, log: RunLog, plant: Plant):
        self.log = log
        self.segment = 0
        self.line = 0
        model, data = plant.model, plant.data
        self._site_xpos = data.site_xpos[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)]
        self._site_xmat = data.site_xmat[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)]
        bodies = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name) for name in ARM_FRAMES]
        self._bodies = np.array(bodies, dtype=np.int64)  # (frames,) rows of xpos, xquat
        self._xpos = data.xpos  # (nbody, 3) world [m], a view: read at each /tf sample
        self._xquat = data.xquat  # (nbody, 4) world, w x y z
        self._quat = np.empty(4)
        self._count = 0

    def __call__(self, sample: Sample, evaluation: Evaluation) -> None:
        """Record one state sample (the runtime calls this at the state rate); see :meth:`record`."""
        self.record(sample.t_s, sample.q, sample.qd, sample.tau, sample.wrench, evaluation)

    def record(
        self,
        t_s: float,
        q: np.ndarray,
        qd: np.ndarray,
        tau: np.ndarray,
        wrench: np.ndarray,
        evaluation: Evaluation,
    ) -> None:
        """Record one state sample: the joint state, the tool pose and twist, the wrench; /tf every 5th.

        Args:
            t_s: Simulated time since start [s].
            q: Joint positions [rad]. # (6,)
            qd: Joint velocities [rad/s]. # (6,)
            tau: Joint torques being applied [N m]. # (6,)
            wrench: Wrench the tool applies to the environment, world [N, N m]. # (6,)
            evaluation: The model's last evaluation (its Jacobian gives the tool twist).
        """
        log = self.log
        _mat2quat(self._quat, self._site_xmat)
        v = evaluation.jacobian.dot(qd)  # (6,) tool twist, world (NumPy's BLAS, as ever: same digits)
        log.state(t_s, q, qd, tau, self._site_xpos, self._quat, v, wrench, self.segment, self.line)
        self._count += 1
        if self._count % TRANSFORM_EVERY == 1:
            log.transforms(t_s, self._xpos, self._xquat, self._bodies)


def fixture_primitives(plant: Plant) -> list[Primitive]:
    """The workcell's fixtures as scene primitives (boxes and cylinders), world poses."""
    model, data = plant.model, plant.data
    primitives: list[Primitive] = []
    for body_name in FIXTURE_BODIES:
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, body_name)
        if body < 0:
            continue
        for geom in range(model.ngeom):
            if model.geom_bodyid[geom] != body:
                continue
            name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, geom) or f"{body_name}_{geom}"
            quat = np.empty(4)
            mujoco.mju_mat2Quat(quat, data.geom_xmat[geom])
            size = model.geom_size[geom]
            position = data.geom_xpos[geom].tolist()
            kind = model.geom_type[geom]
            if kind == mujoco.mjtGeom.mjGEOM_BOX:
                primitives.append(Box(name, position, (2 * size).tolist(), quat.tolist(), FIXTURE_COLOR))
            elif kind == mujoco.mjtGeom.mjGEOM_CYLINDER:
                primitives.append(
                    Cylinder(name, position, float(size[0]), 2 * float(size[1]), quat.tolist(), FIXTURE_COLOR)
                )
            elif kind == mujoco.mjtGeom.mjGEOM_SPHERE:
                primitives.append(Sphere(name, position, float(size[0]), FIXTURE_COLOR))
    return primitives
