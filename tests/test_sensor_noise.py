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


def test_live_signals_take_the_noise_rows_that_readings_take() -> None:
    # The servo loop reads the sensor as live.wrench_raw + live.noise[next_noise_row()]; over
    # more than one block of noise (1024 rows, redrawn in place) and mixed with ordinary
    # readings, it must see what read_wrench_sensor would have returned (a stale block or a
    # skipped or repeated row fails).
    reference, plant = Plant(sensor_noise=SensorNoise(5)), Plant(sensor_noise=SensorNoise(5))
    live = plant.live_signals()
    for i in range(2500):
        expected = reference.read_wrench_sensor()
        if i % 7 == 0:
            np.testing.assert_array_equal(plant.read_wrench_sensor(), expected)
        else:
            np.testing.assert_array_equal(live.wrench_raw + live.noise[plant.next_noise_row()], expected)
    quiet = Plant().live_signals()
    np.testing.assert_array_equal(quiet.noise, np.zeros((1, 6)))
