"""The one table of figures: id -> drawing function and the files it reads.

Every part (``section2``, ``linear``, ``nonlinear``, ``validation``, and ``periodic`` beyond the
thesis) registers its figures here.
The Snakemake rules (``rules/figures.smk``) take their inputs and outputs from this table and
draw with :func:`write`; the notebooks show the same figure with :func:`draw` (or
``figures.show(None, id)``, the rule's own file). Drawing reads files under ``results/`` and
never computes a sweep: what a figure needs beyond the sweep rules' files is written by the rules
``linear_figure_data`` and ``validation_figure_data`` (:mod:`pedalrepro.figdata`).

Input names are the drawing function's keyword arguments; a dotted name ``"time.LA"`` groups
files into a dict (``time={"LA": ..., "LN": ...}``). Files are loaded by suffix: ``.npz`` -> dict
of arrays (the time-solution files ``time.<method>`` through :func:`pedalrepro.timesolution.read`,
which checks their keys), ``.csv`` -> DataFrame, ``.json`` -> dict.
"""

from __future__ import annotations

import importlib
import json
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .. import paths, timesolution
from .page import save, style

__all__ = [
    "MODULES", "TIME_METHODS", "OPTIONAL_METHODS", "MODELS4", "PARTS", "PERIODIC_METHODS",
    "PERIODIC_FINE_METHOD", "COMPLETE", "PARTIAL", "MISSING", "FigureSpec", "FIGURES", "spec",
    "ids", "groups", "code_sources", "inputs", "load_inputs", "draw", "write", "completeness",
]

#: The drawing modules of :mod:`pedalrepro.figures`, imported by name when a figure is drawn
#: (:meth:`FigureSpec.callable`), so that a group's rule depends on its own modules only
#: (:func:`code_sources`), not on every part's.
MODULES: tuple[str, ...] = ("linear", "nonlinear", "periodic", "section2", "validation")

#: Time-solution methods of the thesis; NT and NP are optional inputs (the non-linear part).
TIME_METHODS: tuple[str, ...] = ("LA", "LN", "NT", "NP")
OPTIONAL_METHODS: tuple[str, ...] = ("NT", "NP")
#: The thesis's four systems, pedalrepro.params.MODELS (tests/test_params.py pins the two
#: equal). Spelled here, like every figure id, because importing pedalrepro.params would put
#: the parameter files into every figure group's code inputs (each figure would rerun when
#: one changes; tests/test_change_tracking.py, the groups' shared code).
MODELS4: tuple[str, ...] = ("HS", "CF", "HR", "CR")
PARTS: tuple[str, ...] = ("section2", "linear", "nonlinear", "validation", "periodic")
#: Methods of the periodic orbit maps, and of their finer-grid figure (rules/periodic.smk).
PERIODIC_METHODS: tuple[str, ...] = ("NT", "NP")
PERIODIC_FINE_METHOD = "NT"

COMPLETE, PARTIAL, MISSING = "complete", "partial", "missing"


@dataclass(frozen=True)
class FigureSpec:
    """One registered figure.

    Attributes
    ----------
    id : str
        Figure id (``data/figure_ids.yaml``, e.g. ``"fig_3_10"``), also the file stem.
    part : str
        Thesis part (one of :data:`PARTS`).
    group : str
        Snakemake job that draws it (figures of a group share one Python start-up).
    function : str
        ``"<module>.<function>"`` in :mod:`pedalrepro.figures`: the id itself when the function
        draws this id only, ``figs_<topic>`` when it draws several
        (``tests/figures/test_figure_names.py``).
    inputs : dict
        Keyword argument -> file relative to the results folder.
    kwargs : dict
        Fixed keyword arguments.
    optional : frozenset
        Input names whose file may be absent (drawn with a note when missing).
    complete_when : tuple
        ``(input name, array key or "")`` pairs that must be present for the figure to show
        every method and panel of the thesis (the report's complete / partial count).
    """

    id: str
    part: str
    group: str
    function: str
    inputs: Mapping[str, str]
    kwargs: Mapping[str, Any] = field(default_factory=dict)
    optional: frozenset = frozenset()
    complete_when: tuple[tuple[str, str], ...] = ()

    @property
    def module(self) -> str:
        """The drawing module's name in :mod:`pedalrepro.figures` (one of :data:`MODULES`)."""
        return self.function.rsplit(".", 1)[0]

    def callable(self) -> Callable:
        module, func = self.function.rsplit(".", 1)
        if module not in MODULES:
            raise KeyError(f"{self.id}: {module!r} is not a drawing module ({', '.join(MODULES)})")
        return getattr(importlib.import_module(f"{__package__}.{module}"), func)


FIGURES: dict[str, FigureSpec] = {}


def _register(fid: str, part: str, group: str, function: str, inputs: Mapping[str, str],
              kwargs: Mapping[str, Any] | None = None, optional=(), complete_when=()) -> None:
    if fid in FIGURES:
        raise ValueError(f"figure {fid} registered twice")
    FIGURES[fid] = FigureSpec(fid, part, group, function, dict(inputs), dict(kwargs or {}),
                              frozenset(optional), tuple(complete_when))


def _i(name: str) -> str:
    return f"{paths.LAYOUT['intermediate']}/{name}"


def _t(name: str) -> str:
    return f"{paths.LAYOUT['tables']}/{name}.csv"


# ---- section 2 (Sec 2, Appendix D) -----------------------------------------------------------
for _fid in ("fig_2_2", "fig_2_3", "fig_2_4", "fig_2_5", "fig_2_6", "fig_2_7", "fig_d_1"):
    _register(_fid, "section2", "section2", f"section2.{_fid}",
              {"data": _i("section2/disturbance_hybrid.npz")})

# ---- linear (Sec 3, Appendices F, G, H) ------------------------------------------------------
_register("fig_3_6", "linear", "linear_overview", "linear.figs_eigenvalues",
          {"eigen.benchmark": _i("eigen/benchmark.npz")}, {"models": ("benchmark",)})
_register("fig_3_9", "linear", "linear_overview", "linear.figs_eigenvalues",
          {f"eigen.{m}": _i(f"eigen/{m}.npz") for m in MODELS4}, {"models": MODELS4})
_register("fig_3_8", "linear", "linear_overview", "linear.fig_3_8",
          {"grid": _i("figures/gear_grid.npz")})
_register("fig_3_30", "linear", "linear_overview", "linear.fig_3_30",
          {"cam": _i("figures/cam_HS.npz")}, {"model": "HS"})
for _fid, _m in (("fig_3_31", "HS"), ("fig_f_1", "CF"), ("fig_f_2", "HR"), ("fig_f_3", "CR")):
    _register(_fid, "linear", "linear_overview", "linear.figs_neglected_momenta",
              {"data": _i(f"figures/neglected_{_m}.npz")}, {"model": _m})
_register("fig_3_35", "linear", "linear_overview", "linear.fig_3_35",
          {**{f"ps.{m}": _i(f"ps/{m}.npz") for m in MODELS4},
           "grid": _i("figures/gear_grid.npz")}, {"models": MODELS4})
_register("fig_3_36", "linear", "linear_overview", "linear.figs_gear_sections",
          {"sections": _i("figures/gear_sections_models.npz")}, {"models": MODELS4})
_register("fig_g_8", "linear", "linear_overview", "linear.figs_gear_sections",
          {"sections": _i("figures/gear_sections_benchmark.npz")}, {"models": ("benchmark",)})
_register("fig_g_7", "linear", "linear_overview", "linear.fig_g_7",
          {"ps": _i("ps/benchmark.npz"), "eig": _i("eigen/benchmark.npz")})
_register("fig_3_37", "linear", "linear_overview", "linear.fig_3_37",
          {**{f"rd.{m}": _i(f"rd/{m}.npz") for m in MODELS4},
           **{f"eigen.{m}": _i(f"eigen/{m}.npz") for m in MODELS4}}, {"models": MODELS4})
_register("fig_3_38", "linear", "linear_overview", "linear.fig_3_38",
          {"pairs": _i("rd/pairs.npz")})


def _time_inputs(model: str, first: Mapping[str, str]) -> dict[str, str]:
    return {**first, **{f"time.{m}": _i(f"time/{m}_{model}.npz") for m in TIME_METHODS}}


def _time_group(model: str) -> str:
    """Figure group of a model's time-history figures: HS and CF in one job, HR and CR in
    another, so that each pair is drawn as soon as its own NT/NP sweeps are done (one group of
    all 16 figures took 26-34 s after the slowest sweep, NP HS, on the critical path)."""
    return "linear_time_hs_cf" if model in ("HS", "CF") else "linear_time_hr_cr"


def _time_figure(fid: str, function: str, model: str, coord: str, group: str, first: dict,
                 series: bool = False, **kw) -> None:
    key = f"series_{coord}_rad" if series else ""
    _register(fid, "linear", group, function, _time_inputs(model, first),
              {"model": model, "coord": coord, **kw},
              optional=[f"time.{m}" for m in OPTIONAL_METHODS],
              complete_when=[(f"time.{m}", key) for m in TIME_METHODS])


# (time-history figure, its spectrum figure, model, coordinate): Figs 3.10-3.17 and 3.20-3.27
for _ft, _ff, _m, _c in (("fig_3_10", "fig_3_20", "HS", "roll"),
                         ("fig_3_11", "fig_3_21", "HS", "steer"),
                         ("fig_3_12", "fig_3_22", "CF", "roll"),
                         ("fig_3_13", "fig_3_23", "CF", "steer"),
                         ("fig_3_14", "fig_3_24", "HR", "roll"),
                         ("fig_3_15", "fig_3_25", "HR", "steer"),
                         ("fig_3_16", "fig_3_26", "CR", "roll"),
                         ("fig_3_17", "fig_3_27", "CR", "steer")):
    _ps = {"ps": _i(f"ps/{_m}.npz"), "eig": _i(f"eigen/{_m}.npz")}
    _time_figure(_ft, "linear.figs_ps_time", _m, _c, _time_group(_m), _ps)
    _time_figure(_ff, "linear.figs_fft", _m, _c, "linear_spectra", _ps)
for _fid, _m, _c in (("fig_g_1", "HS", "roll"), ("fig_g_2", "CF", "roll"),
                     ("fig_g_3", "CF", "steer"), ("fig_g_4", "HR", "roll"),
                     ("fig_g_5", "HR", "steer"), ("fig_g_6", "CR", "roll")):
    _time_figure(_fid, "linear.figs_ps_time", _m, _c, _time_group(_m),
                 {"ps": _i(f"ps/{_m}.npz"), "eig": _i(f"eigen/{_m}.npz")}, single_harmonic=True)
for _fid, _func, _m, _g in (("fig_3_18", "linear.figs_series_time", "HS", _time_group("HS")),
                            ("fig_3_19", "linear.figs_series_time", "CR", _time_group("CR")),
                            ("fig_3_28", "linear.figs_series_fft", "HS", "linear_spectra"),
                            ("fig_3_29", "linear.figs_series_fft", "CR", "linear_spectra")):
    _time_figure(_fid, _func, _m, "steer", _g,
                 {"ps": _i(f"ps/{_m}.npz"), "eig": _i(f"eigen/{_m}.npz")}, series=True)
# Fig H.6's caption repeats "roll, HR" (Fig 3.32); the set of appendix figures implies HR steer.
for _fid, _m, _c in (("fig_3_32", "HR", "roll"), ("fig_3_33", "CF", "roll"),
                     ("fig_h_1", "HS", "roll"), ("fig_h_2", "HS", "steer"),
                     ("fig_h_3", "CF", "steer"), ("fig_h_4", "CR", "roll"),
                     ("fig_h_5", "CR", "steer"), ("fig_h_6", "HR", "steer")):
    _register(_fid, "linear", "linear_rd", "linear.figs_rd_points",
              _time_inputs(_m, {"rd": _i(f"rd/{_m}.npz"), "eig": _i(f"eigen/{_m}.npz")}),
              {"model": _m, "coord": _c},
              optional=[f"time.{m}" for m in OPTIONAL_METHODS],
              complete_when=[(f"time.{m}", "") for m in TIME_METHODS])

# ---- non-linear (Sec 3.1.1.3, 3.2.4, Appendix E) ---------------------------------------------
_register("fig_3_34", "nonlinear", "nonlinear", "nonlinear.fig_3_34",
          {"maps": _i("nonlinear/rd_maps.npz"),
           **{f"eigen.{m}": _i(f"eigen/{m}.npz") for m in MODELS4}},
          complete_when=[("maps", f"{m}_{c}_ps_np") for m in MODELS4 for c in ("roll", "steer")])
_register("fig_e_1", "nonlinear", "nonlinear", "nonlinear.fig_e_1",
          {"cf": _i("nonlinear/eigen_cf_own.npz"),
           "cf_original_seat": _i("nonlinear/eigen_cf_original_seat.npz")})
# Not thesis figures: the six example runs of NT against NP per model (the book's Sec 3.4).
for _fid, _m in (("nonlinear_examples_HS", "HS"), ("nonlinear_examples_CF", "CF"),
                ("nonlinear_examples_HR", "HR"), ("nonlinear_examples_CR", "CR")):
    _register(_fid, "nonlinear", "nonlinear", "nonlinear.figs_example_runs",
              {"nt": _i(f"time/NT_{_m}.npz"), "np_": _i(f"time/NP_{_m}.npz")}, {"model": _m})
_register("nonlinear_linearisation_vs_appendix_b", "nonlinear", "nonlinear",
          "nonlinear.nonlinear_linearisation_vs_appendix_b",
          {"table": _t("linearisation_vs_appendix_b")})

# ---- validation (Sec 4.2) --------------------------------------------------------------------
_VALIDATION = {"per_run": _t("validation_runs"), "series": _i("mocap/series.npz"),
               "source": _i("mocap/source.json"), "model": _i("figures/validation.npz")}
for _s, (_ft, _ff) in {"HS": ("fig_4_2", "fig_4_6"), "CF": ("fig_4_3", "fig_4_7"),
                       "HR": ("fig_4_4", "fig_4_8"), "CR": ("fig_4_5", "fig_4_9")}.items():
    _register(_ft, "validation", "validation", "validation.figs_time_series", _VALIDATION,
              {"system": _s})
    _register(_ff, "validation", "validation", "validation.figs_frequency_domain", _VALIDATION,
              {"system": _s})
_register("fig_4_10", "validation", "validation", "validation.fig_4_10", _VALIDATION)
_register("fig_4_11", "validation", "validation", "validation.fig_4_11", _VALIDATION)
# Not a thesis figure: the REAL public-subset run (measured vs model, time and spectrum), or a
# panel saying the build has none.
_register("real_run_panel", "validation", "validation", "validation.real_run_panel",
          {"source": _VALIDATION["source"], "model": _VALIDATION["model"]})


# ---- periodic orbits (beyond the thesis; pedalrepro.periodic, rules/periodic.smk) -------------
for _fid, _m in (("periodic_maps_HS", "HS"), ("periodic_maps_CF", "CF"),
                ("periodic_maps_HR", "HR"), ("periodic_maps_CR", "CR")):
    _register(_fid, "periodic", "periodic", "periodic.figs_orbit_maps",
              {**{f"orbits.{k}": _i(f"periodic/thesis_{k}_{_m}.npz") for k in PERIODIC_METHODS},
               **{f"sims.{k}": _i(f"time/{k}_{_m}.npz") for k in PERIODIC_METHODS}},
              {"model": _m, "methods": PERIODIC_METHODS},
              optional=[f"sims.{k}" for k in PERIODIC_METHODS])
_register("periodic_continuation", "periodic", "periodic", "periodic.periodic_continuation",
          {f"branches.{m}": _i(f"periodic/branch_{m}.npz") for m in MODELS4})
_register("periodic_fine_maps", "periodic", "periodic", "periodic.periodic_fine_maps",
          {f"fine.{m}": _i(f"periodic/fine_{PERIODIC_FINE_METHOD}_{m}.npz") for m in MODELS4},
          {"method": PERIODIC_FINE_METHOD})


# ---- using the table ------------------------------------------------------------------------

def spec(fid: str) -> FigureSpec:
    """The registered figure ``fid`` (KeyError naming the id and where figures are listed)."""
    try:
        return FIGURES[fid]
    except KeyError:
        raise KeyError(f"{fid!r} is not a registered figure (pedalrepro.figures.registry)") \
            from None


def ids(part: str | None = None, group: str | None = None) -> list[str]:
    """Figure ids, optionally of one part or one job group, sorted."""
    return sorted(f for f, s in FIGURES.items()
                  if (part is None or s.part == part) and (group is None or s.group == group))


def groups() -> list[str]:
    """The Snakemake job groups, sorted."""
    return sorted({s.group for s in FIGURES.values()})


def code_sources(group: str) -> list[str]:
    """Source files whose import closure is the code of figure group ``group``'s rule, relative
    to the repository: the drawing modules of its figures (``src/pedalrepro/figures/<m>.py``).
    ``rules/figures.smk`` adds ``scripts/figures.py`` (this registry and the page style) and
    takes :func:`pedalrepro.dependencies.code_inputs` of both, so editing one part's drawing
    code reruns that part's figures only."""
    modules = sorted({s.module for s in FIGURES.values() if s.group == group})
    if not modules:
        raise KeyError(f"{group!r} is not a figure group ({', '.join(groups())})")
    return [f"src/pedalrepro/figures/{m}.py" for m in modules]


def inputs(fid: str, root: str | Path | None = None,
           time_methods: Sequence[str] = TIME_METHODS) -> list[str]:
    """Files figure ``fid`` reads under ``root`` (default: the results folder), as strings;
    optional time-solution files only for the methods in ``time_methods`` (the rules pass the
    methods this build computes)."""
    s = spec(fid)
    base = paths.results() if root is None else Path(root)
    out = []
    for name, rel in s.inputs.items():
        if name in s.optional and name.split(".")[-1] not in time_methods:
            continue
        out.append(str(base / rel))
    return out


def _load(path: Path):
    if path.suffix == ".npz":
        with np.load(path, allow_pickle=False) as d:
            return {k: d[k] for k in d.files}
    if path.suffix == ".csv":
        import pandas as pd

        return pd.read_csv(path)
    if path.suffix == ".json":
        return json.loads(path.read_text())
    raise ValueError(f"{path}: no loader for {path.suffix!r} files")


def load_inputs(fid: str, root: str | Path | None = None) -> dict[str, Any]:
    """The keyword arguments of figure ``fid``: its files loaded, dotted names grouped; an
    absent optional file is left out, an absent required one is a FileNotFoundError."""
    s = spec(fid)
    base = paths.results() if root is None else Path(root)
    args: dict[str, Any] = {}
    for name, rel in s.inputs.items():
        path = base / rel
        if not path.exists():
            if name in s.optional:
                continue
            raise FileNotFoundError(f"{fid} reads {path}, which does not exist (run the "
                                    "pipeline: snakemake <that file>)")
        head, _, key = name.partition(".")
        # time-solution files are read (and their keys checked) by their own module
        value = timesolution.read(path) if head == "time" else _load(path)
        if key:
            args.setdefault(head, {})[key] = value
        else:
            args[head] = value
    return args


def draw(fid: str, root: str | Path | None = None):
    """Draw figure ``fid`` from the files under ``root`` (default: the results folder), in the
    project's style; returns the matplotlib Figure."""
    s = spec(fid)
    args = load_inputs(fid, root)
    with style():
        return s.callable()(**args, **s.kwargs)


def write(fids: Sequence[str], root: str | Path | None = None) -> list[Path]:
    """Draw and save figures (PNG and PDF, :func:`pedalrepro.figures.save`) into the results
    folder ``root``; what the figure rules call."""
    written = []
    for fid in fids:
        written.append(save(draw(fid, root), paths.figure(fid, root)))
    return written


def completeness(fid: str, root: str | Path | None = None) -> tuple[str, list[str]]:
    """Whether this build shows figure ``fid`` as the thesis does: ``("complete", [])``,
    ``("partial", [what is missing])`` (a method or panel the thesis shows is absent) or
    ``("missing", [...])`` (no figure file)."""
    s = spec(fid)
    base = paths.results() if root is None else Path(root)
    if not paths.figure(fid, base).exists():
        return MISSING, [str(paths.figure(fid, base))]
    lacking = []
    for name, key in s.complete_when:
        path = base / s.inputs[name]
        label = name.split(".")[-1] + (f" {key}" if key else "")
        if not path.exists():
            lacking.append(label)
        elif key:
            with np.load(path, allow_pickle=False) as d:
                if key not in d.files:
                    lacking.append(label)
    return (PARTIAL, lacking) if lacking else (COMPLETE, [])
