"""The leg's limits ([limits]): a pose past each limit is unreachable with that limit, its value and
its bound named; the limited quantities against closed forms (law of cosines, the hip axis); the
gait checks name the first sample past a limit with its time; the SDF's joint ranges are the
limits, and the knee's joint range is the least knee angle."""

import dataclasses
import math

import numpy as np
import pytest
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant

from fivebar_drake.gaits import evaluate
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import (KNEES_OUT, LegLimits, UnreachableError, inverse,
                                              path_poses, sample_gait, tree_positions)
from fivebar_drake.robots.quadruped.config import PATH_CHECK_SAMPLES, check_path, with_changes
from fivebar_drake.robots.quadruped.sdf import single_leg_sdf

HOME = np.array([0.0, -0.2])


def law_of_cosines(a, b, opposite):
    """The angle (deg) between sides a and b of a triangle whose third side is `opposite`."""
    return np.degrees(np.arccos((a**2 + b**2 - opposite**2) / (2 * a * b)))


def reference(leg, foot, mode=KNEES_OUT):
    """The limited quantities of the pose reaching foot (deg, m) by a second method: the motor
    angles from the knees' positions, the knee angles by the law of cosines over the triangles
    A-C-E and B-D-E, the extension from the foot to the motors' midpoint, the upper links'
    angle from their directions' dot product."""
    pose = inverse(dataclasses.replace(leg, limits=LegLimits()), foot, mode)
    ac, bd = pose.c - leg.a, pose.d - leg.b
    return {
        "theta_a": math.degrees(math.atan2(ac[1], ac[0])),
        "theta_b": math.degrees(math.atan2(bd[1], bd[0])),
        "knee C angle": law_of_cosines(leg.ac_m, leg.ce_m, np.linalg.norm(pose.e - leg.a)),
        "knee D angle": law_of_cosines(leg.bd_m, leg.de_m, np.linalg.norm(pose.e - leg.b)),
        "extension": float(np.linalg.norm(foot - (np.array(leg.motor_a_m)
                                                  + np.array(leg.motor_b_m)) / 2)),
        "upper": math.degrees(math.acos(ac @ bd / (leg.ac_m * leg.bd_m))),
    }


def cases(ref):
    """(field, the bound a little past the pose, a little within it, the name, the value) per
    limit; the least knee angle is set between the two knees' angles so knee D (the smaller at
    home) is the one named."""
    c, d = ref["knee C angle"], ref["knee D angle"]
    assert d < c
    return [("theta_a_min_deg", ref["theta_a"] + 0.5, ref["theta_a"] - 0.5, "motor A angle",
             ref["theta_a"]),
            ("theta_a_max_deg", ref["theta_a"] - 0.5, ref["theta_a"] + 0.5, "motor A angle",
             ref["theta_a"]),
            ("theta_b_min_deg", ref["theta_b"] + 0.5, ref["theta_b"] - 0.5, "motor B angle",
             ref["theta_b"]),
            ("theta_b_max_deg", ref["theta_b"] - 0.5, ref["theta_b"] + 0.5, "motor B angle",
             ref["theta_b"]),
            ("extension_min_m", ref["extension"] + 1e-3, ref["extension"] - 1e-3,
             "leg extension", ref["extension"]),
            ("extension_max_m", ref["extension"] - 1e-3, ref["extension"] + 1e-3,
             "leg extension", ref["extension"]),
            ("knee_min_deg", (c + d) / 2, d - 0.5, "knee D angle", d),
            ("upper_links_min_deg", ref["upper"] + 0.5, ref["upper"] - 0.5, "upper links' angle",
             ref["upper"])]


def with_limit(leg, **limit):
    return dataclasses.replace(leg, limits=LegLimits(**limit))


@pytest.mark.parametrize("index", range(8))
def test_a_pose_past_each_limit_is_unreachable_naming_it(params, index):
    ref = reference(params.leg, HOME)
    field, past, within, name, value = cases(ref)[index]
    unit = field.rsplit("_", 1)[1]
    leg = with_limit(params.leg, **{field: past})
    with pytest.raises(UnreachableError) as err:
        inverse(leg, HOME)
    sign = "<" if "_min_" in field else ">"
    word = "least" if "_min_" in field else "most"
    text = f"{name} {value:.4g} {unit} {sign} {word} {past:.4g} {unit} ([limits].{field})"
    assert text in str(err.value)
    assert err.value.field == field
    assert np.isnan(inverse(leg, HOME, strict=False).q).all()
    # the same limit a little on the other side of the pose: reachable, the same pose
    free = inverse(params.leg, HOME)
    assert np.allclose(inverse(with_limit(params.leg, **{field: within}), HOME).q, free.q,
                       atol=1e-15)


def test_the_knee_named_is_the_one_past_the_limit(params):
    """At the back of the stride knee C is the smaller angle: it is the one named there."""
    foot = np.array([-0.06, -0.2])
    ref = reference(params.leg, foot)
    c, d = ref["knee C angle"], ref["knee D angle"]
    assert c < d
    leg = with_limit(params.leg, knee_min_deg=(c + d) / 2)
    with pytest.raises(UnreachableError, match=f"knee C angle {c:.4g} deg < least"):
        inverse(leg, foot)


def test_only_the_poses_past_a_limit_are_lost(params):
    """On a grid, the poses lost to a limit are exactly those whose reference value lies past
    it, and the rest keep their pose."""
    leg = with_limit(params.leg, extension_max_m=0.21, knee_min_deg=80.0)
    x, y = np.meshgrid(np.linspace(-0.08, 0.08, 9), np.linspace(-0.23, -0.16, 8))
    feet = np.stack([x, y], -1).reshape(-1, 2)
    got = inverse(leg, feet, strict=False).q
    free = inverse(params.leg, feet).q
    for foot, q, q_free in zip(feet, got, free):
        ref = reference(params.leg, foot)
        past = ref["extension"] > 0.21 or min(ref["knee C angle"], ref["knee D angle"]) < 80.0
        assert np.isnan(q).all() == past
        if not past:
            assert np.array_equal(q, q_free)
    assert 0 < np.isnan(got[:, 0]).sum() < len(feet)       # the grid straddles the limits


@pytest.mark.parametrize("table, field, allowed", [
    ({"theta_a_min_deg": 10.0, "theta_a_max_deg": -10.0}, "limits.theta_a_min_deg",
     "must be < limits.theta_a_max_deg = -10"),
    ({"theta_b_max_deg": 200.0}, "limits.theta_b_max_deg", "must be in [-180, 180]"),
    ({"extension_min_m": 0.3, "extension_max_m": 0.2}, "limits.extension_min_m",
     "must be < limits.extension_max_m = 0.2"),
    ({"extension_max_m": 270.0}, "limits.extension_max_m", "must be in [0, 2]"),
    ({"knee_min_deg": 180.0}, "limits.knee_min_deg", "must be in [0, 180)"),
    ({"upper_links_min_deg": -5.0}, "limits.upper_links_min_deg", "must be in [0, 180)"),
    ({"knee_min_deg": math.nan}, "limits.knee_min_deg", "must be a finite number"),
])
def test_bad_limits_name_the_field_and_the_range(table, field, allowed):
    with pytest.raises(ParameterError) as err:
        LegLimits(**table)
    assert err.value.field == field and allowed in str(err.value)


def test_the_gait_check_names_the_first_sample_past_a_limit(params):
    """The seed's ellipse reaches 230 mm from the hips: with a most extension of 220 mm the
    check names the first sample beyond it and its time, found here from the path alone."""
    limited = with_changes(params, {"limits.extension_max_m": 0.22})
    with pytest.raises(ParameterError) as err:
        check_path(limited, "seed_ellipse")
    t = np.linspace(0.0, params.gait.period_s, PATH_CHECK_SAMPLES)
    extension = np.linalg.norm(evaluate(params.gait, "seed_ellipse", t).pos, axis=-1)
    first = int(np.flatnonzero(extension > 0.22)[0])
    assert err.value.field == "limits.extension_max_m"
    assert (f"seed_ellipse path, sample {first} of {PATH_CHECK_SAMPLES} at t = {t[first]:.4f} s"
            in str(err.value))
    assert f"leg extension {extension[first]:.4g} m > most 0.22 m" in str(err.value)
    check_path(limited, "trot")                 # the trot stays within 209 mm: accepted
    with pytest.raises(UnreachableError, match=r"seed_ellipse path, sample \d+ of 60 at t = "):
        sample_gait(limited.leg, limited.gait, "seed_ellipse")     # the analysis's tracking
    points, pose, _ = path_poses(limited.leg, limited.gait, "trot", t)
    assert not np.isnan(pose.q).any() and len(points.pos) == len(t)


def test_the_default_limits_cut_neither_the_paths_nor_the_home_pose(params):
    """The assumed limits of default.toml: every path and the home point in every mode keep
    their poses (the same as without limits)."""
    free = dataclasses.replace(params.leg, limits=LegLimits())
    assert len(params.limits.given) == 8
    for path in ("seed_ellipse", "trot", "doggo"):
        assert np.array_equal(sample_gait(params.leg, params.gait, path).pose.q,
                              sample_gait(free, params.gait, path).pose.q)
    for mode in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
        assert np.array_equal(inverse(params.leg, HOME, mode).q, inverse(free, HOME, mode).q)


def test_the_sdf_joint_ranges_are_the_limits(params):
    """Drake reads the motors' ranges and the knees' from the leg's SDF; the knee joint angle
    phi of a pose is pi minus its knee angle (law of cosines) in size, so the least knee angle k
    is the joint range |phi| <= pi - k."""
    plant = MultibodyPlant(1e-3)
    Parser(plant).AddModelsFromString(single_leg_sdf(params, None, None), "sdf")
    plant.Finalize()
    lim = params.limits
    for joint, lo, hi in (("A", lim.theta_a_min_deg, lim.theta_a_max_deg),
                          ("B", lim.theta_b_min_deg, lim.theta_b_max_deg),
                          ("C", lim.knee_min_deg - 180.0, 180.0 - lim.knee_min_deg),
                          ("D", lim.knee_min_deg - 180.0, 180.0 - lim.knee_min_deg)):
        j = plant.GetJointByName(f"leg_{joint}")
        assert np.degrees(j.position_lower_limits()[0]) == pytest.approx(lo, abs=1e-9)
        assert np.degrees(j.position_upper_limits()[0]) == pytest.approx(hi, abs=1e-9)
    samples = sample_gait(params.leg, params.gait)
    x = tree_positions(samples.pose)
    knee_c = law_of_cosines(params.leg.ac_m, params.leg.ce_m,
                            np.linalg.norm(samples.pose.e - params.leg.a, axis=-1))
    assert np.allclose(180.0 - np.degrees(np.abs(x[:, 2])), knee_c, atol=1e-9)
    # without limits: no range
    free = dataclasses.replace(params, leg=dataclasses.replace(params.leg, limits=LegLimits()))
    plant = MultibodyPlant(1e-3)
    Parser(plant).AddModelsFromString(single_leg_sdf(free, None, None), "sdf")
    plant.Finalize()
    assert np.isinf(plant.GetJointByName("leg_C").position_upper_limits()[0])


def test_a_sweep_design_past_a_limit_is_named_and_the_others_kept(params):
    """Designs varying a limit (as a sweep does): the seed's ellipse reaches 230 mm from the
    hips, so 0.22 m cuts it and 0.25 m does not; the kept design's figures are those without
    limits."""
    from fivebar_drake.analysis.design_points import evaluate_designs

    free = dataclasses.replace(params, leg=dataclasses.replace(params.leg, limits=LegLimits()))
    designs = [with_changes(params, {"limits.extension_max_m": v}) for v in (0.25, 0.22)]
    kept, cut = evaluate_designs(designs + [free], "seed_ellipse", "full")[:2]
    assert "[limits].extension_max_m" in cut["error"] and "seed_ellipse" in cut["error"]
    assert kept == evaluate_designs([free], "seed_ellipse", "full")[0]
