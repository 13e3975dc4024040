"""The 3-DOF SCARA arm of seed 002: parameters, kinematics, Lagrange dynamics, cubic time laws
and drive sizing (no Drake here; the Drake model is in fivebar_drake.studies.scara)."""

from fivebar_drake.mechanisms.scara.arm import ScaraArm
from fivebar_drake.mechanisms.scara.dynamics import Dynamics, Inertia, seed_inertia
from fivebar_drake.mechanisms.scara.kinematics import ELBOWS, OutOfReach, Scara, ScaraPose
from fivebar_drake.mechanisms.scara.config import check_trajectory, load_params
from fivebar_drake.mechanisms.scara.params import ScaraParams, params_from_dict
from fivebar_drake.mechanisms.scara.trajectory import cubic_coefficients, cubic_law, seed_path

__all__ = ["ScaraArm", "Dynamics", "Inertia", "seed_inertia", "ELBOWS", "OutOfReach", "Scara",
           "ScaraPose", "ScaraParams", "check_trajectory", "load_params", "params_from_dict",
           "cubic_coefficients", "cubic_law", "seed_path"]
