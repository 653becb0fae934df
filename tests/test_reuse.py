"""Terms of reuse: LICENSE, CITATION.cff, and the terms stated beside every data source.

CITATION.cff is checked against the Citation File Format 1.2.0's required keys (``cffconvert
--validate`` checks the full schema; it is not in the lock, so this test reads the YAML itself).
"""

from __future__ import annotations

import tomllib
from importlib import metadata
from pathlib import Path

import pytest
import yaml

from pedalrepro import paths
from pedalrepro.mocap import fetch

#: Keys CFF 1.2.0 requires at the top level and in every reference.
CFF_REQUIRED = ("cff-version", "message", "title", "authors")
REFERENCE_REQUIRED = ("type", "title", "authors")


def cff_problems(cff: dict) -> list[str]:
    """What a CITATION.cff mapping lacks of CFF 1.2.0's required keys (empty when complete)."""
    problems = [f"missing key {k!r}" for k in CFF_REQUIRED if not cff.get(k)]
    if cff.get("cff-version") not in (None, "1.2.0"):
        problems.append(f"cff-version {cff['cff-version']!r} is not 1.2.0")
    for i, ref in enumerate(cff.get("references") or []):
        problems += [f"references[{i}]: missing key {k!r}" for k in REFERENCE_REQUIRED
                     if not ref.get(k)]
        for j, author in enumerate(ref.get("authors") or []):
            if not (author.get("family-names") or author.get("name")):
                problems.append(f"references[{i}].authors[{j}]: no family-names or name")
    return problems


@pytest.fixture(scope="module")
def cff() -> dict:
    return yaml.safe_load((paths.ROOT / "CITATION.cff").read_text())


@pytest.fixture(scope="module")
def pyproject() -> dict:
    return tomllib.loads((paths.ROOT / "pyproject.toml").read_text())


def test_citation_file_has_the_required_keys(cff):
    assert cff_problems(cff) == []


def test_the_key_check_refuses_an_incomplete_file(cff):
    broken = {k: v for k, v in cff.items() if k != "authors"}
    broken["references"] = [dict(cff["references"][0], title="")]
    assert cff_problems(broken) == ["missing key 'authors'", "references[0]: missing key 'title'"]


def test_citation_licence_and_version_match_pyproject_and_license_file(cff, pyproject):
    assert pyproject["project"]["license"] == {"text": "MIT"}
    assert cff["license"] == "MIT"
    assert cff["version"] == pyproject["project"]["version"]
    text = (paths.ROOT / "LICENSE").read_text()
    assert text.splitlines()[0] == "MIT License"
    assert "Copyright (c) 2026 the pedalrepro developers" in text
    assert "THE SOFTWARE IS PROVIDED \"AS IS\"" in text


def test_citation_cites_the_thesis_and_the_data_it_reproduces(cff):
    refs = {r["type"]: r for r in cff["references"]}
    thesis = refs["thesis"]
    assert thesis["title"].strip() == ("The influence of pedalling on the lateral dynamics of "
                                       "cycling; a modelling approach")
    assert thesis["authors"][0]["family-names"] == "Baines"
    assert thesis["institution"]["name"] == "Delft University of Technology"
    data = refs["data"]
    assert data["doi"] == fetch.DOI  # the DOI the workflow downloads from
    assert data["year"] == 2014
    dois = {r.get("doi") for r in cff["references"]}
    assert "10.1098/rspa.2007.1857" in dois  # Meijaard et al. 2007, the benchmark
    titles = {r["title"] for r in cff["references"]}
    assert "BicycleParameters" in titles


@pytest.mark.parametrize("source", ["data/registry.txt", "data/registry_public.txt",
                                    "data/parameters/bicycleparameters/SOURCE.md",
                                    "data/published/meijaard2007.yaml"])
def test_every_data_source_states_its_terms(source):
    text = (paths.ROOT / source).read_text()
    assert "Terms" in text and "CITATION.cff" in text, f"{source} states no terms of reuse"


def test_unlicensed_rehost_is_fetched_not_committed():
    """The public subset's re-hosting repository has no licence file: its files are fetched from
    their origin by URL, and none of them is in the repository."""
    names = []
    for line in (paths.ROOT / "data/registry_public.txt").read_text().splitlines():
        if line and not line.startswith("#"):
            name, _, url = line.split()
            assert url.startswith("https://raw.githubusercontent.com/mechmotum/no-hands-riding/")
            names.append(name)
    assert len(names) == 5
    committed = [p for name in names for p in paths.ROOT.rglob(name)
                 if not {"results", ".snakemake", ".git"} & set(p.relative_to(paths.ROOT).parts)]
    assert committed == []


def test_bicycleparameters_copies_keep_their_licence():
    """The copied BicycleParameters files carry the BSD 2-clause notice of the distribution."""
    ours = (paths.PARAMETERS / "bicycleparameters" / "LICENSE.txt").read_text()
    dist = metadata.distribution("bicycleparameters")
    shipped = [f for f in dist.files or [] if Path(str(f)).name == "LICENSE.txt"]
    assert shipped, "the installed bicycleparameters ships no LICENSE.txt"
    assert ours == Path(dist.locate_file(shipped[0])).read_text()
    assert "Redistributions of source code must retain the above copyright notice" in ours
