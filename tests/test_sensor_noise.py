"""The wrist sensor's noise: reproducible from its seed, of the stated size, zero mean."""

from __future__ import annotations

import numpy as np

from cosmos.plant import Plant, SensorNoise


def readings(plant: Plant, n: int) -> np.ndarray:
    return np.array([plant.read_wrench_sensor() for _ in range(n)])


def test_same_seed_same_noise_other_seed_other_noise() -> None:
    a, b, c = (
        Plant(sensor_noise=SensorNoise(7)),
        Plant(sensor_noise=SensorNoise(7)),
        Plant(sensor_noise=SensorNoise(8)),
    )
    first, second, other = readings(a, 50), readings(b, 50), readings(c, 50)
    np.testing.assert_array_equal(first, second)
    assert not np.allclose(first, other)


def test_noise_has_the_stated_spread_around_the_true_reading() -> None:
    noise = SensorNoise(3)
    quiet, noisy = Plant(), Plant(sensor_noise=noise)
    errors = readings(noisy, 4000) - quiet.read_wrench_sensor()  # the same state: no step taken
    # 4000 samples: the sample standard deviation is within 5 % of the true one (about 4.5 sigma),
    # the mean within 4.5 standard errors of zero.
    np.testing.assert_allclose(errors.std(axis=0), noise.std, rtol=0.05)
    assert np.all(np.abs(errors.mean(axis=0)) < 4.5 * noise.std / np.sqrt(4000))
