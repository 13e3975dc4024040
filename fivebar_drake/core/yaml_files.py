"""YAML inputs (scenarios, sweep specs) read as untrusted data: YAML 1.2 numbers (1e-9 is a
float), a key written twice refused (as TOML does), no aliases (a few hundred bytes of nested
aliases expand to gigabytes), and a bounded nesting depth; errors name the file and the place."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Callable, TypeVar

import yaml

from fivebar_drake.core.files import read_input_text
from fivebar_drake.core.validation import ParameterError

T = TypeVar("T")

MAX_DEPTH = 20          # a scenario or a spec nests 3 levels; deeper is not one of ours
MAX_MESSAGE = 300       # characters of a YAML problem quoted in an error


class _Loader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 floats, duplicate keys and aliases refused, depth bounded."""

    def compose_node(self, parent, index):
        if self.check_event(yaml.AliasEvent):
            mark = self.peek_event().start_mark
            raise yaml.constructor.ConstructorError(
                None, None, "aliases (*name) are not accepted: write the value out", mark)
        self._depth = getattr(self, "_depth", 0) + 1
        try:
            if self._depth > MAX_DEPTH:
                raise yaml.constructor.ConstructorError(
                    None, None, f"nested deeper than {MAX_DEPTH} levels",
                    self.peek_event().start_mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, f"the key {key!r} is written twice", key_node.start_mark)
            seen.add(key)
        return super().construct_mapping(node, deep)


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)[eE][-+]?[0-9]+$"),
    list("-+0123456789."))


def load_yaml(text: str, source: str, hint: str = ""):
    """The YAML document in text (None if empty); ParameterError naming source, the line and
    column and the problem (shortened), with hint appended."""
    try:
        return yaml.load(text, Loader=_Loader)
    except yaml.YAMLError as err:
        where = getattr(err, "problem_mark", None)
        at = f" at line {where.line + 1}, column {where.column + 1}" if where else ""
        problem = str(getattr(err, "problem", None) or err)
        if len(problem) > MAX_MESSAGE:
            problem = problem[:MAX_MESSAGE] + " ..."
        raise ParameterError(f"not valid YAML{at}: {problem}{hint}", source=source) from None
    except RecursionError:
        raise ParameterError(f"not valid YAML: nested too deeply{hint}", source=source) from None


def load_spec_file(path: Path, what: str, from_dict: Callable[[object, Path, str], T]) -> T:
    """A spec file (what: its kind in errors, e.g. "sweep spec") read as untrusted YAML and
    made by from_dict(data, its folder, its path); every ParameterError names the file."""
    data = load_yaml(read_input_text(path, what), str(path))
    try:
        return from_dict(data, path.parent, str(path))
    except ParameterError as err:
        raise err.located(str(path)) from None
