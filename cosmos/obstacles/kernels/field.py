"""The obstacle field's per-evaluation arithmetic, compiled (numba): arm kinematics and the torques.

The maths are those of :class:`cosmos.obstacles.field.ObstacleField` (seed
section 6, FIRAS on each link's point closest to an obstacle, through that
point's Jacobian). In Pinocchio and NumPy the joint frames, the Jacobian and
the links' twists were a dozen small calls and copies per evaluation, and the
force on each (link, obstacle) pair a Python loop; compiled they are two calls.
``tests/obstacles/test_obstacles_field_kernel.py`` checks them against
Pinocchio (kinematics, point Jacobians) and :func:`cosmos.osc.firas.repulsion_magnitude`.

Arrays are written in place, so an evaluation allocates nothing here.
"""

from __future__ import annotations

import math

import numpy as np

from cosmos.jit import kernel

FloatArray = np.ndarray

# ``chain`` (n, CHAIN): per joint k of the arm's n, its fixed placement in joint k-1's frame
# (rotation row-major, translation), its unit axis in its own frame, and ``reach_k``
# (cosmos.obstacles.capsules.joint_reach_m).
CHAIN_ROTATION, CHAIN_TRANSLATION, CHAIN_AXIS, CHAIN_REACH = 0, 9, 12, 15
CHAIN = 16

# ``frames`` (n, FRAMES): per joint k, world rotation of its frame (row-major), its origin [m], its
# Jacobian column (spatial velocity at the world origin per rad/s, linear then angular, as
# Pinocchio's ``data.J`` in WORLD) and the twist of link k (``sum_{j <= k} J_j qd_j``) [m/s, rad/s].
FRAME_ROTATION, FRAME_ORIGIN, FRAME_COLUMN, FRAME_TWIST = 0, 9, 12, 18
FRAMES = 24

# ``obstacles`` (k, OBSTACLE): per obstacle, its centre when added [m], velocity [m/s], the time it
# was added [s], rho_0 [m] and gain factor.
OBSTACLE_CENTER, OBSTACLE_VELOCITY, OBSTACLE_ADDED_S, OBSTACLE_RHO_0, OBSTACLE_GAIN = 0, 3, 6, 7, 8
OBSTACLE = 9

# ``approaches`` (m, APPROACH): per (link, obstacle) within rho_0: link, obstacle, surface distance
# [m], the link's closest point [m] and the unit normal pointing away from the obstacle, world.
APPROACH_LINK, APPROACH_OBSTACLE, APPROACH_DISTANCE, APPROACH_POINT, APPROACH_NORMAL = 0, 1, 2, 3, 6
APPROACH = 9

# ``parameters`` (PARAMETERS,): eta [N m^3], c [N s/m], the cap [N], 1.0 when the field is enabled.
PARAMETER_ETA, PARAMETER_DAMPING, PARAMETER_CAP, PARAMETER_ENABLED = 0, 1, 2, 3
PARAMETERS = 4

# ``acting`` (k, ACTING): per obstacle, 1.0 when it acted at the evaluation, the nearest link's
# distance [m], that link, and the largest force magnitude it exerted [N].
ACTING_FLAG, ACTING_DISTANCE, ACTING_LINK, ACTING_FORCE = 0, 1, 2, 3
ACTING = 4

# ``nearest`` (NEAREST,): of the approaches of every link but the tool's (the last), the nearest's
# surface distance [m] (inf: none), its link and its obstacle.
NEAREST_DISTANCE, NEAREST_LINK, NEAREST_OBSTACLE = 0, 1, 2
NEAREST = 3


@kernel
def chain_kinematics_into(frames: FloatArray, chain: FloatArray, q: FloatArray, qd: FloatArray) -> float:
    """Joint frames, world Jacobian and link twists of a serial chain of revolute joints.

    ``oMi[k] = oMi[k-1] * placement_k * exp(axis_k q_k)`` (Rodrigues), the
    Jacobian column of joint k is ``(p_k x w_k, w_k)`` with ``w_k = R_k axis_k``
    (its spatial velocity at the world origin), and the twist of link k is
    ``sum_{j <= k} J_j qd_j``: what Pinocchio's ``computeJointJacobians`` and
    ``J qd`` give, written into ``frames``. # (n, FRAMES)

    Returns:
        ``sum_j |qd_j| reach_j``, in [m/s]: a bound on the speed of every point of the arm.
    """
    r = np.eye(3)  # R_{k-1}
    m = np.empty((3, 3))
    px, py, pz = 0.0, 0.0, 0.0
    tw = np.zeros(6)
    speed = 0.0
    for k in range(chain.shape[0]):
        c = chain[k]
        # Origin: p_k = R_{k-1} t_k + p_{k-1}.
        tx, ty, tz = c[CHAIN_TRANSLATION], c[CHAIN_TRANSLATION + 1], c[CHAIN_TRANSLATION + 2]
        px, py, pz = (
            r[0, 0] * tx + r[0, 1] * ty + r[0, 2] * tz + px,
            r[1, 0] * tx + r[1, 1] * ty + r[1, 2] * tz + py,
            r[2, 0] * tx + r[2, 1] * ty + r[2, 2] * tz + pz,
        )
        # M = R_{k-1} R_placement.
        for i in range(3):
            for j in range(3):
                m[i, j] = r[i, 0] * c[j] + r[i, 1] * c[3 + j] + r[i, 2] * c[6 + j]
        # exp(axis q) by Rodrigues: I + sin [a]x + (1 - cos) [a]x^2.
        ax, ay, az = c[CHAIN_AXIS], c[CHAIN_AXIS + 1], c[CHAIN_AXIS + 2]
        s, co = math.sin(q[k]), math.cos(q[k])
        v = 1.0 - co
        e = (
            co + v * ax * ax,
            v * ax * ay - s * az,
            v * ax * az + s * ay,
            v * ax * ay + s * az,
            co + v * ay * ay,
            v * ay * az - s * ax,
            v * ax * az - s * ay,
            v * ay * az + s * ax,
            co + v * az * az,
        )
        out = frames[k]
        for i in range(3):
            for j in range(3):
                r[i, j] = m[i, 0] * e[j] + m[i, 1] * e[3 + j] + m[i, 2] * e[6 + j]
                out[FRAME_ROTATION + 3 * i + j] = r[i, j]
        out[FRAME_ORIGIN], out[FRAME_ORIGIN + 1], out[FRAME_ORIGIN + 2] = px, py, pz
        # Jacobian column: w = R_k axis, v = p x w.
        wx = r[0, 0] * ax + r[0, 1] * ay + r[0, 2] * az
        wy = r[1, 0] * ax + r[1, 1] * ay + r[1, 2] * az
        wz = r[2, 0] * ax + r[2, 1] * ay + r[2, 2] * az
        column = (py * wz - pz * wy, pz * wx - px * wz, px * wy - py * wx, wx, wy, wz)
        rate = qd[k]
        for i in range(6):
            out[FRAME_COLUMN + i] = column[i]
            tw[i] += column[i] * rate
            out[FRAME_TWIST + i] = tw[i]
        speed += abs(rate) * c[CHAIN_REACH]
    return speed


@kernel
def repulsion_magnitude(
    distance_m: float, rho_0_m: float, eta: float, damping_ns_per_m: float, cap_n: float, approach_mps: float
) -> float:
    """:func:`cosmos.osc.firas.repulsion_magnitude`: FIRAS plus approach damping, capped, in [N]."""
    if distance_m >= rho_0_m:
        return 0.0
    if distance_m <= 0.0:
        magnitude = cap_n
    else:
        magnitude = min(eta * (1.0 / distance_m - 1.0 / rho_0_m) / (distance_m * distance_m), cap_n)
    if approach_mps > 0.0:
        magnitude += damping_ns_per_m * min(1.0, 1.0 - distance_m / rho_0_m) * approach_mps
    return min(magnitude, cap_n)


@kernel
def field_torque_into(
    torque: FloatArray,
    link_torque: FloatArray,
    nearest: FloatArray,
    acting: FloatArray,
    approaches: FloatArray,
    count: int,
    frames: FloatArray,
    obstacles: FloatArray,
    parameters: FloatArray,
) -> None:
    """The field's joint torques from the approaches (seed section 6), into ``torque`` (n,).

    Each of the first ``count`` approaches is pushed along its normal by
    :func:`repulsion_magnitude` (the approach speed is the point's velocity
    ``v + w x p`` relative to the obstacle, along ``-n``), the force becomes a
    wrench about the world origin summed per link, and joint j carries the
    links beyond it: ``Gamma_j = J_j . sum_{k >= j} W_k``. ``acting`` records,
    per obstacle, the nearest link and the strongest force (also when the field
    is disabled, when ``torque`` is left at zero). ``link_torque`` receives the part
    of ``torque`` from every link but the tool's (the last: it carries the tool),
    which the servo may project into the task's null space
    (:mod:`cosmos.runtime.null_space`), and ``nearest`` those links' nearest approach.
    """
    tool_link = frames.shape[0] - 1
    nearest[NEAREST_DISTANCE], nearest[NEAREST_LINK], nearest[NEAREST_OBSTACLE] = math.inf, -1.0, -1.0
    eta, damping = parameters[PARAMETER_ETA], parameters[PARAMETER_DAMPING]
    cap = parameters[PARAMETER_CAP]
    n = frames.shape[0]
    wrenches = np.zeros((n, 6))  # row k: wrench about the origin on link k
    acting[:, ACTING_FLAG] = 0.0
    for a in range(count):
        row = approaches[a]
        k, j = int(row[APPROACH_LINK]), int(row[APPROACH_OBSTACLE])
        distance = row[APPROACH_DISTANCE]
        px, py, pz = row[APPROACH_POINT], row[APPROACH_POINT + 1], row[APPROACH_POINT + 2]
        nx, ny, nz = row[APPROACH_NORMAL], row[APPROACH_NORMAL + 1], row[APPROACH_NORMAL + 2]
        f = frames[k]
        vx, vy, vz = f[FRAME_TWIST], f[FRAME_TWIST + 1], f[FRAME_TWIST + 2]
        wx, wy, wz = f[FRAME_TWIST + 3], f[FRAME_TWIST + 4], f[FRAME_TWIST + 5]
        o = obstacles[j]
        ux, uy, uz = o[OBSTACLE_VELOCITY], o[OBSTACLE_VELOCITY + 1], o[OBSTACLE_VELOCITY + 2]
        approach = -(
            nx * (vx + wy * pz - wz * py - ux)
            + ny * (vy + wz * px - wx * pz - uy)
            + nz * (vz + wx * py - wy * px - uz)
        )
        scale = o[OBSTACLE_GAIN]
        magnitude = repulsion_magnitude(
            distance, o[OBSTACLE_RHO_0], scale * eta, scale * damping, cap, approach
        )
        fx, fy, fz = magnitude * nx, magnitude * ny, magnitude * nz
        w = wrenches[k]
        w[0] += fx
        w[1] += fy
        w[2] += fz
        w[3] += py * fz - pz * fy
        w[4] += pz * fx - px * fz
        w[5] += px * fy - py * fx
        if k < tool_link and distance < nearest[NEAREST_DISTANCE]:
            nearest[NEAREST_DISTANCE], nearest[NEAREST_LINK], nearest[NEAREST_OBSTACLE] = distance, k, j
        seen = acting[j]
        if seen[ACTING_FLAG] == 0.0:
            seen[ACTING_FLAG] = 1.0
            seen[ACTING_DISTANCE], seen[ACTING_LINK], seen[ACTING_FORCE] = distance, k, magnitude
        else:
            if distance < seen[ACTING_DISTANCE]:
                seen[ACTING_DISTANCE], seen[ACTING_LINK] = distance, k
            seen[ACTING_FORCE] = max(seen[ACTING_FORCE], magnitude)
    if parameters[PARAMETER_ENABLED] == 0.0:
        return
    carried = np.zeros(6)
    carried_links = np.zeros(6)  # without the tool's link
    for j in range(n - 1, -1, -1):
        total = 0.0
        links = 0.0
        for i in range(6):
            carried[i] += wrenches[j, i]
            if j < tool_link:
                carried_links[i] += wrenches[j, i]
            total += frames[j, FRAME_COLUMN + i] * carried[i]
            links += frames[j, FRAME_COLUMN + i] * carried_links[i]
        torque[j] = total
        link_torque[j] = links
