"""BicycleParameters (J. K. Moore) and its Yeadon rider, loaded once per bicycle.

The bicycles' measured data are the copies in ``data/parameters/bicycleparameters``; the rider
is Jason (``add_rider('Jason', reCalc=True)``, Yeadon's inertia model). One cached load serves
the benchmark parameters of the rigid-rider models and the arm segments of CF.

The numbers a load yields (the benchmark parameters with and without the rider, and the
rider's arm segments in the benchmark frame) are kept on disk beside the derived models
(``$PEDALREPRO_CACHE/bicycle_data``, :func:`pedalrepro.integrator.build.cache_root`), keyed by
a hash of the parameter files, this module and the versions of BicycleParameters, Yeadon, dtk,
NumPy and SciPy (:func:`snapshot_key`): importing BicycleParameters (it imports
``matplotlib.pyplot``, ``dtk.control`` and ``scipy.optimize``) took 1.6 s of every job that
builds a non-linear model, about 22 jobs of the thesis profile. JSON keeps every float to the
bit, so a load from the snapshot equals a fresh one exactly (tests/nonlinear/test_bicycle_data.py).
The ``bicycleparameters.Bicycle`` itself is built only when asked for (:attr:`BicycleData.bicycle`).
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.metadata
import io
import json
import os
import warnings
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from .. import paths

__all__ = ["BicycleData", "load", "snapshot_key", "YEADON_TO_BIKE", "ARM_POINTS", "ARM_PARTS"]

#: Yeadon -> bicycle (benchmark) axes: BicycleParameters ``rider.yeadon_vec_to_bicycle_vec``.
YEADON_TO_BIKE = np.array([[0.0, -1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
#: Joint centres of the right arm kept in the snapshot: shoulder (``B1.pos``), elbow
#: (``B1.end_pos``) and the base of the thumb (``B2.solids[2].pos``).
ARM_POINTS: tuple[str, ...] = ("shoulder", "elbow", "grip")
#: Yeadon parts kept (mass, COM and central inertia in the benchmark frame): the four arm
#: segments and the five solids of the right forearm and hand (``B2.solids``: b2, b3 forearm;
#: b4, b5, b6 hand).
ARM_PARTS: tuple[str, ...] = ("A1", "A2", "B1", "B2", "b2", "b3", "b4", "b5", "b6")
_VERSIONED = ("BicycleParameters", "yeadon", "DynamicistToolKit", "numpy", "scipy")


@dataclass(frozen=True)
class BicycleData:
    """One bicycle as loaded by BicycleParameters.

    ``frame``: benchmark parameters of the bicycle alone; ``with_rider``: the same with the
    rider lumped into body B (equal to ``frame`` without a rider); ``arms`` (with a rider):
    ``{"points": {name: (3,)}, "parts": {name: {"mass", "com", "inertia"}}}`` of
    :data:`ARM_POINTS` and :data:`ARM_PARTS`, in the benchmark frame (``None`` without a rider).
    """

    name: str
    rider: bool
    frame: dict[str, float]
    with_rider: dict[str, float]
    arms: dict | None

    @property
    def bicycle(self):
        """The ``bicycleparameters.Bicycle`` with the rider added (``None`` without a rider),
        whose ``human`` is the Yeadon model and whose ``parameters['Measured']``/
        ``['Benchmark']`` place it; built (and BicycleParameters imported) on first use."""
        return _bicycle(self.name, True)[0] if self.rider else None


def _parameter_files() -> list[Path]:
    root = paths.PARAMETERS / "bicycleparameters"
    return sorted(p for p in root.rglob("*") if p.is_file())


def snapshot_key(name: str, rider: bool) -> str:
    """Hash of everything a load depends on: the files of ``data/parameters/bicycleparameters``
    (paths and bytes), this module's source and the versions of BicycleParameters, Yeadon, dtk,
    NumPy and SciPy."""
    h = hashlib.sha256(Path(__file__).read_bytes())
    root = paths.PARAMETERS / "bicycleparameters"
    for f in _parameter_files():
        h.update(f.relative_to(root).as_posix().encode() + b"\0" + f.read_bytes())
    for dist in _VERSIONED:
        h.update(f"{dist}={importlib.metadata.version(dist)}".encode())
    return f"{name}_{'rider' if rider else 'alone'}_{h.hexdigest()[:16]}"


@cache
def _bicycle(name: str, rider: bool = True):
    """BicycleParameters' bicycle ``name`` (with rider Jason), printing and warnings silenced."""
    import bicycleparameters as bp

    with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()):
        warnings.simplefilter("ignore")
        bike = bp.Bicycle(name, pathToData=str(paths.PARAMETERS / "bicycleparameters"),
                          forceRawCalc=name == "Stratos")
        alone = bp.io.remove_uncertainties(dict(bike.parameters["Benchmark"]))
        if rider:
            bike.add_rider("Jason", reCalc=True)
    return bike, alone


def _arm_data(bike) -> dict:
    """The rider's arm points and parts in the benchmark frame (:data:`ARM_POINTS`,
    :data:`ARM_PARTS`)."""
    from bicycleparameters.rider import yeadon_vec_to_bicycle_vec

    human = bike.human
    measured, benchmark = bike.parameters["Measured"], bike.parameters["Benchmark"]

    def point(v) -> list[float]:
        return [float(x) for x in yeadon_vec_to_bicycle_vec(
            np.asarray(v, float).reshape(3, 1), measured, benchmark)[:, 0].astype(float)]

    def part(obj) -> dict:
        inertia = YEADON_TO_BIKE @ np.asarray(obj.inertia, float) @ YEADON_TO_BIKE.T
        return {"mass": float(obj.mass), "com": point(obj.center_of_mass),
                "inertia": [[float(x) for x in row] for row in inertia]}

    solids = dict(zip(("b2", "b3", "b4", "b5", "b6"), human.B2.solids, strict=True))
    parts = {k: part(getattr(human, k)) for k in ("A1", "A2", "B1", "B2")}
    parts.update({k: part(s) for k, s in solids.items()})
    return {"points": {"shoulder": point(human.B1.pos), "elbow": point(human.B1.end_pos),
                       "grip": point(human.B2.solids[2].pos)},
            "parts": {k: parts[k] for k in ARM_PARTS}}


def _compute(name: str, rider: bool) -> dict:
    """The snapshot of one load, from BicycleParameters."""
    import bicycleparameters as bp

    bike, alone = _bicycle(name, rider)
    both, arms = dict(alone), None
    if rider:
        both = bp.io.remove_uncertainties(dict(bike.parameters["Benchmark"]))
        arms = _arm_data(bike)
    return {"frame": {k: float(v) for k, v in alone.items()},
            "with_rider": {k: float(v) for k, v in both.items()}, "arms": arms}


@cache
def load(name: str, rider: bool = True) -> BicycleData:
    """Bicycle ``name`` (``"Stratos"``, ``"Browser"``) with or without rider Jason.

    Stratos is computed from its raw pendulum measurements (``forceRawCalc``). BicycleParameters'
    printing and warnings are silenced; uncertainties are removed. Read from the snapshot when
    one with the same :func:`snapshot_key` exists, else computed and the snapshot written
    (atomically; a folder that cannot be written only costs the recomputation next time).
    """
    path = _snapshot_folder() / f"{snapshot_key(name, rider)}.json"
    data = None
    if path.is_file():
        with contextlib.suppress(OSError, ValueError):
            data = json.loads(path.read_text())
    if not (isinstance(data, dict) and {"frame", "with_rider", "arms"} <= set(data)):
        data = _compute(name, rider)
        with contextlib.suppress(OSError):
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(f".tmp{os.getpid()}")
            tmp.write_text(json.dumps(data, indent=1))
            tmp.replace(path)
    return BicycleData(name, rider, {k: float(v) for k, v in data["frame"].items()},
                       {k: float(v) for k, v in data["with_rider"].items()}, data["arms"])


def _snapshot_folder() -> Path:
    from ..integrator.build import cache_root

    return cache_root() / "bicycle_data"
