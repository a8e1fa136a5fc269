"""A gripper session with a block under the fingers, for the hand's tests.

The numbers that judge the runs are written here from the gripper's datasheet and the
block's declaration (Robotiq 2F-85: 0.925 kg; the wrist sensor's housing on the tool side:
0.25 kg, ``cosmos/models/puma560/scene.xml``), not read from the code under test.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from cosmos.execution.session import Session
from cosmos.hand.tool import Tool
from cosmos.hand.work_object import ObjectShape, WorkObject
from cosmos.lang import compile_program
from cosmos.runtime.rates import Rates
from cosmos.workcell import fixture_frames

G = 9.81
HAND_MASS_KG = 0.925 + 0.25
"""The gripper (datasheet) and the sensor's tool-side housing [kg]."""
HOME_TCP_XY = (0.5963, -0.15005)
"""The tool point's x, y at home [m] (the peg's tip's: the gripper's is on the same axis)."""
BLOCK = WorkObject("block", ObjectShape.BOX, (0.02, 0.015, 0.025), 0.5, (*HOME_TCP_XY, 0.225))
"""A 0.5 kg block, 40 mm between the pads, standing on the table under the home tool point."""
DOWN_TO_BLOCK = "MOVE BY (0, 0, -232.5 mm) SPEED 0.1 m/s\n"
GRASP_BLOCK = (
    "TOOL GRIPPER\nOBJECT block BOX SIZE (40 mm, 30 mm, 50 mm) MASS 0.5 kg AT table\nGRASP block FORCE 40 N\n"
)
"""A GRASP of :data:`BLOCK` with 40 N (declared as the session has it: the text compiles alone)."""
"""From home to the pads' centres 12.5 mm below the block's top (the pads are 25 mm tall)."""


def gripper_session(tmp_path: Path, ideal: bool, objects: tuple[WorkObject, ...] = (BLOCK,)) -> Session:
    """A session of the PUMA with the gripper and ``objects``, logging to ``tmp_path``."""
    return Session(
        "t.cos", None, tmp_path / "t.mcap", Rates(), 3, tool=Tool.GRIPPER, ideal=ideal, objects=objects
    )


def run_text(session: Session, text: str) -> None:
    """Compile ``text`` and run it in ``session``."""
    session.executor.run(compile_program(text, "t.cos", fixture_frames()))


def body_position(session: Session, name: str) -> np.ndarray:
    """MuJoCo's position of body ``name``, world [m]."""
    plant = session.plant
    return plant.data.xpos[plant.model.body(name).id].copy()


def tf_last_pose(log_path: Path, frame: str) -> tuple[np.ndarray, np.ndarray]:
    """The last pose of body ``frame`` on the log's ``/tf`` (MuJoCo's): position [m], quat w x y z."""
    from cosmos.runlog.scan import load_mcap
    from tests.foxglove_proto import decode

    contents = load_mcap(log_path)
    channels = {cid: c for cid, c in contents.channels.items() if c.topic == "/tf"}
    found = None
    for message in contents.messages:
        channel = channels.get(message.channel_id)
        if channel is None:
            continue
        decoded = decode(contents.schemas[channel.schema_id].name, message.data)
        for transform in decoded["transforms"]:
            if transform["child_frame_id"] == frame:
                found = transform
    assert found is not None, f"no /tf pose of {frame} in {log_path}"
    t, r = found["translation"], found["rotation"]
    return np.array([t["x"], t["y"], t["z"]]), np.array([r["w"], r["x"], r["y"], r["z"]])


def hand_samples(log_path: Path) -> list[dict[str, object]]:
    """The messages of the log's ``/cosmos/hand``, in order."""
    import json

    from cosmos.runlog.scan import load_mcap

    contents = load_mcap(log_path)
    ids = {cid for cid, c in contents.channels.items() if c.topic == "/cosmos/hand"}
    return [json.loads(m.data) for m in contents.messages if m.channel_id in ids]


Poses = dict[str, tuple[np.ndarray, np.ndarray]]
"""Per frame, its positions [m] # (n, 3) and quaternions w x y z # (n, 4)."""


def tf_poses(log_path: Path, frames: tuple[str, ...]) -> tuple[np.ndarray, Poses]:
    """The log's ``/tf`` samples that have every one of ``frames`` (MuJoCo's body poses).

    Returns:
        The samples' times [s] # (n,), and per frame its positions [m] # (n, 3) and
        quaternions w x y z # (n, 4).
    """
    from cosmos.runlog.scan import load_mcap
    from tests.foxglove_proto import decode

    contents = load_mcap(log_path)
    channels = {cid: c for cid, c in contents.channels.items() if c.topic == "/tf"}
    times: list[float] = []
    rows: dict[str, list[list[float]]] = {frame: [] for frame in frames}
    for message in contents.messages:
        channel = channels.get(message.channel_id)
        if channel is None:
            continue
        decoded = decode(contents.schemas[channel.schema_id].name, message.data)
        found = {t["child_frame_id"]: t for t in decoded["transforms"] if t["child_frame_id"] in rows}
        if len(found) < len(frames):
            continue
        stamp = found[frames[0]]["timestamp"]
        times.append(float(stamp["sec"]) + 1e-9 * float(stamp["nsec"]))
        for frame, transform in found.items():
            t, r = transform["translation"], transform["rotation"]
            rows[frame].append([t["x"], t["y"], t["z"], r["w"], r["x"], r["y"], r["z"]])
    table = {frame: np.array(values, dtype=float).reshape(-1, 7) for frame, values in rows.items()}
    return np.array(times), {frame: (values[:, :3], values[:, 3:]) for frame, values in table.items()}
