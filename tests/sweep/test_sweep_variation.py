"""A varied workcell changes the real plant (MuJoCo's model) and not the program's frames."""

from __future__ import annotations

import math
import shlex

import mujoco
import numpy as np
import pytest

from cosmos.obstacles import obstacle_scene_xml
from cosmos.plant import Plant, SensorNoise
from cosmos.sweep.variation import WorkcellVariation, rotation_world_xyz
from cosmos.workcell import TOOL_BODY, fixture_frames

G = 9.81


def plant_of(variation: WorkcellVariation) -> Plant:
    return Plant(obstacle_scene_xml(), None, variation.apply_to_spec)


def site(plant: Plant, name: str) -> tuple[np.ndarray, np.ndarray]:
    index = mujoco.mj_name2id(plant.model, mujoco.mjtObj.mjOBJ_SITE, name)
    return plant.data.site_xpos[index].copy(), plant.data.site_xmat[index].reshape(3, 3).copy()


def owned_geoms(plant: Plant, owner: str) -> np.ndarray:
    return np.array([i for i, o in enumerate(plant.geom_owners) if o == owner])


def test_a_moved_hole_moves_its_geoms_and_site_but_not_the_program_s_hole_frame() -> None:
    """Catches the uncertainty leaking into the program (its hole frame moved too) or only the site moved."""
    nominal, moved = (
        plant_of(WorkcellVariation()),
        plant_of(WorkcellVariation(fixtures=(("hole", (0.001, -0.002, 0.0005, 0.0, 0.0, 0.0)),))),
    )
    shift = np.array([0.001, -0.002, 0.0005])
    np.testing.assert_allclose(site(moved, "hole")[0] - site(nominal, "hole")[0], shift, atol=1e-12)
    geoms = owned_geoms(nominal, "hole_fixture")
    assert len(geoms) > 40  # walls, chamfers, tops, bottom
    np.testing.assert_allclose(
        moved.data.geom_xpos[geoms] - nominal.data.geom_xpos[geoms],
        np.tile(shift, (len(geoms), 1)),
        atol=1e-12,
    )
    table = owned_geoms(nominal, "table")
    np.testing.assert_array_equal(moved.data.geom_xpos[table], nominal.data.geom_xpos[table])
    np.testing.assert_allclose(fixture_frames()["hole"].position, site(nominal, "hole")[0], atol=1e-12)


def test_a_turned_slope_turns_about_its_frame_origin() -> None:
    """Catches a rotation about the world origin (the plate flies off) or in the wrong order of axes."""
    turn = (0.0, 0.0, 0.0, math.radians(2.0), math.radians(-1.0), math.radians(3.0))
    nominal, moved = plant_of(WorkcellVariation()), plant_of(WorkcellVariation(fixtures=(("slope", turn),)))
    (p0, r0), (p1, r1) = site(nominal, "slope"), site(moved, "slope")
    np.testing.assert_allclose(p1, p0, atol=1e-12)
    expected = rotation_world_xyz(*turn[3:])
    np.testing.assert_allclose(r1, expected @ r0, atol=1e-12)
    # rotation_world_xyz against MuJoCo's own composition of axis-angle quaternions, z y x order.
    quats = [np.empty(4) for _ in range(3)]
    for quat, axis, angle in zip(quats, np.eye(3), turn[3:], strict=True):
        mujoco.mju_axisAngle2Quat(quat, axis, angle)
    zy, zyx, matrix = np.empty(4), np.empty(4), np.empty(9)
    mujoco.mju_mulQuat(zy, quats[2], quats[1])
    mujoco.mju_mulQuat(zyx, zy, quats[0])
    mujoco.mju_quat2Mat(matrix, zyx)
    np.testing.assert_allclose(expected, matrix.reshape(3, 3), atol=1e-12)


def _static_reading(plant: Plant, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The sensor held still at ``q`` (MuJoCo's inverse dynamics at zero acceleration), and its axes."""
    plant.reset(q)
    plant.data.qacc[:] = 0.0
    mujoco.mj_inverse(plant.model, plant.data)
    sensor = mujoco.mj_name2id(plant.model, mujoco.mjtObj.mjOBJ_SENSOR, "ft_force")
    axes = plant.data.site_xmat[plant.model.sensor_objid[sensor]].reshape(3, 3).copy()
    return plant.read_wrench_sensor(), axes


def test_payload_adds_its_weight_and_the_cell_s_tare_zeroes_it_at_home() -> None:
    """Catches a payload that is only a number (the plant's tool as light as before) or put elsewhere,
    and a sensor left untared with it on: its 9.8 N per kilogram at rest closed the cruise's
    integral as a push (a CONTACT's approach at SPEED 10 mm/s cruised at 4.4 mm/s with 0.34 kg)."""
    nominal, heavy = plant_of(WorkcellVariation()), plant_of(WorkcellVariation(payload_kg=0.4))
    tool = mujoco.mj_name2id(nominal.model, mujoco.mjtObj.mjOBJ_BODY, TOOL_BODY)
    assert heavy.model.body_mass[tool] - nominal.model.body_mass[tool] == pytest.approx(0.4)
    home = nominal.data.qpos[:6].copy()
    turned = home + np.array([0.0, 0.0, 0.0, 0.0, math.pi / 2, 0.0])  # the tool horizontal
    weight = np.array([0.0, 0.0, 0.4 * G])  # what the flange holds up, world axes
    at_home, axes_home = _static_reading(heavy, home)
    np.testing.assert_allclose(at_home, _static_reading(nominal, home)[0], atol=1e-9)
    reading, axes = _static_reading(heavy, turned)
    extra = reading[:3] - _static_reading(nominal, turned)[0][:3]
    np.testing.assert_allclose(extra, axes.T @ weight - axes_home.T @ weight, atol=1e-3 * G)
    payload = mujoco.mj_name2id(heavy.model, mujoco.mjtObj.mjOBJ_GEOM, "payload")
    assert heavy.model.geom_contype[payload] == 0 and heavy.model.geom_conaffinity[payload] == 0


def test_friction_changes_tool_and_fixture_contacts_only() -> None:
    """Catches friction set on the arm's links, or on the tool but not the fixtures (MuJoCo takes the max)."""
    nominal, slippery = plant_of(WorkcellVariation()), plant_of(WorkcellVariation(friction=0.55))
    for name in ("peg", "ft_sensor_housing", "hole_wall00", "hole_chamfer15", "table_top", "slope_plate"):
        geom = mujoco.mj_name2id(slippery.model, mujoco.mjtObj.mjOBJ_GEOM, name)
        assert geom >= 0, name
        assert slippery.model.geom_friction[geom, 0] == pytest.approx(0.55)
        np.testing.assert_array_equal(
            slippery.model.geom_friction[geom, 1:], nominal.model.geom_friction[geom, 1:]
        )
    link = mujoco.mj_name2id(slippery.model, mujoco.mjtObj.mjOBJ_GEOM, "link3_forearm")
    assert slippery.model.geom_friction[link, 0] == nominal.model.geom_friction[link, 0]


def test_sensor_bias_offsets_every_reading_and_keeps_the_noise() -> None:
    """Catches a bias lost in the noise blocks the servo loop reads, or one that changes the noise draws."""
    bias = (0.5, -0.2, 1.0, 0.01, 0.0, -0.02)
    plain = Plant(obstacle_scene_xml(), SensorNoise(11))
    biased = Plant(obstacle_scene_xml(), WorkcellVariation(sensor_bias=bias, noise_seed=11).sensor_noise())
    a = np.array([plain.read_wrench_sensor() for _ in range(1500)])
    b = np.array([biased.read_wrench_sensor() for _ in range(1500)])  # over one noise block of 1024
    np.testing.assert_allclose(b - a, np.tile(bias, (1500, 1)), atol=1e-12)


def test_run_arguments_reproduce_the_variation() -> None:
    """Catches printed --vary arguments that lose precision or a parameter (the run would differ)."""
    from cosmos.sweep.parameters import draw, parse_varies

    varies = parse_varies(
        ["hole.x=normal(0,1mm)", "slope.rz=uniform(-1deg,1deg)", "payload=0.1", "bias.ty=0.003 Nm"]
    )
    variation = WorkcellVariation.from_values(draw(varies, 5, 17))
    words = shlex.split(variation.arguments())  # as a shell reads the printed arguments
    assert words[::2] == ["--vary"] * (len(words) // 2)
    texts = words[1::2]
    again = WorkcellVariation.from_values({v.name: v.a for v in parse_varies(texts)})
    assert again == variation
