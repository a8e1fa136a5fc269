"""A free goal motion against a steady model error: eq. 20-21 leave ``Lambda^-1 f / kp``, its integral not."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import mujoco
import numpy as np

from cosmos.execution.session import Session
from cosmos.runtime.kernels import servo as kernel
from cosmos.runtime.rates import Rates
from cosmos.runtime.servo import ServoGains
from cosmos.runtime.setpoint import DEFAULT_KP, MotionMode, ServoSetpoint
from cosmos.workcell import TOOL_SITE

EXTRA_KG = 1.2
"""Added to the forearm (link3, 4.8 kg in the controller's model): above the wrist sensor, which
does not feel it, as it does not feel the realistic plant's drawn link masses (within 5 %); a
quarter, so that the plain law's error, 1.6 mm, is well over the arrival's 1 mm."""
SETTLE_S = 3.0


def _forearm_error_run(tmp_path: Path, gains: ServoGains) -> tuple[np.ndarray, np.ndarray]:
    """Hold the home pose as a goal motion's goal with the forearm heavier than modelled, friction off.

    Returns the measured tool point minus its goal after SETTLE_S, and the plain law's steady error
    ``-J A^-1 dtau / kp`` (eq. 20-21 near the goal: ``Lambda kp e`` balances the unmodelled force
    ``Jbar^T dtau``, so ``e = -J A^-1 dtau / kp``), from MuJoCo's own J, A and gravity, world [m].
    """
    session = Session("p.cos", None, tmp_path / "p.mcap", Rates(), 0, gains=gains, ideal=True)
    with session:
        runtime, plant = session.runtime, session.plant
        model, data = plant.model, plant.data
        # Without friction the plain law's error is exactly the analytic one (static friction would
        # hold the arm anywhere within its band); the controller compensates none then either.
        model.dof_frictionloss[:] = 0.0
        vectors = runtime.servo._vectors  # the compensation's levels (no setter)
        vectors[kernel.COULOMB_NM] = vectors[kernel.COULOMB_NEGATIVE_NM] = 0.0
        site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, TOOL_SITE)
        goal = data.site_xpos[site].copy()
        forearm = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, "link3")
        at_rest = mujoco.MjData(model)
        at_rest.qpos[:] = data.qpos
        mujoco.mj_forward(model, at_rest)
        gravity = at_rest.qfrc_bias.copy()
        inertia = np.zeros((model.nv, model.nv))
        mujoco.mj_fullM(model, at_rest, inertia)
        jacobian = np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, at_rest, jacobian, None, site)
        model.body_mass[forearm] += EXTRA_KG
        mujoco.mj_forward(model, at_rest)
        extra = at_rest.qfrc_bias - gravity
        expected = -jacobian @ np.linalg.solve(inertia, extra) / DEFAULT_KP
        runtime.set_setpoint(
            ServoSetpoint(
                mode=MotionMode.GOAL,
                position=goal,
                rotation_to_world=runtime.evaluation.rotation_tool_to_world.copy(),
                start_s=runtime.time_s,
                max_speed=0.1,
                max_angular_speed=1.0,
            )
        )
        for _ in range(round(SETTLE_S / plant.dt_s)):
            runtime.tick()
        return data.site_xpos[site] - goal, expected


def test_goal_motion_is_not_held_short_by_a_steady_model_error(tmp_path: Path) -> None:
    """Without the goal integral the tool rests at the analytic ``-J A^-1 dtau / kp`` from its goal
    (within 10 %); with it, within a tenth of that. Catches a free goal motion left short of its goal
    by a model error (a link heavier than modelled; on the realistic plant the gripper's MOVE TO
    stopped 1.1 mm short and failed "no progress"), and an integral that does not act on it."""
    without = replace(ServoGains(), goal_integral=(0.0, 0.0, 0.0, 0.0, 0.0))
    plain, expected = _forearm_error_run(tmp_path, without)
    assert 0.001 < float(np.linalg.norm(expected)) < ServoGains().goal_integral[2]  # within the band
    assert float(np.linalg.norm(plain - expected)) < 0.1 * float(np.linalg.norm(expected)), (plain, expected)
    integrated, _ = _forearm_error_run(tmp_path, ServoGains())
    assert float(np.linalg.norm(integrated)) < 0.1 * float(np.linalg.norm(expected)), (integrated, expected)
