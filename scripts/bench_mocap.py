"""Benchmark of the treadmill-data path: stand-in generation, reading, extraction (one 60 s run).

    python scripts/bench_mocap.py

Prints the median wall time of each step over a few repetitions (no assertions: timings are
measured here, never in tests).
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

import scipy.io

from pedalrepro import config
from pedalrepro.mocap import cadence, kinematics, reader, synthetic


def _time(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main() -> None:
    cfg = config.load()
    mocap = cfg["mocap"]
    run = next(r for r in synthetic.stand_in_runs(mocap) if r.system == "CR")
    t_gen, (mat, _) = _time(lambda: synthetic.simulate_run(run, mocap, cfg["seed"]))
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / f"{run.run_id:04d}.mat"
        scipy.io.savemat(str(path), mat, do_compression=True)
        t_read, r = _time(lambda: reader.read_run(path))
        t_kin, kin = _time(lambda: kinematics.extract(r))
        t_cad, cad = _time(lambda: cadence.detect_cadence(r, kin))
    n = r.t_s.size
    print(f"one {n / r.sample_rate_hz:.0f} s run ({n} samples x 31 markers):")
    for name, t in (("generate (stand-in)", t_gen), ("read .mat", t_read),
                    ("rigid-body fits + angles", t_kin), ("cadence", t_cad)):
        print(f"  {name:26s} {t * 1e3:8.1f} ms")
    print(f"  cadence {cad.cadence_rpm:.3f} rpm (stand-in {run.cadence_rpm:g})")


if __name__ == "__main__":
    main()
