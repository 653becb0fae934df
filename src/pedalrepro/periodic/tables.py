"""Tables of the periodic orbits (``rules/periodic.smk``): the map summary, the multiplier
crossings beside the linear stability boundaries, and the orbit against the simulation-based
estimate (thesis NT/NP)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .. import linear
from .solver import own_linearisation

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["write_tables", "map_summary", "crossing_table", "simulation_comparison"]


def write_tables(map_files, branch_files, time_files, out_maps, out_crossings,
                 out_simulation) -> None:
    """The three tables of ``rules/periodic.smk``: :func:`map_summary`,
    :func:`crossing_table` and :func:`simulation_comparison`, as CSV."""
    maps = [np.load(p) for p in map_files]
    map_summary(maps).to_csv(out_maps, index=False)
    crossing_table([np.load(p) for p in branch_files]).to_csv(out_crossings, index=False)
    simulation_comparison(maps, [np.load(p) for p in time_files]).to_csv(out_simulation,
                                                                         index=False)


def map_summary(maps) -> pd.DataFrame:
    """One row per orbit map: points, converged, stable, residual, multipliers, timing."""
    import pandas as pd

    rows = []
    for d in maps:
        w = np.asarray(d["omega_rad_s"])
        forced = np.broadcast_to(w[None, :] > 0, np.shape(d["converged"]))
        conv = np.asarray(d["converged"]) & forced
        t_ms = 1e3 * np.asarray(d["orbit_time_s"])[forced]
        cpu_ms = 1e3 * np.asarray(d["orbit_cpu_s"])[forced] if "orbit_cpu_s" in d else t_ms
        v = np.asarray(d["speed_m_s"])
        with np.errstate(divide="ignore", invalid="ignore"):
            rd = np.abs(np.asarray(d["roll_amp_rad"]) / np.asarray(d["ps_roll_amp_rad"]) - 1)
        rd = np.where(conv & np.isfinite(rd), 100.0 * rd, -1.0)
        i, j = np.unravel_index(int(np.argmax(rd)), rd.shape)
        rows.append({
            "model": str(d["model"]), "method": str(d["method"]),
            "max_rd_orbit_vs_ps_roll_pct": float(rd[i, j]) if conv.any() else float("nan"),
            "max_rd_at_speed_m_s": float(v[i]), "max_rd_at_omega_rad_s": float(w[j]),
            "median_rd_orbit_vs_ps_roll_pct": float(np.median(rd[conv])) if conv.any()
            else float("nan"),
            "speeds": int(np.size(d["speed_m_s"])), "cadences": int(w.size),
            "orbits": int(forced.sum()), "converged": int(conv.sum()),
            "stable": int((np.asarray(d["stable"]) & forced).sum()),
            "max_residual": float(np.nanmax(np.asarray(d["residual"])[conv])) if conv.any()
            else float("nan"),
            "max_multiplier_abs": float(np.nanmax(np.asarray(d["max_multiplier_abs"])[conv]))
            if conv.any() else float("nan"),
            "max_segments": int(np.max(np.asarray(d["segments"])[forced])) if forced.any()
            else 0,
            "median_ms_per_orbit": float(np.median(t_ms)) if t_ms.size else float("nan"),
            "median_cpu_ms_per_orbit": float(np.median(cpu_ms)) if cpu_ms.size
            else float("nan"),
            "map_s": float(d["elapsed_s"])})
    return pd.DataFrame(rows)


def crossing_table(branch_files) -> pd.DataFrame:
    """Multiplier crossings of the continued branches, beside the nearest stability boundary
    of the model's own linearisation."""
    import pandas as pd

    rows = []
    for b in branch_files:
        bounds = np.asarray(b["linear_stable_ranges_m_s"]).ravel()
        for method in np.atleast_1d(b["methods"]):
            for k, scale in enumerate(np.atleast_1d(b["torque_scales"])):
                key = f"{method}_{k}_crossing_values"
                if key not in b:
                    continue
                for value, kind in zip(b[key], b[f"{method}_{k}_crossing_kinds"], strict=True):
                    near = float(bounds[np.argmin(np.abs(bounds - value))]) if bounds.size \
                        else float("nan")
                    rows.append({"model": str(b["model"]), "method": str(method),
                                 "cadence_rpm": float(b["cadence_rpm"]),
                                 "torque_scale": float(scale), "kind": str(kind),
                                 "speed_m_s": float(value), "linear_boundary_m_s": near,
                                 "shift_m_s": float(value) - near})
    return pd.DataFrame(rows, columns=["model", "method", "cadence_rpm", "torque_scale", "kind",
                                       "speed_m_s", "linear_boundary_m_s", "shift_m_s"])


def simulation_comparison(orbit_maps, time_maps, eigen_step_m_s: float = 0.01) -> pd.DataFrame:
    """Where the simulation-based estimate (thesis NT/NP: DFT of a simulation) agrees with the
    orbit: RD (Eq 3.26, orbit = reference) medians in and outside the self-stable speeds of the
    model's own linearisation, the share of runs that fell, and evaluation point 1a (NT vs NP)
    from orbits and from simulations over the stable region."""
    import pandas as pd

    from .. import evaluation

    orbit = {(str(d["model"]), str(d["method"])): d for d in orbit_maps}
    sim = {(str(d["model"]), str(d["method"])): d for d in time_maps}
    rows = []
    for (model, method), o in orbit.items():
        s = sim.get((model, method))
        if s is None:
            continue
        v, w = np.asarray(o["speed_m_s"]), np.asarray(o["omega_rad_s"])
        if not (np.array_equal(v, s["speed_m_s"]) and np.array_equal(w, s["omega_rad_s"])):
            raise ValueError(f"orbit and simulation grids of {model} {method} differ")
        lin = own_linearisation(model)
        ranges = linear.stable_ranges(lin, np.arange(0.0, v.max() + 2 * eigen_step_m_s,
                                                     eigen_step_m_s))
        stable_v = np.zeros(v.shape, bool)
        for lo, hi in ranges:
            stable_v |= (v > lo) & (v < hi)
        forced = w[None, :] > 0
        st = np.broadcast_to(stable_v[:, None], (v.size, w.size)) & forced
        un = ~np.broadcast_to(stable_v[:, None], (v.size, w.size)) & forced
        row = {"model": model, "method": method}
        for dof in ("roll", "steer"):
            rd = evaluation.relative_difference(o[f"{dof}_amp_rad"], s[f"{dof}_amp_rad"])
            for name, mask in (("stable", st), ("unstable", un)):
                vals = rd[mask & np.isfinite(rd)]
                row[f"{dof}_rd_median_{name}_pct"] = float(np.median(vals)) if vals.size \
                    else float("nan")
        row["fell_unstable_pct"] = 100.0 * float(np.mean(np.asarray(s["fell"])[un])) \
            if un.any() else float("nan")
        row["fell_stable_pct"] = 100.0 * float(np.mean(np.asarray(s["fell"])[st])) \
            if st.any() else float("nan")
        rows.append(row)
    out = pd.DataFrame(rows)
    # evaluation point 1a (NT vs NP, NP the reference) from orbits and from simulations
    for model in sorted({m for m, _ in orbit}):
        if not all(k in orbit and k in sim for k in ((model, "NT"), (model, "NP"))):
            continue
        v = np.asarray(orbit[(model, "NT")]["speed_m_s"])
        w = np.asarray(orbit[(model, "NT")]["omega_rad_s"])
        lin = own_linearisation(model)
        stable_v = np.zeros(v.shape, bool)
        for lo, hi in linear.stable_ranges(lin, np.arange(0.0, v.max() + 0.02, 0.01)):
            stable_v |= (v > lo) & (v < hi)
        mask = np.broadcast_to(stable_v[:, None], (v.size, w.size)) & (w[None, :] > 0)
        for src, d in (("orbit", orbit), ("simulation", sim)):
            rd = evaluation.relative_difference(d[(model, "NP")]["roll_amp_rad"],
                                                d[(model, "NT")]["roll_amp_rad"])
            vals = rd[mask & np.isfinite(rd)]
            out.loc[out["model"] == model, f"1a_roll_median_{src}_pct"] = (
                float(np.median(vals)) if vals.size else float("nan"))
        rd = evaluation.relative_difference(orbit[(model, "NP")]["roll_amp_rad"],
                                            orbit[(model, "NT")]["roll_amp_rad"])
        vals = rd[(w[None, :] > 0) & np.isfinite(rd)]
        out.loc[out["model"] == model, "1a_roll_median_orbit_all_speeds_pct"] = (
            float(np.median(vals)) if vals.size else float("nan"))
    return out
