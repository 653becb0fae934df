"""Arrays drawn by the linear figures that no sweep rule writes (Fig 3.8, 3.30, 3.31, F.1-F.3,
3.36, G.8).

The figures only read files (:mod:`pedalrepro.figures.registry`); what they draw beyond the
eigen, PS, time and RD sweeps is computed here and written by the rule ``linear_figure_data`` to
``results/intermediate/figures/<name>.npz``. Each function returns a dict of arrays (the npz
content).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from . import gears, linear, momentum, params
from .response import forcing, grid, particular_solution, select

__all__ = [
    "LINEAR_KEYS", "ps_grid_of", "gear_grid", "cam_cases", "neglected_momenta", "gear_section",
    "gear_sections", "write_linear", "validation", "write_validation",
]

#: The ``linear`` config keys the figure data use (the rule passes only these).
LINEAR_KEYS: tuple[str, ...] = (
    "ps_speed_step_m_s", "ps_speed_max_m_s", "ps_omega_step_rad_s", "ps_omega_max_rad_s",
    "eigen_speed_step_m_s", "eigen_speed_max_m_s", "gear_ratios", "harmonics",
    "normal_cycling_speed_kmh", "normal_cycling_cadence_rpm", "reference_speed_m_s",
    "reference_cadence_rpm")


def ps_grid_of(lin: Mapping) -> tuple[np.ndarray, np.ndarray]:
    """The particular-solution grid (speeds m/s, cadences rad/s) from the ``linear`` keys."""
    return (grid(lin["ps_speed_step_m_s"], lin["ps_speed_max_m_s"]),
            grid(lin["ps_omega_step_rad_s"], lin["ps_omega_max_rad_s"]))


def gear_grid(speed_m_s: np.ndarray, omega_rad_s: np.ndarray, gear_ratios: Sequence[float],
              normal_cycling_speed_kmh, normal_cycling_cadence_rpm,
              reference: tuple[float, float]) -> dict[str, np.ndarray]:
    """Fig 3.8: the PS grid, gear ratios, the normal-cycling ellipse and the reference point
    (speed m/s, cadence rad/s; city-bicycle wheel, Sec 3.1.3.2); the wheel radius of each
    model's bicycle (Fig 3.35)."""
    ev, ew = gears.normal_cycling_ellipse(normal_cycling_speed_kmh, normal_cycling_cadence_rpm)
    radii = {f"wheel_radius_{m}_m": np.float64(gears.wheel_radius_m(linear.bicycle_of(m)))
             for m in params.LINEAR_MODELS}
    return dict(speed_m_s=speed_m_s, omega_rad_s=omega_rad_s,
                gear_ratios=np.asarray(gear_ratios, float),
                wheel_radius_m=np.float64(gears.wheel_radius_m("city")), **radii,
                ellipse_speed_m_s=np.asarray(ev), ellipse_omega_rad_s=np.asarray(ew),
                reference=np.asarray(reference, float))


def cam_cases(model: str, duration_s: float = 2.0, samples: int = 801) -> dict[str, np.ndarray]:
    """Fig 3.30: CAM angle and rate in time (Sec 3.1.2.3) for the leg model at 2 pi and 4 pi
    rad/s (harmonics 1-15), the cadence-only torque and the roll torque alone at 2 pi rad/s.

    Keys: ``labels`` (n_case,), ``t_s`` (n_t,), ``angle_rad`` and ``rate_rad_s``
    (n_case, 2, n_t), coordinate roll then steer."""
    lm = linear.linear_model(model)
    legs_all = forcing(model, harmonics=tuple(range(1, 16, 2)))
    t = np.linspace(0.0, duration_s, samples)
    labels, angles, rates = [], [], []
    for w0 in (2 * np.pi, 4 * np.pi):
        a, r = momentum.cam_time(lm, legs_all, w0, t)
        labels.append(f"leg model, $\\omega$={w0 / np.pi:.0f}$\\pi$")
        angles.append(a)
        rates.append(r)
    for label, h in (("cadence only", select(legs_all, (1,))),
                     ("roll torque only", select(legs_all, (1,), steer=False))):
        a, r = momentum.cam_time(lm, h, 2 * np.pi, t)
        labels.append(f"{label}, $\\omega$=2$\\pi$")
        angles.append(a)
        rates.append(r)
    return dict(labels=np.array(labels), t_s=t, angle_rad=np.array(angles),
                rate_rad_s=np.array(rates))


def neglected_momenta(model: str, speed_m_s: np.ndarray, omega_rad_s: np.ndarray,
                      harmonics: Sequence[int], gear_ratios: Sequence[float]
                      ) -> dict[str, np.ndarray]:
    """Fig 3.31, F.1-F.3: the neglected momenta of Eq 3.29 as ratios of the leg momentum on the
    PS grid, with the wheel radius and the GR band of the model's bicycle."""
    ratios = momentum.neglected_momenta_ratios(
        linear.linear_model(model), forcing(model, harmonics=tuple(harmonics)),
        speed_m_s[:, None], omega_rad_s[None, :])
    return dict(speed_m_s=speed_m_s, omega_rad_s=omega_rad_s, ratios=ratios,
                wheel_radius_m=np.float64(gears.wheel_radius_m(linear.bicycle_of(model))),
                gear_band=np.array([min(gear_ratios), max(gear_ratios)], float))


def gear_section(model_name: str, torque, gear_ratio: float, wheel_radius: float,
                 speed_m_s: np.ndarray, omega_max_rad_s: float):
    """PS cadence amplitudes along one gear ratio (Fig 3.36): speeds, roll, steer."""
    w = gears.cadence_rad_s(gear_ratio, speed_m_s, wheel_radius)
    keep = w <= omega_max_rad_s
    r, s = particular_solution(linear.linear_model(model_name), speed_m_s[keep], w[keep], torque)
    k = int(np.nonzero(np.asarray(torque.n) == 1)[0][0])
    return speed_m_s[keep], np.abs(r[:, k]), np.abs(s[:, k])


def gear_sections(models: Sequence[str], speed_m_s: np.ndarray, gear_ratios: Sequence[float],
                  omega_max_rad_s: float, harmonics: Sequence[int]) -> dict[str, np.ndarray]:
    """Fig 3.36 / G.8: PS cadence amplitude along every gear ratio, per model.

    Keys ``<model>_<gr>_{speed_m_s,roll_rad,steer_rad}`` with ``gr`` formatted ``%g``, plus
    ``models`` and ``gear_ratios``."""
    out: dict[str, np.ndarray] = dict(models=np.array(list(models)),
                                      gear_ratios=np.asarray(gear_ratios, float))
    for m in models:
        torque = forcing(m, harmonics=tuple(harmonics))
        radius = gears.wheel_radius_m(linear.bicycle_of(m))
        for gr in gear_ratios:
            sv, r, s = gear_section(m, torque, gr, radius, speed_m_s, omega_max_rad_s)
            out[f"{m}_{gr:g}_speed_m_s"], out[f"{m}_{gr:g}_roll_rad"] = sv, r
            out[f"{m}_{gr:g}_steer_rad"] = s
    return out


def write_linear(outputs: Mapping[str, str], lin: Mapping) -> None:
    """Write every figure-data file of the linear part: ``outputs`` maps a name
    (``gear_grid``, ``cam_HS``, ``neglected_<model>``, ``gear_sections_models``,
    ``gear_sections_benchmark``) to its npz path; ``lin``: the :data:`LINEAR_KEYS` of the
    ``linear`` config section."""
    missing = [k for k in LINEAR_KEYS if k not in lin]
    if missing:
        raise KeyError(f"figure data need linear.{missing[0]} (config section 'linear')")
    v, w = ps_grid_of(lin)
    eigen_v = grid(lin["eigen_speed_step_m_s"], lin["eigen_speed_max_m_s"])[1:]
    h, grs = tuple(lin["harmonics"]), list(lin["gear_ratios"])
    for name, path in outputs.items():
        if name == "gear_grid":
            data = gear_grid(v, w, grs, lin["normal_cycling_speed_kmh"],
                             lin["normal_cycling_cadence_rpm"],
                             (lin["reference_speed_m_s"],
                              lin["reference_cadence_rpm"] * np.pi / 30))
        elif name.startswith("cam_"):
            data = cam_cases(name.removeprefix("cam_"))
        elif name.startswith("neglected_"):
            data = neglected_momenta(name.removeprefix("neglected_"), v, w, h, grs)
        elif name.startswith("gear_sections_"):
            models = (("benchmark",) if name == "gear_sections_benchmark" else params.MODELS)
            data = gear_sections(models, eigen_v, grs, lin["ps_omega_max_rad_s"], h)
        else:
            raise KeyError(f"unknown figure-data file {name!r}")
        np.savez_compressed(path, **data)


def validation(per_run, series: Mapping[str, np.ndarray], speed_m_s: np.ndarray,
               omega_rad_s: np.ndarray, examples_per_system: int,
               data_source: str | None = None, spectra=None) -> dict[str, np.ndarray]:
    """Figs 4.2-4.10: the particular-solution amplitude maps of the four systems on the given
    grid and the model's steady-state roll and steer phase-locked to the measured crank angle of
    each system's example runs (:func:`pedalrepro.validation.example_runs`), and the REAL run's
    panel: the first real public-subset run (:func:`pedalrepro.validation.real_example`).

    The example runs are taken from the rows of ``data_source`` only (the build's main source,
    ``source.json``; None: every row): real public-subset rows are never pooled into the
    synthetic or figshare figures.

    Keys: ``speed_m_s``, ``omega_rad_s``, ``<S>_roll_amp_rad``, ``<S>_steer_amp_rad``,
    ``<S>_run_ids`` and ``<S>_<k>_roll_rad``, ``<S>_<k>_steer_rad`` for example ``k``; when the
    build has a real run, ``real_run_id``, ``real_system``, ``real_speed_kmh``,
    ``real_cadence_rpm``, ``real_t_s``, ``real_roll_rad``, ``real_steer_rad``,
    ``real_model_roll_rad``, ``real_model_steer_rad``.

    ``spectra``: the measured closed-loop CF spectra's cadence amplitudes (the rule
    ``closed_loop_spectra``'s table, :func:`pedalrepro.mocap.spectra.cadence_table`; None or
    empty: the build has none). Their points join Figs 4.10 and 4.11 as the CF system's
    published measurements (Sec 4.2): keys ``spectra_speed_kmh``, ``spectra_cadence_rpm``,
    ``spectra_roll_measured_rad``, ``spectra_steer_measured_rad`` (the nearest bin, as the thesis
    reads a spectrum) and the open-loop CF model's particular-solution amplitudes at the same
    speed and cadence, ``spectra_roll_model_rad``, ``spectra_steer_model_rad``: the open-loop
    column of ``closed_loop_validation.csv`` (:func:`pedalrepro.rider.comparison.validation_table`
    solves the same model at the same points), absent when there are no spectra."""
    from . import validation as val

    v, w = np.asarray(speed_m_s, float), np.asarray(omega_rad_s, float)
    out: dict[str, np.ndarray] = dict(speed_m_s=v, omega_rad_s=w)
    main = per_run if data_source is None else per_run[per_run.data_source == data_source]
    for system in params.MODELS:
        out[f"{system}_roll_amp_rad"], out[f"{system}_steer_amp_rad"] = val.ps_map(system, v, w)
        ex = val.example_runs(main, system, examples_per_system)
        out[f"{system}_run_ids"] = ex.run_id.to_numpy(int)
        for k, row in ex.iterrows():
            rid = int(row.run_id)
            r, s = val.model_series(system, row.speed_kmh / 3.6, series[f"{rid}_crank_rad"],
                                    row.cadence_rpm * np.pi / 30)
            out[f"{system}_{k}_roll_rad"], out[f"{system}_{k}_steer_rad"] = r, s
    real = val.real_example(per_run, series)
    if real is not None:
        out.update(real)
    if spectra is not None and len(spectra):
        kmh = spectra.speed_kmh.to_numpy(float)
        rpm = spectra.cadence_rpm.to_numpy(float)
        roll, steer = val.model_amplitudes("CF", kmh / 3.6, rpm * np.pi / 30)
        out.update(spectra_speed_kmh=kmh, spectra_cadence_rpm=rpm,
                   spectra_roll_measured_rad=spectra.roll_nearest_rad.to_numpy(float),
                   spectra_steer_measured_rad=spectra.steer_nearest_rad.to_numpy(float),
                   spectra_roll_model_rad=roll, spectra_steer_model_rad=steer)
    return out


def write_validation(per_run_csv: str, series_npz: str, out_npz: str, lin: Mapping,
                     examples_per_system: int, source_json: str | None = None,
                     spectra_csv: str | None = None) -> None:
    """Read the per-run table and the measured series, write :func:`validation`'s arrays on
    the PS grid of ``lin`` from one step (no zero speed or cadence); ``source_json``: the
    extraction's ``source.json`` (its ``data_source`` picks the example runs); ``spectra_csv``:
    the measured CF spectra's cadence table (header only when the build has none)."""
    import json

    import pandas as pd

    ds = None if source_json is None else json.loads(open(source_json).read())["data_source"]
    spectra = None if spectra_csv is None else pd.read_csv(spectra_csv)
    v, w = (g[1:] for g in ps_grid_of(lin))
    with np.load(series_npz, allow_pickle=False) as series:
        data = validation(pd.read_csv(per_run_csv), series, v, w, examples_per_system, ds,
                          spectra)
    np.savez_compressed(out_npz, **data)
