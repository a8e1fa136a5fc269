"""From the wrist sensor's reading to the wrench the tool applies to the environment.

The force/torque sensor sits between the flange and the tool. Quasi-statically
the tool is in equilibrium under the sensor's wrench, its weight and the
contact wrench, so the wrench the tool applies to the environment, at the tool
point and in world axes, is::

    F_env = f_s + m g                       (f_s: force the flange exerts on the tool)
    M_env = m_s - r_tool x F_env + r_com x m g

where ``r_tool`` and ``r_com`` run from the sensor origin to the tool point and
to the tool's centre of mass. The tool's own weight is so compensated
(issue 3, item 3); its inertial forces are not (they are small at the speeds
of contact tasks).
"""

from __future__ import annotations

import numpy as np

from cosmos.robot_model import GRAVITY

FloatArray = np.ndarray


def environment_wrench(
    flange_on_tool_sensor: FloatArray,
    rotation_sensor_to_world: FloatArray,
    sensor_to_tool_m: FloatArray,
    sensor_to_com_m: FloatArray,
    tool_mass_kg: float,
) -> FloatArray:
    """The wrench the tool applies to the environment, at the tool point, world axes.

    Args:
        flange_on_tool_sensor: Force [N] then moment [N m] the flange exerts on the
            tool, about the sensor origin, in the sensor frame. # (6,)
        rotation_sensor_to_world: Sensor orientation. # (3, 3)
        sensor_to_tool_m: Tool point minus sensor origin, world axes, in [m]. # (3,)
        sensor_to_com_m: Tool centre of mass minus sensor origin, world axes, in [m]. # (3,)
        tool_mass_kg: Mass of everything below the sensor, in [kg].

    Returns:
        Force [N] then moment [N m] applied to the environment, world axes. # (6,)
    """
    (r00, r01, r02), (r10, r11, r12), (r20, r21, r22) = rotation_sensor_to_world.tolist()
    fx, fy, fz, mx, my, mz = flange_on_tool_sensor.tolist()
    wz = GRAVITY[2] * tool_mass_kg  # the weight is (0, 0, wz)
    ex = r00 * fx + r01 * fy + r02 * fz
    ey = r10 * fx + r11 * fy + r12 * fz
    ez = r20 * fx + r21 * fy + r22 * fz + wz
    sx = r00 * mx + r01 * my + r02 * mz
    sy = r10 * mx + r11 * my + r12 * mz
    sz = r20 * mx + r21 * my + r22 * mz
    tx, ty, tz = sensor_to_tool_m.tolist()
    cx, cy, _ = sensor_to_com_m.tolist()
    # M_env = m_s - r_tool x F_env + r_com x (0, 0, wz)
    return np.array(
        (
            ex,
            ey,
            ez,
            sx - (ty * ez - tz * ey) + cy * wz,
            sy - (tz * ex - tx * ez) - cx * wz,
            sz - (tx * ey - ty * ex),
        )
    )


def reading_error(
    sensed: FloatArray, rotation_sensor_to_world: FloatArray, sensor_to_tool_m: FloatArray
) -> FloatArray:
    """The reading error, sensor axes, behind what :func:`environment_wrench` senses [N, N m]. # (6,).

    :func:`environment_wrench` is affine in the reading (``F = R f_s + m g``, ``M = R m_s - r_t x F
    + r_c x m g``): a reading error ``e`` shows as ``dF = R e_f`` and ``dM = R e_m - r_t x dF``, so the
    error behind a sensed ``(dF, dM)`` is ``e_f = R^T dF``, ``e_m = R^T (dM + r_t x dF)``.

    Args:
        sensed: The wrench sensed where there is none (free air), world axes at the tool point. # (6,)
        rotation_sensor_to_world: The sensor's orientation, R. # (3, 3)
        sensor_to_tool_m: The tool point minus the sensor origin, world axes, r_t [m]. # (3,)
    """
    force, moment = sensed[:3], sensed[3:]
    return np.concatenate(
        (
            rotation_sensor_to_world.T @ force,
            rotation_sensor_to_world.T @ (moment + np.cross(sensor_to_tool_m, force)),
        )
    )
