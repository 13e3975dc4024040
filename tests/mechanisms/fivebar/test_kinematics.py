import dataclasses

import numpy as np
import pytest

from fivebar_drake.mechanisms.fivebar import (ALL_MODES, KNEES_OUT, LegGeometry, LegLimits,
                                              UnreachableError, forward, inverse, knee_modes,
                                              reachable, sample_gait)


def workspace_grid(params):
    x, y = np.meshgrid(np.linspace(-0.25, 0.25, 101), np.linspace(-0.32, 0.1, 85))
    grid = np.stack([x, y], -1).reshape(-1, 2)
    return grid


@pytest.mark.parametrize("mode", ALL_MODES)
def test_fk_of_ik_round_trip_on_gait_and_grid(params, mode):
    leg = dataclasses.replace(params.leg, limits=LegLimits())   # the whole geometric reach
    gait = sample_gait(leg, params.gait).foot
    grid = workspace_grid(params)
    targets = np.concatenate([gait, grid[reachable(leg, grid, mode)]])
    assert len(targets) > 2000
    pose = inverse(leg, targets, mode)
    again = forward(leg, pose.q, pose.e_branch)
    assert np.max(np.linalg.norm(again.f - targets, axis=-1)) < 1e-9
    # every joint lands on the same point, and the mode is the one asked for
    assert np.max(np.abs(again.e - pose.e)) < 1e-9
    mode_c, mode_d = knee_modes(leg, pose)
    assert np.all(mode_c == mode[0]) and np.all(mode_d == mode[1])
    # link lengths hold
    for p, r, length in ((leg.a, pose.c, leg.ac_m), (leg.b, pose.d, leg.bd_m),
                         (pose.c, pose.e, leg.ce_m), (pose.d, pose.e, leg.de_m),
                         (pose.e, pose.f, leg.ef_m)):
        assert np.allclose(np.linalg.norm(r - p, axis=-1), length, atol=1e-12)


def test_four_modes_are_distinct(params):
    qs = np.array([inverse(params.leg, [0.01, -0.2], m).q for m in ALL_MODES])
    gaps = np.abs(qs[:, None] - qs[None]).sum(-1) + np.eye(4)
    assert gaps.min() > 1e-3


def test_seed_fk_picks_lower_e_and_matches_gait(params):
    s = sample_gait(params.leg, params.gait)
    assert np.all(s.mode_index == ALL_MODES.index(KNEES_OUT))
    seed = forward(params.leg, s.pose.q)      # the seed's rule: E with the lower y
    assert np.max(np.abs(seed.f - s.foot)) < 1e-12
    other = forward(params.leg, s.pose.q, -seed.e_branch)
    assert np.all(other.e[:, 1] > seed.e[:, 1])
    # foot on the extension of D->E: F = 37/29 E - 8/29 D for the seed's lengths
    assert np.allclose(seed.f, 37 / 29 * seed.e - 8 / 29 * seed.d, atol=1e-15)


def coaxial_leg(l1=0.1, l2=0.2):
    return LegGeometry(motor_a_m=(0.0, 0.0), motor_b_m=(0.0, 0.0), ac_m=l1, bd_m=l1,
                       ce_m=l2, de_m=l2, ef_m=0.0)


def minitaur_length(l1, l2, gamma):
    """Minitaur's leg length r(m) = sqrt(l2^2 - l1^2 sin^2 m) - l1 cos m with m = pi - gamma."""
    m = np.pi - gamma
    return np.sqrt(l2**2 - l1**2 * np.sin(m) ** 2) - l1 * np.cos(m)


def test_coaxial_leg_matches_minitaur_closed_form():
    leg = coaxial_leg()
    gamma = np.linspace(0.05, 2.0, 40)[:, None]
    psi = np.linspace(-np.pi, np.pi, 37)[None, :]
    gamma, psi = np.broadcast_arrays(gamma, psi)
    r = minitaur_length(leg.ac_m, leg.ce_m, gamma)
    foot = np.stack([r * np.cos(psi), r * np.sin(psi)], -1)
    pose = inverse(leg, foot, KNEES_OUT)
    expect = np.stack([psi - gamma, psi + gamma], -1)
    assert np.max(np.abs(np.angle(np.exp(1j * (pose.q - expect))))) < 1e-9
    # FK with the seed's lower-E rule, legs pointing down
    down = np.abs(psi + np.pi / 2) < 0.6
    fk = forward(leg, expect[down])
    assert np.max(np.abs(fk.f - foot[down])) < 1e-12


def test_unreachable_target_names_target_and_reach(params):
    with pytest.raises(UnreachableError) as err:
        inverse(params.leg, [[0.0, -0.2], [0.0, -0.5]])
    text = str(err.value)
    assert "[0.0, -500.0] mm" in text and "|BF| = 501.8" in text
    assert "80.000 .. 290.000 mm" in text and "1 of 2" in text


def test_unreachable_through_motor_a(params):
    # |BF| is fine but E would be out of reach of A
    with pytest.raises(UnreachableError, match=r"\|AE\| = 38.266 mm is outside the reach 40.000 .. 250.000"):
        inverse(params.leg, [-0.1, 0.05])


def test_fk_that_cannot_close_names_angles(params):
    with pytest.raises(UnreachableError, match=r"\[180.0, 0.0\] deg cannot close .*\|CD\| = 295.000 mm"):
        forward(params.leg, [[np.pi, 0.0]])


def test_reachable_mask_agrees_with_inverse(params):
    grid = workspace_grid(params)
    ok = reachable(params.leg, grid)
    inverse(params.leg, grid[ok])
    for target in grid[~ok][:: max(1, (~ok).sum() // 25)]:
        with pytest.raises(UnreachableError):
            inverse(params.leg, target)


def test_kinematics_accepts_single_points(params):
    pose = inverse(params.leg, (0.0, -0.2))
    assert pose.q.shape == (2,)
    assert np.allclose(forward(params.leg, pose.q).f, (0.0, -0.2))
    assert dataclasses.is_dataclass(pose)
