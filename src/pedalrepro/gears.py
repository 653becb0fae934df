"""Gear ratios and the 'normal cycling' region in the speed-cadence plane (Sec 3.1.3.2, Fig 3.8).

A gear ratio GR (front teeth / rear teeth) couples cadence and speed through the rear wheel:
``v = GR * omega * r_R``. The thesis's working range is GR 1 to 4; single-gear bicycles sit at
GR 2 to 2.5.
"""

from __future__ import annotations

import numpy as np

from . import params

__all__ = [
    "wheel_radius_m", "speed_m_s", "cadence_rad_s", "gear_ratio", "normal_cycling_ellipse",
    "inside_ellipse",
]


def wheel_radius_m(bicycle: str) -> float:
    """Rear wheel radius ``rR`` of ``"hybrid"`` (Stratos), ``"city"`` (Browser), ``"benchmark"``."""
    if bicycle == "hybrid":
        return params.stratos_geometry()["rR"]
    if bicycle == "city":
        return params.benchmark_parameters("browser")["rR"]
    if bicycle == "benchmark":
        return params.benchmark_parameters("benchmark")["rR"]
    raise ValueError(f"unknown bicycle {bicycle!r}: expected 'hybrid', 'city' or 'benchmark'")


def speed_m_s(gear_ratio: float, omega_rad_s, wheel_radius: float) -> np.ndarray:
    """Forward speed at cadence ``omega_rad_s`` in gear ``gear_ratio`` (no slip)."""
    return gear_ratio * np.asarray(omega_rad_s, float) * wheel_radius


def cadence_rad_s(gear_ratio: float, speed, wheel_radius: float) -> np.ndarray:
    """Cadence at ``speed`` (m/s) in gear ``gear_ratio``."""
    return np.asarray(speed, float) / (gear_ratio * wheel_radius)


def gear_ratio(speed, omega_rad_s, wheel_radius: float) -> np.ndarray:
    """Gear ratio of a speed-cadence combination (inf at zero cadence)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(speed, float) / (np.asarray(omega_rad_s, float) * wheel_radius)


def normal_cycling_ellipse(speed_kmh: tuple[float, float], cadence_rpm: tuple[float, float],
                           points: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """The 'normal cycling' ellipse (Fig 3.8): inscribed in the given speed and cadence ranges.

    The thesis draws it by hand ("a rough indication"); Sec 3.1.3.2 gives the ranges it is built
    from (config ``linear.normal_cycling_*``).

    Returns
    -------
    speed_m_s, omega_rad_s
        A closed curve.
    """
    th = np.linspace(0, 2 * np.pi, points)
    v0, v1 = np.asarray(speed_kmh, float) / 3.6
    w0, w1 = np.asarray(cadence_rpm, float) * np.pi / 30
    return (0.5 * (v0 + v1) + 0.5 * (v1 - v0) * np.cos(th),
            0.5 * (w0 + w1) + 0.5 * (w1 - w0) * np.sin(th))


def inside_ellipse(speed, omega_rad_s, speed_kmh, cadence_rpm) -> np.ndarray:
    """Boolean mask of the points inside the normal-cycling ellipse."""
    v0, v1 = np.asarray(speed_kmh, float) / 3.6
    w0, w1 = np.asarray(cadence_rpm, float) * np.pi / 30
    x = (np.asarray(speed, float) - 0.5 * (v0 + v1)) / (0.5 * (v1 - v0))
    y = (np.asarray(omega_rad_s, float) - 0.5 * (w0 + w1)) / (0.5 * (w1 - w0))
    return x**2 + y**2 <= 1.0
