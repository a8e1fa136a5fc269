"""A held object's declared mass in the controller's model keeps the tool where it is told to be."""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np
import pytest

from cosmos.errors import TaskFailure
from cosmos.execution.session import Session
from cosmos.hand.tool import Tool
from cosmos.lang import compile_program
from cosmos.runtime.rates import Rates
from cosmos.runtime.setpoint import MotionMode, ServoSetpoint
from cosmos.workcell import fixture_frames
from tests.run.run_support import BOTH_PLANTS

PICK = """TOOL GRIPPER
OBJECT block BOX SIZE (40 mm, 30 mm, 50 mm) MASS 1 kg AT table
MOVE TO table + (0, 0, 32.5 mm) SPEED 50 mm/s
"""
HOLD_S = 1.5


def _steady_error_m(tmp_path: Path, ideal: bool, grasp: bool, declare: bool) -> float:
    """Lift 100 mm (holding the 1 kg block if ``grasp``), hold that goal, return the tool's distance from it.

    The tool is the measured one (MuJoCo's tool site; while held, the block's frame on the hand).
    """
    plan = compile_program(PICK + ("GRASP block\n" if grasp else ""), "p.cos", fixture_frames())
    session = Session(
        "p.cos", None, tmp_path / "p.mcap", Rates(), 0, tool=Tool.GRIPPER, objects=plan.objects, ideal=ideal
    )
    with session:
        executor, runtime = session.executor, session.runtime
        executor.hand.declare_payload = declare  # type: ignore[attr-defined]
        executor.run(plan)
        goal = executor.meter.position + np.array([0.0, 0.0, 0.1])
        with contextlib.suppress(TaskFailure):  # undeclared, the weight may keep it from arriving
            executor.run(compile_program("MOVE BY (0, 0, 100 mm) SPEED 0.1 m/s\n", "p.cos", fixture_frames()))
        runtime.reset_clocks()
        runtime.set_setpoint(
            ServoSetpoint(
                mode=MotionMode.HOLD,
                position=goal,
                rotation_to_world=runtime.evaluation.rotation_tool_to_world.copy(),
                start_s=runtime.time_s,
                force_start_world=runtime.wrench.copy(),
            )
        )
        for _ in range(round(HOLD_S / session.plant.dt_s)):
            runtime.tick()
        return float(np.linalg.norm(executor.meter.position - goal))


@pytest.mark.parametrize("ideal", BOTH_PLANTS)
def test_declared_payload_keeps_the_steady_state_error(tmp_path: Path, ideal: bool) -> None:
    """Holding 1 kg changes the steady-state error by < 1 mm with its mass declared, by more without.

    Catches a payload that does not reach the controller's gravity model (or is added in the
    wrong frame): the arm then sags under the undeclared weight until the integral limit,
    as the comparison run without the declaration shows.
    """
    empty = _steady_error_m(tmp_path, ideal, grasp=False, declare=True)
    declared = _steady_error_m(tmp_path, ideal, grasp=True, declare=True)
    undeclared = _steady_error_m(tmp_path, ideal, grasp=True, declare=False)
    assert abs(declared - empty) < 0.001
    assert undeclared - empty > 0.3e-3
    assert undeclared - empty > 10 * abs(declared - empty), (empty, declared, undeclared)


def test_payload_gravity_is_the_objects_weight_through_the_jacobian() -> None:
    """The held model's g(q) minus the empty hand's is J_c(q)^T m g at the object's centre.

    Catches a payload placed in the wrong frame (joint vs flange), at the wrong centre, or
    with the wrong mass: compared with the weight mapped through the point Jacobian
    (Pinocchio's frame Jacobian of a frame added at the centre, an independent path).
    """
    import pinocchio as pin

    from cosmos.hand.payload import holding
    from cosmos.hand.work_object import ObjectShape, WorkObject
    from cosmos.robot_model import GRAVITY, build_robot_model
    from cosmos.workcell import HOME_Q

    hand = build_robot_model(tool=Tool.GRIPPER)
    item = WorkObject("b", ObjectShape.BOX, (0.02, 0.015, 0.025), 1.0, (0.0, 0.0, 0.0))
    rotation = pin.rpy.rpyToMatrix(0.3, -0.2, 0.5)
    centre = np.array([0.01, -0.02, 0.19])
    held = holding(hand, item, rotation, centre)
    q = HOME_Q + np.array([0.2, -0.3, 0.25, 0.4, 0.3, -0.5])
    extra = pin.computeGeneralizedGravity(held.model, held.data, q) - pin.computeGeneralizedGravity(
        hand.model, hand.data, q
    )
    model = hand.model.copy()
    flange = model.frames[hand.flange_frame]
    point = model.addFrame(
        pin.Frame(
            "centre",
            flange.parentJoint,
            hand.flange_frame,
            flange.placement * pin.SE3(np.eye(3), centre),
            pin.OP_FRAME,
        )
    )
    data = model.createData()
    jacobian = pin.computeFrameJacobian(model, data, q, point, pin.LOCAL_WORLD_ALIGNED)[:3]
    np.testing.assert_allclose(extra, -jacobian.T @ (item.mass_kg * np.asarray(GRAVITY)), atol=1e-9)
    assert held.tool.mass_kg == pytest.approx(hand.tool.mass_kg + 1.0)
