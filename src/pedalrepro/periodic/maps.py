"""Orbit maps over the speed x cadence grid (the maps of Fig 3.35/G.7 for the non-linear
models), and the map rule's output (``rules/periodic.smk``)."""

from __future__ import annotations

import time

import numpy as np

from .. import response
from .solver import Orbit, OrbitSolver

__all__ = ["MAP_KEYS", "orbit_map", "write_map", "nested", "write_submap"]

MAP_KEYS = ("roll_amp_rad", "steer_amp_rad", "roll_phase_rad", "steer_phase_rad",
            "max_multiplier_abs", "residual", "peak_roll_rad", "peak_steer_rad",
            "hold_torque_mean_nm", "orbit_time_s", "orbit_cpu_s", "ps_roll_amp_rad",
            "ps_steer_amp_rad")


def orbit_map(model: str, method: str, speeds_m_s, omegas_rad_s, *, rtol: float = 1e-9,
              max_growth: float = 100.0, torque_scale: float = 1.0) -> dict[str, np.ndarray]:
    """Periodic orbits on ``speeds x omegas`` (the maps of Fig 3.35/G.7 for the non-linear
    models).

    Each point starts from the PS of the model's own linearisation, corrected by the converged
    orbits at the two next lower speeds (``guide`` and ``second`` of
    :meth:`OrbitSolver.solve`: their departure from their own PS and the non-linear part of
    their shooting Jacobian, extrapolated linearly in speed), so that the chord steps start
    closer and contract faster; a failed point is retried from the PS alone with twice the
    shooting segments and then from the converged neighbour at the next lower speed. Zero
    cadence (no forcing) gives zero amplitude and NaN multipliers.

    Returns
    -------
    dict
        ``speed_m_s``, ``omega_rad_s`` and, on the grid, the arrays of :data:`MAP_KEYS`,
        ``multipliers`` (complex, (nv, nw, 4)), ``stable``, ``converged``, ``iterations``,
        ``segments``, ``half_period``, ``n_rhs``. ``ps_*``: PS amplitude at the cadence of the
        model's own linearisation (the linear reference of the same model).
    """
    v = np.asarray(speeds_m_s, float)
    w = np.asarray(omegas_rad_s, float)
    shape = (v.size, w.size)
    out = {k: np.full(shape, np.nan) for k in MAP_KEYS}
    out["multipliers"] = np.full(shape + (4,), np.nan + 0j)
    for k in ("stable", "converged", "half_period"):
        out[k] = np.zeros(shape, bool)
    for k in ("iterations", "segments", "n_rhs"):
        out[k] = np.zeros(shape, int)
    for j, wj in enumerate(w):
        if wj <= 0:
            for key in ("roll_amp_rad", "steer_amp_rad", "ps_roll_amp_rad", "ps_steer_amp_rad"):
                out[key][:, j] = 0.0
            out["converged"][:, j] = True
            continue
        solver = OrbitSolver(model, method, wj, rtol=rtol, max_growth=max_growth,
                             torque_scale=torque_scale)
        roll_ps, steer_ps = response.particular_solution(solver.linear, v, wj, solver.harmonics)
        first = int(np.flatnonzero(np.asarray(solver.harmonics.n) == 1)[0])
        out["ps_roll_amp_rad"][:, j] = np.abs(roll_ps[:, first])
        out["ps_steer_amp_rad"][:, j] = np.abs(steer_ps[:, first])
        previous: Orbit | None = None
        guides: list[Orbit] = []  # converged orbits at the last two speeds, newest first
        for i, vi in enumerate(v):
            t0, c0 = time.perf_counter(), time.process_time()
            orb = solver.solve(vi, guide=guides[0] if guides else None,
                               second=guides[1] if len(guides) > 1 else None)
            if not orb.converged:
                orb = solver.solve(vi, segments=2 * orb.segments)
            if not orb.converged and previous is not None:
                orb = solver.solve(vi, start=previous.nodes)
            out["orbit_time_s"][i, j] = time.perf_counter() - t0
            out["orbit_cpu_s"][i, j] = time.process_time() - c0
            if orb.converged:
                previous = orb
            guides = [orb] + guides[:1] if orb.converged else []
            out["roll_amp_rad"][i, j] = orb.roll_amplitude_rad
            out["steer_amp_rad"][i, j] = orb.steer_amplitude_rad
            out["roll_phase_rad"][i, j] = orb.roll_phase_rad
            out["steer_phase_rad"][i, j] = orb.steer_phase_rad
            out["multipliers"][i, j] = orb.floquet_multipliers
            out["max_multiplier_abs"][i, j] = np.max(np.abs(orb.floquet_multipliers))
            out["residual"][i, j] = orb.periodicity_residual
            out["peak_roll_rad"][i, j] = orb.peak_roll_rad
            out["peak_steer_rad"][i, j] = orb.peak_steer_rad
            out["hold_torque_mean_nm"][i, j] = orb.hold_torque_mean_nm
            out["stable"][i, j] = orb.converged and orb.stable
            out["converged"][i, j] = orb.converged
            out["half_period"][i, j] = orb.half_period
            out["iterations"][i, j] = orb.iterations
            out["segments"][i, j] = orb.segments
            out["n_rhs"][i, j] = orb.n_rhs
            if not orb.converged:  # keep the residual reached, blank the orbit's values
                for key in ("roll_amp_rad", "steer_amp_rad", "roll_phase_rad", "steer_phase_rad",
                            "max_multiplier_abs", "peak_roll_rad", "peak_steer_rad",
                            "hold_torque_mean_nm"):
                    out[key][i, j] = np.nan
    out["speed_m_s"], out["omega_rad_s"] = v, w
    return out



def write_map(path, model: str, method: str, speed_step_m_s: float, speed_max_m_s: float,
              omega_step_rad_s: float, omega_max_rad_s: float, *, rtol: float,
              max_growth: float) -> dict:
    """Orbit map of one model and method on ``0:step:max`` grids, saved as ``.npz``.

    Besides :func:`orbit_map`'s arrays: ``model``, ``method``, ``elapsed_s`` (whole map).
    """
    v = response.grid(speed_step_m_s, speed_max_m_s)
    w = response.grid(omega_step_rad_s, omega_max_rad_s)
    start = time.perf_counter()
    out = orbit_map(model, method, v, w, rtol=rtol, max_growth=max_growth)
    elapsed = time.perf_counter() - start
    np.savez_compressed(path, model=model, method=method, elapsed_s=elapsed, rtol=rtol, **out)
    out["elapsed_s"] = elapsed
    return out




def _indices(coarse: np.ndarray, fine: np.ndarray) -> np.ndarray | None:
    """Index in ``fine`` of every value of ``coarse`` (to 1e-9), or None when one is missing."""
    idx = np.searchsorted(fine, coarse - 1e-9)
    idx = np.minimum(idx, fine.size - 1)
    return idx if np.all(np.abs(fine[idx] - coarse) <= 1e-9) else None


def nested(coarse: dict, fine: dict) -> bool:
    """Whether the ``0:step:max`` speed and cadence grids ``coarse`` (keyword arguments of
    :func:`write_map`: ``speed_step_m_s``, ``speed_max_m_s``, ``omega_step_rad_s``,
    ``omega_max_rad_s``) are subsets of those of ``fine``."""
    return all(_indices(response.grid(coarse[f"{k}_step_{u}"], coarse[f"{k}_max_{u}"]),
                        response.grid(fine[f"{k}_step_{u}"], fine[f"{k}_max_{u}"])) is not None
               for k, u in (("speed", "m_s"), ("omega", "rad_s")))


def write_submap(path, fine_path, speed_step_m_s: float, speed_max_m_s: float,
                 omega_step_rad_s: float, omega_max_rad_s: float) -> dict:
    """The orbit map on the ``0:step:max`` grids cut out of a map on a finer grid that contains
    them (``fine_path``, a :func:`write_map` file), saved as ``.npz`` like :func:`write_map`.

    Every point of :func:`orbit_map` is the same periodic orbit whatever its neighbours: they
    only change the start and the chord Jacobian of Newton (the neighbours at 0.2 m/s on the
    finer grid of config/config.yaml instead of 0.4), so the cut-out orbits are those a map on
    the coarse grid computes to Newton's tolerance (residual at most 1e-10 of the orbit's size
    at convergence; tests/periodic/test_periodic_speed.py solves a column both ways); the grids
    are the coarse ones (to the bit, as the simulation sweeps on that grid have them) and
    ``elapsed_s`` is the orbits' own time (``orbit_time_s`` summed).
    """
    with np.load(fine_path, allow_pickle=False) as d:
        fine = {k: d[k] for k in d.files}
    v = response.grid(speed_step_m_s, speed_max_m_s)
    w = response.grid(omega_step_rad_s, omega_max_rad_s)
    iv, iw = _indices(v, fine["speed_m_s"]), _indices(w, fine["omega_rad_s"])
    if iv is None or iw is None:
        raise ValueError(f"{fine_path}: its grid does not contain the speeds {v} and cadences "
                         f"{w}")
    shape = (fine["speed_m_s"].size, fine["omega_rad_s"].size)
    out = {}
    for key, a in fine.items():
        out[key] = a[np.ix_(iv, iw)] if a.shape[:2] == shape else a
    out["speed_m_s"], out["omega_rad_s"] = v, w
    out["elapsed_s"] = np.float64(np.nansum(out["orbit_time_s"]))
    np.savez_compressed(path, **out)
    return out
