"""Drake's config structs (MultibodyPlantConfig, SimulatorConfig) as plain data: their fields as
a dict, and a copy with some fields changed. pydrake cannot pickle or compare them."""

from __future__ import annotations


def config_fields(config) -> dict:
    """A Drake config's fields as a plain dict."""
    return {f.name: getattr(config, f.name) for f in type(config).__fields__}


def config_with(config, **changes):
    """A copy of a Drake config with the given fields changed."""
    return type(config)(**{**config_fields(config), **changes})
