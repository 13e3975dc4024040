"""The quadruped simulation: a credible trot, per-step measurement, whole-cycle statistics,
control delay, closures, recording, CLI, bad scenarios."""

import dataclasses
import json

import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RotationMatrix
import pytest
from pydrake.systems.analysis import Simulator
from rerun.chunk import RrdReader

from helpers import told
from fivebar_drake.cli import main
from fivebar_drake.gaits import Trot
from fivebar_drake.mechanisms.fivebar import UnreachableError, foot_jacobian, forward
from fivebar_drake.pipeline import summarize_run
from fivebar_drake.core.rerun_files import read_series
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.robots.quadruped.plant import set_standing_pose
from fivebar_drake.simulation.builder import build_diagram, check_run
from fivebar_drake.simulation.signals import signals
from style_rules import report_violations

TEST_DURATION_S = 4.5   # 0.5 s standing, 1 s ramp, 3 whole trot cycles
RPY_DURATION_S = 2.5    # the explicit bushing runs at a quarter of real time: one whole cycle


def _run(simulated, closure, duration_s=TEST_DURATION_S):
    record = simulated(duration_s=duration_s, closure=closure)
    return record.scenario, record.params, record, signals(record), summarize_run(record)


@pytest.fixture(scope="module")
def runs(simulated):
    """The default trot with each closure: closure -> (scenario, params, record, signals,
    summary); bushing_rpy for one whole cycle after the ramp."""
    return {"ball": _run(simulated, "ball"), "bushing": _run(simulated, "bushing"),
            "bushing_rpy": _run(simulated, "bushing_rpy", RPY_DURATION_S)}


@pytest.fixture(params=["bushing", "ball"])
def run(request, runs):
    return runs[request.param]


@pytest.mark.slow
def test_default_trot_is_credible(run):
    """Upright, walking at >= 70 % of the path's speed, swing feet clear, nothing NaN."""
    scenario, params, record, sig, summary = run
    assert not record.error and summary["completed"]
    assert np.all(np.isfinite(record.table["state"]))
    quat = sig.body_quat / np.linalg.norm(sig.body_quat, axis=1, keepdims=True)
    # body z against up, by Drake's rotation of the quaternion (not the package's formula)
    tilt = np.degrees(np.arccos([RotationMatrix(Quaternion(q)).matrix()[2, 2] for q in quat]))
    assert tilt.max() <= 10.0
    start, end = summary["window_s"]
    inside = (sig.t > start) & (sig.t <= end)
    x = sig.body_p[inside, 0]
    speed = (x[-1] - x[0]) / (sig.t[inside][-1] - sig.t[inside][0])
    gait_speed = 2 * params.gait.a_m / (params.gait.duty_factor * params.gait.period_s)
    assert speed >= 0.7 * gait_speed
    assert gait_speed == pytest.approx(Trot().stance_speed(params.gait))
    # swing feet, from the schedule and the measured ground force (> 1 N: on the ground):
    # never dragged through mid-swing; off the ground for >= 80 % of the swing (the rest is an
    # early touchdown at its end, where the catch reflex sends a foot under a sinking hip)
    tau = sig.t[inside] - scenario.stand_s
    for i, phase in enumerate(scenario.phases_rad):
        u = np.mod(params.gait.frequency_hz * tau + phase / (2 * np.pi), 1.0)
        swing = u < 1 - params.gait.duty_factor
        s = u / (1 - params.gait.duty_factor)
        loaded = sig.foot_force_world[inside, i, 2] > 1.0
        mid = swing & (s >= 0.1) & (s <= 0.7)
        assert np.mean(loaded[mid]) <= 0.02, record.layout.legs[i]
        assert np.mean(loaded[swing]) <= 0.20, record.layout.legs[i]
        assert summary["swing_clear_fraction"][record.layout.legs[i]] == pytest.approx(
            1 - np.mean(loaded[swing]), abs=0.02)


@pytest.mark.slow
def test_loop_gap_below_a_tenth_of_a_millimetre(run):
    scenario, params, record, sig, summary = run
    assert sig.gap.shape == (len(sig.t), 4)
    assert np.max(sig.gap) < 1e-4


@pytest.mark.slow
def test_applied_torque_matches_contact_load_in_stance(run):
    """Per step measurement: in full stance the motors carry the ground force (the leg is
    light), so the applied torque and -J^T F agree within 10 % RMS per motor; the torque split
    (contact + links + rotor + friction) sums back to the applied torque within 5 % RMS."""
    scenario, params, record, sig, summary = run
    start, end = summary["window_s"]
    inside = (sig.t > start) & (sig.t <= end)
    for i in range(4):
        stance = inside & sig.stance[:, i] & (sig.foot_force_plane[:, i, 1] > 5.0)
        for j in range(2):
            applied = sig.applied[stance, i, j]
            rms = np.sqrt(np.mean(applied**2))
            err = applied - sig.static_contact[stance, i, j]
            assert np.sqrt(np.mean(err**2)) < 0.10 * rms, (i, j)
            total = sum(x[inside, i, j] for x in (sig.static_contact, sig.links, sig.rotor,
                                                   sig.friction))
            resid = sig.applied[inside, i, j] - total
            assert np.sqrt(np.mean(resid**2)) < 0.05 * np.sqrt(np.mean(sig.applied[inside, i, j]**2))


@pytest.mark.slow
def test_contact_torque_is_jacobian_transpose_times_force(run):
    """-J^T F at one sample, J_F by finite differences of FK, the contact point's offset by
    hand (flat ground: the sphere's lowest point), F rotated by hand."""
    scenario, params, record, sig, summary = run
    k = int(np.argmax(sig.foot_force_plane[:, 0, 1]))            # FL under load
    q = sig.q[k, 0]
    h = 1e-7
    jf = np.stack([(forward(params.leg, q + h * e).f - forward(params.leg, q - h * e).f) / (2 * h)
                   for e in np.eye(2)], -1)
    assert np.allclose(foot_jacobian(params.leg, forward(params.leg, q)), jf, atol=1e-6)
    # a point fixed to link DE at offset d from F moves with J_F + perp(d) dphi_DE/dq
    pose = lambda qq: forward(params.leg, qq)                                   # noqa: E731
    ang = lambda qq: np.arctan2(*(pose(qq).f - pose(qq).d)[::-1])               # noqa: E731
    dphi = np.array([(ang(q + h * e) - ang(q - h * e)) / (2 * h) for e in np.eye(2)])
    w, x, y, z = sig.body_quat[k] / np.linalg.norm(sig.body_quat[k])
    r_wb = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
    r_bp = np.array([[-1.0, 0, 0], [0, 0, 1.0], [0, 1.0, 0]])   # leg plane axes in the body
    r_wp = r_wb @ r_bp
    d = (r_wp.T @ np.array([0, 0, -params.body.foot_radius_m]))[:2]
    jp = jf + np.outer([-d[1], d[0]], dphi)
    force = sig.foot_force_plane[k, 0]
    assert np.allclose(sig.foot_force_world[k, 0], r_wp[:, :2] @ force, atol=1e-9)
    assert np.allclose(sig.static_contact[k, 0], -jp.T @ force, rtol=1e-5, atol=1e-5)


@pytest.mark.slow
@pytest.mark.parametrize("closure, tolerance", [("bushing", 0.10), ("bushing_rpy", 0.15)])
def test_closures_agree_on_rms_torque(runs, closure, tolerance):
    """Per-motor RMS applied torque over the first whole cycle after the ramp (the same
    recorded intervals of both runs) against the rigid ball closure: the implicit compliant
    bushing within 10 %, the explicit bushing within 15 %."""
    scenario, ball = runs["ball"][0], runs["ball"][3]
    other = runs[closure][3]
    start = scenario.stand_s + scenario.ramp_s
    window = [(sig.t > start + 1e-9) & (sig.t <= start + 1.0 / runs["ball"][1].gait.frequency_hz
                                        + 1e-9) for sig in (ball, other)]
    assert np.array_equal(ball.t[window[0]], other.t[window[1]]) and window[0].sum() > 100
    assert runs[closure][4]["max_loop_gap_m"] < 1e-4
    rms = [np.sqrt(np.mean(sig.applied[w] ** 2, axis=0)) for sig, w in zip((ball, other), window)]
    np.testing.assert_allclose(rms[1], rms[0], rtol=tolerance)


@pytest.mark.slow
def test_measured_ground_forces_carry_the_robot(run):
    """Vertical momentum over whole cycles: the feet's mean vertical force (from the
    generalized contact forces) equals the weight plus the body's momentum change."""
    scenario, params, record, sig, summary = run
    start, end = summary["window_s"]
    inside = (sig.t > start) & (sig.t <= end)
    weight = params.robot.total_mass_kg * params.robot.gravity_m_s2
    mean_fz = sig.foot_force_world[inside, :, 2].sum(1).mean()
    k0, k1 = np.flatnonzero(inside)[[0, -1]]
    dp = params.robot.total_mass_kg * (sig.body_v[k1, 2] - sig.body_v[k0 - 1, 2]) / (end - start)
    assert mean_fz == pytest.approx(weight + dp, rel=0.01)


@pytest.mark.slow
def test_touchdowns_keep_the_body_carried(run):
    """Feet take load on measured contact (issue 28): over the statistics window the delivered
    vertical force (every plant step's contact forces, interval means) stays within 0.9 .. 1.33
    of the weight (a foot given load before it touched made it dip to 0.75 and overshoot to
    1.57), and each leg's quasi-static torque -J_P^T F of the measured ground force peaks within
    0.75 .. 1.33 of its applied torque's peak (a touchdown impact it did not apply made it 1.45)."""
    scenario, params, record, sig, summary = run
    start, end = summary["window_s"]
    inside = (sig.t > start) & (sig.t <= end)
    weight = params.robot.total_mass_kg * params.robot.gravity_m_s2
    share = sig.ground_force[inside, 2] / weight
    assert 0.9 <= share.min() and share.max() <= 1.33, (share.min(), share.max())
    reported = summary["vertical_support"]
    assert reported["least_share"] == pytest.approx(share.min(), rel=1e-9)
    assert reported["largest_share"] == pytest.approx(share.max(), rel=1e-9)
    for leg in range(sig.applied.shape[1]):
        ratio = (np.abs(sig.static_contact[inside, leg]).max()
                 / np.abs(sig.applied[inside, leg]).max())
        assert 0.75 <= ratio <= 1.33, (leg, ratio)


@pytest.mark.slow
def test_summary_text_follows_the_parameters(runs):
    """summary.md and the answer take their figures from the parameters used, none written in."""
    from fivebar_drake.simulation.summary_text import answer, answer_details, markdown

    scenario, params, record, sig, summary = runs["ball"]
    other = dataclasses.replace(params, robot=dataclasses.replace(params.robot, structure_kg=2.5),
                                motor=dataclasses.replace(
                                    params.motor, peak_current_A=params.motor.peak_current_A * 1.4))
    again = {**summary, "answer_details": answer_details(summary, other)}
    text = markdown(again, other).split(summary["answer"])[1] + answer(summary, other)
    assert f"{other.robot.weight_share_kg:.3f} kg" in text
    assert f"{other.motor.peak_torque_Nm:.2f} N·m driving" in text and "7.00 N·m" in text
    assert f"{params.robot.weight_share_kg:.3f}" not in text


@pytest.mark.slow
def test_window_is_whole_cycles(run):
    scenario, params, record, sig, summary = run
    start, end = summary["window_s"]
    period = params.gait.period_s
    for edge in (start, end):
        cycles = (edge - scenario.stand_s) / period                  # gait time in cycles
        assert cycles == pytest.approx(round(cycles), abs=1e-9)
    assert start >= scenario.stand_s + scenario.ramp_s - 1e-9
    assert summary["cycles_in_window"] == round((end - start) / period) == 3
    assert summary["verdict"] in ("pass", "warn", "fail")
    m = summary["legs"]["RL"]["A"]
    assert m["safety_factor"] == pytest.approx(params.motor.peak_torque_Nm / m["demand_p99_Nm"])
    lo, hi = m["per_cycle"]["peak_torque_Nm"]
    assert lo <= hi <= m["peak_torque_Nm"] + 1e-12


@pytest.mark.slow
def test_short_run_is_insufficient(tmp_path, capsys):
    out = tmp_path / "short"
    assert main(["simulate", "--duration", "3.0", "--closure", "ball", "--out", str(out)]) == 1
    summary = json.loads((out / "summary.json").read_text())
    assert summary["verdict"] == "insufficient" and summary["cycles_in_window"] == 1
    assert "No verdict" in told(summary)
    assert "no verdict" in capsys.readouterr().err


@pytest.mark.parametrize("delay", [0, 1])
def test_controller_acts_on_the_state_sampled_at_its_tick(delay):
    """The command computed at tick k comes from the plant state at t_k (not one plant step
    later) and is released delay ticks later."""
    scenario = load_scenario(closure="ball", control_delay_periods=delay)
    params = scenario.load_params()
    diagram, setup = build_diagram(scenario, params, check_run(scenario, params))
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    plant_context = setup.plant.GetMyMutableContextFromRoot(context)
    set_standing_pose(setup.plant, plant_context, setup.instance, setup.layout.legs, params)
    simulator.Initialize()
    controller, gait = setup.controller, diagram.GetSubsystemByName("gait_source")
    period, dt = scenario.controller.control_period_s, setup.design.time_step_s
    tick = 0.7                                                  # gait running, a tick time
    simulator.AdvanceTo(tick)                                   # events at t_k not yet handled
    state_k = setup.plant.GetPositionsAndVelocities(plant_context).copy()
    simulator.AdvanceTo(tick + dt)                              # the tick's update happened
    state_next = setup.plant.GetPositionsAndVelocities(plant_context).copy()
    assert not np.allclose(state_k, state_next)
    references = gait.references(tick)
    _, _, loads, memory, _ = controller.tick_inputs(controller.GetMyContextFromRoot(context))
    expect = controller.command(references, state_k, loads, memory.copy(), tick)
    later = controller.command(references, state_next, loads, memory.copy(), tick)
    newest = controller.GetOutputPort("torque_command").Eval(
        controller.GetMyContextFromRoot(context))
    assert np.allclose(newest, expect, rtol=1e-9, atol=1e-9)
    assert not np.allclose(newest, later, rtol=1e-6, atol=1e-6)
    motor = diagram.GetSubsystemByName("motor_model")

    def released():                      # what reaches the motor model (after Drake's delay)
        return motor.GetInputPort("torque_command").Eval(motor.GetMyContextFromRoot(context))

    assert np.allclose(released(), expect) == (delay == 0)
    if delay:
        simulator.AdvanceTo(tick + period + dt)                 # one tick later: released
        assert np.allclose(released(), expect)


@pytest.mark.slow
def test_simulate_cli_writes_outputs_and_recording(tmp_path, capsys):
    out = tmp_path / "sim"
    code = main(["simulate", "--duration", str(TEST_DURATION_S), "--closure", "ball", "--out",
                 str(out)])
    printed = capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert code == (1 if summary["verdict"] == "insufficient" else 0)
    assert "rerun" in printed and str(out.resolve()) in printed and summary["answer"] in printed
    for key in ("gait", "closure", "duration_s", "completed", "cycles_in_window", "window_s",
                "max_tilt_deg", "mean_forward_speed_m_s", "gait_speed_m_s", "max_loop_gap_m",
                "real_time_factor", "verdict", "answer"):
        assert key in summary, key
    assert summary["gait"] == "trot" and summary["closure"] == "ball"
    # the answer first (docs/output_style.md): the verdict, its check, the worst motor's figure
    leg, motor = summary["worst_motor"].split()
    sf = summary["legs"][leg][motor]["checks"]["torque"]["sf"]
    assert summary["answer"].startswith(
        f"{summary['verdict'].upper()}, decided by the {summary['deciding_check']} check: "
        f"worst motor {leg} {motor}, ")
    assert f"SF {sf:.2f} (" in summary["answer"].split(". ")[0]
    assert "At 1 Hz with the trot gait the motors need" in told(summary)
    for leg in ("FL", "FR", "RL", "RR"):
        for motor in ("A", "B"):
            m = summary["legs"][leg][motor]
            for key in ("peak_torque_Nm", "p99_torque_Nm", "rms_torque_Nm", "demand_peak_Nm",
                        "demand_p99_Nm", "static_seed_Nm", "static_trot_Nm", "static_contact_Nm",
                        "dynamic_to_seed_static", "dynamic_to_trot_static", "safety_factor",
                        "verdict", "saturated_fraction", "peak_speed_rad_s",
                        "decomposition_rms_Nm"):
                assert key in m, (leg, motor, key)
            assert set(m["decomposition_rms_Nm"]) >= {"contact", "links", "rotor", "friction"}
            assert 0 <= m["saturated_fraction"] <= 1 and m["peak_torque_Nm"] > 0
            assert m["demand_p99_Nm"] <= m["demand_peak_Nm"] + 1e-12
    assert (out / "summary.md").read_text().splitlines()[2] == summary["answer"]
    assert report_violations(out / "summary.md") == []
    for name in ("summary.md", "sim_torques.png", "sim_motion.png"):
        assert (out / name).stat().st_size > 1000
    check_recording(out / "run.rrd", summary)


def rows(path, entity):
    chunks = RrdReader(path).stream().filter(content=entity, is_static=False).to_chunks()
    return sum(c.num_rows for c in chunks)


def check_recording(path, summary):
    assert path.stat().st_size > 10_000
    reader = RrdReader(path)
    duration = summary["duration_s"]
    samples = rows(path, "/torque/FL/A/applied")
    assert samples == pytest.approx(duration / summary["log_period_s"], abs=2)
    for entity in ("/torque/RR/B/commanded", "/torque/RR/B/static_contact",
                   "/torque/RR/B/static_same_loads", "/torque/RR/B/static_seed",
                   "/contact/normal/FL", "/contact/tangential/RR", "/loop_gap_um/FL",
                   "/joints/speed/RR/B", "/joints/angle/FL/A", "/body/height_m",
                   "/body/forward_speed_m_s", "/body/tilt_deg", "/stats/window"):
        assert rows(path, entity) == samples, entity
    assert rows(path, "/torque/RR/limit_pos") == 2                  # a line from start to end
    frames = rows(path, "/world/body")
    assert frames == pytest.approx(duration * 50, abs=2)            # 3-D poses at 50 Hz
    for leg in ("FL", "FR", "RL", "RR"):
        assert rows(path, f"/world/legs/{leg}") == frames
        assert rows(path, f"/world/forces/{leg}") == frames
        assert rows(path, f"/cycle_peak/{leg}/A") == summary["cycles_in_window"]
    _, gap = read_series(path, "/loop_gap_um/FL")
    assert gap.max() == pytest.approx(summary["max_loop_gap_per_leg_m"]["FL"] * 1e6, rel=1e-12)
    t, applied = read_series(path, "/torque/FL/A/applied")
    assert len(t) == samples and np.all(np.diff(t) > 0)
    start, end = summary["window_s"]
    inside = (t > start + 1e-9) & (t <= end + 1e-9)
    assert np.max(np.abs(applied[inside])) == pytest.approx(
        summary["legs"]["FL"]["A"]["peak_torque_Nm"])
    t, window = read_series(path, "/stats/window")
    assert t[window > 0].min() > start and t[window > 0].max() <= end + 1e-9
    assert reader.blueprints()                                  # the blueprint is in the file


def plant_link_points(plant, instance, layout, params, positions):
    """A, C, E, F, B, D (legs, 6, 3) in m from the plant's own body poses (Drake's kinematics
    of the tree: E and F on link DE) at the plant positions."""
    context = plant.CreateDefaultContext()
    plant.SetPositions(context, positions)
    g = params.leg
    pose = lambda leg, link: plant.EvalBodyPoseInWorld(                        # noqa: E731
        context, plant.GetBodyByName(f"{leg}_{link}", instance))
    return np.array([[pose(leg, "AC").translation(), pose(leg, "AC").multiply([g.ac_m, 0, 0]),
                      pose(leg, "DE").multiply([g.de_m, 0, 0]),
                      pose(leg, "DE").multiply([g.de_m + g.ef_m, 0, 0]),
                      pose(leg, "BD").translation(), pose(leg, "BD").multiply([g.bd_m, 0, 0])]
                     for leg in layout.legs])


@pytest.mark.slow
def test_recorded_link_points_are_the_plants(run, rng):
    """The recording's link points (5-bar FK of the motor angles, placed by the hip, the leg
    plane and the body pose; no plant) against the plant's body poses: all six within 1 nm at
    states whose loops are closed (IK poses, random body poses); at the run's states A, B, C, D
    within 1 nm and E, F within the loop gap carried through the knee: the plant's E lies on the
    circle about D within the gap of the circle about C, so |dE| <= gap / sin(angle CED), and
    F = D + (DE + EF)/DE (E - D)."""
    from pydrake.systems.framework import DiagramBuilder

    from fivebar_drake.mechanisms.fivebar import inverse, tree_positions
    from fivebar_drake.robots.quadruped.plant import add_robot
    from fivebar_drake.simulation.recording import link_points

    scenario, params, record, sig, summary = run
    plant, instance, layout = add_robot(DiagramBuilder(), params, record.design)
    g, gait = params.leg, params.gait
    closed = []
    for _ in range(5):
        q = plant.GetPositions(plant.CreateDefaultContext())
        for leg in layout.legs:
            foot = [gait.x_center_m + rng.uniform(-1, 1) * gait.a_m,
                    gait.y_home_m + rng.uniform(-1, 1) * gait.b_m]
            q[layout.indices[leg].q] = tree_positions(inverse(g, np.array(foot)))
        quat = rng.normal(size=4)
        q[layout.state.body_q:layout.state.body_q + 7] = [*quat / np.linalg.norm(quat),
                                              *rng.uniform(-1, 1, 3)]
        closed.append(q)
    ours = link_points(record.layout, params, np.array(closed))
    for k, q in enumerate(closed):
        assert np.allclose(ours[k], plant_link_points(plant, instance, layout, params, q),
                           rtol=0, atol=1e-9)
    rows = np.linspace(0, len(record.table["t"]) - 1, 40).astype(int)
    ours = link_points(record.layout, params, record.table["state"][rows])
    for k, row in enumerate(rows):
        ref = plant_link_points(plant, instance, layout, params,
                                record.table["state"][row, :layout.state.nq])
        err = np.linalg.norm(ours[k] - ref, axis=-1)                           # (legs, 6)
        assert np.all(err[:, [0, 1, 4, 5]] < 1e-9)
        c, e, d = ref[:, 1], ref[:, 2], ref[:, 5]
        u, v = c - e, d - e
        sin_e = np.linalg.norm(np.cross(u, v), axis=-1) / np.linalg.norm(u, axis=-1) / g.de_m
        bound = 1.1 * record.table["gap"][row] / sin_e + 1e-9
        assert np.all(err[:, 2] <= bound) and np.all(err[:, 3] <= bound * (g.de_m + g.ef_m)
                                                      / g.de_m), (row, err, bound)


def test_two_runs_have_their_own_recording_ids(tmp_path):
    ids = []
    for name in ("a", "b"):
        out = tmp_path / name
        main(["simulate", "--duration", "0.2", "--closure", "ball", "--out", str(out)])
        (entry,) = RrdReader(out / "run.rrd").recordings()
        ids.append(entry.recording_id)
    assert ids[0] != ids[1]


def test_bad_scenario_value_fails_clearly(tmp_path, capsys):
    assert main(["simulate", "--duration", "-1", "--out", str(tmp_path)]) == 2
    assert "command line: scenario.duration_s = -1.0: must be >= 0.002" in capsys.readouterr().err


@pytest.mark.parametrize("option", ["--closure", "--gait"])
def test_bad_choice_fails_clearly(tmp_path, capsys, option):
    assert main(["simulate", option, "glue", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "glue" in err and option in err and "Traceback" not in err


def test_unreachable_gait_in_scenario_file(tmp_path, capsys):
    path = tmp_path / "far.yaml"
    path.write_text("gait_y_home_m: -0.35\nduration_s: 1.0\n")
    assert main(["simulate", "--scenario", str(path), "--out", str(tmp_path)]) == 2
    assert "foot path leaves the workspace" in capsys.readouterr().err


def test_unknown_scenario_key(tmp_path, capsys):
    path = tmp_path / "typo.yaml"
    path.write_text("durration_s: 1.0\n")
    assert main(["simulate", "--scenario", str(path), "--out", str(tmp_path)]) == 2
    assert "durration_s" in capsys.readouterr().err


def test_bushing_time_step_beyond_stability_is_refused(tmp_path, capsys):
    path = tmp_path / "coarse.yaml"
    path.write_text("time_step_s: 0.0005\nclosure: bushing_rpy\n")
    assert main(["simulate", "--scenario", str(path), "--out", str(tmp_path)]) == 2
    assert "scenario.time_step_s = 0.0005: the explicit bushing (k = " in capsys.readouterr().err


def test_failed_run_keeps_what_was_simulated(tmp_path, capsys, monkeypatch):
    """A run that fails midway still writes its summary, plots and recording, and exits 1."""
    from fivebar_drake.simulation import systems

    original = systems.FootLegController.command
    calls = []

    def failing(self, *args):
        calls.append(1)
        if len(calls) > 150:                                    # t = 0.3 s at 500 Hz
            raise UnreachableError("foot target out of reach (injected)")
        return original(self, *args)

    monkeypatch.setattr(systems.FootLegController, "command", failing)
    out = tmp_path / "sim"
    assert main(["simulate", "--duration", "1.0", "--closure", "ball", "--out", str(out)]) == 1
    assert "stopped early: foot target out of reach (injected)" in capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    assert summary["completed"] is False and 0.25 < summary["duration_s"] < 0.35
    assert summary["verdict"] == "insufficient"
    assert (out / "run.rrd").stat().st_size > 10_000 and (out / "sim_torques.png").exists()
    assert report_violations(out / "summary.md") == []    # the demo's fallen seed_ellipse alike
