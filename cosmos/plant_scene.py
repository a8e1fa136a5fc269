"""What the plant reads from a compiled scene: the arm's joints and motors, geom owners, the wrist sensor.

Helpers of :class:`cosmos.plant.Plant`, checked once when it is built.
"""

from __future__ import annotations

from pathlib import Path

import mujoco
import numpy as np

from cosmos.errors import CosmosError
from cosmos.workcell import FORCE_SENSOR, TORQUE_SENSOR


def check_arm(model: mujoco.MjModel, scene_xml: Path | str) -> int:
    """The arm's n; raise unless the first DOFs and actuators are the n joints ``joint1`` .. ``joint<n>``.

    After them a scene may have other joints (fingers, free objects) and actuators (the
    gripper's drive), none named ``joint<k>``.
    """
    all_joints = tuple(model.joint(i).name for i in range(model.njnt))
    count = sum(1 for name in all_joints if name.startswith("joint"))
    joints = all_joints[:count]
    names = tuple(f"joint{k}" for k in range(1, max(count, 1) + 1))
    hinges = all(t == mujoco.mjtJoint.mjJNT_HINGE for t in model.jnt_type[:count])
    if joints != names or not hinges or int(model.jnt_qposadr[count - 1]) != count - 1:
        raise CosmosError(
            f"{scene_xml}: expected exactly the hinge joints {', '.join(names)}, "
            f"found: {', '.join(joints) or 'none'}"
        )
    targets = tuple(model.joint(int(j)).name for j in model.actuator_trnid[:count, 0])
    motors = tuple(model.actuator(i).name for i in range(min(model.nu, count)))
    if motors != names or targets != names:
        raise CosmosError(
            f"{scene_xml}: expected the motors {', '.join(names)} on the joints of the "
            f"same names, found: {', '.join(motors) or 'none'}"
        )
    if not model.actuator_ctrllimited[:count].all():
        raise CosmosError(f"{scene_xml}: every motor needs its torque limits (ctrllimited, ctrlrange)")
    return count


def geom_owners(spec: mujoco.MjSpec, model: mujoco.MjModel) -> tuple[str, ...]:
    """Per geom, the name of its body; for a world geom inside a named frame, that frame's name."""
    frames: dict[str, str] = {}
    for geom in spec.geoms:
        frame = geom.frame
        while frame is not None and not frame.name:
            frame = frame.frame
        if frame is not None and geom.name:
            frames[geom.name] = frame.name
    owners = []
    for i in range(model.ngeom):
        body = int(model.geom_bodyid[i])
        name = model.geom(i).name
        owners.append(frames.get(name, "world") if body == 0 else model.body(body).name)
    return tuple(owners)


def wrench_index(model: mujoco.MjModel) -> slice | np.ndarray | None:
    """Where the wrist sensor's force then torque are in ``sensordata``, if present.

    One slice when they are side by side (as in the workcell: indexing gives a view),
    else their six indices.
    """
    force = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, FORCE_SENSOR)
    torque = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, TORQUE_SENSOR)
    if force < 0 or torque < 0:
        return None
    f0, t0 = int(model.sensor_adr[force]), int(model.sensor_adr[torque])
    if f0 + 3 == t0:
        return slice(f0, t0 + 3)
    return np.r_[f0 : f0 + 3, t0 : t0 + 3]
