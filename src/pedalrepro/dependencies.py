"""What a rule script depends on: its import closure inside ``pedalrepro`` and the data it reads.

``rules/common.smk`` turns :func:`code_inputs` into every rule's code inputs, so that editing a
module or a parameter file reruns exactly the rules that use it, and nobody lists modules by
hand. Everything here is a static reading of the sources (:mod:`ast`; nothing is imported):

* **modules**: every ``import`` / ``from ... import`` statement anywhere in a file (inside
  functions too), absolute (``import pedalrepro.a.b``, ``from pedalrepro import a``) or relative
  (``from . import x``, ``from ..y import z``), followed transitively; importing a module also
  runs its packages' ``__init__.py``, so those are part of the closure.
* **data**: a string literal naming a data file or package resource (``"validation_runs.yaml"``,
  ``"rhs_driver.c"``, ``"bicycleparameters"``; :func:`referenced_files`) makes it an input of
  every rule whose closure holds the module. Files a module reads under a computed name (e.g.
  ``params._parameter_file(name)``) or through a :mod:`pedalrepro.paths` constant
  (``paths.STYLE``) are declared in a module-level tuple of repository-relative paths,
  ``DATA_FILES = ("data/parameters/legs.yaml",)`` (a folder stands for every file under it).
  ``tests/workflow/test_change_tracking.py`` checks the declarations against the files each rule
  really opens in the end-to-end run, so they cannot drift from the code.
* **notebooks**: the code cells of ``.ipynb`` files are read like a script.
"""

from __future__ import annotations

import ast
import json
from collections.abc import Iterable
from functools import cache
from pathlib import Path

from . import paths

__all__ = [
    "DECLARATION", "PACKAGE_DIR", "PACKAGE", "python_source", "module_file", "module_name",
    "import_statements", "imported_modules", "import_closure", "declared_files",
    "LOCATION_MODULES", "referenced_files", "code_inputs",
]

#: Name of the module-level tuple declaring the files a module reads (repository-relative).
DECLARATION = "DATA_FILES"
#: The package's folder and name.
PACKAGE_DIR: Path = Path(__file__).resolve().parent
PACKAGE = PACKAGE_DIR.name


def python_source(path: Path) -> str:
    """Python source of a ``.py`` file, or the code cells of a notebook joined (magics dropped)."""
    text = path.read_text(encoding="utf-8")
    if path.suffix != ".ipynb":
        return text
    cells = json.loads(text).get("cells", [])
    lines = []
    for cell in cells:
        if cell.get("cell_type") != "code":
            continue
        src = cell.get("source", "")
        src = "".join(src) if isinstance(src, list) else src
        lines += [ln for ln in src.splitlines() if not ln.lstrip().startswith(("%", "!"))]
        lines.append("")
    return "\n".join(lines)


@cache
def _tree(path: Path) -> ast.Module:
    try:
        return ast.parse(python_source(path), filename=str(path))
    except SyntaxError as exc:
        raise SyntaxError(f"cannot parse {path} to find its imports: {exc}") from exc


def module_file(name: str, package_dir: Path = PACKAGE_DIR) -> Path | None:
    """Source file of the dotted module ``name`` inside the package, or ``None``.

    ``pedalrepro.nonlinear`` -> ``.../nonlinear/__init__.py``; ``pedalrepro.legs`` -> ``legs.py``.
    """
    parts = name.split(".")
    if parts[0] != package_dir.name:
        return None
    base = package_dir.joinpath(*parts[1:])
    if (base / "__init__.py").is_file():
        return base / "__init__.py"
    if base.with_suffix(".py").is_file():
        return base.with_suffix(".py")
    return None


def module_name(path: Path, package_dir: Path = PACKAGE_DIR) -> str | None:
    """Dotted name of a package source file (``None`` outside the package, e.g. a rule script)."""
    try:
        rel = path.resolve().relative_to(package_dir.parent)
    except ValueError:
        return None
    parts = list(rel.with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _parents(name: str) -> list[str]:
    """``a.b.c`` -> ``["a", "a.b", "a.b.c"]`` (importing a module imports its packages)."""
    parts = name.split(".")
    return [".".join(parts[: i + 1]) for i in range(len(parts))]


def import_statements(path: Path, package_dir: Path = PACKAGE_DIR) -> list[tuple[str, str, int]]:
    """Every import of the package in ``path`` (imports inside functions included), in file order.

    One ``(module, name, line)`` per imported name: ``import pedalrepro.x`` and ``from pedalrepro
    import x`` where ``x`` is a submodule give ``("pedalrepro.x", "", line)``; ``from pedalrepro.x
    import y`` where ``y`` is not a module gives ``("pedalrepro.x", "y", line)``. Relative imports
    are resolved against the file's own module name (and skipped outside the package); imports of
    other packages are left out. The one import scanner of the project: :func:`imported_modules`
    (change tracking) and ``tests/test_imports.py`` (cycles, private helpers) both read it.
    """
    path = Path(path).resolve()
    own = module_name(path, package_dir)
    is_pkg = path.name == "__init__.py"
    package = package_dir.name
    found: list[tuple[str, str, int]] = []
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.Import):
            found += [(alias.name, "", node.lineno) for alias in node.names
                      if alias.name.split(".")[0] == package]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                if own is None:
                    continue  # a relative import outside the package: not ours
                base = own.split(".") if is_pkg else own.split(".")[:-1]
                base = base[: len(base) - (node.level - 1)]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            if stem.split(".")[0] != package:
                continue
            for alias in node.names:
                candidate = f"{stem}.{alias.name}"
                if module_file(candidate, package_dir) is not None:  # `from pkg import module`
                    found.append((candidate, "", node.lineno))
                else:
                    found.append((stem, alias.name, node.lineno))
    return found


def imported_modules(path: Path, package_dir: Path = PACKAGE_DIR) -> set[str]:
    """Package modules imported anywhere in ``path`` (one level, not followed), with their
    packages (importing ``a.b.c`` runs ``a`` and ``a.b`` too); from :func:`import_statements`."""
    return {parent for module, _, _ in import_statements(path, package_dir)
            for parent in _parents(module) if module_file(parent, package_dir) is not None}


def import_closure(sources: Iterable[str | Path],
                   package_dir: Path = PACKAGE_DIR) -> list[Path]:
    """Every package module file reached from ``sources`` (scripts, modules or notebooks).

    Returns the module files (``__init__.py`` of every package passed through included), sorted;
    the sources themselves are not in the list unless they are package modules.
    """
    todo = [Path(s).resolve() for s in sources]
    seen_files: set[Path] = set()
    modules: set[Path] = set()
    while todo:
        path = todo.pop()
        if path in seen_files:
            continue
        seen_files.add(path)
        if module_name(path, package_dir) is not None and path.suffix == ".py":
            modules.add(path)
        for name in imported_modules(path, package_dir):
            f = module_file(name, package_dir)
            if f is not None and f.resolve() not in seen_files:
                todo.append(f.resolve())
    return sorted(modules)


def declared_files(path: str | Path) -> tuple[str, ...]:
    """The repository-relative paths in ``path``'s module-level ``DATA_FILES`` tuple (or ``()``).

    The tuple must be a literal of strings (read without importing the module).
    """
    path = Path(path)
    for node in _tree(path.resolve()).body:
        targets = []
        if isinstance(node, ast.Assign):
            targets = [t.id for t in node.targets if isinstance(t, ast.Name)]
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            targets = [node.target.id]
        if DECLARATION in targets and node.value is not None:
            try:
                value = ast.literal_eval(node.value)
            except ValueError as exc:
                raise ValueError(f"{path}: {DECLARATION} must be a literal tuple of strings"
                                 ) from exc
            if isinstance(value, str) or not all(isinstance(v, str) for v in value):
                raise ValueError(f"{path}: {DECLARATION} must be a tuple of strings, got {value!r}")
            return tuple(value)
    return ()


#: Modules whose string literals name locations rather than files they read (not scanned).
LOCATION_MODULES: tuple[str, ...] = ("paths.py",)


@cache
def _known_files(root: Path, package_dir: Path) -> dict[str, tuple[str, ...]]:
    """Name -> repository-relative paths of every data file (``data/**``), every folder two or more
    levels below ``data`` and every non-Python file of the package, for :func:`referenced_files`.
    """
    names: dict[str, list[str]] = {}
    data = root / "data"
    candidates = [p for p in data.rglob("*") if p.is_file()] if data.is_dir() else []
    candidates += [p for p in data.glob("*/*/") if p.is_dir()] if data.is_dir() else []
    candidates += [p for p in package_dir.rglob("*") if p.is_file()
                   and p.suffix not in (".py", ".pyc") and "__pycache__" not in p.parts]
    for p in candidates:
        try:
            rel = str(p.resolve().relative_to(root))
        except ValueError:
            continue
        names.setdefault(p.name, []).append(rel)
    return {k: tuple(sorted(v)) for k, v in names.items()}


def referenced_files(path: str | Path, root: str | Path = paths.ROOT,
                     package_dir: Path = PACKAGE_DIR) -> tuple[str, ...]:
    """Data files and package resources that a string literal in ``path`` names.

    A literal names a file when it equals the file's name (``"validation_runs.yaml"``,
    ``"rhs_driver.c"``, the folder ``"bicycleparameters"``) or ends with ``/`` + a path under the
    repository (``"data/parameters/legs.yaml"``). :data:`LOCATION_MODULES` are not scanned.
    """
    path = Path(path).resolve()
    if path.name in LOCATION_MODULES and path.parent == package_dir.resolve():
        return ()
    known = _known_files(Path(root).resolve(), package_dir.resolve())
    found: set[str] = set()
    for node in ast.walk(_tree(path)):
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value:
            text = node.value.strip()
            if text in known:
                found.update(known[text])
            elif "/" in text and Path(text).name in known:
                found.update(r for r in known[Path(text).name] if r.endswith(text.lstrip("./")))
    return tuple(sorted(found))


def _expand(rel: str, root: Path) -> list[str]:
    """A declared path as input files: a file itself, a folder as every file under it."""
    p = root / rel
    if p.is_dir():
        return sorted(str(f.relative_to(root)) for f in p.rglob("*") if f.is_file())
    if not p.is_file():
        raise FileNotFoundError(f"declared data file {rel!r} does not exist under {root}")
    return [rel]


def code_inputs(*sources: str | Path, root: str | Path = paths.ROOT,
                package_dir: str | Path | None = None) -> list[str]:
    """Input files of a rule running ``sources``: themselves, their import closure inside the
    package and every file those declare in ``DATA_FILES`` (folders expanded), relative to
    ``root`` (the repository), sorted and without duplicates.

    Parameters
    ----------
    sources
        Rule scripts (``rules/scripts/x.py``), notebooks or modules, relative to ``root`` or
        absolute.
    root
        The repository root (Snakemake's working directory).
    package_dir
        The package whose modules are followed (default ``<root>/src/pedalrepro``, else this
        installed package).
    """
    root = Path(root).resolve()
    files = [(root / s).resolve() for s in sources]
    for f in files:
        if not f.is_file():
            raise FileNotFoundError(f"code_inputs: no such script or notebook {f}")
    # the package of this checkout (a copy of the repository brings its own src/)
    if package_dir is None:
        package_dir = root / "src" / PACKAGE
        package_dir = package_dir if package_dir.is_dir() else PACKAGE_DIR
    package_dir = Path(package_dir).resolve()
    modules = import_closure(files, package_dir)
    out: set[str] = set()
    for f in [*files, *modules]:
        out.add(str(f.relative_to(root)))
        for rel in (*declared_files(f), *referenced_files(f, root, package_dir)):
            out.update(_expand(rel, root))
    return sorted(out)
