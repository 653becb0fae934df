"""Download and verify the treadmill data with pooch (figshare DOI 10.6084/m9.figshare.1082512).

The registry ``data/registry.txt`` lists the published files and their hashes. Refresh it when
online with ``pedalrepro mocap refresh-registry`` (:func:`refresh_registry`, which calls
``pooch.Pooch.load_registry_from_doi``: it reads the file list and figshare's md5 checksums
without downloading any data). Files are cached in ``pooch.os_cache("pedalrepro")``, or in the
folder named by the environment variable ``PEDALREPRO_DATA_DIR`` (a local copy of the data set
works offline once the registry lists it). Every cached file is checked against its hash before
use.

Data source (config ``data_source``): ``figshare`` needs the real files and stops with a clear
message when they cannot be had; ``synthetic`` forces the stand-in; ``auto`` (default) uses the
real files when cached or downloadable, else the stand-in, with the reason
(:func:`resolve_source`).
"""

from __future__ import annotations

import re
from pathlib import Path

import pooch

from .. import paths

DOI = "10.6084/m9.figshare.1082512"
BASE_URL = f"doi:{DOI}/"
REGISTRY: Path = paths.DATA / "registry.txt"
#: Environment variable pointing the cache at a local folder.
ENV = "PEDALREPRO_DATA_DIR"
SOURCES: tuple[str, ...] = ("auto", "figshare", "synthetic")
RUN_FILE = re.compile(r"^(?:.*/)?(\d{4})\.mat$")
ARCHIVES = (".zip", ".tar", ".tar.gz", ".tgz")


class DataUnavailableError(OSError):
    """The real data are needed but neither cached nor downloadable."""


class HashMismatchError(ValueError):
    """A data file whose hash differs from the registry (the message names the file)."""


def offline_message(exc: BaseException | None = None) -> str:
    why = f" ({type(exc).__name__}: {exc})" if exc is not None else ""
    return (
        f"The treadmill data (figshare DOI {DOI}) are needed but cannot be reached{why}. "
        f"Either connect to the internet, or set {ENV} to a folder holding the published files "
        f"(and list them in {REGISTRY} with `pedalrepro mocap refresh-registry` once online), "
        "or set `data_source: synthetic` (or `auto`) to build the labelled synthetic stand-in."
    )


def make_pooch(registry: str | Path | None = REGISTRY, path: str | Path | None = None
               ) -> pooch.Pooch:
    """The project's :class:`pooch.Pooch` for the data set (cache: ``$PEDALREPRO_DATA_DIR`` or
    ``pooch.os_cache("pedalrepro")``; registry from ``registry`` when given and present)."""
    pup = pooch.create(path=path or pooch.os_cache("pedalrepro"), base_url=BASE_URL, env=ENV,
                       registry=None, retry_if_failed=1)
    if registry is not None and Path(registry).is_file():
        pup.load_registry(str(registry))
    return pup


def write_registry(entries: dict[str, str], path: str | Path = REGISTRY) -> Path:
    """Write ``entries`` (file name -> hash) below the comment header of ``path``."""
    path = Path(path)
    header = []
    if path.is_file():
        for line in path.read_text().splitlines():
            if not line.startswith("#"):
                break
            header.append(line)
    body = [f"{name} {entries[name]}" for name in sorted(entries)]
    path.write_text("\n".join(header + body) + "\n")
    return path


def refresh_registry(path: str | Path = REGISTRY, write: bool = True) -> dict[str, str]:
    """Read the published file list and hashes from the DOI (network), optionally save them.

    Raises
    ------
    DataUnavailableError
        When figshare cannot be reached (pooch raises ``requests`` ConnectionError, an
        ``OSError``).
    """
    pup = make_pooch(registry=None)
    try:
        pup.load_registry_from_doi()
    except OSError as exc:
        raise DataUnavailableError(offline_message(exc)) from exc
    if write:
        write_registry(dict(pup.registry), path)
    return dict(pup.registry)


def verify(pup: pooch.Pooch, name: str) -> Path | None:
    """Path of the cached ``name`` after checking its hash; ``None`` when not cached.

    Raises
    ------
    HashMismatchError
        The cached file differs from the registry (corrupt, truncated or not the published one).
    """
    if name not in pup.registry:
        raise KeyError(f"{name!r} is not in the registry {REGISTRY}")
    p = Path(pup.abspath) / name
    if not p.is_file():
        return None
    known = pup.registry[name]
    if known and not pooch.hashes.hash_matches(str(p), known):
        alg = pooch.hashes.hash_algorithm(known)
        got = pooch.file_hash(str(p), alg=alg)
        raise HashMismatchError(
            f"{p}: {alg} hash {got} does not match the registry ({known}): the file is corrupt, "
            "truncated or not the published one; delete it to download it again")
    return p


def fetch(name: str, pup: pooch.Pooch | None = None, progressbar: bool = True) -> Path:
    """A verified local copy of one registry file (download with pooch's progress bar if needed).

    Archives (``.zip``, ``.tar.gz``) are unpacked; the folder is returned.
    """
    pup = pup or make_pooch()
    cached = verify(pup, name)
    processor = None
    if name.endswith(".zip"):
        processor = pooch.Unzip()
    elif name.endswith(ARCHIVES):
        processor = pooch.Untar()
    if cached is not None and processor is None:
        return cached
    try:
        out = pup.fetch(name, progressbar=progressbar, processor=processor)
    except ValueError as exc:  # pooch: downloaded file's hash does not match
        raise HashMismatchError(f"{name}: {exc}") from exc
    except OSError as exc:
        raise DataUnavailableError(offline_message(exc)) from exc
    if isinstance(out, list):
        return Path(out[0]).parent if len(out) == 1 else Path(Path(out[0]).parent)
    return Path(out)


def run_files(pup: pooch.Pooch | None = None, progressbar: bool = True) -> dict[int, Path]:
    """Every published run file (``RNNN.mat``), fetched and verified: run id -> path."""
    pup = pup or make_pooch()
    if not pup.registry:
        raise DataUnavailableError(
            f"{REGISTRY} lists no files yet: run `pedalrepro mocap refresh-registry` online")
    out: dict[int, Path] = {}
    for name in sorted(pup.registry):
        m = RUN_FILE.match(name)
        if m:
            out[int(m.group(1))] = fetch(name, pup, progressbar)
        elif name.endswith(ARCHIVES):
            folder = fetch(name, pup, progressbar)
            for f in Path(folder).rglob("*.mat"):
                mm = RUN_FILE.match(f.name)
                if mm:
                    out.setdefault(int(mm.group(1)), f)
    if not out:
        raise DataUnavailableError(f"no run file RNNN.mat found among the registry's files "
                                   f"{sorted(pup.registry)[:5]}...")
    return out


def cached_complete(pup: pooch.Pooch) -> bool:
    """All registry files are in the cache with the right hashes (no network needed)."""
    if not pup.registry:
        return False
    return all(verify(pup, name) is not None for name in pup.registry)


def resolve_source(requested: str = "auto", pup: pooch.Pooch | None = None
                   ) -> tuple[str, str]:
    """Decide where the treadmill data come from: ``("figshare" | "synthetic", reason)``.

    ``auto``: the real files when cached (and verified) or when figshare answers; otherwise the
    synthetic stand-in, with the reason. ``figshare``: raises :class:`DataUnavailableError`
    when offline. ``synthetic``: always the stand-in.
    """
    if requested not in SOURCES:
        raise ValueError(f"data_source {requested!r} not in {SOURCES}")
    if requested == "synthetic":
        return "synthetic", "data_source: synthetic requested in the configuration"
    pup = pup or make_pooch()
    if pup.registry and cached_complete(pup):
        return "figshare", "all registry files cached and verified"
    try:
        # reachability (and the file list, when the registry is still empty): one API call
        probe = pup if not pup.registry else make_pooch(registry=None, path=pup.abspath)
        probe.load_registry_from_doi()
        return "figshare", f"downloadable from figshare (DOI {DOI})"
    except OSError as exc:
        if requested == "figshare":
            raise DataUnavailableError(offline_message(exc)) from exc
        return "synthetic", (f"figshare unreachable from this machine ({type(exc).__name__}); "
                             "the synthetic stand-in is not the measurement")
