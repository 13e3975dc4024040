"""Rerun recordings (.rrd) of every simulation: a file written atomically with its blueprint
and footer, scalar series logged in columns with their legend and style, the frames at which
3-D poses are logged, and a scalar series read back from a file."""

from __future__ import annotations

import uuid
from contextlib import contextmanager
from pathlib import Path

import numpy as np
import rerun as rr

from fivebar_drake.core.files import atomic_path

TIMELINE = "sim_time"


@contextmanager
def recording_file(path: Path, name: str, blueprint):
    """A recording stream to log into, saved to path with the blueprint inside: complete with
    its footer, then renamed into place when the block ends. Each recording gets its own id
    (name and a random suffix), so two runs open side by side in one viewer; no log time."""
    rec = rr.RecordingStream("fivebar_drake", recording_id=f"{name}-{uuid.uuid4().hex[:12]}")
    rec.set_log_time_enabled(False)
    rec.set_log_tick_enabled(False)
    with atomic_path(path) as tmp:
        rec.save(str(tmp), default_blueprint=blueprint)
        with rec:
            yield rec
        rec.disconnect()


def scalars(rec, path: str, t, values, name: str | None = None, color=None,
            width: float | None = None, visible: bool = True) -> None:
    """A scalar series at times t (s) in one column; name: its legend, color (r, g, b) and
    width (ui points) its line; visible False: drawn only once picked in the legend."""
    rec.send_columns(path, indexes=[rr.TimeColumn(TIMELINE, duration=t)],
                     columns=rr.Scalars.columns(scalars=np.asarray(values, dtype=float)))
    if name or color is not None or width is not None or not visible:
        rec.log(path, rr.SeriesLines(names=name, colors=color, widths=width,
                                     visible_series=None if visible else [False]), static=True)


def pose_frames(t, rate_hz: float) -> np.ndarray:
    """Indices into the times t (s) at which to log poses: the first time at or after each
    multiple of 1 / rate_hz."""
    frames = np.unique(np.searchsorted(t, np.arange(0.0, t[-1] + 1e-9, 1.0 / rate_hz)))
    return frames[frames < len(t)]


def read_series(path: Path, entity: str) -> tuple[np.ndarray, np.ndarray]:
    """Time (s) and values of a scalar entity of a recording, read back from the file."""
    from rerun.chunk import RrdReader

    chunks = RrdReader(str(path)).stream().filter(content=entity, is_static=False).to_chunks()
    if not chunks:
        raise ValueError(f"{path} has no entity {entity!r}")
    t, v = [], []
    for chunk in chunks:
        batch = chunk.to_record_batch()
        t.append(batch.column(TIMELINE).cast("int64").to_numpy() * 1e-9)
        v.append(np.array([row[0] for row in batch.column("Scalars:scalars").to_pylist()]))
    t, v = np.concatenate(t), np.concatenate(v)
    order = np.argsort(t, kind="stable")
    return t[order], v[order]
