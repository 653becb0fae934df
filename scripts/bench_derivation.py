"""Where the one-time derivation of the non-linear models goes: the seconds of each stage.

    python scripts/bench_derivation.py [--variants plain legs arms legs_arms]

Derives each model variant of ``rules/nonlinear.smk`` (``CODEGEN_VARIANTS``: the plain Whipple
bicycle of benchmark, HS, HR and CR; with the moving legs of NP; with CF's arm loops; both) from
nothing, in a temporary cache folder (``PEDALREPRO_CACHE``; the user's cache is neither read nor
written), one after another, and prints the seconds of each stage:

- ``symbrim_assembly``: SymBRiM's Whipple bicycle, the leg bodies, the arm loops;
- ``kane_equations``: Kane's mass matrix and forcing (``KanesMethod.kanes_equations``);
- ``constraints_energy``: the velocity constraints, their time derivative, the energy;
- ``substitution``: plain symbols for the specified motions and coordinates, the explicit arm
  coordinates (:func:`pedalrepro.nonlinear.symbolic.derive`);
- ``c_code``, ``python_code``: common subexpressions (``sympy.cse``) and printing
  (:mod:`pedalrepro.nonlinear.codegen`);
- ``c_compile``: gcc of the generated C with the hand-written driver and integrator
  (:func:`pedalrepro.nonlinear.library.compiled_library`).

The pipeline runs the four variants as four jobs, two at once with ``-j2``. Nothing is written
outside the temporary folder; the numbers are printed.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time

VARIANTS = ("plain", "legs", "arms", "legs_arms")
STAGES = ("symbrim_assembly", "kane_equations", "constraints_energy", "substitution", "c_code",
          "python_code", "c_compile")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--variants", nargs="+", default=list(VARIANTS), choices=VARIANTS)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="pedalrepro-derivation-") as tmp:
        os.environ["PEDALREPRO_CACHE"] = tmp  # before the cache folder is first asked for
        start = time.perf_counter()
        import symbrim  # noqa: F401
        import sympy.physics.mechanics  # noqa: F401  (imported by the derivation itself)

        from pedalrepro.nonlinear import codegen, library, symbolic

        imports_s = time.perf_counter() - start
        rows = {}
        for variant in args.variants:
            options = symbolic.ModelOptions(legs="legs" in variant, arms="arms" in variant)
            timings: dict[str, float] = {}
            start = time.perf_counter()
            codegen.generated_source(options, timings)
            mark = time.perf_counter()
            library.compiled_library(options)
            timings["c_compile"] = time.perf_counter() - mark
            timings["total"] = time.perf_counter() - start
            rows[variant] = timings
    width = max(len(s) for s in STAGES + ("total",))
    print(f"imports (sympy, symbrim; once per job): {imports_s:.1f} s")
    print(f"{'stage':<{width}}  " + "  ".join(f"{v:>9}" for v in rows) + "      sum")
    for stage in STAGES + ("total",):
        values = [rows[v].get(stage, 0.0) for v in rows]
        print(f"{stage:<{width}}  " + "  ".join(f"{x:9.1f}" for x in values)
              + f"  {sum(values):7.1f}")


if __name__ == "__main__":
    main()
