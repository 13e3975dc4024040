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

from .footpath import TROT_PHASES_RAD, check_path
from .config import load_params, with_gait
from .params import Params
from .plant_model import CLOSURES


@dataclass
class Scenario:
    """What to simulate and how (units in the names):
    duration_s: simulated time from t = 0; gait: foot path ("trot" or "seed_ellipse",
    footpath.PATHS); closure: loop closure (plant_model.CLOSURES); time_step_s: plant step, 0 =
    derived (bushing: bushing.bushing_parameters, ball: 1 ms); target_loop_gap_m: the bushing's
    design gap; control_period_s, motor_period_s: update periods of the controller and the motor
    model; control_delay_periods: extra controller periods before a command is released (0: the
    command computed from the state sampled at tick t reaches the motor model's next sample);
    swing_bandwidth_hz, body_bandwidth_hz, damping_ratio: the controller's gains
    (systems.derive_gains); load_transfer_s: time over which a foot takes up or gives off its
    load at touchdown and lift-off; catch_gain (m/m), catch_rate_s (s): the swing legs' catch
    reflex (systems.FootLegController, 0 = off); touchdown_detection: a descending swing foot
    that meets the ground early joins the support; stand_s: standing time before the gait starts; ramp_s: time
    over which the foot path grows to full size; phases_rad: gait phase of FL, FR, RL, RR;
    log_period_s: interval of the recorded means (measured every plant step); pose_rate_hz: 3-D
    pose recording rate; params_file: parameter TOML ("" = packaged); gait_*: optional overrides
    of the parameter file's gait."""

    duration_s: float = 8.0
    gait: str = "trot"
    closure: str = "bushing"
    time_step_s: float = 0.0
    target_loop_gap_m: float = 4e-6
    control_period_s: float = 0.002
    motor_period_s: float = 0.001
    control_delay_periods: int = 0
    swing_bandwidth_hz: float = 15.0
    body_bandwidth_hz: float = 3.0
    damping_ratio: float = 0.7
    load_transfer_s: float = 0.04
    catch_gain: float = 1.0
    catch_rate_s: float = 0.1
    touchdown_detection: bool = True
    stand_s: float = 0.5
    ramp_s: float = 1.0
    phases_rad: list[float] = field(default_factory=lambda: list(TROT_PHASES_RAD))
    log_period_s: float = 0.002
    pose_rate_hz: float = 50.0
    params_file: str = ""
    gait_a_m: Optional[float] = None
    gait_b_m: Optional[float] = None
    gait_y_home_m: Optional[float] = None
    gait_frequency_hz: Optional[float] = None
    gait_duty_factor: Optional[float] = None

    def validate(self) -> None:
        """Raise ValueError naming the first bad field, its value and the allowed range."""
        check_path(self.gait)
        if self.closure not in CLOSURES:
            raise ValueError(f"scenario.closure = {self.closure!r}: allowed {list(CLOSURES)}")
        positive = ("duration_s", "target_loop_gap_m", "control_period_s", "motor_period_s",
                    "log_period_s", "pose_rate_hz", "swing_bandwidth_hz", "body_bandwidth_hz",
                    "damping_ratio")
        for name in positive:
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"scenario.{name} = {value!r}: must be > 0")
        for name in ("time_step_s", "stand_s", "ramp_s", "load_transfer_s", "catch_gain",
                     "catch_rate_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"scenario.{name} = {value!r}: must be >= 0")
        if not (isinstance(self.control_delay_periods, int) and self.control_delay_periods >= 0):
            raise ValueError(f"scenario.control_delay_periods = {self.control_delay_periods!r}: "
                             "must be an integer >= 0")
        if len(self.phases_rad) != 4:
            raise ValueError(f"scenario.phases_rad = {self.phases_rad!r}: needs 4 values "
                             "(FL, FR, RL, RR)")

    def load_params(self) -> Params:
        """The parameter file with this scenario's gait overrides (validated: reachable gait)."""
        params = load_params(self.params_file or None)
        overrides = {name[len("gait_"):]: value for name, value in dataclasses.asdict(self).items()
                     if name.startswith("gait_") and value is not None}
        return with_gait(params, **overrides) if overrides else params


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
