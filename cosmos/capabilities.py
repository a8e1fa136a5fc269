"""What the workcell can do: the wrist sensor's rating, the arm's capabilities at the tool, home.

Declared numbers, part of the workcell model (:mod:`cosmos.workcell` re-exports
them) but kept here, below the language in the package's layers, because the
checker refuses programs that ask for more (:mod:`cosmos.lang.check.limits`) and the
executor's protective stops use the sensor's rating. Where a number is also in
the MuJoCo scene (the tool's pose at home) a test compares the two.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SensorRating:
    """The wrist force/torque sensor's measuring range (any direction).

    Attributes:
        force_n: Largest force it measures [N].
        torque_nm: Largest moment it measures [N m].
    """

    force_n: float
    torque_nm: float


@dataclass(frozen=True)
class ArmCapability:
    """What the arm with its drives and servo can do at the tool; programs stay within it.

    Attributes:
        tool_speed_mps: Largest tool-point speed [m/s].
        tool_acceleration_mps2: Largest tool-point acceleration a timed move may ask [m/s^2].
        angular_speed_rad_s: Largest tool rotation speed [rad/s].
        angular_acceleration_rad_s2: Largest tool angular acceleration a timed move may ask [rad/s^2].
        stiffness_n_per_m: Largest translational COMPLY stiffness the 1 kHz servo renders [N/m].
        stiffness_nm_per_rad: Largest rotational COMPLY stiffness [N m/rad].
        damping_ns_per_m: Largest translational damping [N s/m].
        damping_nms_per_rad: Largest rotational damping [N m s/rad].
        reach_m: Largest distance from the shoulder (joint 2's axis) to the wrist centre [m].
    """

    tool_speed_mps: float
    tool_acceleration_mps2: float
    angular_speed_rad_s: float
    angular_acceleration_rad_s2: float
    stiffness_n_per_m: float
    stiffness_nm_per_rad: float
    damping_ns_per_m: float
    damping_nms_per_rad: float
    reach_m: float


WRIST_SENSOR = SensorRating(force_n=130.0, torque_nm=10.0)
"""The wrist sensor's rating: a 6-axis sensor of the ATI Gamma class (130 N, 10 N m on
every axis, the smaller of its x-y and z ranges). The largest FORCE a program may ask."""

ARM_CAPABILITY = ArmCapability(
    # The PUMA 560's tool speed is of the order of 1 m/s (Unimation's data sheet gives
    # 0.5 m/s with full payload); the joint speed limits (8, 10, 10, 5, 5, 5) rad/s of
    # the reference bound the rotation at the wrist. Accelerations: what the drives'
    # torque limits leave after gravity for the effective masses of the arm at full
    # reach (about 20 kg along the worst axis, 170 N of spare force), with margin.
    tool_speed_mps=1.0,
    tool_acceleration_mps2=5.0,
    angular_speed_rad_s=3.0,
    angular_acceleration_rad_s2=20.0,
    # Stiffness: the servo's kp = K / lambda stays below (0.3 / dt)^2 at the smallest
    # effective mass (about 1 kg) for a 1 kHz servo; damping likewise kv = D / lambda.
    stiffness_n_per_m=20_000.0,
    stiffness_nm_per_rad=200.0,
    damping_ns_per_m=2_000.0,
    damping_nms_per_rad=20.0,
    # DH: a2 = 0.4318, a3 = 0.0203, d4 = 0.4318, d3 = 0.15005 (shoulder offset).
    reach_m=float(np.hypot(0.15005, 0.4318 + np.hypot(0.0203, 0.4318))),
)
"""The arm's capabilities at the tool (the checker refuses requests beyond them)."""


@dataclass(frozen=True)
class Pose:
    """A tool pose in the world.

    Attributes:
        position: Tool point [m]. # (3,)
        rotation: Tool frame to world. # (3, 3)
    """

    position: tuple[float, float, float]
    rotation: tuple[tuple[float, float, float], ...]


_TOOL_DOWN = ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0))

HOME_TOOLS: dict[tuple[str, str], Pose] = {
    ("puma560", "peg"): Pose((0.5963031486, -0.15005, 0.4574757323), _TOOL_DOWN),
    ("puma560", "gripper"): Pose((0.5963031486, -0.15005, 0.4699757323), _TOOL_DOWN),
    ("panda", "peg"): Pose((0.5963031486, -0.15005, 0.4574757323), _TOOL_DOWN),
    ("panda", "gripper"): Pose((0.5963031486, -0.15005, 0.4120757323), _TOOL_DOWN),
}
"""The tool point at each arm's ``home`` keyframe, by arm and TOOL: 596 mm out, pointing down;
the PUMA's gripper point is 12.5 mm above the peg's tip, the Panda's hand 45.4 mm below
(tests/check/test_home_tools.py reads them from the scenes)."""

HOME_TOOL = HOME_TOOLS[("puma560", "peg")]
"""The PUMA's peg at home (:data:`cosmos.workcell.HOME_TOOL_POSITION` reads it from the scene)."""
