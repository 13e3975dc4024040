"""The top speed for any controller (optimal/top_speed.py) held against other methods: Drake's
inverse dynamics for the swing's torques, the work-energy balance over the swing, the impulse
of the stance forces against the body's weight over a period, the package's fixed path, and
the design's direction (a stronger motor runs no slower, a payload no faster). The searches run
on a one-cell grid (one duty factor, one stride) to keep the suite quick; the full grid is
benchmarks/bench_optimal.py's."""

import dataclasses
import math

import numpy as np
import pytest

from fivebar_drake.gaits import foot_path
from fivebar_drake.mechanisms.fivebar import link_coms, mass_matrix
from fivebar_drake.optimal.gait_floor import fastest_gait, gait_floor
from fivebar_drake.optimal.top_speed import (_leg_motion, _swing_torques, check,
                                             longest_half_stride, speed_bound, top_speed)
from fivebar_drake.robots.quadruped.closure import fixed_leg
from fivebar_drake.robots.quadruped.config import with_changes, with_gait, with_path_defaults
from fivebar_drake.robots.quadruped.inverse_dynamics import projected_inverse_dynamics
from fivebar_drake.robots.quadruped.leg_loads import full_model

CELL = {"duties": (0.5,), "shares": (0.75,)}


@pytest.fixture(scope="module")
def trot(params):
    """The default robot's trot top speed on the one-cell grid, and its design at the optimum."""
    found = top_speed(params, "trot", **CELL)
    at = with_gait(with_path_defaults(params, "trot"), a_m=found.stride_m / 2,
                   frequency_hz=found.frequency_hz)
    return found, at


def test_the_optimum_is_a_gait_within_the_bound(trot):
    found, at = trot
    assert 0.0 < found.speed_m_s <= found.bound_m_s
    assert found.speed_m_s == pytest.approx(found.path.stance_speed(at.gait), rel=1e-9)
    assert found.path.beta(at.gait) == found.duty_factor == 0.5
    assert check(at, "trot", 0.5, found.stride_m / 2, found.frequency_hz).passed
    assert found.limited_by                       # what stopped a faster one is named


def test_the_swing_torques_match_drakes_inverse_dynamics(trot):
    """The optimum's swing (its shape terms set) through Drake's plant of one leg (tree inverse
    dynamics projected through the loop, the rotors included) within 1 % of the peak."""
    found, at = trot
    torque, _ = _swing_torques(at, found.path)
    t = np.linspace(0.0, 1.0 - found.duty_factor, torque.shape[0]) * at.gait.period_s
    pose, qd, qdd = _leg_motion(at, found.path, t)
    plant, context, instance, idx = fixed_leg(at)
    drake = projected_inverse_dynamics(plant, context, instance, at, "leg", idx, pose, qd, qdd,
                                       0.0)
    assert np.abs(drake - torque).max() <= 0.01 * np.abs(torque).max()
    assert any(abs(v) > 1e-4 for v in (found.path.swing_reach_m, found.path.swing_skew_m))


def test_the_swing_work_is_its_energy(trot):
    """Work-energy over the swing: the motors' work (the trapezoid of tau . q') equals the
    change of the links' and rotors' kinetic energy and the links' potential energy, within
    1 % of the work done either way."""
    found, at = trot
    t = np.linspace(0.0, 1.0 - found.duty_factor, 2001) * at.gait.period_s
    pose, qd, qdd = _leg_motion(at, found.path, t)
    model = dataclasses.replace(full_model(at), foot_load_N=0.0)
    tau = at.fivebar_leg.torques(model, pose, qd, qdd).total
    power = np.einsum("ni,ni->n", tau, qd)
    work = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(t)))
    ends = [0, -1]
    inertia = mass_matrix(at.leg, at.links, model.izz, type(pose)(
        *(a[ends] for a in (pose.q, pose.c, pose.d, pose.e, pose.f))))
    inertia = inertia + at.motor.reflected_inertia_kg_m2 * np.eye(2)
    kinetic = 0.5 * np.einsum("ni,nij,nj->n", qd[ends], inertia, qd[ends])
    masses = np.array([link.mass_kg for link in at.links.values()])
    potential = at.robot.gravity_m_s2 * link_coms(at.leg, at.links, pose)[..., 1] @ masses
    change = kinetic[1] - kinetic[0] + potential[-1] - potential[0]
    assert work == pytest.approx(change, abs=0.01 * float(np.sum(np.abs(power[1:]) * np.diff(t))))


def test_the_stance_forces_carry_the_weight_over_a_period(trot):
    """Momentum over a period of the periodic body: the feet's vertical impulse is the weight's
    (m g T) and their forward impulse zero, within 1e-6 of m g T."""
    found, at = trot
    floor = gait_floor(at, dataclasses.replace(found.path, swing_reach_m=0.0, swing_skew_m=0.0,
                                               swing_lift_skew_m=0.0))
    dt = floor.t[1] - floor.t[0]
    weight = floor.mass_kg * at.robot.gravity_m_s2 * at.gait.period_s
    impulse = floor.force_N.sum((0, 1)) * dt
    assert impulse[1] == pytest.approx(weight, rel=1e-6)
    assert abs(impulse[0]) <= 1e-6 * weight


def test_the_free_optimum_is_at_or_above_the_paths_own(trot, params):
    """The package's own trot path, at its stride and duty factor, is one gait of the search's
    family: the free optimum runs at least as fast."""
    found, _ = trot
    assert found.speed_m_s >= fastest_gait(params, "trot")["speed_m_s"]


def test_a_stronger_motor_runs_no_slower_and_a_payload_no_faster(trot, params):
    """A higher bus voltage (the no-load speed up by half) runs at least as fast, faster where
    the voltage limited the default; a 1 kg payload no faster."""
    found, _ = trot
    stronger = top_speed(with_changes(params, {"motor.bus_voltage_V": 36.0}), "trot", **CELL)
    assert stronger.speed_m_s >= found.speed_m_s
    if "voltage" in found.limited_by:
        assert stronger.speed_m_s > 1.02 * found.speed_m_s
    loaded = top_speed(params, "trot", payload_kg=1.0, **CELL)
    assert loaded.speed_m_s <= found.speed_m_s


def test_a_payload_beyond_the_motors_has_no_speed_and_says_why(params):
    found = top_speed(params, "trot", payload_kg=25.0, **CELL)
    assert math.isnan(found.speed_m_s) and found.path is None
    assert "stance" in found.limited_by or "swing" in found.limited_by


def test_the_no_load_bound_scales_with_the_no_load_speed(params):
    """The bound is the no-load speed times a lever of the workspace: 1.5x the bus voltage,
    1.5x the bound (to the grid's resolution)."""
    faster = with_changes(params, {"motor.bus_voltage_V": 36.0})
    assert speed_bound(faster) == pytest.approx(1.5 * speed_bound(params), rel=1e-9)


def test_the_pronk_flies_the_rest_of_its_period(params):
    """The pronk at another duty factor keeps its flight: the dip's lift-off speed throws the
    body for (1 - beta) T."""
    gait = with_path_defaults(params, "pronk").gait
    path = foot_path("pronk").at_duty(0.4, gait)
    stance_s = 0.4 * gait.period_s
    lift_off_speed = math.pi * path.dip_m / stance_s
    assert 2 * lift_off_speed / gait.gravity_m_s2 == pytest.approx(0.6 * gait.period_s)


def test_the_search_finds_a_pass_between_too_slow_and_too_fast(params):
    """The pronk at one duty factor and stride passes only in a band of frequencies: slower, its
    four feet held long topple the body past the pitch bound; faster, the swing leaves the
    voltage line. The search's top speed there is at or above every pass of an even scan of
    the frequencies (within its bisection's 2 %), where one pass exists."""
    cell = {"duties": (0.5,), "shares": (0.5,)}
    found = top_speed(params, "pronk", **cell)
    base = with_path_defaults(params, "pronk")
    a = 0.5 * longest_half_stride(base, foot_path("pronk").at_duty(0.5, base.gait))
    scan = [(f, check(base, "pronk", 0.5, a, f)) for f in np.arange(2.5, 6.01, 0.25)]
    passes = [f for f, result in scan if result.passed]
    assert passes and any(result.slow for f, result in scan if f < min(passes))
    assert found.speed_m_s >= 0.98 * 2.0 * a * max(passes) / 0.5


def test_the_tracked_run_is_the_optimums_gait(trot, params, monkeypatch):
    """A gait at its top speed (gait: {kind, speed_m_s: max}, optimal --simulate's scenario):
    the optimum's path (duty factor, swing shape) at its stride and frequency on the tracking
    controller, the load transfer within a quarter of the stance and at least a hundred
    recorded intervals a period; a gait beyond 10 Hz cannot be recorded so and is refused
    (ParameterError), not run. (The optimum is the one-cell grid's, handed in.)"""
    from fivebar_drake.core.validation import ParameterError
    from fivebar_drake.pipeline import top_speed_scenario
    from fivebar_drake.simulation import runner

    found, _ = trot
    monkeypatch.setattr(runner, "top_speed", lambda p, kind, payload, duties: found)
    asked = top_speed_scenario("trot")
    assert asked.top_speed and asked.controller.kind == "tracking"
    scenario, design = runner.at_top_speed(asked, params)
    assert scenario.gait == found.path and not scenario.top_speed
    assert design.gait.a_m == pytest.approx(found.stride_m / 2)
    assert design.gait.frequency_hz == pytest.approx(found.frequency_hz)
    assert found.path.stance_speed(design.gait) == pytest.approx(found.speed_m_s)
    period = 1.0 / found.frequency_hz
    assert scenario.load_transfer_s <= 0.25 * found.duty_factor * period + 1e-12
    assert scenario.log_period_s <= period / 100
    monkeypatch.setattr(runner, "top_speed",
                        lambda p, kind, payload, duties: dataclasses.replace(found,
                                                                             frequency_hz=12.0))
    with pytest.raises(ParameterError, match=r"frequency_hz = 12.0: must be in \(0, 10\]"):
        runner.at_top_speed(asked, params)
    monkeypatch.setattr(runner, "top_speed", lambda p, kind, payload, duties: dataclasses.replace(
        found, speed_m_s=math.nan, limited_by="the motors' torque (5 of 5 checks)"))
    with pytest.raises(ParameterError, match=r"no trot at any speed: the motors' torque"):
        runner.at_top_speed(asked, params)


@pytest.mark.parametrize("kind", ["trot", "bound", "pronk"])
def test_a_top_speed_at_a_duty_factor_searches_that_one_alone(kind, trot, params, monkeypatch):
    """{kind: KIND, speed_m_s: max, duty_factor: D} searches the top speed at D alone; without
    duty_factor every duty factor of the search's (not the bound's or pronk's default 0.75 or
    0.7): the duties the search is handed."""
    from fivebar_drake.simulation import runner
    from fivebar_drake.simulation.scenario import load_scenario

    found, asked = trot[0], []

    def search(p, kind, payload, duties):
        asked.append(duties)
        return found
    monkeypatch.setattr(runner, "top_speed", search)
    runner.at_top_speed(load_scenario(gait={"kind": kind, "speed_m_s": "max",
                                            "duty_factor": 0.55}), params)
    runner.at_top_speed(load_scenario(gait={"kind": kind, "speed_m_s": "max"}), params)
    assert asked == [(0.55,), None]


@pytest.mark.parametrize("gait, extra, why", [
    ({"kind": "trot", "speed_m_s": 1.0}, {}, r"speed_m_s = 1.0: max \(the gait's top speed"),
    ({"kind": "walk", "speed_m_s": "max"}, {}, r"gait.kind = 'walk': speed_m_s: max is searched "
                                                r"for trot, bound, pronk"),
    ({"kind": "bound", "speed_m_s": "max", "swing_reach_m": 0.01}, {},
     r"no swing_reach_m beside speed_m_s: max \(duty_factor: the top speed at that duty"),
    ({"kind": "trot", "speed_m_s": "max", "duty_factor": 1.0}, {},
     r"gait.duty_factor = 1.0: must be in \(0, 1\)"),
    ({"kind": "pronk", "speed_m_s": "max", "duty_factor": "half"}, {},
     r"gait.duty_factor = 'half': must be a number"),
    ({"kind": "bound", "speed_m_s": "max"}, {"gait_frequency_hz": 2.0},
     r"gait_frequency_hz = 2.0: at its top speed"),
])
def test_a_top_speed_request_the_search_cannot_honour_is_refused(gait, extra, why):
    from fivebar_drake.core.validation import ParameterError
    from fivebar_drake.simulation.scenario import load_scenario

    with pytest.raises(ParameterError, match=why):
        load_scenario(gait=gait, **extra)


def test_the_ladder_keeps_climbing_past_a_band_with_nothing_in_hand(monkeypatch):
    """The frequency search (top_speed._fastest_at) on a stand-in check: too slow below
    0.5 Hz, a band of passes up to 0.6 Hz, too fast (not hopeless) up to 1.5 Hz, passing above.
    With no speed in hand it climbs past the band to the top of its ladder (the no-load bound's
    frequency, 5 Hz here) and blames that bound, not the failure it climbed past; with a speed
    in hand it keeps the band's pass."""
    import fivebar_drake.optimal.top_speed as ts
    from fivebar_drake.optimal.top_speed import Check, _fastest_at, _Tally

    def stand_in(base, kind, beta, a, f, payload_kg=0.0):
        if f < 0.5:
            return Check(False, "the stance's balance (stand-in)", slow=True)
        if f < 0.52 or 0.6 <= f < 1.5:
            return Check(False, "the stance's torque (stand-in)")
        return Check(True, "")

    monkeypatch.setattr(ts, "check", stand_in)
    beta, a, bound = 0.5, 0.05, 1.0                 # the bound's frequency: 1.0 * 0.5 / 0.1
    speed, f, _, why = _fastest_at(None, "pronk", beta, a, None, bound, 0.0, _Tally())
    assert f == pytest.approx(5.0) and why == "the no-load bound"
    in_hand = 2 * a * 0.45 / beta                          # a speed at 0.45 Hz
    speed, f, _, why = _fastest_at(None, "pronk", beta, a, in_hand, bound, 0.0, _Tally())
    assert 0.52 <= f < 0.6 and why.startswith("the stance's torque")
