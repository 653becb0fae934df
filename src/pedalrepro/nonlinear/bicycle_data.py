"""BicycleParameters (J. K. Moore) and its Yeadon rider, loaded once per bicycle.

The bicycles' measured data are the copies in ``data/parameters/bicycleparameters``; the rider
is Jason (``add_rider('Jason', reCalc=True)``, Yeadon's inertia model). One cached load serves
the benchmark parameters of the rigid-rider models and the arm segments of CF.
"""

from __future__ import annotations

import contextlib
import io
import warnings
from dataclasses import dataclass
from functools import cache

from .. import paths

__all__ = ["BicycleData", "load"]


@dataclass(frozen=True)
class BicycleData:
    """One bicycle as loaded by BicycleParameters.

    ``frame``: benchmark parameters of the bicycle alone; ``with_rider``: the same with the
    rider lumped into body B (equal to ``frame`` without a rider); ``bicycle``: the
    ``bicycleparameters.Bicycle`` with the rider added (``None`` without a rider), whose
    ``human`` is the Yeadon model and whose ``parameters['Measured']``/``['Benchmark']`` place it.
    """

    frame: dict[str, float]
    with_rider: dict[str, float]
    bicycle: object | None


@cache
def load(name: str, rider: bool = True) -> BicycleData:
    """Bicycle ``name`` (``"Stratos"``, ``"Browser"``) with or without rider Jason.

    Stratos is computed from its raw pendulum measurements (``forceRawCalc``). BicycleParameters'
    printing and warnings are silenced; uncertainties are removed.
    """
    import bicycleparameters as bp

    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        bike = bp.Bicycle(name, pathToData=str(paths.PARAMETERS / "bicycleparameters"),
                          forceRawCalc=name == "Stratos")
        alone = bp.io.remove_uncertainties(dict(bike.parameters["Benchmark"]))
        both = dict(alone)
        if rider:
            bike.add_rider("Jason", reCalc=True)
            both = bp.io.remove_uncertainties(dict(bike.parameters["Benchmark"]))
    return BicycleData({k: float(v) for k, v in alone.items()},
                       {k: float(v) for k, v in both.items()}, bike if rider else None)
