"""Everything the tool reads and writes, made safe: input files read with their name in every
error, output folders checked (and cleared of a previous run's files) before any work, files
written atomically (a temporary file renamed over the target, so a reader sees the old complete
file or the new complete one, never a truncated one), console lines that survive a closed pipe."""

from __future__ import annotations

import contextlib
import fcntl
import math
import os
import stat
import sys
import tempfile
from pathlib import Path

from fivebar_drake.core.validation import ParameterError


NAME_MAX, PATH_MAX = 255, 4096   # bytes: Linux's (and most file systems') limits
LOCK_NAME = ".fivebar-lock"      # the file an output folder's run holds (lock_folder)
TEMP_PREFIX = ".fivebar-tmp-"   # temporary files of an atomic write, named so a later run removes them
MAX_INPUT_BYTES = 10_000_000    # an input file (parameters, scenario, spec, summary) is a few kB;
#                                 this bounds what a wrong file (a log, a data dump) costs
_UMASK = os.umask(0)

os.umask(_UMASK)


def read_input_text(path, what: str) -> str:
    """The text of an input file (UTF-8); ParameterError naming the file and what is wrong."""
    path = Path(path)
    try:
        mode = path.stat().st_mode
        if stat.S_ISDIR(mode):
            raise IsADirectoryError
        if not stat.S_ISREG(mode):         # a FIFO or a device would block or never end
            raise ParameterError(f"is not a regular file (a pipe, socket or device); the {what} "
                                 "must be a file", source=str(path))
        with open(path, "rb") as f:
            data = f.read(MAX_INPUT_BYTES + 1)
    except FileNotFoundError:
        raise ParameterError(f"{what} not found", source=str(path)) from None
    except IsADirectoryError:
        raise ParameterError(f"is a folder; {what} must be a file", source=str(path)) from None
    except OSError as err:
        raise ParameterError(f"cannot read the {what}: {err.strerror}", source=str(path)) from None
    if len(data) > MAX_INPUT_BYTES:
        raise ParameterError(f"the {what} is larger than {MAX_INPUT_BYTES:,} bytes: not a file "
                             "of this tool", source=str(path))
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as err:
        raise ParameterError(f"the {what} is not UTF-8 text (byte 0x{data[err.start]:02x} at "
                             f"offset {err.start})", source=str(path)) from None


def check_path_name(path, option: str) -> None:
    """ParameterError naming `option` where the file system cannot hold the path's name: a
    part longer than NAME_MAX bytes or the whole longer than PATH_MAX (checked before any
    folder is made or read)."""
    text = os.fsencode(os.path.abspath(path))
    longest = max((len(part) for part in text.split(b"/")), default=0)
    if longest > NAME_MAX or len(text) > PATH_MAX:
        raise ParameterError(f"{option}: a name of {longest} bytes in a path of {len(text)}: "
                             f"the file system takes names up to {NAME_MAX} bytes and paths up "
                             f"to {PATH_MAX}", option, "command line")


def lock_folder(path, option: str) -> None:
    """Hold folder `path` (an existing output folder, given with `option`) for this process
    until release_folders: ParameterError naming the option where another process holds it. An
    advisory lock on LOCK_NAME in it (flock): the system drops it when its holder exits or is
    killed, so a killed run never leaves it stuck; this process may take it again."""
    key = os.path.realpath(path)
    if key in _LOCKS:
        return
    fd = os.open(os.path.join(key, LOCK_NAME), os.O_RDWR | os.O_CREAT, 0o644)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        os.close(fd)
        raise ParameterError("another fivebar-drake run is writing into this folder: wait for it "
                             "to finish, or choose another folder", option,
                             f"{option} {path}") from None
    _LOCKS[key] = fd


def release_folders() -> None:
    """Let go of every folder this process holds (lock_folder)."""
    for fd in _LOCKS.values():
        os.close(fd)
    _LOCKS.clear()


_LOCKS: dict[str, int] = {}   # the folders this process holds (lock_folder): path -> descriptor


def prepare_output_dir(path, option: str, previous_outputs=()) -> Path:
    """Make sure folder `path` (given with command-line `option`) exists and is writable, hold
    it for this run (lock_folder: another process's run in it is refused), and remove the files
    of a previous run (the names in previous_outputs, and temporary files of an
    interrupted write), so no stale file can pass for this run's. ParameterError otherwise."""
    path = Path(path)
    where = f"{option} {path}"
    if path.exists() and not path.is_dir():
        raise ParameterError("is a file; the output must be a folder", source=where)
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path, prefix=TEMP_PREFIX):
            pass
    except (FileExistsError, NotADirectoryError):
        raise ParameterError("a part of the path is a file, not a folder", source=where) from None
    except OSError as err:
        raise ParameterError(f"cannot create or write into this folder: {err.strerror}",
                             source=where) from None
    lock_folder(path, option)
    for name in previous_outputs:
        (path / name).unlink(missing_ok=True)
    for stale in path.glob(TEMP_PREFIX + "*"):
        stale.unlink(missing_ok=True)
    return path


def check_output_file(path, option: str) -> Path:
    """Make sure file `path` (command-line `option`) can be written: its folder exists (made if
    needed) and is writable, and the path is not a folder. ParameterError otherwise."""
    path = Path(path)
    if path.is_dir():
        raise ParameterError("is a folder; give a file name", source=f"{option} {path}")
    prepare_output_dir(path.parent, option)
    return path


@contextlib.contextmanager
def atomic_path(path):
    """A temporary path beside `path` to write to; renamed over `path` when the block ends
    without an error, removed otherwise."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=TEMP_PREFIX, suffix=path.suffix)
    os.close(fd)
    try:
        yield Path(tmp)
        os.chmod(tmp, 0o666 & ~_UMASK)        # mkstemp makes it private; a plain file is not
        os.replace(tmp, path)
    finally:
        Path(tmp).unlink(missing_ok=True)


def write_atomic(path, text: str | bytes) -> Path:
    """Write text (UTF-8) or bytes to path atomically (see atomic_path); returns path."""
    path = Path(path)
    with atomic_path(path) as tmp:
        with (open(tmp, "wb") if isinstance(text, bytes) else
              open(tmp, "w", encoding="utf-8")) as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
    return path


def json_ready(value, undefined: list | None = None, path: str = ""):
    """value (nested dicts, lists, numbers) with every non-finite float as None, so json.dumps
    with allow_nan=False takes it; the dotted path of each one is appended to undefined."""
    if isinstance(value, dict):
        return {k: json_ready(v, undefined, f"{path}.{k}" if path else str(k))
                for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_ready(v, undefined, f"{path}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, float) and not math.isfinite(value):
        if undefined is not None:
            undefined.append(path)
        return None
    return value


def say(text: str, stream=None) -> None:
    """Print a line to stream (default stdout). If its reader has gone (piped into `head`),
    the rest of the output goes to /dev/null instead of raising BrokenPipeError."""
    stream = sys.stdout if stream is None else stream
    try:
        print(text, file=stream, flush=True)
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), stream.fileno())


Z_RLE = 3   # zlib's run-length strategy: plots are runs of one colour (smaller, and faster)


def save_figure(fig, path, dpi: int = 110, compress_level: int = 6) -> Path:
    """Write a matplotlib figure to path (PNG, zlib compress_level 0..9: 1 is several times
    faster than the default 6, for a larger file) atomically and close it; returns path."""
    import matplotlib.pyplot as plt

    path = Path(path)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=dpi,
                    pil_kwargs={"compress_level": compress_level, "compress_type": Z_RLE})
    plt.close(fig)
    return path
