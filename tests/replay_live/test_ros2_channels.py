"""The ROS 2 channels of `cosmos run --ros2` decode with mcap-ros2-support and match /cosmos/state."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from replay_live_logs import PROGRAM

from cosmos.commands.run import run_program
from cosmos.runlog.foxglove import ARM_FRAMES
from cosmos.runtime.rates import Rates
from cosmos.workcell import JOINT_NAMES
from tests import foxglove_proto


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    directory = tmp_path_factory.mktemp("ros2")
    program = directory / "tiny.cos"
    program.write_text(PROGRAM)
    path = directory / "run.mcap"
    assert run_program(program, path, Rates(), seed=0, ros2=True) == 0
    return path


def test_ros2_channels_decode_and_carry_the_state(log: Path) -> None:
    """Catches CDR a ROS 2 reader cannot decode (alignment, string lengths, schema text), joint names
    other than the arm's, values out of step with /cosmos/state, or a wrench or pose misplaced."""
    states: dict[int, dict] = {}
    frames: dict[int, dict] = {}
    ros: dict[str, list[tuple[int, object]]] = {}
    with open(log, "rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        for schema, channel, message, decoded in reader.iter_decoded_messages(
            topics=["/joint_states", "/wrench", "/tf_ros"]
        ):
            assert schema is not None and schema.encoding == "ros2msg"
            assert channel.message_encoding == "cdr"
            ros.setdefault(schema.name, []).append((message.log_time, decoded))
    with open(log, "rb") as stream:
        for schema, channel, message in make_reader(stream).iter_messages(topics=["/cosmos/state", "/tf"]):
            assert schema is not None
            if channel.topic == "/cosmos/state":
                states[message.log_time] = json.loads(message.data)
            else:
                frames[message.log_time] = foxglove_proto.decode(schema.name, message.data)

    joints = ros["sensor_msgs/msg/JointState"]
    wrenches = ros["geometry_msgs/msg/WrenchStamped"]
    transforms = ros["tf2_msgs/msg/TFMessage"]
    assert len(joints) == len(wrenches) == len(states) > 100
    assert len(transforms) == len(frames) > 10
    for t_ns, js in joints:
        state = states[t_ns]
        assert js.header.stamp.sec * 10**9 + js.header.stamp.nanosec == t_ns
        assert list(js.name) == list(JOINT_NAMES)
        np.testing.assert_allclose(js.position, state["q"], atol=6e-7)
        np.testing.assert_allclose(js.velocity, state["qd"], atol=6e-7)
        np.testing.assert_allclose(js.effort, state["tau"], atol=6e-7)
    for t_ns, ws in wrenches:
        w = ws.wrench
        got = [w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z]
        np.testing.assert_allclose(got, states[t_ns]["wrench"], atol=6e-7)
        assert ws.header.frame_id == "world"
    for t_ns, tf in transforms:
        expected = frames[t_ns]["transforms"]
        assert [t.child_frame_id for t in tf.transforms] == list(ARM_FRAMES)
        for got, want in zip(tf.transforms, expected, strict=True):
            assert got.header.frame_id == "world"
            assert got.header.stamp.sec * 10**9 + got.header.stamp.nanosec == t_ns
            tr, rot = got.transform.translation, got.transform.rotation
            assert [tr.x, tr.y, tr.z] == [want["translation"][a] for a in "xyz"]
            assert [rot.x, rot.y, rot.z, rot.w] == [want["rotation"][a] for a in "xyzw"]
