"""The maneuvers that size a leg (issue 22), each run once, short, on the default robot: each is
achieved (a jump leaves the ground and lands standing, a stand-up and a drop end standing, the
gaits reach their speed within the tilt bound), and its physics holds by a second method: the
jump's takeoff speed against the ground's impulse, its rise against the motors' work and the
ballistic flight, the landing's impulse against the momentum it absorbs, the crawl's motor
torques against the closed-form statics of the same poses under the measured foot loads; motors
too weak to jump get not_achieved with exit 1."""

import dataclasses
import json

import numpy as np
import pytest

from helpers import told
from fivebar_drake.cli import main
from fivebar_drake.verdicts.checks import CHECK_ORDER
from fivebar_drake.gaits import PATHS, evaluate
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.mechanisms.fivebar import forward, static_torques
from fivebar_drake.pipeline import run_simulation, summarize_run
from fivebar_drake.robots.quadruped.leg_loads import full_model
from fivebar_drake.robots.quadruped.plant import standing_height
from fivebar_drake.simulation.runner import load_run
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.simulation.signals import signals

# each maneuver's scenario, as short as its verdict allows (3 whole cycles after the ramp for a
# gait, the maneuver's span after standing for a one-shot one)
RUNS = {
    "jump": dict(gait="jump", duration_s=2.6),
    "drop": dict(gait="drop", duration_s=1.5),
    "stand_up": dict(gait="stand_up", duration_s=2.5),
    "walk": dict(gait="walk", duration_s=4.5, gait_frequency_hz=1.0),
    "trot_slow": dict(gait="trot", duration_s=5.9, gait_frequency_hz=0.75),
    "trot_fast": dict(gait="trot", duration_s=3.9, gait_frequency_hz=1.5),
    "bound": dict(gait="bound", duration_s=4.0),
    "pronk": dict(gait="pronk", duration_s=2.5),
    "trot_payload_slope": dict(gait="trot", duration_s=4.5, payload_kg=1.0,
                               payload_offset_m=[0.03, 0.0, 0.04], slope_deg=5.0),
}


@pytest.fixture(scope="module")
def runs():
    out = {}
    for name, fields in RUNS.items():
        scenario = load_scenario(**{k: v for k, v in fields.items() if k != "payload_offset_m"})
        if "payload_offset_m" in fields:
            scenario.payload_offset_m = fields["payload_offset_m"]
        record = run_simulation(scenario, progress=False)
        out[name] = (record, signals(record), summarize_run(record))
    return out


@pytest.mark.parametrize("name", list(RUNS))
def test_each_maneuver_is_achieved(runs, name):
    record, sig, s = runs[name]
    assert record.completed, record.error
    assert s["verdict"] not in ("not_achieved", "insufficient"), s["answer"]
    # the answer opens with the verdict, its check and the worst motor, as a gait's does
    assert s["answer"].startswith(f"{s['verdict'].upper()}, decided by the "
                                  f"{s['deciding_check']} check: worst motor {s['worst_motor']}, ")
    for leg in s["legs"].values():
        for m in leg.values():
            assert m["checks"]["achieved"]["verdict"] == "pass", m["checks"]["achieved"]
    assert s["max_tilt_deg"] <= record.params.checks.achieved_max_tilt_deg
    if s["periodic"]:                       # a gait reaches its speed
        assert s["gait_speed_m_s"] > 0
        assert s["mean_forward_speed_m_s"] >= 0.7 * s["gait_speed_m_s"]
    else:                                   # a maneuver ends standing
        assert abs(sig.body_p[-1, 2] - standing_height(record.params)) < 0.01
    if name == "pronk":                     # all four feet off the ground, repeatedly
        assert np.mean(sig.ground_force[sig.t > 1.5, 2] < 1.0) > 0.1
    if name == "jump":
        j = s["jump"]
        air = (sig.t > j["takeoff_s"]) & (sig.t < j["apex_s"])
        assert air.any() and np.all(sig.ground_force[air, 2] < 1.0)   # every foot off
        assert j["height_m"] > 0.03 and j["agility_m_s"] > 0


def test_trot_speeds_follow_the_scenario(runs):
    """A slower and a faster trot walk at the path's speed 2 a / (beta T) of their frequency."""
    slow, fast = runs["trot_slow"][2], runs["trot_fast"][2]
    assert fast["gait_speed_m_s"] == pytest.approx(2 * slow["gait_speed_m_s"], rel=1e-12)
    assert fast["mean_forward_speed_m_s"] > 1.5 * slow["mean_forward_speed_m_s"]


def test_payload_and_slope(runs):
    """The payload adds to the robot's mass; the gravity of the plant is tilted by the slope."""
    record = runs["trot_payload_slope"][0]
    base = runs["trot_slow"][0]
    assert record.layout.mass_kg == pytest.approx(base.layout.mass_kg + 1.0, rel=1e-9)
    g = record.layout.gravity_m_s2
    assert np.degrees(np.arctan2(-g[0], -g[2])) == pytest.approx(5.0, rel=1e-12)
    assert np.linalg.norm(g) == pytest.approx(record.params.robot.gravity_m_s2, rel=1e-12)


def _weight(record):
    return record.layout.mass_kg * record.params.robot.gravity_m_s2


def _dt(sig, record):
    return np.diff(sig.t, prepend=sig.t[0] - record.scenario.log_period_s)


def test_jump_takeoff_speed_is_the_ground_impulse(runs):
    """m (v_takeoff - v_onset) = sum of the per-step accumulated ground force over the push-off
    minus m g t, within 2 %: the state's centre-of-mass speed against the contact forces."""
    record, sig, s = runs["jump"]
    j, mass, dt = s["jump"], record.layout.mass_kg, _dt(sig, record)
    k0 = int(np.searchsorted(sig.t, j["onset_s"]))            # the row ending at the onset
    k1 = int(np.searchsorted(sig.t, j["takeoff_s"]))
    push = slice(k0 + 1, k1 + 1)
    impulse = np.sum(sig.ground_force[push, 2] * dt[push]) - _weight(record) * (sig.t[k1] - sig.t[k0])
    v = sig.com_v[k0, 2] + impulse / mass
    assert v == pytest.approx(j["takeoff_speed_m_s"], rel=0.02)
    assert j["takeoff_speed_m_s"] > 0.5


def test_jump_height_against_ballistics_and_the_motors_work(runs):
    """In flight the centre of mass rises v^2 / 2g; from the onset it rises no more than the
    motors' work over the push-off allows, W / (m g), and not far less (the push-off is a
    lift, most of the work goes into it)."""
    record, _, s = runs["jump"]
    j, g = s["jump"], record.params.robot.gravity_m_s2
    assert j["com_rise_after_takeoff_m"] == pytest.approx(j["takeoff_speed_m_s"] ** 2 / (2 * g),
                                                          rel=0.03)
    assert j["com_rise_m"] <= j["energy_bound_rise_m"]
    assert j["com_rise_m"] >= 0.8 * j["energy_bound_rise_m"]


@pytest.mark.parametrize("name", ["drop", "jump"])
def test_landing_impulse_absorbs_the_momentum(runs, name):
    """Over the landing (touchdown until the centre of mass stops falling) the ground's
    impulse is m v_touchdown + m g t_landing within 3 %, the touchdown speed is the fall's
    (drop: sqrt(2 g h)), and the peak force is at least the mean the impulse needs."""
    record, sig, s = runs[name]
    ld, mass, g = s["landing"], record.layout.mass_kg, record.params.robot.gravity_m_s2
    dt = _dt(sig, record)
    land = (sig.t > ld["touchdown_s"]) & (sig.t <= ld["end_s"])
    impulse = np.sum(sig.ground_force[land, 2] * dt[land])
    need = mass * ld["touchdown_speed_m_s"] + _weight(record) * ld["duration_s"]
    assert impulse == pytest.approx(need, rel=0.03)
    assert ld["peak_force_N"] >= impulse / ld["duration_s"]
    if name == "drop":
        h = record.scenario.gait.height_m
        assert ld["touchdown_speed_m_s"] == pytest.approx(np.sqrt(2 * g * h), rel=0.03)
        assert ld["peak_force_N"] > mass * (g + ld["touchdown_speed_m_s"] / ld["duration_s"])


def test_event_figures_do_not_depend_on_the_log_interval(runs):
    """The landing's and the jump's figures come from every plant step and motor sample: the
    same drop logged every 1 ms instead of 2 ms (the same motion) gives the same figures (the
    2 ms means gave a peak force 22 % lower)."""
    record, _, s = runs["drop"]
    fine = run_simulation(dataclasses.replace(record.scenario, log_period_s=0.001),
                          progress=False)
    assert len(fine.table["t"]) == 2 * len(record.table["t"])
    again = summarize_run(fine)
    for key, value in s["landing"].items():
        assert again["landing"][key] == pytest.approx(value, rel=1e-9, abs=1e-12), key
    assert s["landing"]["peak_force_N"] > 1.1 * np.max(runs["drop"][1].ground_force[:, 2])


def test_the_summary_says_what_ran(runs):
    """summary.json records every variant's kind and fields and a maneuver's planned events
    beside the measured ones: the jump planned at height_m with its takeoff and touchdown."""
    record, _, s = runs["jump"]
    gait, ran = record.scenario.gait, s["ran"]
    assert ran["gait"] == {"kind": "jump", **dataclasses.asdict(gait)}
    assert ran["controller"]["kind"] == "foot_leg" and ran["closure"]["kind"] == "bushing"
    assert ran["controller"]["catch_rate_s"] == record.scenario.controller.catch_rate_s
    start = record.scenario.stand_s
    assert ran["planned_events_s"] == pytest.approx(
        {k: start + v for k, v in gait.events(record.params.gait).planned().items()})
    assert abs(s["jump"]["takeoff_s"] - ran["planned_events_s"]["takeoff"]) < 0.05


def test_no_motor_at_its_limit_with_its_foot_in_the_air(runs):
    """Feet join the support on measured contact: in the jump no motor is clipped in a
    recorded interval where its foot carries no load (below 1 N)."""
    record, sig, s = runs["jump"]
    air = sig.foot_force_world[..., 2] < 1.0
    clipped = (sig.clipped_peak + sig.clipped_line) > 0
    assert air.any() and not np.any(clipped & air[..., None]), sig.t[np.any(clipped & air[..., None], axis=(1, 2))]


def test_the_bound_front_motors_are_not_at_their_limit(runs):
    """The bound's front B motors were clipped 3 % of the time while an early front foot's
    swing speed entered the body's speed target; with support on measured contact under 1 %."""
    s = runs["bound"][2]
    for leg in ("FL", "FR"):
        m = s["legs"][leg]["B"]
        assert m["clipped_peak_fraction"] + m["clipped_line_fraction"] < 0.01, (leg, m)


def test_a_landing_beyond_the_braking_limit_gives_way(runs, tmp_path):
    """A drop from 0.3 m asks the motors to brake beyond their braking limit (a landing of
    1.1 m/s more than the 0.1 m drop's over the same stroke): the legs give way, the run is not
    achieved and says why, and the landing's delivered torque sits at the braking peak; the
    0.1 m drop's landing holds (its phases: fall, landing, recovery)."""
    s = runs["drop"][2]
    assert list(s["phases"]) == ["fall", "landing", "recovery"]
    assert not s["phases"]["landing"]["gives_way"]
    assert s["phases"]["landing"]["braking_beyond_limit_s"] == 0.0
    path = tmp_path / "drop.yaml"
    path.write_text("gait: {kind: drop, height_m: 0.3}\nduration_s: 1.5\n")
    assert main(["simulate", "--scenario", str(path), "--out", str(tmp_path / "out")]) == 1
    high = json.loads((tmp_path / "out" / "summary.json").read_text())
    landing = high["phases"]["landing"]
    assert landing["gives_way"] and landing["braking_beyond_limit_s"] > 0.005
    assert high["verdict"] == "not_achieved" and "gave way at the landing" in told(high)
    assert landing["delivered_peak_Nm"] >= 0.99 * runs["drop"][0].params.motor.braking_peak_torque_Nm


def test_the_bound_demand_beyond_the_limit_is_the_early_rear_landing(monkeypatch):
    """The bound's rear A motors are asked for more than their braking limit (README, "The
    bound"): at every controller tick where a rear A command exceeds it, the rear feet are down
    ahead of their schedule (early touchdown, the front feet due in stance); the package's own
    law at those ticks without the rear's early support asks less than the limit. The cause
    removed, the demand is gone."""
    from pydrake.systems.framework import DiagramBuilder

    from fivebar_drake.robots.quadruped.plant import add_robot
    from fivebar_drake.simulation import systems
    from fivebar_drake.simulation.builder import check_run

    ticks, update = [], systems.FootLegController._update

    def recording(self, context, discrete_state):
        ticks.append(self.tick_inputs(context))
        update(self, context, discrete_state)

    monkeypatch.setattr(systems.FootLegController, "_update", recording)
    record = run_simulation(load_scenario(**RUNS["bound"]), progress=False)
    monkeypatch.undo()
    scenario, params = record.scenario, record.params
    _, _, layout = add_robot(DiagramBuilder(), params, check_run(scenario, params),
                             scenario.plant_config)
    law = scenario.controller.add_to(DiagramBuilder(), params, layout, scenario)
    rear_a, limit = layout.state.actuators[2:, 0], params.motor.braking_peak_torque_Nm
    beyond = 0
    for references, state, loads, memory, t in ticks:
        if np.abs(law.command(references, state, loads, memory.copy(), t)[rear_a]).max() <= limit:
            continue
        beyond += 1
        assert np.all(memory[2:, 1] == 1.0) and np.all(references[-2:] == 0.0), t   # early
        assert np.all(references[-4:-2] > 0.0), t                                    # front due
        without = memory.copy()
        without[2:] = (0.0, 0.0, 1e9, t)                   # the rear feet not in the support
        free = np.array([loads[0], loads[1], 0.0, 0.0])
        assert np.abs(law.command(references, state, free, without, t)[rear_a]).max() < limit
    assert beyond > 10                                  # the bound does ask it: the test can fail


def test_crawl_torques_match_the_closed_form_statics(runs):
    """Mid-stance of a crawl (quasi-static), each motor's delivered torque against the full
    model's static torque of the same pose with the measured vertical foot load (analysis
    formula, dynamics.static_torques), within 10 % of the torques' RMS."""
    record, sig, s = runs["walk"]
    params = record.params
    start, end = s["window_s"]
    win = (sig.t > start) & (sig.t <= end)
    path, gait = record.scenario.gait, params.gait
    u = np.stack([path.phase(gait, sig.t - record.scenario.stand_s, ph)
                  for ph in record.scenario.phases_rad], 1)
    sigma = (u - path.stance_start(gait)) / (1 - path.stance_start(gait))
    mid = win[:, None] & sig.stance & (sigma > 0.2) & (sigma < 0.8)
    pose = forward(params.leg, sig.q)
    model = dataclasses.replace(full_model(params), foot_load_N=sig.foot_force_plane[..., 1])
    static = static_torques(params.leg, params.links, model, pose)
    measured, predicted = sig.applied[mid], static[mid]
    assert mid.sum() > 500
    error = np.sqrt(np.mean((measured - predicted) ** 2))
    assert error < 0.1 * np.sqrt(np.mean(measured ** 2))


def test_saturation_is_not_called_a_need(runs):
    """The bound drives its motors into their limits: where a motor's commands were clipped
    (counted from the recorded clip flags) more than 1 % of the window, its demand p99 was not
    met, so the torque check takes what the motor delivered, each sample against the limit of
    its own quadrant (by hand: the driving peak where torque and speed have one sign, the
    driving peak / eta^2 where not), which gives no SF below 1; the check of the kind of limit it
    sat at most (torque: peak current, speed: voltage) fails naming it with its quadrant, and
    the answer does not call the demand a need; below 1 % the SF is the same measure on the
    demand."""
    record, sig, s = runs["bound"]
    start, end = s["window_s"]
    win = (sig.t > start) & (sig.t <= end)
    motor = record.params.motor
    peak, braking_peak = motor.peak_torque_Nm, motor.peak_torque_Nm / motor.gear_efficiency**2

    def sf(torque, speed):
        limit = np.where(torque * speed >= 0, peak, braking_peak)
        return 1.0 / np.percentile(np.abs(torque) / limit, 99)

    limited = 0
    for i, (leg, ms) in enumerate(s["legs"].items()):
        for j, (name, m) in enumerate(ms.items()):
            speed = sig.qd[win, i, j]
            torque = float(np.mean(sig.clipped_peak[win, i, j]))
            share = torque + float(np.mean(sig.clipped_line[win, i, j]))
            demand_sf = sf(sig.command[win, i, j], speed)
            if share <= 0.01:
                assert m["safety_factor"] == pytest.approx(demand_sf, rel=1e-9)
                assert all("at_limit_fraction" not in m["checks"][c] for c in CHECK_ORDER)
                continue
            limited += 1
            check = m["checks"]["torque" if torque >= share - torque else "speed"]
            assert check["verdict"] == "fail"
            assert check["at_limit_fraction"] == pytest.approx(share, rel=1e-9)
            assert ("driving" in check["why"]) or ("braking" in check["why"])
            assert m["safety_factor"] == pytest.approx(sf(sig.applied[win, i, j], speed),
                                                       rel=1e-9)
            assert m["safety_factor"] >= 1.0 - 1e-9       # what a motor gives is within its limit
            assert m["checks"]["torque"]["demand_sf"] == pytest.approx(demand_sf, rel=1e-9)
    assert limited                          # the bound does clip: the test can fail
    worst = s["legs"][s["worst_motor"].split()[0]][s["worst_motor"].split()[1]]
    if any("at_limit_fraction" in worst["checks"][c] for c in CHECK_ORDER):
        assert "the motors need" not in told(s) and "worked at their limits" in told(s)


def test_motors_too_weak_to_jump_get_not_achieved(tmp_path, capsys):
    """1.2 A instead of 3.36 A peak current: the robot stands (1.5 N m a motor) but cannot
    jump; exit 1, verdict not_achieved with its reason, every file written."""
    code = main(["simulate", "--gait", "jump", "--duration", "2.6", "--set",
                 "motor.peak_current_A=1.2", "--out", str(tmp_path)])
    assert code == 1
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["verdict"] == "not_achieved"
    assert "NOT ACHIEVED" in told(s) and "not achieved" in capsys.readouterr().err
    assert (tmp_path / "force_capability.png").exists() or s["force_capability"] is None


@pytest.mark.parametrize("kind", ["jump", "drop", "stand_up", "pronk", "walk", "bound"])
def test_paths_derivatives_by_central_differences(params, kind):
    """Each new path's velocity and acceleration are its position's derivatives (away from the
    maneuvers' deliberate speed steps at takeoff and touchdown)."""
    path = PATHS[kind]()
    gait = load_run(None, gait=kind)[1].gait
    h = 1e-5
    span = path.span_s(gait)
    t = np.linspace(0.01, span - 0.01, 997)
    p0, pm, pp = (evaluate(gait, path, t + d) for d in (0.0, -h, h))
    smooth = np.all((pp.pos - pm.pos) / (2 * h) - p0.vel < 1e-3, axis=-1)   # not at a step
    assert smooth.mean() > 0.98
    np.testing.assert_allclose(((pp.pos - pm.pos) / (2 * h))[smooth], p0.vel[smooth], atol=2e-5)
    np.testing.assert_allclose(((pp.vel - pm.vel) / (2 * h))[smooth], p0.acc[smooth], atol=5e-3)


@pytest.mark.parametrize("kind", ["jump", "drop", "stand_up"])
def test_the_path_check_covers_the_whole_maneuver(monkeypatch, kind):
    """check_path samples a one-shot maneuver from its start to its end (its span, longer
    than the gait's period), not over one gait period."""
    from fivebar_drake.robots.quadruped import config

    scenario, params = load_run(None, gait=kind)
    span = scenario.gait.span_s(params.gait)
    assert span > params.gait.period_s
    seen = []
    monkeypatch.setattr(config, "path_poses", lambda leg, gait, path, t: seen.append(t))
    config.check_path(params, scenario.gait)
    assert seen[0][0] == 0.0 and seen[0][-1] == pytest.approx(span, rel=1e-12)


def test_a_crawl_keeps_three_feet_down():
    with pytest.raises(ParameterError, match="scenario.gait.duty_factor = 0.7"):
        load_scenario(gait={"kind": "walk", "duty_factor": 0.7})
    scenario, params = load_run(None, gait="walk")
    t = np.linspace(0, params.gait.period_s, 2001)
    down = sum(evaluate(params.gait, scenario.gait, t, ph).stance for ph in scenario.phases_rad)
    assert down.min() == 3
