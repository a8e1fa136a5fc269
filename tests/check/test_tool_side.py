"""The checker warns where the tool's side meets a fixture at a goal, as MuJoCo finds the peg."""

from __future__ import annotations

import functools
import math

import mujoco
import numpy as np
import pytest

from cosmos.robots import ROBOTS
from cosmos.workcell import scene_spec
from tests.check.test_goal_inside_fixture import inside_warnings

PEG_RADIUS_M, PEG_FROM_M, PEG_TO_M = 0.0099125, 0.0015, 0.15
"""The scene's peg (``cosmos/models/puma560/scene.xml``): radius, and from and to how far back
from the tool point it runs [m]."""


@functools.cache
def _scene() -> tuple[mujoco.MjModel, mujoco.MjData]:
    """The workcell with a free-standing copy of the peg on a mocap body."""
    spec = scene_spec(ROBOTS["puma560"].scene_xml)
    body = spec.worldbody.add_body(name="peg_probe", mocap=True)
    half = (PEG_TO_M - PEG_FROM_M) / 2.0
    body.add_geom(
        name="peg_probe",
        type=mujoco.mjtGeom.mjGEOM_CYLINDER,
        size=[PEG_RADIUS_M, half, 0],
        contype=0,
        conaffinity=0,
    )
    model = spec.compile()
    return model, mujoco.MjData(model)


def _peg_into_hole_block(goal: np.ndarray) -> float:
    """How far MuJoCo finds the peg, its tip at ``goal`` pointing down the hole, into the hole's block [m]."""
    model, data = _scene()
    mujoco.mj_kinematics(model, data)
    rotation = data.site("hole").xmat.copy()
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rotation)
    data.mocap_pos[0] = goal - rotation.reshape(3, 3)[:, 2] * (PEG_FROM_M + PEG_TO_M) / 2.0
    data.mocap_quat[0] = quat
    mujoco.mj_kinematics(model, data)
    probe = model.geom("peg_probe").id
    block = [
        g for g in range(model.ngeom) if model.geom_bodyid[g] == 0 and model.geom(g).name.startswith("hole")
    ]
    return -min(mujoco.mj_geomDistance(model, data, probe, g, 0.01, None) for g in block)


CASES = [(offset, angle) for offset in (0.0, 0.05, 0.3, 1.0, 2.5) for angle in (0.0, 30.0, 45.0, 101.25)]


@pytest.mark.parametrize(("offset_mm", "angle_deg"), CASES)
def test_a_peg_off_the_bores_axis_is_warned_as_mujoco_finds_it(offset_mm: float, angle_deg: float) -> None:
    """``MOVE TO hole + (dx, dy, -30 mm)``: the tool point is in the bore (no solid), but off the
    axis by more than the clearance (0.12 mm) the peg's side is in the block's wall. Warned exactly
    when MuJoCo finds a copy of the peg there more than 0.1 mm into the block, with its depth; on
    the axis, or within the clearance, not. Catches the bore's walls ignored (the run stops at
    the touch) and the bore taken as solid."""
    angle = math.radians(angle_deg)
    dx, dy = offset_mm * math.cos(angle), offset_mm * math.sin(angle)
    goal = _scene()[1].site("hole").xpos + np.array((dx / 1e3, dy / 1e3, -0.03))
    into = _peg_into_hole_block(goal)
    found = inside_warnings(f"MOVE TO hole + ({dx:.6f} mm, {dy:.6f} mm, -30 mm)\n")
    if into <= 1e-4:
        assert not found, (into, found)
        return
    assert len(found) == 1, (into, found)
    match = found[0][1]
    assert "the tool's side" in match.group(0) and match["fixture"] == "hole"
    assert float(match["depth"]) == pytest.approx(into * 1e3, abs=0.051)
