"""Figures of the linear part drawn from files through the registry: methods present/missing,
the time panels' zoom (CONTRIBUTING.md, "Figures in the book"; issue 13)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pedalrepro import evaluation, figures, linear, response, timesolution  # noqa: E402
from pedalrepro.figures import linear as figlin  # noqa: E402
from pedalrepro.figures import registry  # noqa: E402


def test_inputs_follow_time_methods():
    two = registry.inputs("fig_3_10", "R", ["LA", "LN"])
    four = registry.inputs("fig_3_10", "R", ["LA", "LN", "NT", "NP"])
    assert sorted(set(four) - set(two)) == ["R/intermediate/time/NP_HS.npz",
                                            "R/intermediate/time/NT_HS.npz"]
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
    series_v = np.full(len(pts.series_omega_rad_s), pts.series_speed_m_s)
    for method in ("LA", "LN"):  # every key a time-solution file must have (timesolution)
        timesolution.write(
            tmp_path / "intermediate" / "time" / f"{method}_HR.npz",
            dict(speed_m_s=v, omega_rad_s=w, roll_amp_rad=np.abs(r[..., 0]),
                 steer_amp_rad=np.abs(s[..., 0]), t_end_s=np.full(r.shape[:2], t[-1]),
                 fell=np.zeros(r.shape[:2], bool), method=method, model="HR", harmonics=h.n,
                 sample_rate_hz=20.0, example_speed_m_s=pts.speed_m_s,
                 example_omega_rad_s=pts.omega_rad_s, example_t_s=t,
                 example_roll_rad=np.stack(rolls), example_steer_rad=np.stack(rolls),
                 series_speed_m_s=series_v, series_omega_rad_s=pts.series_omega_rad_s,
                 series_roll_rad=np.stack(rolls), series_steer_rad=np.stack(rolls)))
    return tmp_path, np.stack(rolls)


def _texts(fig):
    return " ".join(t.get_text() for t in fig.texts)


def _zoom_axes(fig):
    """The six zoom panels (titled "<k>: v = ...") of a time figure, in order."""
    import re

    return [ax for ax in fig.axes if re.match(r"\d+: v = .*zoom", ax.get_title(loc="left"))]


def test_time_figure_draws_present_methods_and_names_missing(results):
    tmp, rolls = results
    (tmp / "intermediate" / "time" / "LN_HR.npz").unlink(missing_ok=True)
    with pytest.raises(FileNotFoundError, match="LN_HR.npz"):  # LN is required, NT/NP optional
        registry.draw("fig_3_14", tmp)
    import shutil

    shutil.copy(tmp / "intermediate" / "time" / "LA_HR.npz",
                tmp / "intermediate" / "time" / "LN_HR.npz")
    fig = registry.draw("fig_3_14", tmp)  # HR roll
    assert "NT, NP" in _texts(fig)
    zooms = _zoom_axes(fig)
    assert len(zooms) == 6
    # each point: the whole run (small) and the zoom draw LA, LN and the particular solution
    la = [ln for ax in fig.axes for ln in ax.get_lines() if ln.get_label() == "LA"]
    assert len(la) == 12
    assert {ln.get_color() for ln in la} == {figures.palette.METHOD_STYLE["LA"]["color"]}
    np.testing.assert_allclose(la[4].get_ydata(), rolls[2])  # point 3, whole run
    # the zoom ends at the end of the run (or at the fall: NaN after it) and shows the last 5
    # cadence periods (4-15 s)
    t = np.arange(0, 5.0, 0.05)
    for k, ax in enumerate(zooms):
        lo, hi = ax.get_xlim()
        w = evaluation.example_points("HR").omega_rad_s[k]
        t_end = t[np.isfinite(rolls[k])][-1]
        assert hi == pytest.approx(t_end)
        assert hi - lo == pytest.approx(min(max(5 * 2 * np.pi / w, 4.0), 15.0, t_end), abs=1e-9)
    # an extra method file (here a copy standing in for NT) is drawn and no longer "missing"
    shutil.copy(tmp / "intermediate" / "time" / "LA_HR.npz",
                tmp / "intermediate" / "time" / "NT_HR.npz")
    fig = registry.draw("fig_3_14", tmp)
    assert "NT" not in _texts(fig).split("here:")[1].split("(")[0]
    assert sum(ln.get_label() == "NT" for ax in fig.axes for ln in ax.get_lines()) == 12
    assert registry.completeness("fig_3_14", tmp)[0] == "missing"  # no PNG written yet
    figures.save(fig, tmp / "figures" / "fig_3_14.png")
    assert registry.completeness("fig_3_14", tmp) == ("partial", ["NP"])


def test_zoom_window_ends_at_the_first_fall():
    t = np.linspace(0.0, 20.0, 2001)
    a = np.sin(t)
    b = np.where(t <= 7.5, np.sin(t), np.nan)  # this method fell at 7.5 s
    lo, hi = figlin.zoom_window(t, [a, b], omega_rad_s=2 * np.pi)  # 5 periods = 5 s
    assert (lo, hi) == pytest.approx((2.5, 7.5))
    lo, hi = figlin.zoom_window(t, [a], omega_rad_s=0.5)  # 5 periods = 63 s -> 15 s at most
    assert (lo, hi) == pytest.approx((5.0, 20.0))


def test_draw_rejects_unknown_id():
    with pytest.raises(KeyError, match="not a registered figure"):
        registry.draw("fig_9_9")
