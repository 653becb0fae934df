"""Your own bicycle (issue 13 part 6): ``pedalrepro.own_bicycle`` and ``pedalrepro resonance``."""

from __future__ import annotations

import csv
import shutil

import numpy as np
import pytest

from pedalrepro import cli, config, disturbance, linear, own_bicycle, paths, response
from pedalrepro.nonlinear import bicycle_data

DATA = paths.PARAMETERS / "bicycleparameters"
#: The thesis shortened the Browser seat post so the legs reach the pedals (Sec 2.1.1): hip at
#: 0.72 m from the crank axis; the unshortened 0.77 m (and the Rigid's 0.751 m) are too long.
SEAT_M = 0.72
#: The summary CSV prints 12 significant digits.
CSV_REL = 1e-11


def _nominal(a) -> np.ndarray:
    return np.vectorize(lambda x: float(getattr(x, "nominal_value", x)))(np.asarray(a))


def _summary(path) -> dict[str, str]:
    with open(path) as fh:
        rows = list(csv.reader(line for line in fh if not line.startswith("#")))
    return {k: v for k, v in rows[1:]}


@pytest.fixture(scope="module")
def lin() -> dict:
    return config.load()["linear"]


@pytest.fixture(scope="module")
def browser() -> own_bicycle.OwnBicycle:
    return own_bicycle.load_bicycle(DATA, "Browser", "Jason", seat_height_m=SEAT_M)


@pytest.fixture(scope="module")
def browser_map(browser, lin) -> own_bicycle.ResonanceMap:
    v, w = response.speed_cadence_grid(lin["ps_speed_step_m_s"], lin["ps_speed_max_m_s"],
                                       lin["ps_omega_step_rad_s"], lin["ps_omega_max_rad_s"])
    return own_bicycle.resonance_map(browser, v, w, lin["harmonics"],
                                     normal_speed_kmh=lin["normal_cycling_speed_kmh"],
                                     normal_cadence_rpm=lin["normal_cycling_cadence_rpm"])


def test_browser_jason_matrices_equal_bicycleparameters(browser):
    """M, C1, K0, K2 equal BicycleParameters' own ``canonical()`` (its independent implementation
    of Meijaard 2007) and the project's rigid-rider load (bicycle_data) through dtk, to 1e-9."""
    from dtk.bicycle import benchmark_par_to_canonical

    loaded = bicycle_data.load("Browser")
    theirs = [_nominal(x) for x in loaded.bicycle.canonical()]
    ours = [browser.model.M, browser.model.C1, browser.model.K0, browser.model.K2]
    project = benchmark_par_to_canonical(loaded.with_rider)
    for a, b, c in zip(ours, theirs, project, strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9)
        np.testing.assert_allclose(a, np.asarray(c, float), rtol=0, atol=1e-9)
    # the rider is on: the rear-frame mass is the Browser's plus the Yeadon model's body mass
    assert browser.benchmark["mB"] - loaded.frame["mB"] == pytest.approx(
        float(loaded.bicycle.human.mass), rel=1e-12)


def test_browser_torques_equal_city_torques(browser):
    """Leg geometry from the Browser's measured seat angle (lamst, 10 digits = 68.5 deg) and the
    0.72 m seat gives the thesis's city-bicycle pedalling torques (Eq 3.14)."""
    ours = own_bicycle.torques(browser)
    city = disturbance.torque_harmonics("city")
    np.testing.assert_allclose(ours.roll, city.roll, rtol=1e-8)
    np.testing.assert_allclose(ours.steer, city.steer, rtol=1e-8)


def test_map_equals_per_point_solve(browser, browser_map):
    """The batched map equals an independent per-point ``np.linalg.solve`` (loop) to 1e-10."""
    v, w = browser_map.speed_m_s[::7], browser_map.omega_rad_s[::9]
    roll, steer = response.particular_solution_loop(browser.model, v, w,
                                                    own_bicycle.torques(browser))
    np.testing.assert_allclose(browser_map.roll_amp_rad[::7, ::9], np.abs(roll[..., 0]),
                               rtol=1e-10, atol=1e-15)
    np.testing.assert_allclose(browser_map.steer_amp_rad[::7, ::9], np.abs(steer[..., 0]),
                               rtol=1e-10, atol=1e-15)


def test_cli_on_shipped_rigid(tmp_path, lin, capsys):
    """``pedalrepro resonance`` on the shipped Rigid (a bicycle the thesis did not study)."""
    code = cli.main(["resonance", str(DATA), "--bicycle", "Rigid", "--rider", "Jason",
                     "--out", str(tmp_path), "--seat-height-m", str(SEAT_M)])
    assert code == 0
    s = _summary(tmp_path / "Rigid_Jason_summary.csv")
    own = own_bicycle.load_bicycle(DATA, "Rigid", "Jason", seat_height_m=SEAT_M)
    # the PS peak of the CSV is the library's grid maximum, and an independent 2x2 solve there
    v, w = float(s["roll_peak_speed_m_s"]), float(s["roll_peak_omega_rad_s"])
    roll, _ = response.particular_solution_loop(own.model, [v], [w], own_bicycle.torques(own))
    assert float(s["roll_peak_rad"]) == pytest.approx(abs(roll[0, 0, 0]), rel=CSV_REL)
    with open(tmp_path / "Rigid_Jason_resonance_map.csv") as fh:
        rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
    assert len(rows) == 101 * 102  # the config PS grid, v = 0:0.1:10, w = 0:0.124:4 pi
    amp = np.array([float(r["roll_amp_rad"]) for r in rows])
    assert amp.max() == pytest.approx(float(s["roll_peak_rad"]), rel=CSV_REL)
    # the weave speed is a root of the largest real part (Sec 3.2.1)
    e = linear.eigenvalues(own.model, float(s["weave_speed_m_s"]))
    assert abs(e.real.max()) < 1e-8
    # Fig G.7: the PS maximum sits at the weave frequency at the weave speed (one grid step)
    assert w == pytest.approx(float(s["weave_frequency_at_weave_speed_rad_s"]),
                              abs=lin["ps_omega_step_rad_s"])
    assert v == pytest.approx(float(s["weave_speed_m_s"]), abs=lin["ps_speed_step_m_s"])
    assert (tmp_path / "Rigid_Jason_resonance.png").stat().st_size > 10_000


def test_rigid_default_seat_is_too_high_with_a_clear_error(tmp_path, capsys):
    """With lst + lsp = 0.751 m + a 0.17 m crank the 0.92 m leg is 0.9 mm short: exit code 2."""
    code = cli.main(["resonance", str(DATA), "--bicycle", "Rigid", "--rider", "Jason",
                     "--out", str(tmp_path)])
    err = capsys.readouterr().err
    assert code == 2
    assert "cannot reach the pedal" in err and "0.9 mm short" in err


def _user_folder(root, name="Mybike"):
    """A user's folder: the shipped Browser and Jason copied and renamed."""
    src = DATA / "bicycles" / "Browser"
    bdir = root / "bicycles" / name
    (bdir / "Parameters").mkdir(parents=True)
    (bdir / "RawData").mkdir()
    shutil.copy(src / "Parameters" / "BrowserBenchmark.txt",
                bdir / "Parameters" / f"{name}Benchmark.txt")
    shutil.copy(src / "RawData" / "BrowserMeasured.txt", bdir / "RawData" / f"{name}Measured.txt")
    rdir = root / "riders" / "Jason" / "RawData"
    rdir.mkdir(parents=True)
    shutil.copy(DATA / "riders" / "Jason" / "RawData" / "JasonYeadonMeas.txt", rdir)
    shutil.copy(DATA / "riders" / "Jason" / "RawData" / "JasonBrowserYeadonCFG.txt",
                rdir / f"Jason{name}YeadonCFG.txt")
    return root


def test_cli_on_user_folder(tmp_path, browser_map):
    """A renamed copy of the Browser gives the library's Browser map (same physics)."""
    data = _user_folder(tmp_path / "data")
    code = cli.main(["resonance", str(data), "--bicycle", "Mybike", "--rider", "Jason",
                     "--out", str(tmp_path / "out"), "--seat-height-m", str(SEAT_M)])
    assert code == 0
    s = _summary(tmp_path / "out" / "Mybike_Jason_summary.csv")
    i, j = np.unravel_index(np.argmax(browser_map.roll_amp_rad), browser_map.roll_amp_rad.shape)
    assert float(s["roll_peak_rad"]) == pytest.approx(browser_map.roll_amp_rad[i, j], rel=CSV_REL)
    assert float(s["roll_peak_speed_m_s"]) == pytest.approx(browser_map.speed_m_s[i], abs=1e-12)
    assert float(s["roll_peak_omega_rad_s"]) == pytest.approx(browser_map.omega_rad_s[j],
                                                              abs=1e-12)
    assert float(s["steer_peak_rad"]) == pytest.approx(browser_map.steer_amp_rad.max(),
                                                       rel=CSV_REL)


def test_bad_folders_give_clear_errors(tmp_path, capsys):
    """A folder not in BicycleParameters' format: exit code 2 and the missing path named."""
    (tmp_path / "notbp").mkdir()
    code = cli.main(["resonance", str(tmp_path / "notbp"), "--bicycle", "X", "--rider", "Jason",
                     "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2
    assert "not in BicycleParameters' format" in err and str(tmp_path / "notbp" / "bicycles") in err
    # bicycle present, rider's configuration file for it missing
    data = _user_folder(tmp_path / "data")
    (data / "riders" / "Jason" / "RawData" / "JasonMybikeYeadonCFG.txt").unlink()
    with pytest.raises(FileNotFoundError, match="JasonMybikeYeadonCFG.txt"):
        own_bicycle.check_folder(data, "Mybike", "Jason")
    # a bicycle folder without parameter or measurement files
    (data / "bicycles" / "Empty").mkdir()
    with pytest.raises(FileNotFoundError, match="EmptyBenchmark.txt.*EmptyMeasured.txt"):
        own_bicycle.check_folder(data, "Empty", "Jason")
    assert not (tmp_path / "out").exists()


def test_ridge_inside_a_normal_cycling_ellipse(browser, browser_map):
    """Ridge points inside an ellipse placed on the ridge (24-30 km/h, 40-60 rpm) match an
    independent count: interior cadence maximum per speed, ellipse equation written out."""
    kmh, rpm = (24.0, 30.0), (40.0, 60.0)
    v, w = browser_map.speed_m_s, browser_map.omega_rad_s
    rmap = own_bicycle.resonance_map(browser, v, w, normal_speed_kmh=kmh, normal_cadence_rpm=rpm)
    values = own_bicycle.summary(browser, rmap, np.linspace(0.01, 10, 1000))
    amp = browser_map.roll_amp_rad
    inside = []
    for i in range(len(v)):
        j = int(np.argmax(amp[i]))
        if 0 < j < len(w) - 1:
            x = (v[i] - 27.0 / 3.6) / (3.0 / 3.6)
            y = (w[j] - 50.0 * np.pi / 30) / (10.0 * np.pi / 30)
            if x**2 + y**2 <= 1:
                inside.append((v[i], w[j]))
    assert len(inside) > 0
    assert values["roll_ridge_in_normal_points"] == len(inside)
    assert values["roll_ridge_in_normal_speed_m_s_min"] == pytest.approx(inside[0][0], abs=1e-12)
    assert values["roll_ridge_in_normal_speed_m_s_max"] == pytest.approx(inside[-1][0], abs=1e-12)
    gr = [sp / (om * browser.benchmark["rR"]) for sp, om in inside]  # v = GR w rR (Sec 3.1.3.2)
    assert values["roll_ridge_in_normal_gear_ratio_min"] == pytest.approx(min(gr), rel=1e-12)
    assert values["roll_ridge_in_normal_gear_ratio_max"] == pytest.approx(max(gr), rel=1e-12)
