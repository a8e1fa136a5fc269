"""What the arm is doing, read off the runtime and put in words: pose, force, control mode.

Pure functions of arrays (tested without the simulator) and one snapshot type
taken from a :class:`~cosmos.runtime.loop.Runtime`. Lengths are shown in mm,
angles in degrees, forces in N and moments in N m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from cosmos.runtime.loop import Runtime

FloatArray = np.ndarray

AXIS_NAMES = ("X", "Y", "Z")
_AXIS_TOLERANCE = 1e-6
"""A selection block entry this close to 0 or 1 counts as exactly that."""


def matrix_to_rpy(rotation: FloatArray) -> tuple[float, float, float]:
    """Roll, pitch, yaw [rad] about the fixed world axes (the language's ``RPY``).

    Inverse of ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)``; at pitch = +-90 deg the roll
    is taken as 0 and the whole turn about z goes into the yaw.

    Args:
        rotation: Frame to world rotation, (3, 3).
    """
    r = np.asarray(rotation, dtype=float)
    pitch = math.asin(float(np.clip(-r[2, 0], -1.0, 1.0)))
    if abs(r[2, 0]) > 1.0 - 1e-9:
        return 0.0, pitch, math.atan2(-float(r[0, 1]), float(r[1, 1]))
    roll = math.atan2(float(r[2, 1]), float(r[2, 2]))
    yaw = math.atan2(float(r[1, 0]), float(r[0, 0]))
    return roll, pitch, yaw


def _number(value: float, digits: int) -> str:
    text = f"{value:.{digits}f}"
    return "0" if float(text) == 0.0 else text.rstrip("0").rstrip(".") if "." in text else text


def format_vector(values: FloatArray, scale: float = 1.0, digits: int = 1) -> str:
    """``(a, b, c)`` with each value times ``scale`` to ``digits`` decimals (-0 shown as 0)."""
    return "(" + ", ".join(_number(float(v) * scale, digits) for v in values) + ")"


def format_pose(position_m: FloatArray, rotation: FloatArray | None) -> str:
    """A pose as the language writes it: ``(x, y, z) mm RPY (r, p, y) deg``.

    Args:
        position_m: Position [m], world, (3,).
        rotation: Frame to world, (3, 3), or None for a bare position.
    """
    text = f"{format_vector(position_m, 1000.0)} mm"
    if rotation is not None:
        degrees = np.degrees(matrix_to_rpy(rotation))
        degrees[np.isclose(degrees, -180.0, atol=0.05)] = 180.0  # one way to write a half turn
        text += f" RPY {format_vector(degrees)} deg"
    return text


def force_directions(omega_bar: FloatArray | None) -> list[str]:
    """Names of the force-controlled directions of a world-axes force selection.

    Args:
        omega_bar: The seed's force selection Omega_bar in world axes, (6, 6), or None.

    Returns:
        ``["Z"]``, ``["X", "Y", "RX", "RY"]`` ... for axes aligned with the world;
        a unit vector such as ``"(0.34, 0, -0.94)"`` for a force direction of a
        rotated task frame (rotations get an ``R`` prefix). Empty: every axis is
        under motion control.
    """
    if omega_bar is None:
        return []
    names: list[str] = []
    for block, prefix in ((omega_bar[:3, :3], ""), (omega_bar[3:, 3:], "R")):
        block = np.asarray(block, dtype=float)
        diagonal = np.diag(block)
        aligned = np.allclose(block, np.diag(np.round(diagonal)), atol=_AXIS_TOLERANCE)
        if aligned:
            names += [prefix + AXIS_NAMES[i] for i in range(3) if diagonal[i] > 0.5]
            continue
        values, vectors = np.linalg.eigh((block + block.T) / 2.0)
        for value, vector in zip(values, vectors.T, strict=True):
            if value > 0.5:
                vector = vector if vector[np.argmax(np.abs(vector))] > 0 else -vector
                names.append(prefix + format_vector(vector, digits=2))
    return names


def describe_mode(force_axes: list[str]) -> str:
    """``"position"`` or ``"force Z"``: which axes are force-controlled."""
    return "force " + " ".join(force_axes) if force_axes else "position (all axes)"


@dataclass(frozen=True)
class ArmStatus:
    """A snapshot of the arm as the controller senses it.

    Attributes:
        t_s: Simulated time [s].
        q_rad: Joint angles [rad], (6,).
        position_m: Tool point [m], world, (3,).
        rotation: Tool orientation, tool to world, (3, 3).
        wrench: Force [N] and moment [N m] the tool applies to the environment, world, (6,).
        force_axes: Force-controlled directions (see :func:`force_directions`).
    """

    t_s: float
    q_rad: FloatArray
    position_m: FloatArray
    rotation: FloatArray
    wrench: FloatArray
    force_axes: tuple[str, ...]

    @classmethod
    def of(cls, runtime: Runtime) -> ArmStatus:
        """The runtime's latest sensed state (the tool pose of its last model evaluation)."""
        evaluation = runtime.evaluation
        selection = runtime.servo.selection
        omega_bar = None if selection is None else selection.omega_bar
        return cls(
            t_s=runtime.time_s,
            q_rad=np.array(runtime.q, dtype=float),
            position_m=np.array(evaluation.position, dtype=float),
            rotation=np.array(evaluation.rotation_tool_to_world, dtype=float),
            wrench=np.array(runtime.wrench, dtype=float),
            force_axes=tuple(force_directions(omega_bar)),
        )

    @property
    def force_n(self) -> float:
        """Magnitude of the force [N]."""
        return float(np.linalg.norm(self.wrench[:3]))

    def toolbar(self) -> str:
        """One line: tool pose, sensed force, mode."""
        return (
            f"tool {format_pose(self.position_m, self.rotation)} | "
            f"F {format_vector(self.wrench[:3])} N | {describe_mode(list(self.force_axes))}"
        )

    def lines(self) -> list[str]:
        """The ``:state`` report: joints, tool pose, wrench, mode, time."""
        return [
            f"joints   {format_vector(np.degrees(self.q_rad), digits=2)} deg",
            f"tool     {format_pose(self.position_m, self.rotation)}",
            f"force    {format_vector(self.wrench[:3], digits=2)} N  (|F| = {self.force_n:.2f} N)",
            f"moment   {format_vector(self.wrench[3:], digits=3)} N m",
            f"mode     {describe_mode(list(self.force_axes))}",
            f"time     {self.t_s:.3f} s (simulated)",
        ]
