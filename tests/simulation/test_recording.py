"""A run's recording read at a glance and its output files: the key events (synthetic signals
with known times, and a short real trot against its gait schedule), the blueprint read back
from the file, one unit per plot, the motors' hues, the plots' reduced curves, the seed's
reference figures and the timing split in summary.json."""

import colorsys
import json
import time

import numpy as np
import pytest
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RotationMatrix
from rerun.chunk import RrdReader

from fivebar_drake.analysis.torques import analyze, seed_results
from fivebar_drake.pipeline import write_simulation
from fivebar_drake.simulation.events import CONTACT_N, detect_events, phases
from fivebar_drake.simulation.plots import Band, StripChart, band_of, extremes
from fivebar_drake.core.rerun_files import read_series
from fivebar_drake.simulation.recording import EYE_OFFSET_M
from fivebar_drake.simulation.signals import signals

LEGS = ("FL", "FR", "RL", "RR")
G = 9.81


def test_phases_join_chatter_and_keep_real_phases():
    t = np.arange(1, 201) * 1e-3                                   # 1 ms rows
    on = np.ones(200, dtype=bool)
    on[50:53] = False                                              # a 3 ms dip: chatter
    on[100:140] = False                                            # 40 ms off: a phase
    on[120:122] = True                                             # a 2 ms blip inside it
    out = phases(t, on, 0.01)
    expect = np.ones(200, dtype=bool)
    expect[100:140] = False
    assert np.array_equal(out, expect)
    assert np.array_equal(phases(t, on, 0.001), on)               # nothing shorter than 1 ms


def test_events_of_a_synthetic_jump():
    """Stand, lift off foot by foot, fly ballistically, land foot by foot, with contact chatter
    (a 3 ms spike in flight, 2 ms dips in stance): the events are where the construction puts
    them, the apex at v0/g after takeoff, v0^2/(2g) above the takeoff height."""
    dt = 1e-3
    t = np.arange(1, 2001) * dt
    h0, v0, t_off = 0.20, 1.2, 0.800                 # takeoff height m, speed m/s, time s
    t_land = t_off + 2 * v0 / G
    tau = t - t_off
    height = np.where((tau > 0) & (t < t_land), h0 + v0 * tau - G * tau ** 2 / 2, h0)
    lift = {"FL": t_off - 0.006, "FR": t_off - 0.003, "RL": t_off - 0.001, "RR": t_off}
    down = {"FL": t_land + 0.004, "FR": t_land, "RL": t_land + 0.002, "RR": t_land + 0.008}
    force = np.stack([np.where((t >= lift[leg]) & (t < down[leg]), 0.0, 16.0)
                      for leg in LEGS], 1)
    spike = np.flatnonzero((t > t_off + 0.05) & (t <= t_off + 0.053))
    force[spike, 0] = 30.0                                          # a touch in flight
    force[100:102, 2] = 0.5                                         # dips in stance
    events = detect_events(t, force, height, LEGS)
    near = lambda a, b: abs(a - b) <= 1.5 * dt                      # noqa: E731 the row at/after b
    foot = {(e.kind, e.leg): e.t_s for e in events if e.leg}
    assert len(foot) == 8 and len([e for e in events if e.leg]) == 8
    for leg in LEGS:
        assert near(foot[("lift-off", leg)], lift[leg])
        assert near(foot[("touchdown", leg)], down[leg])
    flight = [e for e in events if not e.leg]
    assert [e.kind for e in flight] == ["takeoff", "apex", "touchdown"]
    takeoff, apex, touchdown = flight
    assert near(takeoff.t_s, max(lift.values())) and near(touchdown.t_s, min(down.values()))
    assert abs(apex.t_s - (t_off + v0 / G)) <= dt
    assert apex.height_m == pytest.approx(h0 + v0 ** 2 / (2 * G), abs=G * dt ** 2)
    assert [e.t_s for e in events] == sorted(e.t_s for e in events)


def test_a_trot_like_schedule_has_no_flight():
    """Diagonal pairs alternating with a 10 % overlap (always a foot down): each foot lifts off
    once per cycle, and there is no takeoff."""
    t = np.arange(1, 3001) * 1e-3
    period, duty = 1.0, 0.6
    phase = np.array([0.0, 0.5, 0.5, 0.0])
    u = (t[:, None] / period + phase) % 1.0
    force = np.where(u < duty, 20.0, 0.0)
    events = detect_events(t, force, np.full(len(t), 0.2), LEGS)
    assert not [e for e in events if not e.leg]
    for i, leg in enumerate(LEGS):
        lifts = [e.t_s for e in events if e.leg == leg and e.kind == "lift-off"]
        expect = (np.arange(4) + duty - phase[i]) * period
        expect = expect[(expect > 0) & (expect <= t[-1])]
        assert len(lifts) == len(expect) and np.allclose(lifts, expect, atol=1.5e-3)


def test_extremes_keep_every_buckets_minimum_and_maximum(rng):
    t = np.linspace(0.0, 10.0, 10_001)
    v = rng.normal(size=t.size).cumsum()
    rt, rv = extremes(t, v, 1000)
    assert len(rt) <= 1002 and np.all(np.diff(rt) >= 0)
    assert rv.max() == v.max() and rv.min() == v.min()
    size = -(-t.size // 500)
    for k in range(0, t.size, size):                                # brute force, per bucket
        inside = (rt >= t[k]) & (rt <= t[min(k + size, t.size) - 1])
        assert rv[inside].max() == v[k:k + size].max() and rv[inside].min() == v[k:k + size].min()
    short = v[:50]
    assert extremes(t[:50], short, 1000)[1] is short                # short enough: as it is


def test_strip_chart_bands_hold_their_values_apart():
    """Band k's range maps linearly into [K-1-k, K-k) of the axes: bands stacked top down,
    none overlapping, each value at its place."""
    import matplotlib.pyplot as plt

    fig = plt.figure()
    bands = [Band("torque (N·m)", -5.0, 5.0), band_of("height (mm)", [200.0, 215.0])]
    chart = StripChart(fig, (0.0, 10.0), bands)
    top, bottom = chart.put(0, [-5.0, 0.0, 5.0]), chart.put(1, [bands[1].low, bands[1].high])
    assert 1.0 <= top[0] < top[1] < top[2] < 2.0 and 0.0 <= bottom[0] < bottom[1] < 1.0
    assert top[1] - top[0] == pytest.approx(top[2] - top[1])
    assert bands[1].low < 200.0 and bands[1].high > 215.0             # a margin around the data
    assert chart.ax.get_ylim() == (0.0, 2.0)
    plt.close(fig)


def test_seed_results_are_the_analysis_seed_results(params):
    assert seed_results(params) == analyze(params).results["results"]["seed"]


@pytest.fixture(scope="module")
def short_run(tmp_path_factory, simulated):
    """A 2.5 s default trot (0.5 s standing, 1 s ramp, one cycle) written to a folder; the
    write's own wall time (s)."""
    record = simulated(gait="trot", duration_s=2.5)
    out = tmp_path_factory.mktemp("short")
    start = time.perf_counter()
    summary, _ = write_simulation(record, out)
    return record, signals(record), summary, out, time.perf_counter() - start


def blueprint_rows(path):
    """The blueprint's entities (path -> {component: first value})."""
    reader = RrdReader(path)
    (entry,) = reader.blueprints()
    found = {}
    for chunk in reader.stream(store=entry).to_chunks():
        batch = chunk.to_record_batch()
        found.setdefault(chunk.entity_path, {}).update(
            {n: batch.column(n).to_pylist()[0] for n in batch.schema.names if ":" in n})
    return found


def static_value(path, entity, component):
    chunks = RrdReader(path).stream().filter(content=entity, is_static=True).to_chunks()
    return [c.to_record_batch().column(component).to_pylist()[0] for c in chunks
            if component in c.to_record_batch().schema.names][0]


@pytest.mark.slow
def test_blueprint_frames_the_robot_and_keeps_one_unit_per_plot(short_run):
    record, sig, summary, out, _ = short_run
    rows = blueprint_rows(out / "run.rrd")
    views = {v["ViewBlueprint:space_origin"][0]: (v["ViewBlueprint:class_identifier"][0],
                                                 v["ViewBlueprint:display_name"][0])
             for v in rows.values() if "ViewBlueprint:space_origin" in v}
    assert views["world/follow"][0] == "3D"
    for origin, unit in (("body/height_m", "(m)"), ("body/forward_speed_m_s", "(m/s)"),
                         ("body/tilt_deg", "(deg)"), ("loop_gap_um", "(µm)"),
                         ("contact/normal", "(N)"), ("joints/angle", "(rad)"),
                         ("joints/speed", "(rad/s)"), *((f"torque/{leg}", "(N·m)") for leg in LEGS)):
        kind, name = views[origin]
        assert kind == "TimeSeries" and unit in name, (origin, name)
        assert sum(u in name for u in ("(m)", "(m/s)", "(deg)", "(µm)", "(N)", "(rad)")) <= 1
    assert views["events"][0] == "TextLog"
    # the camera: EYE_OFFSET_M from the body's standing height, in the frame world/follow,
    # which is the ground under the body at every pose frame
    eye = next(v for k, v in rows.items() if k.endswith("EyeControls3D"))
    look = [0.0, 0.0, sig.body_p[0, 2]]
    assert np.allclose(eye["EyeControls3D:look_target"], look, atol=1e-6)
    assert np.allclose(np.subtract(eye["EyeControls3D:position"], look), EYE_OFFSET_M, atol=1e-6)
    chunks = RrdReader(out / "run.rrd").stream().filter(content="/world/follow",
                                                         is_static=False).to_chunks()
    batch = chunks[0].to_record_batch()
    t = batch.column("sim_time").cast("int64").to_numpy() * 1e-9
    follow = np.array([row[0] for row in batch.column("Transform3D:translation").to_pylist()])
    rows_at = np.searchsorted(sig.t, t - 1e-9)
    assert len(t) > 50 and np.allclose(sig.t[rows_at], t)
    assert np.allclose(follow[:, :2], sig.body_p[rows_at, :2]) and np.all(follow[:, 2] == 0)
    # the ground: a patch under the path of the body, not a 6 m plane
    half = np.asarray(static_value(out / "run.rrd", "/world/ground", "Boxes3D:half_sizes")[0])
    walked = np.ptp(sig.body_p[:, :2], axis=0)
    assert np.all(half[:2] <= walked / 2 + 0.41) and np.all(half[:2] >= walked / 2)


@pytest.mark.slow
def test_recorded_units_and_motor_hues(short_run):
    record, sig, summary, out, _ = short_run
    path = out / "run.rrd"
    for i, leg in enumerate(LEGS):
        t, gap_um = read_series(path, f"/loop_gap_um/{leg}")
        assert np.allclose(t, sig.t) and np.allclose(gap_um, sig.gap[:, i] * 1e6, rtol=1e-12)
    _, tilt = read_series(path, "/body/tilt_deg")
    quat = sig.body_quat / np.linalg.norm(sig.body_quat, axis=1, keepdims=True)
    drake = np.degrees(np.arccos(np.clip([RotationMatrix(Quaternion(q)).matrix()[2, 2]
                                          for q in quat], -1, 1)))
    assert np.allclose(tilt, drake, atol=1e-6)
    _, height = read_series(path, "/body/height_m")
    assert 0.1 < height.min() and height.max() < 0.4               # metres, not millimetres
    _, limit = read_series(path, "/torque/FL/limit_pos")
    assert np.all(limit == record.params.motor.peak_torque_Nm)

    def style(entity):
        rgba = static_value(path, entity, "SeriesLines:colors")[0]
        width = static_value(path, entity, "SeriesLines:widths")[0]
        r, g, b = ((rgba >> s) & 255 for s in (24, 16, 8))
        return colorsys.rgb_to_hls(r / 255, g / 255, b / 255), width

    hue = {m: style(f"/torque/FL/{m}/applied")[0][0] for m in ("A", "B")}
    apart = abs(hue["A"] - hue["B"]) % 1.0
    assert min(apart, 1 - apart) > 0.25                            # > 90 degrees of hue apart
    for m in ("A", "B"):
        shades = [style(f"/torque/FL/{m}/{n}") for n in ("applied", "commanded",
                                                          "static_same_loads")]
        lightness = [s[0][1] for s in shades]
        assert min(np.diff(sorted(lightness))) > 0.1 or len({s[1] for s in shades}) == 3
        assert shades[0][1] > shades[1][1]                          # applied drawn bolder


@pytest.mark.slow
def test_real_trot_events_follow_its_gait_schedule(short_run):
    """Once the foot path has its full size (after standing and the ramp) each foot lifts off
    within 20 ms of a scheduled lift-off (the gait's schedule, sig.stance) and touches down
    after it, at most 50 ms after the scheduled touchdown (earlier when the ground comes sooner:
    the controller's early touchdown; later when the swing ends above the ground, by 2-4 mm of
    tracking lag measured, and the foot reaches down at control_law.SEARCH_SPEED_M_S, then takes
    load over a few ms: measured up to 42 ms); at an event's row the foot's ground force is above
    CONTACT_N after a touchdown, below it after a lift-off; a trot never flies; the text log
    holds every event."""
    record, sig, summary, out, _ = short_run
    path = out / "run.rrd"
    chunks = RrdReader(path).stream().filter(content="/events", is_static=False).to_chunks()
    texts = [x[0] for c in chunks for x in c.to_record_batch().column("TextLog:text").to_pylist()]
    full_size = record.scenario.stand_s + record.scenario.ramp_s - 0.02
    found, checked = 0, 0
    for i, leg in enumerate(LEGS):
        change = np.diff(sig.stance[:, i].astype(int))
        lifts, downs = sig.t[1:][change < 0], sig.t[1:][change > 0]
        for kind in ("lift-off", "touchdown"):
            try:
                times, _ = read_series(path, f"/contact/normal/{leg}/{kind}")
            except ValueError:
                continue
            found += len(times)
            total = np.linalg.norm(sig.foot_force_world[np.searchsorted(sig.t, times), i], axis=-1)
            assert np.all((total > CONTACT_N) == (kind == "touchdown"))
            for x in times[times >= full_size]:
                checked += 1
                if kind == "lift-off":
                    assert np.min(np.abs(lifts - x)) <= 0.02, (leg, x, lifts)
                else:
                    lifted = lifts[lifts < x].max()
                    assert x <= downs[downs > lifted].min() + 0.05, (leg, x, lifted, downs)
    assert checked >= 4 and len(texts) == found
    assert not any(text.startswith("flight") for text in texts)


@pytest.mark.slow
def test_summary_records_the_timing_split(short_run):
    record, sig, summary, out, measured = short_run
    timing = json.loads((out / "summary.json").read_text())["timing"]
    assert timing == pytest.approx(summary["timing"])
    assert timing["simulate_s"] == pytest.approx(record.wall_s)
    assert 0 < timing["outputs_s"] <= measured
    assert timing["outputs_share"] == pytest.approx(
        timing["outputs_s"] / (timing["outputs_s"] + timing["simulate_s"]))


@pytest.fixture(scope="module")
def jump_recording(tmp_path_factory, simulated):
    """The 2.6 s jump other tests share, its recording written here: (record, signals,
    summary, the file)."""
    from fivebar_drake.pipeline import _review
    from fivebar_drake.simulation.recording import write_recording

    record = simulated(gait="jump", duration_s=2.6)
    sig, _, summary = _review(record)
    path = write_recording(tmp_path_factory.mktemp("jump") / "run.rrd", sig, record, summary)
    return record, sig, summary, path


@pytest.mark.slow
def test_a_jumps_recording_answers_at_a_glance(jump_recording):
    """Issue 32: the default layout shows the verdict (a text panel), the worst motor's torque
    against the limit of its deciding quadrant with the maneuver's phases as vertical lines,
    every motor's share of its limit; no forward-speed panel for a jump, and its static estimate
    named for the loads it uses, not the trot."""
    record, sig, summary, path = jump_recording
    leg, motor = summary["worst_motor"].split()
    torque = summary["legs"][leg][motor]["checks"]["torque"]
    text = static_value(path, "/verdict", "TextDocument:text")[0]
    assert text.startswith(f"## {summary['verdict'].upper()} by the {summary['deciding_check']}")
    assert (f"Worst motor {leg} {motor}: {torque['torque_Nm']:.2f} N·m, "
            f"{torque['share_of_limit'] * 100:.0f} % of its {torque['limit_Nm']:.2f} N·m "
            f"{torque['quadrant']} limit") in text
    assert "SF ≥ 2 pass" in text and all(name in text for name in summary["phases"])
    limit = (record.params.motor.braking_peak_torque_Nm if torque["quadrant"] == "braking"
             else record.params.motor.peak_torque_Nm)
    assert np.all(read_series(path, "/worst/limit_pos")[1] == pytest.approx(limit))
    t, worst = read_series(path, "/worst/applied")
    assert np.array_equal(worst, read_series(path, f"/torque/{leg}/{motor}/applied")[1])
    for k, p in enumerate(summary["phases"].values()):          # a vertical line at its start
        t, v = read_series(path, f"/worst/phase_{k}")
        assert np.all(t == pytest.approx(p["start_s"], abs=1e-9)) and v[0] == -v[1]
    _, share = read_series(path, f"/share/{leg}/{motor}")
    i, j = LEGS.index(leg), ("A", "B").index(motor)
    up, lo = record.params.motor.limits(sig.qd[:, i, j])
    demand = sig.command[:, i, j]
    assert np.allclose(share, 100 * np.abs(demand / np.where(demand >= 0, up, lo)))
    rows = blueprint_rows(path)
    views = {v["ViewBlueprint:space_origin"][0]: (v["ViewBlueprint:class_identifier"][0],
                                                 v["ViewBlueprint:display_name"][0])
             for v in rows.values() if "ViewBlueprint:space_origin" in v}
    assert views["verdict"][0] == "TextDocument"
    assert f"worst motor {leg} {motor}" in views["worst"][1] and f"{limit:.2f}" in views["worst"][1]
    assert "share" in views and "body/forward_speed_m_s" not in views
    entities = {c.entity_path for c in RrdReader(path).stream().to_chunks()}
    assert not any("static_trot" in e for e in entities)


# The web viewer at the screenshots' size (tools/recording_screenshot.py): the height its panels
# share (the window, less its top bar and collapsed time panel), what each time series loses to
# its title, a tab bar and its time axis, and the spacing at which it labels a tick (it puts
# ticks at powers of ten: 1 N·m, 10 %, and labels them once they are this far apart; seen in
# its screenshots: 11 px apart unlabelled, 25 px labelled).
VIEWER_PX, PANEL_CHROME_PX, LABEL_PX = 1000 - 80, 70, 24


def view_heights(rows) -> dict[str, float]:
    """Each view's share of the viewer's height at the blueprint's default layout (a view in
    tabs has the tabs' share): view entity -> share."""
    import uuid

    root = next(v["ViewportBlueprint:root_container"][0] for v in rows.values()
                if "ViewportBlueprint:root_container" in v)
    shares = {}

    def walk(entity, share):
        row = rows.get(entity, {})
        if "ContainerBlueprint:contents" not in row:
            shares[entity] = share
            return
        contents = row["ContainerBlueprint:contents"]
        split = row["ContainerBlueprint:container_kind"] == [3]                # vertical
        weights = ((row.get("ContainerBlueprint:row_shares") if split else None)
                   or [1.0] * len(contents))
        for child, w in zip(contents, weights):
            walk("/" + child, share * w / sum(weights) if split else share)

    walk(f"/container/{uuid.UUID(bytes=bytes(root))}", 1.0)
    return shares


def labelled_ticks(low: float, high: float, share: float) -> int:
    """How many ticks the viewer labels on a fixed y range (low, high) in a panel with this
    share of its height: the finest power of ten at least LABEL_PX apart."""
    pixels = share * VIEWER_PX - PANEL_CHROME_PX
    step = 10.0 ** np.ceil(np.log10(LABEL_PX * (high - low) / pixels))
    return int(np.floor(high / step) - np.ceil(low / step)) + 1


@pytest.mark.slow
@pytest.mark.parametrize("run", ["trot", "jump"])
def test_every_fixed_range_plot_labels_its_ticks_at_the_default_layout(run, request):
    """Issue 32: at the default layout, without maximizing anything, each torque panel (the
    worst motor's, each leg's in its tab, the per-cycle peaks) labels every N·m and the share
    panel every 10 % (not a lone "0" or only 0 and 100); every plot with a fixed range labels
    at least 4 ticks; the worst motor's time axis leaves room beside the run for its legend."""
    path = (request.getfixturevalue("short_run")[3] / "run.rrd" if run == "trot"
            else request.getfixturevalue("jump_recording")[3])
    rows = blueprint_rows(path)
    shares = view_heights(rows)
    origin = {k: v["ViewBlueprint:space_origin"][0] for k, v in rows.items()
              if "ViewBlueprint:space_origin" in v}
    ranged = {origin[k.rsplit("/", 1)[0]]: (v["ScalarAxis:range"][0], shares[k.rsplit("/", 1)[0]])
              for k, v in rows.items() if "ScalarAxis:range" in v}
    assert {"worst", "share", *(f"torque/{leg}" for leg in LEGS)} <= set(ranged)
    for name, ((low, high), share) in ranged.items():
        pixels = share * VIEWER_PX - PANEL_CHROME_PX
        unit = 10.0 if name == "share" else 1.0 if ("torque" in name or name in (
            "worst", "cycle_peak")) else None
        if unit is not None:
            assert pixels * unit / (high - low) >= LABEL_PX, (name, share)
        assert labelled_ticks(low, high, share) >= 4, (name, low, high, share)
    end_s = next(v["TimeAxis:view_range"][0]["end"] for k, v in rows.items()
                 if "TimeAxis:view_range" in v and origin[k.rsplit("/", 1)[0]] == "worst") * 1e-9
    t, _ = read_series(path, "/worst/applied")
    assert end_s >= 1.2 * t[-1]
