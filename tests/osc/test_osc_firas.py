"""FIRAS force vs its potential, and capsule proximity vs brute-force sampling."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cosmos.osc.firas import (
    capsule_box,
    capsule_cylinder,
    capsule_plane,
    capsule_sphere,
    firas_magnitude,
    firas_potential,
)
from cosmos.osc.orientation import so3_exp

SAMPLES = np.linspace(0.0, 1.0, 20001)[:, None]  # segment parameter, 1e-5 of its length apart


def test_firas_force_is_the_negative_gradient_of_the_potential():
    rho_0, eta = 0.1, 2e-4
    rho = np.linspace(0.005, 0.15, 300)
    h = 1e-8
    gradient = (firas_potential(rho + h, rho_0, eta) - firas_potential(rho - h, rho_0, eta)) / (2 * h)
    np.testing.assert_allclose(firas_magnitude(rho, rho_0, eta, np.inf), -gradient, rtol=1e-5, atol=1e-9)
    assert np.all(firas_magnitude(rho[rho >= rho_0], rho_0, eta, np.inf) == 0.0)


def test_firas_force_is_capped_near_and_inside_the_surface():
    f = firas_magnitude(np.array([-0.01, 0.0, 1e-6, 0.05]), 0.1, 2e-4, 50.0)
    np.testing.assert_allclose(f[:3], 50.0)
    assert f[3] == pytest.approx(2e-4 * (20 - 10) / 0.05**2)  # below the cap: the plain formula


def brute(a, b, point_distance):
    """Min over dense segment samples of an exact point-to-solid distance (vectorised)."""
    points = a + SAMPLES * (b - a)
    d = point_distance(points)
    return d.min()


def check(prox, a, b, radius, point_distance):
    expected = brute(a, b, point_distance) - radius
    assert prox.distance == pytest.approx(expected, abs=2e-5)
    assert np.linalg.norm(prox.normal) == pytest.approx(1.0)
    # The returned point is on the capsule surface, and stepping back along the normal by the
    # distance lands on the obstacle surface.
    seg_point = prox.point + radius * prox.normal
    t = np.clip((seg_point - a) @ (b - a) / ((b - a) @ (b - a)), 0, 1)
    assert np.linalg.norm(a + t * (b - a) - seg_point) < 1e-9
    on_obstacle = prox.point - prox.distance * prox.normal
    assert point_distance(on_obstacle[None, :])[0] < 1e-4


def random_segment(rng, scale=0.6):
    return rng.uniform(-scale, scale, 3), rng.uniform(-scale, scale, 3)


def test_capsule_sphere_matches_brute_force(rng):
    c, r_s = np.array([0.1, 0.0, 0.2]), 0.1
    done = 0
    while done < 50:
        a, b = random_segment(rng)
        prox = capsule_sphere(a, b, 0.03, c, r_s)
        if prox.distance <= 0:
            continue
        check(prox, a, b, 0.03, lambda p: np.linalg.norm(p - c, axis=1) - r_s)
        done += 1


def test_capsule_plane_matches_brute_force(rng):
    point, normal = np.array([0.0, 0.0, -0.7]), np.array([0.1, -0.2, 1.0])
    unit = normal / np.linalg.norm(normal)
    for _ in range(50):
        a, b = random_segment(rng)
        prox = capsule_plane(a, b, 0.02, point, normal)
        check(prox, a, b, 0.02, lambda p: (p - point) @ unit)
        np.testing.assert_allclose(prox.normal, unit)


def cylinder_distance(base, radius, height):
    def distance(p):
        rel = p - base
        radial = np.linalg.norm(rel[:, :2], axis=1) - radius
        axial = (
            np.abs(rel[:, 2] - height / 2) - height / 2 if np.isfinite(height) else np.full(len(p), -np.inf)
        )
        outside = np.hypot(np.maximum(radial, 0), np.maximum(axial, 0))
        return outside + np.minimum(np.maximum(radial, axial), 0)

    return distance


@pytest.mark.parametrize("height", [0.5, math.inf])
def test_capsule_cylinder_matches_brute_force(rng, height):
    base, radius = np.array([0.1, -0.05, -0.2]), 0.08
    distance = cylinder_distance(base, radius, height)
    done = 0
    while done < 60:
        a, b = random_segment(rng)
        prox = capsule_cylinder(a, b, 0.03, base, radius, height)
        if prox.distance <= 0:
            continue
        check(prox, a, b, 0.03, distance)
        done += 1


def box_distance(center, rotation, half):
    def distance(p):
        local = (p - center) @ rotation
        q = np.abs(local) - half
        return np.linalg.norm(np.maximum(q, 0), axis=1) + np.minimum(q.max(axis=1), 0)

    return distance


def test_capsule_box_matches_brute_force(rng):
    done = 0
    while done < 60:
        center = rng.uniform(-0.1, 0.1, 3)
        rotation = so3_exp(rng.normal(size=3))
        half = rng.uniform(0.02, 0.3, 3)
        a, b = random_segment(rng)
        prox = capsule_box(a, b, 0.02, center, rotation, half)
        if prox.distance <= 0:
            continue
        check(prox, a, b, 0.02, box_distance(center, rotation, half))
        done += 1


def test_penetration_gives_a_negative_distance_and_an_outward_normal():
    a, b = np.array([-1.0, 0.0, 0.05]), np.array([1.0, 0.0, 0.05])
    # The segment passes 0.05 above a box's centre, inside it (half height 0.1): deepest point is
    # 0.05 below the top face, so the distance is -(0.05 + capsule radius) and the normal is +z.
    prox = capsule_box(a, b, 0.01, np.zeros(3), np.eye(3), np.array([0.2, 0.2, 0.1]))
    assert prox.distance == pytest.approx(-0.06, abs=1e-6)
    np.testing.assert_allclose(prox.normal, [0, 0, 1], atol=1e-12)
    prox = capsule_sphere(a, b, 0.01, np.zeros(3), 0.1)
    assert prox.distance == pytest.approx(0.05 - 0.1 - 0.01)
    np.testing.assert_allclose(prox.normal, [0, 0, 1], atol=1e-12)
    prox = capsule_cylinder(a, b, 0.01, np.array([0.0, 0.0, -1.0]), 0.1, 2.0)
    assert prox.distance < 0
    prox = capsule_plane(a, b, 0.01, np.array([0, 0, 0.1]), np.array([0, 0, 1.0]))
    assert prox.distance == pytest.approx(-0.06)


def test_firas_scalar_and_array_forms_agree():
    rho = np.array([-0.01, 0.0, 1e-4, 0.03, 0.0999, 0.1, 0.2])
    array = firas_magnitude(rho, 0.1, 2e-4, 50.0)
    scalar = [firas_magnitude(float(r), 0.1, 2e-4, 50.0) for r in rho]
    np.testing.assert_allclose(scalar, array, rtol=1e-15)
