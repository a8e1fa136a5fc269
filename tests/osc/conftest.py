"""Independent engine for the osc tests: Pinocchio's sample 6-DoF manipulator."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import pytest


@dataclass(frozen=True)
class ArmState:
    q: np.ndarray
    qd: np.ndarray
    inertia: np.ndarray  # (n, n) A
    jacobian: np.ndarray  # (6, n) tool point, world axes, [linear; angular]
    bias: np.ndarray  # (n,) b
    gravity: np.ndarray  # (n,) g
    jdot_qdot: np.ndarray  # (6,) h: classical acceleration of the tool at qdd = 0


class SampleArm:
    """Joint-space model quantities from Pinocchio, the engine the osc maths is checked against."""

    def __init__(self) -> None:
        self.model = pin.buildSampleModelManipulator()
        self.data = self.model.createData()
        self.frame = self.model.getFrameId("effector_body")
        self.n = self.model.nv

    def state(self, q: np.ndarray, qd: np.ndarray) -> ArmState:
        m, d = self.model, self.data
        inertia = pin.crba(m, d, q)
        inertia = np.triu(inertia) + np.triu(inertia, 1).T
        nle = pin.nonLinearEffects(m, d, q, qd)
        gravity = pin.computeGeneralizedGravity(m, d, q).copy()
        jac = pin.computeFrameJacobian(m, d, q, self.frame, pin.LOCAL_WORLD_ALIGNED)
        pin.forwardKinematics(m, d, q, qd, np.zeros(self.n))
        pin.updateFramePlacements(m, d)
        acc = pin.getFrameClassicalAcceleration(m, d, self.frame, pin.LOCAL_WORLD_ALIGNED)
        return ArmState(
            q=q,
            qd=qd,
            inertia=inertia,
            jacobian=jac.copy(),
            bias=nle - gravity,
            gravity=gravity,
            jdot_qdot=np.concatenate([acc.linear, acc.angular]),
        )

    def joint_acceleration(self, q: np.ndarray, qd: np.ndarray, tau: np.ndarray) -> np.ndarray:
        return pin.aba(self.model, self.data, q, qd, tau).copy()

    def random_state(self, rng: np.random.Generator) -> ArmState:
        q = rng.uniform(-2.5, 2.5, self.n)
        return self.state(q, rng.normal(0.0, 1.0, self.n))


@pytest.fixture(scope="session")
def arm() -> SampleArm:
    return SampleArm()


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240601)
