"""Periodic-orbit figures (issue 24): in the figure registry like every other figure, and the
maps' colour bars beside their own rows (before, the amplitude bar of both methods' rows and
the RD bar of the RD rows were both placed on the right over overlapping row spans, drawn on top
of each other)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pedalrepro.figures import periodic as figp  # noqa: E402
from pedalrepro.figures import registry  # noqa: E402


def _map(rng, nv=6, nw=5):
    v, w = np.linspace(0, 10, nv), np.linspace(0, 12, nw)
    amp = rng.uniform(1e-3, 1e-1, (nv, nw))
    return {"speed_m_s": v, "omega_rad_s": w, "stable": rng.uniform(size=(nv, nw)) > 0.5,
            "converged": np.ones((nv, nw), bool), "roll_amp_rad": amp, "steer_amp_rad": amp,
            "ps_roll_amp_rad": amp * 1.1, "ps_steer_amp_rad": amp * 0.9}


def _sim(rng, nv=6, nw=5):
    amp = rng.uniform(1e-3, 1e-1, (nv, nw))
    return {"roll_amp_rad": amp, "steer_amp_rad": amp, "fell": rng.uniform(size=(nv, nw)) > 0.8}


def _overlap(a, b) -> bool:
    return a.x0 < b.x1 and b.x0 < a.x1 and a.y0 < b.y1 and b.y0 < a.y1


def test_colour_bars_do_not_overlap():
    rng = np.random.default_rng(0)
    fig = figp.figs_orbit_maps({m: _map(rng) for m in ("NT", "NP")}, "HR", ("NT", "NP"),
                              sims={m: _sim(rng) for m in ("NT", "NP")})
    fig.canvas.draw()
    bars = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
    assert len(bars) == 4  # amplitude and RD for each method
    boxes = [ax.get_window_extent() for ax in bars]
    for i in range(len(boxes)):
        for j in range(i + 1, len(boxes)):
            assert not _overlap(boxes[i], boxes[j]), (i, j)
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    for bar in boxes:  # and no bar covers a panel
        assert not any(_overlap(bar, p.get_window_extent()) for p in panels)
    assert fig.get_size_inches()[0] <= 7.0


def test_periodic_figures_are_registered():
    ids = registry.ids(part="periodic")
    assert ids == sorted(["periodic_continuation", "periodic_fine_maps"]
                         + [f"periodic_maps_{m}" for m in registry.MODELS4])
    assert registry.groups().count("periodic") == 1
    spec = registry.spec("periodic_maps_HR")
    assert spec.inputs["orbits.NT"] == "intermediate/periodic/thesis_NT_HR.npz"
    assert spec.inputs["sims.NP"] == "intermediate/time/NP_HR.npz"
    for fid in ids:
        registry.spec(fid).callable()


def test_orbit_map_figure_without_simulations_says_so():
    rng = np.random.default_rng(1)
    fig = figp.figs_orbit_maps({"NT": _map(rng)}, "HR", ("NT",))
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert texts.count("no simulation") == 4  # simulation and RD panels, roll and steer


@pytest.mark.parametrize("fid", ["periodic_maps_HR", "periodic_continuation"])
def test_beyond_thesis_label(fid):
    from pedalrepro import figures

    assert figures.thesis_label(fid) == figures.BEYOND_THESIS
    html = figures.figure_html(fid, b"\x89PNG", caption="c", link=True)
    assert "Beyond the thesis" in html and f"../figures/{fid}.pdf" in html
    with pytest.raises(ValueError, match="not fig_"):
        figures.thesis_label("no_such_figure")


def test_thesis_map_cut_out_of_the_finer_grid(tmp_path):
    """write_submap: the thesis-grid map (0.4 m/s, 0.5 rad/s) taken from the finer grid (0.2 m/s,
    0.25 rad/s) holds exactly the finer map's values at the thesis points, on the thesis grid as
    response.grid makes it (bit for bit: the simulation sweeps' grid); a grid that does not nest
    is refused naming the file."""
    from pedalrepro import periodic, response

    fine_grid = dict(speed_step_m_s=0.2, speed_max_m_s=10.0, omega_step_rad_s=0.25,
                     omega_max_rad_s=4 * np.pi)
    thesis_grid = dict(speed_step_m_s=0.4, speed_max_m_s=10.0, omega_step_rad_s=0.5,
                       omega_max_rad_s=4 * np.pi)
    assert periodic.nested(thesis_grid, fine_grid)
    assert not periodic.nested(dict(thesis_grid, speed_step_m_s=0.3), fine_grid)
    v, w = response.grid(0.2, 10.0), response.grid(0.25, 4 * np.pi)
    vv, ww = np.meshgrid(v, w, indexing="ij")
    fine = {"speed_m_s": v, "omega_rad_s": w, "model": "HR", "method": "NT", "rtol": 1e-9,
            "elapsed_s": 99.0, "roll_amp_rad": vv + 100 * ww, "orbit_time_s": np.ones(vv.shape),
            "multipliers": (vv + 1j * ww)[..., None] * np.ones(4)}
    path = tmp_path / "fine.npz"
    np.savez(path, **fine)
    out = periodic.write_submap(tmp_path / "thesis.npz", path, **thesis_grid)
    tv, tw = response.grid(0.4, 10.0), response.grid(0.5, 4 * np.pi)
    assert np.array_equal(out["speed_m_s"], tv) and np.array_equal(out["omega_rad_s"], tw)
    tvv, tww = np.meshgrid(tv, tw, indexing="ij")
    np.testing.assert_allclose(out["roll_amp_rad"], tvv + 100 * tww, rtol=0, atol=1e-12)
    assert out["multipliers"].shape == (tv.size, tw.size, 4)
    assert out["elapsed_s"] == tv.size * tw.size and str(out["model"]) == "HR"
    with np.load(tmp_path / "thesis.npz") as d:
        assert np.array_equal(d["roll_amp_rad"], out["roll_amp_rad"])
    with pytest.raises(ValueError, match="fine.npz"):
        periodic.write_submap(tmp_path / "x.npz", path, **dict(thesis_grid, speed_step_m_s=0.3))
