"""What an envelope's worker does with a maneuver: plain data in (the checked scenario and
parameters), plain data out (ManeuverResult). The worker builds and runs the Diagram itself
(pydrake objects do not pickle), writes the normal `simulate` outputs into a folder of its own
and returns their bytes, so the files need no filesystem shared with the client (a remote
cluster) and their cost stays on the worker."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from fivebar_drake.verdicts.summary_schema import Summary
from fivebar_drake.envelope.spec import Maneuver
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.pipeline import (run_contact_check, run_simulation, run_step_check,
                                    write_simulation)
from fivebar_drake.simulation.signals import per_motor
from fivebar_drake.simulation.run_statistics import window_rows

OPERATING_POINTS = 2000      # (speed, torque) samples per motor and maneuver for the picture
EXTREMES = 50                # of them, the largest |torque| and the largest |speed| samples


@dataclass(frozen=True)
class ManeuverResult:
    """A maneuver's run as plain data: its name; the summary (summary.json's dictionary, None if
    the run raised) and the files `simulate` writes (name, bytes) in the order written, summary.json
    last; per motor (A, B) the operating points of every leg over the rows of the verdict (the
    statistics window; the whole run without one), decimated: joint speed (rad/s) and demand
    (N*m), arrays (2, n); the motor currents of those rows (rows, legs, 2) in A and the interval
    of a row current_dt_s (s) for the duty cycle; `rows`: "window" or "whole run"; `error`: why
    the task raised ("" if it ran; a run that stopped early says so in its summary); power_W:
    the robot's electrical power over those rows (W, summed over the motors;
    Motor.electrical_power_W; None for a motor without an electrical model)."""

    name: str
    summary: Summary | None = None
    files: tuple[tuple[str, bytes], ...] = ()
    speed: np.ndarray | None = None
    demand: np.ndarray | None = None
    current: np.ndarray | None = None
    current_dt_s: float = 0.0
    rows: str = ""
    error: str = ""
    power_W: np.ndarray | None = None


def run_maneuvers(points: int, maneuvers: list[Maneuver]) -> list[ManeuverResult]:
    """A Dask task: each maneuver run (run_maneuver), points operating points per motor."""
    return [run_maneuver(m, points) for m in maneuvers]


def run_maneuver(maneuver: Maneuver, points: int = OPERATING_POINTS) -> ManeuverResult:
    """Simulate the maneuver (pipeline.run_simulation), write its `simulate` outputs in a
    temporary folder (pipeline.write_simulation, the recording named for the maneuver) and
    return them with the operating points and currents (ManeuverResult); with its step check,
    judged against its run at half the plant step (pipeline.run_step_check), with its contact
    check against its runs with the foot contact softer and stiffer (run_contact_check)."""
    record = run_simulation(maneuver.scenario, maneuver.params, progress=False)
    ran = not record.error and not record.interrupted
    half = run_step_check(record, progress=False) if maneuver.step_check and ran else None
    contacts = (run_contact_check(record, progress=False) if maneuver.contact_check and ran
                else None)
    with tempfile.TemporaryDirectory(prefix="fivebar-envelope-") as tmp:
        summary, written = write_simulation(record, tmp, half=half, name=maneuver.name,
                                            contacts=contacts)
        files = tuple((p.name, Path(p).read_bytes()) for p in written)
    t = record.table["t"]
    rows = window_rows(t, summary["window_s"])
    which = "window"
    if not rows.any():
        rows, which = np.ones(len(t), dtype=bool), "whole run"
    speed = per_motor(record, "speed")[rows]                           # (rows, legs, 2)
    demand = per_motor(record, "command")[rows]
    keep = [decimate(speed[..., j].ravel(), demand[..., j].ravel(), points)
            for j in range(len(MOTORS))]
    torque = per_motor(record, "motor_torque")[rows]
    current = record.params.motor.currents(torque, speed)
    power = getattr(record.params.motor, "electrical_power_W", None)
    dt = float(np.median(np.diff(t))) if len(t) > 1 else record.scenario.log_period_s
    return ManeuverResult(
        name=maneuver.name, summary=summary, files=files,
        speed=np.stack([speed[..., j].ravel()[k] for j, k in enumerate(keep)]),
        demand=np.stack([demand[..., j].ravel()[k] for j, k in enumerate(keep)]),
        current=current, current_dt_s=dt, rows=which,
        power_W=None if power is None else power(torque, speed).sum(axis=(1, 2)))


def decimate(speed: np.ndarray, torque: np.ndarray, points: int) -> np.ndarray:
    """Indices of at most `points` samples (sorted, without repeats): evenly spaced ones and the
    EXTREMES largest |torque| and |speed| samples (the edges of the cloud the envelope must
    hold); all of them if there are no more. Always `points` indices when n >= points."""
    n = speed.size
    if n <= points:
        return np.arange(n)
    extremes = np.union1d(np.argsort(-np.abs(torque))[:EXTREMES],
                          np.argsort(-np.abs(speed))[:EXTREMES])
    rest = np.setdiff1d(np.arange(n), extremes)
    even = rest[np.linspace(0, rest.size - 1, points - extremes.size).round().astype(int)]
    return np.union1d(extremes, even)
