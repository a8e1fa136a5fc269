"""LogRecorder against MuJoCo's own tool pose, NumPy's J qd and the frames' poses, read back from the log."""

import json
from pathlib import Path

import mujoco
import numpy as np
from mcap.reader import make_reader

from cosmos.execution.recording import TRANSFORM_EVERY, LogRecorder
from cosmos.plant import Plant
from cosmos.robot_model import build_robot_model
from cosmos.runlog import RunLog
from cosmos.runlog.foxglove import ARM_FRAMES
from cosmos.runtime.parameters import ParameterLevel
from cosmos.workcell import TOOL_SITE
from tests import foxglove_proto


def test_recorded_state_and_frames_are_the_simulators(tmp_path: Path) -> None:
    plant = Plant()
    level = ParameterLevel(build_robot_model())
    path = tmp_path / "recorder.mcap"
    log = RunLog(
        path, program="r.cos", source=None, servo_hz=1000, param_hz=125, state_hz=250, model="m", seed=0
    )
    recorder = LogRecorder(log, plant)
    model, data = plant.model, plant.data
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)
    bodies = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name) for name in ARM_FRAMES]
    rng = np.random.default_rng(2)
    expected_states, expected_frames = [], []
    for k in range(12):
        tau = rng.uniform(-20, 20, 6)
        for _ in range(4):
            plant.step(tau)
        q, qd = plant.read_encoders()
        evaluation = level.evaluate(q, qd)
        wrench = rng.normal(size=6)
        recorder.segment, recorder.line = k // 4, 10 + k // 4
        v = evaluation.jacobian @ qd
        recorder.record(plant.time_s, q, qd, tau, wrench, v)
        quat = np.empty(4)
        mujoco.mju_mat2Quat(quat, data.site_xmat[site])
        expected_states.append((plant.time_s, q, qd, tau, data.site_xpos[site].copy(), quat, v, wrench, k))
        if k % TRANSFORM_EVERY == 0:
            expected_frames.append((plant.time_s, data.xpos[bodies].copy(), data.xquat[bodies].copy()))
    log.close()

    by_topic: dict[str, list[dict]] = {}
    with open(path, "rb") as stream:
        for schema, channel, message in make_reader(stream).iter_messages():
            if channel.message_encoding == "protobuf":
                assert schema is not None
                decoded = foxglove_proto.decode(schema.name, message.data)
            else:
                decoded = json.loads(message.data)
            by_topic.setdefault(channel.topic, []).append(decoded)
    states, frames = by_topic["/cosmos/state"], by_topic["/tf"]
    assert len(states) == 12 and len(frames) == len(expected_frames) == 3
    for message, (t, q, qd, tau, x, quat, v, wrench, k) in zip(states, expected_states, strict=True):
        assert message["t"] == round(t, 9)
        for name, value in zip(
            ("q", "qd", "tau", "x", "quat", "v", "wrench"), (q, qd, tau, x, quat, v, wrench), strict=True
        ):
            np.testing.assert_allclose(message[name], value, rtol=0, atol=5.0000001e-7, err_msg=name)
        assert (message["segment"], message["line"]) == (k // 4, 10 + k // 4)
    for message, (t, positions, quats) in zip(frames, expected_frames, strict=True):
        assert [f["child_frame_id"] for f in message["transforms"]] == list(ARM_FRAMES)
        for f, p, wxyz in zip(message["transforms"], positions, quats, strict=True):
            assert f["timestamp"]["sec"] * 10**9 + f["timestamp"]["nsec"] == round(t * 1e9)
            np.testing.assert_allclose([f["translation"][a] for a in "xyz"], p, atol=5.0000001e-7)
            np.testing.assert_allclose([f["rotation"][a] for a in "wxyz"], wxyz, atol=5.0000001e-7)
