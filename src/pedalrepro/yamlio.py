"""Reading YAML mappings with errors that name the file (parameters, configuration, published
values). No data files of its own, so importing it adds no rule inputs
(:mod:`pedalrepro.dependencies`)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

__all__ = ["read_mapping"]


def read_mapping(path: str | Path, what: str = "YAML",
                 error: type[Exception] = ValueError) -> dict[str, Any]:
    """The mapping at the top level of the YAML file ``path``.

    Raises FileNotFoundError ("``what`` file not found: path") when it is missing, and ``error``
    when it cannot be parsed or its top level is not a mapping.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
    ...     _ = f.write("- a list\\n")
    >>> try:
    ...     read_mapping(f.name, "parameter")
    ... except ValueError as exc:
    ...     print(str(exc).endswith("expected a mapping at the top level, got list"))
    True
    >>> os.unlink(f.name)
    """
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise FileNotFoundError(f"{what} file not found: {path}") from None
    except yaml.YAMLError as exc:
        raise error(f"cannot parse YAML file {path}: {exc}") from exc
    if not isinstance(data, dict):
        raise error(f"{path}: expected a mapping at the top level, got {type(data).__name__}")
    return data
