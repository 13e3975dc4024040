"""The pipeline API: a run's record is plain data (no Drake object) that pickles, crosses a process
boundary, and gives the same files once unpickled."""

import dataclasses
import json
import math
import multiprocessing
import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from fivebar_drake.pipeline import (AnalysisRecord, SimulationRecord, run_analysis,
                                    run_simulation, summarize_run, write_analysis,
                                    write_simulation)
from fivebar_drake.core.drake_configs import config_fields
from fivebar_drake.simulation.scenario import DRAKE_CONFIGS, load_scenario

TEST_DURATION_S = 4.5   # 0.5 s standing, 1 s ramp, 3 whole trot cycles
WALL_CLOCK = ("real_time_factor", "wall_time_s")


def foreign_objects(obj, path="record", seen=None) -> list[str]:
    """Where obj holds an object of Drake's (a pydrake type, also as the owner of the memory a
    numpy array views, e.g. a Drake log's): walks dataclass fields, attributes, mappings,
    sequences, numpy arrays and what their memory belongs to. Drake's config structs in the
    scenario (MultibodyPlantConfig, SimulatorConfig) are plain values: a few numbers and
    strings, which the Scenario pickles as their fields."""
    seen = set() if seen is None else seen
    if id(obj) in seen or obj is None or isinstance(obj, (str, bytes, int, float, bool)):
        return []
    seen.add(id(obj))
    kind = type(obj)
    if kind in DRAKE_CONFIGS.values():
        return []
    if kind.__module__.split(".")[0] == "pydrake":
        return [f"{path}: {kind.__module__}.{kind.__name__}"]
    if isinstance(obj, np.ndarray):
        children = [("base", obj.base)] + (list(enumerate(obj.ravel()))
                                           if obj.dtype == object else [])
    elif isinstance(obj, dict):
        children = list(obj.items())
    elif isinstance(obj, (list, tuple, set)):
        children = list(enumerate(obj))
    elif dataclasses.is_dataclass(obj):
        children = [(f.name, getattr(obj, f.name)) for f in dataclasses.fields(obj)]
    elif hasattr(obj, "__dict__"):
        children = list(vars(obj).items())
    else:
        return []
    return [hit for key, child in children for hit in foreign_objects(child, f"{path}.{key}", seen)]


def equal(a, b) -> bool:
    """a and b hold the same values (arrays element by element, NaN equal to NaN; Drake's
    config structs field by field)."""
    if type(a) in DRAKE_CONFIGS.values():
        return type(a) is type(b) and config_fields(a) == config_fields(b)
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.array_equal(a, b, equal_nan=True)
    if dataclasses.is_dataclass(a) and not isinstance(a, type):
        return type(a) is type(b) and all(equal(getattr(a, f.name), getattr(b, f.name))
                                          for f in dataclasses.fields(a))
    if isinstance(a, dict):
        return isinstance(b, dict) and a.keys() == b.keys() and all(equal(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(map(equal, a, b))
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return a == b


@pytest.fixture(scope="module")
def record(simulated):
    return simulated(duration_s=TEST_DURATION_S, closure="ball")


def test_the_walker_finds_drake_objects():
    """The check below can fail: it finds a Drake object, and a numpy view into a Drake log."""
    from pydrake.systems.primitives import VectorLog

    log = VectorLog(2)
    log.AddData(0.0, np.zeros(2))
    assert foreign_objects({"x": [1.0, log]}) == ["record.x.1: pydrake.systems.primitives.VectorLog"]
    assert foreign_objects({"t": log.data()[0]})


@pytest.mark.slow
def test_simulation_record_is_plain_data_and_pickles(record, tmp_path):
    """The record holds no Drake object; its unpickled copy has every value of the original and
    writes the same summary, number for number (but the timing of the writing itself)."""
    assert isinstance(record, SimulationRecord) and record.completed
    assert foreign_objects(record) == []
    copy = pickle.loads(pickle.dumps(record))
    assert copy is not record and copy.table["state"] is not record.table["state"]
    assert equal(copy, record)
    written, summaries = {}, {}
    for name, rec in (("original", record), ("copy", copy)):
        summaries[name], paths = write_simulation(rec, tmp_path / name)
        assert [p.name for p in paths][-1] == "summary.json"
        written[name] = {p.name: p for p in paths}
        assert summaries[name].pop("timing")["simulate_s"] == record.wall_s
    assert equal(summaries["copy"], summaries["original"])
    assert equal(summarize_run(copy), summaries["original"])
    original, unpickled = (json.loads(written[k]["summary.json"].read_text())
                           for k in ("original", "copy"))
    unpickled.pop("timing"), original.pop("timing")
    assert unpickled == original
    assert written["copy"]["summary.md"].read_text() == written["original"]["summary.md"].read_text()
    # the summary describes this run: three whole cycles, every motor's figures finite
    assert original["completed"] and original["cycles_in_window"] == 3
    assert original["duration_s"] == pytest.approx(TEST_DURATION_S)
    assert original["closure"] == "ball" and set(original["legs"]) == set(record.layout.legs)
    assert all(math.isfinite(m["demand_p99_Nm"]) and m["demand_p99_Nm"] > 0
               for motors in original["legs"].values() for m in motors.values())


def test_analysis_record_is_plain_data_and_pickles(tmp_path):
    """The analysis record pickles; report.json and report.md written from the copy are those
    written from the original."""
    record = run_analysis()
    assert isinstance(record, AnalysisRecord) and foreign_objects(record) == []
    copy = pickle.loads(pickle.dumps(record))
    assert equal(copy, record)
    paths = {name: write_analysis(rec, tmp_path / name) for name, rec in
             (("original", record), ("copy", copy))}
    assert [p.name for p in paths["original"]][-1] == "report.json"
    for a, b in zip(paths["original"], paths["copy"]):
        if a.suffix != ".png":
            assert a.read_text() == b.read_text(), a.name
    report = json.loads(paths["copy"][-1].read_text())
    assert report["results"]["seed"]["A"]["peak_torque_Nm"] > 0
    assert report["path"]["gait"] == "seed_ellipse" and report["path"]["samples"] == 60


def test_a_run_crosses_a_process_boundary():
    """run_simulation in a fresh spawned process (nothing inherited) returns its record through
    pickling: the same run as here, bit for bit, and the same summary."""
    scenario = load_scenario(duration_s=0.3, closure="ball")
    with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
        remote = pool.submit(run_simulation, scenario, progress=False).result(timeout=600)
    local = run_simulation(scenario, progress=False)
    assert remote.completed and remote.table["t"][-1] == pytest.approx(0.3)
    assert equal(remote.table, local.table)
    assert equal(dataclasses.replace(remote, wall_s=0.0), dataclasses.replace(local, wall_s=0.0))
    clock = lambda s: {k: v for k, v in s.items() if k not in WALL_CLOCK}  # noqa: E731
    assert equal(clock(summarize_run(remote)), clock(summarize_run(local)))


def test_run_simulation_checks_the_scenario_it_is_given():
    """A Scenario made in code is checked like a scenario file: a clear error, no run."""
    from fivebar_drake.core.validation import ParameterError
    from fivebar_drake.simulation.scenario import Scenario

    with pytest.raises(ParameterError, match=r"scenario.duration_s = -1.0: must be >= 0.002"):
        run_simulation(Scenario(duration_s=-1), progress=False)


def test_write_simulation_never_leaves_a_stale_summary(tmp_path, monkeypatch):
    """The writer alone keeps the guarantee: a previous run's summary.json is removed before
    anything is written, so a write that fails midway leaves no summary claiming completeness."""
    from fivebar_drake import pipeline

    (tmp_path / "summary.json").write_text('{"completed": true}')
    (tmp_path / "notes.txt").write_text("mine")
    record = run_simulation(load_scenario(duration_s=0.1, closure="ball"), progress=False)

    def broken(*args, **kwargs):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(pipeline, "write_recording", broken)
    with pytest.raises(OSError, match="No space left"):
        write_simulation(record, tmp_path)
    assert not (tmp_path / "summary.json").exists()
    assert (tmp_path / "sim_torques.png").exists() and (tmp_path / "notes.txt").read_text() == "mine"
    monkeypatch.undo()
    summary, paths = write_simulation(record, tmp_path)
    assert json.loads((tmp_path / "summary.json").read_text())["duration_s"] == pytest.approx(0.1)
    assert [p.name for p in paths] == ["sim_torques.png", "sim_motion.png",
                                       "sim_torque_speed.png", "run.rrd",
                                       "summary.md", "summary.json"]
