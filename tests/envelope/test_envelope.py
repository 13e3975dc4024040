"""The duty envelope (`fivebar-drake envelope`): hostile specs refused before anything is written;
a short envelope of trot variants on a local cluster and on a scheduler started here giving the
same envelope; a maneuver's row equal to `simulate`'s summary of the same scenario; the
operating points holding the demand's peak; the duty cycle's winding temperature against a hand
integration of the thermal ODE and its steady state; an interrupted envelope keeping what
finished."""

import json
import os
import signal
import subprocess
import sys
import time
import tomllib
from contextlib import nullcontext
from pathlib import Path

import numpy as np
import pytest
from rerun.chunk import RrdReader

from helpers import signal_mask
from fivebar_drake.cli import main
from fivebar_drake.envelope import run as envelope_run
from fivebar_drake.envelope.duty_cycle import duty_temperature
from fivebar_drake.envelope.maneuver import decimate
from fivebar_drake.envelope.spec import DATA, DutyStep, load_envelope_spec
from fivebar_drake.robots.quadruped.config import DEFAULT_PATH
from fivebar_drake.core.rerun_files import read_series
from style_rules import report_violations

# two short trot variants with a verdict: 3 whole cycles after 0.2 s standing and the ramp
SPEC = """\
scenario: {stand_s: 0.2, ramp_s: 0.5}
maneuvers:
  - {name: trot, gait: trot, gait_frequency_hz: 1.5, duration_s: 2.9}
  - {name: trot_fast, gait: trot, gait_frequency_hz: 2.0, gait_a_m: 0.03, duration_s: 2.2}
duty_cycle:
  - {maneuver: trot, duration_s: 3.0}
  - {maneuver: trot_fast, duration_s: 2.0}
  - {maneuver: trot, duration_s: 1.5}
"""
TIMING = ("real_time_factor", "wall_time_s", "timing")   # wall-clock figures: differ run to run
MOTOR = tomllib.loads(DEFAULT_PATH.read_text())["motor"]


def write(tmp_path, text, name="spec.yaml"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def local(tmp_path_factory, shared_client):
    """The test spec's envelope on a local cluster of one worker: (its folder, the spec's path,
    the EnvelopeRun)."""
    folder = tmp_path_factory.mktemp("envelope")
    spec = write(folder, SPEC)
    run = envelope_run.run_envelope(load_envelope_spec(spec), folder / "local",
                                    client=shared_client, progress=False)
    return folder / "local", spec, run


def envelope(out):
    return json.loads((out / "envelope.json").read_text())


def without_timing(report):
    for entry in report["maneuvers"].values():
        entry.pop("timing")
    return report


def summary(folder):
    data = json.loads((folder / "summary.json").read_text())
    return {k: v for k, v in data.items() if k not in TIMING}


@pytest.mark.parametrize("text, words", [
    ("maneuvers:\n  - {name: w, gait: moonwalk}\n", ["maneuvers[0]", "'moonwalk'", "allowed",
                                                   "trot"]),
    ("maneuvers:\n  - {name: t, gait: {kind: trot, duty: 0.5}}\n", ["duty", "duty_factor"]),
    ("maneuvers:\n  - {name: t, duration_s: -1}\n", ["duration_s = -1", "must be >="]),
    ("duration_s: 0\nmaneuvers:\n  - {name: t}\n", ["duration_s = 0", "> 0"]),
    ("maneuvers:\n  - {name: t}\n  - {name: t, gait_frequency_hz: 1.5}\n",
     ["maneuvers[1].name = 't'", "two maneuvers"]),
    ("maneuvers:\n  - {name: ../up}\n", ["maneuvers[0].name", "letters"]),
    ("maneuvers:\n  - {name: t, speed: 3}\n", ["maneuvers[0].speed", "unknown field"]),
    ("maneuvers: []\n", ["maneuvers = []"]),
    ("maneuvers:\n  - {name: t}\nduty_cycle:\n  - {maneuver: jump, duration_s: 5}\n",
     ["duty_cycle[0].maneuver = 'jump'", "['t']"]),
    ("maneuvers:\n  - {name: t}\nduty_cycle:\n  - {maneuver: t, duration_s: 0}\n",
     ["duty_cycle[0].duration_s = 0"]),
    ("maneuvers:\n  - {name: t}\nduty_cycle:\n  - {maneuver: t, duration_s: ten}\n",
     ["duty_cycle[0].duration_s = 'ten'", "number"]),
    ("maneuvers:\n  - {name: t}\nduty_cycle:\n  - {maneuver: t}\n", ["duty_cycle[0]"]),
    ("maneuvers:\n  - {name: t}\nduty_cycle:\n" + "  - {maneuver: t, duration_s: 50000}\n" * 2,
     ["total duration_s", "86400"]),
    ("maneuvers:\n  - {name: t}\nmaneuvers:\n  - {name: u}\n", ["written twice"]),
    ("m: &x {name: t}\nmaneuvers: [*x]\n", ["aliases"]),
    ("maneuvers:\n  - {name: t}\nrepeat: 2\n", ["repeat", "unknown key"]),
    ("scenario: {gait_frequency_hz: 50}\nmaneuvers:\n  - {name: t}\n",
     ["maneuver 't'", "gait_frequency_hz"]),
    # issue 33's twenty-first class: the field named where it was given
    ("scenario: {log_period_s: -1}\nmaneuvers:\n  - {name: t}\n",
     ["scenario.log_period_s = -1", "maneuver 't'"]),
    ("duration_s: 1.0e9\nmaneuvers:\n  - {name: t}\n", ["duration_s = 1000000000", "<= 1000"]),
    ("scenario: {log_period_s: 0.002}\nmaneuvers:\n  - {name: t, log_period_s: -1}\n",
     ["maneuvers[0].log_period_s = -1"]),
])
def test_bad_specs_exit_2_and_write_nothing(tmp_path, capsys, text, words):
    out = tmp_path / "out"
    assert main(["envelope", str(write(tmp_path, text)), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    for word in ["spec.yaml", *words]:
        assert word in err, err
    assert "Traceback" not in err and not out.exists()


@pytest.mark.parametrize("options, words", [(["--workers", "0"], ["--workers = 0"]),
                                            (["--scheduler", "nowhere"], ["--scheduler"])])
def test_bad_cluster_options_exit_2_and_write_nothing(tmp_path, capsys, options, words):
    """(A well-formed address where no scheduler answers: the sweep's engine, which the
    envelope shares, is tested with it in tests/sweep/test_sweep_hostile.py.)"""
    out = tmp_path / "out"
    spec = write(tmp_path, "maneuvers:\n  - {name: t, duration_s: 0.1}\n")
    assert main(["envelope", str(spec), "--out", str(out), *options]) == 2
    err = capsys.readouterr().err
    assert all(w in err for w in words), err
    assert not out.exists()


def test_a_maneuver_folder_that_is_a_file_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "t").write_text("mine")
    spec = write(tmp_path, "maneuvers:\n  - {name: t, duration_s: 0.1}\n")
    assert main(["envelope", str(spec), "--out", str(out)]) == 2
    assert "maneuver 't'" in capsys.readouterr().err
    assert sorted(p.name for p in out.iterdir()) == ["t"]


def test_packaged_specs_load():
    default = load_envelope_spec()
    # the default set: trot at two speeds, walk, bound, pronk, jump, drop from 0.1 m,
    # stand-up, and trot with a payload and on a slope
    by_name = {m.name: m for m in default.maneuvers}
    assert list(by_name) == ["trot_1hz", "trot_fast", "walk", "bound", "pronk", "jump",
                             "drop_10cm", "stand_up", "trot_payload", "trot_slope"]
    assert by_name["trot_fast"].params.gait.frequency_hz == 1.5
    assert by_name["drop_10cm"].scenario.gait.height_m == 0.1
    assert by_name["trot_payload"].scenario.payload_kg > 0
    assert by_name["trot_slope"].scenario.slope_deg > 0
    demo = load_envelope_spec(DATA / "envelope_demo.yaml")
    assert len(demo.maneuvers) <= 3 and demo.duty_cycle


@pytest.mark.slow
def test_the_envelope_and_its_files(local):
    out, _, _ = local
    assert report_violations(out) == []          # envelope.md, each maneuver's summary.md
    report = envelope(out)
    assert report["complete"] and report["verdict"] in ("pass", "warn", "fail")
    for name in ("operating_points.png", "duty_cycle.png"):
        assert (out / name).read_bytes()[:4] == b"\x89PNG"
    ids = set()
    for name, entry in report["maneuvers"].items():
        folder = out / entry["folder"]
        assert summary(folder)["verdict"] == entry["verdict"]
        # the worst of each motor's four checks is the maneuver's verdict, as in summary.json
        worst = max((entry["motors"][m] for m in ("A", "B")),
                    key=lambda r: ("pass", "warn", "fail", "not_achieved").index(r["verdict"]))
        assert worst["verdict"] == entry["verdict"]
        (recording,) = RrdReader(folder / "run.rrd").recordings()
        assert name in recording.recording_id
        ids.add(recording.recording_id)
        assert len(RrdReader(folder / "run.rrd").blueprints()) == 1
    assert len(ids) == 2
    # the sizing maneuver of each motor has its lowest safety factor where the torque decides
    for motor, sized in report["sized_by"].items():
        sfs = {n: e["motors"][motor]["checks"]["torque"]["sf"]
               for n, e in report["maneuvers"].items()}
        assert sized["worst_per_check"]["torque"] == min(sfs, key=sfs.get)
        if sized["deciding_check"] == "torque":
            assert sized["maneuver"] == min(sfs, key=sfs.get)
    assert report["answer"].startswith(f"Worst verdict {report['verdict'].upper()}")
    assert (out / "envelope.md").read_text().splitlines()[2] == report["design_answer"]["text"]


def test_a_figure_has_one_value_in_every_report(local):
    """Each check's worst figure of a maneuver, as summary.md writes it (the motor where it is
    worst) and as envelope.md's rows write it (each motor's worst leg): the same text."""
    import re

    out, _, _ = local
    table = (out / "envelope.md").read_text()
    for name, entry in envelope(out)["maneuvers"].items():
        told = (out / entry["folder"] / "summary.md").read_text()
        checks = "\n".join(re.findall(r"- At the motor where it is worst, .*", told))
        sf = re.search(r"torque: safety factor ([\d.]+)", checks).group(1)
        margin = re.search(r"speed: least margin ([\d.]+), ([\d.]+)%", checks).groups()
        current = re.search(r"thermal: continuous / RMS current ([\d.]+)", checks).group(1)
        rows = [[c.strip() for c in line.split("|")[1:-1]] for line in table.splitlines()
                if line.startswith(f"| {name} |")]
        cells = [c for c in rows if len(c) == 7 and c[1] in ("PASS", "WARN", "FAIL")]
        assert len(cells) == 2                                  # motor A's row, motor B's
        assert min(float(c[3].split()[0]) for c in cells) == float(sf)
        speeds = [c[4].split(" (")[0] for c in cells]
        assert f"{margin[0]}, {margin[1]}%" in speeds
        assert min(float(c[5].split(",")[0]) for c in cells) == float(current)


@pytest.mark.slow
def test_the_trot_row_equals_simulates_summary(local, tmp_path):
    out, _, _ = local
    scenario = write(tmp_path, "stand_s: 0.2\nramp_s: 0.5\ngait: trot\ngait_frequency_hz: 1.5\n"
                     "duration_s: 2.9\n", "trot.yaml")
    assert main(["simulate", "--scenario", str(scenario), "--out", str(tmp_path / "sim")]) == 0
    alone = summary(tmp_path / "sim")
    assert summary(out / "trot") == alone                   # the same run, figure for figure
    entry = envelope(out)["maneuvers"]["trot"]
    assert entry["verdict"] == alone["verdict"]
    for motor in ("A", "B"):
        legs = {leg: ms[motor] for leg, ms in alone["legs"].items()}
        row = entry["motors"][motor]["checks"]
        sf = {leg: m["checks"]["torque"]["sf"] for leg, m in legs.items()}
        assert row["torque"]["sf"] == min(sf.values()) and row["torque"]["leg"] == min(sf, key=sf.get)
        rms = {leg: m["checks"]["thermal"]["rms_current_A"] for leg, m in legs.items()}
        assert row["thermal"]["rms_current_A"] == max(rms.values())
        assert row["speed"]["outside_fraction"] == max(
            m["checks"]["speed"]["outside_fraction"] for m in legs.values())


@pytest.mark.slow
def test_a_scheduler_started_here_gives_the_same_envelope(local, tmp_path, scheduler_address):
    out, spec, _ = local
    remote = tmp_path / "remote"
    assert main(["envelope", str(spec), "--out", str(remote), "--scheduler",
                 scheduler_address]) == 0
    assert without_timing(envelope(remote)) == without_timing(envelope(out))
    for name in ("trot", "trot_fast"):
        assert summary(remote / name) == summary(out / name)


def hand_current(torque, speed):
    """Motor current (A) of output torques at output speeds from the motor's file: driving
    through the gearbox's losses, braking helped by them (k_t i at the motor)."""
    n, eta, kt = MOTOR["gear_ratio"], MOTOR["gear_efficiency"], MOTOR["torque_constant_Nm_per_A"]
    return np.where(torque * speed >= 0, np.abs(torque) / (n * eta * kt),
                    np.abs(torque) * eta / (n * kt))


def window_currents(folder, leg, motor):
    """The hand currents (A) of a maneuver's window rows from its recording, and the row's
    interval (s)."""
    s = summary(folder)
    t, torque = read_series(folder / "run.rrd", f"/torque/{leg}/{motor}/applied")
    _, speed = read_series(folder / "run.rrd", f"/joints/speed/{leg}/{motor}")
    start, end = s["window_s"]
    rows = (t > start + 1e-3) & (t <= end + 1e-3)           # the window's 2 ms rows
    i = hand_current(torque[rows], speed[rows])
    assert np.sqrt(np.mean(i ** 2)) == pytest.approx(
        s["legs"][leg][motor]["checks"]["thermal"]["rms_current_A"], rel=1e-9)
    return i, float(np.median(np.diff(t)))


@pytest.mark.slow
def test_duty_cycle_against_a_hand_integration(local):
    """Every winding by forward Euler at a tenth of a row on
    dT/dt = (ambient + R_th 1.5 R i^2 - T) / tau from the recorded torques and speeds."""
    out, spec_path, _ = local
    spec = load_envelope_spec(spec_path)
    r, tau = MOTOR["winding_resistance_ohm"], MOTOR["thermal_time_constant_s"]
    r_th, ambient = MOTOR["thermal_resistance_K_W"], MOTOR["ambient_C"]
    legs, motors = ("FL", "FR", "RL", "RR"), ("A", "B")
    currents = {name: [[window_currents(out / name, leg, m) for m in motors] for leg in legs]
                for name in ("trot", "trot_fast")}
    temp = np.full((4, 2), ambient)
    peak = temp.copy()
    for step in spec.duty_cycle:
        (_, dt) = currents[step.maneuver][0][0]
        loss = np.stack([[1.5 * r * np.resize(i, round(step.duration_s / dt)) ** 2
                          for i, _ in per_leg] for per_leg in currents[step.maneuver]])
        for p in np.repeat(loss, 10, axis=-1).transpose(2, 0, 1):
            temp += dt / 10 * (ambient + r_th * p - temp) / tau
            peak = np.maximum(peak, temp)
    duty = envelope(out)["duty_cycle"]
    for j, motor in enumerate(motors):
        hottest = int(np.argmax(peak[:, j]))
        assert duty["motors"][motor]["peak_C"] == pytest.approx(peak[hottest, j], abs=1e-5)
        assert duty["motors"][motor]["leg"] == legs[hottest]
        assert duty["motors"][motor]["end_C"] == pytest.approx(temp[:, j].max(), abs=1e-5)
    assert duty["verdict"] == "pass" and peak.max() > ambient + 0.1


@pytest.mark.slow
def test_a_long_step_settles_at_the_rms_currents_temperature(local):
    """Held for 8 time constants, the winding follows the closed form of the RMS current,
    ambient + 1.5 R i_rms^2 R_th (1 - exp(-t / tau)): exactly with bins of whole repetitions
    (their mean loss is the RMS current's), to the ripple within a repetition with others."""
    out, spec_path, _ = local
    motor = load_envelope_spec(spec_path).maneuvers[0].params.motor
    i, dt = window_currents(out / "trot", "FL", "B")
    repetitions = 1600
    held = repetitions * i.size * dt
    assert held == pytest.approx(8 * MOTOR["thermal_time_constant_s"], rel=0.01)
    steady = 1.5 * MOTOR["winding_resistance_ohm"] * np.mean(i ** 2) \
        * MOTOR["thermal_resistance_K_W"]
    rise = steady * -np.expm1(-held / MOTOR["thermal_time_constant_s"])
    for bins, tolerance in ((repetitions, 1e-9), (5000, 1e-3)):
        duty = duty_temperature(motor, [DutyStep("trot", held)],
                                {"trot": (i[:, None, None], dt)}, max_bins=bins)
        assert duty.temperature[-1, 0, 0] - MOTOR["ambient_C"] == pytest.approx(
            rise, rel=tolerance)


def test_decimation_keeps_the_edges_of_the_cloud(rng):
    torque, speed = rng.normal(size=10_001), rng.normal(size=10_001)
    torque[4321], speed[777] = 50.0, -40.0            # off the even grid of 100 of 10,001
    keep = decimate(speed, torque, 100)
    assert keep.size == 100 and np.all(np.diff(keep) > 0)
    assert {4321, 777} <= set(keep.tolist())
    assert decimate(speed[:50], torque[:50], 100).tolist() == list(range(50))


@pytest.mark.slow
def test_operating_points_hold_the_demand_peak(local):
    out, _, run = local
    for name, result in run.results.items():
        s = summary(out / name)
        for j, motor in enumerate(("A", "B")):
            peak = max(ms[motor]["demand_peak_Nm"] for ms in s["legs"].values())
            assert np.abs(result.demand[j]).max() == peak
            assert result.demand[j].size == 2000 < result.current.shape[0] * 4
    from fivebar_drake.envelope.plots import load_points
    saved = load_points(out / "operating_points.npz")      # what the dossier's overlay reads
    assert list(saved) == list(run.results)
    for name, result in run.results.items():
        np.testing.assert_array_equal(saved[name][0], result.speed)
        np.testing.assert_array_equal(saved[name][1], result.demand)


def without_dask(monkeypatch, first, second):
    """run_envelope with no cluster: the first maneuver finishes with `first` (a result),
    then `second` happens (an exception raised, or the error text of a failed task)."""
    def tasks(client, task, args, chunks):
        yield chunks[0], [first], ""
        if isinstance(second, BaseException):
            raise second
        yield chunks[1], None, second

    monkeypatch.setattr(envelope_run, "finished_tasks", tasks)
    monkeypatch.setattr(envelope_run, "dask_client", lambda *a: nullcontext())


@pytest.mark.slow
def test_an_interrupted_envelope_keeps_what_finished(local, tmp_path, monkeypatch, capsys):
    out, spec_path, run = local
    without_dask(monkeypatch, run.results["trot"], KeyboardInterrupt())
    stopped = tmp_path / "stopped"
    assert main(["envelope", str(spec_path), "--out", str(stopped)]) == 130
    assert "complete: false" in capsys.readouterr().err
    report = envelope(stopped)
    assert not report["complete"]
    assert report["maneuvers"]["trot"]["status"] == "ok"
    assert report["maneuvers"]["trot_fast"]["status"] == "missing"
    assert "trot_fast" in report["answer"] and report["duty_cycle"] is None
    assert summary(stopped / "trot") == summary(out / "trot")
    assert not (stopped / "trot_fast" / "summary.json").exists()


@pytest.mark.slow
def test_a_failed_maneuver_is_reported_and_exits_1(local, tmp_path, monkeypatch, capsys):
    _, spec_path, run = local
    without_dask(monkeypatch, run.results["trot"], "KilledWorker: the worker died")
    failed = tmp_path / "failed"
    assert main(["envelope", str(spec_path), "--out", str(failed)]) == 1
    assert "trot_fast" in capsys.readouterr().err
    report = envelope(failed)
    assert report["complete"]
    entry = report["maneuvers"]["trot_fast"]
    assert entry["status"] == "failed" and "the worker died" in entry["error"]
    assert "No verdict for trot_fast" in report["answer"]
    assert report["sized_by"]["A"]["maneuver"] == "trot"
    assert "did not run or has no samples" in report["duty_cycle_why_none"]


def test_an_envelope_without_verdicts_never_passes(tmp_path, shared_client):
    """Issue 33's second class: a jump cut shorter than its span (1 s of about 2 s) has no
    verdict; the envelope of it then has none either (not PASS), and its duty cycle, which
    would repeat the cut run's currents (standing) for 600 s, is not computed."""
    spec = write(tmp_path, "maneuvers:\n  - {name: jump, gait: jump, duration_s: 1.0}\n"
                           "duty_cycle:\n  - {maneuver: jump, duration_s: 600}\n")
    envelope_run.run_envelope(load_envelope_spec(spec), tmp_path / "out",
                              client=shared_client, progress=False)
    report = envelope(tmp_path / "out")
    assert report["maneuvers"]["jump"]["verdict"] == "insufficient"
    assert report["verdict"] == "insufficient" and "No verdict" in report["answer"]
    assert report["duty_cycle"] is None and "no verdict" in report["duty_cycle_why_none"]
    assert (tmp_path / "out" / "envelope.md").read_text().count("PASS") == 0


@pytest.mark.slow
def test_a_maneuver_that_raises_in_its_worker_is_a_bug_report(local, tmp_path, monkeypatch,
                                                              capsys):
    """Issue 33's thirteenth class: a task that raised in its worker (a write refused by the
    worker's machine, a bug) is no "no verdict" of the maneuver: exit 3 with the log of a bug,
    the envelope of the rest written (that maneuver failed, its error kept). A lost worker stays
    a failed maneuver (exit 1: test_a_failed_maneuver_is_reported_and_exits_1)."""
    _, spec_path, run = local
    without_dask(monkeypatch, run.results["trot"], "OSError: [Errno 27] File too large")
    out = tmp_path / "raised"
    assert main(["envelope", str(spec_path), "--out", str(out)]) == 3
    err = capsys.readouterr().err
    assert "internal error" in err and "File too large" in err and "trot_fast" in err
    assert "Traceback" not in err
    report = envelope(out)
    assert report["maneuvers"]["trot_fast"]["status"] == "failed"
    assert "File too large" in report["maneuvers"]["trot_fast"]["error"]


def test_a_maneuver_asks_for_its_contact_check(tmp_path):
    """`contact_check: true` on a maneuver runs it again with the foot contact varied (the
    packaged envelopes' jump and drop); anything but a boolean is refused naming the field."""
    from fivebar_drake.core.validation import ParameterError
    from fivebar_drake.envelope.spec import load_envelope_spec

    packaged = {m.name: m.contact_check for m in load_envelope_spec().maneuvers}
    assert packaged["jump"] and packaged["drop_10cm"] and not packaged["trot_1hz"]
    spec = tmp_path / "spec.yaml"
    spec.write_text("maneuvers:\n  - {name: jump, gait: jump, contact_check: yes please}\n")
    with pytest.raises(ParameterError, match=r"maneuvers\[0\]\.contact_check"):
        load_envelope_spec(spec)


def _sigint_ignored(pid: int) -> bool:
    """Whether the process ignores SIGINT."""
    return bool(signal_mask(pid, "SigIgn") & (1 << (signal.SIGINT - 1)))


@pytest.mark.slow
def test_a_terminals_ctrl_c_stops_the_local_cluster_quietly(tmp_path):
    """A terminal's Ctrl-C reaches the whole process group, the local cluster's workers too
    (issue 44's reliability round): exit 130, the finished maneuvers kept, and not a traceback
    from any process (each worker printed its KeyboardInterrupt's, and its heartbeat's to a
    scheduler gone, before the workers ignored SIGINT and their logs below CRITICAL were
    silenced). Waits on the event: both workers started and ignoring SIGINT."""
    out = tmp_path / "envelope"
    proc = subprocess.Popen([sys.executable, "-m", "fivebar_drake", "envelope", str(DATA / "envelope_demo.yaml"),
                             "--workers", "2", "--out", str(out)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and proc.poll() is None:
        workers = [int(p.name) for p in Path("/proc").iterdir() if p.name.isdigit()
                   and _parent(int(p.name)) == proc.pid and b"spawn_main" in _cmdline(p)]
        if sum(_sigint_ignored(w) for w in workers) >= 2:
            break
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err and "ERROR" not in err, err
    assert "interrupted by SIGINT" in err


def _cmdline(folder: Path) -> bytes:
    """A /proc process folder's command line (empty where it is gone)."""
    try:
        return (folder / "cmdline").read_bytes()
    except OSError:
        return b""


def _parent(pid: int) -> int:
    """The process's parent id (0 where it is gone)."""
    try:
        return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return 0
