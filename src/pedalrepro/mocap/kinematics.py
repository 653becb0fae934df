"""Bicycle kinematics from the markers: rigid-body fits, yaw, roll, steer and crank angle.

Angle definitions (Moore et al. 2011, moorepants/MotionCapture ``states.py``), in the benchmark
frame N (x forward, y right, z down) and the **benchmark sign convention of Meijaard et al.
(2007)** used everywhere in this project (the thesis's Eq 3.1 states ``q = [roll, steer]``):

- rear frame: ``b2`` = unit normal (pointing right) of the plane through the seat-post marker
  26, the head-tube centre (22 + 28)/2 and the rear-wheel centre (25 + 31)/2;
  ``b1 = unit(b2 x n3)`` (heading, pitch taken as zero), ``b3 = b1 x b2``;
- yaw ``psi = atan2(b1.n2, b1.n1)``; roll ``phi = atan2(b2.n3, b3.n3)`` (positive = lean right);
- steer axis ``d1 = cos(lam) b1 - sin(lam) b3``, ``d2 = b2``, ``d3 = d1 x d2`` (down the axis);
  front axle ``e2 = unit(r21 - r27)`` (pointing right); steer ``delta = atan2(-e2.d1, e2.d2)``,
  positive = front wheel turned right. This is ``states.py``'s sign (``e1 = e2 x e3``);
  ``convertData.m`` and the 2011 paper use ``e1 = e3 x e2`` and so report ``-delta``;
- crank angle ``theta_A = -atan2(p.b3, p.b1)``, ``p`` = left foot -> right foot (markers 5 -> 1)
  in the b1-b3 plane: 0 with the right foot forward, decreasing while pedalling (Sec 2.1.1).

The robust version of these definitions: each frame's orientation is a weighted least-squares
rigid-body fit (Kabsch/SVD) of all its visible markers to a reference shape, and the triads
above are computed once, on the reference shape, and rotated with the fit. Two 0.1 m-apart axle
markers with 0.15 mm noise alone would give about 3e-3 rad of steer noise; the fit over four fork
markers (the handlebar ends are 0.5 m apart) and seven rear-frame markers is about ten times
better and survives any one missing marker.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import signal

from .. import params
from .reader import FORK_MARKERS, REAR_FRAME_MARKERS, Run, marker_index

__all__ = [
    "N3", "MIN_MARKERS", "OUTLIER_M", "LOWPASS_HZ", "kabsch", "robust_fit", "reference_shape",
    "Kinematics", "fill_gaps", "steer_axis_tilt_rad", "extract",
]

N3 = np.array([0.0, 0.0, 1.0])
#: Minimum number of visible markers for a rigid-body fit.
MIN_MARKERS = 3
#: Residual above which a marker sample is an outlier (spike, swap) and dropped from a fit (m);
#: the markers are accurate to about 0.15 mm and the frames stiff to about a millimetre.
OUTLIER_M = 0.01
#: Default low-pass corner of the extracted angles (Hz).
LOWPASS_HZ = 12.0


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def kabsch(reference: np.ndarray, points: np.ndarray, weights: np.ndarray | None = None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Weighted least-squares rotation and translation mapping a shape onto observed points.

    Minimises ``sum_i w_i |R s_i + t - p_i|^2`` for every frame (Kabsch 1976, SVD with the
    reflection fix), vectorised over the leading axis.

    Parameters
    ----------
    reference
        ``(k, 3)`` reference shape ``s``.
    points
        ``(n, k, 3)`` observed points ``p`` (NaN where missing).
    weights
        ``(n, k)``; default 1 where ``points`` is finite, else 0.

    Returns
    -------
    R, t, rms
        ``(n, 3, 3)``, ``(n, 3)``, ``(n,)`` (RMS residual, m); NaN for frames with fewer than
        :data:`MIN_MARKERS` visible markers.
    """
    p = np.asarray(points, dtype=float)
    valid = np.all(np.isfinite(p), axis=-1)
    w = valid.astype(float) if weights is None else np.where(valid, weights, 0.0)
    p = np.where(valid[..., None], p, 0.0)
    sw = w.sum(axis=1)
    ok = (valid.sum(axis=1) >= MIN_MARKERS) & (sw > 0)
    sw_safe = np.where(ok, sw, 1.0)
    cs = np.einsum("nk,kj->nj", w, reference) / sw_safe[:, None]
    cp = np.einsum("nk,nkj->nj", w, p) / sw_safe[:, None]
    s0 = reference[None, :, :] - cs[:, None, :]
    p0 = p - cp[:, None, :]
    h = np.einsum("nk,nki,nkj->nij", w, s0, p0)
    u, _, vt = np.linalg.svd(h)
    d = np.sign(np.linalg.det(np.einsum("nij,njk->nik", u, vt)))
    d = np.where(d == 0, 1.0, d)
    fix = np.ones((len(p), 3))
    fix[:, 2] = d
    rot = np.einsum("nji,nj,nkj->nik", vt, fix, u)  # V diag(1,1,d) U^T
    t = cp - np.einsum("nij,nj->ni", rot, cs)
    resid = np.einsum("nij,nkj->nki", rot, s0) - p0
    rms = np.sqrt(np.sum(w * np.sum(resid**2, axis=-1), axis=1) / sw_safe)
    rot[~ok] = np.nan
    t[~ok] = np.nan
    rms[~ok] = np.nan
    return rot, t, rms


def robust_fit(reference: np.ndarray, points: np.ndarray, outlier_m: float | None = None,
               passes: int = 2) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """:func:`kabsch` that drops, per frame, the worst marker when its residual exceeds
    ``outlier_m`` (a spike or a swapped marker), and refits; up to ``passes`` times.

    Returns ``R, t, rms`` as :func:`kabsch` and the number of marker samples dropped per frame.
    A frame keeps at least :data:`MIN_MARKERS` markers; a frame with an outlier and no marker
    to spare gets no fit (NaN, and a drop count of -1).
    """
    outlier_m = OUTLIER_M if outlier_m is None else outlier_m
    pts = np.array(points, dtype=float)
    dropped = np.zeros(len(pts), int)
    rot, t, rms = kabsch(reference, pts)
    for _ in range(passes):
        fit = np.einsum("nij,kj->nki", rot, reference) + t[:, None, :]
        resid = np.linalg.norm(fit - pts, axis=-1)
        resid = np.where(np.isfinite(resid), resid, -1.0)
        worst = np.argmax(resid, axis=1)
        n_valid = np.all(np.isfinite(pts), axis=-1).sum(axis=1)
        over = resid[np.arange(len(pts)), worst] > outlier_m
        hopeless = over & (n_valid <= MIN_MARKERS)  # an outlier and no marker to spare
        if hopeless.any():
            rot[hopeless], t[hopeless], rms[hopeless] = np.nan, np.nan, np.nan
            pts[hopeless] = np.nan
            dropped[hopeless] = -1
        bad = over & (n_valid > MIN_MARKERS)
        if not bad.any():
            break
        pts[np.flatnonzero(bad), worst[bad]] = np.nan
        dropped[bad] += 1
        r2, t2, rms2 = kabsch(reference, pts[bad])
        rot[bad], t[bad], rms[bad] = r2, t2, rms2
    return rot, t, rms, dropped


def reference_shape(points: np.ndarray, max_frames: int = 400, iterations: int = 3
                    ) -> np.ndarray:
    """Mean rigid shape of a body from its fully visible frames (generalised Procrustes,
    frames with outlying residuals left out).

    Parameters
    ----------
    points
        ``(n, k, 3)`` trajectories of the body's markers (NaN where missing).
    max_frames
        Number of fully visible frames used (evenly spread over the run).

    Raises
    ------
    ValueError
        When no frame shows all the body's markers (give a static run's shape instead).
    """
    clean = np.flatnonzero(np.all(np.isfinite(points), axis=(1, 2)))
    if clean.size == 0:
        raise ValueError("no frame shows every marker of the body: a reference shape needs at "
                         "least one clean frame (or use the static run as reference)")
    pick = clean[np.linspace(0, clean.size - 1, min(max_frames, clean.size)).astype(int)]
    frames = points[pick]
    ref = frames[0]
    for _ in range(iterations):
        # align every frame onto ref, average the aligned shapes of the frames that fit well
        # (a frame with a spike, rms above 3 x the median, is left out)
        rot, t, rms = kabsch(ref, frames)  # maps ref -> frame
        aligned = np.einsum("nji,nkj->nki", rot, frames - t[:, None, :])
        good = rms <= 3.0 * np.median(rms) + 1e-12
        ref = aligned[good].mean(axis=0)
    return ref


@dataclass
class Kinematics:
    """Bicycle states of one run (benchmark frame and sign convention, Meijaard et al. 2007).

    Attributes
    ----------
    t_s, yaw_rad, roll_rad, steer_rad, crank_rad
        Time (s) and angles (rad); the crank angle is ``theta_A``, unwrapped.
    rear_rms_m, fork_rms_m
        RMS residuals of the rigid-body fits (m), NaN where a fit was impossible.
    repaired_fraction
        Share of samples whose angles were interpolated (fewer than 3 markers of a body).
    valid
        Per sample: roll and steer come from marker fits (not interpolated).
    notes
        Repairs (markers never seen, fallbacks to the gap-repaired arrays).
    """

    t_s: np.ndarray
    yaw_rad: np.ndarray
    roll_rad: np.ndarray
    steer_rad: np.ndarray
    crank_rad: np.ndarray
    rear_rms_m: np.ndarray
    fork_rms_m: np.ndarray
    repaired_fraction: float
    notes: list[str] = field(default_factory=list)
    valid: np.ndarray | None = None


def _body_points(run: Run, numbers: tuple[int, ...], notes: list[str]
                 ) -> tuple[np.ndarray, np.ndarray, tuple[int, ...]]:
    """Markers of a body that are ever seen: (raw only, mixed, their numbers).

    ``mixed`` = the raw points, except in frames where fewer than 3 raw markers are seen, where
    the gap-repaired ``x, y, z`` of the file fill the holes. A marker never seen is dropped
    (documented repair, noted)."""
    idx = [marker_index(m) for m in numbers]
    raw = run.raw_m[:, idx, :]
    rep = run.markers_m[:, idx, :]
    raw_ok = np.all(np.isfinite(raw), axis=-1)
    seen = raw_ok.any(axis=0) | np.all(np.isfinite(rep), axis=-1).any(axis=0)
    never = [m for m, s in zip(numbers, seen, strict=True) if not s]
    if never:
        notes.append(f"markers {never} never visible: excluded from the rigid-body fit")
    if seen.sum() < MIN_MARKERS:
        raise ValueError(f"run {run.run_id}: markers {never} missing; the body "
                         f"{list(numbers)} needs at least {MIN_MARKERS} markers")
    raw, rep, raw_ok = raw[:, seen], rep[:, seen], raw_ok[:, seen]
    few = raw_ok.sum(axis=1) < MIN_MARKERS
    combined = np.where(raw_ok[..., None], raw, rep)
    if few.any():
        notes.append(f"{int(few.sum())} frames with < {MIN_MARKERS} raw markers of "
                     f"{list(numbers)}: gap-repaired x, y, z used")
    kept = tuple(m for m, s in zip(numbers, seen, strict=True) if s)
    return raw, np.where(few[:, None, None], combined, raw), kept


def _rear_normal(ref: dict[int, np.ndarray], notes: list[str]) -> np.ndarray:
    """``b2`` of the reference shape: normal of the plane through 26, (22+28)/2, (25+31)/2
    (``states.py``); if one of them is missing, the least-squares plane through the available
    ones of 26 and the left/right midpoints (22/28, 24/30, 25/31), pointing right."""
    def mid(a, b):
        return 0.5 * (ref[a] + ref[b]) if a in ref and b in ref else None

    head, wheel = mid(22, 28), mid(25, 31)
    if 26 in ref and head is not None and wheel is not None:
        n = np.cross(head - wheel, ref[26] - wheel)
    else:
        pts = [p for p in (ref.get(26), head, mid(24, 30), wheel) if p is not None]
        if len(pts) < 3:
            raise ValueError("the rear frame's symmetry plane needs 3 of: 26, 22/28, 24/30, "
                             "25/31")
        pts = np.array(pts)
        n = np.linalg.svd(pts - pts.mean(axis=0))[2][-1]
        notes.append("rear-frame plane from the left/right marker midpoints (a plane marker "
                     "is missing)")
    side = next((ref[a] - ref[b] for a, b in ((25, 31), (24, 30), (22, 28))
                 if a in ref and b in ref), np.array([0.0, 1.0, 0.0]))
    n = _unit(n)
    return -n if n @ side < 0 else n


def _axle(ref: dict[int, np.ndarray], notes: list[str]) -> np.ndarray:
    """``e2`` of the reference fork shape: unit(r21 - r27); without a front-wheel marker, the
    handlebar ends unit(r23 - r29) (assumed parallel to the axle: a constant steer offset,
    which does not change the cadence amplitudes)."""
    if 21 in ref and 27 in ref:
        return _unit(ref[21] - ref[27])
    if 23 in ref and 29 in ref:
        notes.append("front axle direction from the handlebar ends (a wheel marker is missing)")
        return _unit(ref[23] - ref[29])
    raise ValueError("the fork needs both front-wheel (21, 27) or both handlebar (23, 29) "
                     "markers")


def fill_gaps(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Linear interpolation over NaN (nearest value at the ends)."""
    ok = np.isfinite(x)
    if ok.all():
        return x
    if not ok.any():
        raise ValueError("no valid sample to interpolate from")
    return np.interp(t, t[ok], x[ok])


def steer_axis_tilt_rad(bicycle: str) -> float:
    """Steer-axis tilt ``lam`` of the run's bicycle (``params.steer_geometry``).

    The original code used 0.2967 (Stratos) and 0.4058 rad (Browser); the project's geometry
    differs by < 0.006 rad, which scales the extracted steer angle by ``cos`` of the difference
    (a relative change below 2e-5).
    """
    return params.steer_geometry({"stratos": "hybrid", "browser": "city"}.get(bicycle, bicycle)
                                 )["lam"]


def extract(run: Run, reference: Run | None = None, lam_rad: float | None = None,
            lowpass_hz: float | None = LOWPASS_HZ) -> Kinematics:
    """Yaw, roll, steer and crank angle of a run from rigid-body fits of its markers.

    Parameters
    ----------
    run
        A dynamic run (:func:`pedalrepro.mocap.reader.read_run`).
    reference
        Optional static run giving the reference shapes; by default the run's own fully visible
        frames (generalised Procrustes mean, :func:`reference_shape`).
    lam_rad
        Steer-axis tilt; default :func:`steer_axis_tilt_rad` of the run's bicycle.
    lowpass_hz
        Zero-phase 4th-order Butterworth low-pass of the angles (``None``/0: off). The default
        :data:`LOWPASS_HZ` keeps the cadence harmonics of interest (5 x 90 rpm = 7.5 Hz) and
        halves the white marker noise of a 100 Hz record.

    Returns
    -------
    Kinematics
        Benchmark convention (Meijaard et al. 2007): roll and steer positive to the right.
    """
    notes: list[str] = []
    lam = steer_axis_tilt_rad(run.bicycle) if lam_rad is None else float(lam_rad)
    t = run.t_s
    _, rear, rear_ids = _body_points(run, REAR_FRAME_MARKERS, notes)
    fork_raw, fork, fork_ids = _body_points(run, FORK_MARKERS, notes)
    if reference is not None:
        rear_ref = reference_shape(reference.markers_m[:, [marker_index(m) for m in rear_ids]])
        fork_ref = reference_shape(reference.markers_m[:, [marker_index(m) for m in fork_ids]])
    else:
        rear_ref, fork_ref = reference_shape(rear), reference_shape(fork)

    # triads on the reference shapes
    b2_ref = _rear_normal(dict(zip(rear_ids, rear_ref, strict=True)), notes)
    e2_ref = _axle(dict(zip(fork_ids, fork_ref, strict=True)), notes)

    rot_b, _, rms_b, drop_b = robust_fit(rear_ref, rear)
    rot_f, _, rms_f, drop_f = robust_fit(fork_ref, fork_raw)
    n_drop = int(np.abs(drop_b).sum() + np.abs(drop_f).sum())
    if n_drop:
        notes.append(f"{n_drop} marker samples more than {OUTLIER_M * 1e3:g} mm off the "
                     "rigid-body fit (spikes) dropped")
    b2 = np.einsum("nij,j->ni", rot_b, b2_ref)
    b1 = _unit(np.cross(b2, N3))
    b3 = np.cross(b1, b2)
    yaw = np.arctan2(b1[:, 1], b1[:, 0])
    roll = np.arctan2(b2[:, 2], b3[:, 2])
    d1 = np.cos(lam) * b1 - np.sin(lam) * b3
    e2 = np.einsum("nij,j->ni", rot_f, e2_ref)
    steer = np.arctan2(-np.sum(e2 * d1, axis=1), np.sum(e2 * b2, axis=1))
    # fewer than 3 raw fork markers: a raw pair about the steer axis, else the repaired markers
    spiked = drop_f < 0  # an outlier among only 3 fork markers: no pair is trustworthy
    steer = _steer_from_pairs(fork_raw, steer, d1, b2, notes, exclude=spiked)
    still = ~np.isfinite(steer) & ~spiked
    if still.any():
        rot_m, _, _, _ = robust_fit(fork_ref, fork[still])
        e2m = np.einsum("nij,j->ni", rot_m, e2_ref)
        steer[still] = np.arctan2(-np.sum(e2m * d1[still], axis=1),
                                  np.sum(e2m * b2[still], axis=1))

    # crank angle from the raw feet markers; across their gaps the unwrapped angle, nearly
    # linear in time, is interpolated (better than the straight-line repair of a foot that moves
    # on a circle); the gap-repaired arrays only if the raw ones miss half the run
    feet = []
    for m in (1, 5):
        raw, rep = run.marker(m, raw=True), run.marker(m)
        seen = np.all(np.isfinite(raw), axis=1).mean()
        feet.append(raw if seen >= 0.5 else np.where(np.isfinite(raw), raw, rep))
    p = feet[0] - feet[1]
    crank = -np.arctan2(np.sum(p * b3, axis=1), np.sum(p * b1, axis=1))
    ok = np.isfinite(crank)
    if ok.sum() < 2:
        raise ValueError(f"run {run.run_id}: feet markers 1 and 5 missing: no crank angle")
    crank_u = _unwrap_across_gaps(t, crank)

    bad_rear, bad_steer = ~np.isfinite(roll), ~np.isfinite(steer)
    bad = bad_rear | bad_steer
    if bad.any():
        notes.append(f"{int(bad_rear.sum())} samples without a rear-frame fit, "
                     f"{int(bad_steer.sum())} without a steer angle: interpolated")
    angles = [fill_gaps(t, np.where(bad_rear, np.nan, yaw)), fill_gaps(t, roll),
              fill_gaps(t, steer)]
    if lowpass_hz:
        fs = run.sample_rate_hz
        if lowpass_hz >= fs / 2:
            raise ValueError(f"lowpass_hz {lowpass_hz} must be below the Nyquist rate {fs / 2}")
        sos = signal.butter(4, lowpass_hz, fs=fs, output="sos")
        angles = [signal.sosfiltfilt(sos, a) for a in angles]
    return Kinematics(t_s=t, yaw_rad=angles[0], roll_rad=angles[1], steer_rad=angles[2],
                      crank_rad=fill_gaps(t, crank_u), rear_rms_m=rms_b, fork_rms_m=rms_f,
                      repaired_fraction=float(bad.mean()), notes=notes, valid=~bad)


def _steer_from_pairs(fork: np.ndarray, steer: np.ndarray, d1: np.ndarray, d2: np.ndarray,
                      notes: list[str], exclude: np.ndarray | None = None) -> np.ndarray:
    """Steer where the fork fit failed (fewer than 3 fork markers) but the rear frame is known.

    Steer is one rotation about the steer axis ``d3``, so the vector between any two visible
    fork markers rotates by ``delta`` in the ``d1``-``d2`` plane: ``delta = alpha - alpha_0``
    with ``alpha = atan2(u.d2, u.d1)`` and ``alpha_0`` the pair's mean offset over the frames
    with a full fit. The pair with the longest projection is used.
    """
    missing = ~np.isfinite(steer) & np.all(np.isfinite(d1), axis=1)
    if exclude is not None:
        missing &= ~exclude
    full = np.isfinite(steer)
    if not missing.any() or full.sum() < 10:
        return steer
    out = steer.copy()
    best_len = np.zeros(len(steer))
    k = fork.shape[1]
    for i in range(k):
        for j in range(i + 1, k):
            u = fork[:, i] - fork[:, j]
            pu1, pu2 = np.sum(u * d1, axis=1), np.sum(u * d2, axis=1)
            alpha = np.arctan2(pu2, pu1)
            length = np.hypot(pu1, pu2)
            ref = full & np.isfinite(alpha)
            if ref.sum() < 10:
                continue
            # a pair whose distance is off its rigid value holds a spike: not used
            dist = np.linalg.norm(u, axis=1)
            rigid = np.abs(dist - np.median(dist[ref])) <= OUTLIER_M
            alpha = np.where(rigid, alpha, np.nan)
            ref &= rigid
            off = np.angle(np.mean(np.exp(1j * (alpha[ref] - steer[ref]))))
            use = missing & np.isfinite(alpha) & (length > best_len)
            out[use] = np.angle(np.exp(1j * (alpha[use] - off)))
            best_len[use] = length[use]
    n = int((missing & np.isfinite(out)).sum())
    if n:
        notes.append(f"{n} samples: steer from a pair of fork markers about the steer axis")
    return out


def _unwrap_across_gaps(t: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Unwrap an angle sampled with gaps: across a gap the number of turns is the one closest
    to the mean rate of the contiguous stretches (the crank turns at a nearly steady cadence)."""
    ok = np.flatnonzero(np.isfinite(angle))
    if ok.size < 2:
        raise ValueError("fewer than 2 samples of the crank angle")
    a = angle[ok]
    da = np.angle(np.exp(1j * np.diff(a)))  # wrapped increments
    dt = np.diff(t[ok])
    step = np.median(dt)
    contiguous = dt <= 1.5 * step
    rate = np.median(da[contiguous] / dt[contiguous]) if contiguous.any() else 0.0
    jumps = ~contiguous
    da[jumps] += 2 * np.pi * np.round((rate * dt[jumps] - da[jumps]) / (2 * np.pi))
    out = np.full_like(angle, np.nan)
    out[ok] = a[0] + np.concatenate([[0.0], np.cumsum(da)])
    return out
