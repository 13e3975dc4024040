"""The console entry point (`fivebar-drake`, `python -m fivebar_drake`): the command line, with a
Ctrl-C during its imports (Drake and numba take seconds to load) ending quietly with exit code
130, as one during a command does, instead of a Python traceback."""

from __future__ import annotations

import sys


def main() -> int:
    try:
        from fivebar_drake.cli import main as command_line
    except KeyboardInterrupt:
        print("fivebar-drake: interrupted: stopped", file=sys.stderr)
        return 130
    return command_line()
