"""The tool's contacts are steel (issue 14, item 5): read from MuJoCo's compiled scene.

MuJoCo mixes two geoms' ``solref`` and ``solimp`` by their ``solmix`` weights
(``mix = solmix1 / (solmix1 + solmix2)``, XML reference "geom/solmix"); these tests
apply that documented rule to the compiled model's own parameters for every pair
the peg can touch, and read one contact MuJoCo itself made.
"""

from __future__ import annotations

import mujoco
import numpy as np
import pytest

from cosmos.workcell import SCENE_XML

STEEL_TIME_CONSTANT_S = 0.02
"""The softest contact time constant counted as steel-like (MuJoCo's own default)."""


@pytest.fixture(scope="module")
def model() -> mujoco.MjModel:
    return mujoco.MjModel.from_xml_path(str(SCENE_XML))


def _tool_geoms(model: mujoco.MjModel) -> list[int]:
    tool = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "tool")
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] == tool]


def _world_geoms(model: mujoco.MjModel) -> list[int]:
    return [g for g in range(model.ngeom) if model.geom_bodyid[g] == 0 and model.geom_conaffinity[g]]


def _mixed_time_constant(model: mujoco.MjModel, a: int, b: int) -> float:
    wa, wb = float(model.geom_solmix[a]), float(model.geom_solmix[b])
    mix = 0.5 if wa + wb == 0.0 else wa / (wa + wb)
    return float(mix * model.geom_solref[a, 0] + (1.0 - mix) * model.geom_solref[b, 0])


def test_every_tool_contact_has_a_steel_time_constant(model: mujoco.MjModel) -> None:
    """Each pair (tool geom, fixture geom): the mixed solref time constant at most 0.02 s.

    Catches a tool geom softened to hide impact spikes (its solref was 0.18 s, 45 times the
    fixtures' 0.004 s, and the pair's mix 0.092 s); impacts are the force loop's job."""
    pairs = [(t, w) for t in _tool_geoms(model) for w in _world_geoms(model)]
    assert pairs
    softest = max(pairs, key=lambda p: _mixed_time_constant(model, *p))
    name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_GEOM, softest[1]) or str(softest[1])
    assert _mixed_time_constant(model, *softest) <= STEEL_TIME_CONSTANT_S, name


def test_the_peg_on_the_table_contact_is_the_mixed_one(model: mujoco.MjModel) -> None:
    """The peg's tip set just into the table: MuJoCo's own contact carries the mixed solref.

    Catches the mixing rule the test above applies differing from MuJoCo's (a solmix the
    compiler ignores would leave the contact at other parameters)."""
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    mujoco.mj_forward(model, data)
    tool_site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "tool")
    table = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "table_top")
    peg = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_GEOM, "peg")
    top_z = float(model.geom_pos[table, 2] + model.geom_size[table, 2])
    # Lower the arm along joint 2 (down as q2 falls) until the tip is 0.1 mm into the table.
    below, above = float(data.qpos[1]) - 0.6, float(data.qpos[1])
    for _ in range(60):
        data.qpos[1] = 0.5 * (below + above)
        mujoco.mj_forward(model, data)
        if data.site_xpos[tool_site, 2] > top_z - 1e-4:
            above = float(data.qpos[1])
        else:
            below = float(data.qpos[1])
    data.qpos[1] = below
    mujoco.mj_forward(model, data)
    contacts = [
        data.contact[i]
        for i in range(data.ncon)
        if {data.contact[i].geom1, data.contact[i].geom2} == {peg, table}
    ]
    assert contacts, "the peg does not touch the table"
    assert np.isclose(contacts[0].solref[0], _mixed_time_constant(model, peg, table), rtol=1e-9)
    assert contacts[0].solref[0] <= STEEL_TIME_CONSTANT_S
