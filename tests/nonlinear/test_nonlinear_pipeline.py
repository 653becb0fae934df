"""The non-linear sweep functions and figures on tiny inputs (numbers checked, not just drawn)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from pedalrepro import response
from pedalrepro.figures import nonlinear as fig_nl
from pedalrepro.nonlinear import sweep


def test_grid_runs_zero_cadence_and_nt_np_agree_when_stable():
    """Zero cadence: no forcing, amplitude 0; at 6 m/s (HR self-stable) NT and NP agree to 5 %
    (thesis evaluation point 1a, 0.1-5 %) and the amplitude is in the thesis's 0.01-0.02 rad
    order of magnitude at normal cycling (Sec 3.3)."""
    settings = sweep.RunSettings(40.0, 50.0, 1e-6, 1e-8, 1.0)
    h = response.forcing("HR", None)
    nt = sweep.grid_runs("NT", "HR", [6.0], [0.0, 6.0], h, settings)
    npp = sweep.grid_runs("NP", "HR", [6.0], [0.0, 6.0], h, settings)
    assert nt["roll_amp_rad"][0, 0] == 0.0 and not nt["fell"][0, 0]
    assert not nt["fell"][0, 1] and not npp["fell"][0, 1]
    rd = abs(nt["roll_amp_rad"][0, 1] - npp["roll_amp_rad"][0, 1]) / npp["roll_amp_rad"][0, 1]
    assert rd < 0.05
    assert 1e-3 < npp["roll_amp_rad"][0, 1] < 0.1


def test_unknown_method_is_an_error():
    settings = sweep.RunSettings(1.0, 10.0, 1e-6, 1e-8, 1.0)
    with pytest.raises(ValueError, match="unknown non-linear method"):
        sweep.run("XX", "HR", 5.0, 6.0, None, settings)


def test_figures_draw_the_given_arrays():
    v, w = np.arange(0.0, 10.1, 2.0), np.arange(0.0, 12.1, 4.0)
    maps = {"speed_m_s": v, "omega_rad_s": w, "models": np.array(["HR"]),
            "HR_roll_ps_np": np.full((v.size, w.size), 2.0),
            "HR_steer_ps_np": np.full((v.size, w.size), 3.0),
            "HR_stable": (v > 4) & (v < 8)}
    fig = fig_nl.fig_3_34(maps)
    cs = fig.axes[0].collections[0]  # roll RD 2 %: only the 1-2.5 % band is filled
    filled = [i for i, p in enumerate(cs.get_paths()) if len(p.vertices)]
    assert [(cs.levels[i], cs.levels[i + 1]) for i in filled] == [(1.0, 2.5)]
    table = pd.DataFrame({"model": ["HR", "HR"], "matrix": ["M", "K0"], "i": [0, 0],
                          "j": [0, 1], "rel_diff": [0.1, 0.2]})
    fig2 = fig_nl.nonlinear_linearisation_vs_appendix_b(table)
    assert np.allclose(fig2.axes[0].lines[0].get_ydata(), [10.0, 20.0])
