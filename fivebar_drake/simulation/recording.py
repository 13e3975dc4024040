"""Rerun recording (.rrd) of a simulated run, logged in columns, with its blueprint inside: a
3-D view that follows the robot, each motor's torques in its own hue, one unit per plot, and the
run's key events (simulation/events.py) on the timeline.

Entities (timeline "sim_time"), SI units unless the name says otherwise:
- world/ground (a patch under the path walked, world/ground/grid its lines every GRID_M),
  world/follow (the point of the ground under the
  body: the 3-D view's frame), world/body (box + pose), world/legs/<leg> (link
  segments A-C-E-F and B-D-E-F, in the hue of their motor), world/feet/<leg> (foot trace), world/forces/<leg> (ground
  force at the foot, 1 mm per N), at pose_rate_hz;
- per log interval (means over the plant steps of the interval): torque/<leg>/<A|B>/{applied,
  commanded, static_same_loads, static_contact, static_seed} and torque/<leg>/limit_{pos,neg}
  (N·m; A in blues, B in oranges: applied bold, commanded light, static dark; static_contact
  and static_seed left out of the default layout, added to a view from the blueprint panel);
  joints/angle/<leg>/<A|B> (rad),
  joints/speed/<leg>/<A|B> (rad/s); contact/{normal, tangential}/<leg> (N, leg plane);
  loop_gap_um/<leg> (µm, worst of the interval); body/height_m, body/forward_speed_m_s (with
  body/forward_speed_m_s/gait, the gait's speed), body/tilt_deg; stats/window (1 inside the
  statistics window);
- cycle_peak/<leg>/<A|B>: the peak applied torque of each whole cycle, at the cycle's end (N·m);
- events (text log) and markers at the event times: body/height_m/<takeoff|apex|touchdown>,
  contact/normal/<leg>/<lift-off|touchdown> (on the foot's normal force).
Each run gets its own recording id, so two runs open side by side in one viewer.
"""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from fivebar_drake.verdicts.checks import thresholds_text
from fivebar_drake.core.text import verdict_word
from fivebar_drake.core.rerun_files import TIMELINE, pose_frames, recording_file, scalars
from fivebar_drake.core.rotation import body_rotations
from fivebar_drake.verdicts.summary_schema import Summary
from fivebar_drake.mechanisms.fivebar import MOTORS, forward_points
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import RobotLayout
from fivebar_drake.robots.quadruped.legs import plane_to_body
from fivebar_drake.simulation.plots import coinciding
from fivebar_drake.simulation.events import FLIGHT_KINDS, FOOT_KINDS, detect_events
from fivebar_drake.simulation.runner import SimulationRecord
from fivebar_drake.simulation.signals import Signals


RECORDING_FILE = "run.rrd"
FORCE_ARROW_M_PER_N = 0.001    # 1 mm of arrow per newton
FORCE_SAME_N = 0.5             # feet whose forces agree within this at every sample: one curve
# of link_points' A, C, E, F, B, D: A-C-E-F and B-D-E-F (link DE carries the foot F)
LEG_STRIPS = ([0, 1, 2, 3], [4, 5, 2, 3])
GROUND_MARGIN_M = 0.4          # the ground patch reaches this far beyond the path of the body
GRID_M = 0.1                   # spacing of the lines on the ground (the robot passes over them)
EYE_OFFSET_M = (0.40, -0.80, 0.25)   # the camera from the body at standing height (world/follow)
# per torque series: its Signals field, the shade of the motor's hue (0 light .. 2 dark), line
# width, its name in the legends (the glossary's words), in a leg's panel at first (else left
# out of the default layout: added to a view from the blueprint panel)
TORQUE_SERIES = {"applied": ("applied", 1, 2.5, "applied", True),
                 "commanded": ("command", 0, 1.2, "demand", True),
                 "static_same_loads": ("static_trot", 2, 1.5, "static, same loads", True),
                 "static_contact": ("static_contact", 1, 1.0, "static, contact", False),
                 "static_seed": ("static_seed", 2, 1.0, "static, seed's model", False)}
WORST_SERIES = ("applied", "commanded", "static_same_loads")    # the worst motor's, in its panel
MOTOR_SHADES = {"A": ((150, 200, 240), (40, 120, 220), (20, 50, 140)),      # blues
                "B": ((255, 190, 120), (240, 110, 20), (150, 55, 0))}       # oranges
LIMIT_COLOR = (200, 40, 40)
LEG_COLORS = ((102, 194, 165), (252, 141, 98), (141, 160, 203), (231, 138, 195))
LEG_COLOR_NAMES = ("green", "orange", "blue", "pink")
MOTOR_WIDTHS = {"A": 1.6, "B": 0.8}   # per-leg plots (joints, per-cycle peaks): A bold, B thin
EVENT_MARKERS = {"takeoff": "Up", "apex": "Diamond", "touchdown": "Down", "lift-off": "Up"}
FLIGHT_COLOR = (255, 230, 0)
WORST_ROOM = 1.25   # the worst motor's time axis: the run and a quarter more, for its legend
PHASE_COLORS = ((120, 120, 120), (150, 90, 200), (0, 160, 160), (200, 140, 0), (90, 90, 220),
                (60, 160, 60))


class Headline(NamedTuple):
    """What the recording answers at a glance: the worst motor (leg, motor), its limit in the
    quadrant that decided it (N·m) and the phases of the run ((name, start s, end s))."""
    leg: str
    motor: str
    limit_Nm: float
    quadrant: str
    phases: tuple


def headline(sig: Signals, legs, params: Params, summary: Summary) -> Headline:
    """The run's worst motor (the summary's, else the one with the largest demand), the limit
    of its deciding quadrant, and its phases: a maneuver's own (summary["phases"]), a gait's
    standing and ramp before its statistics window."""
    worst = (summary.get("worst_motor") or "").split()
    if len(worst) != 2:
        peak = (np.max(np.nan_to_num(np.abs(sig.command), nan=-1.0), axis=0) if len(sig.t)
                else np.zeros((len(legs), 2)))
        i, j = np.unravel_index(np.argmax(peak), peak.shape)
        worst = [legs[i], MOTORS[j]]
    torque = ((summary["legs"].get(worst[0], {}).get(worst[1], {}).get("checks") or {})
              .get("torque") or {})
    quadrant = torque.get("quadrant") or "driving"
    limit = torque.get("limit_Nm") or (params.motor.braking_peak_torque_Nm if
                                       quadrant == "braking" else params.motor.peak_torque_Nm)
    start, end = summary["window_s"]
    if summary.get("phases"):
        phases = tuple((name, p["start_s"], p["end_s"]) for name, p in summary["phases"].items())
    else:
        phases = (("standing and ramp", 0.0, start), ("statistics window", start, end))
    return Headline(worst[0], worst[1], float(limit), quadrant, phases)


def blueprint(legs, height_m: float, head: Headline | None = None,
              periodic: bool = True, duration_s: float = 0.0) -> rrb.Blueprint:
    """The viewer's layout, answering at a glance: on the left the verdict (a text panel: the
    worst motor, its figure against its limit, when, the thresholds, the phases), the robot
    seen from the frame world/follow (it moves with the body over the ground; the camera
    EYE_OFFSET_M from a point height_m above the ground under the body) and the event log; on
    the right, half its height, the worst motor's torques against its limit with the phases
    marked (its time axis WORST_ROOM times the run's duration_s: the legend beside the data,
    not over it); below it, side by side, every motor's share of its limit (%) and tabs: the
    per-cycle peaks against the limit (a gait) or the body's height (a maneuver) in front, the
    foot normal forces, each leg's torques, the body's speed (a gait), height and tilt, the
    tangential forces, loop gaps, joint angles and speeds and the statistics window. Every time
    series gets half the window's height and the torque and share panels fixed y ranges: the
    viewer labels its ticks at powers of ten (1 N·m, 10 %) only when they lie some 25 pixels
    apart, so at the default size (1600 x 1000) every unit of N·m and every 10 % is labelled."""
    head = head or Headline(legs[0], MOTORS[0], 1.0, "driving", ())
    span = 1.15 * head.limit_Nm

    def torques(leg):
        hidden = [f"- torque/{leg}/{m}/{name}" for m in MOTORS
                  for name, series in TORQUE_SERIES.items() if not series[-1]]
        return rrb.TimeSeriesView(origin=f"torque/{leg}", contents=["$origin/**", *hidden],
                                  name=f"{leg} torque (N·m): A blue, B orange",
                                  axis_y=rrb.ScalarAxis(range=(-span, span)),
                                  plot_legend=rrb.PlotLegend(visible=False))

    worst = f"{head.leg} {head.motor}"
    colours = ", ".join(f"{leg} {name}" for leg, name in zip(legs, LEG_COLOR_NAMES))
    look = np.array([0.0, 0.0, height_m])
    below = [rrb.TimeSeriesView(origin="cycle_peak", name="per-cycle peak (N·m)",
                                axis_y=rrb.ScalarAxis(range=(0.0, span)),
                                plot_legend=rrb.PlotLegend(visible=False))
             if periodic else
             rrb.TimeSeriesView(origin="body/height_m", name="body height (m)",
                                axis_y=rrb.ScalarAxis(range=(0.0, 1.6 * height_m)),
                                plot_legend=rrb.PlotLegend("RightBottom"))]
    body = ([rrb.TimeSeriesView(origin="body/forward_speed_m_s", name="forward speed (m/s)"),
             rrb.TimeSeriesView(origin="body/height_m", name="body height (m)")]
            if periodic else [])
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.TextDocumentView(origin="verdict", name="verdict"),
                rrb.Spatial3DView(
                    origin="world/follow", contents="world/**",
                    name="robot (the camera follows the body)",
                    line_grid=rrb.LineGrid3D(visible=False),
                    eye_controls=rrb.EyeControls3D(position=look + EYE_OFFSET_M,
                                                   look_target=look, eye_up=[0.0, 0.0, 1.0])),
                rrb.TextLogView(origin="events", name="events", columns=rrb.TextLogColumns(
                    text_log_columns=[rrb.encodings.TextLogColumn(kind, visible=kind == "Body")
                                      for kind in ("EntityPath", "LogLevel", "Body")])),
                row_shares=[3, 4, 2]),
            rrb.Vertical(
                rrb.TimeSeriesView(
                    origin="worst", name=f"worst motor {worst}: torque (N·m) against its "
                    f"±{head.limit_Nm:.2f} N·m {head.quadrant} limit; phases marked",
                    axis_y=rrb.ScalarAxis(range=(-span, span)),
                    axis_x=rrb.TimeAxis(view_range=rr.TimeRange(
                        rr.TimeRangeBoundary.absolute(seconds=0.0),
                        rr.TimeRangeBoundary.absolute(seconds=WORST_ROOM * duration_s)))
                    if duration_s > 0 else None,
                    plot_legend=rrb.PlotLegend("RightBottom")),
                rrb.Horizontal(
                    rrb.TimeSeriesView(origin="share", name=f"|demand| / limit (%): A {colours}; "
                                       "B darker",
                                       axis_y=rrb.ScalarAxis(range=(0.0, 120.0)),
                                       plot_legend=rrb.PlotLegend(visible=False)),
                    rrb.Tabs(
                        *below,
                        rrb.TimeSeriesView(origin="contact/normal",
                                           name="foot normal force (N)",
                                           plot_legend=rrb.PlotLegend("RightBottom")),
                        *[torques(leg) for leg in legs],
                        *body,
                        rrb.TimeSeriesView(origin="body/tilt_deg", name="tilt (deg)"),
                        rrb.TimeSeriesView(origin="contact/tangential",
                                           name="foot tangential force (N)"),
                        rrb.TimeSeriesView(origin="loop_gap_um", name="loop gap (µm)"),
                        rrb.TimeSeriesView(origin="joints/angle", name="joint angles (rad)"),
                        rrb.TimeSeriesView(origin="joints/speed", name="joint speeds (rad/s)"),
                        rrb.TimeSeriesView(origin="stats", name="statistics window")),
                    column_shares=[3, 2]),
                row_shares=[1, 1]),
            column_shares=[2, 3]),
        rrb.BlueprintPanel(state="collapsed"), rrb.SelectionPanel(state="collapsed"),
        rrb.TimePanel(state="collapsed", timeline=TIMELINE))


def verdict_text(sig: Signals, legs, head: Headline, params: Params, summary: Summary) -> str:
    """The verdict panel (markdown): the verdict and the check that decided it, the worst
    motor's figure against its limit (N·m and share) and when its demand peaked (in which
    phase), the thresholds, the phases, the run's answer."""
    verdict = verdict_word(summary["verdict"])
    check = summary.get("deciding_check")
    m = (summary.get("legs") or {}).get(head.leg, {}).get(head.motor, {})
    torque = ((m.get("checks") or {}).get("torque") or {})
    i, j = list(legs).index(head.leg), MOTORS.index(head.motor)
    start, end = summary["window_s"]
    inside = (sig.t > start) & (sig.t <= end) if len(sig.t) else np.zeros(0, bool)
    demand = (np.where(inside, np.nan_to_num(np.abs(sig.command[:, i, j]), nan=-np.inf),
                       -np.inf) if len(sig.t) else [])
    k = int(np.argmax(demand)) if len(demand) and np.isfinite(np.max(demand)) else None
    when = ""
    if k is not None:
        t = float(sig.t[k])
        phase = next((n for n, a, b in head.phases if a <= t <= b), "")
        when = (f" Its demand peaks at {demand[k]:.2f} N·m at t = {t:.2f} s"
                + (f" ({phase})" if phase else "") + ".")
    figure_line = (f"**Worst motor {head.leg} {head.motor}: {torque['torque_Nm']:.2f} N·m, "
                   f"{torque['share_of_limit'] * 100:.0f} % of its {head.limit_Nm:.2f} N·m "
                   f"{head.quadrant} limit (SF {torque['sf']:.2f}).**"
                   if torque.get("torque_Nm") is not None and torque.get("sf") is not None else
                   f"**Worst motor {head.leg} {head.motor}** (no torque figure: the run has no "
                   "verdict).")
    phases = " · ".join(f"{n} {a:.2f}–{b:.2f} s" for n, a, b in head.phases)
    return "\n\n".join([
        f"## {verdict}" + (f" by the {check} check" if check else ""),
        figure_line + when, f"**Phases:** {phases}", thresholds_text(params.checks),
        str(summary.get("answer") or "")])


def link_points(layout: RobotLayout, params: Params, states: np.ndarray) -> np.ndarray:
    """World positions (rows, legs, 6, 3) in m of the joints A, C, E, F, B, D of every leg for
    plant states (rows, nx): the 5-bar's forward kinematics (the seed's E branch) of the motor
    angles in the leg plane, placed by the hip (layout.hips_m, body frame), the leg plane's
    rotation in the body and the body pose of the state. The plant's own E and F differ by at
    most a few loop gaps; NaN where the motor angles cannot close the loop (a run that came
    apart)."""
    q = states[:, layout.state.q_index]                                     # (rows, legs, 2) rad
    ta, tb = (np.ascontiguousarray(q[..., j].ravel()) for j in (0, 1))
    cx, cy, dx, dy, ex, ey, fx, fy = forward_points(params.leg.core, ta, tb,
                                                    np.ones_like(ta), True)
    a, b = (np.broadcast_to(p, (ta.size, 2)) for p in (params.leg.a, params.leg.b))
    plane = np.stack([a, np.stack([cx, cy], -1), np.stack([ex, ey], -1), np.stack([fx, fy], -1),
                      b, np.stack([dx, dy], -1)], 1).reshape(q.shape[:2] + (6, 2))
    in_body = plane_to_body(layout.hips_m[:, None, :], plane)
    pose = states[:, layout.state.body_q:layout.state.body_q + 7]                 # quaternion wxyz, position
    r_world_body = body_rotations(np.ascontiguousarray(pose[:, :4]))
    return pose[:, None, None, 4:] + np.einsum("sij,slpj->slpi", r_world_body, in_body)


def run_events(sig: Signals, legs):
    """The run's events (events.detect_events) from its foot forces and body height."""
    return detect_events(sig.t, np.linalg.norm(sig.foot_force_world, axis=-1), sig.body_p[:, 2],
                         legs)


def write_recording(path: Path, sig: Signals, record: SimulationRecord, summary: Summary,
                    name: str = "") -> Path:
    """Write the run's .rrd file atomically (complete with its footer, then renamed into place)
    from its signals (signals.signals), its record (the 3-D poses come from the recorded plant
    states) and its summary (statistics window, per-cycle peaks). name: the run's name in its
    recording id (e.g. an envelope's maneuver), beside the gait and the closure."""
    scenario = record.scenario
    path.parent.mkdir(parents=True, exist_ok=True)
    title = "-".join(filter(None, ("fivebar_drake", name, scenario.gait.kind,
                                   scenario.closure.kind)))
    legs = record.layout.legs
    head = headline(sig, legs, record.params, summary)
    with recording_file(path, title,
                        blueprint(legs, float(sig.body_p[0, 2]) if len(sig.t) else 0.0, head,
                                  bool(summary["periodic"]),
                                  float(sig.t[-1]) if len(sig.t) else 0.0)) as rec:
        rec.log("verdict", rr.TextDocument(verdict_text(sig, legs, head, record.params, summary),
                                           media_type=rr.MediaType.MARKDOWN), static=True)
        if len(sig.t):
            _log_scene(rec, sig, record)
            names = force_names(sig, legs)
            _log_series(rec, sig, legs, record.params, summary, names)
            _log_headline(rec, sig, legs, record.params, head)
            _log_events(rec, sig, legs, names)
    return path


def _log_headline(rec, sig: Signals, legs, params: Params, head: Headline):
    """worst/: the worst motor's demand, applied and static torques, its limits and the phase
    boundaries (vertical lines); share/<leg>/<A|B>: every motor's demand over its limit at
    its speed, in the quadrant of each sample (%)."""
    i, j = list(legs).index(head.leg), MOTORS.index(head.motor)
    ends = sig.t[[0, -1]]
    for name in WORST_SERIES:
        field, shade, width, label, _ = TORQUE_SERIES[name]
        scalars(rec, f"worst/{name}", sig.t, getattr(sig, field)[:, i, j],
                f"{head.leg} {head.motor} {label}", MOTOR_SHADES[head.motor][shade], width)
    for sign, side in ((1, "pos"), (-1, "neg")):
        scalars(rec, f"worst/limit_{side}", ends, [sign * head.limit_Nm] * 2,
                f"{head.quadrant} limit ±{head.limit_Nm:.2f} N·m", LIMIT_COLOR, 1.5)
    span = 1.15 * head.limit_Nm
    for k, (name, start, _) in enumerate(head.phases):
        path = f"worst/phase_{k}"
        rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=[start, start])],
                         columns=rr.Scalars.columns(scalars=[-span, span]))
        rec.log(path, rr.SeriesLines(names=f"{name} from {start:.2f} s",
                                     colors=PHASE_COLORS[k % len(PHASE_COLORS)], widths=1.0,
                                     aggregation_policy="MinMax"), static=True)
    up, lo = params.motor.limits(sig.qd)
    share = np.where(sig.command >= 0, sig.command / up, sig.command / lo) * 100.0
    for i, leg in enumerate(legs):
        for j, m in enumerate(MOTORS):
            scalars(rec, f"share/{leg}/{m}", sig.t, np.abs(share[:, i, j]), f"{leg} {m}",
                    _motor_colour(i, m), MOTOR_WIDTHS[m])
    scalars(rec, "share/limit", ends, [100.0, 100.0], "limit 100 %", LIMIT_COLOR, 1.5)


def _motor_colour(i: int, motor: str):
    """Leg i's colour for motor A, a darker one for B."""
    return LEG_COLORS[i] if motor == MOTORS[0] else tuple(int(c * 0.55) for c in LEG_COLORS[i])


def _log_scene(rec, sig: Signals, record: SimulationRecord):
    b = record.params.body
    low, high = sig.body_p[:, :2].min(0) - GROUND_MARGIN_M, sig.body_p[:, :2].max(0) + \
        GROUND_MARGIN_M
    rec.log("world/ground", rr.Boxes3D(centers=[[*(low + high) / 2, -0.006]],
                                       half_sizes=[[*(high - low) / 2, 0.005]],
                                       colors=[[95, 105, 95]]), static=True)
    lines = [np.arange(np.ceil(lo / GRID_M), np.floor(hi / GRID_M) + 1) * GRID_M
             for lo, hi in zip(low, high)]
    rec.log("world/ground/grid", rr.LineStrips3D(np.array(
        [[[x, low[1], 0.0], [x, high[1], 0.0]] for x in lines[0]]
        + [[[low[0], y, 0.0], [high[0], y, 0.0]] for y in lines[1]]),
        radii=0.0008, colors=[[150, 160, 150]]), static=True)
    rec.log("world/body", rr.Boxes3D(half_sizes=[[b.length_m / 2, b.width_m / 2, b.height_m / 2]],
                                     colors=[[150, 150, 165]]), static=True)
    t = sig.t
    frames = pose_frames(t, record.scenario.pose_rate_hz)
    time = [rr.TimeColumn(TIMELINE, duration=t[frames])]
    quat = sig.body_quat[frames]
    rec.send_columns("world/body", indexes=time, columns=rr.Transform3D.columns(
        translation=sig.body_p[frames], quaternion=np.column_stack([quat[:, 1:], quat[:, :1]])))
    under = sig.body_p[frames] * [1.0, 1.0, 0.0]                  # the ground under the body
    rec.send_columns("world/follow", indexes=time, columns=rr.Transform3D.columns(
        translation=under))
    points = link_points(record.layout, record.params, record.table["state"][frames])
    for i, leg in enumerate(record.layout.legs):
        strips = np.ascontiguousarray(points[:, i][:, LEG_STRIPS])     # (frames, strips, 4, 3)
        rec.send_columns(f"world/legs/{leg}", indexes=time, columns=rr.LineStrips3D.columns(
            strips=strips.reshape(-1, *strips.shape[2:])).partition(
                np.full(len(frames), len(LEG_STRIPS))))
        rec.log(f"world/legs/{leg}", rr.LineStrips3D.from_fields(
            radii=0.004, colors=[MOTOR_SHADES[m][1] for m in MOTORS]), static=True)
        rec.log(f"world/feet/{leg}", rr.LineStrips3D([points[:, i, 3]], radii=0.0015,
                                                     colors=[LEG_COLORS[i]]), static=True)
        origin = points[:, i, 3] - np.array([0.0, 0.0, b.foot_radius_m])
        force = sig.foot_force_world[frames, i] * FORCE_ARROW_M_PER_N
        rec.send_columns(f"world/forces/{leg}", indexes=time, columns=rr.Arrows3D.columns(
            origins=origin, vectors=force))
        rec.log(f"world/forces/{leg}", rr.Arrows3D.from_fields(colors=[[40, 200, 80]],
                                                               radii=0.002), static=True)


def _log_series(rec, sig: Signals, legs, params: Params, summary: Summary, names):
    limit, braking = params.motor.peak_torque_Nm, params.motor.braking_peak_torque_Nm
    ends = sig.t[[0, -1]]
    start, end = summary["window_s"]
    cycle_ends = start + summary["cycle_s"] * np.arange(1, summary["cycles_in_window"] + 1)
    force = sig.foot_force_plane
    first = {i: name for i, (name, drawn) in enumerate(names) if drawn}
    for i, leg in enumerate(legs):
        scalars(rec, f"loop_gap_um/{leg}", sig.t, sig.gap[:, i] * 1e6, leg, LEG_COLORS[i])
        for kind, axis in (("normal", 1), ("tangential", 0)):
            scalars(rec, f"contact/{kind}/{leg}", sig.t, force[:, i, axis],
                    first.get(i, leg), LEG_COLORS[i], 1.5, visible=i in first)
        for sign, side in ((1, "pos"), (-1, "neg")):
            scalars(rec, f"torque/{leg}/limit_{side}", ends, [sign * limit] * 2,
                    f"driving limit ±{limit:.2f} N·m", LIMIT_COLOR, 1.0)
            scalars(rec, f"torque/{leg}/braking_limit_{side}", ends, [sign * braking] * 2,
                    f"braking limit ±{braking:.2f} N·m", LIMIT_COLOR, 0.5)
        for j, m in enumerate(MOTORS):
            scalars(rec, f"joints/angle/{leg}/{m}", sig.t, sig.q[:, i, j], f"{leg} {m}",
                    LEG_COLORS[i], MOTOR_WIDTHS[m])
            scalars(rec, f"joints/speed/{leg}/{m}", sig.t, sig.qd[:, i, j], f"{leg} {m}",
                    LEG_COLORS[i], MOTOR_WIDTHS[m])
            for name, (field, shade, width, label, _) in TORQUE_SERIES.items():
                scalars(rec, f"torque/{leg}/{m}/{name}", sig.t, getattr(sig, field)[:, i, j],
                        f"{m} {label}", MOTOR_SHADES[m][shade], width)
            if len(cycle_ends):
                scalars(rec, f"cycle_peak/{leg}/{m}", cycle_ends,
                        summary["legs"][leg][m]["per_cycle_peak_Nm"], f"{leg} {m}",
                        _motor_colour(i, m), MOTOR_WIDTHS[m])
                rec.log(f"cycle_peak/{leg}/{m}", rr.SeriesPoints(
                    names=f"{leg} {m}", colors=_motor_colour(i, m), marker_sizes=3.0,
                    markers="Circle" if m == MOTORS[0] else "Square"), static=True)
    if len(cycle_ends):
        scalars(rec, "cycle_peak/limit", cycle_ends[[0, -1]] if len(cycle_ends) > 1 else
                np.array([start, cycle_ends[0]]), [limit] * 2, f"limit {limit:.2f} N·m",
                LIMIT_COLOR, 1.5)
    scalars(rec, "body/height_m", sig.t, sig.body_p[:, 2], "height (m)", (120, 220, 120), 1.5)
    scalars(rec, "body/forward_speed_m_s", sig.t, sig.body_v[:, 0], "forward speed (m/s)",
            (120, 200, 255), 1.5)
    scalars(rec, "body/forward_speed_m_s/gait", ends, [summary["gait_speed_m_s"]] * 2,
            "gait speed (m/s)", (160, 160, 160), 1.0)
    scalars(rec, "body/tilt_deg", sig.t, sig.tilt_deg, "tilt (deg)", (255, 200, 80), 1.5)
    scalars(rec, "stats/window", sig.t, ((sig.t > start) & (sig.t <= end)).astype(float),
            "statistics window")


def force_names(sig: Signals, legs) -> list[tuple[str, bool]]:
    """Per leg, the name of its foot force in the legends and whether its curve is drawn: legs
    whose foot forces coincide (a jump's four feet) are drawn once, by the first of them, named
    together ("FL = FR")."""
    force = sig.foot_force_plane
    groups = coinciding((force[..., 1], force[..., 0]), (FORCE_SAME_N, FORCE_SAME_N))
    name = {i: " = ".join(legs[k] for k in g) for g in groups for i in g}
    return [(name[i], any(g[0] == i for g in groups)) for i in range(len(legs))]


def _log_events(rec, sig: Signals, legs, names):
    """The events as a text log and as markers: a flight's on the body height plot, a foot's on
    its normal force (named as its leg's curve: one legend entry per curve, the markers' shapes
    say lift-off or touchdown, the event log which)."""
    events = run_events(sig, legs)
    if not events:
        return
    rec.send_columns("events", indexes=[rr.TimeColumn(TIMELINE, duration=[e.t_s for e in events])],
                     columns=rr.TextLog.columns(text=[e.text for e in events],
                                                level=["INFO"] * len(events)))
    for kind, i, leg in [(k, 0, "") for k in FLIGHT_KINDS] + [
            (k, i, leg) for k in FOOT_KINDS for i, leg in enumerate(legs)]:
        times = [e.t_s for e in events if e.kind == kind and e.leg == leg]
        if not times:
            continue
        rows = np.searchsorted(sig.t, times)
        path, values = ((f"body/height_m/{kind}", sig.body_p[rows, 2]) if not leg else
                        (f"contact/normal/{leg}/{kind}", sig.foot_force_plane[rows, i, 1]))
        rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=times)],
                         columns=rr.Scalars.columns(scalars=values))
        rec.log(path, rr.SeriesPoints(names=names[i][0] if leg else kind,
                                      markers=EVENT_MARKERS[kind], marker_sizes=5.0,
                                      colors=LEG_COLORS[i] if leg else FLIGHT_COLOR),
                static=True)
