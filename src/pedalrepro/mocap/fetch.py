"""Download and verify the treadmill data with pooch (figshare DOI 10.6084/m9.figshare.1082512).

Two registries, one data folder:

- ``data/registry.txt``: the published figshare set (one ``RNNN.mat`` per run). It may be
  empty or partial: online, the file list and figshare's md5 checksums are read from the DOI
  at run time (``pooch.Pooch.load_registry_from_doi``, :func:`figshare_registry`) and merged
  with it. ``pedalrepro mocap refresh-registry`` saves them. Only rider 3's runs are fetched
  (:func:`run_files`: the thesis's tables and figures use rider 3 alone), not the 271 files.
- ``data/registry_public.txt``: the public subset of real recordings re-hosted on GitHub
  (per-coordinate exports of runs 3045 and 3101, raw URLs at a pinned commit, sha256),
  read by :mod:`pedalrepro.mocap.exports` (:func:`public_files`).

Data folder: the environment variable ``PEDALREPRO_DATA_DIR`` (:data:`ENV`), else
``pooch.os_cache("pedalrepro")``. Offline, put the files there (a copy of the public subset
is enough for the real 3045 row): nothing is downloaded when a file is present with the right
hash. Every file is checked against its hash before use; a file whose hash does not match is
reported, removed and fetched again once (:func:`fetch`). Downloads show a progress bar (tqdm,
as pooch's) and **resume** after an interruption: the bytes received so far stay in
``<name>.part`` in the data folder and the next attempt asks the server for the rest (HTTP
``Range``;
:class:`ResumingDownloader`); one retry follows at once, a later run resumes again.

Data source (config ``data_source``, :func:`resolve_source`): ``figshare`` needs the real files
and stops with one clear message when they cannot be had; ``synthetic`` forces the stand-in;
``auto`` (default) uses the figshare set when it can be had, else the synthetic stand-in plus
whatever real public-subset run is available, each row labelled with its own source
(:mod:`pedalrepro.mocap.prepare`); ``auto`` never fails the workflow.
"""

from __future__ import annotations

import logging
import os
import re
import shutil
from pathlib import Path

import pooch
import requests

from .. import paths

__all__ = [
    "DOI", "BASE_URL", "REGISTRY", "REGISTRY_PUBLIC", "ENV", "SOURCES", "RUN_FILE", "ARCHIVES",
    "TIMEOUT_S", "ATTEMPTS", "LOG", "DataUnavailableError", "HashMismatchError", "CorruptDataError",
    "offline_message", "data_dir", "make_pooch", "make_public_pooch", "write_registry",
    "refresh_registry", "verify", "ResumingDownloader", "fetch", "figshare_registry",
    "rider_run_names", "run_files", "public_files", "cache_state", "cached_complete",
    "resolve_source",
]

DOI = "10.6084/m9.figshare.1082512"
BASE_URL = f"doi:{DOI}/"
REGISTRY: Path = paths.DATA / "registry.txt"
REGISTRY_PUBLIC: Path = paths.DATA / "registry_public.txt"
#: Environment variable naming the data folder (pooch cache) of both registries.
ENV = "PEDALREPRO_DATA_DIR"
SOURCES: tuple[str, ...] = ("auto", "figshare", "synthetic")
RUN_FILE = re.compile(r"^(?:.*/)?(\d)(\d{3})\.mat$")
ARCHIVES = (".zip", ".tar", ".tar.gz", ".tgz")
#: Network timeout of one request (s).
TIMEOUT_S = 30.0
#: Attempts per file: the first and one more after a hash mismatch or an interruption.
ATTEMPTS = 2
LOG = logging.getLogger("pedalrepro.mocap")


class DataUnavailableError(OSError):
    """The real data are needed but neither cached nor downloadable."""


class HashMismatchError(ValueError):
    """A data file whose hash differs from the registry (the message names the file)."""


class CorruptDataError(HashMismatchError, DataUnavailableError):
    """A cached data file whose hash differs from the registry and that cannot be fetched
    again (offline): the message names the file and both hashes (the registry's and the
    file's), never only "cannot be reached"."""


def offline_message(exc: BaseException | None = None) -> str:
    why = f" ({type(exc).__name__}: {exc})" if exc is not None else ""
    return (
        f"data_source: figshare, but the treadmill data (figshare DOI {DOI}) cannot be "
        f"reached{why}. Either connect to the internet, or set {ENV} to a folder holding the "
        f"published run files listed in {REGISTRY.name} (`pedalrepro mocap refresh-registry` "
        "lists them once online), or set `data_source: auto` (stand-in plus the real public "
        "subset, labelled) or `synthetic`."
    )


def data_dir() -> Path:
    """The data folder: ``$PEDALREPRO_DATA_DIR`` or ``pooch.os_cache("pedalrepro")``."""
    return Path(os.environ.get(ENV) or pooch.os_cache("pedalrepro"))


def make_pooch(registry: str | Path | None = REGISTRY, path: str | Path | None = None
               ) -> pooch.Pooch:
    """The project's :class:`pooch.Pooch` for the figshare set (data folder :func:`data_dir`;
    registry from ``registry`` when given and present)."""
    pup = pooch.create(path=path or pooch.os_cache("pedalrepro"), base_url=BASE_URL, env=ENV,
                       registry=None, retry_if_failed=0)
    if registry is not None and Path(registry).is_file():
        pup.load_registry(str(registry))
    return pup


def make_public_pooch(registry: str | Path = REGISTRY_PUBLIC, base_url: str | None = None,
                      path: str | Path | None = None) -> pooch.Pooch:
    """:class:`pooch.Pooch` of the public subset (``data/registry_public.txt``: name, sha256,
    raw GitHub URL at the pinned commit). ``base_url`` replaces the registry's URLs by
    ``base_url + name`` (a mirror, or a local test server)."""
    pup = pooch.create(path=path or pooch.os_cache("pedalrepro"),
                       base_url=base_url or "https://raw.githubusercontent.com/", env=ENV,
                       registry=None, retry_if_failed=0)
    pup.load_registry(str(registry))
    if base_url:
        pup.urls = {}
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
        raise KeyError(f"{name!r} is not in the registry")
    p = Path(pup.abspath) / name
    if not p.is_file():
        return None
    known = pup.registry[name]
    if known and not pooch.hashes.hash_matches(str(p), known):
        alg = pooch.hashes.hash_algorithm(known)
        got = pooch.file_hash(str(p), alg=alg)
        raise HashMismatchError(
            f"{p}: {alg} hash {got} does not match the registry ({known}): the file is corrupt, "
            "truncated or not the published one")
    return p


class ResumingDownloader:
    """A pooch downloader that resumes an interrupted download (HTTP ``Range``).

    The bytes received so far are kept in ``part`` (``<data folder>/<name>.part``); the next
    call asks for the rest (``Range: bytes=<size>-``) and appends it. A server that ignores the
    range (status 200) sends the whole file again, which replaces the part. A ``doi:`` URL is
    resolved to the repository's download URL first (as :class:`pooch.DOIDownloader` does).
    When the transfer stops short of the announced length, the part is kept and
    ``requests.exceptions.ConnectionError`` is raised (pooch then removes its temporary file;
    :func:`fetch` tries once more, resuming).
    """

    def __init__(self, part: str | Path, progressbar: bool = False, timeout_s: float = TIMEOUT_S,
                 chunk_size: int = 1 << 16):
        self.part = Path(part)
        self.progressbar = progressbar
        self.timeout_s = timeout_s
        self.chunk_size = chunk_size

    def resolve(self, url: str) -> str:
        if not url.startswith("doi:"):
            return url
        # "doi:10.6084/m9.figshare.1082512/3045.mat" -> the DOI and the file name
        prefix, _, rest = url[4:].partition("/")
        suffix, _, name = rest.partition("/")
        repo = pooch.downloaders.doi_to_repository(f"{prefix}/{suffix}",
                                                   timeout=self.timeout_s)
        return repo.download_url(name)

    def __call__(self, url: str, output_file, pup=None, check_only: bool = False):
        url = self.resolve(url)
        have = self.part.stat().st_size if self.part.is_file() else 0
        headers = {"Range": f"bytes={have}-"} if have else {}
        with requests.get(url, stream=True, headers=headers, timeout=self.timeout_s) as r:
            if r.status_code == 416 and have:  # nothing left to send: the part is complete
                total = have
            else:
                r.raise_for_status()
                if r.status_code != 206:  # the server sent the whole file
                    have = 0
                length = int(r.headers.get("Content-Length", 0)) or None
                total = have + length if length is not None else None
                bar = None
                if self.progressbar:
                    from tqdm import tqdm

                    bar = tqdm(total=total, initial=have, unit="B", unit_scale=True,
                               desc=self.part.name.removesuffix(".part"), leave=True)
                self.part.parent.mkdir(parents=True, exist_ok=True)
                try:
                    with self.part.open("ab" if have else "wb") as fh:
                        for chunk in r.iter_content(chunk_size=self.chunk_size):
                            fh.write(chunk)
                            if bar is not None:
                                bar.update(len(chunk))
                finally:
                    if bar is not None:
                        bar.close()
        size = self.part.stat().st_size
        if total is not None and size < total:
            raise requests.exceptions.ConnectionError(
                f"{url}: download interrupted at {size} of {total} bytes (kept in "
                f"{self.part.name}; the next attempt resumes)")
        if hasattr(output_file, "write"):
            with self.part.open("rb") as fh:
                shutil.copyfileobj(fh, output_file)
        else:
            shutil.copyfile(self.part, output_file)
        self.part.unlink()


def fetch(name: str, pup: pooch.Pooch | None = None, progressbar: bool = True,
          events: list[str] | None = None) -> Path:
    """A verified local copy of one registry file (downloaded if needed, resuming).

    A cached file whose hash does not match is reported (``events`` and the log), removed and
    fetched again; a download whose hash does not match is fetched once more; an interrupted
    download resumes once. Archives (``.zip``, ``.tar.gz``) are unpacked; the folder is
    returned.

    Raises
    ------
    HashMismatchError
        The file still does not match its hash after the second attempt.
    DataUnavailableError
        The file is not cached and cannot be downloaded (offline, server error).
    """
    pup = pup or make_pooch()
    events = [] if events is None else events

    def say(msg: str) -> None:
        events.append(msg)
        LOG.warning(msg)

    mismatch = None
    try:
        cached = verify(pup, name)
    except HashMismatchError as exc:
        mismatch = str(exc)
        say(f"{exc}: removed, fetching it again")
        (Path(pup.abspath) / name).unlink()
        cached = None
    processor = None
    if name.endswith(".zip"):
        processor = pooch.Unzip()
    elif name.endswith(ARCHIVES):
        processor = pooch.Untar()
    if cached is not None and processor is None:
        return cached
    part = Path(pup.abspath) / f"{name}.part"
    for attempt in range(1, ATTEMPTS + 1):
        last = attempt == ATTEMPTS
        try:
            out = pup.fetch(name, progressbar=progressbar, processor=processor,
                            downloader=ResumingDownloader(part, progressbar))
            break
        except ValueError as exc:  # pooch: the downloaded file's hash does not match
            part.unlink(missing_ok=True)
            if last:
                raise HashMismatchError(f"{name}: hash mismatch again after {ATTEMPTS} "
                                        f"downloads: {exc}") from exc
            say(f"{name}: downloaded file does not match its hash ({exc}); removed, "
                "fetching it again")
        except (requests.exceptions.RequestException, OSError) as exc:
            if last or not part.is_file():
                if mismatch is not None:
                    raise CorruptDataError(
                        f"{mismatch}; it was removed and cannot be downloaded again "
                        f"({type(exc).__name__}: {exc}): put the published file in "
                        f"{pup.abspath}") from exc
                raise DataUnavailableError(
                    f"{name}: cannot be downloaded ({type(exc).__name__}: {exc})") from exc
            say(f"{name}: download interrupted ({exc}); resuming from "
                f"{part.stat().st_size} bytes")
    if isinstance(out, list):
        return Path(out[0]).parent
    return Path(out)


def figshare_registry(pup: pooch.Pooch, events: list[str] | None = None,
                      require_doi: bool = False) -> dict[str, str]:
    """The figshare file list with hashes: the committed registry, completed from the DOI.

    When the committed registry lists no run file (the shipped, empty one) or only some, the
    list and figshare's md5 checksums are read from the DOI at run time
    (``load_registry_from_doi``, network) and merged (committed entries win); the merged list is
    used for this run, not written (``pedalrepro mocap refresh-registry`` writes it).

    Raises
    ------
    DataUnavailableError
        The DOI cannot be resolved (offline) and the registry has no run file, or
        ``require_doi`` (files that are not cached need the network anyway).
    """
    committed = dict(pup.registry)
    probe = make_pooch(registry=None, path=pup.abspath)
    try:
        probe.load_registry_from_doi()
    except (OSError, ValueError) as exc:
        if not require_doi and any(RUN_FILE.match(n) for n in committed):
            if events is not None:
                events.append(f"figshare file list not refreshed from the DOI "
                              f"({type(exc).__name__}); the committed registry is used")
            return committed
        raise DataUnavailableError(offline_message(exc)) from exc
    merged = {**probe.registry, **committed}
    pup.registry.update(merged)
    pup.urls.update({k: v for k, v in probe.urls.items() if k not in pup.urls})
    return merged


def rider_run_names(names, rider: int) -> list[str]:
    """The run files ``RNNN.mat`` of one rider among registry names (the static runs too)."""
    return sorted(n for n in names if (m := RUN_FILE.match(n)) and int(m.group(1)) == rider)


def run_files(pup: pooch.Pooch | None = None, progressbar: bool = True, rider: int | None = 3,
              events: list[str] | None = None) -> dict[int, Path]:
    """Rider ``rider``'s published run files (``RNNN.mat``), fetched and verified.

    The file list comes from :func:`figshare_registry` (the DOI at run time when the committed
    registry is empty). Only the rider's runs are fetched (``None``: every run); archives are
    fetched and searched for run files when there are no single run files.
    """
    pup = pup or make_pooch()
    figshare_registry(pup, events)
    names = list(pup.registry)
    wanted = (rider_run_names(names, rider) if rider is not None
              else sorted(n for n in names if RUN_FILE.match(n)))
    out: dict[int, Path] = {}
    for name in wanted:
        m = RUN_FILE.match(name)
        out[int(m.group(1) + m.group(2))] = fetch(name, pup, progressbar, events)
    if not out:
        for name in sorted(n for n in names if n.endswith(ARCHIVES)):
            folder = fetch(name, pup, progressbar, events)
            for f in Path(folder).rglob("*.mat"):
                mm = RUN_FILE.match(f.name)
                if mm and (rider is None or int(mm.group(1)) == rider):
                    out.setdefault(int(mm.group(1) + mm.group(2)), f)
    if not out:
        raise DataUnavailableError(
            f"no run file RNNN.mat of rider {rider} among the figshare files "
            f"{sorted(names)[:5]}...")
    return out


def public_files(pup: pooch.Pooch | None = None, progressbar: bool = True,
                 events: list[str] | None = None) -> dict[str, Path]:
    """The public subset's files that can be had (cached or downloaded), each verified.

    Never raises for a file that cannot be had: it is left out and ``events`` says why.
    """
    pup = pup or make_public_pooch()
    events = [] if events is None else events
    out = {}
    for name in sorted(pup.registry):
        try:
            out[name] = fetch(name, pup, progressbar, events)
        except (DataUnavailableError, HashMismatchError) as exc:
            events.append(f"{name} not available: {exc}")
    return out


def cache_state(pup: pooch.Pooch, rider: int | None = 3) -> tuple[list[str], list[str]]:
    """The rider's registry run files that are corrupt in the cache (each as the
    :func:`verify` message: the file, the registry's hash and the file's) and those missing
    from it (names), offline."""
    names = rider_run_names(pup.registry, rider) if rider is not None else list(pup.registry)
    corrupt, missing = [], []
    for name in names:
        try:
            if verify(pup, name) is None:
                missing.append(name)
        except HashMismatchError as exc:
            corrupt.append(str(exc))
    return corrupt, missing


def _listed(names: list[str], most: int = 8) -> str:
    more = f" and {len(names) - most} more" if len(names) > most else ""
    return ", ".join(names[:most]) + more


def cached_complete(pup: pooch.Pooch, rider: int | None = 3) -> bool:
    """The rider's registry run files are all in the cache with the right hashes (offline)."""
    names = rider_run_names(pup.registry, rider) if rider is not None else list(pup.registry)
    if not names:
        return False
    try:
        return all(verify(pup, name) is not None for name in names)
    except HashMismatchError:
        return False


def resolve_source(requested: str = "auto", pup: pooch.Pooch | None = None
                   ) -> tuple[str, str]:
    """Decide where the treadmill runs come from: ``("figshare" | "synthetic", reason)``.

    ``auto``: the figshare files when cached (and verified) or when the DOI answers; otherwise
    the synthetic stand-in, with the reason. ``figshare``: raises :class:`DataUnavailableError`
    with one clear message when offline. ``synthetic``: always the stand-in. (The real
    public-subset runs are added beside the stand-in by :mod:`pedalrepro.mocap.prepare`.)
    """
    if requested not in SOURCES:
        raise ValueError(f"data_source {requested!r} not in {SOURCES}")
    if requested == "synthetic":
        return "synthetic", "data_source: synthetic requested in the configuration"
    pup = pup or make_pooch()
    if cached_complete(pup):
        return "figshare", "all registry run files cached and verified"
    corrupt, missing = cache_state(pup)
    try:
        figshare_registry(pup, require_doi=True)
        return "figshare", f"downloadable from figshare (DOI {DOI})"
    except DataUnavailableError as exc:
        why = f"{type(exc.__cause__ or exc).__name__}"
        if corrupt:  # the files are the problem, not only the network: name them
            msg = (f"data_source: {requested}: {len(corrupt)} cached figshare file(s) corrupt: "
                   + "; ".join(corrupt) + f"; figshare cannot be reached to fetch them again "
                   f"({why}): replace them with the published files in {pup.abspath}")
            if requested == "figshare":
                raise CorruptDataError(msg) from exc
            return "synthetic", msg + "; the synthetic stand-in is used, not the measurement"
        if requested == "figshare":
            if missing:
                raise DataUnavailableError(
                    f"{exc} Missing from {pup.abspath}: {_listed(missing)} "
                    f"({len(missing)} of rider 3's run files in {REGISTRY.name}).") from exc
            raise
        return "synthetic", (f"figshare unreachable from this machine ({why}); the synthetic "
                             "stand-in is not the measurement")
