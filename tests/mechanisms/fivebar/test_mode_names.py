"""Assembly-mode names mean what a person sees, whatever the hip spacing: each physical knee
configuration of the seed's leg at 85 mm spacing, followed continuously as the hips move together
to one axis (Stanford Doggo's and Minitaur's layout), keeps its name; the name agrees with a
by-eye reading of the picture (which side of the hip-to-drive-point line each knee is on); and
the modes whose knees end up on one point are refused there."""

import dataclasses
import numpy as np
import pytest

from fivebar_drake.mechanisms.fivebar import (ALL_MODES, MODE_ALIASES, MODE_NAMES, LegLimits,
                                              UnreachableError, inverse, mode_name)
from fivebar_drake.robots.quadruped.config import load_params

FOOT = np.array([0.01, -0.19])     # m, a foot point below the hips every spacing reaches
SPACINGS_MM = np.linspace(85.0, 0.0, 171)


BASE_LEG = load_params().leg


def _leg(spacing_m):
    """The seed's leg at this hip spacing (m), its geometry alone: the limits would cut modes."""
    return dataclasses.replace(BASE_LEG, motor_a_m=(-spacing_m / 2, 0.0), motor_b_m=(spacing_m / 2, 0.0),
                               limits=LegLimits())


def _side_by_eye(hip, through, knee):
    """'forward' when the knee lies at smaller x (leg-plane -x is the robot's heading) than the
    line from the hip through the drive point, read at the knee's height; the foot is below."""
    x_line = hip[0] + (through[0] - hip[0]) * (knee[1] - hip[1]) / (through[1] - hip[1])
    return "forward" if knee[0] < x_line else "back"


def _seen(leg, pose):
    c = _side_by_eye(leg.motor_a_m, pose.e, pose.c)
    d = _side_by_eye(leg.motor_b_m, pose.f, pose.d)
    return {("forward", "back"): "knees_out", ("back", "forward"): "knees_in",
            ("forward", "forward"): "knees_forward", ("back", "back"): "knees_back"}[(c, d)]


@pytest.mark.parametrize("mode", ALL_MODES, ids=MODE_NAMES)
def test_a_knee_configuration_keeps_its_name_as_the_hips_come_together(mode):
    name = mode_name(mode)
    start = inverse(_leg(SPACINGS_MM[0] * 1e-3), FOOT, mode)
    assert _seen(_leg(SPACINGS_MM[0] * 1e-3), start) == name
    knees = np.concatenate([start.c, start.d])
    for spacing in SPACINGS_MM[1:]:
        leg = _leg(spacing * 1e-3)
        poses = {m: inverse(leg, FOOT, m, strict=False) for m in ALL_MODES}
        real = {m: p for m, p in poses.items() if not np.isnan(p.q).any()}
        if spacing == 0.0 and mode not in real:
            # the knees of both-forward / both-back meet on one point: no assembly, refused
            assert name in ("knees_forward", "knees_back")
            with pytest.raises(UnreachableError, match=f"{name}: the knees C and D coincide"):
                inverse(leg, FOOT, mode)
            return
        # the same physical configuration: the real assembly nearest to the previous one
        nearest = min(real, key=lambda m: np.linalg.norm(
            np.concatenate([real[m].c, real[m].d]) - knees))
        assert mode_name(nearest) == name, f"{spacing:.1f} mm"
        assert _seen(leg, real[nearest]) == name, f"{spacing:.1f} mm"
        knees = np.concatenate([real[nearest].c, real[nearest].d])
    assert name in ("knees_out", "knees_in")      # these reach the coaxial leg


def test_former_names_map_to_the_same_modes():
    # the former names said out/in for knee C then knee D; out = away from the centre line
    for old, new in MODE_ALIASES.items():
        c, d = (1 if part == "out" else -1 for part in old.split("_"))
        assert mode_name((c, d)) == new
