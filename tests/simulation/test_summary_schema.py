"""summary.json's schema (verdicts/summary_schema.py) holds what a run writes: a short trot and a jump,
each with its step check, through the pipeline's writer; their summaries, and summary.json read
back, have exactly the keys the typed dictionaries declare, at every depth (NotRequired keys may
be absent), with values of the declared types (a non-finite float is null in the file). The
check itself finds a key the schema lacks, a key missing and a value of the wrong type. A jump
records its plan beside what it measured (summary.json and summary.md)."""

import copy
import json
import types
from typing import Union, get_args, get_origin, get_type_hints, is_typeddict

import pytest

from fivebar_drake.verdicts.summary_schema import Summary
from fivebar_drake.mechanisms.fivebar import MOTORS
from fivebar_drake.pipeline import run_step_check, write_simulation

# as short as gives every group of keys: a trot's first whole cycle after the ramp (its motors'
# checks), a jump's span after standing (its jump, landing, phases and force capability)
RUNS = {"trot": dict(gait="trot", duration_s=2.5), "jump": dict(gait="jump", duration_s=2.6)}


def mismatches(value, hint, path: str = "summary", in_file: bool = False) -> list[str]:
    """Where value differs from the type hint: a typed dictionary's keys it lacks or does not
    declare, recursively, and values of another type (float takes an int, not a bool; in_file:
    null stands for a non-finite float)."""
    if is_typeddict(hint):
        if not isinstance(value, dict):
            return [f"{path}: {type(value).__name__}, not a {hint.__name__}"]
        hints = get_type_hints(hint)
        out = [f"{path}.{k}: not in {hint.__name__}" for k in value if k not in hints]
        out += [f"{path}.{k}: missing ({hint.__name__} requires it)"
                for k in sorted(hint.__required_keys__) if k not in value]
        for k, v in value.items():
            if k in hints:
                out += mismatches(v, hints[k], f"{path}.{k}", in_file)
        return out
    origin, args = get_origin(hint), get_args(hint)
    if origin in (Union, types.UnionType):
        tried = [mismatches(value, h, path, in_file) for h in args
                 if value is None or h is not type(None)]
        if any(not t for t in tried):
            return []
        return tried[0] if len(tried) == 1 else [f"{path}: {value!r:.60} is not {hint}"]
    if origin is list:
        if not isinstance(value, list):
            return [f"{path}: {type(value).__name__}, not a list"]
        return [m for i, v in enumerate(value) for m in mismatches(v, args[0], f"{path}[{i}]",
                                                                   in_file)]
    if origin is dict:
        if not isinstance(value, dict):
            return [f"{path}: {type(value).__name__}, not a dict"]
        return ([f"{path}: key {k!r} is not text" for k in value if not isinstance(k, str)]
                + [m for k, v in value.items()
                   for m in mismatches(v, args[1], f"{path}.{k}", in_file)])
    if hint is type(None):
        return [] if value is None else [f"{path}: {value!r:.60} is not null"]
    if hint is float:
        number = isinstance(value, (float, int)) and not isinstance(value, bool)
        return [] if number or (in_file and value is None) else [
            f"{path}: {value!r:.60} is not a float"]
    if hint in (int, str, bool):
        right = isinstance(value, hint) and (hint is bool or not isinstance(value, bool))
        return [] if right else [f"{path}: {value!r:.60} is not {hint.__name__}"]
    raise TypeError(f"{path}: the check does not know the type {hint}")


@pytest.fixture(scope="module")
def written(tmp_path_factory, simulated):
    """Per run: (its record, the summary as written, summary.json read back, summary.md)."""
    out = {}
    for name, fields in RUNS.items():
        record = simulated(**fields)
        half = run_step_check(record, progress=False)
        folder = tmp_path_factory.mktemp(name)
        summary, _ = write_simulation(record, folder, half)
        out[name] = (record, summary, json.loads((folder / "summary.json").read_text()),
                     (folder / "summary.md").read_text())
    return out


@pytest.mark.parametrize("name", list(RUNS))
def test_the_summary_has_the_schemas_keys_and_types(written, name):
    record, summary, _, _ = written[name]
    assert record.completed, record.error
    assert mismatches(summary, Summary) == []
    assert list(summary["legs"]) == list(record.layout.legs)
    assert all(list(motors) == list(MOTORS) for motors in summary["legs"].values())
    # the groups each run has, so the check above reached their keys
    assert summary["step_check"] and "timing" in summary
    assert all(m["checks"] for motors in summary["legs"].values() for m in motors.values())
    if name == "jump":
        assert summary["jump"] and summary["landing"] and summary["phases"]
        assert summary["force_capability"]


@pytest.mark.parametrize("name", list(RUNS))
def test_summary_json_read_back_has_the_schemas_keys_and_types(written, name):
    _, summary, data, _ = written[name]
    assert mismatches(data, Summary, in_file=True) == []
    assert list(data) == list(summary)         # summary.json keeps the schema's order
    assert list(data) == [k for k in get_type_hints(Summary) if k in data]


def test_the_check_finds_what_the_schema_does_not_say(written):
    """A key the schema lacks, a key missing and a value of another type, at any depth."""
    _, summary, data, _ = written["jump"]
    for value, in_file in ((summary, False), (data, True)):
        wrong = copy.deepcopy(value)
        wrong["legs"]["FL"]["A"]["new_figure_Nm"] = 1.0
        wrong["jump"]["planned"]["height_m"] = "high"
        del wrong["step_check"]["motors"]["RR B"]["sf_error"]
        del wrong["answer"]
        wrong["cycles_in_window"] = 1.0
        assert sorted(mismatches(wrong, Summary, in_file=in_file)) == sorted([
            "summary.legs.FL.A.new_figure_Nm: not in MotorSummary",
            "summary.jump.planned.height_m: 'high' is not a float",
            "summary.step_check.motors.RR B.sf_error: missing (StepCheckMotor requires it)",
            "summary.answer: missing (Summary requires it)",
            "summary.cycles_in_window: 1.0 is not int"])


def test_a_jump_records_its_plan_beside_its_measure(written):
    """The jump's planned height (the variant's height_m) and event times beside the measured
    ones, in summary.json and in summary.md's maneuver lines."""
    record, _, data, text = written["jump"]
    jump, landing, ran = data["jump"], data["landing"], data["ran"]
    assert jump["planned"]["height_m"] == record.scenario.gait.height_m == ran["gait"]["height_m"]
    assert jump["planned"]["takeoff_s"] == ran["planned_events_s"]["takeoff"]
    assert landing["planned"]["touchdown_s"] == ran["planned_events_s"]["touchdown"]
    assert abs(jump["height_m"] - jump["planned"]["height_m"]) < 0.02
    assert (f"apex {jump['height_m'] * 1e3:.1f} mm (planned "
            f"{record.scenario.gait.height_m * 1e3:.1f} mm)") in text
    assert f"touchdown at t = {landing['touchdown_s']:.3f} s (planned " in text


def test_the_check_knows_every_type_the_schema_uses():
    """Every hint in the schema is one the check reads (else it raises)."""
    seen, todo = set(), [Summary]
    while todo:
        hint = todo.pop()
        if is_typeddict(hint):
            if hint not in seen:
                seen.add(hint)
                todo += list(get_type_hints(hint).values())
        elif get_args(hint):
            todo += list(get_args(hint))
        else:
            assert hint in (float, int, str, bool, type(None)), hint
    assert len(seen) > 20
