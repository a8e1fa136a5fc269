"""The arm drawn on /scene sits where MuJoCo has it: link shapes composed with /tf vs geom_xpos."""

from __future__ import annotations

import json
from pathlib import Path

import mujoco
import numpy as np
import pytest
from mcap.reader import make_reader
from replay_live_logs import PROGRAM, run_to_log

from cosmos.obstacles import obstacle_scene_xml
from cosmos.plant import Plant
from cosmos.realism.encoders import encoder_resolution_rad
from cosmos.robots import PUMA560
from cosmos.runlog.foxglove import ARM_FRAMES
from tests import foxglove_proto


@pytest.fixture(scope="module")
def log(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return run_to_log(tmp_path_factory.mktemp("arm"), PROGRAM)


def _read(log: Path) -> dict[str, list[tuple[int, dict]]]:
    out: dict[str, list[tuple[int, dict]]] = {}
    with open(log, "rb") as stream:
        for schema, channel, message in make_reader(stream).iter_messages():
            assert schema is not None
            if channel.message_encoding == "protobuf":
                decoded = foxglove_proto.decode(schema.name, message.data)
            else:
                decoded = json.loads(message.data)
            out.setdefault(channel.topic, []).append((message.log_time, decoded))
    return out


def _rotation(q: dict) -> np.ndarray:
    """Rotation matrix of a Foxglove {x, y, z, w} quaternion (computed by MuJoCo)."""
    out = np.empty(9)
    mujoco.mju_quat2Mat(out, np.array([q["w"], q["x"], q["y"], q["z"]]))
    return out.reshape(3, 3)


REACH_M = 1.0
"""Longer than any lever from a joint axis to a link geom of the PUMA (its reach is under 0.9 m)."""
TOLERANCE_M = 1e-5 + REACH_M * float(encoder_resolution_rad(PUMA560).sum()) / 2
"""/tf is the arm's true pose, the state's q the encoders' (realistic plant: within half a count
of it), so MuJoCo placed at that q may be off by sum(half a count x lever): 0.32 mm at most."""


def _xyz(v: dict) -> np.ndarray:
    return np.array([v["x"], v["y"], v["z"]])


def test_link_shapes_composed_with_tf_are_mujocos_geoms(log: Path) -> None:
    """Catches link shapes placed in the wrong frame, with the geom's pose misapplied (not composed
    with the link's /tf pose, quaternion order swapped) or missing a geom, which a screenshot
    of Foxglove's 3D panel would show as an arm in pieces."""
    topics = _read(log)
    (t0, first), *_ = topics["/scene"]
    assert t0 == 0
    entities = {e["id"]: e for e in first["entities"]}
    states = {t: m for t, m in topics["/cosmos/state"]}
    t_ns, tf = topics["/tf"][len(topics["/tf"]) // 2]  # mid-run: the arm has moved
    frames = {f["child_frame_id"]: f for f in tf["transforms"]}

    plant = Plant(obstacle_scene_xml())
    model, data = plant.model, plant.data
    data.qpos[:] = states[t_ns]["q"]
    mujoco.mj_kinematics(model, data)

    checked = 0
    for frame in ARM_FRAMES:
        entity = entities[frame]
        assert entity["frame_id"] == frame and entity["frame_locked"]
        link = frames[frame]
        rotation, origin = _rotation(link["rotation"]), _xyz(link["translation"])
        centres = [
            origin + rotation @ _xyz(p["pose"]["position"]) for p in entity["cubes"] + entity["cylinders"]
        ]
        body = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, frame)
        geoms = np.flatnonzero(model.geom_bodyid == body)
        assert len(centres) == len(geoms) > 0
        for g in geoms:
            error = min(np.linalg.norm(c - data.geom_xpos[g]) for c in centres)
            assert error < TOLERANCE_M, (frame, model.geom(g).name, error)
            if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_CAPSULE:  # its end caps
                axis = data.geom_xmat[g].reshape(3, 3)[:, 2] * model.geom_size[g][1]
                ends = [origin + rotation @ _xyz(s["pose"]["position"]) for s in entity["spheres"]]
                for end in (data.geom_xpos[g] + axis, data.geom_xpos[g] - axis):
                    assert min(np.linalg.norm(e - end) for e in ends) < TOLERANCE_M
            checked += 1
    assert checked >= 10
