"""Force capability against a brute-force search over the torque box: the box's boundary mapped
through J_F^-T is the polygon of holdable foot forces; its crossings with the axes and its
nearest point to the origin are found on a dense sampling of the boundary, independently of the
closed forms."""

import numpy as np
import pytest

from fivebar_drake.analysis.force_capability import (CAPABILITY_KEYS, capability_map,
                                                     force_capability, home_capability,
                                                     support_available)
from fivebar_drake.analysis.torques import analyze
from fivebar_drake.mechanisms.fivebar import (ALL_MODES, MODE_NAMES, foot_jacobian, inverse,
                                              sample_gait)

PEAK = 5.0


def box_boundary(peak, n=20001):
    """Torques (4 n, 2) around the boundary of the box |tau_i| <= peak, in order."""
    s = np.linspace(-peak, peak, n)
    full = np.full(n, peak)
    return np.concatenate([np.stack(e, -1) for e in ((full, s), (-s, full), (-full, -s),
                                                     (s, -full))])


def brute_force(jf, peak):
    """Largest vertical and horizontal force and the inscribed radius of the force polygon."""
    forces = np.linalg.solve(jf.T, box_boundary(peak).T).T     # F = J^-T tau
    closed = np.vstack([forces, forces[:1]])
    out = {}
    for key, axis in (("max_vertical_N", 1), ("max_horizontal_N", 0)):
        a, b = closed[:-1], closed[1:]
        other = 1 - axis
        cross = np.sign(a[:, other]) != np.sign(b[:, other])
        t = a[cross, other] / (a[cross, other] - b[cross, other])
        out[key] = float(np.min(np.abs(a[cross, axis] + t * (b[cross, axis] - a[cross, axis]))))
    out["isotropic_N"] = float(np.min(np.linalg.norm(forces, axis=-1)))
    return out


def poses(params):
    home = np.array([params.gait.x_center_m, params.gait.y_home_m])
    yield from ((mode, inverse(params.leg, home, mode)) for mode in ALL_MODES)
    gait = sample_gait(params.leg, params.gait)
    for k in (0, 13, 37):
        yield "gait", inverse(params.leg, gait.foot[k])


def test_capability_matches_brute_force(params):
    for label, pose in poses(params):
        jf = foot_jacobian(params.leg, pose)
        got = force_capability(jf, PEAK)
        want = brute_force(jf, PEAK)
        for key in CAPABILITY_KEYS:
            assert got[key] == pytest.approx(want[key], rel=1e-6), (label, key)


def test_isotropic_is_the_smallest_over_directions(params):
    """peak / max ||column||: check against the largest force along 3600 directions."""
    pose = inverse(params.leg, np.array([0.03, -0.21]), (1, -1))
    jf = foot_jacobian(params.leg, pose)
    angle = np.linspace(0, 2 * np.pi, 3600, endpoint=False)
    u = np.stack([np.cos(angle), np.sin(angle)], -1)
    along = PEAK / np.max(np.abs(u @ jf), axis=-1)
    assert force_capability(jf, PEAK)["isotropic_N"] == pytest.approx(along.min(), rel=1e-5)


def test_support_while_moving_by_search(params, rng):
    gait = sample_gait(params.leg, params.gait)
    jf = foot_jacobian(params.leg, gait.pose)
    spent = rng.uniform(-6, 6, (len(gait.t), 2))     # some beyond the peak: no load is held
    got = support_available(jf, PEAK, spent)
    loads = np.linspace(0, 200, 200001)
    for k in range(0, len(gait.t), 3):
        tau = spent[k] + loads[:, None] * -jf[k, 1, :]      # the foot load's torques per N
        inside = np.all(np.abs(tau) <= PEAK, axis=-1)
        want = loads[inside].max() if inside.any() else 0.0     # upward loads only
        assert got[k] == pytest.approx(want, abs=2e-3), k


def test_home_pose_modes_in_the_analysis(params):
    home = analyze(params).results["force_capability"]
    assert home["home_foot_m"] == [params.gait.x_center_m, params.gait.y_home_m]
    assert list(home["home_pose"]) == ["knees_out", "knees_forward", "knees_back", "knees_in"] \
        == list(MODE_NAMES)
    for mode, name in zip(ALL_MODES, MODE_NAMES):
        jf = foot_jacobian(params.leg, inverse(params.leg, np.array(home["home_foot_m"]), mode))
        want = brute_force(jf, params.motor.peak_torque_Nm)
        for key in CAPABILITY_KEYS:
            assert home["home_pose"][name][key] == pytest.approx(want[key], rel=1e-6)
    ranked = home["support_ranking"]
    vertical = [home["home_pose"][m]["max_vertical_N"] for m in ranked]
    assert vertical == sorted(vertical, reverse=True)
    assert home["most_support_over_next"] == pytest.approx(vertical[0] / vertical[1])


def test_map_and_unreachable_points(params):
    x, y = np.array([0.0, 1.0]), np.array([-0.2])          # the second point is out of reach
    cmap = capability_map(params.leg, PEAK, x, y, (1, 1))
    want = brute_force(foot_jacobian(params.leg, inverse(params.leg, np.array([0.0, -0.2]))),
                       PEAK)
    for key in CAPABILITY_KEYS:
        assert cmap.forces[key].shape == (1, 2)
        assert cmap.forces[key][0, 0] == pytest.approx(want[key], rel=1e-6)
        assert np.isnan(cmap.forces[key][0, 1])
    far = home_capability(params.leg, PEAK, (1.0, -0.2))
    assert far == {name: None for name in MODE_NAMES}
