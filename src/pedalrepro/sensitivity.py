"""Inputs chosen with a published number in view, moved: how much of the agreement survives.

Three inputs of this project were chosen partly because the thesis's numbers fit them
(``data/published/claims.yaml``, key ``chosen_input``):

``hip_width_m``
    ``l_hh = 0.26 m`` (``data/parameters/legs.yaml``): BicycleParameters' value, and also the one
    of 0.25/0.26/0.27 m for which most Table 4.1 model numbers round to the printed ones. The
    pedalling torques scale with ``m_L l_hh`` (Eq 2.22-2.23), so the Table 4.1 model columns move
    by the same factor. Moved by +-2 % (:data:`HIP_WIDTH_FACTORS`).
``cr_cadence_order``
    Table 4.1's header lists the CR cadences 70, 64, 77 rpm at 20, 25, 30 km/h, Sec 4.1.1's text
    77, 64, 70 rpm; the project follows the header because the model columns fit it. Moved: the
    text's order (``data/parameters/validation_runs.yaml``, ``cr_cadence_rpm_text_order``).
``example_points``
    The six numbered example points (Fig 3.10-3.29) were placed on the time grid's diagonal to fit
    the text of Sec 3.2.1 (:mod:`pedalrepro.evaluation`); the HS weave frequency of Fig 3.18 is
    read at point 3. Moved: one grid step along the diagonal either way
    (:data:`EXAMPLE_POINT_SHIFTS`).

A report row that passes with the chosen input but fails with a moved one is ``calibrated``
(:mod:`pedalrepro.report.statuses`): its agreement rests on the choice.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np
import pandas as pd

from . import disturbance, legs, linear, response

__all__ = [
    "HIP_WIDTH_FACTORS", "EXAMPLE_POINT_SHIFTS", "Variant", "table_4_1_variants", "table_4_1_model",
    "weave_frequency_at_example_point", "summary",
]

#: Hip width factors of the sensitivity runs (+-2 %).
HIP_WIDTH_FACTORS: tuple[float, ...] = (0.98, 1.02)
#: Shifts of the example points along the time grid's diagonal (grid steps).
EXAMPLE_POINT_SHIFTS: tuple[int, ...] = (-1, 1)


@dataclass(frozen=True)
class Variant:
    """One moved input: its name, the input it moves, and how.

    ``hip_width_factor`` scales ``l_hh``; ``cr_cadences`` (km/h -> rpm) replaces the CR runs'
    cadences."""

    name: str
    chosen_input: str
    description: str
    hip_width_factor: float = 1.0
    cr_cadences: Mapping[float, float] | None = None


def table_4_1_variants(cr_text_order: Mapping[float, float]) -> tuple[Variant, ...]:
    """The moved inputs of the Table 4.1 model columns: hip width -2 % and +2 %, and the CR
    cadences in the order of the text (``cr_text_order``: speed km/h -> cadence rpm)."""
    hip = tuple(Variant(f"hip_width_{'+' if f > 1 else '-'}{abs(f - 1) * 100:.0f}%",
                        "hip_width_m", f"hip width x {f:g}", hip_width_factor=f)
                for f in HIP_WIDTH_FACTORS)
    order = Variant("cr_cadence_text_order", "cr_cadence_order",
                    "CR cadences in the order of Sec 4.1.1 ("
                    + ", ".join(f"{c:g}" for c in cr_text_order.values()) + " rpm)",
                    cr_cadences={float(k): float(v) for k, v in cr_text_order.items()})
    return (*hip, order)


def table_4_1_model(runs: Sequence[Mapping[str, float | str]], harmonics: Sequence[int],
                    variant: Variant | None = None) -> pd.DataFrame:
    """Table 4.1's model columns: the particular solution (Eq 3.14-3.15) at each run's speed and
    cadence, cadence-frequency amplitudes of roll and steer (rad).

    Parameters
    ----------
    runs
        Mappings with ``system`` (``"HR"``/``"CR"``), ``speed_kmh``, ``cadence_rpm``.
    harmonics
        The harmonics of the pedalling torque (config ``linear.harmonics``).
    variant
        A moved input (:func:`table_4_1_variants`); None for the project's inputs.

    Returns
    -------
    pandas.DataFrame
        Columns ``system, speed_kmh, cadence_rpm, roll_model_rad, steer_model_rad``.
    """
    rows = []
    for run in runs:
        system = str(run["system"])
        speed_kmh, cadence_rpm = float(run["speed_kmh"]), float(run["cadence_rpm"])
        if variant is not None and variant.cr_cadences and system == "CR":
            cadence_rpm = float(variant.cr_cadences.get(speed_kmh, cadence_rpm))
        model = linear.linear_model(system)
        bicycle = linear.bicycle_of(system)
        geometry = legs.leg_geometry(bicycle)
        if variant is not None and variant.hip_width_factor != 1.0:
            geometry = replace(geometry,
                               hip_width_m=geometry.hip_width_m * variant.hip_width_factor)
        h = disturbance.torque_harmonics(bicycle, harmonics=tuple(harmonics), geometry=geometry)
        k = int(np.nonzero(h.n == 1)[0][0])
        r, s = response.particular_solution(model, speed_kmh / 3.6, cadence_rpm * np.pi / 30, h)
        rows.append({"system": system, "speed_kmh": speed_kmh, "cadence_rpm": cadence_rpm,
                     "roll_model_rad": abs(r[k]), "steer_model_rad": abs(s[k])})
    return pd.DataFrame(rows)


def weave_frequency_at_example_point(model: str, shift: int = 0) -> tuple[float, float]:
    """The largest imaginary part of the eigenvalues (rad/s) at example point 3's speed moved by
    ``shift`` diagonal grid steps (:mod:`pedalrepro.evaluation`), and that speed (m/s)."""
    from . import evaluation

    pts = evaluation.example_points(model)
    speed = pts.series_speed_m_s + shift * evaluation.DIAGONAL_SPEED_STEP_M_S
    e = linear.eigenvalues(linear.linear_model(model), speed)
    return float(np.abs(np.imag(e)).max()), float(speed)


def summary(rows: Sequence[Mapping[str, object]]) -> pd.DataFrame:
    """Per moved input: how many of the rows that depend on it hold with it moved.

    ``rows``: mappings with ``chosen_input``, ``variant``, ``description``, ``id`` and a bool
    ``holds`` (one per dependent report row and variant). Returns columns ``chosen_input,
    variant, description, rows, rows_holding``."""
    df = pd.DataFrame(rows, columns=["chosen_input", "variant", "description", "id", "holds"])
    out = (df.groupby(["chosen_input", "variant", "description"], sort=False)
           .agg(rows=("id", "size"), rows_holding=("holds", "sum")).reset_index())
    out["rows_holding"] = out["rows_holding"].astype(int)
    return out
