"""Active force control on one axis (seed section 3, Figure 2), from the wrist sensor.

z is force-controlled at 10 N against the table, x, y and the orientation are
motion-controlled. The wrench used by the loop is the sensor's, compensated for
the tool's weight; the reference here is MuJoCo's own contact force between
the peg and the table, which the controller never sees.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.runtime.setpoint import MotionMode, ServoSetpoint
from cosmos.workcell import fixture_frames
from tests.runtime.runtime_helpers import run_for, runtime_at

SETPOINT_N = 10.0


def contact_force_on_tool_z(plant) -> float:  # type: ignore[no-untyped-def]
    """World z component of the force the fixtures exert on the tool (MuJoCo's contact solver)."""
    model, data = plant.model, plant.data
    tool = model.body("tool").id
    total = 0.0
    wrench = np.zeros(6)
    for i in range(data.ncon):
        contact = data.contact[i]
        bodies = (model.geom_bodyid[contact.geom1], model.geom_bodyid[contact.geom2])
        if tool not in bodies:
            continue
        mujoco.mj_contactForce(model, data, i, wrench)
        force_world = contact.frame.reshape(3, 3).T @ wrench[:3]  # on geom2, from geom1
        total += force_world[2] if bodies[1] == tool else -force_world[2]
    return total


def test_force_axis_settles_on_its_setpoint() -> None:
    runtime = runtime_at()
    table = fixture_frames()["table"]
    ev = runtime.evaluation
    above = ev.position.copy()
    above[2] = table.position[2] + 0.003
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.GOAL,
            position=above,
            rotation_to_world=ev.rotation_tool_to_world.copy(),
            start_s=runtime.time_s,
        )
    )
    run_for(runtime, 1.5)
    ev = runtime.evaluation
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.HOLD,
            position=ev.position.copy(),
            rotation_to_world=ev.rotation_tool_to_world.copy(),
            motion_axes=(True, True, False, True, True, True),
            force_task=np.array((0.0, 0.0, -SETPOINT_N, 0.0, 0.0, 0.0)),  # pressing down
            start_s=runtime.time_s,
        )
    )
    sensed, true = [], []
    end = runtime.time_s + 2.0
    while runtime.time_s < end:
        runtime.tick()
        sensed.append(-runtime.wrench[2])
        true.append(contact_force_on_tool_z(runtime.plant))
    last = slice(-500, None)  # the last 0.5 s
    sensed_last, true_last = np.array(sensed[last]), np.array(true[last])
    assert np.all(np.abs(sensed_last - SETPOINT_N) < 0.03 * SETPOINT_N), (
        f"sensed {sensed_last.min():.3f}..{sensed_last.max():.3f} N"
    )
    # The table really pushes back with the setpoint (the sensor is not fooling the loop).
    assert np.all(np.abs(true_last - SETPOINT_N) < 0.03 * SETPOINT_N), (
        f"contact {true_last.min():.3f}..{true_last.max():.3f} N"
    )
