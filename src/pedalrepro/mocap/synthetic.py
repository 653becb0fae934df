"""The synthetic stand-in for the treadmill data, in exactly the published file format.

The real data (figshare DOI 10.6084/m9.figshare.1082512) cannot be reached from the machines
that built this project. So that the reader and the marker-to-angle code are tested end to end,
and so that the pipeline runs, this module writes per-run MATLAB files ``RNNN.mat`` with the
published variables (``t``, ``x``, ``y``, ``z``, ``xori``, ``yori``, ``zori``, ``bike``,
``condition``, ``V``, ``gearing``; Optotrak frame, metres; static runs in millimetres with only
``x``, ``y``, ``z``) generated from the project's own model, with the ground truth beside them.

Content of a run (rider 3, one system HS, CF, HR or CR, speed ``v``, cadence ``w``):

- open-loop response: the particular solution of the Appendix B model of the system driven by the
  pedalling torques of Eq 3.14 (:func:`pedalrepro.response.particular_solution`,
  :func:`pedalrepro.disturbance.torque_harmonics`, harmonics 1, 3, 5), phase-locked to the crank;
- control-like roll and steer motion: Gaussian noise through a 2nd-order low-pass filter
  (corner :data:`CONTROL_CORNER_HZ`), larger at low speed (:func:`control_std_rad`);
- an upper-body component at 2 x cadence in steer and roll (the second harmonic seen in HS and
  CF, Sec 4.2) and a lateral sway of the trunk markers at 2 x cadence;
- yaw from the kinematic relation ``psi' = cos(lam) (v delta + c delta') / w`` with its slow
  drift removed (the rider stays on the belt);
- rider markers moving with the crank (the dual four-bar of :func:`pedalrepro.legs.leg_motion`);
- marker noise (``marker_noise_m``, 0.15 mm: the Optotrak Certus accuracy) and gaps: NaN, zeros or
  the ``1e28`` sentinel in ``xori`` (the conventions the reader must accept); ``x`` holds the
  gaps up to ``repair_gap_max_s`` linearly repaired (inferred behaviour of the original
  gap-filling), longer gaps left NaN.

This is not the measurement: anything built from it is labelled SYNTHETIC.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.io
from scipy import signal

from .. import disturbance, legs, linear, params, response
from ..params import read_yaml
from .reader import MARKERS, N_MARKERS, marker_index

__all__ = [
    "BIKE_KIND", "SYSTEMS", "HR_STAND_IN_FIRST_TRIAL", "CONTROL_CORNER_HZ", "UPPER_BODY_STEER_RAD",
    "UPPER_BODY_ROLL_RAD", "TRUNK_ANGLE_RAD", "GAP_STYLES", "SENTINEL_VALUE", "StandInRun",
    "control_std_rad", "stand_in_runs", "bicycle_shapes", "open_loop", "simulate_run", "static_run",
    "MAT_HEADER", "savemat", "write_stand_in", "marker_names",
]

#: Bicycle name in the files -> params name; system -> (bicycle, condition string, task)
BIKE_KIND = {"stratos": "hybrid", "browser": "city"}
SYSTEMS = {
    "HS": ("stratos", "pedaling"),
    "CF": ("browser", "pedaling"),
    "HR": ("stratos", "nohands"),
    "CR": ("browser", "nohands"),
}
#: Stand-in trial numbers of the Stratos no-hands runs (the real ones are not known here; runs
#: are selected by metadata, never by these numbers).
HR_STAND_IN_FIRST_TRIAL = 40
#: Corner frequency of the control-like motion (Hz).
CONTROL_CORNER_HZ = 0.6
#: Upper-body 2 x cadence amplitudes (rad): hands on the bars, hands free.
UPPER_BODY_STEER_RAD = {"HS": 3e-3, "CF": 4e-3, "HR": 1e-3, "CR": 1e-3}
UPPER_BODY_ROLL_RAD = {"HS": 1e-3, "CF": 1e-3, "HR": 5e-4, "CR": 5e-4}
#: Trunk angle from the horizontal (rad) per posture.
TRUNK_ANGLE_RAD = {"HS": 0.75, "CF": 1.0, "HR": 1.35, "CR": 1.35}
#: Value written for a missing sample in ``xori`` by gap style.
GAP_STYLES = ("nan", "zero", "sentinel")
SENTINEL_VALUE = 1e28


@dataclass(frozen=True)
class StandInRun:
    """One stand-in run: identity and conditions."""

    run_id: int
    system: str
    speed_kmh: float
    cadence_rpm: float
    gear: float

    @property
    def bicycle(self) -> str:
        return SYSTEMS[self.system][0]

    @property
    def condition(self) -> str:
        return SYSTEMS[self.system][1]


def control_std_rad(speed_m_s: float) -> tuple[float, float]:
    """Standard deviation of the control-like roll and steer motion at a speed (rad).

    Larger at low speed, where the thesis sees erratic, large low-frequency motion (Sec 4.2).
    """
    e = np.exp(-speed_m_s / 2.0)
    return 0.003 + 0.02 * e, 0.003 + 0.04 * e


def _gear_cadence(speed_kmh: float, bicycle: str, ratios: list[float], target_rpm: float
                  ) -> tuple[float, float]:
    """Stand-in cadence of a run without a published cadence: ``v / (GR 2 pi rR)`` with the
    gear ratio GR (Sec 3.1.2.2.1's gear relation) of ``ratios`` nearest ``target_rpm``."""
    r_r = params.stratos_geometry()["rR"] if bicycle == "stratos" else \
        params.benchmark_parameters("browser")["rR"]
    rpm = np.array([speed_kmh / 3.6 / (g * 2 * np.pi * r_r) * 60 for g in ratios])
    i = int(np.argmin(np.abs(rpm - target_rpm)))
    return float(rpm[i]), float(i + 1)


def stand_in_runs(mocap_cfg: dict, runs_file: str | Path | None = None) -> list[StandInRun]:
    """The runs of the stand-in: Table 4.1's (HR, CR at the header's speeds and cadences) and the
    normal-pedalling HS and CF runs plus the other CR no-hands runs (``validation_runs.yaml``).

    ``mocap_cfg["max_runs_per_system"]`` thins the HS and CF runs (the quick profile); the
    Table 4.1 runs are always present.
    """
    v = read_yaml(runs_file or params.paths.PARAMETERS / "validation_runs.yaml")
    ratios = list(mocap_cfg["stand_in_gear_ratios"])
    target = float(mocap_cfg["stand_in_cadence_rpm"])
    rider = int(v["rider"]) * 1000
    out: list[StandInRun] = []
    t41 = {(r["system"], float(r["speed_kmh"])): float(r["cadence_rpm"]) for r in v["table_4_1"]}
    hr = [(s, c) for (sys, s), c in t41.items() if sys == "HR"]
    for i, (s, c) in enumerate(hr):
        out.append(StandInRun(rider + HR_STAND_IN_FIRST_TRIAL + i, "HR", s, c, 0.0))
    r = v["runs"]
    for trial, s in zip(r["CR_trials"], r["CR_speeds_kmh"], strict=True):
        c = t41.get(("CR", float(s)))
        gear = 0.0
        if c is None:
            c, gear = _gear_cadence(s, "browser", ratios, target)
        out.append(StandInRun(rider + int(trial), "CR", float(s), c, gear))
    n_max = int(mocap_cfg["max_runs_per_system"])
    for system, first in (("HS", r["HS_first_trial"]), ("CF", r["CF_first_trial"])):
        speeds = list(r["pedalling_speeds_kmh"])
        idx = np.arange(len(speeds))
        if n_max < len(speeds):
            idx = np.unique(np.linspace(0, len(speeds) - 1, n_max).round().astype(int))
        for i in idx:
            c, gear = _gear_cadence(speeds[i], SYSTEMS[system][0], ratios, target)
            out.append(StandInRun(rider + int(first) + int(i), system, float(speeds[i]), c, gear))
    return out


def _lowpass_noise(rng: np.random.Generator, n: int, fs: float, std: float) -> np.ndarray:
    b, a = signal.butter(2, CONTROL_CORNER_HZ / (fs / 2))
    x = signal.lfilter(b, a, rng.standard_normal(n + 2000))[2000:]
    return std * x / x.std()


def _rotation_z(a: np.ndarray) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)],
                    -2)


def _rotation_x(a: np.ndarray) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    z, o = np.zeros_like(a), np.ones_like(a)
    return np.stack([np.stack([o, z, z], -1), np.stack([z, c, -s], -1), np.stack([z, s, c], -1)],
                    -2)


def _rotate_about(points: np.ndarray, axis: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Rodrigues rotation of ``points`` (n, k, 3) about the unit ``axis`` by ``angle`` (n,)."""
    c, s = np.cos(angle)[:, None, None], np.sin(angle)[:, None, None]
    cross = np.cross(axis, points)
    dot = (points @ axis)[..., None]
    return points * c + cross * s + axis * dot * (1 - c)


def bicycle_shapes(bicycle: str) -> dict[int, np.ndarray]:
    """Body-frame positions (m; origin at the rear contact point, x forward, y right, z down) of
    the bicycle markers at zero steer, from the bicycle's ``w``, ``c``, ``lam`` and wheel radii.

    The marker layout follows the published marker list (rear frame 22, 24, 25, 26, 28, 30, 31;
    fork and handlebar 21, 23, 27, 29); the exact positions on the real bicycles are not known
    and do not matter for the angle definitions.
    """
    g = params.steer_geometry(BIKE_KIND[bicycle])
    w, c, lam = g["w"], g["c"], g["lam"]
    if bicycle == "stratos":
        sg = params.stratos_geometry()
        r_r, r_f = sg["rR"], sg["rF"]
    else:
        b = params.benchmark_parameters("browser")
        r_r, r_f = b["rR"], b["rF"]

    def axis_point(s):  # point at distance s up the steer axis from the ground
        return np.array([w + c - s * np.sin(lam), 0.0, -s * np.cos(lam)])

    bb = np.array([0.43, 0.0, -(r_r - 0.07)])
    head = axis_point(0.8)
    bar = axis_point(1.05) + np.array([-0.12, 0.0, 0.0])
    return {
        25: np.array([0.0, 0.07, -r_r]), 31: np.array([0.0, -0.07, -r_r]),
        24: np.array([0.18, 0.06, -r_r - 0.15]), 30: np.array([0.18, -0.06, -r_r - 0.15]),
        26: bb + 0.55 * np.array([-np.cos(1.3), 0.0, -np.sin(1.3)]) + np.array([-0.03, 0, 0]),
        22: head + np.array([0.0, 0.03, 0.0]), 28: head + np.array([0.0, -0.03, 0.0]),
        21: np.array([w, 0.07, -r_f]), 27: np.array([w, -0.07, -r_f]),
        23: bar + np.array([0.0, 0.28, 0.0]), 29: bar + np.array([0.0, -0.28, 0.0]),
        0: bb,  # crank axis (not a marker)
    }


def open_loop(system: str, speed_m_s: float, cadence_rad_s: float
              ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Harmonic numbers and complex roll and steer responses (Sec 3.1.2.2.1) of a system."""
    h = disturbance.torque_harmonics(params.BICYCLE_OF_MODEL[system])
    roll, steer = response.particular_solution(linear.linear_model(system), speed_m_s,
                                               cadence_rad_s, h)
    return np.asarray(h.n), np.asarray(roll), np.asarray(steer)


def _harmonic_series(n: np.ndarray, coef: np.ndarray, phase: np.ndarray) -> np.ndarray:
    return np.real(np.exp(1j * np.multiply.outer(phase, n)) @ coef)


def simulate_run(run: StandInRun, mocap_cfg: dict, seed: int, gap_style: str = "nan"
                 ) -> tuple[dict, dict]:
    """Marker data (published variables) and ground truth of one stand-in run.

    Returns
    -------
    mat, truth
        ``mat``: the variables of ``RNNN.mat``; ``truth``: ``t_s``, ``roll_rad``, ``steer_rad``,
        ``yaw_rad``, ``crank_rad`` (``theta_A``), the open-loop harmonics and the components.
    """
    if gap_style not in GAP_STYLES:
        raise ValueError(f"gap_style {gap_style!r} not in {GAP_STYLES}")
    rng = np.random.default_rng([int(seed), int(run.run_id)])
    fs = float(mocap_cfg["sample_rate_hz"])
    n_t = int(round(float(mocap_cfg["duration_s"]) * fs))
    t = np.arange(n_t) / fs
    v = run.speed_kmh / 3.6
    omega = run.cadence_rpm * 2 * np.pi / 60
    crank0 = rng.uniform(0, 2 * np.pi)
    crank = omega * t + crank0  # omega t (= -theta_A)
    n, roll_c, steer_c = open_loop(run.system, v, omega)
    roll_ol = _harmonic_series(n, roll_c, crank)
    steer_ol = _harmonic_series(n, steer_c, crank)
    s_roll, s_steer = control_std_rad(v)
    roll_ctl = _lowpass_noise(rng, n_t, fs, s_roll)
    steer_ctl = _lowpass_noise(rng, n_t, fs, s_steer)
    ph2 = rng.uniform(0, 2 * np.pi)
    roll_ub = UPPER_BODY_ROLL_RAD[run.system] * np.cos(2 * crank + ph2)
    steer_ub = UPPER_BODY_STEER_RAD[run.system] * np.cos(2 * crank + ph2 + 0.5)
    roll = roll_ol + roll_ctl + roll_ub
    steer = steer_ol + steer_ctl + steer_ub
    g = params.steer_geometry(BIKE_KIND[run.bicycle])
    yaw_rate = np.cos(g["lam"]) * (v * steer + g["c"] * np.gradient(steer, t)) / g["w"]
    yaw = np.cumsum(yaw_rate) / fs
    yaw = yaw - signal.filtfilt(*signal.butter(2, 0.05 / (fs / 2)), yaw, padlen=min(n_t - 1, 300))
    x0 = 0.1 * _lowpass_noise(rng, n_t, fs, 1.0) / 5
    y0 = 0.1 * _lowpass_noise(rng, n_t, fs, 1.0) / 3

    shapes = bicycle_shapes(run.bicycle)
    lam = g["lam"]
    axis = np.array([np.sin(lam), 0.0, np.cos(lam)])
    axis_ground = np.array([g["w"] + g["c"], 0.0, 0.0])
    body = np.full((n_t, N_MARKERS, 3), np.nan)
    rear_ids = (22, 24, 25, 26, 28, 30, 31)
    for m in rear_ids:
        body[:, marker_index(m)] = shapes[m]
    fork_ids = (21, 23, 27, 29)
    fork = np.stack([np.broadcast_to(shapes[m] - axis_ground, (n_t, 3)) for m in fork_ids], 1)
    fork = _rotate_about(fork, axis, steer) + axis_ground
    for j, m in enumerate(fork_ids):
        body[:, marker_index(m)] = fork[:, j]

    # rider: legs from the dual four-bar, relative to the crank axis (x, z), at y = +-l_hh/2
    geom = legs.leg_geometry(BIKE_KIND[run.bicycle])
    bb = shapes[0]
    half = 0.5 * geom.hip_width_m
    for side, sign, ids in (("right", 1.0, (1, 2, 3, 4)), ("left", -1.0, (5, 6, 7, 8))):
        lm = legs.leg_motion(geom, omega, crank / omega, left=(side == "left"))
        pedal = np.stack([lm.pedal[:, 0], np.full(n_t, sign * half), lm.pedal[:, 1]], 1) + bb
        knee = np.stack([lm.knee[:, 0], np.full(n_t, sign * half), lm.knee[:, 1]], 1) + bb
        hip = np.stack([lm.hip[:, 0], np.full(n_t, sign * (half + 0.04)), lm.hip[:, 1]], 1) + bb
        ankle = pedal + 0.12 * (knee - pedal) / geom.shank_length_m
        foot = pedal + np.array([0.04, 0.0, -0.02])
        for m, p in zip(ids, (foot, ankle, knee, hip), strict=True):
            body[:, marker_index(m)] = p
    hip_c = 0.5 * (body[:, marker_index(4)] + body[:, marker_index(8)])
    a = TRUNK_ANGLE_RAD[run.system]
    trunk = np.array([np.cos(a), 0.0, -np.sin(a)])
    sway = 0.01 * np.cos(2 * crank + ph2)  # lateral upper-body motion at 2 x cadence (m)

    def up(frac, dy=0.0, dx=0.0):
        p = hip_c + frac * 0.7 * trunk + np.array([dx, dy, 0.0])
        p[:, 1] += frac * sway
        return p

    body[:, marker_index(9)] = up(0.0, dx=-0.08)
    body[:, marker_index(10)] = up(0.3, dx=-0.08)
    body[:, marker_index(11)] = up(0.65, dx=-0.08)
    body[:, marker_index(12)] = up(1.05, dx=-0.05)
    body[:, marker_index(15)] = up(0.8, 0.2)
    body[:, marker_index(19)] = up(0.8, -0.2)
    body[:, marker_index(16)] = up(1.0, 0.07, 0.08)
    body[:, marker_index(20)] = up(1.0, -0.07, 0.08)
    hands_on = run.system in ("HS", "CF")
    for wrist, elbow, shoulder, bar, sgn in ((13, 14, 15, 23, 1.0), (17, 18, 19, 29, -1.0)):
        if hands_on:
            w_p = body[:, marker_index(bar)] + np.array([0.0, -sgn * 0.06, -0.03])
        else:
            w_p = hip_c + np.array([0.0, sgn * 0.2, -0.08])
        body[:, marker_index(wrist)] = w_p
        body[:, marker_index(elbow)] = 0.5 * (w_p + body[:, marker_index(shoulder)]) + \
            np.array([0.0, sgn * 0.08, 0.05])

    # rear frame orientation (yaw then roll, zero pitch) and position on the belt
    rot = _rotation_z(yaw) @ _rotation_x(roll)
    pos = np.stack([x0 + 0.0, y0, np.zeros(n_t)], 1)
    world = np.einsum("nij,nkj->nki", rot, body) + pos[:, None, :]

    # marker noise, gaps; Optotrak frame M = diag(1, -1, -1) N
    noise = float(mocap_cfg["marker_noise_m"])
    raw = world + rng.normal(0.0, noise, world.shape)
    raw_m = raw * np.array([1.0, -1.0, -1.0])
    gap = np.zeros((n_t, N_MARKERS), bool)
    n_gaps = rng.poisson(float(mocap_cfg["gaps_per_marker_per_min"]) * n_t / fs / 60.0,
                         N_MARKERS)
    max_len = int(float(mocap_cfg["max_gap_s"]) * fs)
    for k in range(N_MARKERS):
        for _ in range(n_gaps[k]):
            length = int(rng.integers(2, max(3, max_len)))
            start = int(rng.integers(0, n_t - length))
            gap[start:start + length, k] = True
    repaired = raw_m.copy()
    repaired[np.broadcast_to(gap[..., None], raw_m.shape)] = np.nan
    rep_max = int(float(mocap_cfg["repair_gap_max_s"]) * fs)
    for k in np.flatnonzero(gap.any(axis=0)):
        ok = ~gap[:, k]
        idx = np.flatnonzero(gap[:, k])
        runs = np.split(idx, np.flatnonzero(np.diff(idx) > 1) + 1)
        for seg in runs:
            if seg.size <= rep_max and seg[0] > 0 and seg[-1] < n_t - 1:
                for j in range(3):
                    repaired[seg, k, j] = np.interp(t[seg], t[ok], raw_m[ok, k, j])
    ori = raw_m.copy()
    fill = {"nan": np.nan, "zero": 0.0, "sentinel": SENTINEL_VALUE}[gap_style]
    ori[np.broadcast_to(gap[..., None], ori.shape)] = fill
    mat = {
        "t": t[:, None], "x": repaired[..., 0], "y": repaired[..., 1], "z": repaired[..., 2],
        "xori": ori[..., 0], "yori": ori[..., 1], "zori": ori[..., 2],
        "bike": run.bicycle, "condition": run.condition, "V": np.array([[run.speed_kmh]]),
        "gearing": np.array([[run.gear]]),
    }
    truth = {
        "t_s": t, "roll_rad": roll, "steer_rad": steer, "yaw_rad": yaw, "crank_rad": -crank,
        "cadence_rpm": run.cadence_rpm, "speed_kmh": run.speed_kmh,
        "harmonics": n, "roll_open_loop": roll_c, "steer_open_loop": steer_c,
        "roll_open_loop_rad": roll_ol, "steer_open_loop_rad": steer_ol,
        "gap_fraction": float(gap.mean()),
    }
    return mat, truth


def static_run(bicycle: str, mocap_cfg: dict, seed: int, trial: int) -> dict:
    """Variables of a static run: only ``x``, ``y``, ``z``, in millimetres (as published)."""
    rng = np.random.default_rng([int(seed), 3000 + trial])
    fs = float(mocap_cfg["sample_rate_hz"])
    n_t = int(5 * fs)
    shapes = bicycle_shapes(bicycle)
    pts = np.zeros((N_MARKERS, 3))
    for m, p in shapes.items():
        if m:
            pts[marker_index(m)] = p
    world = np.broadcast_to(pts, (n_t, N_MARKERS, 3)) + rng.normal(
        0.0, float(mocap_cfg["marker_noise_m"]), (n_t, N_MARKERS, 3))
    mm = 1000.0 * world * np.array([1.0, -1.0, -1.0])
    rider = [marker_index(m) for m in range(1, 21)]
    mm[:, rider, :] = np.nan  # no rider on the static bicycle
    return {"x": mm[..., 0], "y": mm[..., 1], "z": mm[..., 2]}


#: Fixed 116-byte text header of the stand-in files (scipy writes the creation time there, which
#: would make two identical runs differ byte-wise).
MAT_HEADER = b"MATLAB 5.0 MAT-file, written by pedalrepro.mocap.synthetic (stand-in, not data)"


def savemat(path: str | Path, variables: dict, compress: bool = True) -> Path:
    """``scipy.io.savemat`` (MATLAB 5 format, as published) with a fixed header text, so the
    same inputs give byte-identical files. ``compress=False``: stored, not deflated (the
    stand-in's marker noise barely compresses: 13 % smaller files for 20 times the write
    time, 0.5 s a run)."""
    path = Path(path)
    scipy.io.savemat(str(path), variables, do_compression=compress, oned_as="column")
    with path.open("r+b") as fh:
        fh.write(MAT_HEADER.ljust(116, b" "))
    return path


def write_stand_in(out_dir: str | Path, mocap_cfg: dict, seed: int) -> pd.DataFrame:
    """Write every stand-in run (``RNNN.mat``) and its truth (``truth/RNNN.npz``) to ``out_dir``.

    Returns the index (one row per run: ``run_id, system, bicycle, condition, speed_kmh,
    cadence_rpm, roll_open_loop_amp_rad, steer_open_loop_amp_rad, gap_style, file``), also
    written to ``out_dir/truth/truth.csv``. Same ``mocap_cfg`` and ``seed`` give the same files.
    """
    out = Path(out_dir)
    (out / "truth").mkdir(parents=True, exist_ok=True)
    rows = []
    for i, run in enumerate(stand_in_runs(mocap_cfg)):
        style = GAP_STYLES[i % len(GAP_STYLES)]
        mat, truth = simulate_run(run, mocap_cfg, seed, style)
        path = out / f"{run.run_id:04d}.mat"
        savemat(path, mat, compress=False)  # an intermediate file (see savemat)
        np.savez_compressed(out / "truth" / f"{run.run_id:04d}.npz", **truth)
        rows.append({
            "run_id": run.run_id, "system": run.system, "bicycle": run.bicycle,
            "condition": run.condition, "speed_kmh": run.speed_kmh,
            "cadence_rpm": run.cadence_rpm,
            "roll_open_loop_amp_rad": float(abs(truth["roll_open_loop"][0])),
            "steer_open_loop_amp_rad": float(abs(truth["steer_open_loop"][0])),
            "gap_style": style, "gap_fraction": truth["gap_fraction"], "file": path.name,
        })
    for bicycle, trial in (("stratos", 1), ("browser", 51)):
        savemat(out / f"3{trial:03d}.mat", static_run(bicycle, mocap_cfg, seed, trial),
                compress=False)
    index = pd.DataFrame(rows)
    index.to_csv(out / "truth" / "truth.csv", index=False)
    return index


def marker_names() -> tuple[str, ...]:
    """The 31 published marker names (for documentation of the stand-in files)."""
    return MARKERS
