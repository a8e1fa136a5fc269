"""The runtime hands the recorder one state per state period, each what the plant was at that time.

At a 1 kHz servo every sample falls at a tick's start and is what the tick sensed and
commanded; at the seed's 225 Hz servo most fall inside a zero-order hold and are
sensed on their own. Either way the samples lie on one grid and match the plant: its
sensors' readings at that time (on the realistic plant the encoders' counts, within half a
count of MuJoCo's angle, and the velocity observer's estimate, not ``qvel``).
"""

from __future__ import annotations

import numpy as np
import pytest

from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint
from tests.runtime.runtime_helpers import run_for, runtime_at


class PlantWitness:
    """A recorder that checks each sample against the plant's own state at the call."""

    def __init__(self, runtime):
        self.runtime = runtime
        self.plant = runtime.plant
        self.times: list[float] = []
        self.peak_speed = 0.0

    def record(self, t_s, q, qd, tau, wrench, twist) -> None:
        data = self.plant.data
        assert t_s == pytest.approx(data.time, abs=1e-12)
        sensed_q, sensed_qd = self.plant.read_encoders()
        np.testing.assert_array_equal(q, sensed_q)
        np.testing.assert_array_equal(qd, sensed_qd)
        realism = self.plant.realism
        half_count = 0.0 if realism is None else 0.5 * np.array(realism.encoder_resolution_rad)
        assert np.all(np.abs(q - data.qpos) <= half_count + 1e-15)
        assert np.all(np.abs(tau) < 200.0)  # the torque applied from t_s on, within the drives
        assert np.all(np.isfinite(wrench)) and abs(wrench[2]) < 5.0  # free air: noise and model error
        # J of the last evaluation times this sample's qd (not another tick's), NumPy's product
        np.testing.assert_allclose(
            twist, self.runtime.evaluation.jacobian @ sensed_qd, rtol=1e-12, atol=1e-15
        )
        self.times.append(t_s)
        self.peak_speed = max(self.peak_speed, float(np.linalg.norm(twist[:3])))


@pytest.mark.parametrize("servo_hz", [1000.0, 225.0])
def test_states_on_one_grid_match_the_plant(servo_hz: float) -> None:
    runtime = runtime_at(rates=Rates(servo_hz=servo_hz, param_hz=100.0, state_hz=250.0))
    ev = runtime.evaluation  # a goal 10 cm away: the arm moves, so the twist is not zero
    runtime.set_setpoint(
        ServoSetpoint(
            mode=MotionMode.GOAL,
            position=ev.position + np.array((0.1, 0.0, 0.0)),
            rotation_to_world=ev.rotation_tool_to_world.copy(),
            start_s=runtime.time_s,
            max_speed=0.25,
        )
    )
    witness = PlantWitness(runtime)
    runtime.recorder = witness
    run_for(runtime, 0.5)
    assert witness.peak_speed > 0.05  # m/s
    steps = np.diff(witness.times)
    assert len(witness.times) >= 0.5 * 250 - 2
    np.testing.assert_allclose(steps, 1.0 / 250.0, atol=1e-9)
