"""The servo's held null-space torques: posture, joint-limit potential and the links' field (section 4).

At each parameter evaluation the servo folds the task (kernels.parameter) and
obtains its ``N^T``; where a null space exists (a position-only task on the
PUMA, any task on a redundant arm) the torques held until the next evaluation
are then shaped by :mod:`cosmos.osc.null_space`: the posture spring in the null
space, and the joint-limit potential and the obstacle field on the links
through ``N^T`` unless a joint or a link is dangerously close. The field on the
tool's own link is the end effector's obstacle avoidance and acts whole. With
no null space (a full task on the six-joint arm away from singularities) and no
posture this costs one trace per evaluation and changes nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cosmos.osc.null_space import (
    AbsorptionPolicy,
    absorbed_weight,
    null_space_dimension,
    null_space_intent,
    posture_torque,
    through_null_space,
)
from cosmos.runtime.kernels import servo as kernel
from cosmos.runtime.parameters import Evaluation
from cosmos.runtime.servo_gains import ServoGains

FloatArray = np.ndarray


@dataclass(frozen=True)
class LinkField:
    """The obstacle field's joint torques split by where they act, and the nearest link.

    Attributes:
        tool: Torques of the forces on the tool's link (it carries the tool), [N m]. # (n,)
        links: Torques of the forces on every other link, [N m]. # (n,)
        clearance_m: Surface distance of the nearest other link to an obstacle, [m] (inf: none).
        link: That link's name ("" when none).
        obstacle: That obstacle's name ("" when none).
    """

    tool: FloatArray
    links: FloatArray
    clearance_m: float = math.inf
    link: str = ""
    obstacle: str = ""


class NullSpaceTerms:
    """What the null space adds to the servo's held torque at one evaluation.

    Args:
        posture_kp: Unit-mass stiffness of the posture task, in [1/s^2].
        policy: When a field acts through the null space only.
        observer: A free hold's disturbance observer while the null space is driven
            (:func:`cosmos.osc.integral_action.observe_hold_disturbance`): ``(L [1/s], bound
            [m/s^2], band [m], quiet [N])``.
        lookahead_s: How far ahead the Coulomb compensation counts a commanded joint
            acceleration toward the direction of motion, in [s] (:mod:`cosmos.osc.friction`).
    """

    def __init__(
        self,
        posture_kp: float,
        policy: AbsorptionPolicy,
        observer: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0),
        lookahead_s: float = 0.0,
    ):
        self.posture_kp = posture_kp
        self.policy = policy
        self._observer, self._lookahead_s = observer, lookahead_s
        self.observer_gain = 0.0
        """L for the hold's observer at the last evaluation: ``observer``'s while a posture, the
        links' field or the joint-limit potential acts through the null space, else 0 [1/s]."""
        self.known_acceleration = np.zeros(3)
        """``J A^-1 Gamma`` of the potentials as applied, translation, world [m/s^2]: what of them
        reaches the tool by design (the posture's part is zero), which the observer expects."""
        self.intent = np.zeros(0)
        """``L A^-1 Gamma`` of the same: where they tell the joints to turn, over the friction's
        look-ahead, in [rad/s] (:func:`cosmos.osc.null_space.null_space_intent`). # (n,)"""
        self.dimension = 0.0
        """``trace(N^T)`` of the last evaluation: the null space's dimension."""
        self.link_share_to_tool = 0.0
        """Share (0..1) of the links' field that reaches the tool although a null space exists."""

    @classmethod
    def of(cls, gains: ServoGains, policy: AbsorptionPolicy) -> NullSpaceTerms:
        """The terms for the servo's gains (posture, hold observer, friction look-ahead)."""
        band, quiet = gains.goal_integral[2], gains.goal_integral[4]  # the goal integral's gate
        observer = (*gains.hold_observer, band, quiet)
        return cls(gains.posture_kp, policy, observer, gains.coulomb_lookahead_s)

    def write(self, scalars: FloatArray, vectors: FloatArray, n: int) -> None:
        """Put the last evaluation's observer gain, known acceleration and intent in the servo's rows."""
        scalars[kernel.HOLD_OBSERVER : kernel.HOLD_OBSERVER + 4] = (self.observer_gain, *self._observer[1:])
        vectors[kernel.HOLD_KNOWN, :3] = self.known_acceleration
        vectors[kernel.NULL_INTENT, :n] = self.intent if self.intent.size else 0.0

    def clear(self) -> None:
        """No null space in use: no observer, nothing expected, no intent."""
        self.observer_gain, self.known_acceleration, self.intent = 0.0, np.zeros(3), np.zeros(0)

    def correction(
        self,
        null_space_t: FloatArray,
        evaluation: Evaluation,
        limit_margin_rad: float,
        field: LinkField,
        field_torque: FloatArray,
        posture_rad: FloatArray | None,
    ) -> FloatArray:
        """What to add to the raw potentials (joint limits + field) held until the next evaluation.

        Args:
            null_space_t: N^T of the task at this evaluation. # (n, n)
            evaluation: The evaluation (A(q), q and the joint-limit potential).
            limit_margin_rad: The smallest distance of a joint to its limit, in [rad].
            field: The obstacle field, split.
            field_torque: Its total, ``field.tool + field.links``, in [N m]. # (n,)
            posture_rad: The posture the arm returns to, or None. # (n,)

        Returns:
            Joint torques in [N m]; zero where there is no null space to use. # (n,)
        """
        policy = self.policy
        limit_torque = evaluation.joint_limit_torque
        self.dimension = dimension = null_space_dimension(null_space_t)
        self.link_share_to_tool = 0.0
        self.clear()
        if dimension < policy.min_dimension:
            return np.zeros(null_space_t.shape[0])
        torque = field.tool.copy()
        if field.links.any():
            weight = absorbed_weight(field.clearance_m, policy.link_full_below_m, policy.link_absorbed_from_m)
            torque += through_null_space(field.links, null_space_t, weight)
            self.link_share_to_tool = 1.0 - weight
        if limit_torque.any():
            weight = absorbed_weight(
                limit_margin_rad, policy.joint_full_below_rad, policy.joint_absorbed_from_rad
            )
            torque += through_null_space(limit_torque, null_space_t, weight)
        if posture_rad is not None:
            q, inertia = evaluation.q, evaluation.inertia
            torque += posture_torque(null_space_t, inertia, q, posture_rad, self.posture_kp)
        if posture_rad is not None or field.links.any() or limit_torque.any():
            # The joints the null space turns bring their friction error (and what of N^T the
            # model's A does not keep from the task) to the held tool: the hold takes it back,
            # but not what of the fields is meant to reach the tool (its own link's, a link's
            # too close), whose acceleration ``J A^-1 Gamma`` the observer is told.
            self.observer_gain = self._observer[0]
            self.known_acceleration = evaluation.jacobian[:3].dot(evaluation.inertia_inv.dot(torque))
            self.intent = null_space_intent(evaluation.inertia_inv, torque, self._lookahead_s)
        return torque - limit_torque - field_torque
