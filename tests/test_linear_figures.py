"""Figures of the linear part: groups, inputs, methods present/missing (CONTRIBUTING.md)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pedalrepro import evaluation, linear, response  # noqa: E402
from pedalrepro.figures import linear as figlin  # noqa: E402


def test_every_figure_in_exactly_one_group():
    groups = [f for g in figlin.FIGURE_GROUPS for f in figlin.figure_group(g)]
    assert sorted(groups) == sorted(figlin.FIGURE_SPECS)
    assert len(groups) == len(set(groups)) == 48
    with pytest.raises(ValueError, match="unknown figure group"):
        figlin.figure_group("all")


def test_inputs_follow_time_methods():
    two = figlin.inputs_of("fig_3_10", "R", ["LA", "LN"])
    four = figlin.inputs_of("fig_3_10", "R", ["LA", "LN", "NT", "NP"])
    assert "R/intermediate/time/NP_HS.npz" in four and "R/intermediate/time/NP_HS.npz" not in two
    assert "R/intermediate/ps/HS.npz" in two and "R/intermediate/eigen/HS.npz" in two


@pytest.fixture()
def results(tmp_path, monkeypatch):
    """Tiny but physical results of model HR in a temporary results folder."""
    monkeypatch.setenv("PEDALREPRO_RESULTS", str(tmp_path))
    model = linear.linear_model("HR")
    h = response.forcing("HR")
    v, w = np.linspace(0, 10, 11), np.linspace(0, 4 * np.pi, 9)
    r, s = response.particular_solution(model, v[:, None], w[None, :], h)
    (tmp_path / "intermediate" / "ps").mkdir(parents=True)
    np.savez(tmp_path / "intermediate" / "ps" / "HR.npz", speed_m_s=v, omega_rad_s=w, n=h.n,
             roll=r, steer=s, roll_amp_rad=np.abs(r[..., 0]), steer_amp_rad=np.abs(s[..., 0]),
             cam_roll_rad=0.01, cam_steer_rad=0.02)
    speeds = np.arange(0, 10.001, 0.05)
    sweep = linear.eigen_sweep(model, speeds)
    (tmp_path / "intermediate" / "eigen").mkdir()
    np.savez(tmp_path / "intermediate" / "eigen" / "HR.npz", speed_m_s=speeds,
             eigenvalues=sweep.eigenvalues, names=np.array(sweep.names),
             weave_frequency_rad_s=sweep.weave_frequency_rad_s(),
             stable_ranges_m_s=np.array(linear.stable_ranges(model, speeds)).reshape(-1, 2))
    pts = evaluation.example_points("HR")
    t = np.arange(0, 5.0, 0.05)
    rolls = [response.analytic_time_solution(model, np.array([a]), np.array([b]), h,
                                             t).roll_rad[0, 0]
             for a, b in zip(pts.speed_m_s, pts.omega_rad_s, strict=True)]
    (tmp_path / "intermediate" / "time").mkdir()
    np.savez(tmp_path / "intermediate" / "time" / "LA_HR.npz", example_speed_m_s=pts.speed_m_s,
             example_omega_rad_s=pts.omega_rad_s, example_t_s=t,
             example_roll_rad=np.stack(rolls), example_steer_rad=np.stack(rolls))
    return tmp_path, np.stack(rolls)


def _texts(fig):
    return " ".join(t.get_text() for t in fig.texts)


def test_time_figure_draws_present_methods_and_names_missing(results):
    tmp, rolls = results
    fig = figlin.draw("fig_3_14", {})  # HR roll
    assert "NT, NP" in _texts(fig) and "LN" in _texts(fig)
    la_lines = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_label() == "LA"]
    assert len(la_lines) == 6
    np.testing.assert_allclose(la_lines[2].get_ydata(), rolls[2])
    # an extra method file (here a copy standing in for NT) is drawn and no longer "missing"
    import shutil

    shutil.copy(tmp / "intermediate" / "time" / "LA_HR.npz",
                tmp / "intermediate" / "time" / "NT_HR.npz")
    fig = figlin.draw("fig_3_14", {})
    assert "NT" not in _texts(fig).split("here:")[1].split("(")[0]
    assert sum(ln.get_label() == "NT" for ax in fig.axes for ln in ax.get_lines()) == 6


def test_draw_rejects_unknown_id():
    with pytest.raises(KeyError, match="not a figure of the linear part"):
        figlin.draw("fig_9_9", {})
