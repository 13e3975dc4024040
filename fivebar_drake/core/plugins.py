"""Variants from other packages: a package registers its gaits, maneuvers, controllers, stance
laws, closures or studies through the entry point group fivebar_drake.plugins, each entry a
module whose import registers them (the registries' decorators: register_path,
register_controller, register_stance_law, register_closure; catalog.register_study), as
Gymnasium's `register` does. In its pyproject.toml:

    [project.entry-points."fivebar_drake.plugins"]
    gallop = "my_package.gallop"

load() imports every such module once per process; the command line calls it before it builds
its choices, and a registry asked for a kind it does not know calls it before it says no (a
Dask worker loading a scenario, a script). A plugin cannot hijack: a kind registered twice is
refused naming both (core/variants.registrar) unless the newcomer says it replaces the other
(`replaces: ClassVar[bool] = True`), which every run records (origin); a plugin that exits or
fails at import is refused naming its entry point. Plugins are off with the environment
variable FIVEBAR_DRAKE_NO_PLUGINS=1 or the command line's --no-plugins (disable())."""

from __future__ import annotations

import functools
import importlib
import os
from importlib.metadata import entry_points, packages_distributions, version

from fivebar_drake.core.validation import ParameterError

GROUP = "fivebar_drake.plugins"
DISABLE_ENV = "FIVEBAR_DRAKE_NO_PLUGINS"
_loaded: dict[str, str] = {}       # entry point name -> module, once imported
_state = {"disabled": False, "loading": ""}   # disable(); the entry point being imported
registered: dict[str, tuple[str, str]] = {}   # class -> ("what kind", its entry point)
replaced: dict[str, str] = {}      # class -> the class it replaced (it said so)


def disable() -> None:
    """Load no plugin in this process from now on (--no-plugins)."""
    _state["disabled"] = True


def enabled() -> bool:
    """Whether plugins load: not disabled here nor by FIVEBAR_DRAKE_NO_PLUGINS (any value but
    "", "0")."""
    return not _state["disabled"] and os.environ.get(DISABLE_ENV, "") in ("", "0")


def loading() -> str:
    """The entry point being imported ("name = module"), "" outside load()."""
    return _state["loading"]


def load() -> dict[str, str]:
    """Import the module of every entry point of GROUP not imported yet (none where plugins
    are off: enabled); returns {name: module} of all loaded. ParameterError naming the entry
    point whose module fails to import or exits at import (an installed package's fault, not
    this one's), or registers a kind that another already has."""
    if not enabled():
        return dict(_loaded)
    for point in entry_points(group=GROUP):
        if point.name in _loaded:
            continue
        _state["loading"] = f"{point.name} = {point.value}"
        try:
            importlib.import_module(point.module)
        except ParameterError as err:
            raise ParameterError(f"entry point {point.name} = {point.value}: {err.message}",
                                 f"entry point {point.name}", f"plugin group {GROUP}") from err
        except (Exception, SystemExit) as err:  # noqa: BLE001  (someone else's module)
            what = (f"it exits at import (SystemExit {err.code!r})"
                    if isinstance(err, SystemExit) else
                    f"its module cannot be imported ({type(err).__name__}: {err})")
            raise ParameterError(f"entry point {point.name} = {point.value}: {what}; fix or "
                                 f"uninstall the package that declares it, or run without "
                                 f"plugins ({DISABLE_ENV}=1 or --no-plugins)",
                                 f"entry point {point.name}", f"plugin group {GROUP}") from err
        finally:
            _state["loading"] = ""
        _loaded[point.name] = point.module
    return dict(_loaded)


@functools.lru_cache(maxsize=1)
def _distributions() -> dict[str, list[str]]:
    """Top-level module -> the distributions that install it, read once per process (it reads
    every installed distribution's records: 0.15 s a call, and every summary asks)."""
    return packages_distributions()


def origin(cls: type) -> dict[str, str]:
    """Where a variant class comes from: its module
    and class, its distribution with the version ("fivebar_drake 0.1.0"; "" where none is
    installed), for a plugin's its entry point, and the class it replaced where it asked to."""
    top = cls.__module__.split(".")[0]
    names = _distributions().get(top, [])
    name = f"{cls.__module__}.{cls.__qualname__}"
    out = {"module": name, "distribution": f"{names[0]} {version(names[0])}" if names else ""}
    if name in registered:
        out["entry_point"] = registered[name][1]
    if name in replaced:
        out["replaces"] = replaced[name]
    return out


def claim(what: str, name: str, old: str | None, new: str, replaces: bool) -> None:
    """Record that `new` (module.class, or a module) registers `name` in the registry of
    `what`, where `old` is what has it now (None: nothing). ParameterError naming both where
    another has it and the newcomer does not say it replaces it (replaces); else the
    replacement and the entry point being loaded are recorded (origin)."""
    key = f"{what} {name}"
    if old is not None and old != new:
        if not replaces:
            point = f" (entry point {loading()})" if loading() else ""
            raise ParameterError(
                f"{what} {name!r} is registered twice: by {old} and by {new}{point}; a plugin "
                "that means to replace it says so (replaces: ClassVar[bool] = True on the "
                "class), and every run then records it", key, "plugin registry")
        replaced[new] = old
    if loading():
        registered[new] = (key, loading())


def plugin_names() -> set[str]:
    """The kinds and mechanisms plugins added (not the built-ins they replaced)."""
    return {key.split(" ", 1)[1] for name, (key, _) in registered.items()
            if name not in replaced}
