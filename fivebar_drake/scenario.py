"""Simulation scenario: what to simulate and how, as a dataclass loadable from YAML.

Units: s, m, rad, N*m. A YAML file names any subset of the fields, e.g.

    duration_s: 5.0
    closure: ball
    gait_frequency_hz: 1.5
"""

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

from pydrake.common.yaml import yaml_load_typed

from .footpath import check_path
from .params import Params, load_params
from .plant_model import CLOSURES


@dataclass
class Scenario:
    """duration_s: simulated time after t = 0; closure: "bushing" or "ball"; time_step_s: plant
    step, 0 = derived (bushing: bushing.bushing_parameters, ball: 1 ms); target_loop_gap_m: the
    bushing's design gap; control_period_s / motor_period_s: update periods of the IK controller
    and motor model; kp_Nm_rad, kd_Nm_s_rad: joint PD gains; stand_s: standing time before the
    gait starts; ramp_s: time over which the ellipse grows to full size; phases_rad: gait phase
    of FL, FR, RL, RR (diagonal pairs in phase); balance_gain, balance_rate_s: tilt feedback of
    the controller (0 = plain trot; see systems.FootIKController); log_period_s: time-series sampling;
    pose_rate_hz: 3-D pose recording rate; params_file: parameter TOML ("" = packaged);
    gait_*: optional overrides of the parameter file's gait."""

    duration_s: float = 10.0
    gait: str = "trot"
    closure: str = "bushing"
    time_step_s: float = 0.0
    target_loop_gap_m: float = 4e-6
    control_period_s: float = 0.002
    motor_period_s: float = 0.001
    kp_Nm_rad: float = 30.0
    kd_Nm_s_rad: float = 0.08
    balance_gain: float = 1.0
    balance_rate_s: float = 0.1
    stand_s: float = 0.5
    ramp_s: float = 1.0
    phases_rad: list[float] = field(default_factory=lambda: [0.0, math.pi, math.pi, 0.0])
    log_period_s: float = 0.002
    pose_rate_hz: float = 50.0
    params_file: str = ""
    gait_a_m: Optional[float] = None
    gait_b_m: Optional[float] = None
    gait_y_home_m: Optional[float] = None
    gait_frequency_hz: Optional[float] = None

    def validate(self) -> None:
        """Raise ValueError naming the first bad field, its value and the allowed range."""
        check_path(self.gait)
        if self.closure not in CLOSURES:
            raise ValueError(f"scenario.closure = {self.closure!r}: allowed {list(CLOSURES)}")
        positive = ("duration_s", "target_loop_gap_m", "control_period_s", "motor_period_s",
                    "log_period_s", "pose_rate_hz")
        for name in positive:
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"scenario.{name} = {value!r}: must be > 0")
        for name in ("time_step_s", "kp_Nm_rad", "kd_Nm_s_rad", "stand_s", "ramp_s",
                     "balance_gain", "balance_rate_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"scenario.{name} = {value!r}: must be >= 0")
        if len(self.phases_rad) != 4:
            raise ValueError(f"scenario.phases_rad = {self.phases_rad!r}: needs 4 values "
                             "(FL, FR, RL, RR)")

    def load_params(self) -> Params:
        """The parameter file with this scenario's gait overrides (validated: reachable gait)."""
        params = load_params(self.params_file or None)
        overrides = {name[len("gait_"):]: value for name, value in dataclasses.asdict(self).items()
                     if name.startswith("gait_") and value is not None}
        return params.with_gait(**overrides) if overrides else params


def load_scenario(path: "str | Path | None" = None, **overrides) -> "Scenario":
    """Scenario from a YAML file (None: defaults) with keyword overrides; validated."""
    scenario = Scenario()
    if path is not None:
        path = Path(path)
        if not path.exists():
            raise ValueError(f"scenario file not found: {path}")
        try:
            scenario = yaml_load_typed(schema=Scenario, filename=str(path), defaults=Scenario())
        except RuntimeError as err:
            raise ValueError(f"{path}: {err}") from None
    scenario = dataclasses.replace(scenario, **{k: v for k, v in overrides.items() if v is not None})
    scenario.validate()
    return scenario
