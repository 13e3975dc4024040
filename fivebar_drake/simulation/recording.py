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
  commanded, static_trot, static_contact, static_seed} and torque/<leg>/limit_{pos,neg}
  (N·m; A in blues, B in oranges: applied bold, commanded light, static dark, static_contact
  and static_seed in the legend, drawn once picked); joints/angle/<leg>/<A|B> (rad),
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
import numpy as np
import rerun as rr
import rerun.blueprint as rrb

from fivebar_drake.core.rerun_files import TIMELINE, pose_frames, recording_file, scalars
from fivebar_drake.core.rotation import body_rotations
from fivebar_drake.core.summary_schema import Summary
from fivebar_drake.mechanisms.fivebar import MOTORS, forward_points
from fivebar_drake.robots.quadruped.params import Params
from fivebar_drake.robots.quadruped.plant import RobotLayout
from fivebar_drake.robots.quadruped.legs import plane_to_body
from fivebar_drake.simulation.events import FLIGHT_KINDS, FOOT_KINDS, detect_events
from fivebar_drake.simulation.runner import SimulationRecord
from fivebar_drake.simulation.signals import Signals


RECORDING_FILE = "run.rrd"
FORCE_ARROW_M_PER_N = 0.001    # 1 mm of arrow per newton
# of link_points' A, C, E, F, B, D: A-C-E-F and B-D-E-F (link DE carries the foot F)
LEG_STRIPS = ([0, 1, 2, 3], [4, 5, 2, 3])
GROUND_MARGIN_M = 0.4          # the ground patch reaches this far beyond the path of the body
GRID_M = 0.1                   # spacing of the lines on the ground (the robot passes over them)
EYE_OFFSET_M = (0.40, -0.80, 0.25)   # the camera from the body at standing height (world/follow)
# per torque series: its Signals field, the shade of the motor's hue (0 light .. 2 dark), line
# width, drawn at first (else once picked in the legend)
TORQUE_SERIES = {"applied": ("applied", 1, 2.5, True), "commanded": ("command", 0, 1.2, True),
                 "static_trot": ("static_trot", 2, 1.5, True),
                 "static_contact": ("static_contact", 1, 1.0, False),
                 "static_seed": ("static_seed", 2, 1.0, False)}
MOTOR_SHADES = {"A": ((150, 200, 240), (40, 120, 220), (20, 50, 140)),      # blues
                "B": ((255, 190, 120), (240, 110, 20), (150, 55, 0))}       # oranges
LIMIT_COLOR = (200, 40, 40)
LEG_COLORS = ((102, 194, 165), (252, 141, 98), (141, 160, 203), (231, 138, 195))
LEG_COLOR_NAMES = ("green", "orange", "blue", "pink")
MOTOR_WIDTHS = {"A": 1.6, "B": 0.8}   # per-leg plots (joints, per-cycle peaks): A bold, B thin
EVENT_MARKERS = {"takeoff": "Up", "apex": "Diamond", "touchdown": "Down", "lift-off": "Up"}
FLIGHT_COLOR = (255, 230, 0)


def blueprint(legs, height_m: float) -> rrb.Blueprint:
    """The viewer's layout: the robot seen from the frame world/follow (it moves with the body
    over the ground, so the robot stays framed while the ground and the foot traces pass under
    it; the camera EYE_OFFSET_M from a point height_m above the ground under the body) and the
    event log on the left; on the right the four legs' motor torques, the body's height, speed
    and tilt, and tabs with the foot forces, loop gaps, joint angles and speeds, per-cycle peaks
    and the statistics window. The torque and force plots name their colours in their titles
    (their legends would cover the curves; FL's shows the series)."""
    torque = [rrb.TimeSeriesView(origin=f"torque/{leg}", name=f"{leg} torque (N·m): A blue, B "
                                 "orange", plot_legend=rrb.PlotLegend("LeftBottom", visible=k == 0))
              for k, leg in enumerate(legs)]
    colours = ", ".join(f"{leg} {name}" for leg, name in zip(legs, LEG_COLOR_NAMES))
    look = np.array([0.0, 0.0, height_m])
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(
                    origin="world/follow", contents="world/**",
                    name="robot (the camera follows the body)",
                    line_grid=rrb.LineGrid3D(visible=False),
                    eye_controls=rrb.EyeControls3D(position=look + EYE_OFFSET_M,
                                                   look_target=look, eye_up=[0.0, 0.0, 1.0])),
                rrb.TextLogView(origin="events", name="events", columns=rrb.TextLogColumns(
                    text_log_columns=[rrb.encodings.TextLogColumn(kind, visible=kind == "Body")
                                      for kind in ("EntityPath", "LogLevel", "Body")])),
                row_shares=[3, 1]),
            rrb.Vertical(
                rrb.Grid(*torque, grid_columns=2),
                rrb.Horizontal(
                    rrb.TimeSeriesView(origin="body/height_m", name="body height (m)"),
                    rrb.TimeSeriesView(origin="body/forward_speed_m_s",
                                       name="forward speed (m/s)"),
                    rrb.TimeSeriesView(origin="body/tilt_deg", name="tilt (deg)")),
                rrb.Tabs(rrb.TimeSeriesView(origin="contact/normal",
                                            name=f"foot normal force (N): {colours}",
                                            plot_legend=rrb.PlotLegend(visible=False)),
                         rrb.TimeSeriesView(origin="contact/tangential",
                                            name="foot tangential force (N)"),
                         rrb.TimeSeriesView(origin="loop_gap_um", name="loop gap (µm)"),
                         rrb.TimeSeriesView(origin="joints/angle", name="joint angles (rad)"),
                         rrb.TimeSeriesView(origin="joints/speed", name="joint speeds (rad/s)"),
                         rrb.TimeSeriesView(origin="cycle_peak", name="per-cycle peaks (N·m)"),
                         rrb.TimeSeriesView(origin="stats", name="statistics window")),
                row_shares=[5, 2, 2]),
            column_shares=[2, 3]),
        rrb.BlueprintPanel(state="collapsed"), rrb.SelectionPanel(state="collapsed"),
        rrb.TimePanel(state="collapsed", timeline=TIMELINE))


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
    with recording_file(path, title,
                        blueprint(record.layout.legs, float(sig.body_p[0, 2]) if len(sig.t)
                                  else 0.0)) as rec:
        if len(sig.t):
            _log_scene(rec, sig, record)
            _log_series(rec, sig, record.layout.legs, record.params, summary)
            _log_events(rec, sig, record.layout.legs)
    return path


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


def _log_series(rec, sig: Signals, legs, params: Params, summary: Summary):
    limit = params.motor.peak_torque_Nm
    ends = sig.t[[0, -1]]
    start, end = summary["window_s"]
    cycle_ends = start + summary["cycle_s"] * np.arange(1, summary["cycles_in_window"] + 1)
    for i, leg in enumerate(legs):
        scalars(rec, f"loop_gap_um/{leg}", sig.t, sig.gap[:, i] * 1e6, leg, LEG_COLORS[i])
        scalars(rec, f"contact/normal/{leg}", sig.t, sig.foot_force_plane[:, i, 1], leg,
                LEG_COLORS[i], 1.5)
        scalars(rec, f"contact/tangential/{leg}", sig.t, sig.foot_force_plane[:, i, 0], leg,
                LEG_COLORS[i], 1.5)
        for sign, side in ((1, "pos"), (-1, "neg")):
            scalars(rec, f"torque/{leg}/limit_{side}", ends, [sign * limit] * 2,
                    f"{'+' if sign > 0 else '-'}limit {limit:g}", LIMIT_COLOR, 1.0)
        for j, m in enumerate(MOTORS):
            scalars(rec, f"joints/angle/{leg}/{m}", sig.t, sig.q[:, i, j], f"{leg} {m}",
                    LEG_COLORS[i], MOTOR_WIDTHS[m])
            scalars(rec, f"joints/speed/{leg}/{m}", sig.t, sig.qd[:, i, j], f"{leg} {m}",
                    LEG_COLORS[i], MOTOR_WIDTHS[m])
            for name, (field, shade, width, visible) in TORQUE_SERIES.items():
                scalars(rec, f"torque/{leg}/{m}/{name}", sig.t, getattr(sig, field)[:, i, j],
                        f"{m} {name}", MOTOR_SHADES[m][shade], width, visible)
            if len(cycle_ends):
                scalars(rec, f"cycle_peak/{leg}/{m}", cycle_ends,
                        summary["legs"][leg][m]["per_cycle_peak_Nm"], f"{leg} {m}",
                        LEG_COLORS[i], MOTOR_WIDTHS[m])
    scalars(rec, "body/height_m", sig.t, sig.body_p[:, 2], "height (m)", (120, 220, 120), 1.5)
    scalars(rec, "body/forward_speed_m_s", sig.t, sig.body_v[:, 0], "forward speed (m/s)",
            (120, 200, 255), 1.5)
    scalars(rec, "body/forward_speed_m_s/gait", ends, [summary["gait_speed_m_s"]] * 2,
            "gait speed (m/s)", (160, 160, 160), 1.0)
    scalars(rec, "body/tilt_deg", sig.t, sig.tilt_deg, "tilt (deg)", (255, 200, 80), 1.5)
    scalars(rec, "stats/window", sig.t, ((sig.t > start) & (sig.t <= end)).astype(float),
            "statistics window")


def _log_events(rec, sig: Signals, legs):
    """The events as a text log and as markers: a flight's on the body height plot, a foot's on
    its normal force."""
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
        rec.log(path, rr.SeriesPoints(names=f"{leg} {kind}".strip(),
                                      markers=EVENT_MARKERS[kind], marker_sizes=5.0,
                                      colors=LEG_COLORS[i] if leg else FLIGHT_COLOR),
                static=True)
