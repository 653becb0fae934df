"""Benchmark of the linear part on the thesis grids (config/config.yaml).

1. Particular solution of one model on the 10302-point PS grid (Sec 3.1.2.2.1): the batched
   complex solve of :func:`pedalrepro.response.particular_solution` against a per-point Python
   loop (same results checked). Target: < 50 ms.
2. The 676 analytic time solutions (LA, 180 s at the configured sample rate) of one model and
   their Hann-DFT amplitudes at the cadence. Target: < 10 s.

Usage: ``python scripts/bench_linear.py [MODEL]`` (default HR). Prints a small table.
"""

from __future__ import annotations

import sys
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


def main(model_name: str = "HR") -> None:
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

    rows = [
        (f"PS batched, {v.size * w.size} points x {len(h.n)} harmonics", t_ps, "< 0.050 s"),
        ("PS per-point Python loop (reference)", t_loop, ""),
        (f"LA analytic time solutions, {tv.size * tw.size} runs x {len(t)} samples", t_la, ""),
        ("Hann-DFT amplitude at the cadence, all runs", t_dft, ""),
        ("LA + DFT total", t_la + t_dft, "< 10 s"),
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
    main(*sys.argv[1:])
