"""Workflow configuration: load ``config/*.yaml`` and validate it against ``config/schema.yaml``.

The Snakefile validates with ``snakemake.utils.validate`` against the same schema; this module
serves the library, the CLI and notebooks.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import jsonschema

from . import paths
from .params import read_yaml


class ConfigError(ValueError):
    """A configuration value outside the schema."""


def validate(config: dict[str, Any], schema_path: str | Path | None = None) -> dict[str, Any]:
    """Validate ``config`` against the JSON schema, raising :class:`ConfigError` with the key path.

    Returns the same mapping (defaults are not filled in here; the schema documents them).
    """
    schema = read_yaml(schema_path or paths.CONFIG / "schema.yaml")
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(config), key=lambda e: list(e.absolute_path))
    if errors:
        lines = [f"  {'/'.join(map(str, e.absolute_path)) or '<top>'}: {e.message}" for e in errors]
        raise ConfigError("configuration does not match config/schema.yaml:\n" + "\n".join(lines))
    return config


def load(path: str | Path | None = None, *overrides: str | Path) -> dict[str, Any]:
    """Load ``config/config.yaml`` (or ``path``), merge override files on top, and validate.

    Parameters
    ----------
    path
        The base configuration (default ``config/config.yaml``).
    overrides
        Further YAML files (e.g. ``config/quick.yaml``) merged key by key, recursively.
    """
    config = read_yaml(path or paths.CONFIG / "config.yaml")
    for extra in overrides:
        config = merge(config, read_yaml(extra))
    return validate(config)


def merge(base: dict[str, Any], extra: dict[str, Any]) -> dict[str, Any]:
    """Recursive dictionary merge, ``extra`` winning (Snakemake's ``--configfile`` semantics)."""
    out = dict(base)
    for key, value in extra.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = value
    return out
