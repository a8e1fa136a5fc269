"""The obstacles' artificial potential field (seed section 6), as joint torques for the runtime.

For every link ``k`` of the arm (its capsules, :mod:`cosmos.obstacles.capsules`;
link 6 carries the tool) and every obstacle ``O``, the link's point ``p``
closest to ``O``, at surface distance ``rho`` along the unit normal ``n``
pointing away from ``O``, is pushed by::

    F = [ eta (1/rho - 1/rho_0) / rho^2            FIRAS, -grad U (cosmos.osc.firas)
          + c (1 - rho/rho_0) max(0, -n . (v_p - v_O)) ]  n     for rho < rho_0

The second term damps the approach: ``v_p - v_O`` is the point's velocity
relative to the obstacle (``v_O`` its ``MOVING`` velocity, so a moving obstacle
is a time-varying potential whose position is taken at time ``t`` and whose
motion enters the damping), and the ramp ``1 - rho/rho_0`` keeps the force
continuous at the edge of the influence zone. The magnitude is capped. An
obstacle's ``gain_scale`` multiplies both eta and c.

The force acts on the arm through the point's Jacobian, ``Gamma = J_p^T F``.
With Pinocchio's world Jacobian ``J`` (spatial velocities of the joints'
bodies at the world origin, columns 0..k for link k), ``J_p = J_v + J_w x p``
column by column, so ``Gamma = J[:, :k+1]^T (F, p x F)``: the force becomes a
wrench about the world origin, summed per link, and joint j carries the links
beyond it, ``Gamma_j = J_j . sum_{k >= j} W_k``.

Cost: the runtime asks for the field at the parameter rate; it evaluates
itself every ``period_s`` (8 ms) and holds its torque in between. The closest
points come from the controller's own geometric model (:mod:`cosmos.obstacles.geometry`: candidate
lists, MuJoCo's ``mj_geomDistance``, :mod:`cosmos.osc.firas` where a link
touches), measured every ``geometry_every`` evaluations and estimated to first
order in between. docs/obstacles.md has the figures.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from cosmos.errors import CosmosError
from cosmos.obstacles.capsules import LINK_BODIES, arm_capsules, joint_reach_m
from cosmos.obstacles.geometry import ProximityModel
from cosmos.obstacles.obstacle import Obstacle
from cosmos.osc.firas import firas_magnitude
from cosmos.robot_model import RobotModel

FloatArray = np.ndarray


@dataclass(frozen=True)
class FieldParameters:
    """Defaults of the obstacle field; ``OBSTACLE`` may set rho_0 and scale eta and c per obstacle.

    Attributes:
        influence_m: rho_0, the distance from the surface beyond which an obstacle
            exerts no force, in [m].
        eta: FIRAS gain, in [N m^3]: the force is ``eta (1/rho - 1/rho_0)/rho^2``.
        damping_ns_per_m: c, damping of the approach speed at the surface, in [N s/m]
            (it ramps to 0 at rho_0).
        force_cap_n: Largest force on one link from one obstacle, in [N].
        geometry_every: The closest points are measured at every this many
            evaluations and estimated to first order in between (as the seed's
            servo level estimates the end effector between evaluations); 1 measures
            them every time.
        period_s: Least time between two evaluations, in [s]: asked again sooner
            (the runtime asks at its parameter rate), the field returns its last
            torque, which the servo holds. 0 evaluates at every request.
    """

    influence_m: float = 0.10
    eta: float = 1.0e-3
    damping_ns_per_m: float = 300.0
    force_cap_n: float = 400.0
    geometry_every: int = 2
    period_s: float = 0.008

    def __post_init__(self) -> None:
        positive = (self.influence_m, self.eta, self.force_cap_n)
        if min(positive) <= 0.0 or min(self.damping_ns_per_m, self.period_s) < 0.0 or self.geometry_every < 1:
            raise CosmosError(
                "obstacle field: rho_0, eta and the cap must be > 0, the damping and period >= 0 and "
                f"geometry_every >= 1; got {self}"
            )


class Influence(NamedTuple):
    """What one obstacle does to the arm at one evaluation.

    Attributes:
        obstacle: The obstacle's name.
        link: The link nearest to it (``link6`` includes the tool).
        distance_m: That link's surface distance to the obstacle, in [m].
        force_n: Largest force magnitude the obstacle exerts on a link, in [N].
    """

    obstacle: str
    link: str
    distance_m: float
    force_n: float


class ObstacleField:
    """FIRAS repulsion of every link from every obstacle; a runtime ``PotentialField``.

    Args:
        robot: The controller's model (the field keeps its own Pinocchio data).
        parameters: Default rho_0, eta, damping and cap.
    """

    def __init__(self, robot: RobotModel, parameters: FieldParameters = FieldParameters()) -> None:
        self.parameters = parameters
        self.enabled = True
        """When False, :meth:`torque` is zero (the obstacles are still tracked)."""
        self._model = robot.model
        self._data = robot.model.createData()
        self._capsules = arm_capsules(robot)
        self._reach = joint_reach_m(robot, self._capsules).tolist()
        self._obstacles: dict[str, Obstacle] = {}
        self._geometry: ProximityModel | None = None
        self._obstacle_speed = 0.0
        self._evaluations = 0
        self._speed_bound = 0.0
        self._evaluated_s = -np.inf
        self._torque = np.zeros(6)
        self._acting: dict[int, list] = {}  # obstacle index -> [distance, link, strongest force]
        self._influences: tuple[Influence, ...] | None = ()

    @property
    def influences(self) -> tuple[Influence, ...]:
        """Obstacles whose field acted at the last evaluation, with their nearest link."""
        if self._influences is None:
            obstacles = self._geometry.obstacles if self._geometry is not None else ()
            self._influences = tuple(
                Influence(obstacles[j].name, LINK_BODIES[k], distance, force)
                for j, (distance, k, force) in sorted(self._acting.items())
            )
        return self._influences

    @property
    def obstacles(self) -> tuple[Obstacle, ...]:
        """The obstacles the field repels from."""
        return tuple(self._obstacles.values())

    def add(self, obstacle: Obstacle) -> None:
        """Start repelling from ``obstacle``.

        Raises:
            CosmosError: If an obstacle of that name is already in the field.
        """
        if obstacle.name in self._obstacles:
            raise CosmosError(f"obstacle '{obstacle.name}' is already in the scene; remove it first")
        self._obstacles[obstacle.name] = obstacle
        self._geometry, self._acting, self._influences = None, {}, ()
        self._evaluated_s = -np.inf

    def remove(self, name: str) -> None:
        """Stop repelling from the obstacle ``name``.

        Raises:
            CosmosError: If there is no obstacle of that name.
        """
        if self._obstacles.pop(name, None) is None:
            present = ", ".join(self._obstacles) or "none"
            raise CosmosError(f"no obstacle '{name}' in the scene (present: {present})")
        self._geometry, self._acting, self._influences = None, {}, ()
        self._evaluated_s = -np.inf

    def torque(self, q: FloatArray, qd: FloatArray, t_s: float) -> FloatArray:
        """Joint torques of the field at ``(q, qd)`` and simulated time ``t_s``, in [N m]. # (6,)."""
        if t_s - self._evaluated_s < self.parameters.period_s - 1e-9:
            return self._torque
        self._evaluated_s = t_s
        torque = self._torque = np.zeros(6)
        if not self._obstacles:
            self._acting, self._influences = {}, None
            return torque
        geometry = self._geometry
        if geometry is None:
            default = self.parameters.influence_m
            influence = [default if o.influence_m is None else o.influence_m for o in self.obstacles]
            geometry = self._geometry = ProximityModel(self._capsules, self.obstacles, influence)
            self._evaluations = 0
            self._obstacle_speed = max(float(np.linalg.norm(o.velocity_world_mps)) for o in self.obstacles)
        model, data = self._model, self._data
        pin.computeJointJacobians(model, data, q)
        jacobian = data.J  # (6, 6) world: spatial velocity of joint k's body at the origin
        columns = jacobian.T.tolist()  # row j: joint j's spatial axis at the origin
        rates = qd.tolist()
        twists = np.cumsum(jacobian * qd, axis=1).T.tolist()  # row k: twist of joint k's body
        # |velocity| of any arm point <= sum |qd_j| * (its distance to axis j) <= sum |qd_j| reach_j.
        speed = sum([abs(rate) * reach for rate, reach in zip(rates, self._reach, strict=True)])
        speed += self._obstacle_speed
        self._speed_bound = max(self._speed_bound, speed)
        if self._evaluations % self.parameters.geometry_every == 0:
            placements = np.array([data.oMi[i].homogeneous for i in range(1, 7)])  # (6, 4, 4)
            near = geometry.measure(placements[:, :3, :3], placements[:, :3, 3], t_s, self._speed_bound)
            self._speed_bound = speed
        else:
            near = geometry.estimate(twists, t_s)
        self._evaluations += 1
        if not near:
            self._acting, self._influences = {}, None
            return torque
        wrenches = [[0.0] * 6 for _ in range(6)]  # row k: wrench about the origin on link k
        acting: dict[int, list] = {}  # obstacle -> [distance, link, strongest force]
        obstacles, influence, velocities = geometry.obstacles, geometry.influence_m, geometry.velocities
        par = self.parameters
        for k, j, distance, (px, py, pz), (nx, ny, nz) in near:
            vx, vy, vz, wx, wy, wz = twists[k]
            ux, uy, uz = velocities[j]
            # The point's velocity v + w x p relative to the obstacle, along -n: > 0 when closing in.
            approach = -(
                nx * (vx + wy * pz - wz * py - ux)
                + ny * (vy + wz * px - wx * pz - uy)
                + nz * (vz + wx * py - wy * px - uz)
            )
            scale = obstacles[j].gain_scale
            magnitude = repulsion_magnitude(
                distance,
                influence[j],
                scale * par.eta,
                scale * par.damping_ns_per_m,
                par.force_cap_n,
                approach,
            )
            fx, fy, fz = magnitude * nx, magnitude * ny, magnitude * nz
            w = wrenches[k]
            w[0] += fx
            w[1] += fy
            w[2] += fz
            w[3] += py * fz - pz * fy
            w[4] += pz * fx - px * fz
            w[5] += px * fy - py * fx
            seen = acting.setdefault(j, [distance, k, magnitude])
            if distance < seen[0]:
                seen[0], seen[1] = distance, k
            seen[2] = max(seen[2], magnitude)
        self._acting, self._influences = acting, None
        if not self.enabled:
            return torque
        # Gamma_j = J_j . (sum of the wrenches on links k >= j): joint j carries the links beyond it.
        carried = [0.0] * 6
        for j in range(5, -1, -1):
            carried = [c + w for c, w in zip(carried, wrenches[j], strict=True)]
            torque[j] = sum([a * c for a, c in zip(columns[j], carried, strict=True)])
        return torque


def repulsion_magnitude(
    distance_m: float, rho_0_m: float, eta: float, damping_ns_per_m: float, cap_n: float, approach_mps: float
) -> float:
    """|F| of the field on one link's point: FIRAS plus approach damping, capped, in [N].

    Args:
        distance_m: rho, the point's distance to the obstacle's surface, in [m].
        rho_0_m: Influence distance, in [m].
        eta: FIRAS gain, in [N m^3].
        damping_ns_per_m: c, in [N s/m].
        cap_n: Largest magnitude, in [N].
        approach_mps: Speed of the point toward the obstacle along the normal, in [m/s].

    Returns:
        ``eta (1/rho - 1/rho_0)/rho^2 + c (1 - rho/rho_0) max(0, approach)``, capped;
        0 at and beyond rho_0.
    """
    if distance_m >= rho_0_m:
        return 0.0
    magnitude = firas_magnitude(distance_m, rho_0_m, eta, cap_n)
    if approach_mps > 0.0:
        magnitude += damping_ns_per_m * min(1.0, 1.0 - distance_m / rho_0_m) * approach_mps
    return min(magnitude, cap_n)
