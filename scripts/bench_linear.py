"""Benchmark of the linear part on the thesis grids (config/config.yaml).

1. Particular solution of one model on the 10302-point PS grid (Sec 3.1.2.2.1): the batched
   complex solve of :func:`pedalrepro.response.particular_solution` against a per-point Python
   loop (same results checked). Target: < 50 ms.
2. The 676 analytic time solutions (LA, 180 s at the configured sample rate) of one model and
   their Hann-DFT amplitudes at the cadence. Target: < 10 s.
3. The numerical time solutions (LN, Dormand-Prince at the thesis's ode45 tolerances, fall
   event) through the compiled integrator against ``scipy.integrate.solve_ivp`` for the same
   runs in the same process (every ``--ln-stride``-th speed and cadence of the time grid;
   ``--ln-stride 1``: all 676), their largest amplitude difference, and the speed-up; then the
   whole compiled LN sweep of the model (all runs + Hann DFT), timed directly.

Usage: ``python scripts/bench_linear.py [MODEL] [--ln-stride K]`` (default HR, K = 3). Prints a
small table.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from pedalrepro import config, evaluation, linear, response


def best_of(func, repeat: int) -> tuple[float, object]:
    best, out = np.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        best = min(best, time.perf_counter() - t0)
    return best, out


def ln_comparison(model, h, v, w, t, fs, lin) -> list[tuple[str, float, str]]:
    """LN compiled vs solve_ivp on the runs ``v x w``; rows of the table (and prints a line)."""
    kw = dict(rtol=lin["rtol"], atol=lin["atol"], fall_roll_rad=lin["fall_roll_rad"])
    t0 = time.perf_counter()
    fast = response.numerical_time_solutions(model, v, w, h, t, **kw)
    t_fast = time.perf_counter() - t0
    t0 = time.perf_counter()
    slow = response.numerical_time_solutions(model, v, w, h, t, compiled=False, **kw)
    t_slow = time.perf_counter() - t0
    ra, _ = response.cadence_amplitudes(fast, fs)
    rb, _ = response.cadence_amplitudes(slow, fs)
    forced = (w > 0)[None, :] & np.isfinite(rb)
    rel = np.abs(ra - rb)[forced] / np.abs(rb)[forced]
    same_fall = int(np.sum(fast.fell == slow.fell))
    print(f"LN compiled vs solve_ivp on {v.size * w.size} runs: amplitude at the cadence, largest "
          f"relative difference {rel.max():.2g}, median {np.median(rel):.2g}; fall flags equal "
          f"in {same_fall} of {fast.fell.size}; largest fall-time difference "
          f"{np.max(np.abs(fast.t_end_s - slow.t_end_s)):.2g} s")
    n = v.size * w.size
    return [(f"LN solve_ivp (scipy RK45, Python rhs), {n} runs", t_slow, ""),
            (f"LN compiled Dormand-Prince (same runs), {n} runs", t_fast,
             f"speed-up {t_slow / t_fast:.0f}x")]


def main(model_name: str = "HR", ln_stride: int = 3) -> None:
    cfg = config.load()
    model = linear.linear_model(model_name)
    lin = cfg["linear"]
    h = response.forcing(model_name, lin["harmonics"])
    v, w = response.speed_cadence_grid(lin["ps_speed_step_m_s"], lin["ps_speed_max_m_s"],
                                       lin["ps_omega_step_rad_s"], lin["ps_omega_max_rad_s"])
    t_ps, (roll, _) = best_of(lambda: response.particular_solution(
        model, v[:, None], w[None, :], h), 5)
    t_loop, (roll_loop, _) = best_of(lambda: response.particular_solution_loop(model, v, w, h), 1)
    assert np.allclose(roll, roll_loop, rtol=1e-10, atol=1e-15)

    tv, tw = response.speed_cadence_grid(lin["time_speed_step_m_s"], lin["time_speed_max_m_s"],
                                         lin["time_omega_step_rad_s"], lin["time_omega_max_rad_s"])
    t = response.time_samples(lin["duration_s"], lin["sample_rate_hz"])
    fs = cfg["linear"]["sample_rate_hz"]
    t0 = time.perf_counter()
    sol = response.analytic_time_solution(model, tv, tw, h, t, cfg["linear"]["fall_roll_rad"])
    t_la = time.perf_counter() - t0
    t0 = time.perf_counter()
    ra, _ = response.cadence_amplitudes(sol, fs)
    t_dft = time.perf_counter() - t0
    rp, _ = response.particular_solution(model, tv[:, None], tw[None, :], h)
    rd = evaluation.relative_difference(np.abs(rp[..., 0]), ra)
    stable = evaluation.stable_speed_mask(model_name, tv)[:, None] & (tw[None, :] > 0)
    st = evaluation.rd_stats(rd, stable)

    lin = cfg["linear"]
    ln_rows = ln_comparison(model, h, tv[::ln_stride], tw[::ln_stride], t, fs, lin)
    t0 = time.perf_counter()
    ln = response.numerical_time_solutions(model, tv, tw, h, t, rtol=lin["rtol"],
                                           atol=lin["atol"], fall_roll_rad=lin["fall_roll_rad"])
    response.cadence_amplitudes(ln, fs)
    t_ln = time.perf_counter() - t0
    per_run_slow = ln_rows[0][1] / (tv[::ln_stride].size * tw[::ln_stride].size)
    rows = [
        (f"PS batched, {v.size * w.size} points x {len(h.n)} harmonics", t_ps, "< 0.050 s"),
        ("PS per-point Python loop (reference)", t_loop, ""),
        (f"LA analytic time solutions, {tv.size * tw.size} runs x {len(t)} samples", t_la, ""),
        ("Hann-DFT amplitude at the cadence, all runs", t_dft, ""),
        ("LA + DFT total", t_la + t_dft, "< 10 s"),
        *ln_rows,
        (f"LN compiled sweep + DFT, all {tv.size * tw.size} runs", t_ln,
         f"solve_ivp extrapolated: {per_run_slow * tv.size * tw.size:.0f} s"),
    ]
    print(f"model {model_name}, thesis grids (config/config.yaml)")
    print(f"{'step':<62} {'time (s)':>10}  target")
    for name, sec, target in rows:
        print(f"{name:<62} {sec:>10.4f}  {target}")
    print(f"speed-up of the batched PS over the loop: {t_loop / t_ps:.0f}x")
    print(f"{int(sol.fell.sum())} of {sol.fell.size} runs fell; evaluation point 3b (PS vs LA "
          f"Hann-DFT, roll) over the self-stable region: median {st.median:.3g} %, range "
          f"{st.minimum:.3g}-{st.maximum:.3g} % ({st.count} runs)")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model", nargs="?", default="HR")
    ap.add_argument("--ln-stride", type=int, default=3,
                    help="compare LN compiled vs solve_ivp on every K-th speed and cadence")
    args = ap.parse_args()
    main(args.model, args.ln_stride)
