"""The wrist sensor's tare with a payload on the tool: what the cell zeroes before the run.

A cell tares its force/torque sensor in free air with the tool as it is mounted
(:mod:`cosmos.realism.wrist_sensor`). The controller compensates the weight of the tool it
knows (the datasheet's, :mod:`cosmos.runtime.wrench`); a payload it does not know (a sweep's
``payload``, :mod:`cosmos.sweep.variation`) is on the tool at that tare, so the tare zeroes
its static reading at the pose the arm stands in then (its home pose), and only a turned
tool, or an accelerated one, reads it. Untared, a 1 kg payload read 9.8 N at rest, the free
motion took that for a push, and a MOVE at SPEED 20 mm/s cruised at 12.8 mm/s (its cruise
integral held off, :mod:`cosmos.osc.cruise_speed`); a CONTACT's touch felt 2 N only after
pressing the surface with 2 N more than the payload's weight.

The payload's static reading, at rest (the sensor's convention, :mod:`cosmos.plant`: the
wrench the flange exerts on the tool, about the sensor origin ``o``, sensor axes ``R``),
holds its weight ``W = m g`` at its centre ``c``::

    f = -R^T W,    tau = -R^T ((c - o) x W)
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.workcell import FORCE_SENSOR

PAYLOAD_GEOM = "payload"
"""The name of the geom a workcell's unknown payload is (:mod:`cosmos.sweep.variation`)."""


def payload_tare(spec: mujoco.MjSpec, model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """The payload's static reading at ``data``'s pose, force then torque, sensor axes [N, N m].

    Zeros without a payload geom or a wrist sensor. ``data`` must have had ``mj_forward``
    (or ``mj_kinematics``) at the pose of the tare. # (6,)
    """
    geom = spec.geom(PAYLOAD_GEOM)
    sensor = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SENSOR, FORCE_SENSOR)
    if geom is None or sensor < 0:
        return np.zeros(6)
    site = int(model.sensor_objid[sensor])
    weight = geom.mass * np.asarray(model.opt.gravity)
    centre = data.geom_xpos[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, PAYLOAD_GEOM)]
    axes = data.site_xmat[site].reshape(3, 3)
    lever = centre - data.site_xpos[site]
    return np.concatenate((-axes.T @ weight, -axes.T @ np.cross(lever, weight)))
