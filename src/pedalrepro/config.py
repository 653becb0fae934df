"""Workflow configuration: load ``config/*.yaml``, validate it, and write the copy in effect.

Validation has two layers, both run at workflow start (``rules/common.smk``) and by :func:`load`:

1. ``config/schema.yaml`` (JSON schema): every key required, types and ranges, each key with a
   ``description``;
2. :func:`check`: what a JSON schema cannot say -- no NaN or infinity (YAML's ``.nan`` and
   ``.inf`` are numbers to a JSON schema), sample rates above twice the highest frequency they
   must resolve (Nyquist), grid steps below their maxima, and a results folder that is not a
   system folder and holds no file of the repository. Every failure names its key.

The workflow writes the configuration in effect to ``<results>/config.used.yaml``
(:data:`COPY_NAME`, rule ``write_config``; a name no source file has, so no results folder can
make it overwrite ``config/config.yaml``); notebooks read that copy with
:func:`results_config`, so a quick build shows the quick profile's values.
"""

from __future__ import annotations

import math
import os
import subprocess
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

import jsonschema
import yaml

from . import paths, yamlio

__all__ = [
    "DATA_FILES", "SYSTEM_ROOTS", "COPY_NAME", "SOURCE_ENTRIES", "STEP_MAXIMA",
    "PERIODIC_STEP_MAXIMA", "GRID_CAPS", "MAX_TIME_SAMPLES", "UNIQUE_LISTS", "INCREASING_RANGES",
    "RETIRED_KEYS",
    "grid_count", "ConfigError", "read_yaml", "validate", "source_entries", "source_owner",
    "check_results_dir", "check", "load", "merge", "canonical", "write", "results_config",
]

DATA_FILES = ("config/schema.yaml",)

#: Folders the results may never be written to (nor the repository root or $HOME itself).
SYSTEM_ROOTS: tuple[str, ...] = ("/", "/bin", "/boot", "/dev", "/etc", "/home", "/lib",
                                 "/lib64", "/opt", "/proc", "/root", "/run", "/sbin", "/srv",
                                 "/sys", "/tmp", "/usr", "/var")
#: File name of the configuration in effect inside the results folder (rule write_config). No
#: source file has this name: ``results_dir: config`` can never overwrite config/config.yaml.
COPY_NAME = "config.used.yaml"
#: Top-level entries of the repository that are sources (tracked by git), used with those
#: ``git ls-files`` lists: the results folder may lie neither inside one nor on one. ``.git`` and
#: ``.snakemake`` (Snakemake's state) are never tracked and never results either.
SOURCE_ENTRIES: tuple[str, ...] = (".ci", ".git", ".github", ".snakemake", "book", "config",
                                   "data", "notebooks", "profiles", "rules", "scripts", "src",
                                   "tests", "CONTRIBUTING.md", "README.md", "Snakefile",
                                   "environment.lock", "package.json", "package-lock.json",
                                   "pyproject.toml", "requirements.in", ".gitignore")
#: (step key, maximum key) pairs of config section ``linear``: each step below its maximum.
STEP_MAXIMA: tuple[tuple[str, str], ...] = (
    ("ps_omega_step_rad_s", "ps_omega_max_rad_s"), ("ps_speed_step_m_s", "ps_speed_max_m_s"),
    ("time_omega_step_rad_s", "time_omega_max_rad_s"),
    ("time_speed_step_m_s", "time_speed_max_m_s"),
    ("eigen_speed_step_m_s", "eigen_speed_max_m_s"))
#: The same for config section ``periodic`` (the finer orbit map).
PERIODIC_STEP_MAXIMA: tuple[tuple[str, str], ...] = (
    ("fine_speed_step_m_s", "fine_speed_max_m_s"),
    ("fine_omega_step_rad_s", "fine_omega_max_rad_s"))
#: Largest number of points of each grid, ``(section, [(step, maximum), ...], cap, what)``: a
#: hundred times or more the thesis profile's count (in brackets), so that a mistyped step is
#: refused at workflow start with the count instead of exhausting memory inside a job
#: (``eigen_speed_step_m_s: 1e-9`` asked for 1e10 speeds and a 74.5 GiB array).
GRID_CAPS: tuple[tuple[str, tuple[tuple[str, str], ...], int, str], ...] = (
    ("linear", (("ps_speed_step_m_s", "ps_speed_max_m_s"),
                ("ps_omega_step_rad_s", "ps_omega_max_rad_s")), 1_000_000,
     "particular-solution grid (thesis 10302)"),
    ("linear", (("time_speed_step_m_s", "time_speed_max_m_s"),
                ("time_omega_step_rad_s", "time_omega_max_rad_s")), 100_000,
     "time-solution grid (thesis 676)"),
    ("linear", (("eigen_speed_step_m_s", "eigen_speed_max_m_s"),), 1_000_000,
     "eigenvalue speeds (thesis 1001)"),
    ("periodic", (("fine_speed_step_m_s", "fine_speed_max_m_s"),
                  ("fine_omega_step_rad_s", "fine_omega_max_rad_s")), 100_000,
     "finer orbit map (thesis profile 2601)"),
)
#: Largest number of samples of one time solution, ``linear.duration_s * sample_rate_hz + 1``
#: (thesis 18001; the cap is 100 times that).
MAX_TIME_SAMPLES = 1_800_100
#: Lists in which each item must be unique (a repeated item changes the science: a repeated
#: harmonic doubles its torque, a repeated model or method repeats jobs and report rows). Also
#: ``uniqueItems`` in config/schema.yaml; checked here too so the message names the item.
UNIQUE_LISTS: tuple[str, ...] = (
    "linear.harmonics", "linear.gear_ratios", "mocap.stand_in_gear_ratios",
    "periodic.methods", "periodic.fine_methods",
    "periodic.continuation_methods", "periodic.continuation_torque_scales")
#: Keys the configuration no longer has, with the reason given when a configuration sets one (an
#: old config file, a --config override): refused by :func:`validate` before the schema, whose
#: "additional properties" message would not say why. The model lists are fixed by the thesis
#: (pedalrepro.params; not imported here, so that the parameter files stay out of rule
#: write_config's inputs).
RETIRED_KEYS: dict[str, str] = {
    "linear.models": (
        "the linear models are fixed by the thesis (pedalrepro.params.LINEAR_MODELS: the Meijaard "
        "2007 benchmark and the four systems of pedalrepro.params.MODELS, Sec 3.1.1.3, Appendix "
        "B), since every figure, table and notebook of the book covers all of them"),
    "nonlinear.models": (
        "the non-linear models are fixed by the thesis (pedalrepro.params.MODELS: the four "
        "systems of Sec 3.1.1.3, each with a non-linear model), since every figure, table and "
        "notebook of the book covers all of them"),
}
#: What to do instead, added to each :data:`RETIRED_KEYS` message.
_RETIRED_ADVICE = ("; remove the key. To study another bicycle, use pedalrepro.own_bicycle (rule "
                   "own_bicycle_resonance, command `pedalrepro resonance`)")
#: ``[low, high]`` ranges that must increase.
INCREASING_RANGES: tuple[str, ...] = (
    "linear.normal_cycling_speed_kmh", "linear.normal_cycling_cadence_rpm",
    "periodic.continuation_speed_m_s")


def grid_count(step: float, maximum: float) -> float:
    """Points of ``0:step:maximum`` (:func:`pedalrepro.response.grid`'s count, without numpy;
    ``inf`` when ``maximum / step`` overflows)."""
    ratio = maximum / step
    return math.floor(ratio + 1e-9) + 1 if math.isfinite(ratio) else math.inf


def _get(config: Mapping[str, Any], dotted: str) -> Any:
    section, key = dotted.split(".")
    return config[section][key]


def _has(config: Mapping[str, Any], dotted: str) -> bool:
    section, key = dotted.split(".")
    return isinstance(config.get(section), Mapping) and key in config[section]


class ConfigError(ValueError):
    """A configuration value outside the schema or the cross-key rules (the message names it)."""


def read_yaml(path: str | Path) -> dict[str, Any]:
    """A YAML mapping, with an error naming the file (:class:`ConfigError` when it cannot be
    parsed or is not a mapping). Not pedalrepro.params.read_yaml: importing params would make the
    parameter files inputs of rule write_config."""
    return yamlio.read_mapping(path, "configuration", ConfigError)


def validate(config: dict[str, Any], schema_path: str | Path | None = None) -> dict[str, Any]:
    """Validate ``config`` against the JSON schema, raising :class:`ConfigError` with the key path.

    A key of :data:`RETIRED_KEYS` is refused first, with its reason. Returns the same mapping
    (defaults are not filled in here; the schema documents them).
    """
    retired = [f"  {key}: {reason}{_RETIRED_ADVICE}" for key, reason in RETIRED_KEYS.items()
               if _has(config, key)]
    if retired:
        raise ConfigError("configuration sets retired keys (refused, not ignored):\n"
                          + "\n".join(retired))
    schema = read_yaml(schema_path or paths.CONFIG / "schema.yaml")
    validator = jsonschema.Draft202012Validator(schema)
    errors = sorted(validator.iter_errors(config), key=lambda e: list(e.absolute_path))
    if errors:
        lines = [f"  {_dotted(e.absolute_path) or '<top>'}: {e.message}" for e in errors]
        raise ConfigError("configuration does not match config/schema.yaml:\n" + "\n".join(lines))
    return config


def _dotted(path: Any) -> str:
    """A key path as the messages name it: ``linear.harmonics[1]``."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def _numbers(value: Any, key: str = "") -> Iterator[tuple[str, float]]:
    """Every float in a nested config, with its dotted key (list items as ``key[i]``)."""
    if isinstance(value, Mapping):
        for k, v in value.items():
            yield from _numbers(v, f"{key}.{k}" if key else str(k))
    elif isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            yield from _numbers(v, f"{key}[{i}]")
    elif isinstance(value, float):
        yield key, value


def source_entries(root: str | Path = paths.ROOT) -> list[Path]:
    """The repository's top-level source folders and files (resolved): :data:`SOURCE_ENTRIES`
    and the first component of every path ``git ls-files`` lists (when ``root`` is a git
    checkout and git runs; a copy without git keeps the fixed list)."""
    root = Path(root).resolve()
    names = set(SOURCE_ENTRIES)
    try:
        listed = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], capture_output=True,
                                text=True, timeout=30, check=True).stdout
        names |= {f.split("/", 1)[0] for f in listed.split("\0") if f}
    except (OSError, subprocess.SubprocessError):
        pass
    return sorted(root / n for n in names)


def source_owner(path: str | Path, root: str | Path = paths.ROOT) -> Path | None:
    """The source entry of the repository (:func:`source_entries`) that ``path`` (resolved) lies
    in or on, or ``None``."""
    path = Path(path).resolve()
    for entry in source_entries(root):
        if path == entry or entry in path.parents:
            return entry
    return None


def check_results_dir(results_dir: str, root: str | Path = paths.ROOT,
                      home: str | Path | None = None) -> Path:
    """The results folder resolved against ``root``; :class:`ConfigError` naming ``results_dir``
    when it is a system folder (:data:`SYSTEM_ROOTS`), ``$HOME`` itself, the repository root or
    a folder holding it, inside a source folder or on a source file of the repository
    (:func:`source_owner`: ``config``, ``src/...``, ``README.md``), an existing file, or when
    its nearest existing parent is not writable."""
    path = Path(os.path.expanduser(results_dir))
    path = (path if path.is_absolute() else Path(root) / path).resolve()
    home = Path(home if home is not None else os.path.expanduser("~")).resolve()
    repo = Path(root).resolve()
    forbidden = {Path(p).resolve() for p in SYSTEM_ROOTS} | {home, repo}
    if path in forbidden:
        raise ConfigError(f"results_dir: {results_dir!r} resolves to {path}, a system folder, "
                          "$HOME or the repository root; choose a folder inside one, e.g. "
                          "'results' or '/scratch/<you>/pedalrepro'")
    if path in repo.parents:
        raise ConfigError(f"results_dir: {results_dir!r} resolves to {path}, which holds the "
                          f"repository {repo}; choose e.g. 'results'")
    owner = source_owner(path, repo)
    if owner is not None:
        raise ConfigError(f"results_dir: {results_dir!r} resolves to {path}, inside or on the "
                          f"repository's source {owner} (tracked files would be overwritten); "
                          "choose e.g. 'results' or 'results/<name>'")
    if path.exists() and not path.is_dir():
        raise ConfigError(f"results_dir: {path} exists and is not a folder")
    parent = path
    while not parent.exists():
        parent = parent.parent
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ConfigError(f"results_dir: {results_dir!r} ({path}) cannot be created or written: "
                          f"{parent} is not writable")
    return path


def _sampling_errors(config: Mapping[str, Any]) -> list[str]:
    """The sampling rules of :func:`check` (Nyquist and a whole period).

    Parameters
    ----------
    config
        The configuration (finite numbers).

    Returns
    -------
    list of str
        The broken rules' messages, in this order: ``linear.sample_rate_hz`` against the highest
        harmonic frequency, ``linear.duration_s`` against one period of the smallest cadence,
        ``section2.harmonics`` and ``mocap.angle_lowpass_hz`` against half their sample rates.
    """
    errors = []
    lin, s2, mocap = config["linear"], config["section2"], config["mocap"]
    f_max_hz = max(lin["harmonics"]) * lin["time_omega_max_rad_s"] / (2 * math.pi)
    if not lin["sample_rate_hz"] > 2 * f_max_hz:
        errors.append(
            f"linear.sample_rate_hz: {lin['sample_rate_hz']:g} Hz is not above twice the highest "
            f"harmonic frequency of the time grid, max(linear.harmonics) * "
            f"linear.time_omega_max_rad_s / 2 pi = {f_max_hz:.4g} Hz (Nyquist: amplitudes "
            "would alias)")
    period_s = 2 * math.pi / lin["time_omega_step_rad_s"]
    if lin["duration_s"] < period_s:
        errors.append(f"linear.duration_s: {lin['duration_s']:g} s is shorter than one period "
                      f"({period_s:.4g} s) of the smallest non-zero cadence "
                      "linear.time_omega_step_rad_s")
    if not s2["harmonics"] < s2["samples_per_revolution"] / 2:
        errors.append(f"section2.harmonics: {s2['harmonics']} is not below half of "
                      f"section2.samples_per_revolution ({s2['samples_per_revolution']}; "
                      "Nyquist)")
    if mocap["angle_lowpass_hz"] and not mocap["angle_lowpass_hz"] < mocap["sample_rate_hz"] / 2:
        errors.append(f"mocap.angle_lowpass_hz: {mocap['angle_lowpass_hz']:g} Hz is not below "
                      f"half of mocap.sample_rate_hz ({mocap['sample_rate_hz']:g} Hz; Nyquist)")
    return errors


def _step_errors(config: Mapping[str, Any]) -> list[str]:
    """The grid-step rules of :func:`check`.

    Parameters
    ----------
    config
        The configuration (finite numbers).

    Returns
    -------
    list of str
        The messages for each step of :data:`STEP_MAXIMA` then :data:`PERIODIC_STEP_MAXIMA`
        not below its maximum, then for each range of :data:`INCREASING_RANGES` not increasing.
    """
    errors = []
    steps = [("linear", st, mx) for st, mx in STEP_MAXIMA] \
        + [("periodic", st, mx) for st, mx in PERIODIC_STEP_MAXIMA]
    for section, step, maximum in steps:
        sec = config[section]
        if not sec[step] < sec[maximum]:
            errors.append(f"{section}.{step}: {sec[step]:g} is not below {section}.{maximum} "
                          f"({sec[maximum]:g}): the grid would have one point")
    for key in INCREASING_RANGES:
        lo, hi = _get(config, key)
        if not lo < hi:
            errors.append(f"{key}: [{lo:g}, {hi:g}] is not an increasing range [low, high]")
    return errors


def _cap_errors(config: Mapping[str, Any]) -> list[str]:
    """The size caps of :func:`check`.

    Parameters
    ----------
    config
        The configuration (finite numbers).

    Returns
    -------
    list of str
        The messages for each grid of :data:`GRID_CAPS` above its cap (named by the step giving
        the most points), then for a time solution above :data:`MAX_TIME_SAMPLES` samples.
    """
    errors = []
    for section, pairs, cap, what in GRID_CAPS:
        sec = config[section]
        counts = [grid_count(sec[st], sec[mx]) for st, mx in pairs]
        total = math.prod(counts)
        if total > cap:
            keys = " x ".join(f"{sec[mx]:g} / {section}.{st} -> {c:.6g}"
                              for (st, mx), c in zip(pairs, counts, strict=True))
            lead = pairs[counts.index(max(counts))][0]  # the step giving the most points
            errors.append(f"{section}.{lead}: the {what} would have {total:.4g} points "
                          f"({keys}), above the cap of {cap} (pedalrepro.config.GRID_CAPS)")
    lin = config["linear"]
    samples = lin["duration_s"] * lin["sample_rate_hz"] + 1
    if samples > MAX_TIME_SAMPLES:
        errors.append(f"linear.sample_rate_hz: linear.duration_s x sample_rate_hz = "
                      f"{samples:.4g} samples per time solution, above the cap of "
                      f"{MAX_TIME_SAMPLES}")
    return errors


def _list_errors(config: Mapping[str, Any]) -> list[str]:
    """The list rules of :func:`check`.

    Parameters
    ----------
    config
        The configuration (finite numbers).

    Returns
    -------
    list of str
        The messages for each list of :data:`UNIQUE_LISTS` with a repeated item, then for
        ``linear.harmonics`` not starting at 1 and increasing.
    """
    errors = []
    for key in UNIQUE_LISTS:
        items = list(_get(config, key))
        repeated = sorted({x for x in items if items.count(x) > 1}, key=str)
        if repeated:
            errors.append(f"{key}: {items} repeats {', '.join(map(str, repeated))} (each item "
                          "once: a repeated item counts twice)")
    harmonics = list(config["linear"]["harmonics"])
    if harmonics[0] != 1 or harmonics != sorted(set(harmonics)):
        errors.append(f"linear.harmonics: {harmonics} must start at 1 (the cadence, whose "
                      "amplitude the maps show) and increase, e.g. [1, 3, 5]")
    return errors


def _job_errors(config: Mapping[str, Any], root: str | Path) -> list[str]:
    """The rules of :func:`check` on how the workflow runs: sweep jobs and the results folder.

    Parameters
    ----------
    config
        The configuration (finite numbers).
    root
        The repository root, against which ``results_dir`` resolves.

    Returns
    -------
    list of str
        The message for ``nonlinear.chunks`` above the speeds of the time grid, then that of
        :func:`check_results_dir`.
    """
    errors = []
    lin = config["linear"]
    speeds = grid_count(lin["time_speed_step_m_s"], lin["time_speed_max_m_s"])
    chunks = config["nonlinear"]["chunks"]
    if chunks > speeds:
        errors.append(f"nonlinear.chunks: {chunks} sweep jobs is more than the {speeds:.4g} "
                      "speeds of the time grid (linear.time_speed_*); at most "
                      f"{min(speeds, 64):.4g}, or jobs would have no speed")
    try:
        check_results_dir(config["results_dir"], root)
    except ConfigError as exc:
        errors.append(str(exc))
    return errors


def check(config: Mapping[str, Any], root: str | Path = paths.ROOT) -> None:
    """The cross-key rules a JSON schema cannot express; :class:`ConfigError` naming the key.

    * no NaN or infinity anywhere;
    * ``linear.sample_rate_hz`` above twice the highest harmonic frequency of the time grid,
      ``max(linear.harmonics) * linear.time_omega_max_rad_s / 2 pi`` (Nyquist: the DFT amplitudes
      of Sec 3.1.2.1 would alias);
    * ``linear.duration_s`` at least one period of the smallest non-zero cadence of the time grid
      (``2 pi / linear.time_omega_step_rad_s``): the DFT needs a whole period;
    * ``section2.harmonics`` below half of ``section2.samples_per_revolution`` (Nyquist);
    * ``mocap.angle_lowpass_hz`` (when not 0) below half of ``mocap.sample_rate_hz``;
    * each grid step of :data:`STEP_MAXIMA` below its maximum, and each
      ``linear.normal_cycling_*`` range increasing;
    * ``results_dir`` as :func:`check_results_dir`.
    """
    errors = [f"{key}: {value!r} is not a finite number" for key, value in _numbers(config)
              if not math.isfinite(value)]
    if errors:
        raise ConfigError("configuration has non-finite values:\n  " + "\n  ".join(errors))
    errors += _sampling_errors(config)
    errors += _step_errors(config)
    errors += _cap_errors(config)
    errors += _list_errors(config)
    errors += _job_errors(config, root)
    if errors:
        raise ConfigError("configuration fails its cross-key rules:\n  " + "\n  ".join(errors))


def load(path: str | Path | None = None, *overrides: str | Path) -> dict[str, Any]:
    """Load ``config/config.yaml`` (or ``path``), merge override files on top, and validate.

    Parameters
    ----------
    path
        The base configuration (default ``config/config.yaml``).
    overrides
        Further YAML files (e.g. ``config/quick.yaml``) merged key by key, recursively.
    """
    config = read_yaml(path or paths.CONFIG / "config.yaml")
    for extra in overrides:
        config = merge(config, read_yaml(extra))
    validate(config)
    check(config)
    return config


def merge(base: dict[str, Any], extra: dict[str, Any]) -> dict[str, Any]:
    """Recursive dictionary merge, ``extra`` winning (Snakemake's ``--configfile`` semantics)."""
    out = dict(base)
    for key, value in extra.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = merge(out[key], value)
        else:
            out[key] = value
    return out


def canonical(value: Any) -> Any:
    """``value`` with every mapping's keys sorted, recursively (lists keep their order).

    Snakemake compares a rule's ``params`` by their ``repr``, so a dictionary of the same values
    in another key order (``--configfile`` merges put the overriding file's keys first; another
    tool may write the merged YAML sorted) would plan the rule again as "params have changed".
    The Snakefile puts the configuration in this form once, after validation, so a rule reruns
    exactly when a value it reads changes (tests/workflow/test_change_tracking.py)."""
    if isinstance(value, Mapping):
        return {k: canonical(value[k]) for k in sorted(value)}
    if isinstance(value, list):
        return [canonical(v) for v in value]
    return value


def write(config: Mapping[str, Any], path: str | Path, root: str | Path = paths.ROOT) -> Path:
    """Write the configuration in effect as YAML (keys in the order given).

    Refuses (:class:`ConfigError` naming ``path``) a path inside or on a source of the
    repository (:func:`source_owner`), whatever results folder reached it."""
    path = Path(path)
    owner = source_owner(path, root)
    if owner is not None:
        raise ConfigError(f"{path}: the configuration copy would be written inside or on the "
                          f"repository's source {owner}; not written")
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", encoding="utf-8") as fh:
        fh.write("# The configuration this results folder was built with (written by the "
                 "workflow; do not edit).\n")
        yaml.safe_dump(_plain(config), fh, sort_keys=False, default_flow_style=None)
    return path


def _plain(value: Any) -> Any:
    """Snakemake's config mappings and lists as plain dicts and lists (for yaml.safe_dump)."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def results_config(results: str | Path | None = None) -> dict[str, Any]:
    """The configuration a results folder was built with (``<results>/config.used.yaml``,
    :data:`COPY_NAME`).

    Notebooks read this copy, never ``config/config.yaml``, so that what they show matches the
    results (quick or thesis profile). ``results`` defaults to :func:`pedalrepro.paths.results`.
    """
    path = Path(results if results is not None else paths.results()) / COPY_NAME
    if not path.is_file():
        raise FileNotFoundError(f"{path} not found: run the workflow (rule write_config) first")
    return read_yaml(path)
