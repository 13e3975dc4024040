"""Run a duty envelope on Dask through the sweep's engine (sweep/engine.py: a local cluster of
process workers, one thread each, or an existing scheduler; only plain data crosses to the
workers, each builds its own Diagrams) and write it:

    OUT/envelope.md, envelope.json    per motor and maneuver the four checks, what sizes each
                                      motor, the worst verdict in one sentence, the duty cycle
    OUT/operating_points.png          every maneuver's operating points over the envelope
    OUT/operating_points.npz          those points (per maneuver: speed, demand; motors A, B)
    OUT/duty_cycle.png                the windings' temperature over the duty cycle
    OUT/<maneuver>/                   `simulate`'s outputs of each maneuver (summary.json last,
                                      run.rrd with the maneuver's name in its recording id)

Everything is checked before anything is written (the spec, --workers, --scheduler and a
scheduler that answers, the output folders). A maneuver's folder is written the moment it
finishes; an interrupted envelope keeps those and writes envelope.md/json of what finished
(complete: false), then stops."""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path

from fivebar_drake.core.progress import Progress
from fivebar_drake.core.files import prepare_output_dir, say, write_atomic
from fivebar_drake.core.interrupts import Interrupted
from fivebar_drake.core.validation import ParameterError
from fivebar_drake.envelope.duty_cycle import duty_temperature, duty_verdict
from fivebar_drake.envelope.maneuver import OPERATING_POINTS, ManeuverResult, run_maneuvers
from fivebar_drake.envelope.plots import (DUTY_CYCLE_FILE, OPERATING_POINTS_FILE, PLOT_FILES,
                                          POINTS_FILE, plot_duty_cycle, plot_operating_points,
                                          save_points)
from fivebar_drake.envelope.report import REPORT_FILES, envelope_report, write_report
from fivebar_drake.envelope.spec import EnvelopeSpec
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.pipeline import SIMULATION_FILES
from fivebar_drake.robots.quadruped.legs import LEGS
from fivebar_drake.sweep.engine import (check_output_folder, check_scheduler, check_workers,
                                        dask_client, finished_tasks, raised_by_task)

ENVELOPE_FILES = PLOT_FILES + REPORT_FILES            # envelope.json last


@dataclass
class EnvelopeRun:
    """What run_envelope did: envelope.json's dictionary, each maneuver's result (spec order;
    only those that finished), the envelope's files and each maneuver's, in the order written."""

    report: dict
    results: dict[str, ManeuverResult]
    files: list[Path]
    maneuver_files: dict[str, list[Path]] = field(default_factory=dict)


def check_folders(out: Path, spec: EnvelopeSpec) -> None:
    """ParameterError unless out and every maneuver's folder in it can be written (nothing is
    left behind by the check)."""
    check_output_folder(out)
    for m in spec.maneuvers:
        folder = out / m.name
        if folder.exists() and not folder.is_dir():
            raise ParameterError(f"is a file; maneuver {m.name!r} writes its outputs into this "
                                 "folder", source=f"--out {folder}")


class ManeuverTaskError(RuntimeError):
    """A maneuver's task raised inside its worker (not a lost worker: those are failed
    maneuvers with no verdict)."""


def run_envelope(spec: EnvelopeSpec, out: str | Path, workers: int | None = None,
                 scheduler: str | None = None, progress: bool = True,
                 client=None) -> EnvelopeRun:
    """Run the spec's maneuvers and write the envelope into out (module docstring). client: a
    Dask client to use (and leave open); otherwise one of the scheduler, or of a new local
    cluster of `workers`."""
    out = Path(out)
    check_workers(workers)
    if scheduler:
        check_scheduler(scheduler)
    check_folders(out, spec)
    results, written, prepared = {}, {}, False
    try:
        with dask_client(workers, scheduler, client) as dask:
            prepare_output_dir(out, "--out", ENVELOPE_FILES)   # the scheduler answers
            for m in spec.maneuvers:
                prepare_output_dir(out / m.name, "--out", SIMULATION_FILES)
            prepared = True
            bar = Progress(len(spec.maneuvers), 0, progress, "envelope", "maneuvers")
            for (maneuver,), done, error in finished_tasks(
                    dask, run_maneuvers, (OPERATING_POINTS,), [[m] for m in spec.maneuvers]):
                result = done[0] if done else ManeuverResult(maneuver.name, error=error)
                written[maneuver.name] = [write_atomic(out / maneuver.name / name, data)
                                          for name, data in result.files]
                results[maneuver.name] = result
                bar.add(1, int(result.summary is None or bool(result.summary["error"])))
                if progress:
                    say(f"  {maneuver_line(result)}", sys.stderr)
    except (KeyboardInterrupt, Interrupted):
        if prepared:
            write_envelope(spec, results, out)
        raise
    ordered = {m.name: results[m.name] for m in spec.maneuvers}
    report, files = write_envelope(spec, ordered, out)
    raised = [r for r in ordered.values() if raised_by_task(r.error)]
    if raised:      # written as failed maneuvers; a task that raised is a bug (exit 3), not a verdict
        raise ManeuverTaskError(f"maneuver {raised[0].name!r} raised in its worker: "
                                f"{raised[0].error} (the envelope of the rest is written in {out})")
    return EnvelopeRun(report, ordered, files, written)



def maneuver_line(result: ManeuverResult) -> str:
    """One line on a finished maneuver: its verdict and speed, or why it has none."""
    s = result.summary
    if s is None:
        return f"{result.name}: failed: {result.error}"
    head = f"{result.name}: {s['verdict'].upper()}"
    if s["deciding_check"]:
        head += f" ({s['deciding_check']} check, {s['worst_motor']})"
    if s["error"]:
        head += f"; stopped early: {s['error']}"
    return f"{head}; {s['real_time_factor']:.2f}x real time"


def duty_of(spec: EnvelopeSpec, results: dict[str, ManeuverResult]):
    """(DutyTemperature, its verdicts (duty_cycle.duty_verdict), "") of the spec's duty cycle,
    or (None, None, why there is none)."""
    params = spec.maneuvers[0].params
    if not spec.duty_cycle:
        return None, None, "The spec gives no duty cycle."
    if not params.motor.has_thermal_model:
        return None, None, "The motor has no thermal model: no duty-cycle temperature."
    lacking = sorted({s.maneuver for s in spec.duty_cycle if s.maneuver not in results
                      or results[s.maneuver].current is None
                      or not results[s.maneuver].current.size})
    if lacking:
        return None, None, (f"No duty-cycle temperature: {', '.join(lacking)} did not run or "
                            "has no samples.")
    unrated = sorted({s.maneuver for s in spec.duty_cycle
                      if results[s.maneuver].summary["verdict"] == "insufficient"})
    if unrated:       # its currents would be whatever the run did (a cut run: standing)
        return None, None, (f"No duty-cycle temperature: {', '.join(unrated)} has no verdict "
                            "(too short a run for its statistics), so its currents are not "
                            "the maneuver's.")
    temperature = duty_temperature(params.motor, spec.duty_cycle, {
        name: (r.current, r.current_dt_s) for name, r in results.items() if r.current is not None})
    return temperature, duty_verdict(params.motor, params.checks, temperature, LEGS, MOTORS), ""


def write_envelope(spec: EnvelopeSpec, results: dict[str, ManeuverResult],
                   out: Path) -> tuple[dict, list[Path]]:
    """The pictures, envelope.md and envelope.json (last) of the finished maneuvers' results;
    returns (envelope.json's dictionary, the files in the order written)."""
    params = spec.maneuvers[0].params
    temperature, duty, why = duty_of(spec, results)
    files = []
    points = {n: (r.speed, r.demand) for n, r in results.items() if r.speed is not None}
    if points:
        files += [plot_operating_points({"": (params.motor, points)}, out / OPERATING_POINTS_FILE),
                  save_points(points, out / POINTS_FILE)]
    if temperature is not None:
        files.append(plot_duty_cycle(params.motor, params.checks, temperature, spec.duty_cycle,
                                     LEGS, out / DUTY_CYCLE_FILE))
    report = envelope_report(spec, results, duty, why, params)
    files += write_report(report, out)
    return report, files
