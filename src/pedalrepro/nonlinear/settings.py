"""The non-linear models' settings: ``data/parameters/nonlinear_models.yaml``.

Which thesis models have a non-linear counterpart, their bicycle, legs, rider and arms, and the
assumptions of their parameter sets (Sec 2.1.1, 3.1.1.3); the symbolic model options of each.
"""

from __future__ import annotations

from functools import cache

from .. import params, paths
from . import symbolic

__all__ = [
    "NONLINEAR_MODELS", "settings", "thesis_inputs", "model_spec", "has_arms", "model_options",
]

#: Models with a non-linear counterpart here: every linear model
#: (:data:`pedalrepro.params.LINEAR_MODELS`, the benchmark and the four systems). CF and HS have
#: arm loops (:mod:`pedalrepro.nonlinear.arms`, :mod:`pedalrepro.nonlinear.arm_design`).
NONLINEAR_MODELS: tuple[str, ...] = params.LINEAR_MODELS


@cache
def settings() -> dict:
    """``data/parameters/nonlinear_models.yaml`` (read once; do not modify)."""
    return params.read_yaml(paths.PARAMETERS / "nonlinear_models.yaml")


@cache
def thesis_inputs() -> dict:
    """``data/parameters/thesis_inputs.yaml``: the thesis's bicycle, wheel and rider inputs and
    the calibration settings (read once; do not modify)."""
    return params.read_yaml(paths.PARAMETERS / "thesis_inputs.yaml")


def model_spec(model: str) -> dict:
    """The ``models`` entry of ``model`` (bicycle, legs, rider, arms, arm_plane)."""
    models = settings()["models"]
    if model not in models:
        raise KeyError(f"no non-linear model {model!r} in nonlinear_models.yaml: expected one of "
                       f"{sorted(models)}")
    return models[model]


def has_arms(model: str) -> bool:
    """True for a model with arm loops (``arms`` in nonlinear_models.yaml: CF, HS)."""
    return model != "benchmark" and bool(model_spec(model).get("arms"))


def model_options(model: str, legs: bool = False) -> symbolic.ModelOptions:
    """The symbolic model of ``model`` (arm loops for CF, HS), with or without moving legs."""
    return symbolic.ModelOptions(legs=legs, arms=has_arms(model))
