"""Parameter sets: bicycles, rider, legs and the Appendix B linear models.

One source of truth per number: everything is read from ``data/parameters/*.yaml`` (each file
cites its source). Benchmark parameter names follow Meijaard et al. (2007) and BicycleParameters
(``w``, ``c``, ``lam``, ``rR``, ``mB``, ``xB``, ``IBxx`` ...), so a user's own bicycle file
drops in.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np

from . import paths, yamlio

__all__ = [
    "DATA_FILES", "MODELS", "LINEAR_MODELS", "BICYCLE_OF_MODEL", "read_yaml",
    "benchmark_parameters", "stratos_geometry", "steer_geometry", "legs", "LinearModel",
    "appendix_b_model", "published",
]

#: Files read under a computed name (``_parameter_file(name)``; see pedalrepro.dependencies):
#: the rules importing this module rerun when one of them changes.
DATA_FILES: tuple[str, ...] = ("data/parameters/appendix_b.yaml", "data/parameters/benchmark.yaml",
                               "data/parameters/browser.yaml", "data/parameters/legs.yaml",
                               "data/parameters/stratos.yaml")
#: The thesis's four bicycle-rider systems (Sec 3.1.1.3, Appendix B; the treadmill runs of Sec
#: 4.1): H = hybrid (Batavus Stratos), C = city (Batavus Browser); S = straight arms on the
#: handlebars, F = flexed arms, R = rigid upper body, hands free. THE model list of the project:
#: every rule, figure, table and notebook covers exactly these (each has a non-linear
#: counterpart, CF and HS with arm loops), so the list is fixed, not configured (config keys
#: ``linear.models`` and ``nonlinear.models`` are refused, pedalrepro.config.RETIRED_KEYS). A
#: user's own bicycle goes through :mod:`pedalrepro.own_bicycle` (rule ``own_bicycle_resonance``,
#: command ``pedalrepro resonance``).
MODELS: tuple[str, ...] = ("HS", "CF", "HR", "CR")
#: The linear models analysed (Sec 3.1.1, 3.2): the Meijaard et al. (2007) benchmark (eigen and
#: PS figures only; thesis Appendix B's reference) and the four systems of :data:`MODELS`.
LINEAR_MODELS: tuple[str, ...] = ("benchmark", *MODELS)
#: The bicycle of each model, as named in ``legs.yaml`` ``seat_geometry``.
BICYCLE_OF_MODEL: dict[str, str] = {"HS": "hybrid", "HR": "hybrid", "CF": "city", "CR": "city"}


def read_yaml(path: str | Path) -> dict[str, Any]:
    """Read a YAML file, with a clear error naming the file when it is missing or malformed."""
    return yamlio.read_mapping(path, "parameter", ValueError)


@cache
def _parameter_file(name: str) -> dict[str, Any]:
    return read_yaml(paths.PARAMETERS / f"{name}.yaml")


def benchmark_parameters(name: str = "benchmark") -> dict[str, float]:
    """Benchmark (Meijaard 2007) parameters of a bicycle file in ``data/parameters``.

    Parameters
    ----------
    name
        ``"benchmark"`` (Meijaard et al. 2007, Table 1) or ``"browser"`` (Batavus Browser,
        bicycle only), or the stem of any user file with a ``parameters:`` mapping.

    Returns
    -------
    dict
        A fresh copy: parameter name -> value (SI units).
    """
    data = _parameter_file(name)
    if "parameters" not in data:
        raise KeyError(f"data/parameters/{name}.yaml has no 'parameters' mapping")
    return {k: float(v) for k, v in data["parameters"].items()}


def stratos_geometry() -> dict[str, float]:
    """Batavus Stratos steer geometry derived from its raw measurements.

    ``lam = 90 deg - gamma``, ``rF = dF / (2 pi nF)``, trail ``c = (rF sin(lam) - f) / cos(lam)``
    (BicycleParameters' geometry relations; tested in ``tests/test_params.py``).

    Returns
    -------
    dict
        ``w``, ``lam`` (rad), ``c``, ``rF``, ``rR``, ``f`` in SI units.
    """
    raw = _parameter_file("stratos")["raw"]
    lam = np.deg2rad(90.0 - float(raw["gamma"]))
    r_f = float(raw["dF"]) / (2.0 * np.pi * float(raw["nF"]))
    r_r = float(raw["dR"]) / (2.0 * np.pi * float(raw["nR"]))
    c = (r_f * np.sin(lam) - float(raw["f"])) / np.cos(lam)
    return {"w": float(raw["w"]), "lam": float(lam), "c": float(c), "rF": r_f, "rR": r_r,
            "f": float(raw["f"])}


def steer_geometry(bicycle: str) -> dict[str, float]:
    """Wheelbase ``w``, trail ``c`` and steer-axis tilt ``lam`` of ``"hybrid"`` or ``"city"``.

    These set the yaw-to-steer factor ``c cos(lam) / w`` of Eq 2.15.
    """
    if bicycle == "hybrid":
        g = stratos_geometry()
    elif bicycle == "city":
        g = benchmark_parameters("browser")
    elif bicycle == "benchmark":
        g = benchmark_parameters("benchmark")
    else:
        raise ValueError(f"unknown bicycle {bicycle!r}: expected 'hybrid', 'city' or 'benchmark'")
    return {"w": g["w"], "c": g["c"], "lam": g["lam"]}


def legs() -> dict[str, Any]:
    """The leg, crank and seat parameters of ``data/parameters/legs.yaml`` (Sec 2.1.1)."""
    return dict(_parameter_file("legs"))


@dataclass(frozen=True)
class LinearModel:
    """Linearised roll-steer equations ``M q'' + v C1 q' + (g K0 + v^2 K2) q = f`` (Eq 3.1).

    ``q = [roll, steer]`` (rad); matrices as in Meijaard et al. (2007) and thesis Appendix B.
    """

    name: str
    M: np.ndarray
    C1: np.ndarray
    K0: np.ndarray
    K2: np.ndarray
    g: float = 9.81


def appendix_b_model(name: str) -> LinearModel:
    """The Appendix B linear model ``HS``, ``CF``, ``HR`` or ``CR`` (the thesis's own inputs)."""
    models = _parameter_file("appendix_b")["appendix_B_linear_models"]
    if name not in models or name == "equation":
        raise KeyError(f"unknown Appendix B model {name!r}: expected one of {MODELS}")
    m = models[name]
    return LinearModel(name, *(np.array(m[k], dtype=float) for k in ("M", "C1", "K0", "K2")))


def published() -> dict[str, Any]:
    """The thesis's published numbers (``data/published/thesis_values.yaml``): expected values."""
    return read_yaml(paths.PUBLISHED / "thesis_values.yaml")
