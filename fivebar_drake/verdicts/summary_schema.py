"""summary.json's schema: the summary of a simulated run (simulation/summary.summarize) as typed
dictionaries, every key it has, in the order summary.json writes them. The modules that build the
summary and the ones that read it (the pipeline, the envelope, the sweep, the plots, the
recording, the comparison, the 5-bar study's report) take these types, so a key is named in one
place; tests/simulation/test_summary_schema.py holds a real run's summary, and its summary.json
read back, to exactly these keys and value types.

Units are SI (the key's suffix names it). A float that is not finite (NaN: a figure over an empty
window; inf) is written as null in summary.json (files.json_ready). NotRequired marks a key that
only some runs have; `X | None` one that is null where it does not apply (a gait has no jump, a
run without the step check has no step_check). The schema holds no pydrake and no simulation:
the verdict policy beside checks.py (verdicts.py) takes it too.
"""

# no `from __future__ import annotations`: Python 3.11's TypedDict reads NotRequired only from
# evaluated annotations
import re
from typing import NotRequired, TypedDict

Scalar = float | int | bool | str | None   # a variant's field (Variant.fields)


class AtLimit(TypedDict, total=False):
    """The keys checks.at_limit adds to the check of the kind of limit a motor sat at most (the
    torque check for the peak current, the speed check for the voltage)."""

    at_limit_fraction: float
    limit: str                      # "<quadrant>_<kind>", e.g. "braking_torque"
    limits: dict[str, float]        # every limit's share (LimitShares' keys)
    why: str


class TorqueCheck(AtLimit):
    """checks.torque_check (None where there was no demand); at the limit (checks.at_limit) on
    what the motor delivered, the demand's sf and quadrant kept as demand_*."""

    sf: float | None
    verdict: str
    quadrant: str | None
    limit_Nm: float | None
    torque_Nm: float | None
    share_of_limit: float | None
    demand_sf: NotRequired[float | None]
    demand_quadrant: NotRequired[str | None]


class SpeedCheck(AtLimit):
    """checks.speed_check."""

    least_margin: float | None
    outside_fraction: float
    verdict: str


class ThermalCheck(TypedDict):
    """checks.thermal_check: without a thermal model margin None and why; with one the currents
    (and the steady winding temperature where the motor has its thermal data)."""

    margin: float | None
    rms_current_A: NotRequired[float]
    continuous_current_A: NotRequired[float]
    verdict: str
    why: NotRequired[str]
    steady_state_C: NotRequired[float]


class AchievedCheck(TypedDict):
    """verdicts.motor_achieved."""

    verdict: str                    # "pass" or "not_achieved"
    why: str
    at_limit_fraction: float


class MotorChecks(TypedDict):
    """A motor's checks (checks.motor_checks, checks.at_limit) and its achieved check."""

    torque: TorqueCheck
    speed: SpeedCheck
    thermal: ThermalCheck
    verdict: str
    deciding_check: str
    achieved: AchievedCheck


class LimitShares(TypedDict):
    """checks.limit_shares: the share of the window at each quadrant's torque and voltage
    limit."""

    driving_torque: float
    driving_voltage: float
    braking_torque: float
    braking_voltage: float


class TorqueParts(TypedDict):
    """The applied torque's parts (N*m; signals.Signals): contact -J^T F, links M q'' + c + G,
    rotor N^2 J q'', friction."""

    contact: float
    links: float
    rotor: float
    friction: float


class TorquePartsRms(TorqueParts):
    """The parts' RMS and the residual's: applied - their sum."""

    residual: float


class PerCycle(TypedDict):
    """[least, largest] over the window's cycles."""

    peak_torque_Nm: list[float]
    rms_torque_Nm: list[float]
    demand_p99_Nm: list[float]


class MotorSummary(TypedDict):
    """One motor's statistics over the window (run_statistics.motor_summary), its checks and
    verdict (checks None and verdict "insufficient" for an empty window)."""

    checks: MotorChecks | None
    unsaturated_demand_p99_Nm: float
    peak_torque_Nm: float
    p99_torque_Nm: float
    rms_torque_Nm: float
    demand_peak_Nm: float
    demand_p99_Nm: float
    static_seed_Nm: float
    static_trot_Nm: float
    static_contact_Nm: float
    dynamic_to_seed_static: float
    dynamic_to_trot_static: float
    safety_factor: float
    verdict: str
    deciding_check: str | None
    saturated_fraction: float
    limit_shares: LimitShares
    clipped_peak_fraction: float
    clipped_line_fraction: float
    peak_speed_rad_s: float
    p99_speed_rad_s: float
    no_load_speed_rad_s: float
    speed_ok: bool
    decomposition_rms_Nm: TorquePartsRms
    decomposition_at_peak_Nm: TorqueParts
    per_cycle_peak_Nm: list[float]
    per_cycle: PerCycle


class Ran(TypedDict):
    """What ran: each variant's kind and fields (Variant.fields) and the plan's events (s from
    t = 0)."""

    gait: dict[str, Scalar]
    controller: dict[str, Scalar]
    closure: dict[str, Scalar]
    origins: dict[str, dict[str, str]]   # what -> core.plugins.origin (module, distribution, ...)
    planned_events_s: dict[str, float]


class JumpFigures(TypedDict):
    """maneuver_figures' jump; planned: the plan's value of each figure it plans (the variant's
    field or event of the figure's name: height_m, onset_s, takeoff_s)."""

    height_m: float
    takeoff_speed_m_s: float
    takeoff_s: float
    apex_s: float
    onset_s: float
    time_to_apex_s: float
    agility_m_s: float
    com_rise_after_takeoff_m: float
    com_rise_m: float
    push_work_J: float
    energy_bound_rise_m: float
    planned: dict[str, float]
    landing_peak_torque_Nm: NotRequired[float]     # where it landed
    landing_compression_m: NotRequired[float]


class LandingFigures(TypedDict):
    """maneuver_figures' landing; planned as in JumpFigures (touchdown_s)."""

    touchdown_s: float
    end_s: float
    touchdown_speed_m_s: float
    duration_s: float
    impulse_N_s: float
    momentum_change_N_s: float
    peak_force_N: float
    peak_torque_Nm: float
    compression_m: float
    planned: dict[str, float]


class PhaseFigures(TypedDict):
    """maneuver_figures.phase_figures: one phase's peaks; gives_way for the landing."""

    start_s: float
    end_s: float
    demand_peak_Nm: float
    demand_peak_motor: str
    delivered_peak_Nm: float
    braking_beyond_limit_s: float
    gives_way: NotRequired[bool]


class CapabilityAt(TypedDict):
    """Where a capability ratio is least."""

    phase: str
    t_s: float
    leg: str


class ForceCapability(TypedDict):
    """maneuver_figures.capability_along without its arrays: the least ratios available /
    required (None where no foot was loaded)."""

    least_ratio_box: float | None
    least_box_at: CapabilityAt | None
    least_ratio_envelope: float | None
    least_envelope_at: CapabilityAt | None


class BodyHeight(TypedDict):
    min: float
    max: float


class VerticalSupport(TypedDict):
    """run_statistics.vertical_support: shares of the weight."""

    least_share: float
    least_at_s: float
    largest_share: float
    largest_at_s: float


class Bushing(TypedDict):
    stiffness_N_m: float
    damping_N_s_m: float


class MotorRating(TypedDict):
    """The motor's figures at the output."""

    model: str
    gear_ratio: float
    peak_torque_Nm: float
    braking_peak_torque_Nm: float
    no_load_speed_rad_s: float
    continuous_torque_Nm: float | None


class LimitHit(TypedDict):
    """A (leg, limit) reached (run_statistics.limit_report), in the limit's unit."""

    leg: str
    limit: str
    field: str
    bound: float
    unit: str
    first_t_s: float
    share_of_time: float
    worst_value: float
    worst_t_s: float


class LimitReport(TypedDict):
    set: dict[str, float]           # the limits set ([limits] of the parameter file)
    hits: list[LimitHit]


class StepCheckMotor(TypedDict):
    """A motor at half the plant step (verdicts.step_check)."""

    demand_p99_change: float
    rms_change: float
    sf_change: float
    sf_at_half_step: float
    sf_converged: float
    sf_error: float
    verdict_at_half_step: str


class EventStepCheck(TypedDict):
    """A maneuver's event figure at half the plant step, extrapolated (verdicts.extrapolated)."""

    at_half_step: float
    converged: float
    error: float


class StepCheck(TypedDict):
    """verdicts.step_check: the run against itself at half the plant step."""

    time_step_s: float
    half_time_step_s: float
    order: int
    motors: dict[str, StepCheckMotor]           # "<leg> <motor>"
    worst_sf_change: float
    worst_demand_p99_change: float
    converged_worst_motor: str | None
    converged_sf: float | None
    converged_sf_error: float | None
    torque_verdict_converged: str | None
    events: dict[str, dict[str, EventStepCheck]]   # "jump", "landing" -> figure ->
    verdict_at_half_step: str
    fails_for_at_half_step: str | None       # any_controller's at half the step
    achieved: bool                           # the motion done (verdict neither not_achieved
    achieved_at_half_step: bool              # nor insufficient) at the step, at half of it
    marginal: bool
    why: str


class ContactCheck(TypedDict):
    """verdicts.contact_check: the run against itself with the foot contact softer and stiffer
    (pipeline.run_contact_check)."""

    variants: dict[str, dict[str, float]]     # label -> its contact (stiffness N/m, relaxation s)
    verdicts: dict[str, str]                  # "nominal" and each variant -> its verdict
    achieved: dict[str, bool]
    worst_sf: dict[str, float]
    worst_sf_band: list[float] | None         # [least, largest]
    events: dict[str, dict[str, list[float]]]    # "jump", "landing" -> figure -> [least, largest]
    marginal: bool
    why: str


class Timing(TypedDict):
    """pipeline.write_simulation's wall times."""

    simulate_s: float
    outputs_s: float
    outputs_share: float


class PhaseFloor(TypedDict):
    """One phase's need for any controller (verdicts.rules.fails_for): status (verdicts.NEEDS:
    "floor", "undecided" between the model's optimum and its bound, "beyond bound",
    "unknown": no floor for this task), the floor (the least peak motor torque any controller
    needs for it, N*m; None without one), the motors' limit in the quadrant the phase acts
    (driving peak, or braking for a landing, N*m) and what this run's controller asked in it."""

    status: str
    floor_Nm: float | None
    limit_Nm: float
    asked_Nm: float | None


class AnyController(TypedDict):
    """What any controller would need for this maneuver (optimal/; pipeline.any_controller):
    per phase (a jump's push-off and landing, a drop's landing, a gait's stance, a stand-up) its
    need and what this run's controller asked; the maneuver's floor (the largest; None: a phase
    has none) with its safety factor (each phase's limit in its quadrant over its floor, the
    least) and the model margin a claim needs (checks.floor_margin); a jump's optima (the
    highest jump on the push's stroke and over the leg's whole reach, or the highest drop the
    landing's stroke absorbs, m), the bound by another method (m) and what this run reached
    (m); what the controller asked at most in those phases and its ratio to the floor; and
    whom a failing verdict blames (verdicts.fails_for: "any controller": no controller could;
    "this controller": the need within the motors, the demand not; "undecided": between the
    model's optimum and its bound; "unknown": no floor; None: nothing failed)."""

    maneuver: str
    height_m: float
    phases: dict[str, PhaseFloor]
    floor_Nm: float | None
    floor_safety_factor: float | None
    floor_margin: float
    ceiling_m: float | None
    reach_ceiling_m: float | None
    bound_m: float | None
    reached_m: float | None
    asked_Nm: float | None
    controller_cost: float | None
    fails_for: str | None
    why: str


class Summary(TypedDict):
    """summary.json (simulation/summary.summarize; timing from pipeline.write_simulation)."""

    gait: str
    closure: str
    ran: Ran
    duration_s: float
    requested_duration_s: float
    completed: bool
    interrupted: bool
    error: str
    cycles_in_window: int
    window_s: list[float]
    verdict: str
    deciding_check: str | None
    worst_motor: str                # "<leg> <motor>"
    max_tilt_deg: float
    mean_forward_speed_m_s: float
    gait_speed_m_s: float
    gait_frequency_hz: float
    periodic: bool
    cycle_s: float
    jump: JumpFigures | None
    landing: LandingFigures | None
    phases: dict[str, PhaseFigures] | None
    force_capability: ForceCapability | None
    payload_kg: float
    slope_deg: float
    swing_clear_fraction: dict[str, float]     # per leg
    swing_drag_fraction: dict[str, float]
    body_height_m: BodyHeight | None
    vertical_support: VerticalSupport | None
    max_loop_gap_m: float
    max_loop_gap_per_leg_m: dict[str, float]
    time_step_s: float
    log_period_s: float
    real_time_factor: float
    wall_time_s: float
    bushing: Bushing | None
    knee_effective_mass_kg: float
    design_loop_force_N: float
    controller_gains: dict[str, float | list[float]] | None
    seed_peak_torque_Nm: float
    seed_load_model: str
    motor_peak_torque_Nm: float
    motor: MotorRating
    step_check: StepCheck | None
    step_check_interrupted: str                # why the step check has no result ("": it ran)
    contact: dict[str, float]                  # the foot contact: stiffness_N_m, relaxation_time_s
    contact_check: ContactCheck | None
    limits: LimitReport
    legs: dict[str, dict[str, MotorSummary]]   # leg -> motor ("A", "B") ->
    any_controller: AnyController | None       # a jump's floor (pipeline.any_controller)
    answer: str                              # the answer in one line (at most 200 characters)
    answer_details: list[str]                # its reasons, one item each
    timing: NotRequired[Timing]


def schema_markdown() -> str:
    """The reference page of summary.json (docs/reference/summary.md): Summary first, then every
    record it holds in the order this module declares them, each with its docstring and a table
    of its keys, types and the comment beside each key."""
    import inspect
    import sys
    import typing

    module = sys.modules[__name__]
    classes = [c for _, c in inspect.getmembers(module, typing.is_typeddict)
               if c.__module__ == __name__]
    classes.sort(key=lambda c: (c is not Summary, inspect.getsourcelines(c)[1]))
    out = ["# summary.json", "",
           "Every simulation writes `summary.json` with these keys (SI units). Generated from "
           "`fivebar_drake/verdicts/summary_schema.py` by `tools/gen_docs.py`; a test keeps it "
           "current.", ""]
    for cls in classes:
        doc = " ".join(inspect.getdoc(cls).split()) if cls.__doc__ else ""
        comments = {}
        for line in inspect.getsource(cls).splitlines():
            found = re.match(r"\s+(\w+):\s*([^#]+?)\s*(?:#\s*(.*))?$", line)
            if found:
                comments[found.group(1)] = (found.group(2), found.group(3) or "")
        out += [f"## {cls.__name__}", "", doc, "", "| key | type | note |", "|---|---|---|"]
        cell = (lambda text: text.replace("|", "\\|").replace("<", "&lt;"))   # noqa: E731
        out += [f"| `{key}` | `{cell(kind)}` | {cell(note)} |"
                for key, (kind, note) in comments.items() if key in cls.__annotations__]
        out.append("")
    return "\n".join(out).rstrip() + "\n"
