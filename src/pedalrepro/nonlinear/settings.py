"""The non-linear models' settings: ``data/parameters/nonlinear_models.yaml``.

Which thesis models have a non-linear counterpart, their bicycle, legs, rider and arms, and the
assumptions of their parameter sets (Sec 2.1.1, 3.1.1.3); the symbolic model options of each.
"""

from __future__ import annotations

from .. import params, paths
from . import model as symbolic

#: Models with a non-linear counterpart here. CF has its own arm loops
#: (:mod:`pedalrepro.nonlinear.arms`); HS is a substitute (rigid-rider body plus a linear
#: correction to Appendix B, :mod:`pedalrepro.nonlinear.substitute`).
NONLINEAR_MODELS: tuple[str, ...] = ("benchmark", "HS", "CF", "HR", "CR")


def settings() -> dict:
    """``data/parameters/nonlinear_models.yaml``."""
    return params.read_yaml(paths.PARAMETERS / "nonlinear_models.yaml")


def model_spec(model: str) -> dict:
    """The ``models`` entry of ``model`` (bicycle, legs, rider, arms, substitute)."""
    models = settings()["models"]
    if model not in models:
        raise KeyError(f"no non-linear model {model!r} in nonlinear_models.yaml: expected one of "
                       f"{sorted(models)}")
    return models[model]


def has_arms(model: str) -> bool:
    """True for a model with arm loops (``arms`` in nonlinear_models.yaml: CF)."""
    return model != "benchmark" and bool(model_spec(model).get("arms"))


def model_options(model: str, legs: bool = False) -> symbolic.ModelOptions:
    """The symbolic model of ``model`` (arm loops for CF), with or without moving legs."""
    return symbolic.ModelOptions(legs=legs, arms=has_arms(model))
