"""Gaits and maneuvers, one module each, registered by kind in PATHS in this order: the seed's
ellipse, trot, walk, bound, pronk, the Doggo-style path, jump, drop, stand-up. The machinery
they share (FootPath, the evaluator, the gait's parameters, the registry) is base.py; a one-shot
maneuver's is maneuver.py. `from fivebar_drake.gaits import X` reaches every name below."""

# noqa: F401 throughout: these imports are the package's interface
from fivebar_drake.gaits.base import (  # noqa: F401
    EXTENSION_STOP_S, MAX_MANEUVER_S, MIN_CRAWL_DUTY, PATHS, PUSH_SHARES, REACH_SPEED_M_S,
    REFERENCES_PER_LEG, Events, FootPath, Gait, Outcome, PathPoints, cycle_phase, cycle_times,
    evaluate, foot_path, path_arrays, phase_of, reference_parts, references_kernel, register_path,
    shared_loads, smoothstep, stance_loads, stance_weight, stance_weight_arrays, stance_weight_at)
from fivebar_drake.gaits.seed_ellipse import (  # noqa: F401
    EllipseConstants, SeedEllipse, ellipse_point)
from fivebar_drake.gaits.trot import Trot, TrotConstants, trot_point  # noqa: F401
from fivebar_drake.gaits.walk import Walk  # noqa: F401
from fivebar_drake.gaits.bound import Bound  # noqa: F401
from fivebar_drake.gaits.pronk import Pronk  # noqa: F401
from fivebar_drake.gaits.doggo import Doggo, DoggoConstants, doggo_point  # noqa: F401
from fivebar_drake.gaits.maneuver import (  # noqa: F401
    REST, Landing, Maneuver, ManeuverConstants, hermite5, hold, maneuver_point, move)
from fivebar_drake.gaits.jump import Jump  # noqa: F401
from fivebar_drake.gaits.drop import Drop  # noqa: F401
from fivebar_drake.gaits.stand_up import StandUp  # noqa: F401
