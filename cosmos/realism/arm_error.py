"""How the real arm differs from the published one the controller knows: model error.

The controller's model (:mod:`cosmos.robot_model`) is the published arm (the PUMA 560 of
``shared/reference/puma560.md``, or the Panda's published model). A real arm of the type is
not: its links carry cables and covers, its drives' friction changes with temperature and
wear. The realistic plant is the published arm changed by an :class:`ArmError` drawn from
the run's seed:

* each moving link's mass, and separately its inertia about its centre of mass, scaled
  by ``1 + s u`` (``u`` uniform in [-1, 1], ``s`` the model-error scale: 0.05 by default,
  so up to 5 % either way; the centres of mass stay);
* each drive's rotor inertia (``armature``) scaled the same way;
* each drive's viscous friction, and its Coulomb friction, scaled by ``1 + 2 s u``
  (friction is known less well than mass: up to 10 % by default);
* Coulomb friction with the published asymmetry where the arm has one
  (:attr:`cosmos.robots.Robot.coulomb_by_direction_nm`, the PUMA's drive table): MuJoCo's
  ``frictionloss`` holds the two directions' mean, the plant adds the rest
  (:func:`asymmetry_torque`); the controller compensates the published values by
  direction (:mod:`cosmos.osc.friction`), so what it misses is the drawn error. An arm
  without (the Panda) keeps its model file's symmetric ``frictionloss``, scaled.

The scale is ``--vary model_error=...`` in a sweep. With ``s = 0`` the arm's masses and
friction levels are the published ones, the asymmetry stays.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from cosmos.osc._types import FloatArray
from cosmos.robots import Robot

DEFAULT_SCALE = 0.05
"""Default model-error scale ``s``: link masses, inertias, rotor inertias within 5 %."""

FRICTION_SCALE = 2.0
"""Friction's error is this many times ``s``."""

ASYMMETRY_SPEED_RAD_S = 0.005
"""The asymmetric part of the Coulomb friction ramps in over this joint speed [rad/s]."""


@dataclass(frozen=True)
class ArmError:
    """The real arm's parameters relative to the published ones, per joint (and its link).

    Attributes:
        joints: Joint names, in order; factor ``i`` applies to joint ``i`` and the body it moves.
        mass: Factor on the link's mass. # (n,)
        inertia: Factor on the link's inertia about its centre of mass. # (n,)
        armature: Factor on the drive's rotor inertia. # (n,)
        viscous: Factor on the drive's viscous friction. # (n,)
        coulomb: Factor on the drive's Coulomb friction (both directions). # (n,)
        coulomb_positive_nm: Published Coulomb friction while turning positively [N m];
            None where the arm's file is all there is (symmetric). # (n,)
        coulomb_negative_nm: The same, turning negatively [N m]. # (n,)
    """

    joints: tuple[str, ...]
    mass: tuple[float, ...]
    inertia: tuple[float, ...]
    armature: tuple[float, ...]
    viscous: tuple[float, ...]
    coulomb: tuple[float, ...]
    coulomb_positive_nm: tuple[float | None, ...]
    coulomb_negative_nm: tuple[float | None, ...]

    @classmethod
    def drawn(cls, rng: np.random.Generator, scale: float, robot: Robot) -> ArmError:
        """An arm of ``robot``'s type drawn with ``rng`` at model-error scale ``scale`` (module docstring)."""
        joints, n = robot.joint_names, robot.dof

        def factors(spread: float) -> tuple[float, ...]:
            return tuple(float(f) for f in 1.0 + spread * rng.uniform(-1.0, 1.0, n))

        mass, inertia, armature = factors(scale), factors(scale), factors(scale)
        viscous, coulomb = factors(FRICTION_SCALE * scale), factors(FRICTION_SCALE * scale)
        by_direction = robot.coulomb_by_direction_nm
        published = [None] * n if by_direction is None else list(by_direction)
        return cls(
            joints=tuple(joints),
            mass=mass,
            inertia=inertia,
            armature=armature,
            viscous=viscous,
            coulomb=coulomb,
            coulomb_positive_nm=tuple(None if p is None else p[0] for p in published),
            coulomb_negative_nm=tuple(None if p is None else p[1] for p in published),
        )

    def apply_to_spec(self, spec: mujoco.MjSpec) -> None:
        """Scale the links, rotor inertias and friction in the scene, before it is compiled."""
        for i, name in enumerate(self.joints):
            joint = spec.joint(name)
            body = _body_of(spec, name)
            body.mass = body.mass * self.mass[i]
            body.inertia = np.asarray(body.inertia) * self.inertia[i]
            joint.armature = joint.armature * self.armature[i]
            joint.damping = np.asarray(joint.damping) * self.viscous[i]
            positive, negative = self.coulomb_positive_nm[i], self.coulomb_negative_nm[i]
            mean = joint.frictionloss if positive is None or negative is None else 0.5 * (positive + negative)
            joint.frictionloss = mean * self.coulomb[i]

    def asymmetry_nm(self) -> FloatArray:
        """Half the two directions' Coulomb friction difference, ``(Tc+ - |Tc-|) / 2`` [N m]. # (n,)."""
        return np.array(
            [
                0.0 if p is None or m is None else 0.5 * (p - m) * f
                for p, m, f in zip(
                    self.coulomb_positive_nm, self.coulomb_negative_nm, self.coulomb, strict=True
                )
            ]
        )

    def summary(self) -> dict[str, list[float]]:
        """The drawn factors by name, for the log's metadata."""
        return {
            "mass": list(self.mass),
            "inertia": list(self.inertia),
            "armature": list(self.armature),
            "viscous": list(self.viscous),
            "coulomb": list(self.coulomb),
        }


def asymmetry_torque(qd: FloatArray, asymmetry_nm: FloatArray) -> FloatArray:
    """The friction torque that the symmetric ``frictionloss`` leaves out [N m]. # (n,).

    Coulomb friction opposing motion is ``-Tc+`` turning positively and ``+|Tc-|``
    turning negatively; with ``m = (Tc+ + |Tc-|) / 2`` (``frictionloss``) and ``d = (Tc+ -
    |Tc-|) / 2`` both are ``-m sign(qd) - d``. The ``-d`` is added here, ramped in over
    :data:`ASYMMETRY_SPEED_RAD_S` so that it is zero at rest (where ``frictionloss`` holds).
    """
    return -asymmetry_nm * np.minimum(np.abs(qd) / ASYMMETRY_SPEED_RAD_S, 1.0)


def _body_of(spec: mujoco.MjSpec, joint_name: str) -> mujoco.MjsBody:
    """The body a joint moves."""
    for body in spec.bodies:
        if any(joint.name == joint_name for joint in body.joints):
            return body
    raise KeyError(joint_name)
