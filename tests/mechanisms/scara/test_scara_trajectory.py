"""Cubic time laws and the seed's path: boundary conditions, the seed's coefficients, and
velocity/acceleration against finite differences."""

import math

import numpy as np
import pytest

from fivebar_drake.mechanisms.scara import cubic_coefficients, cubic_law, load_params, seed_path


def test_cubic_meets_its_boundary_conditions():
    T = 2.5
    x, v, a = cubic_law(1.0, -3.0, T, np.array([0.0, T]))
    assert x == pytest.approx([1.0, -3.0]) and v == pytest.approx([0.0, 0.0], abs=1e-15)
    # at rest before and after
    x, v, a = cubic_law(1.0, -3.0, T, np.array([-1.0, T + 1.0]))
    assert x == pytest.approx([1.0, -3.0]) and v == pytest.approx([0, 0]) and a == pytest.approx(
        [0, 0])
    # acceleration 6 dx / T^2 at the start, the opposite at the end
    _, _, a = cubic_law(0.0, 1.0, T, np.array([0.0, T]))
    assert a == pytest.approx([6 / T**2, -6 / T**2])


def test_seed_coefficients():
    # eq. 2.48: z(t) = 400 + 75 t^2 - 25 t^3 in the seed's mm (its sign of (z_c - z_0) is
    # the seed's; the law itself goes from 400 to 300: a2 = -75, a3 = +25)
    a0, a1, a2, a3 = cubic_coefficients(400.0, 300.0, 2.0)
    assert (a0, a1, a2, a3) == pytest.approx((400.0, 0.0, -75.0, 25.0))
    # eq. 2.51: phi = 1.178 t^2 - 0.196 t^3 over 4 s for one turn
    _, _, b2, b3 = cubic_coefficients(0.0, 2 * math.pi, 4.0)
    assert b2 == pytest.approx(1.178, abs=5e-4) and b3 == pytest.approx(-0.196, abs=5e-4)


def test_seed_path_points_and_continuity():
    tr = load_params().trajectory
    t = np.array([0.0, 2.0, 4.0, 6.0, 8.0])
    p, v, _ = seed_path(tr, t)
    assert p == pytest.approx(np.array([[0.25, 0.5, 0.4], [0.25, 0.5, 0.3], [0.25, 0.4, 0.3],
                                        [0.25, 0.5, 0.3], [0.25, 0.5, 0.4]]), abs=1e-12)
    assert v[[0, 1, 3, 4]] == pytest.approx(np.zeros((4, 3)), abs=1e-12)
    # halfway round the circle (4 s) at its top speed R * 3 (2 pi) / (2 T) = 0.1178 m/s
    assert np.linalg.norm(v[2]) == pytest.approx(0.05 * 3 * math.pi / 4.0)
    tt = np.linspace(0, 8, 8001)
    p, _, _ = seed_path(tr, tt)
    assert np.abs(np.diff(p, axis=0)).max() < 1e-3
    circle = (tt > 2) & (tt < 6)
    assert np.linalg.norm(p[circle, :2] - [0.25, 0.45], axis=1) == pytest.approx(0.05)


def test_seed_path_derivatives_by_finite_differences():
    tr = load_params().trajectory
    t, h = np.linspace(0.05, 7.95, 300), 1e-6
    t = t[np.min(np.abs(t[:, None] - [2.0, 6.0]), axis=1) > 1e-3]
    p, v, a = seed_path(tr, t)
    pp, vp, _ = seed_path(tr, t + h)
    pm, vm, _ = seed_path(tr, t - h)
    assert v == pytest.approx((pp - pm) / (2 * h), abs=1e-7)
    assert a == pytest.approx((vp - vm) / (2 * h), abs=1e-6)
