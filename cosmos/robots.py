"""The arms cosmos drives: where each one's model is and what it can do at the tool.

A :class:`Robot` is a description, not a model: paths to the MJCF files (the bare arm,
from which the controller's Pinocchio model is built, and the workcell scene the
plant simulates), the joints' names, and the capabilities the checker holds
programs to. Everything else (home, joint ranges, drive limits, the tool) is read
from the model files by :mod:`cosmos.workcell` and :mod:`cosmos.robot_model`.

Both arms stand in the same workcell and carry the same tool and wrist sensor; the
PUMA 560 is the default, the Panda is chosen by ``ROBOT panda`` as a program's first
statement or ``cosmos run --robot panda``. Like :mod:`cosmos.capabilities` this
module sits below the language (it imports no simulator).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from cosmos.capabilities import ARM_CAPABILITY, ArmCapability
from cosmos.errors import CosmosError

MODELS_DIR = Path(__file__).resolve().parent / "models"


@dataclass(frozen=True)
class Robot:
    """One arm of the workcell.

    Attributes:
        name: Its name in programs and on the command line (``ROBOT panda``, ``--robot panda``).
        title: Its name in messages (``Franka Emika Panda``).
        source: What its model was derived from, for the run log.
        model_dir: Directory of its model files (``README.md`` there says where every number
            comes from).
        arm_xml: The bare arm (no tool): the controller's model is built from it.
        scene_xml: The workcell with this arm, its tool and wrist sensor: the plant.
        joint_names: Hinge joints (and their motors, same names) in the order of q; link
            ``k`` is body ``link<k>``, turned by joint ``k``.
        shoulder_m: A point of the shoulder from which the reach is measured, world [m]. # (3,)
        capability: What the arm can do at the tool; ``reach_m`` is the largest distance
            from ``shoulder_m`` to the flange origin.
        wrist_joint: Index in q of the joint whose zero aligns the wrist's first and last
            axes (a spherical wrist's singularity), or None if the wrist has none.
        coulomb_by_direction_nm: Published joint-side Coulomb friction by the direction the
            joint turns, ``(|G| Tc+, |G| |Tc-|)`` per joint [N m], or None where only the
            model file's symmetric ``frictionloss`` is known. The controller compensates it
            by direction; the model file holds the two directions' mean.
        joint_speed_limits_rad_s: Each joint's published speed limit [rad/s] (the model dir's
            README.md says where from). The goal motion keeps the joints within
            :data:`cosmos.osc.joint_speed.JOINT_SPEED_FRACTION` of them, and a joint beyond them
            is a protective stop (:mod:`cosmos.execution.joint_speed_watch`). # (n,)
        encoder_counts_per_degree: The joints' position encoders, counts per joint degree,
            which the realistic plant rounds the angles to (:mod:`cosmos.realism.encoders`);
            None: read exactly.
    """

    name: str
    title: str
    source: str
    model_dir: Path
    arm_xml: Path
    scene_xml: Path
    joint_names: tuple[str, ...]
    shoulder_m: tuple[float, float, float]
    capability: ArmCapability
    wrist_joint: int | None
    joint_speed_limits_rad_s: tuple[float, ...]
    coulomb_by_direction_nm: tuple[tuple[float, float], ...] | None = None
    encoder_counts_per_degree: tuple[float, ...] | None = None

    @property
    def dof(self) -> int:
        """The number of joints n."""
        return len(self.joint_names)

    @property
    def link_bodies(self) -> tuple[str, ...]:
        """Bodies of the arm's links in the scene, ``link1`` .. ``link<n>``."""
        return tuple(f"link{k}" for k in range(1, self.dof + 1))

    @property
    def frames(self) -> tuple[str, ...]:
        """The bodies whose poses the run log publishes on ``/tf``: the links, then the tool."""
        return (*self.link_bodies, "tool")


PUMA560_COULOMB_NM = (
    (24.7314, 27.2358),
    (13.5847, 7.65487),
    (7.08923, 5.63916),
    (0.851608, 1.28502),
    (0.666007, 1.04288),
    (0.303677, 0.805203),
)
"""Joint-side Coulomb friction of the PUMA 560 [N m]: ``(|G| Tc+, |G| |Tc-|)`` per joint.

From the drive table (``shared/reference/puma560.md``): ``Tc+`` acts while the joint
turns positively, ``Tc-`` negatively, whatever the gear's sign (Corke's Robotics Toolbox,
``Link.friction``: "depends on the sign of the joint velocity, not the motor velocity").
"""

PUMA560_COUNTS_PER_DEGREE = (173.92, 239.59, 149.18, 211.21, 199.79, 106.51)
"""Encoder counts per joint degree of the PUMA 560, joints 1-6: the Unimation controller's
conversion factors (posted with the PUMA's servo interface on comp.robotics, "Puma 560
encoders->degrees", 4 Oct 1990); 1000, 800, 1000, 1000, 1000 and 500 counts per motor
revolution through the published gear ratios (:mod:`cosmos.realism.encoders`)."""

PUMA560_SPEED_LIMITS_RAD_S = (8.0, 10.0, 10.0, 5.0, 5.0, 5.0)
"""Joint speed limits of the PUMA 560 [rad/s], joints 1-6: the drives' limits commonly used in
teaching models (``shared/reference/puma560.md``)."""

PUMA560 = Robot(
    name="puma560",
    model_dir=MODELS_DIR / "puma560",
    arm_xml=MODELS_DIR / "puma560" / "puma560.xml",
    scene_xml=MODELS_DIR / "puma560" / "scene.xml",
    title="PUMA 560",
    source="PUMA 560 (Corke & Armstrong-Helouvry 1994) in the cosmos workcell",
    joint_names=tuple(f"joint{k}" for k in range(1, 7)),
    shoulder_m=(0.0, 0.0, 0.67183),  # DH d1: joint 2's axis crosses joint 1's there
    capability=ARM_CAPABILITY,
    wrist_joint=4,  # joint 5: at zero joints 4 and 6 are aligned
    joint_speed_limits_rad_s=PUMA560_SPEED_LIMITS_RAD_S,
    coulomb_by_direction_nm=PUMA560_COULOMB_NM,
    encoder_counts_per_degree=PUMA560_COUNTS_PER_DEGREE,
)

PANDA_CAPABILITY = ArmCapability(
    # Franka's datasheet: the tool flange's top speed is 1.7 m/s, its rotation 2.5 rad/s, and
    # 13 m/s^2 / 25 rad/s^2 its accelerations; the drives' 12 N m on joints 5-7 bound what the
    # cosmos tool (0.65 kg, 0.2 m out) may be asked, so the same margins as the PUMA's are kept.
    tool_speed_mps=1.0,
    tool_acceleration_mps2=5.0,
    angular_speed_rad_s=2.5,
    angular_acceleration_rad_s2=20.0,
    # The servo's gains are those of the PUMA (unit-mass gains, 1 kHz): the same bounds.
    stiffness_n_per_m=ARM_CAPABILITY.stiffness_n_per_m,
    stiffness_nm_per_rad=ARM_CAPABILITY.stiffness_nm_per_rad,
    damping_ns_per_m=ARM_CAPABILITY.damping_ns_per_m,
    damping_nms_per_rad=ARM_CAPABILITY.damping_nms_per_rad,
    # Franka's datasheet: reach 855 mm. From joint 2's axis to the flange: upper arm
    # hypot(0.316, 0.0825), forearm hypot(0.384, 0.0825), wrist hypot(0.088, 0.107): 858 mm.
    reach_m=0.855,
)
"""The Panda's capabilities at the tool (the checker refuses requests beyond them)."""

PANDA_COUNTS_PER_DEGREE = (2**19 / 360.0,) * 7
"""Encoder counts per joint degree of the Panda: assumed. Franka publishes no encoder
resolution; the joints' angles are measured on the link side, taken here as a 19-bit absolute
encoder per joint (2^19 counts a turn, 1.2e-5 rad a count, a common grade for the class), so
8 times finer than the PUMA's joint 2."""

PANDA_SPEED_LIMITS_RAD_S = (2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61)
"""Joint speed limits of the Panda [rad/s], joints 1-7: Franka's datasheet (Franka Control
Interface documentation, "Robot and interface specifications"), the URDF's ``velocity``."""

PANDA = Robot(
    name="panda",
    model_dir=MODELS_DIR / "panda",
    arm_xml=MODELS_DIR / "panda" / "panda.xml",
    scene_xml=MODELS_DIR / "panda" / "scene.xml",
    title="Franka Emika Panda",
    source="Franka Emika Panda (franka_description URDF via example-robot-data 6.0.0) in the cosmos workcell",
    joint_names=tuple(f"joint{k}" for k in range(1, 8)),
    shoulder_m=(0.0, 0.0, 0.533),  # joint 2's axis: URDF joint 1 at 0.333 m on the 0.2 m pedestal
    capability=PANDA_CAPABILITY,
    wrist_joint=None,  # joints 5 and 7 are offset (0.088 m): no spherical wrist
    joint_speed_limits_rad_s=PANDA_SPEED_LIMITS_RAD_S,
    encoder_counts_per_degree=PANDA_COUNTS_PER_DEGREE,
)

ROBOTS: dict[str, Robot] = {robot.name: robot for robot in (PUMA560, PANDA)}
"""The arms by name."""

DEFAULT_ROBOT = PUMA560
"""The arm of a program that names none."""


def robot_named(name: str) -> Robot:
    """The arm called ``name`` (case-insensitive).

    Raises:
        CosmosError: If there is no such arm; the message names the arms there are.
    """
    robot = ROBOTS.get(name.lower())
    if robot is None:
        raise CosmosError(f"no robot '{name}': the workcell has {', '.join(ROBOTS)}")
    return robot
