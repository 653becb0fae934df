"""Time solutions of the non-linear models on the speed x cadence grid: methods NT and NP.

NT (Sec 3.1.2.1, Fig 3.7): legs fixed to the rear frame (lumped into body B) plus the harmonic
generalised pedalling torques of Eq 3.14 (w, 3w, 5w). NP: legs and cranks move as prescribed by
the four-bar at the cadence (no torques applied: the pedalling disturbance comes from the leg
motion itself). Each run starts upright and straight ahead at the grid speed with zero roll and
steer rates (Sec 3.1.2.2), ends at the fall event or the horizon, and is reduced to the
Hann-windowed DFT amplitude at the cadence (Sec 3.1.2.1.1, ``spectral.amplitude_at``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import spectral
from ..integrator import Simulation
from .models import np_model, nt_model
from .nonlinear_model import NonlinearModel
from .simulate import simulate

__all__ = [
    "METHODS", "RunSettings", "run", "model_for", "amplitudes", "time_histories", "grid_runs",
]

METHODS: tuple[str, ...] = ("NT", "NP")


@dataclass
class RunSettings:
    """Integration settings of a sweep (config ``nonlinear`` and ``linear`` time keys)."""

    duration_s: float
    sample_rate_hz: float
    rtol: float
    atol: float
    fall_roll_rad: float
    method: str = "RK45"
    #: compiled RK45 variant (:data:`pedalrepro.integrator.VARIANTS`): "hermite", the scheme the
    #: NT/NP tables were made with ("scipy" reproduces solve_ivp's RK45 step for step and would
    #: change them at the tolerance level)
    variant: str = "hermite"

    @classmethod
    def from_config(cls, cfg: dict) -> RunSettings:
        lin, nl = cfg["linear"], cfg["nonlinear"]
        return cls(lin["duration_s"], lin["sample_rate_hz"], nl["rtol"], nl["atol"],
                   nl["fall_roll_rad"], nl["method"])


def run(method: str, name: str, speed_m_s: float, omega_rad_s: float, harmonics,
        settings: RunSettings, model: NonlinearModel | None = None) -> Simulation | None:
    """One time solution; ``None`` at zero cadence (no forcing: the upright motion persists).

    ``model``: the model to integrate, if already built (:func:`model_for`)."""
    if omega_rad_s <= 0:
        return None
    if method not in METHODS:
        raise ValueError(f"unknown non-linear method {method!r}: expected one of {METHODS}")
    nl = model if model is not None else model_for(method, name, omega_rad_s)
    # NT: harmonic torques (Eq 3.14); NP: the prescribed leg motion only (in the model)
    return simulate(nl, speed_m_s, settings.duration_s, settings.sample_rate_hz,
                    harmonics=harmonics if method == "NT" else None, omega_rad_s=omega_rad_s,
                    rtol=settings.rtol, atol=settings.atol, fall_roll_rad=settings.fall_roll_rad,
                    method=settings.method, variant=settings.variant)


def model_for(method: str, name: str, omega_rad_s: float) -> NonlinearModel:
    """The model a run integrates: NT's is the same at every cadence, NP's has the leg motion
    of the cadence (:func:`.models.np_model`)."""
    return nt_model(name) if method == "NT" else np_model(name, omega_rad_s)


def amplitudes(sim: Simulation | None, omega_rad_s: float, sample_rate_hz: float,
               min_samples: int = 2) -> tuple[float, float]:
    """Hann-windowed DFT amplitude at the cadence over the simulated part (NaN if too short)."""
    if sim is None:
        return 0.0, 0.0
    ok = np.isfinite(sim.roll_rad)
    if ok.sum() < min_samples:
        return np.nan, np.nan
    f = omega_rad_s / (2 * np.pi)
    return (float(spectral.amplitude_at(sim.roll_rad[ok], sample_rate_hz, f)),
            float(spectral.amplitude_at(sim.steer_rad[ok], sample_rate_hz, f)))


def time_histories(method: str, name: str, speeds_m_s, omegas_rad_s, harmonics,
                   settings: RunSettings, t_s: np.ndarray) -> dict[str, np.ndarray]:
    """Roll and steer time histories of the runs at the points ``(speeds_m_s[k],
    omegas_rad_s[k])`` on the samples ``t_s`` (the example runs and one-speed series of Figs
    3.18-3.29): ``roll_rad``, ``steer_rad`` (NaN after a fall), ``t_end_s``, ``fell``. A point
    at zero cadence is the unforced upright motion: zero roll and steer to the end."""
    roll = np.full((len(speeds_m_s), t_s.size), np.nan)
    steer = np.full_like(roll, np.nan)
    end = np.zeros(len(speeds_m_s))
    fell = np.zeros(len(speeds_m_s), bool)
    for k, (vk, wk) in enumerate(zip(speeds_m_s, omegas_rad_s, strict=True)):
        sim = run(method, name, vk, wk, harmonics, settings)
        if sim is None:
            roll[k], steer[k], end[k] = 0.0, 0.0, t_s[-1]
            continue
        n = min(t_s.size, sim.t_s.size)
        roll[k, :n], steer[k, :n] = sim.roll_rad[:n], sim.steer_rad[:n]
        end[k], fell[k] = sim.t_end_s, sim.fell
    return {"roll_rad": roll, "steer_rad": steer, "t_end_s": end, "fell": fell}


def grid_runs(method: str, name: str, speeds_m_s, omegas_rad_s, harmonics,
              settings: RunSettings) -> dict[str, np.ndarray]:
    """Amplitudes, end times and fall flags on ``speeds x omegas`` (one run per point)."""
    v = np.asarray(speeds_m_s, float)
    w = np.asarray(omegas_rad_s, float)
    shape = (v.size, w.size)
    out = {k: np.zeros(shape) for k in ("roll_amp_rad", "steer_amp_rad", "t_end_s")}
    out["fell"] = np.zeros(shape, bool)
    out["n_rhs"] = np.zeros(shape, int)
    # built once for all speeds: NT one model, NP one per cadence (~20 ms to build each)
    cadences = sorted({wj for wj in w.tolist() if wj > 0})
    if method == "NT":
        built = dict.fromkeys(cadences, nt_model(name))
    else:
        built = {wj: model_for(method, name, wj) for wj in cadences}
    for i, vi in enumerate(v):
        for j, wj in enumerate(w):
            sim = run(method, name, vi, wj, harmonics, settings, built.get(float(wj)))
            out["roll_amp_rad"][i, j], out["steer_amp_rad"][i, j] = amplitudes(
                sim, wj, settings.sample_rate_hz)
            out["t_end_s"][i, j] = settings.duration_s if sim is None else sim.t_end_s
            out["fell"][i, j] = False if sim is None else sim.fell
            out["n_rhs"][i, j] = 0 if sim is None else sim.n_rhs
    return out
