"""Drake's config structs (MultibodyPlantConfig, SimulatorConfig) as plain data: their fields as
a dict, and a copy with some fields changed (pydrake cannot pickle or compare them); and their
checks before any work. Some bad values make Drake abort the process (a failed C++ condition:
stiction_tolerance <= 0, sap_near_rigid_threshold < 0, start_time ahead of the run), others it
refuses late with its own words: every field is held to named bounds first, then Drake is
asked on a throwaway object, its refusal worded with the field."""

from __future__ import annotations

import math

from fivebar_drake.core.validation import ParameterError, check_number, require

MAX_STICTION_TOLERANCE_M_S = 1.0    # a "stiction" slip this fast is sliding, not sticking
MAX_NEAR_RIGID_THRESHOLD = 10.0     # SAP's threshold is a fraction of a time scale (default 1)
MAX_PENETRATION_M = 0.1             # more than 10 cm of penetration is not contact
CONTACT_MODELS = ("point", "hydroelastic_with_fallback")   # the feet declare point contact
SURFACE_REPRESENTATIONS = ("triangle", "polygon")
MIN_REALTIME_RATE = 0.1             # 0 = as fast as possible; slower than 1/10 of real time
MAX_REALTIME_RATE = 1000.0          # would only stretch a run (a 10 s trot to 100 s)
MAX_INTEGRATOR_STEP_S = 1.0


def check_plant_config_values(config, field: str) -> None:
    """Named bounds on a MultibodyPlantConfig's values (ParameterError naming field.NAME)."""
    check_number(f"{field}.stiction_tolerance", config.stiction_tolerance, 0.0,
                 MAX_STICTION_TOLERANCE_M_S, low_open=True, why="a slip speed (m/s)")
    check_number(f"{field}.sap_near_rigid_threshold", config.sap_near_rigid_threshold, 0.0,
                 MAX_NEAR_RIGID_THRESHOLD, why="Drake's default is 1")
    check_number(f"{field}.penetration_allowance", config.penetration_allowance, 0.0,
                 MAX_PENETRATION_M, low_open=True, why="m")
    require(config.contact_model in CONTACT_MODELS, f"{field}.contact_model",
            config.contact_model, f"one of {list(CONTACT_MODELS)}: the robot's feet declare "
            "point-contact properties, no hydroelastic ones")
    require(config.contact_surface_representation in SURFACE_REPRESENTATIONS,
            f"{field}.contact_surface_representation", config.contact_surface_representation,
            f"one of {list(SURFACE_REPRESENTATIONS)}")


def check_simulator_config(config, field: str) -> None:
    """A SimulatorConfig's values against named bounds, then Drake on a throwaway simulator
    (ParameterError naming field.NAME)."""
    from pydrake.systems.analysis import (ApplySimulatorConfig, GetIntegrationSchemes,
                                          Simulator)
    from pydrake.systems.primitives import ConstantVectorSource

    schemes = list(GetIntegrationSchemes())
    require(config.integration_scheme in schemes, f"{field}.integration_scheme",
            config.integration_scheme, f"one of {schemes}")
    check_number(f"{field}.max_step_size", config.max_step_size, 0.0, MAX_INTEGRATOR_STEP_S,
                 low_open=True, why="s")
    check_number(f"{field}.accuracy", config.accuracy, 0.0, 1.0, low_open=True)
    require(config.start_time == 0.0, f"{field}.start_time", config.start_time,
            "must be 0: a run starts at t = 0 (its times, the gait's included, count from it)")
    rate = config.target_realtime_rate
    require(isinstance(rate, float) and math.isfinite(rate) and (
        rate == 0.0 or MIN_REALTIME_RATE <= rate <= MAX_REALTIME_RATE),
        f"{field}.target_realtime_rate", rate, f"0 (as fast as possible) or "
        f"{MIN_REALTIME_RATE:g} .. {MAX_REALTIME_RATE:g}")
    try:
        ApplySimulatorConfig(config, Simulator(ConstantVectorSource([0.0])))
    except (RuntimeError, ValueError) as err:
        raise ParameterError(f"{field}: Drake refuses it: {err}", field) from None


def config_fields(config) -> dict:
    """A Drake config's fields as a plain dict."""
    return {f.name: getattr(config, f.name) for f in type(config).__fields__}


def config_with(config, **changes):
    """A copy of a Drake config with the given fields changed."""
    return type(config)(**{**config_fields(config), **changes})
