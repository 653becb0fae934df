"""One figure convention (issue 10 part 4) and figures drawn for the page (issue 13 parts 1-3):
the registry covers every thesis figure id, the results layout is defined once, figures are at
most the book's content width with text of at least 8 pt, saved as PNG + PDF, and the maps use
the thesis's axes, RD levels and stable-range lines."""

from __future__ import annotations

import struct
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pedalrepro import figures, paths, report  # noqa: E402
from pedalrepro.figures import linear as figlin  # noqa: E402
from pedalrepro.figures import nonlinear as fig_nl  # noqa: E402
from pedalrepro.figures import palette, registry  # noqa: E402

#: Registered figures that are not thesis ids (checks shown beside a thesis figure).
EXTRA = {"nonlinear_linearisation_vs_appendix_b", "real_run_panel", "periodic_continuation",
         "periodic_fine_maps", *(f"periodic_maps_{m}" for m in registry.MODELS4),
         *(f"nonlinear_examples_{m}" for m in registry.MODELS4)}


def test_registry_covers_every_thesis_figure_once():
    thesis = set(report.figure_ids()["id"])
    figs = {i for i in thesis if i.startswith("fig_")}
    assert figs == set(registry.FIGURES) - EXTRA
    assert set(registry.FIGURES) - thesis == EXTRA
    # every id in exactly one part and one job group
    assert {s.part for s in registry.FIGURES.values()} == set(registry.PARTS)
    assert sum(len(registry.ids(group=g)) for g in registry.groups()) == len(registry.FIGURES)


def test_every_figure_id_is_written_out_in_the_registry():
    """Grepping a figure id finds where it is registered: every id is a quoted literal in
    registry.py (no id is computed, as ``f"fig_3_{10 + k}"`` once was)."""
    import ast
    import re

    source = Path(registry.__file__).read_text()
    literal = {n.value for n in ast.walk(ast.parse(source))
               if isinstance(n, ast.Constant) and isinstance(n.value, str)}
    assert not set(registry.FIGURES) - literal, sorted(set(registry.FIGURES) - literal)
    assert not re.search(r'f"(fig|table|periodic_maps|nonlinear_examples)_\{', source)


def test_drawing_modules_compute_no_sweep():
    """CONTRIBUTING: drawing reads files and never computes a sweep. The import closure of every
    drawing module (the registry's and the closed loop's) holds no module that solves or
    simulates: the figures get those results as arrays from the rules' files."""
    from pedalrepro import dependencies

    solvers = ("response.py", "linear.py", "evaluation.py", "disturbance.py", "legs.py",
               "figdata.py", "integrator/", "nonlinear/", "periodic/", "mocap/", "rider/")
    package = dependencies.PACKAGE_DIR
    for module in (*registry.MODULES, "closed_loop"):
        closure = dependencies.import_closure([package / "figures" / f"{module}.py"])
        rel = [str(p.relative_to(package)) for p in closure]
        assert f"figures/{module}.py" in rel
        assert not [r for r in rel if r.startswith(solvers)], (module, rel)


def test_every_input_is_under_the_results_layout():
    dirs = set(paths.LAYOUT.values())
    for fid, spec in registry.FIGURES.items():
        for rel in spec.inputs.values():
            assert rel.split("/")[0] in dirs, (fid, rel)
        spec.callable()  # the drawing function exists


def test_results_layout_is_defined_once():
    assert paths.table("table_d_1", root="R") == Path("R/tables/table_d_1.csv")
    assert paths.figure("fig_2_3", root="R", fmt="pdf") == Path("R/figures/fig_2_3.pdf")
    assert paths.interm("eigen/HS.npz", root="R") == Path("R/intermediate/eigen/HS.npz")
    assert paths.log("book", root="R") == Path("R/logs/book.log")
    assert paths.benchmark("linear_ps", root="R") == Path("R/benchmarks/linear_ps.tsv")
    with pytest.raises(ValueError, match="figure format"):
        paths.figure("fig_2_3", fmt="jpg")
    common = (paths.ROOT / "rules" / "common.smk").read_text()
    for kind in paths.LAYOUT.values():  # the Snakemake helpers call pedalrepro.paths
        assert "{R}/" + kind + "/" not in common
    for helper in ("table", "figure", "interm", "log", "benchmark"):
        assert f"_paths.{helper}(" in common


def test_save_refuses_small_text_and_wide_figures(tmp_path):
    fig, ax = plt.subplots(figsize=(7.0, 3.0))
    ax.set_title("fine", fontsize=8)
    ax.text(0.5, 0.5, "too small", fontsize=7)
    with pytest.raises(ValueError, match="below 8.0 pt"):
        figures.save(fig, tmp_path / "a.png")
    fig, _ = plt.subplots(figsize=(9.0, 3.0))
    with pytest.raises(ValueError, match="9.00 in wide"):
        figures.save(fig, tmp_path / "b.png")


def test_save_writes_png_and_pdf_at_the_content_width(tmp_path):
    with figures.style():
        fig, ax = plt.subplots(figsize=(7.0, 3.0), layout="constrained")
        ax.plot([0, 1], [0, 1])
        ax.set_xlabel("x")
    out = figures.save(fig, tmp_path / "c.png")
    width = struct.unpack(">I", out.read_bytes()[16:20])[0]
    with figures.style():
        dpi = matplotlib.rcParams["savefig.dpi"]
    # bbox tight trims the margin (pad 0.04 in): 90-102 % of 7 in at the style's dpi
    assert 0.9 * 7 * dpi <= width <= 1.02 * 7 * dpi
    # displayed at the 672 px content width, 8 pt text is 8 pt (10.7 px) or larger
    assert 672 / width * 8 * dpi / 72 >= 8 * 96 / 72 - 1e-9
    assert out.with_suffix(".pdf").read_bytes()[:5] == b"%PDF-"


def test_book_html_links_full_size_png_and_pdf():
    html = figures.figure_html("fig_3_10", b"\x89PNG", caption="c", link=True)
    assert '<a class="pedalrepro-full-size" href="../figures/fig_3_10.png"' in html
    assert 'href="../figures/fig_3_10.pdf"' in html
    assert "href" not in figures.figure_html("fig_3_10", b"\x89PNG", caption="c")


def _rd_maps():
    v, w = np.arange(0.0, 10.1, 2.0), np.arange(0.0, 12.1, 4.0)
    return v, w, {"speed_m_s": v, "omega_rad_s": w, "models": np.array(["HR"]),
                  "HR_roll_ps_np": np.full((v.size, w.size), 2.0),
                  "HR_steer_ps_np": np.full((v.size, w.size), 30.0),
                  "HR_stable": (v > 3) & (v < 7)}


def test_fig_3_34_speed_on_x_cadence_on_y_levels_and_lines():
    v, w, maps = _rd_maps()
    eig = {"HR": {"speed_m_s": np.array([0.0, 10.0]),
                  "weave_frequency_rad_s": np.array([5.0, 7.0])}}
    with figures.style():
        fig = fig_nl.fig_3_34(maps, eig)
    ax = fig.axes[0]
    assert ax.get_xlim() == (0.0, 10.0) and ax.get_ylim() == (0.0, 12.0)
    assert "speed" in fig.axes[0].get_xlabel() or "speed" in fig.axes[1].get_xlabel()
    # stable speeds 4 and 6 on a 2 m/s grid: lines half a step outside, at 3 and 7 m/s
    vlines = sorted(ln.get_xdata()[0] for ln in ax.get_lines() if len(set(ln.get_xdata())) == 1)
    assert vlines == [3.0, 7.0]
    weave = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    np.testing.assert_allclose(weave[0].get_ydata(), [5.0, 7.0])
    # roll RD 2 % falls in the 1-2.5 % band, steer 30 % in 25-100 %
    for axis, band in ((ax, (1.0, 2.5)), (fig.axes[1], (25.0, 100.0))):
        cs = axis.collections[0]
        filled = [i for i, p in enumerate(cs.get_paths()) if len(p.vertices)]
        assert [(cs.levels[i], cs.levels[i + 1]) for i in filled] == [band]
    cbar = fig.axes[-1]
    ticks = [float(t.get_text().replace("\u2212", "-")) for t in cbar.get_yticklabels()]
    assert ticks == list(palette.RD_TICKS_PERCENT)
    figures.check_legible(fig, "fig_3_34")


def test_g_7_has_a_cadence_rpm_axis():
    v, w = np.linspace(0, 10, 6), np.linspace(0, 4 * np.pi, 5)
    amp = np.outer(v + 1, w + 1) * 1e-3
    ps = {"speed_m_s": v, "omega_rad_s": w, "roll_amp_rad": amp, "steer_amp_rad": amp,
          "cam_roll_rad": 0.01, "cam_steer_rad": 0.01}
    eig = {"speed_m_s": v, "weave_frequency_rad_s": np.full(v.size, 3.0),
           "stable_ranges_m_s": np.array([[4.0, 6.0]])}
    with figures.style():
        fig = figlin.fig_g_7(ps, eig)
    children = [c for a in fig.axes for c in a.child_axes]
    rpm = [c for c in children if c.get_ylabel() == "cadence (rpm)"]
    kmh = [c for c in children if c.get_xlabel() == "speed (km/h)"]
    assert len(rpm) == 2 and len(kmh) == 2
    sec = rpm[0]
    # the secondary axis maps 2 pi rad/s to 60 rpm
    assert sec._functions[0](2 * np.pi) == pytest.approx(60.0)
    figures.check_legible(fig, "fig_g_7")


def test_every_chapter_uses_one_model_colour():
    import pandas as pd

    from pedalrepro.figures import validation as fv

    per_run = pd.DataFrame({"system": ["HS", "CR"], "speed_kmh": [10.0, 20.0],
                            "roll_rd_percent": [5.0, 6.0], "steer_rd_percent": [7.0, 8.0]})
    with figures.style():
        fig = fv.run_relative_differences(per_run)
    colours = {ln.get_label(): ln.get_color() for ln in fig.axes[0].get_lines()}
    assert colours == {"HS": palette.MODEL_COLOURS["HS"], "CR": palette.MODEL_COLOURS["CR"]}
    sections = {"gear_ratios": np.array([1.0]), "HS_1_speed_m_s": np.array([1.0, 2.0]),
                "HS_1_roll_rad": np.array([0.01, 0.02]), "HS_1_steer_rad": np.array([0.0, 0.01])}
    with figures.style():
        fig = figlin.figs_gear_sections(sections, ["HS"])
    assert {ln.get_color() for ln in fig.axes[0].get_lines()} == {palette.MODEL_COLOURS["HS"]}


def test_figure_data_gear_sections_follow_the_gear_line():
    """Fig 3.36 data: along GR 2 the cadence is v / (GR r_wheel) (Sec 3.1.3.2), and the drawn
    amplitude is the PS amplitude of the cadence harmonic there."""
    from pedalrepro import figdata, gears, linear, response

    v = np.array([2.0, 4.0, 6.0])
    d = figdata.gear_sections(["HS"], v, [2.0], 12.0, (1, 3, 5))
    r_wheel = gears.wheel_radius_m(linear.bicycle_of("HS"))
    w = v / (2.0 * r_wheel)
    np.testing.assert_allclose(d["HS_2_speed_m_s"], v[w <= 12.0])
    roll, _ = response.particular_solution(linear.linear_model("HS"), v[1], w[1],
                                           response.forcing("HS", harmonics=(1, 3, 5)))
    assert d["HS_2_roll_rad"][1] == pytest.approx(abs(np.ravel(roll)[0]), rel=1e-12)


def test_figure_data_names_a_missing_config_key(tmp_path):
    from pedalrepro import figdata

    with pytest.raises(KeyError, match="linear.ps_speed_step_m_s"):
        figdata.write_linear({"gear_grid": str(tmp_path / "g.npz")}, {"harmonics": [1]})


def test_validation_figure_data_keeps_the_real_run_apart(tmp_path):
    """Figs 4.2-4.10 take their example runs from the build's main source only (a real
    public-subset row is never pooled into the synthetic figures); the REAL run goes into the
    real_* keys and its panel is drawn at most 7 in wide with text >= 8 pt (figures.save)."""
    import pandas as pd

    from pedalrepro import figdata
    from pedalrepro.figures import validation as fv

    rows = [dict(run_id=k + 1, system=s, speed_kmh=20.0, cadence_rpm=80.0,
                 data_source="synthetic") for k, s in enumerate(("HS", "CF", "HR", "CR"))]
    rows.append(dict(run_id=3045, system="HR", speed_kmh=25.0, cadence_rpm=82.39,
                     data_source="public_subset"))
    per_run = pd.DataFrame(rows)
    t = np.arange(0.0, 20.0, 0.01)
    series = {}
    for r in rows:
        key = f"public_{r['run_id']}" if r["data_source"] == "public_subset" else r["run_id"]
        crank = 2 * np.pi * r["cadence_rpm"] / 60 * t
        series.update({f"{key}_t_s": t, f"{key}_crank_rad": crank,
                       f"{key}_roll_rad": 0.01 * np.sin(crank),
                       f"{key}_steer_rad": 0.02 * np.sin(crank)})
    out = figdata.validation(per_run, series, np.array([5.0, 6.0]), np.array([8.0, 9.0]), 6,
                             "synthetic")
    assert out["HR_run_ids"].tolist() == [3]  # not 3045
    assert int(out["real_run_id"]) == 3045 and str(out["real_system"]) == "HR"
    assert float(out["real_cadence_rpm"]) == pytest.approx(82.39, abs=1e-9)
    source = {"data_source": "synthetic", "reason": "stand-in"}
    with figures.style():
        fig = fv.real_run_panel(source, out)
    assert fig.get_size_inches()[0] <= 7.0 + 1e-9
    figures.save(fig, tmp_path / "real_run_panel.png")  # refuses wide figures or small text
    assert (tmp_path / "real_run_panel.pdf").exists()
    no_real = {k: v for k, v in out.items() if not k.startswith("real_")}
    with figures.style():
        fig = fv.real_run_panel(source, no_real)
    assert "No real public-subset run" in fig.axes[0].texts[0].get_text()
    figures.save(fig, tmp_path / "no_real_run.png")


def test_figs_4_10_4_11_show_the_measured_cf_spectra(tmp_path):
    """The measured CF spectra's points (rule closed_loop_spectra's table) join Figs 4.10 and
    4.11: the figure data hold the measured nearest-bin amplitudes and the open-loop CF model at
    the same speed and cadence, which equals the closed-loop comparison's open-loop column
    (pedalrepro.rider.comparison solves the CF model through response.forcing, a second path
    to the torque harmonics) to 1e-12; Fig 4.10 draws them as diamonds at (v, w) on both CF
    maps, Fig 4.11 their RD (Eq 3.26); without spectra neither figure draws a diamond."""
    import pandas as pd

    from pedalrepro import figdata
    from pedalrepro.figures import validation as fv
    from pedalrepro.rider import comparison

    rows = [dict(run_id=k + 1, system=s, speed_kmh=20.0, cadence_rpm=80.0,
                 roll_measured_rad=0.01, steer_measured_rad=0.02, roll_model_rad=0.012,
                 steer_model_rad=0.018, roll_rd_percent=20.0, steer_rd_percent=10.0,
                 data_source="synthetic") for k, s in enumerate(("HS", "CF", "HR", "CR"))]
    per_run = pd.DataFrame(rows)
    t = np.arange(0.0, 20.0, 0.01)
    series = {}
    for r in rows:
        crank = 2 * np.pi * r["cadence_rpm"] / 60 * t
        series.update({f"{r['run_id']}_t_s": t, f"{r['run_id']}_crank_rad": crank,
                       f"{r['run_id']}_roll_rad": 0.01 * np.sin(crank),
                       f"{r['run_id']}_steer_rad": 0.02 * np.sin(crank)})
    spectra = pd.DataFrame(dict(speed_kmh=[10.0, 25.0], cadence_rpm=[48.0, 64.08],
                                roll_nearest_rad=[0.0033, 0.0031],
                                steer_nearest_rad=[0.0057, 0.0137]))
    v, w = np.array([2.0, 5.0, 8.0]), np.array([4.0, 7.0, 10.0])
    out = figdata.validation(per_run, series, v, w, 6, "synthetic", spectra)
    assert out["spectra_roll_measured_rad"].tolist() == [0.0033, 0.0031]
    other = comparison.model_amplitudes("CF", spectra.speed_kmh / 3.6, spectra.cadence_rpm)
    for q in ("roll", "steer"):
        np.testing.assert_allclose(out[f"spectra_{q}_model_rad"], other[f"{q}_open"],
                                   rtol=1e-12)
    source = {"data_source": "synthetic", "reason": "stand-in"}
    with figures.style():
        f10 = fv.fig_4_10(per_run, series, source, out)
        f11 = fv.fig_4_11(per_run, series, source, out)
    cf_axes = [ax for ax in f10.axes if ax.get_title().startswith("CF ")]
    assert len(cf_axes) == 2
    for ax in cf_axes:
        diamonds = [c for c in ax.collections if c.get_label() == fv.SPECTRA_LABEL]
        assert len(diamonds) == 1
        np.testing.assert_allclose(diamonds[0].get_offsets(),
                                   np.c_[spectra.speed_kmh / 3.6,
                                         spectra.cadence_rpm * np.pi / 30], rtol=1e-12)
    for ax, q in zip(f11.axes[:2], ("roll", "steer"), strict=True):
        line = next(ln for ln in ax.lines if ln.get_label() == fv.SPECTRA_LABEL)
        measured = spectra[f"{q}_nearest_rad"].to_numpy()
        rd = np.abs(measured - out[f"spectra_{q}_model_rad"]) / measured * 100
        np.testing.assert_allclose(line.get_ydata(), rd, rtol=1e-12)
    assert "diamonds" in f10.get_suptitle() and "real measurements" in f11.get_suptitle()
    # built from the synthetic stand-in: stamped SYNTHETIC (figures.synthetic_stamp); from the
    # figshare runs: not
    assert "SYNTHETIC" in f10.get_suptitle() and "SYNTHETIC" in f11.get_suptitle()
    with figures.style():
        real_runs = per_run.assign(data_source="figshare")
        real = [fv.fig_4_10(real_runs, series, {"data_source": "figshare"}, out),
                fv.fig_4_11(real_runs, series, {"data_source": "figshare"}, out)]
    assert not any("SYNTHETIC" in t.get_text() for f in real for t in f.texts)
    assert not any("SYNTHETIC" in f.get_suptitle() for f in real)
    figures.save(f10, tmp_path / "fig_4_10.png")
    figures.save(f11, tmp_path / "fig_4_11.png")
    none = figdata.validation(per_run, series, v, w, 6, "synthetic", spectra.iloc[:0])
    assert not any(k.startswith("spectra_") for k in none)
    with figures.style():
        f10 = fv.fig_4_10(per_run, series, source, none)
        f11 = fv.fig_4_11(per_run, series, source, none)
    assert not any(c.get_label() == fv.SPECTRA_LABEL for ax in f10.axes
                   for c in ax.collections)
    assert not any(ln.get_label() == fv.SPECTRA_LABEL for ax in f11.axes for ln in ax.lines)
    assert "diamonds" not in f10.get_suptitle()
    plt.close("all")


def test_save_lays_out_once_and_matches_savefig_tight(tmp_path):
    """figures.save lays the figure out once at the PNG's dpi and freezes it: the PNG has the
    size matplotlib's own ``savefig(bbox_inches="tight")`` gives to 2 px, the axes keep the
    positions of that one layout (to 1e-12), and the layout engine is off afterwards."""
    import struct

    from pedalrepro.figures import page

    def make():
        with figures.style():
            fig, axes = plt.subplots(2, 2, figsize=(7.0, 5.0), layout="constrained")
            for k, ax in enumerate(axes.flat):
                ax.pcolormesh(np.arange(12.0).reshape(3, 4) * (k + 1))
                ax.set_title(f"panel {k}")
                ax.set_xlabel("forward speed v (m/s)")
            fig.colorbar(axes[0, 0].collections[0], ax=axes, label="amplitude (rad)")
            fig.suptitle("a title")
        return fig

    ref = make()
    with figures.style():
        ref.savefig(tmp_path / "ref.png")
    ref_pos = [ax.get_position().bounds for ax in ref.axes]
    fig = make()
    page.save(fig, tmp_path / "new.png")
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    assert not isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine)
    np.testing.assert_allclose([ax.get_position().bounds for ax in fig.axes], ref_pos,
                               atol=1e-12)

    def size(name):
        return struct.unpack(">II", (tmp_path / name).read_bytes()[16:24])

    # the box is grown to whole pixels (page.whole_pixels): up to 1 px at each edge
    assert np.max(np.abs(np.subtract(size("new.png"), size("ref.png")))) <= 2
    assert (tmp_path / "new.pdf").stat().st_size > 0
    plt.close("all")


def test_png_is_the_first_draw_cropped_as_savefig_renders_it(tmp_path):
    """figures.save writes the PNG from its one draw at the PNG's dpi, cropped to the padded
    tight box grown to whole pixels: byte for byte what savefig renders with that box (colour
    bar, suptitle and the padding past the figure's edge included). A text sticking out of
    the figure, which that draw clips, makes it fall back to savefig's own render."""
    from matplotlib.transforms import Bbox

    from pedalrepro.figures import page

    def make(outside=False):
        with figures.style():
            fig, axes = plt.subplots(1, 2, figsize=(6.0, 3.0), layout="constrained")
            for k, ax in enumerate(axes):
                ax.pcolormesh(np.arange(12.0).reshape(3, 4) * (k + 1))
                ax.plot([0, 4], [0, 3], "k--")
                ax.set_xlabel("forward speed v (m/s)")
            fig.colorbar(axes[0].collections[0], ax=axes, label="amplitude (rad)")
            fig.suptitle("a title")
            if outside:
                fig.text(1.02, 0.5, "outside", fontsize=9)
        return fig

    for outside in (False, True):
        fig = make(outside)
        with figures.style():
            dpi = float(matplotlib.rcParams["savefig.dpi"])
            fig.set_dpi(dpi)
            fig.canvas.draw()
            tight = fig.get_tightbbox(fig.canvas.get_renderer())
            box = page.whole_pixels(tight.padded(0.04), dpi)
            assert all(abs(x * dpi - round(x * dpi)) < 1e-9 for x in box.extents)
            assert box.contains(tight.x0, tight.y0) and box.contains(tight.x1, tight.y1)
            written = page.png_from_draw(fig, tight, box, dpi, tmp_path / "mine.png")
            assert written is (not outside)
            fig.set_layout_engine("none")
            fig.savefig(tmp_path / "ref.png", bbox_inches=Bbox(box.get_points()))
        if written:
            assert (tmp_path / "mine.png").read_bytes() == (tmp_path / "ref.png").read_bytes()
        plt.close(fig)


def test_overlapping_colour_bars_are_found():
    """Two colour bars on one spot (the periodic maps' fault, issue 25) are found from the drawn
    bounding boxes; two side by side, each beside its own axes, are not."""
    from pedalrepro.figures import page

    z = np.arange(12.0).reshape(3, 4)
    fig, axes = plt.subplots(1, 2, figsize=(7, 3), layout="constrained")
    for ax in axes:
        ax.pcolormesh(z)
    fig.colorbar(axes[0].collections[0], ax=axes[0], label="amplitude (rad)")
    fig.colorbar(axes[1].collections[0], ax=axes[1], label="RD (%)")
    assert page.overlapping_colorbars(fig) == []
    plt.close(fig)
    fig, axes = plt.subplots(1, 2, figsize=(7, 3))
    for ax in axes:
        ax.pcolormesh(z)
    cax = fig.add_axes([0.90, 0.1, 0.03, 0.8])
    fig.colorbar(axes[0].collections[0], cax=cax, label="amplitude (rad)")
    cax2 = fig.add_axes([0.905, 0.1, 0.03, 0.8])  # drawn on top of the first
    fig.colorbar(axes[1].collections[0], cax=cax2, label="RD (%)")
    found = page.overlapping_colorbars(fig)
    assert any("'amplitude (rad)' overlaps colour bar 'RD (%)'" in f for f in found), found
    cax3 = fig.add_axes([0.3, 0.3, 0.03, 0.4])  # over the first plot
    fig.colorbar(axes[0].collections[0], cax=cax3, label="over")
    assert any("'over' overlaps axes" in f for f in page.overlapping_colorbars(fig))
    plt.close(fig)


def test_save_refuses_overlapping_colour_bars(tmp_path):
    """figures.save checks every figure a rule saves (so every build checks every figure): two
    colour bars on one spot are refused, naming both, and nothing is written; the figure with
    its colour bars side by side is saved."""
    z = np.arange(12.0).reshape(3, 4)
    with figures.style():
        fig, axes = plt.subplots(1, 2, figsize=(6.5, 3), layout="constrained")
        for ax in axes:
            ax.pcolormesh(z)
        fig.colorbar(axes[0].collections[0], ax=axes[0], label="amplitude (rad)")
        fig.colorbar(axes[1].collections[0], ax=axes[1], label="RD (%)")
        assert figures.save(fig, tmp_path / "ok.png").exists()
        fig, axes = plt.subplots(1, 2, figsize=(6.5, 3))
        for ax in axes:
            ax.pcolormesh(z)
        fig.colorbar(axes[0].collections[0], cax=fig.add_axes([0.90, 0.1, 0.03, 0.8]),
                     label="amplitude (rad)")
        fig.colorbar(axes[1].collections[0], cax=fig.add_axes([0.905, 0.1, 0.03, 0.8]),
                     label="RD (%)")
        with pytest.raises(ValueError, match=r"bad.png: colour bar 'amplitude \(rad\)' overlaps "
                                             r"colour bar 'RD \(%\)'"):
            figures.save(fig, tmp_path / "bad.png")
    assert not (tmp_path / "bad.png").exists() and not (tmp_path / "bad.pdf").exists()
