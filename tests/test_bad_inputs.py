"""Every input mistake gets exit code 2 and one message naming the file (or the command line),
the field and what is allowed; never a traceback, never an output file. Table-driven over
parameter files, scenario files, command-line values and output paths of every subcommand, run
in-process; a few as real subprocesses; property-based cases with hypothesis."""

import json
import math
import os
import re
import subprocess
import sys
import uuid
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from fivebar_drake.cli import main
from fivebar_drake.robots.quadruped.config import DEFAULT_PATH
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.simulation.runner import load_run

DEFAULT = DEFAULT_PATH.read_text()


def params_file(tmp, old, new, name="params.toml"):
    """The packaged parameter file with the first line matching regex old replaced by new."""
    assert re.search(old, DEFAULT, flags=re.M), old
    path = tmp / name
    path.write_text(re.sub(old, lambda _: new, DEFAULT, count=1, flags=re.M))
    return path


def text_file(tmp, text, name="scenario.yaml"):
    path = tmp / name
    path.write_bytes(text if isinstance(text, bytes) else text.encode())
    return path


def sim(tmp, *args):
    return ["simulate", *args, "--out", str(tmp / "out")]


def scen(text, *expect, name="scenario.yaml"):
    """A simulate case with a scenario file holding text."""
    return (lambda t: sim(t, "--scenario", str(text_file(t, text, name))), name, *expect)


def conf(command, old, new, *expect):
    """A case of `command --config FILE` with the edited parameter file."""
    def argv(t):
        path = str(params_file(t, old, new))
        out = ["--out", str(t / "out")]
        return [command, "--config", path, *out]
    return (argv, "params.toml", *expect)


def fifo(t, name="fifo.yaml"):
    path = t / name
    os.mkfifo(path)
    return str(path)


def a_file(t):
    (t / "afile").write_text("not a folder")
    return t / "afile"


def unwritable(t):
    """A folder this process cannot create (root ignores permission bits: use /sys)."""
    if os.geteuid() == 0:
        return Path("/sys/fivebar-drake-test")
    t.joinpath("ro").mkdir(mode=0o500)
    return t / "ro" / "out"


def broken_run(t, text):
    run = t / "run"
    run.mkdir()
    (run / "summary.json").write_text(text)
    return str(run)


def summary_text(**changes) -> str:
    """A minimal summary.json of `simulate`, with some top-level values changed."""
    motor = {"demand_p99_Nm": 3.0, "rms_torque_Nm": 1.5, "static_seed_Nm": 1.9,
             "static_trot_Nm": 2.9, "verdict": "fail"}
    data = {"gait": "trot", "closure": "bushing", "answer": "", "verdict": "fail",
            "mean_forward_speed_m_s": 0.1, "gait_speed_m_s": 0.16, "max_tilt_deg": 2.0,
            "seed_peak_torque_Nm": 1.95, "motor_peak_torque_Nm": 5.0,
            "legs": {"FL": {"A": motor, "B": motor}}, **changes}
    return json.dumps(data)


def good_run(t):
    return broken_run(t, summary_text())


def c_png_folder(t):
    (t / "c.png").mkdir()
    return ["compare", good_run(t), "--out", str(t / "c.md")]


def published(table: str):
    """A [published] table put before [checks] of the default parameter file."""
    return r"^\[checks\]", table + "\n\n[checks]"


# (argv builder taking tmp_path, what the message names (a file name or option; {t}: tmp_path),
#  expected parts)
CASES = {
    # parameter files
    "published: unknown figure": conf(
        "analyze", *published("[published.top_speed]\nvalue = 1.0\nsource = 'a paper'"),
        "published.top_speed = 'top_speed': must be one of ['extension_range_m'"),
    "published: range reversed": conf(
        "analyze", *published("[published.extension_range_m]\nvalue = [0.25, 0.08]\n"
                              "source = 'a paper'"),
        "published.extension_range_m.value = [0.25, 0.08]: a range must be [low, high]"),
    "published: no source": conf(
        "analyze", *published("[published.no_load_speed_rad_s]\nvalue = 12.0"),
        "published.no_load_speed_rad_s = ", "must be a table with value, source"),
    "published: a pair for a number": conf(
        "analyze", *published("[published.peak_output_torque_Nm]\nvalue = [1.0, 2.0]\n"
                              "source = 'a paper'"),
        "published.peak_output_torque_Nm.value = [1.0, 2.0]: must be one number"),
    "published: negative value": conf(
        "analyze", *published("[published.peak_output_torque_Nm]\nvalue = -5.0\n"
                              "source = 'a paper'"),
        "published.peak_output_torque_Nm.value = -5.0: must be a positive finite number"),
    "config missing": (lambda t: ["analyze", "--config", str(t / "nope.toml")], "nope.toml",
                       "parameter file not found"),
    "config is a folder": (lambda t: ["analyze", "--config", str(t)], "{t}:",
                           "is a folder; parameter file must be a file"),
    "config not utf-8": (lambda t: ["analyze", "--config", str(text_file(t, b"\xff\xfe[leg]",
                                                                        "p.toml"))],
                         "p.toml", "not UTF-8"),
    "config not toml": conf("analyze", r"^mass_kg = 0.02488", "mass_kg = [", "not valid TOML"),
    "text for a number": conf("analyze", r"^a_m = 0.060", "a_m = 'three'",
                              "gait.a_m = 'three': must be a number"),
    "nan hip height, analyze": conf("analyze", r"^hip_z_m = 0.0", "hip_z_m = nan",
                                    "body.hip_z_m = nan: must be a finite number in [-2, 2]"),
    "nan hip height, simulate": conf("simulate", r"^hip_z_m = 0.0", "hip_z_m = nan",
                                     "body.hip_z_m = nan"),
    "nan hip height, models": conf("models", r"^hip_z_m = 0.0", "hip_z_m = nan",
                                   "body.hip_z_m = nan"),
    "infinite length": conf("analyze", r"^ce_m = 0.145", "ce_m = inf",
                            "leg.ce_m = inf: must be a finite number in (0, 2]"),
    "millimetres as metres": conf("analyze", r"^ac_m = 0.105", "ac_m = 105",
                                  "leg.ac_m = 105.0: must be in (0, 2]"),
    "negative mass": conf("analyze", r"^mass_kg = 0.02056", "mass_kg = -0.02",
                          "links.CE.mass_kg = -0.02"),
    "three legs": conf("simulate", r"^legs = 4", "legs = 3",
                       "robot.legs = 3: must be 4 (the simulation builds a quadruped"),
    "legs a float": conf("analyze", r"^legs = 4", "legs = 4.0",
                         "robot.legs = 4.0: must be an integer"),
    "samples a boolean": conf("analyze", r"^samples = 60", "samples = true",
                              "gait.samples = True: must be an integer"),
    "feet above the hips": conf("analyze", r"^y_home_m = -0.200", "y_home_m = -0.01",
                                "gait.y_home_m = -0.01: the feet must stay below the hips"),
    "body below the ground": conf("analyze", r"^hip_z_m = 0.0", "hip_z_m = 0.5",
                                  "body.hip_z_m = 0.5: the body starts", "below the ground"),
    "links outweigh the robot": conf("analyze", r"^battery_electronics_kg = 2.00\nstructure_kg = "
                                     "1.62", "battery_electronics_kg = 0.01\nstructure_kg = 0.01",
                                     "links.*.mass_kg"),
    "friction beyond the motor": conf("analyze", r"^coulomb_friction_Nm = 0.02",
                                      "coulomb_friction_Nm = 6.0",
                                      "motor.coulomb_friction_Nm = 6.0", "could not turn"),
    "warn above pass": conf("analyze", r"^sf_warn = 1.5", "sf_warn = 2.5",
                            "checks.sf_warn = 2.5: must be <= checks.sf_pass"),
    "point given as a number": conf("analyze", r"^motor_a_m = .*$", "motor_a_m = 0.0",
                                    "leg.motor_a_m = 0.0: must be [x, y]"),
    "no gravity": conf("analyze", r"^gravity_m_s2 = 9.81", "gravity_m_s2 = 0",
                       "robot.gravity_m_s2 = 0.0"),
    "unknown key": conf("models", r"^b_m = 0.030", "b_m = 0.030\nc_m = 1",
                        "[gait] has unknown key(s) ['c_m']"),
    "gait out of the workspace": conf("analyze", r"^y_home_m = -0.200", "y_home_m = -0.400",
                                      "foot path leaves the workspace", "gait.y_home_m"),
    # [limits]: the default gait leaves them (the seed's ellipse bends knee D to 66.8 deg), or
    # they are no limits
    "limits the gait leaves, analyze": conf(
        "analyze", r"^knee_min_deg = 20.0", "knee_min_deg = 70.0",
        "the foot path leaves the leg's limits (seed_ellipse path, sample ", " of 241 at t = ",
        "knee D angle", "deg < least 70 deg ([limits].knee_min_deg)"),
    "limits the gait leaves, simulate": conf(
        "simulate", r"^extension_max_m = 0.27", "extension_max_m = 0.2",
        "the foot path leaves the leg's limits (", " m > most 0.2 m ([limits].extension_max_m)"),
    "limits the gait leaves, --set": (lambda t: sim(t, "--set", "limits.theta_b_max_deg=-30"),
                                      "command line (--set)", "motor B angle",
                                      "> most -30 deg ([limits].theta_b_max_deg)"),
    "tracking a path without a floor": scen("gait: seed_ellipse\ncontroller: {kind: tracking}\n",
                                            "scenario.gait", "follows a gait's floor"),
    "tracking a stand-up": scen("gait: stand_up\ncontroller: {kind: tracking}\n",
                                "scenario.gait = 'stand_up'", "a jump's or a drop's"),
    "tracking takeover beyond the ramp": scen(
        "gait: bound\ncontroller: {kind: tracking, takeover: 2}\n",
        "scenario.controller.takeover = 2.0: must be in [0, 1]"),
    "tracking takeover in words": scen(
        "gait: bound\ncontroller: {kind: tracking, takeover: soon}\n",
        "scenario.controller.takeover = 'soon': must be a number"),
    "push share beyond the quintic": scen("gait: {kind: jump, push_share: 3}\n",
                                          "scenario.gait.push_share = 3.0: must be in (0.5, 1.25]"),
    "tracking with other leg phases": scen(
        "gait: bound\ncontroller: {kind: tracking}\nphases_rad: [0, 0, 0, 0]\n",
        "scenario.phases_rad", "the gait's own leg phases"),
    "scenario's path leaves the limits": scen("gait: {kind: doggo, stance_depth_m: 0.08}\n",
                                              "the foot path leaves the leg's limits (doggo path",
                                              "m > most 0.27 m ([limits].extension_max_m)"),
    "limit min above its max": conf("analyze", r"^theta_a_max_deg = 10.0",
                                    "theta_a_max_deg = -175.0",
                                    "limits.theta_a_min_deg = -170.0: must be < "
                                    "limits.theta_a_max_deg = -175"),
    "motor limit beyond a turn": conf("analyze", r"^theta_b_min_deg = -170.0",
                                      "theta_b_min_deg = -400.0",
                                      "limits.theta_b_min_deg = -400.0: must be in [-180, 180]"),
    "extension in millimetres": conf("simulate", r"^extension_max_m = 0.27",
                                     "extension_max_m = 270",
                                     "limits.extension_max_m = 270.0: must be in [0, 2]"),
    "knee limit of a straight knee": conf("analyze", r"^knee_min_deg = 20.0", "knee_min_deg = 180",
                                          "limits.knee_min_deg = 180.0: must be in [0, 180)"),
    "negative interference angle": conf("models", r"^upper_links_min_deg = 10.0",
                                        "upper_links_min_deg = -1.0",
                                        "limits.upper_links_min_deg = -1.0: must be in [0, 180)"),
    "limit in words": conf("analyze", r"^theta_a_min_deg = -170.0", "theta_a_min_deg = 'down'",
                           "limits.theta_a_min_deg = 'down': must be a number"),
    "unknown limit": conf("models", r"^upper_links_min_deg = 10.0",
                          "upper_links_min_deg = 10.0\nhip_min_deg = 3.0",
                          "[limits] has unknown key(s) ['hip_min_deg']"),
    "limits inside [leg]": conf("analyze", r"^ef_m = 0.040", "ef_m = 0.040\nlimits = 3",
                                "leg.limits = 3: the leg's limits are the [limits] table"),
    # scenario files
    "scenario missing": (lambda t: sim(t, "--scenario", str(t / "no.yaml")), "no.yaml",
                         "scenario file not found"),
    "scenario is a folder": (lambda t: sim(t, "--scenario", str(t)), "{t}:",
                             "is a folder"),
    "scenario not utf-8": scen(b"duration_s: 1.0 \xff\n", "not UTF-8"),
    "malformed yaml": scen("duration_s: [1, 2\n", "not valid YAML at line"),
    "toml as scenario": scen(DEFAULT, "a parameter file goes to --config", name="default.toml"),
    "scenario a list": scen("- 1\n- 2\n", "must be a mapping of scenario fields"),
    "scalar for a list": scen("phases_rad: 0.0\n",
                              "scenario.phases_rad = 0.0: must be a list of numbers"),
    "three phases": scen("phases_rad: [0, 1, 2]\n", "scenario.phases_rad", "needs 4 values"),
    "text for a float": scen("duration_s: three\n",
                             "scenario.duration_s = 'three': must be a number"),
    "nan duration": scen("duration_s: .nan\n", "scenario.duration_s = nan: must be a finite"),
    "integer beyond any float": scen("catch_gain: 1" + "0" * 400 + "\n", "scenario.catch_gain",
                                     "must be a finite number"),
    "ball step of half a second": scen("closure: ball\ntime_step_s: 0.5\n",
                                       "scenario.time_step_s = 0.5", "motor model"),
    "nanosecond step": scen("time_step_s: 1e-9\n", "scenario.time_step_s = 1e-09",
                            "must be >= 1e-06"),
    "log period of 10 s": scen("duration_s: 20.0\nlog_period_s: 10\n",
                               "scenario.log_period_s = 10.0", "intervals per gait cycle"),
    "plant config not a mapping": scen("plant_config: sap\n", "scenario.plant_config = 'sap'",
                                       "must be a mapping of MultibodyPlantConfig"),
    "plant config unknown field": scen("plant_config: {solver: sap}\n",
                                       "scenario.plant_config.solver", "unknown field"),
    "plant config time step": scen("plant_config: {time_step: 0.001}\n",
                                   "scenario.plant_config.time_step = 0.001", "time_step_s"),
    "closure constraints need SAP": scen(
        "plant_config: {discrete_contact_approximation: tamsi}\n",
        "scenario.plant_config.discrete_contact_approximation = 'tamsi'", "SAP constraint"),
    "plant config contact model": scen("plant_config: {contact_model: magic}\n",
                                       "scenario.plant_config.contact_model = 'magic'"),
    "plant config hydroelastic": scen("plant_config: {contact_model: hydroelastic}\n",
                                      "contact_model = 'hydroelastic'", "point-contact"),
    # values Drake would abort the process on (a failed C++ condition), or refuse late
    "plant config zero stiction": scen("plant_config: {stiction_tolerance: 0}\n",
                                       "scenario.plant_config.stiction_tolerance = 0"),
    "plant config negative near-rigid": scen("plant_config: {sap_near_rigid_threshold: -5}\n",
                                             "sap_near_rigid_threshold = -5"),
    "plant config zero penetration": scen("plant_config: {penetration_allowance: 0}\n",
                                          "penetration_allowance = 0"),
    "simulator config scheme": scen("simulator_config: {integration_scheme: bogus}\n",
                                    "integration_scheme = 'bogus'", "runge_kutta3"),
    "simulator config step": scen("simulator_config: {max_step_size: -1}\n",
                                  "max_step_size = -1"),
    "simulator config start": scen("simulator_config: {start_time: 5}\n",
                                   "start_time = 5", "starts at t = 0"),
    "simulator config crawl": scen("simulator_config: {target_realtime_rate: 0.001}\n",
                                   "target_realtime_rate = 0.001", "as fast as possible"),
    "simulator config accuracy": scen("simulator_config: {accuracy: -1}\n", "accuracy = -1"),
    "scenario alias bomb": scen("a: &a [1, 1, 1, 1, 1, 1, 1, 1, 1]\nb: &b [*a, *a, *a, *a]\n"
                                "c: &c [*b, *b, *b, *b]\nduration_s: *c\n", "aliases"),
    "scenario field twice": scen("duration_s: 1.0\nduration_s: 2.0\n", "written twice"),
    "scenario nested deep": scen("plant_config: " + "[" * 50 + "]" * 50 + "\n", "nested deeper"),
    "scenario that is a FIFO": (lambda t: sim(t, "--scenario", fifo(t)), "fifo.yaml",
                                "not a regular file"),
    "parameter file that is a FIFO": (lambda t: ["analyze", "--config", fifo(t, "p.toml"),
                                                 "--out", str(t / "out")], "p.toml",
                                      "not a regular file"),
    "empty --out": (lambda t: ["simulate", "--out", ""], "command line", "--out = ''"),
    # --set FIELD=VALUE (analyze, simulate) and the gait variants' own fields
    "--set without a value": (lambda t: sim(t, "--set", "motor.gear_ratio"), "command line",
                              "FIELD=VALUE"),
    "--set an unknown field": (lambda t: sim(t, "--set", "motor.nonsense=1"), "command line",
                               "motor.nonsense"),
    "--set a value out of bounds": (lambda t: ["analyze", "--set", "motor.gear_ratio=-3",
                                               "--out", str(t / "out")], "command line",
                                    "motor.gear_ratio = -3"),
    "--set not a parameter": (lambda t: sim(t, "--set", "wheel.radius=1"), "command line",
                              "not a parameter"),
    "--set text for a number": (lambda t: sim(t, "--set", "motor.gear_ratio=fast"),
                                "command line", "motor.gear_ratio"),
    "doggo flight share beyond 1": scen("gait: {kind: doggo, flight_share: 1.5}\n",
                                        "flight_share = 1.5"),
    "doggo negative depth": scen("gait: {kind: doggo, stance_depth_m: -0.01}\n",
                                 "stance_depth_m = -0.01"),
    "doggo unknown field": scen("gait: {kind: doggo, wings: 2}\n", "wings"),
    # the maneuvers' fields and modifiers (issue 22)
    "negative payload": scen("payload_kg: -1.0\n", "scenario.payload_kg = -1.0"),
    "payload offset of 2 values": scen("payload_kg: 1.0\npayload_offset_m: [0.0, 0.1]\n",
                                       "scenario.payload_offset_m", "3 values"),
    "slope of 80 deg": scen("slope_deg: 80.0\n", "scenario.slope_deg = 80.0"),
    "slope as text": scen("slope_deg: steep\n", "scenario.slope_deg", "steep"),
    "jump of negative height": scen("gait: {kind: jump, height_m: -0.1}\n", "height_m", "-0.1"),
    "drop height as text": scen("gait: {kind: drop, height_m: high}\n", "height_m", "high"),
    "crawl below three feet down": scen("gait: {kind: walk, duty_factor: 0.5}\n",
                                        "duty_factor", "0.5"),
    "pronk unknown field": scen("gait: {kind: pronk, spring: 2}\n", "spring"),
    # a top speed at a chosen duty factor (issue 41)
    "top speed at a duty factor of 1": scen("gait: {kind: trot, speed_m_s: max, duty_factor: 1}\n",
                                            "duty_factor = 1", "(0, 1)"),
    "top speed at a duty factor in words": scen(
        "gait: {kind: bound, speed_m_s: max, duty_factor: half}\n", "duty_factor = 'half'"),
    "top speed at a duty factor no stance sample holds": scen(
        "gait: {kind: trot, speed_m_s: max, duty_factor: 0.02}\n", "no trot at any speed",
        "the stance's balance"),
    "top speed at a share beyond 1": scen("gait: {kind: trot, speed_m_s: max, share: 1.2}\n",
                                          "scenario.top_speed_share = 1.2", "(0, 1]"),
    "top speed at a share of 0": scen("gait: {kind: pronk, speed_m_s: max, share: 0}\n",
                                      "scenario.top_speed_share = 0", "(0, 1]"),
    "top speed at a share in words": scen(
        "gait: {kind: bound, speed_m_s: max, share: most}\n", "scenario.top_speed_share",
        "most"),
    "a share without a top speed": scen("gait: trot\ntop_speed_share: 0.9\n",
                                        "scenario.top_speed_share = 0.9", "top speed"),
    "models into an empty --out": (lambda t: ["models", "--out", ""], "command line", "--out = ''"),
    "simulator config text for a number": scen(
        "simulator_config: {target_realtime_rate: fast}\n",
        "scenario.simulator_config.target_realtime_rate = 'fast'", "must be a number"),
    "log period not whole motor periods": scen(
        "closure: ball\ntime_step_s: 5e-4\nmotor_period_s: 8e-4\n",
        "scenario.log_period_s = 0.002", "whole number of motor periods"),
    "typo field": scen("durration_s: 1.0\n", "scenario.durration_s", "unknown field"),
    "bad closure": scen("closure: glue\n", "scenario.closure = 'glue': allowed"),
    "text for a boolean": scen("touchdown_detection: maybe\n",
                               "scenario.touchdown_detection = 'maybe': must be true or false"),
    "fractional delay": scen("control_delay_periods: 1.5\n",
                             "scenario.control_delay_periods = 1.5: must be an integer"),
    "long delay": scen("control_delay_periods: 100\n", "scenario.control_delay_periods = 100",
                       "phase margin"),
    "bandwidth beyond the controller": scen("swing_bandwidth_hz: 100\n",
                                            "scenario.control_period_s = 0.002",
                                            "20x its bandwidth"),
    "params_file missing beside the scenario": scen("params_file: mine.toml\n",
                                                    "parameter file not found (the params_file "
                                                    "of", "mine.toml"),
    "gait override out of range": scen("gait_frequency_hz: -1\n", "scenario gait_frequency_hz",
                                       "gait.frequency_hz = -1.0"),
    "gait override out of the workspace": scen("gait_y_home_m: -0.35\n", "gait_y_home_m",
                                               "foot path leaves the workspace"),
    "load transfer beyond the stance": scen("load_transfer_s: 1.0\n",
                                            "scenario.load_transfer_s = 1.0", "stance"),
    "pose rate beyond the log": scen("pose_rate_hz: 1e6\n", "scenario.pose_rate_hz",
                                     "1 / log_period_s"),
    "explicit bushing step": scen("time_step_s: 0.0005\nclosure: bushing_rpy\n",
                                  "scenario.time_step_s = 0.0005: the explicit bushing"),
    "tiny loop gap": scen("target_loop_gap_m: 1e-12\n", "scenario.target_loop_gap_m"),
    # command-line values
    "duration not a number": (lambda t: sim(t, "--duration", "three"), "--duration",
                              "invalid float value: 'three'"),
    "duration nan": (lambda t: sim(t, "--duration", "nan"), "command line",
                     "scenario.duration_s = nan"),
    "duration negative": (lambda t: sim(t, "--duration", "-1"), "command line",
                          "scenario.duration_s = -1.0"),
    "duration shorter than a log interval": (lambda t: sim(t, "--duration", "1e-300"),
                                             "command line", "scenario.duration_s = 1e-300"),
    "duration of 1e9 s": (lambda t: sim(t, "--duration", "1e9"), "command line",
                          "scenario.duration_s = 1000000000.0", "kept in memory"),
    "closure not a choice": (lambda t: sim(t, "--closure", "glue"), "--closure", "glue"),
    "gait not a choice": (lambda t: ["analyze", "--gait", "glue"], "--gait", "glue"),
    "no command": (lambda t: [], "fivebar-drake", "required"),
    "unknown command": (lambda t: ["simulte"], "simulte", "invalid choice"),
    # output paths
    "analyze into a file": (lambda t: ["analyze", "--out", str(a_file(t))], "--out",
                            "afile: is a file; the output must be a folder"),
    "simulate into a file": (lambda t: ["simulate", "--out", str(a_file(t))], "--out",
                             "is a file"),
    "simulate below a file": (lambda t: ["simulate", "--out", str(a_file(t) / "sub")], "--out",
                              "a part of the path is a file"),
    "simulate unwritable": (lambda t: ["simulate", "--out", str(unwritable(t))], "--out",
                            "cannot create or write into this folder"),
    "models into a file": (lambda t: ["models", "--out", str(a_file(t))], "--out", "is a file"),
    "compare into a folder": (lambda t: ["compare", broken_run(t, "{}"), "--out", str(t)],
                              "--out", "is a folder; give a file name"),
    "compare a missing run": (lambda t: ["compare", str(t / "nowhere"), "--out",
                                         str(t / "c.md")], "summary.json",
                              "run summary not found", "simulate --out"),
    "compare a truncated summary": (lambda t: ["compare", broken_run(t, '{"gait": "tr'),
                                               "--out", str(t / "c.md")], "summary.json",
                                    "not valid JSON"),
    "compare a foreign summary": (lambda t: ["compare", broken_run(t, '{"gait": "trot"}'),
                                             "--out", str(t / "c.md")], "summary.json",
                                  "lacks the keys"),
    "compare a null verdict": (lambda t: ["compare", broken_run(t, summary_text(verdict=None)),
                                          "--out", str(t / "c.md")], "summary.json",
                               "verdict = None: must be text"),
    "compare a speed in words": (lambda t: ["compare", broken_run(t, summary_text(
        mean_forward_speed_m_s="fast")), "--out", str(t / "c.md")], "summary.json",
        "mean_forward_speed_m_s = 'fast': must be a number or null"),
    "compare a summary nested 100000 deep": (lambda t: ["compare", broken_run(
        t, "[" * 100_000 + "]" * 100_000), "--out", str(t / "c.md")], "summary.json",
        "nested too deeply"),
    "compare into a PNG": (lambda t: ["compare", good_run(t), "--out", str(t / "x.png")],
                           "--out", "give a .md file name"),
    "compare over its input": (lambda t: ["compare", good_run(t), "--out",
                                          str(t / "run" / "summary.json")], "--out",
                               "give a .md file name"),
    "compare over an input named .md": (lambda t: ["compare", good_run(t), "--out",
                                                   str(t / "run")], "--out", "is a folder"),
    # issue 33's eleventh class: any file in a run's folder is the run's
    "compare over an input's summary.md": (lambda t: ["compare", good_run(t), "--out",
                                                      str(t / "run" / "summary.md")], "--out",
                                           "never writes into a run's folder"),
    "compare into an input's subfolder": (lambda t: ["compare", good_run(t), "--out",
                                                     str(t / "run" / "sub" / "c.md")], "--out",
                                          "never writes into a run's folder"),
    # issue 33's twelfth class: the runs are read before the output's folder is made
    "compare a missing run into new folders": (lambda t: ["compare", str(t / "nowhere"),
                                                          "--out", str(t / "new" / "c.md")],
                                               "nowhere", "not found"),
    "compare beside a folder named like its PNG": (c_png_folder, "--out", "c.png is a folder"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_bad_input_exits_2_with_a_named_message(case, tmp_path, capsys):
    argv, names, *expected = CASES[case]
    args = argv(tmp_path)
    code = main(args)
    captured = capsys.readouterr()
    err = captured.err
    assert code == 2, (case, err)
    assert "Traceback" not in err + captured.out
    assert names.format(t=tmp_path) in err, (case, err)
    for part in expected:
        assert part in err, (case, part, err)
    if not any("params_file" in part for part in expected):
        assert "params_file of" not in err, err
    assert not (tmp_path / "out" / "summary.json").exists()
    assert not (tmp_path / "out" / "report.json").exists()
    assert not (tmp_path / "out" / "leg.sdf").exists()
    assert not (tmp_path / "new").exists()
    messages = [line for line in err.splitlines() if line.startswith("fivebar-drake")]
    assert len(messages) <= 1, err                        # one message


def test_there_are_enough_cases():
    assert len(CASES) >= 40


@pytest.mark.parametrize("argv, expect", [
    (["analyze", "--config", "{t}/nope.toml"], "nope.toml: parameter file not found"),
    (["simulate", "--scenario", "{t}/bad.yaml", "--out", "{t}/o"], "not valid YAML"),
    (["simulate", "--duration", "1e9", "--out", "{t}/o"], "scenario.duration_s = 1000000000.0"),
])
def test_bad_input_as_a_real_process(tmp_path, argv, expect):
    (tmp_path / "bad.yaml").write_text("duration_s: {1\n")
    run = subprocess.run([sys.executable, "-m", "fivebar_drake",
                          *[a.format(t=tmp_path) for a in argv]], capture_output=True, text=True)
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert expect in run.stderr


def test_params_file_is_relative_to_the_scenario(tmp_path, monkeypatch):
    """A scenario's params_file is found beside the scenario, whatever the working folder."""
    folder = tmp_path / "study"
    folder.mkdir()
    params_file(folder, r"^frequency_hz = 1.0", "frequency_hz = 2.0", name="fast.toml")
    (folder / "s.yaml").write_text("params_file: fast.toml\n")
    monkeypatch.chdir(tmp_path)
    scenario, params = load_run(folder / "s.yaml")
    assert params.gait.frequency_hz == 2.0
    scenario, params = load_run(folder / "s.yaml", params_file=str(DEFAULT_PATH))   # --config
    assert params.gait.frequency_hz == 1.0


def test_empty_scenario_file_is_the_defaults(tmp_path):
    (tmp_path / "s.yaml").write_text("# nothing changed\n")
    assert load_run(tmp_path / "s.yaml")[0] == load_run()[0]


def test_version(capsys):
    assert main(["--version"]) == 0
    assert re.fullmatch(r"fivebar-drake \d+\.\d+\.\d+ \(drake 1\.51\.1\)\n", capsys.readouterr().out)


def test_yaml_numbers_without_a_dot_are_numbers(tmp_path):
    (tmp_path / "s.yaml").write_text("time_step_s: 5e-4\nlog_period_s: 2E-3\n")
    scenario, _ = load_run(tmp_path / "s.yaml")
    assert scenario.time_step_s == 5e-4 and scenario.log_period_s == 2e-3


def test_internal_error_points_to_a_log(tmp_path, capsys, monkeypatch):
    """An unexpected error is a short message and a log file with the traceback (exit 3)."""
    from fivebar_drake import pipeline

    def broken(*args, **kwargs):
        raise ZeroDivisionError("injected")

    monkeypatch.setattr(pipeline, "analyze", broken)
    assert main(["analyze", "--out", str(tmp_path)]) == 3
    err = capsys.readouterr().err
    assert "Traceback" not in err and "internal error" in err and "injected" in err
    log = Path(re.search(r"the traceback is in (\S+)", err).group(1))
    assert "Traceback" in log.read_text() and "ZeroDivisionError" in log.read_text()
    log.unlink()


# -- property-based: any value in any field of a parameter file --------------------------------

NUMERIC_KEYS = [(m.group(1), m.group(2)) for m in
                re.finditer(r"^(\w+) = (-?[0-9][0-9.e+-]*)\s", DEFAULT, flags=re.M)]


def toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") \
            if math.isinf(value) else repr(value)
    if isinstance(value, (int, str)):
        return json.dumps(value)
    return "[" + ", ".join(toml_value(v) for v in value) + "]"


ANY_VALUE = st.one_of(
    st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -1.0, 1e300, -1e-300]),
    st.floats(allow_nan=False, allow_infinity=False, min_value=-1e9, max_value=1e9),
    st.integers(min_value=-10**12, max_value=10**12),
    st.text(max_size=5), st.booleans(), st.lists(st.floats(-1, 1), max_size=3),
    st.floats(min_value=0.5, max_value=2.0),          # a factor near the default: often valid
)


@settings(max_examples=30, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=st.sampled_from(NUMERIC_KEYS), value=ANY_VALUE)
def test_any_parameter_value_is_refused_cleanly_or_analysed(tmp_path, capsys, key, value):
    """analyze with one parameter set to anything: exit 2 naming the field, or a valid report."""
    name, default = key
    if isinstance(value, float) and 0.5 <= value <= 2.0:
        value = float(default) * value
    path = params_file(tmp_path, rf"^{name} = {re.escape(default)}\s", f"{name} = "
                       f"{toml_value(value)}\n")
    out = tmp_path / uuid.uuid4().hex                        # one per example
    code = main(["analyze", "--config", str(path), "--out", str(out)])
    err = capsys.readouterr().err
    assert "Traceback" not in err
    if code == 2:
        assert str(path) in err and "error:" in err
        assert not (out / "report.json").exists()
    else:
        assert code == 0, err
        report = json.loads((out / "report.json").read_text())     # valid JSON, no NaN
        assert all(math.isfinite(m["safety_factor"]) for r in report["results"].values()
                   for m in r.values())


SCENARIO_FLOATS = ["duration_s", "time_step_s", "control_period_s", "motor_period_s",
                   "log_period_s", "pose_rate_hz", "swing_bandwidth_hz", "damping_ratio",
                   "load_transfer_s", "catch_gain", "stand_s", "target_loop_gap_m",
                   "gait_frequency_hz", "gait_a_m", "control_delay_periods", "phases_rad",
                   "touchdown_detection", "closure"]


@settings(max_examples=60, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(name=st.sampled_from(SCENARIO_FLOATS), value=ANY_VALUE)
def test_any_scenario_value_is_refused_cleanly_or_accepted(tmp_path, name, value):
    """A scenario with one field set to anything: a ParameterError naming the file and the
    field, or a scenario that passes every check before a run (not simulated here)."""
    path = tmp_path / "s.yaml"
    path.write_text(json.dumps({name: value}) if not (isinstance(value, float)
                                                      and not math.isfinite(value))
                    else f"{name}: {'.nan' if math.isnan(value) else '.inf' if value > 0 else '-.inf'}\n")
    try:
        load_run(path)
    except ParameterError as err:
        assert str(path) in str(err) and ("scenario" in str(err) or "gait" in str(err))


def test_the_step_checks_second_run_is_checked_before_anything_runs(tmp_path, capsys):
    """Issue 33's ninth class: a 1 us plant step with --step-check would run, then fail on its
    0.5 us half step after the folder was cleared; now the half step's checks come first: exit
    2 naming --step-check and the field, nothing simulated, the folder as it was."""
    scenario = tmp_path / "s.yaml"
    scenario.write_text("time_step_s: 1.0e-6\nduration_s: 0.5\n")
    out = tmp_path / "run"
    out.mkdir()
    (out / "summary.json").write_text("{}")
    assert main(["simulate", "--scenario", str(scenario), "--step-check", "--out",
                 str(out)]) == 2
    err = capsys.readouterr().err
    assert "--step-check" in err and "scenario.time_step_s" in err and "step check:" not in err
    assert sorted(p.name for p in out.iterdir()) == ["summary.json"]


@pytest.mark.parametrize("argv", [
    ["envelope", "SPEC", "--out", "LONG"], ["compare", "RUN", "RUN", "--out", "LONG.md"],
    ["sweep", "SPEC", "--out", "LONG"], ["optimal", "--out", "LONG"],
    ["analyze", "--out", "LONG"], ["simulate", "--out", "LONG/x"]])
def test_an_output_name_too_long_for_the_file_system_is_exit_2(argv, tmp_path, capsys):
    """Issue 33's twentieth class: a 300-byte folder name (the file system takes 255) was a
    bug report (exit 3) in envelope and compare; every command refuses it naming --out,
    before anything is read or made."""
    long = str(tmp_path / ("x" * 300))
    spec = tmp_path / "spec.yaml"
    spec.write_text("maneuvers:\n  - {name: trot, gait: trot}\n")
    argv = [a.replace("LONG", long).replace("SPEC", str(spec)).replace("RUN", str(tmp_path))
            for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "--out" in err and "255 bytes" in err and len(err) < 1000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.yaml"]


def test_an_error_quotes_at_most_a_few_hundred_characters_of_a_value(tmp_path, capsys):
    """Issue 33's nineteenth class: a duty cycle of 30 000 steps (over its 1000) echoed whole
    gave a message of megabytes; now under 1 kB, naming the field and the count."""
    spec = tmp_path / "big.yaml"
    spec.write_text("maneuvers:\n  - {name: trot, gait: trot}\nduty_cycle:\n"
                    + "  - {maneuver: trot, duration_s: 1}\n" * 30000)
    assert main(["envelope", str(spec), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "duty_cycle" in err and "characters" in err and len(err) < 1000


def test_a_folder_in_use_by_another_run_is_refused_and_a_killed_run_leaves_no_lock(tmp_path,
                                                                                  capsys):
    """Issue 33's eighth class: one folder, one run. While another process holds an output
    folder (as a running command does: core/files.lock_folder), a command into it exits 2
    naming --out and writes nothing; once that process is killed (SIGKILL: no clean-up) the
    folder is free again."""
    import signal

    out = tmp_path / "models"
    holder = subprocess.Popen([sys.executable, "-c",
                               "import sys, time\n"
                               "from fivebar_drake.core.files import prepare_output_dir\n"
                               f"prepare_output_dir({str(out)!r}, '--out')\n"
                               "print('held', flush=True)\n"
                               "time.sleep(60)\n"], stdout=subprocess.PIPE, text=True)
    try:
        assert holder.stdout.readline().strip() == "held"
        assert main(["models", "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert "--out" in err and "another fivebar-drake run" in err
        assert not any(p.suffix == ".sdf" for p in out.iterdir())
    finally:
        holder.send_signal(signal.SIGKILL)
        holder.wait()                 # reaped: the system has dropped its flock
    assert main(["models", "--out", str(out)]) == 0
    assert any(p.suffix == ".sdf" for p in out.iterdir())


@pytest.mark.parametrize("setting, field, words", [
    ("motor.bus_voltage_V=1e-6", "motor.bus_voltage_V", "[1, 1000]"),
    ("motor.peak_current_A=1e-300", "motor.peak_current_A", "[0.001, 10000]"),
    ("motor.torque_constant_Nm_per_A=1e-9", "motor.torque_constant_Nm_per_A", "[0.0001, 10]"),
    ("motor.model=torque_speed_line", "motor.model", "rather than change the model alone")])
def test_an_absurd_motor_value_is_blamed_on_itself(setting, field, words, capsys):
    """Issue 33's twenty-first class: a bus of a microvolt, a peak current of 1e-300 A or a
    torque constant of 1e-9 N m/A were reported as the friction's or the gear ratio's fault;
    switching a bldc [motor] to a torque-speed line was refused with a list that holds it."""
    assert main(["analyze", "--set", setting, "--out", "unused"]) == 2
    err = capsys.readouterr().err
    assert f"{field} = " in err and words in err and "friction" not in err
    assert not Path("unused").exists()


def test_set_takes_what_a_sweep_takes():
    """Issue 33's sixteenth class: --set reads its value as a sweep's spec (YAML): an integer
    field and a list field are set; a fraction for an integer is still refused."""
    from fivebar_drake.robots.quadruped.config import load_params
    from fivebar_drake.studies.fivebar_leg import with_sets

    params = with_sets(load_params(None), ["gait.samples=120", "leg.motor_a_m=[-0.05, 0.0]"])
    assert params.gait.samples == 120 and tuple(params.leg.motor_a_m) == (-0.05, 0.0)
    with pytest.raises(ParameterError, match="gait.samples"):
        with_sets(load_params(None), ["gait.samples=12.5"])


def test_compare_tells_same_named_runs_apart(tmp_path):
    """Issue 33's twenty-third class: two envelopes' `drop` maneuvers were both labelled
    "drop"; each run is labelled by as many parent folders as it takes to tell them apart."""
    from fivebar_drake.simulation.comparison import load_summaries

    runs = []
    for parent in ("gear8", "gear11"):
        folder = tmp_path / parent / "drop"
        folder.mkdir(parents=True)
        (folder / "summary.json").write_text(summary_text())
        runs.append(str(folder))
    assert [s["label"] for s in load_summaries(runs)] == ["gear8/drop", "gear11/drop"]


def test_compare_answers_first_and_says_when_the_deciding_check_moves(tmp_path):
    """Issue 32: the comparison's first paragraph gives each run's verdict and deciding check,
    and says when a change (a gearbox) turned one check's failure into another's."""
    import json as json_

    from fivebar_drake.simulation.comparison import load_summaries, markdown

    runs = []
    for name, check in (("gear8", "torque"), ("gear11.5", "speed")):
        folder = tmp_path / name
        folder.mkdir()
        data = json_.loads(summary_text(verdict="fail"))
        data.update(deciding_check=check, worst_motor="FL A")
        data["legs"]["FL"]["A"]["checks"] = {
            "torque": {"sf": 1.41, "torque_Nm": 3.55, "limit_Nm": 5.0, "quadrant": "driving"},
            "speed": {"least_margin": 0.8, "outside_fraction": 0.04}, "thermal": {"margin": 1.3}}
        (folder / "summary.json").write_text(json_.dumps(data))
        runs.append(str(folder))
    text = markdown(load_summaries(runs))
    first = text.split("\n\n")[1]
    assert first.startswith("**Answer:** gear8 FAIL (torque, SF 1.41)")
    assert "gear11.5 FAIL (speed, 4.0 % beyond the envelope)" in first
    assert "moved the limit from the torque check to the speed check" in first
    from style_rules import report_violations

    (tmp_path / "gear_comparison.md").write_text(markdown(load_summaries(runs)))
    assert report_violations(tmp_path / "gear_comparison.md") == []
