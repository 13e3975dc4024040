"""Loading the SCARA parameter file: the packaged data/scara.toml or a user's file of the same
layout, validated field by field (params.py) and then as a whole: the seed's trajectory must stay
inside the workspace with the configured elbow."""

from __future__ import annotations

from pathlib import Path
import numpy as np

from fivebar_drake.core.parameter_files import load_parameter_file
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.scara.kinematics import OutOfReach, Scara
from fivebar_drake.mechanisms.scara.params import ScaraParams, params_from_dict
from fivebar_drake.mechanisms.scara.trajectory import seed_path


def check_trajectory(params: ScaraParams) -> None:
    """ParameterError unless every sample of the trajectory is reachable with the elbow of
    the parameters under the joint limits."""
    tr = params.trajectory
    t = np.linspace(0.0, tr.duration_s, int(round(tr.duration_s * tr.samples_per_s)) + 1)
    try:
        Scara(params.kinematics).inverse_path(seed_path(tr, t)[0], params.kinematics.elbow)
    except OutOfReach as err:
        raise ParameterError(f"trajectory (a_m, b_m, center_m): {err} (kinematics: lengths, "
                             "limits, q3_direction, elbow)", "trajectory") from None


def load_params(path: str | Path | None = None) -> ScaraParams:
    """The validated parameters of a TOML file (None: the packaged data/scara.toml);
    ParameterError naming the file and the field."""
    def build(data):
        params = params_from_dict(data, str(path or "packaged scara.toml"))
        check_trajectory(params)
        return params

    return load_parameter_file(path, "scara.toml", build)
