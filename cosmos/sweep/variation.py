"""A varied workcell: the changes one run of a sweep makes to the real (simulated) cell.

A :class:`WorkcellVariation` edits the MuJoCo scene before it is compiled
(:meth:`WorkcellVariation.apply_to_spec`, given to :class:`cosmos.plant.Plant` through
:class:`cosmos.execution.session.Session`) and sets the wrist sensor's bias and noise seed.
The program's view is not changed: its ``hole``, ``table`` and ``slope`` frames stay the
nominal ones of :func:`cosmos.workcell.fixture_frames`, as a real program does not know
that the hole sits 1 mm off. That difference is the uncertainty a sweep measures.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mujoco
import numpy as np

from cosmos.errors import UsageError
from cosmos.plant import SensorNoise
from cosmos.realism.tare import PAYLOAD_GEOM
from cosmos.sweep.parameters import (
    BIAS_AXES,
    FIXTURES,
    MODEL_ERROR,
    PARAMETERS,
    POSE_AXES,
    SEED,
    Kind,
    Vary,
    parse_varies,
)
from cosmos.workcell import TOOL, TOOL_BODY, fixture_frames

FIXTURE_FRAMES = {"hole": "hole_fixture", "table": "table", "slope": "slope_fixture"}
"""The scene's frame that carries each language fixture's geoms and site."""
PAYLOAD_RADIUS_M = 0.005
"""Radius of the (non-colliding) sphere that carries the payload's mass at the tool's centre of mass."""
TOOL_CONTYPE, FIXTURE_CONTYPE = 4, 1
"""Contact types of the tool's and the fixtures' geoms (scene.xml)."""

Pose = tuple[float, float, float, float, float, float]
ZERO_POSE: Pose = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class WorkcellVariation:
    """How one run's real workcell differs from the nominal one.

    Attributes:
        fixtures: Per fixture (``hole``, ``table``, ``slope``) its offset: translation along
            world x, y, z [m], then rotations about world x, y, z [rad] (applied in that
            order) through the fixture frame's nominal origin.
        friction: Sliding friction coefficient of every tool and fixture geom (None: the scene's).
        payload_kg: Mass added to the tool at its centre of mass [kg].
        sensor_bias: Constant offset of the wrist sensor's readings, sensor axes [N, N m].
        noise_seed: Seed of the wrist sensor's noise, and of the realistic plant's drawn arm.
        model_error: The realistic plant's model-error scale (None: its default,
            :mod:`cosmos.realism.arm_error`).
        ideal: The run is on the ideal plant (``--ideal``: no model error, exact sensing).
    """

    fixtures: tuple[tuple[str, Pose], ...] = ()
    friction: float | None = None
    payload_kg: float = 0.0
    sensor_bias: tuple[float, float, float, float, float, float] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    noise_seed: int = 0
    model_error: float | None = None
    ideal: bool = False

    @classmethod
    def from_values(cls, values: Mapping[str, float], ideal: bool = False) -> WorkcellVariation:
        """The variation of a run's drawn values (:func:`cosmos.sweep.parameters.draw`), SI.

        ``ideal``: the run is on the ideal plant.
        """
        unknown = sorted(set(values) - set(PARAMETERS))
        if unknown:
            raise ValueError(f"unknown parameters: {', '.join(unknown)}")
        fixtures = []
        for fixture in FIXTURES:
            pose = tuple(float(values.get(f"{fixture}.{axis}", 0.0)) for axis in POSE_AXES)
            if any(pose):
                fixtures.append((fixture, pose))
        friction = values.get("friction")
        model_error = values.get(MODEL_ERROR)
        return cls(
            fixtures=tuple(fixtures),  # type: ignore[arg-type]
            friction=None if friction is None else float(friction),
            payload_kg=float(values.get("payload", 0.0)),
            sensor_bias=tuple(float(values.get(f"bias.{axis}", 0.0)) for axis in BIAS_AXES),  # type: ignore[arg-type]
            noise_seed=int(values.get(SEED, 0)),
            model_error=None if model_error is None else float(model_error),
            ideal=ideal,
        )

    def sensor_noise(self) -> SensorNoise:
        """The wrist sensor's noise with this run's seed and bias."""
        return SensorNoise(self.noise_seed, bias=self.sensor_bias)

    def apply_to_spec(self, spec: mujoco.MjSpec) -> None:
        """Move the fixtures, set the friction and add the payload in the scene, before compiling."""
        nominal = fixture_frames()
        for fixture, pose in self.fixtures:
            frame = spec.frame(FIXTURE_FRAMES[fixture])
            position, quat = moved_frame(
                np.array(frame.pos), np.array(frame.quat), nominal[fixture].position, pose
            )
            frame.pos, frame.quat = position, quat
        if self.friction is not None:
            for geom in spec.geoms:
                if geom.contype in (TOOL_CONTYPE, FIXTURE_CONTYPE):
                    geom.friction = [self.friction, geom.friction[1], geom.friction[2]]
        if self.payload_kg > 0.0:
            # The tool body's frame is the flange frame (scene.xml), as TOOL's quantities are.
            spec.body(TOOL_BODY).add_geom(
                name=PAYLOAD_GEOM,
                type=mujoco.mjtGeom.mjGEOM_SPHERE,
                size=[PAYLOAD_RADIUS_M, 0.0, 0.0],
                pos=np.asarray(TOOL.com_in_flange),
                mass=self.payload_kg,
                contype=0,
                conaffinity=0,
                group=4,
            )

    def arguments(self) -> str:
        """The ``cosmos run`` options that reproduce this variation (exact SI values)."""
        varies = " ".join(f"--vary '{vary.text()}'" for vary in self.varies())
        return f"--ideal {varies}" if self.ideal else varies

    def varies(self) -> tuple[Vary, ...]:
        """The variation as constants, one per parameter that differs from nominal, and the seed."""
        out = [
            Vary(f"{fixture}.{axis}", Kind.CONSTANT, value)
            for fixture, pose in self.fixtures
            for axis, value in zip(POSE_AXES, pose, strict=True)
            if value
        ]
        if self.friction is not None:
            out.append(Vary("friction", Kind.CONSTANT, self.friction))
        if self.payload_kg:
            out.append(Vary("payload", Kind.CONSTANT, self.payload_kg))
        out += [
            Vary(f"bias.{axis}", Kind.CONSTANT, value)
            for axis, value in zip(BIAS_AXES, self.sensor_bias, strict=True)
            if value
        ]
        if self.model_error is not None:
            out.append(Vary(MODEL_ERROR, Kind.CONSTANT, self.model_error))
        out.append(Vary(SEED, Kind.CONSTANT, float(self.noise_seed)))
        return tuple(out)


def constant_variation(texts: Sequence[str], seed: int, ideal: bool = False) -> WorkcellVariation:
    """The workcell of ``NAME=VALUE`` constants (``cosmos run --vary``, ``cosmos.run(vary=...)``).

    ``seed`` is the noise seed unless ``seed`` is among them.

    Raises:
        UsageError: A text that does not parse, a name given twice, or a distribution.
    """
    varies = parse_varies(texts)
    distributions = [text for text, v in zip(texts, varies, strict=True) if v.kind is not Kind.CONSTANT]
    if distributions:
        raise UsageError(f"--vary {distributions[0]}: cosmos run takes one value, not a distribution")
    values = {v.name: v.a for v in varies}
    values.setdefault(SEED, float(seed))
    return WorkcellVariation.from_values(values, ideal=ideal)


def rotation_world_xyz(rx: float, ry: float, rz: float) -> np.ndarray:
    """``Rz(rz) Ry(ry) Rx(rx)``: turns about world x, then world y, then world z [rad], ``(3, 3)``."""
    cx, sx, cy, sy, cz, sz = np.cos(rx), np.sin(rx), np.cos(ry), np.sin(ry), np.cos(rz), np.sin(rz)
    x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    z = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return z @ y @ x


def moved_frame(
    position: np.ndarray, quat: np.ndarray, origin: np.ndarray, pose: Pose
) -> tuple[np.ndarray, np.ndarray]:
    """A world frame's pose after turning it by ``pose``'s rotation about ``origin``, then shifting it.

    A point ``w`` of the frame goes to ``origin + R_d (w - origin) + d``, so the frame
    ``(R_f, p_f)`` becomes ``(R_d R_f, origin + R_d (p_f - origin) + d)``.

    Args:
        position: The frame's origin in the world [m]. # (3,)
        quat: Its orientation (w, x, y, z). # (4,)
        origin: The point turned about [m], world. # (3,)
        pose: ``(dx, dy, dz, rx, ry, rz)`` [m, rad], world axes.

    Returns:
        The new position # (3,) and quaternion (w, x, y, z) # (4,).
    """
    turn = rotation_world_xyz(*pose[3:])
    frame_rotation = np.empty(9)
    mujoco.mju_quat2Mat(frame_rotation, quat / np.linalg.norm(quat))
    new_rotation = turn @ frame_rotation.reshape(3, 3)
    new_quat = np.empty(4)
    mujoco.mju_mat2Quat(new_quat, new_rotation.ravel())
    new_position = origin + turn @ (position - origin) + np.asarray(pose[:3])
    return new_position, new_quat
