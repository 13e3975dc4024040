"""Typed variants: a gait, a controller, a stance law or a loop closure is a small frozen
dataclass registered by its kind in its registry (a dict kind -> class) with the registry's
decorator (registrar), loaded from the scenario by name (its defaults) or as a mapping {kind:
KIND, field: value, ...} (simulation/scenario.py). One in another package registers the same
way, its module named by an entry point (core/plugins.py)."""

from __future__ import annotations

import dataclasses
from typing import ClassVar

from fivebar_drake.core import plugins


class Variant:
    """Base of the variants: `kind` names it in its registry; check validates its fields."""

    kind: ClassVar[str] = ""
    replaces: ClassVar[bool] = False   # a plugin's class that replaces a registered kind says so

    def __str__(self) -> str:
        """The kind, with the fields that differ from the kind's defaults, e.g. trot or
        trot(duty_factor=0.7)."""
        default = type(self)()
        changed = [f"{f.name}={getattr(self, f.name)!r}" for f in dataclasses.fields(self)
                   if getattr(self, f.name) != getattr(default, f.name)]
        return f"{self.kind}({', '.join(changed)})" if changed else self.kind

    def described(self) -> str:
        """The kind with every field, e.g. foot_leg (swing_bandwidth_hz = 15, ...)."""
        return f"{self.kind} (" + ", ".join(f"{f.name} = {getattr(self, f.name)!r}"
                                            for f in dataclasses.fields(self)) + ")"

    def fields(self) -> dict:
        """{"kind": its kind, every field: its value} (summary.json's record of what ran)."""
        return {"kind": self.kind, **{f.name: getattr(self, f.name)
                                      for f in dataclasses.fields(self)}}

    def check(self, field: str) -> None:
        """ParameterError naming f"{field}.NAME" for a field out of its bounds (none here)."""


def documented(default, doc: str):
    """A variant's field with its default and its description (metadata["doc"], README)."""
    return dataclasses.field(default=default, metadata={"doc": doc})


def by_kind(registry: dict, value, what: str) -> Variant:
    """value if it is a variant, else the registered variant of that kind with its defaults
    (ValueError naming `what` and the kinds)."""
    if isinstance(value, Variant):
        return value
    if not known(registry, value):
        raise ValueError(f"{what} = {value!r}: allowed {list(registry)}")
    return registry[value]()


def known(registry: dict, kind) -> bool:
    """Whether kind is registered, after loading the plugins (core/plugins.py) if it is not."""
    if kind not in registry:
        plugins.load()
    return kind in registry


def registrar(registry: dict, what: str):
    """The class decorator that registers a Variant subclass in registry (the registry of
    `what`, e.g. "gait") under its kind; a kind another class has is refused unless the class
    says it replaces it (plugins.claim)."""
    def register(cls):
        old = registry.get(cls.kind)
        name = (lambda c: f"{c.__module__}.{c.__qualname__}")    # noqa: E731
        plugins.claim(what, cls.kind, None if old is None else name(old), name(cls),
                      cls.replaces)
        registry[cls.kind] = cls
        return cls
    return register
