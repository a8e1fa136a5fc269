"""Active force control on one axis (seed section 3, Figure 2), from the wrist sensor.

z is force-controlled at 10 N against the table, x, y and the orientation are
motion-controlled. The wrench used by the loop is the sensor's, compensated for
the tool's weight; the reference here is MuJoCo's own contact force between
the peg and the table, which the controller never sees.

On the realistic plant the sensor reads through a 200 Hz low-pass, with white noise
(0.05 N per component, :class:`cosmos.plant.SensorNoise`) and a drawn bias. Every one of
the last 500 readings may then stray by 4.5 noise standard deviations beyond the ideal
plant's 3 % (a chance of 3e-3 that one of 500 normal samples does), and the table's true
push by the sensor's bias as well (the loop holds the biased reading on its setpoint) and
the noise the loop passes on.
"""

from __future__ import annotations

import mujoco
import numpy as np

from cosmos.plant import SensorNoise
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
    """Catches a force loop that does not hold its setpoint, or one fooled by its sensor (the
    table's real push elsewhere), beyond the sensor's noise and bias."""
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
    realism = runtime.plant.realism
    noise_n = 0.0 if realism is None else 4.5 * SensorNoise(0).force_std_n
    bias_n = 0.0 if realism is None else float(np.linalg.norm(realism.wrist_bias[:3]))
    sensed_limit = 0.03 * SETPOINT_N + noise_n
    assert np.all(np.abs(sensed_last - SETPOINT_N) < sensed_limit), (
        f"sensed {sensed_last.min():.3f}..{sensed_last.max():.3f} N (+-{sensed_limit:.3f} N)"
    )
    # The table really pushes back with the setpoint (the sensor is not fooling the loop).
    true_limit = sensed_limit + bias_n
    assert np.all(np.abs(true_last - SETPOINT_N) < true_limit), (
        f"contact {true_last.min():.3f}..{true_last.max():.3f} N (+-{true_limit:.3f} N)"
    )
