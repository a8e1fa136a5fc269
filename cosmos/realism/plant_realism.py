"""One run's realistic plant: its arm error and its sensors, all drawn from the run's seed.

A run's seed (``cosmos run --seed``, a sweep run's noise seed) fixes everything: the
wrist sensor's noise stream uses ``default_rng(seed)`` (:class:`cosmos.plant.SensorNoise`);
the arm error and the sensor's bias come from a second, independent stream,
``default_rng(SeedSequence(seed, spawn_key=(19,)))``. So a log's ``seed``, ``plant`` and
``model_error`` metadata remake the same plant (``cosmos replay --verify``); the drawn
values are in the metadata too (``plant_realism``), for people.
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from cosmos.realism.arm_error import DEFAULT_SCALE, ArmError
from cosmos.realism.encoders import OBSERVER_HZ, encoder_resolution_rad, one_count_speed_rad_s
from cosmos.realism.wrist_sensor import CUTOFF_HZ, drawn_bias
from cosmos.robots import Robot

REALISM_STREAM = 19
"""The spawn key of the arm error's random stream (the issue that asked for it)."""

IDEAL, REALISTIC = "ideal", "realistic"
"""Values of the log's ``plant`` metadata."""

Wrench = tuple[float, float, float, float, float, float]


@dataclass(frozen=True)
class PlantRealism:
    """How one run's plant differs from the controller's model, and how it is sensed.

    Attributes:
        seed: The run's seed it was drawn from.
        model_error: The model-error scale ``s`` (:mod:`cosmos.realism.arm_error`).
        arm: The arm's drawn parameters.
        encoder_resolution_rad: One encoder count per joint [rad]. # (n,)
        observer_hz: Bandwidth of the velocity observer [Hz].
        wrist_cutoff_hz: Cut-off of the wrist sensor's low-pass [Hz].
        wrist_bias: The wrist sensor's drawn bias, force then torque, sensor axes [N, N m].
    """

    seed: int
    model_error: float
    arm: ArmError
    encoder_resolution_rad: tuple[float, ...]
    observer_hz: float
    wrist_cutoff_hz: float
    wrist_bias: Wrench

    @classmethod
    def drawn(cls, seed: int, robot: Robot, model_error: float = DEFAULT_SCALE) -> PlantRealism:
        """The realistic plant of a run of ``robot`` with this seed (module docstring).

        Its published friction by direction and its encoders come from ``robot``
        (:class:`cosmos.robots.Robot`).

        Raises:
            ValueError: If ``model_error`` is negative or not finite.
        """
        if not (np.isfinite(model_error) and model_error >= 0.0):
            raise ValueError(f"model_error must be a finite number >= 0; got {model_error!r}")
        rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(REALISM_STREAM,)))
        arm = ArmError.drawn(rng, model_error, robot)
        bias = drawn_bias(rng)
        return cls(
            seed=seed,
            model_error=float(model_error),
            arm=arm,
            encoder_resolution_rad=tuple(float(r) for r in encoder_resolution_rad(robot)),
            observer_hz=OBSERVER_HZ,
            wrist_cutoff_hz=CUTOFF_HZ,
            wrist_bias=bias,
        )

    def one_count_speed_rad_s(self, dt_s: float) -> np.ndarray:
        """The velocity observer's largest answer to one count's rounding [rad/s]. # (n,).

        Stepped every ``dt_s`` (:func:`cosmos.realism.encoders.one_count_speed_rad_s`).
        """
        omega = 2.0 * np.pi * self.observer_hz
        return one_count_speed_rad_s(omega, dt_s, np.asarray(self.encoder_resolution_rad))

    def metadata(self) -> dict[str, str]:
        """The log's metadata of this plant: what remakes it and, for people, what was drawn."""
        drawn = self.arm.summary() | {
            "encoder_resolution_rad": list(self.encoder_resolution_rad),
            "observer_hz": self.observer_hz,
            "wrist_cutoff_hz": self.wrist_cutoff_hz,
            "wrist_bias": list(self.wrist_bias),
        }
        return {
            "plant": REALISTIC,
            "model_error": repr(self.model_error),
            "plant_realism": json.dumps(drawn, separators=(",", ":")),
        }


def ideal_metadata() -> dict[str, str]:
    """The log's metadata of the ideal plant (``--ideal``)."""
    return {"plant": IDEAL}
