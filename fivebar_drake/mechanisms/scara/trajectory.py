"""Cubic rest-to-rest time laws (seed 002 eq. 2.43-2.46, generic: any coordinate) and the
seed's path built from them (section 2.2.2): A -> B straight, one circle about I starting and
ending at B, B -> A straight."""

from __future__ import annotations

import numpy as np

from fivebar_drake.mechanisms.scara.params import Trajectory


def cubic_coefficients(x0, x1, duration_s) -> tuple:
    """a0..a3 of x(t) = a0 + a1 t + a2 t^2 + a3 t^3 from x0 at rest (t = 0) to x1 at rest
    (t = duration_s) (eq. 2.46): (x0, 0, 3 (x1 - x0) / T^2, -2 (x1 - x0) / T^3)."""
    dx, T = np.asarray(x1, dtype=float) - x0, float(duration_s)
    return np.asarray(x0, dtype=float), 0.0 * dx, 3.0 * dx / T**2, -2.0 * dx / T**3


def cubic_law(x0, x1, duration_s, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position, speed, acceleration of the cubic rest-to-rest law at times t (n,): at rest
    outside [0, T]; x0, x1 scalars (arrays (n,)) or vectors (arrays (n, d))."""
    a0, a1, a2, a3 = cubic_coefficients(x0, x1, duration_s)
    t = np.asarray(t, dtype=float)
    moving = (t >= 0.0) & (t <= duration_s)
    t = np.clip(t, 0.0, duration_s)
    if np.ndim(a0):
        t, moving = t[..., None], moving[..., None]
    return (a0 + a1 * t + a2 * t**2 + a3 * t**3, a1 + 2 * a2 * t + 3 * a3 * t**2,
            np.where(moving, 2 * a2 + 6 * a3 * t, 0.0))


def seed_path(tr: Trajectory, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tool point, velocity, acceleration (n, 3) in m, m/s, m/s^2 along the seed's path at
    times t (s): the lines are cubic in the straight coordinate (eq. 2.49, 2.53), the circle
    x = xI + R sin(phi), y = yI + R cos(phi) with phi cubic from 0 to 2 pi (eq. 2.51-2.52).
    Beyond the end the tool rests at A."""
    t = np.asarray(t, dtype=float)
    a, b, c = (np.asarray(v, dtype=float) for v in (tr.a_m, tr.b_m, tr.center_m))
    t1, t2 = tr.line_s, tr.line_s + tr.circle_s
    p, v, acc = cubic_law(a, b, tr.line_s, t)
    back = cubic_law(b, a, tr.return_s, t - t2)
    phi, w, e = cubic_law(0.0, 2 * np.pi, tr.circle_s, t - t1)
    rot = np.arctan2(b[0] - c[0], b[1] - c[1])              # B's angle from I (0: B above I)
    sn, cs, r = np.sin(phi + rot), np.cos(phi + rot), tr.radius_m
    circle = (np.stack([c[0] + r * sn, c[1] + r * cs, np.full_like(phi, c[2])], axis=-1),
              np.stack([r * cs * w, -r * sn * w, 0 * w], axis=-1),
              np.stack([r * (cs * e - sn * w**2), r * (-sn * e - cs * w**2), 0 * w], axis=-1))
    on_circle, on_back = ((t > t1) & (t <= t2))[:, None], (t > t2)[:, None]
    out = []
    for line, arc, ret in zip((p, v, acc), circle, back):
        out.append(np.where(on_back, ret, np.where(on_circle, arc, line)))
    return tuple(out)
