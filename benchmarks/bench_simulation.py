"""Simulation benchmark (`make bench`), in one process: the default trot of --duration seconds
(default 10) with each loop closure, with the share of writing its files (summary.json's
timing: plots, recording and the review, over them and the stepping; target <= 10 %); the plant alone replaying the default run's actuation,
step by step (the replay must end in the run's exact state, or the figure is not of the same
run; the actuation is recorded by a separate, identical run, so the timed runs carry no
benchmark logger), alternating with the default run --pairs times (the ratio is the median over the pairs:
this machine's speed drifts between runs); where the default run's time goes (plant, the Python
blocks, the rest of the Diagram, the summary and the output files after the run; and each block's
whole cost, dispatch and caches included, by replacing the others with the replayed actuation:
cost_by_replacement); and the peak
memory of a 10 s and a 60 s default run (each in a fresh process). Every run goes through the
pipeline (run_simulation, summarize_run, write_simulation). Prints tables, then, as its last
line, one JSON object: rtf (per closure), plant_alone_rtf, diagram_to_plant_ratio (and
_per_pair), max_loop_gap_m (per closure), rms_torque_agreement (largest per-motor relative RMS
difference against `ball`), logging_share (the Rerun recording / the whole simulate job),
output_share (writing the run's files: plots, recording, summary /
whole simulate job), step_check_ratio (simulate --step-check over simulate, median of --pairs),
peak_rss_mb_10s, peak_rss_mb_60s, split_us_per_step, python_callbacks_per_step,
cost_by_replacement_us_per_step."""

from __future__ import annotations

import argparse
import collections
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import Multiplexer, TrajectorySource, VectorLogSink
from pydrake.trajectories import PiecewisePolynomial

from fivebar_drake.simulation.builder import (PERIODIC, actuator_speeds, add_contact_integral,
                                              add_controller, add_recorders, recorded_periods)
from fivebar_drake.simulation.gait_source import GaitSource
from fivebar_drake.simulation.motor_model import MotorModel, MotorStep
from fivebar_drake.pipeline import (run_simulation, run_step_check, summarize_run,
                                    write_simulation)
from fivebar_drake.robots.quadruped.closure import CLOSURES
from fivebar_drake.robots.quadruped.plant import add_robot, set_standing_pose
from fivebar_drake.simulation import systems
from fivebar_drake.simulation.recording import write_recording
from fivebar_drake.simulation.scenario import load_scenario
from fivebar_drake.simulation.signals import signals

MEMORY_RUN = """
import resource, sys
from fivebar_drake.pipeline import run_simulation
from fivebar_drake.simulation.scenario import load_scenario
run_simulation(load_scenario(duration_s=float(sys.argv[1])), progress=False)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024)
"""
PYTHON_BLOCKS = {"gait source": (GaitSource, ("_calc",)),   # each block's Python callbacks
                 "leg controller": (systems.FootLegController, ("_update",)),
                 "motor model": (MotorStep, ("_calc",))}


def run_closure(closure: str, duration: float):
    """(record, summary, seconds to summarize, seconds to write the run's files, seconds of the
    Rerun recording alone) of the default trot with the closure."""
    record = run_simulation(load_scenario(duration_s=duration, closure=closure), progress=False)
    start = time.perf_counter()
    summary = summarize_run(record)
    post = time.perf_counter() - start
    with tempfile.TemporaryDirectory() as tmp:
        written, _ = write_simulation(record, Path(tmp))
        files = written["timing"]["outputs_s"]        # as summary.json records it
        start = time.perf_counter()
        write_recording(Path(tmp) / "again.rrd", signals(record), record, summary)
        rerun = time.perf_counter() - start
    return record, summary, post, files, rerun


def plant_alone(params, design, actuation, duration: float):
    """(real-time factor, final state) of the same plant, closure, contact and step fed the
    run's per-step joint torques (zero-order hold) with no Python systems."""
    builder = DiagramBuilder()
    plant, instance, layout = add_robot(builder, params, design)
    times, torques = actuation
    source = builder.AddSystem(TrajectorySource(PiecewisePolynomial.ZeroOrderHold(times,
                                                                                  torques.T)))
    builder.Connect(source.get_output_port(), plant.get_actuation_input_port())
    simulator = Simulator(builder.Build())
    context = plant.GetMyMutableContextFromRoot(simulator.get_mutable_context())
    set_standing_pose(plant, context, instance, layout.legs, params)
    simulator.Initialize()
    start = time.perf_counter()
    simulator.AdvanceTo(duration)
    return duration / (time.perf_counter() - start), plant.GetPositionsAndVelocities(context)


REPLACEMENTS = ("plant alone", "plant and the C++ blocks", "motor model", "controller and gait source",
                "the whole Diagram")


def replaced_run(record, actuation, keep: str, duration: float) -> tuple[float, np.ndarray]:
    """(CPU seconds, final state) of the default run's plant driven by its own per-step
    actuation (a C++ replay: the same physics bit for bit), with some of the Diagram's blocks
    kept beside it (REPLACEMENTS): none; the contact integral and the recorders; the motor
    model (its command replayed too, its output logged every step, as the plant would ask for
    it); the controller and the gait source (their command unused); all of them, wired as the
    tool wires them (the motor model driving the plant)."""
    scenario, params, design = record.scenario, record.params, record.design
    times, torques = actuation
    builder = DiagramBuilder()
    plant, instance, layout = add_robot(builder, params, design, scenario.plant_config)
    replay = builder.AddSystem(TrajectorySource(PiecewisePolynomial.ZeroOrderHold(times,
                                                                                 torques.T)))
    actuated = replay.get_output_port()
    if keep != "plant alone":
        contact = add_contact_integral(builder, plant, instance, layout, design.time_step_s)
    if keep == "the whole Diagram":
        _, motor = add_controller(builder, scenario, params, plant, instance, layout, contact,
                                  design.time_step_s)
        actuated = None                               # add_controller drives the plant
        add_recorders(builder, scenario, plant, instance, layout, motor, design.time_step_s,
                      contact)
    elif keep == "plant and the C++ blocks":
        rows = builder.AddSystem(Multiplexer([layout.nx, layout.nv]))
        log_period, _ = recorded_periods(scenario, design.time_step_s)
        recorder = builder.AddSystem(VectorLogSink(layout.nx + layout.nv, PERIODIC, log_period))
        builder.Connect(plant.get_state_output_port(instance), rows.get_input_port(0))
        builder.Connect(contact.get_output_port(), rows.get_input_port(1))
        builder.Connect(rows.get_output_port(), recorder.get_input_port())
    elif keep == "motor model":
        motor = builder.AddSystem(MotorModel(params.motor, actuator_speeds(layout), layout.nx,
                                             scenario.motor_period_s, design.time_step_s))
        builder.Connect(replay.get_output_port(), motor.GetInputPort("torque_command"))
        builder.Connect(plant.get_state_output_port(instance), motor.GetInputPort("plant_state"))
        sink = builder.AddSystem(VectorLogSink(torques.shape[1], PERIODIC, design.time_step_s))
        builder.Connect(motor.GetOutputPort("applied_torque"), sink.get_input_port())
    elif keep == "controller and gait source":
        gait = GaitSource.add_to(builder, params.gait, scenario.gait, scenario.phases_rad,
                                 scenario.stand_s, scenario.ramp_s, scenario.load_transfer_s)
        controller = scenario.controller.add_to(builder, params, layout, scenario)
        builder.Connect(gait.GetOutputPort("foot_references"),
                        controller.GetInputPort("foot_references"))
        builder.Connect(plant.get_state_output_port(instance),
                        controller.GetInputPort("plant_state"))
        builder.Connect(contact.get_output_port(), controller.GetInputPort("contact_impulse"))
    if actuated is not None:
        builder.Connect(actuated, plant.get_actuation_input_port())
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    set_standing_pose(plant, plant.GetMyMutableContextFromRoot(context), instance, layout.legs,
                      params, scenario.gait.home(params.gait), scenario.gait.lift_m(params.gait))
    simulator.Initialize()
    diagram.CalcForcedDiscreteVariableUpdate(context, diagram.AllocateDiscreteVariables())
    start = time.process_time()
    simulator.AdvanceTo(duration)
    return (time.process_time() - start,
            plant.GetPositionsAndVelocities(plant.GetMyContextFromRoot(context)))


def cost_by_replacement(record, actuation, duration: float, pairs: int) -> dict:
    """Each block's whole cost per plant step (us, CPU time, median of `pairs` rounds of
    REPLACEMENTS): what keeping it beside the replayed plant adds, its dispatch, its primitives
    and the caches it costs the plant included; and whether every variant ended in the run's
    state bit for bit."""
    steps = duration / record.design.time_step_s
    times = {keep: [] for keep in REPLACEMENTS}
    same = True
    for _ in range(pairs):
        for keep in REPLACEMENTS:
            seconds, final = replaced_run(record, actuation, keep, duration)
            times[keep].append(seconds / steps * 1e6)
            same &= bool(np.array_equal(final, record.table["state"][-1]))
    us = {keep: float(np.median(t)) for keep, t in times.items()}
    base = us["plant and the C++ blocks"]
    return {"plant alone": us["plant alone"],
            "contact integral and recorders (C++)": base - us["plant alone"],
            "motor model (its block, primitives and dispatch)": us["motor model"] - base,
            "controller and gait source (their blocks and dispatch)":
                us["controller and gait source"] - base,
            "the whole Diagram": us["the whole Diagram"],
            "same state": same}


def python_time_per_block(duration: float) -> tuple[dict, dict, float, float]:
    """Seconds spent in each Python block's callbacks during a default run (timers wrapped
    around them; a callback inside another of its block counts once), the number of callbacks
    Drake made into each block, the run's wall time and its number of plant steps."""
    spent, calls, inside = collections.Counter(), collections.Counter(), set()
    originals = {(cls, m): getattr(cls, m) for cls, methods in PYTHON_BLOCKS.values()
                 for m in methods}

    def timed(name, update):
        def wrapper(*args):
            if name in inside:
                return update(*args)
            inside.add(name)
            start = time.perf_counter()
            try:
                return update(*args)
            finally:
                spent[name] += time.perf_counter() - start
                calls[name] += 1
                inside.discard(name)
        return wrapper

    for name, (cls, methods) in PYTHON_BLOCKS.items():
        for m in methods:
            setattr(cls, m, timed(name, originals[cls, m]))
    try:
        record = run_simulation(load_scenario(duration_s=duration), progress=False)
    finally:
        for (cls, m), update in originals.items():
            setattr(cls, m, update)
    return dict(spent), dict(calls), record.wall_s, duration / record.design.time_step_s


def step_check_ratio(duration: float, pairs: int) -> tuple[float, list[float]]:
    """The simulate job with --step-check over the job without it (run, summary and files, as
    the command line does), alternating pairs times: (median ratio, the ratios)."""
    ratios = []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(pairs):
            walls = []
            for check in (False, True):
                start = time.perf_counter()
                record = run_simulation(load_scenario(duration_s=duration), progress=False)
                half = run_step_check(record, progress=False) if check else None
                write_simulation(record, Path(tmp) / str(check), half)
                walls.append(time.perf_counter() - start)
            ratios.append(walls[1] / walls[0])
    return float(np.median(ratios)), ratios


def peak_rss_mb(duration: float) -> float:
    out = subprocess.run([sys.executable, "-c", MEMORY_RUN, str(duration)], check=True,
                         capture_output=True, text=True).stdout
    return float(out.strip().splitlines()[-1])


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--duration", type=float, default=10.0)
    parser.add_argument("--pairs", type=int, default=3,
                        help="diagram / plant-alone pairs for the throughput ratio")
    args = parser.parse_args()
    print(f"{args.duration:g} s default trot per closure; one core")
    print(f"{'closure':>12} {'step (ms)':>9} {'sim wall (s)':>12} {'real-time':>9} "
          f"{'worst gap (mm)':>14} {'files (s)':>9} {'output share':>12} (target <= 10 %)")
    runs, rtf, gap, share, logging = {}, {}, {}, {}, {}
    for closure in CLOSURES:
        record, summary, post, files, rerun = run_closure(closure, args.duration)
        runs[closure] = (record, summary, post, files)
        rtf[closure] = summary["real_time_factor"]
        gap[closure] = summary["max_loop_gap_m"]
        share[closure] = files / (record.wall_s + files)
        logging[closure] = rerun / (record.wall_s + post + files)
        print(f"{closure:>12} {record.design.time_step_s * 1e3:9.4f} {record.wall_s:12.2f} "
              f"{rtf[closure]:8.2f}x {gap[closure] * 1e3:14.4f} {files:9.2f} "
              f"{share[closure] * 100:11.1f}%" + (f"  stopped: {record.error}" if record.error
                                                  else ""))
    record, _, post, files = runs["bushing"]
    # the diagram and the plant alone in alternation, args.pairs times: the ratio of each pair
    # (this machine's speed drifts by 10-20 % between runs), its median is the figure
    # the actuation is recorded by a run of its own (the logger is the benchmark's, not the
    # tool's: the timed runs are the plain default run); the runs are deterministic, and the
    # replay must end in their state bit for bit
    logged = run_simulation(record.scenario, record.params, progress=False, log_actuation=True)
    ratios, alones, same = [], [], np.array_equal(logged.table["state"][-1],
                                                  record.table["state"][-1])
    for _ in range(args.pairs):
        timed = run_simulation(record.scenario, record.params, progress=False)
        alone, final = plant_alone(logged.params, logged.design, logged.actuation,
                                   args.duration)
        same &= np.array_equal(final, timed.table["state"][-1])
        ratios.append(args.duration / timed.wall_s / alone)
        alones.append(alone)
    alone, ratio = float(np.median(alones)), float(np.median(ratios))
    print(f"plant alone (bushing closure, the run's per-step actuation): {alone:.2f}x real time "
          f"(median of {args.pairs}); diagram / plant per pair "
          f"{', '.join(f'{r:.2f}' for r in ratios)}, median {ratio:.2f}; replay ends in the "
          f"run's state: {'yes (bit for bit)' if same else 'NO'}")
    replaced = cost_by_replacement(logged, logged.actuation, args.duration, args.pairs)
    print(f"each block's whole cost, by replacing the others with the run's replayed actuation "
          f"(CPU time, median of {args.pairs}; every variant ends in the run's state bit for bit: "
          f"{'yes' if replaced['same state'] else 'NO'}):")
    for name, us in replaced.items():
        if name != "same state":
            print(f"  {name:55s} {us:7.1f} us/step")
    spent, calls, wall, steps = python_time_per_block(args.duration)
    per_step = {"plant (alone)": args.duration / alone / steps * 1e6}
    per_step.update({f"{name} ({calls.get(name, 0) / steps:.2f} Python callbacks/step)":
                     t / steps * 1e6 for name, t in spent.items()})
    per_step["rest of the Diagram (Drake dispatch, logs, cache effects)"] = (
        wall / steps * 1e6 - sum(per_step.values()))
    per_step["summary (after the run)"] = post / steps * 1e6
    per_step["output files: plots, recording, summary (after the run)"] = files / steps * 1e6
    print(f"where the time goes, default run with timers (wall {wall / steps * 1e6:.0f} us per "
          "plant step):")
    for name, us in per_step.items():
        print(f"  {name:55s} {us:7.1f} us/step")
    ball = runs["ball"][1]["legs"]
    agreement = {c: max(abs(runs[c][1]["legs"][leg][m]["rms_torque_Nm"]
                            / ball[leg][m]["rms_torque_Nm"] - 1)
                        for leg in ball for m in ball[leg]) for c in CLOSURES if c != "ball"}
    print("per-motor RMS torque against ball, largest difference: "
          + ", ".join(f"{c} {v * 100:.1f} %" for c, v in agreement.items()))
    check, checks = step_check_ratio(args.duration, args.pairs)
    print(f"simulate --step-check / simulate (run, summary, files): "
          f"{', '.join(f'{r:.2f}' for r in checks)}, median {check:.2f} (target <= 3.2)")
    rss10, rss60 = peak_rss_mb(10.0), peak_rss_mb(60.0)
    print(f"peak memory (fresh process): 10 s run {rss10:.0f} MB, 60 s run {rss60:.0f} MB "
          f"({rss60 / rss10:.2f}x)")
    print(json.dumps({"rtf": rtf, "plant_alone_rtf": alone, "replay_exact": bool(same),
                      "diagram_to_plant_ratio": ratio,
                      "diagram_to_plant_ratio_per_pair": ratios,
                      "max_loop_gap_m": gap, "rms_torque_agreement": agreement,
                      "step_check_ratio": check,
                      "output_share": share["bushing"], "logging_share": logging["bushing"], "peak_rss_mb_10s": rss10,
                      "peak_rss_mb_60s": rss60,
                      "split_us_per_step": {k: round(v, 1) for k, v in per_step.items()},
                      "python_callbacks_per_step": {k: v / steps for k, v in calls.items()},
                      "cost_by_replacement_us_per_step": {
                          k: (round(v, 1) if k != "same state" else v)
                          for k, v in replaced.items()}}))


if __name__ == "__main__":
    main()
