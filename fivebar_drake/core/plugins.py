"""Variants from other packages: a package registers its gaits, maneuvers, controllers, stance
laws, closures or studies through the entry point group fivebar_drake.plugins, each entry a
module whose import registers them (the registries' decorators: register_path,
register_controller, register_stance_law, register_closure; catalog.register_study), as
Gymnasium's `register` does. In its pyproject.toml:

    [project.entry-points."fivebar_drake.plugins"]
    gallop = "my_package.gallop"

load() imports every such module once per process; the command line calls it before it builds
its choices, and a registry asked for a kind it does not know calls it before it says no (a
Dask worker loading a scenario, a script)."""

from __future__ import annotations

import importlib
from importlib.metadata import entry_points

from fivebar_drake.core.validation import ParameterError

GROUP = "fivebar_drake.plugins"
_loaded: dict[str, str] = {}       # entry point name -> module, once imported


def load() -> dict[str, str]:
    """Import the module of every entry point of GROUP not imported yet; returns {name:
    module} of all loaded. ParameterError naming the entry point whose module fails to import
    (an installed package's fault, not this one's)."""
    for point in entry_points(group=GROUP):
        if point.name in _loaded:
            continue
        try:
            importlib.import_module(point.module)
        except Exception as err:  # noqa: BLE001  (any failure of someone else's module)
            raise ParameterError(f"entry point {point.name} = {point.module}: its module "
                                 f"cannot be imported ({type(err).__name__}: {err}); fix or "
                                 "uninstall the package that declares it",
                                 f"entry point {point.name}", f"plugin group {GROUP}") from err
        _loaded[point.name] = point.module
    return dict(_loaded)
