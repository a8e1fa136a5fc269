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
With the world Jacobian ``J`` (spatial velocities of the joints' bodies at the
world origin, columns 0..k for link k, as Pinocchio's ``data.J``), ``J_p = J_v + J_w x p``
column by column, so ``Gamma = J[:, :k+1]^T (F, p x F)``: the force becomes a
wrench about the world origin, summed per link, and joint j carries the links
beyond it, ``Gamma_j = J_j . sum_{k >= j} W_k``.

Cost: the runtime asks for the field at the parameter rate; it evaluates
itself every ``period_s`` (8 ms) and holds its torque in between. The closest
points come from the controller's own geometric model (:mod:`cosmos.obstacles.geometry`:
candidate lists, closed forms for spheres and planes, MuJoCo's ``mj_geomDistance``
for boxes and cylinders, :mod:`cosmos.osc.firas` where a link touches), measured
every ``geometry_every`` evaluations and estimated to first order in between.
The arithmetic (the arm's kinematics, the bookkeeping of the closest points,
the forces and torques) is compiled: :mod:`cosmos.obstacles.kernels.field` and
:mod:`cosmos.obstacles.kernels.geometry`; :func:`cosmos.osc.firas.repulsion_magnitude` is
the readable reference. docs/obstacles.md has the figures.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
import pinocchio as pin

from cosmos.errors import CosmosError
from cosmos.obstacles.capsules import arm_capsules, joint_reach_m
from cosmos.obstacles.geometry import CANDIDATE_MARGIN_M, ProximityModel
from cosmos.obstacles.kernels import evaluation as ek
from cosmos.obstacles.kernels import field as fk
from cosmos.obstacles.kernels.arrays import ArrayTable
from cosmos.obstacles.obstacle import Obstacle
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
        self._kernel_parameters = np.zeros(fk.PARAMETERS)  # PARAMETER_*
        self.parameters = parameters
        self.enabled = True
        self._capsules = arm_capsules(robot)
        self._chain = chain_table(robot, joint_reach_m(robot, self._capsules))
        self._frames = np.zeros((robot.model.nv, fk.FRAMES))
        self._obstacles: dict[str, Obstacle] = {}
        self._geometry: ProximityModel | None = None
        self._evaluations = 0
        self._evaluated_s = -np.inf
        self._torque = np.zeros(robot.model.nv)
        self._link_torque = np.zeros(robot.model.nv)
        # What the evaluation's kernels write and keep (kernels.evaluation), listed once per geometry.
        self._torque_out, self._link_torque_out = np.zeros(robot.model.nv), np.zeros(robot.model.nv)
        self._scalars = np.zeros(ek.SCALARS)  # SCALAR_*
        self._arrays: ArrayTable | None = None
        self._table = np.zeros(0, dtype=np.int64)
        self._nearest = np.full(fk.NEAREST, np.inf)
        self._acting = np.zeros((0, fk.ACTING))  # per obstacle at the last evaluation (ACTING_*)
        self._influences: tuple[Influence, ...] | None = ()
        self._names: tuple[str, ...] = ()  # the obstacles' names, in the kernels' order
        self._link_names = tuple(f"link{k + 1}" for k in range(robot.model.nv))  # link6 includes the tool

    @property
    def parameters(self) -> FieldParameters:
        """Default rho_0 (taken when the obstacles change), eta, damping and cap."""
        return self._parameters

    @parameters.setter
    def parameters(self, parameters: FieldParameters) -> None:
        self._parameters = parameters
        self._kernel_parameters[: fk.PARAMETER_ENABLED] = (
            parameters.eta,
            parameters.damping_ns_per_m,
            parameters.force_cap_n,
        )

    @property
    def enabled(self) -> bool:
        """When False, :meth:`torque` is zero (the obstacles are still tracked)."""
        return bool(self._kernel_parameters[fk.PARAMETER_ENABLED])

    @enabled.setter
    def enabled(self, enabled: bool) -> None:
        self._kernel_parameters[fk.PARAMETER_ENABLED] = 1.0 if enabled else 0.0

    @property
    def influences(self) -> tuple[Influence, ...]:
        """Obstacles whose field acted at the last evaluation, with their nearest link."""
        if self._influences is None:  # once per evaluation the executor looks at (every 8 ms)
            names, links = self._names, self._link_names
            self._influences = tuple(
                [
                    Influence(names[j], links[int(link)], distance, force)
                    for j, (flag, distance, link, force) in enumerate(self._acting.tolist())
                    if flag
                ]
            )
        return self._influences

    @property
    def link_torque(self) -> FloatArray:
        """The part of the last :meth:`torque` from every link but the tool's, in [N m]. # (6,)."""
        return self._link_torque

    @property
    def nearest_link(self) -> tuple[float, str, str]:
        """Of the links but the tool's, the nearest to an obstacle: distance [m] (inf: none), link, name."""
        distance, link, obstacle = self._nearest.tolist()
        if not math.isfinite(distance) or self._geometry is None:
            return math.inf, "", ""
        return distance, f"link{int(link) + 1}", self._geometry.obstacles[int(obstacle)].name

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
        self._geometry, self._influences = None, ()
        self._evaluated_s = -np.inf

    def remove(self, name: str) -> None:
        """Stop repelling from the obstacle ``name``.

        Raises:
            CosmosError: If there is no obstacle of that name.
        """
        if self._obstacles.pop(name, None) is None:
            present = ", ".join(self._obstacles) or "none"
            raise CosmosError(f"no obstacle '{name}' in the scene (present: {present})")
        self._geometry, self._influences = None, ()
        self._evaluated_s = -np.inf

    def torque(self, q: FloatArray, qd: FloatArray, t_s: float) -> FloatArray:
        """Joint torques of the field at ``(q, qd)`` and simulated time ``t_s``, in [N m]. # (n,)."""
        if t_s - self._evaluated_s < self._parameters.period_s - 1e-9:
            return self._torque
        self._evaluated_s = t_s
        geometry, table = self._geometry, self._table
        if geometry is None:
            if not self._obstacles:
                self._nearest[:] = np.inf
                self._influences = ()
                self._torque, self._link_torque = np.zeros(len(q)), np.zeros(len(q))
                return self._torque
            geometry, table = self._measure_anew()
        measuring = self._evaluations % self._parameters.geometry_every == 0
        self._evaluations += 1
        self._influences = None
        if not measuring:  # one compiled call: kinematics, estimate, torques
            ek.estimated_into(table, q, qd, t_s)
        else:  # kinematics and the queries; MuJoCo's distances; the approaches and the torques
            queued, remotes = ek.select_into(table, q, qd, t_s)
            geometry.query(remotes)
            count, touching = ek.nearest_into(table, queued, t_s)
            if touching:  # firas's distances, points and normals first
                geometry.touching(count, self._frames, t_s)
                ek.torque_into(table, count)
        # New arrays each evaluation: the runtime tells a new evaluation by its torque's identity.
        self._torque, self._link_torque = self._torque_out.copy(), self._link_torque_out.copy()
        return self._torque

    def _measure_anew(self) -> tuple[ProximityModel, np.ndarray]:
        """A proximity model for the obstacles now, and the table of an evaluation's arrays.

        The bound on the arm's speed over the last estimates is kept; the candidates are
        listed again at the next measurement (the next evaluation).
        """
        obstacles = self.obstacles
        geometry = self._geometry = ProximityModel(
            self._capsules, obstacles, obstacle_table(obstacles, self._parameters)
        )
        self._names = tuple(obstacle.name for obstacle in geometry.obstacles)
        self._acting = np.zeros((len(obstacles), fk.ACTING))
        self._evaluations = 0
        scalars = self._scalars
        scalars[ek.SCALAR_TRAVEL], scalars[ek.SCALAR_LAST_S], scalars[ek.SCALAR_COUNT] = 0.0, np.nan, -1.0
        scalars[ek.SCALAR_HELD] = 0.0
        scalars[ek.SCALAR_OBSTACLE_SPEED] = max(
            float(np.linalg.norm(o.velocity_world_mps)) for o in obstacles
        )
        scalars[ek.SCALAR_MARGIN] = CANDIDATE_MARGIN_M
        self._arrays = ArrayTable(
            self._torque_out,
            self._link_torque_out,
            self._nearest,
            self._acting,
            self._frames,
            self._chain,
            self._kernel_parameters,
            *geometry.arrays,
            scalars,
        )
        self._table = self._arrays.entries
        return geometry, self._table


def obstacle_table(obstacles: tuple[Obstacle, ...], parameters: FieldParameters) -> FloatArray:
    """Per obstacle its centre, velocity, time added, rho_0 and gain (``OBSTACLE_*`` of the field kernel).

    Args:
        obstacles: The obstacles, in the order their indices refer to.
        parameters: The field's defaults (rho_0 where an obstacle sets none).

    Returns:
        The packed table. # (k, OBSTACLE)
    """
    table = np.zeros((len(obstacles), fk.OBSTACLE))
    for j, o in enumerate(obstacles):
        table[j, fk.OBSTACLE_CENTER : fk.OBSTACLE_CENTER + 3] = o.position_world
        table[j, fk.OBSTACLE_VELOCITY : fk.OBSTACLE_VELOCITY + 3] = o.velocity_world_mps
        table[j, fk.OBSTACLE_ADDED_S] = o.added_s
        table[j, fk.OBSTACLE_RHO_0] = parameters.influence_m if o.influence_m is None else o.influence_m
        table[j, fk.OBSTACLE_GAIN] = o.gain_scale
    return table


def chain_table(robot: RobotModel, reach_m: FloatArray) -> FloatArray:
    """The arm's kinematic chain for :func:`cosmos.obstacles.kernels.field.chain_kinematics_into`.

    Args:
        robot: The controller's model: n revolute joints in a serial chain.
        reach_m: Per joint, the bound of :func:`cosmos.obstacles.capsules.joint_reach_m`, in [m]. # (n,)

    Returns:
        Per joint its placement in its parent's frame, its axis in its own frame and its reach. # (n, CHAIN)

    Raises:
        CosmosError: If the model is not a serial chain of one-degree-of-freedom joints.
    """
    model = robot.model
    n = model.nv
    serial = list(model.parents) == [0, *range(n)]
    if model.njoints != n + 1 or not serial or model.nq != n:
        raise CosmosError("the obstacle field needs a serial chain of revolute joints")
    data = model.createData()
    pin.computeJointJacobians(model, data, pin.neutral(model))
    chain = np.zeros((n, fk.CHAIN))
    for k in range(n):
        placement = model.jointPlacements[k + 1]
        chain[k, fk.CHAIN_ROTATION : fk.CHAIN_ROTATION + 9] = placement.rotation.reshape(9)
        chain[k, fk.CHAIN_TRANSLATION : fk.CHAIN_TRANSLATION + 3] = placement.translation
        # The joint's axis in its own frame: the angular part of its Jacobian column at q = 0.
        axis = data.oMi[k + 1].rotation.T.dot(data.J[3:, k])
        if abs(float(np.linalg.norm(axis)) - 1.0) > 1e-9:
            raise CosmosError(f"the obstacle field needs revolute joints; joint {k + 1} is not one")
        chain[k, fk.CHAIN_AXIS : fk.CHAIN_AXIS + 3] = axis
        chain[k, fk.CHAIN_REACH] = reach_m[k]
    return chain
