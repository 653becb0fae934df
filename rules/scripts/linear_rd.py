"""Snakemake script: relative-difference maps of the linear evaluation points (Eq 3.26).

One npz per model with the maps, plus results/tables/rd_summary.csv: median and range of each
map over the self-stable region (points 1c, 2b, 3a, 3b) and over the normal-cycling ellipse
(points 4, 5, 6), and over the low-speed / high-cadence corner for 1c (Sec 3.2.4).
"""

import sys

import numpy as np
import pandas as pd

from pedalrepro import evaluation, gears, spectral

sys.stderr = open(snakemake.log[0], "w")  # noqa: SIM115
lin = snakemake.params.normal_cycling
models = list(snakemake.params.models)
ps = {m: dict(np.load(p)) for m, p in zip(models, snakemake.input.ps, strict=True)}
la = {m: dict(np.load(p)) for m, p in zip(models, snakemake.input.la, strict=True)}
ln = {m: dict(np.load(p)) for m, p in zip(models, snakemake.input.ln, strict=True)}
rows = []


def summary(model, point, coord, region, rd, mask):
    st = evaluation.rd_stats(rd, mask)
    rows.append({"model": model, "point": point, "coordinate": coord, "region": region,
                 "median_percent": np.nan if st is None else st.median,
                 "min_percent": np.nan if st is None else st.minimum,
                 "max_percent": np.nan if st is None else st.maximum,
                 "count": 0 if st is None else st.count})


for m, path in zip(models, snakemake.output.maps, strict=True):
    p, a, n = ps[m], la[m], ln[m]
    vp, wp = p["speed_m_s"], p["omega_rad_s"]
    vt, wt = a["speed_m_s"], a["omega_rad_s"]
    stable_p = evaluation.stable_speed_mask(m, vp)[:, None] & (wp[None, :] > 0)
    stable_t = evaluation.stable_speed_mask(m, vt)[:, None] & (wt[None, :] > 0)
    ellipse = gears.inside_ellipse(vp[:, None], wp[None, :], lin["normal_cycling_speed_kmh"],
                                   lin["normal_cycling_cadence_rpm"])
    corner = (vp[:, None] <= 1.0) & (wp[None, :] >= 3 * np.pi)
    out = {"speed_m_s": vp, "omega_rad_s": wp, "time_speed_m_s": vt, "time_omega_rad_s": wt}
    # PS at the time grid (for 3b): rows/cols of the PS solved again exactly at the time grid
    from pedalrepro import linear, response

    h = response.forcing(m, snakemake.params.harmonics)
    k = int(np.nonzero(h.n == 1)[0][0])
    r_t, s_t = response.particular_solution(linear.linear_model(m), vt[:, None], wt[None, :], h)
    ps_t = {"roll": np.abs(r_t[..., k]), "steer": np.abs(s_t[..., k])}
    for coord in ("roll", "steer"):
        amp = p[f"{coord}_amp_rad"]
        cam = float(p[f"cam_{coord}_rad"])
        out[f"1c_{coord}"] = evaluation.relative_difference(amp, np.full_like(amp, cam))
        out[f"2b_{coord}"] = evaluation.relative_difference(a[f"{coord}_amp_rad"],
                                                            a[f"{coord}_amp_h1_rad"])
        out[f"3a_{coord}"] = evaluation.relative_difference(a[f"{coord}_amp_rad"],
                                                            n[f"{coord}_amp_rad"])
        out[f"3b_{coord}"] = evaluation.relative_difference(ps_t[coord], a[f"{coord}_amp_rad"])
        ref = float(p[f"reference_{coord}_rad"])
        out[f"4_{coord}"] = evaluation.relative_difference(np.full_like(amp, ref), amp)
        out[f"4_{coord}"][:, wp == 0] = 100.0  # no forcing: the amplitude is 0, RD exactly 100 %
        summary(m, "1c", coord, "self-stable", out[f"1c_{coord}"], stable_p)
        summary(m, "1c", coord, "v<=1 m/s, w>=3pi rad/s", out[f"1c_{coord}"], corner)
        for point in ("2b", "3a", "3b"):
            summary(m, point, coord, "self-stable", out[f"{point}_{coord}"], stable_t)
        summary(m, "4", coord, "normal cycling", out[f"4_{coord}"], ellipse)
    # 3a with tight tolerances, at the six example points that did not fall (LN converges to LA)
    fs = float(a["sample_rate_hz"])
    ok = ~np.asarray(a["example_fell"]) & (np.asarray(a["example_omega_rad_s"]) > 0)
    for coord in ("roll", "steer"):
        amps = {}
        for key, d in (("LA", a[f"example_{coord}_rad"]), ("LN", n[f"example_{coord}_rad"]),
                       ("LN_tight", n[f"example_{coord}_tight_rad"])):
            amps[key] = np.array([spectral.amplitude_at(x[np.isfinite(x)], fs, wk / (2 * np.pi))
                                  if good else np.nan
                                  for x, wk, good in zip(d, a["example_omega_rad_s"], ok,
                                                         strict=True)])
        summary(m, "3a", coord, "example points, thesis tolerances",
                evaluation.relative_difference(amps["LA"], amps["LN"]), ok)
        summary(m, "3a", coord, "example points, tight tolerances",
                evaluation.relative_difference(amps["LA"], amps["LN_tight"]), ok)
    np.savez(path, **out)

# evaluation points 5 and 6: model pairs on the PS grid
pairs = {}
for point, plist in evaluation.MODEL_PAIRS.items():
    for ref_m, cmp_m in plist:
        if ref_m not in ps or cmp_m not in ps:
            continue
        vp, wp = ps[ref_m]["speed_m_s"], ps[ref_m]["omega_rad_s"]
        ellipse = gears.inside_ellipse(vp[:, None], wp[None, :], lin["normal_cycling_speed_kmh"],
                                       lin["normal_cycling_cadence_rpm"])
        for coord in ("roll", "steer"):
            rd = evaluation.relative_difference(ps[ref_m][f"{coord}_amp_rad"],
                                                ps[cmp_m][f"{coord}_amp_rad"])
            pairs[f"{point}_{cmp_m}_vs_{ref_m}_{coord}"] = rd
            summary(f"{cmp_m} vs {ref_m}", point, coord, "normal cycling", rd, ellipse)
            summary(f"{cmp_m} vs {ref_m}", point, coord, "whole grid", rd, np.isfinite(rd))
np.savez(snakemake.output.pairs, speed_m_s=vp, omega_rad_s=wp, **pairs)
df = pd.DataFrame(rows)
df.to_csv(snakemake.output.table, index=False, float_format="%.6g")
print(df.to_string(), file=sys.stderr)
