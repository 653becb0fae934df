"""Import structure of ``src/pedalrepro`` (issue 10 part 3): no cycles, no private helpers
shared across modules, and an ``__all__`` in every public module (issue 26).

A static scan (``ast``) of every module, imports inside functions included: an import hidden in a
function body still makes two modules depend on each other, it only defers the failure. The
graph has one node per module (``pedalrepro.nonlinear.arms``); ``from . import x`` where ``x`` is
a submodule is an edge to that submodule, ``from .x import y`` an edge to ``x``. Importing a
package's ``__init__`` is an edge to the package module, not to every submodule.
"""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

from pedalrepro import dependencies

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "pedalrepro"


def module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted((SRC / PACKAGE).rglob("*.py"))}


def imports(path: Path) -> list[tuple[str, str, int]]:
    """(imported module, imported attribute or "", line) for every import of the package in the
    module: the package's own scanner (``pedalrepro.dependencies.import_statements``)."""
    return dependencies.import_statements(path, SRC / PACKAGE)


def graph() -> dict[str, set[str]]:
    mods = modules()
    known = set(mods)
    edges: dict[str, set[str]] = {m: set() for m in mods}
    for name, path in mods.items():
        for target, _, _ in imports(path):
            # importing pedalrepro.x.y runs pedalrepro.x's __init__ too; the edge that matters
            # for a cycle is to the module itself
            if target in known and target != name:
                edges[name].add(target)
    return edges


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def test_scanner_finds_a_cycle_through_a_function_level_import():
    """The scan sees imports inside functions (the way the nonlinear cycles used to hide)."""
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert cycles(edges) == [["a", "b", "c"]]
    src = "def f():\n    from . import b\n    return b\n"
    tree = ast.parse(src)
    found = [n for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    assert len(found) == 1 and found[0].level == 1


def test_no_import_cycles_in_pedalrepro():
    edges = graph()
    assert len(edges) > 30  # the scan found the package's modules
    assert "pedalrepro.nonlinear.nonlinear_model" in edges["pedalrepro.nonlinear.sweep"] | {
        d for m in edges["pedalrepro.nonlinear.sweep"] for d in edges[m]}
    found = cycles(edges)
    assert not found, "import cycles (imports inside functions included): " + "; ".join(
        " <-> ".join(c) for c in found)


def _private_uses() -> list[str]:
    bad = []
    for name, path in modules().items():
        for target, attr, line in imports(path):
            if attr.startswith("_") and not attr.startswith("__") and target != name:
                bad.append(f"{path.relative_to(SRC)}:{line} imports {target}.{attr}")
    return bad


def test_no_private_helper_used_across_modules():
    bad = _private_uses()
    assert not bad, "private helpers used across modules (make them public or move them): " + \
        "; ".join(bad)


@pytest.mark.parametrize("folder", ["tests", "scripts", "rules/scripts"])
def test_tests_and_scripts_use_no_private_helper(folder):
    """``module._name`` attribute access or ``from pedalrepro.x import _name`` outside src."""
    root = SRC.parent / folder
    bad = []
    for path in sorted(root.rglob("*.py")):  # tests/: the subfolders mirroring src/ too
        tree = ast.parse(path.read_text(), str(path))
        aliases = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith(PACKAGE):
                for a in node.names:
                    if a.name.startswith("_") and not a.name.startswith("__"):
                        bad.append(f"{path.relative_to(root)}:{node.lineno} imports {a.name}")
                    aliases.add(a.asname or a.name)
            elif isinstance(node, ast.Import):
                aliases |= {(a.asname or a.name).split(".")[0] for a in node.names
                            if a.name.startswith(PACKAGE)}
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and node.attr.startswith("_")
                    and not node.attr.startswith("__") and isinstance(node.value, ast.Name)
                    and node.value.id in aliases):
                bad.append(f"{path.relative_to(root)}:{node.lineno} "
                           f"uses {node.value.id}.{node.attr}")
    assert not bad, f"private helpers of pedalrepro used in {folder}: " + "; ".join(bad)


def test_sweep_jobs_import_no_scipy():
    """The NT/NP sweep jobs (rules/scripts/nonlinear_time_chunk.py and nonlinear_time.py: 8 jobs
    each on the thesis grid, ~1 s of start-up apiece) import no scipy module: the compiled
    integrator, the numpy Hann window and the lazy scipy.optimize imports of
    pedalrepro.linear keep it out (scipy.optimize alone cost ~0.5 s per job)."""
    import subprocess
    import sys

    code = ("import sys\nfrom pedalrepro import evaluation, response\n"
            "from pedalrepro.nonlinear import calibration, sweep\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'scipy'))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"


def _bound_names(tree: ast.Module) -> tuple[list[str], list[str]]:
    """(defined, imported): the public names a module binds at top level. Defined: functions,
    classes and assignment targets (an annotation without a value binds nothing); imported:
    ``import``/``from ... import`` aliases (``from __future__`` excluded). ``if TYPE_CHECKING``
    blocks bind nothing at run time and are not read."""
    defined: list[str] = []
    imported: list[str] = []
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            defined.append(node.name)
        elif isinstance(node, ast.Assign):
            defined += [n.id for t in node.targets for n in ast.walk(t) if isinstance(n, ast.Name)]
        elif isinstance(node, ast.AnnAssign) and node.value is not None:
            defined += [n.id for n in ast.walk(node.target) if isinstance(n, ast.Name)]
        elif isinstance(node, ast.ImportFrom) and node.module != "__future__":
            imported += [a.asname or a.name for a in node.names]
        elif isinstance(node, ast.Import):
            imported += [(a.asname or a.name).split(".")[0] for a in node.names]
    public = [n for n in dict.fromkeys(defined) if not n.startswith("_")]
    return public, [n for n in dict.fromkeys(imported) if not n.startswith("_")]


def _declared_all(tree: ast.Module) -> list[str] | None:
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets):
            return ast.literal_eval(node.value)
    return None


def public_modules() -> dict[str, Path]:
    """Modules that must declare ``__all__``: every module whose name does not start with ``_``
    (the set of tests/test_book.py's API check), and each package ``__init__`` that binds a
    public name (its re-exports); a docstring-only ``__init__`` (``pedalrepro``,
    ``pedalrepro.nonlinear``, ``pedalrepro.rider``) has no API of its own."""
    out = {}
    for name, path in modules().items():
        rel = path.relative_to(SRC / PACKAGE)
        if any(p.startswith("_") for p in rel.parts if p != "__init__.py"):
            continue
        if path.name == "__init__.py" and not any(_bound_names(ast.parse(path.read_text()))):
            continue
        out[name] = path
    return out


def test_every_public_module_is_checked():
    mods = public_modules()
    assert len(mods) >= 85  # the scan found the package's modules
    assert {"pedalrepro.figures", "pedalrepro.nonlinear.symbolic",
            "pedalrepro.nonlinear.nonlinear_model"} <= set(mods)
    assert not {"pedalrepro", "pedalrepro.nonlinear", "pedalrepro.rider"} & set(mods)


@pytest.mark.parametrize("name", sorted(public_modules()))
def test_public_module_declares_its_api(name):
    """``__all__`` is a literal list of distinct public names, each bound in the module
    (``from module import *`` binds exactly them), and it is complete:

    * a module lists every public name it *defines* at top level -- function, class or
      assignment (constant, type alias, ``DATA_FILES``) -- and nothing it imports: a re-export
      belongs to a package ``__init__``, and since the book's autodoc documents every name of
      ``__all__``, a listed import would be documented twice. A name is private by its leading
      underscore, never by being left out of ``__all__``.
    * a package ``__init__`` lists every public name it binds: its re-exports.

    The order is free; the book's API pages (``autodoc_member_order: bysource``) follow it, so
    modules keep their source order.
    """
    path = public_modules()[name]
    tree = ast.parse(path.read_text(), str(path))
    declared = _declared_all(tree)
    assert declared is not None, f"{path.relative_to(SRC)} has no __all__"
    assert isinstance(declared, list | tuple) and all(isinstance(n, str) for n in declared)
    assert len(declared) == len(set(declared)), f"duplicates in __all__ of {name}"
    assert not [n for n in declared if n.startswith("_")], f"private names in __all__ of {name}"
    defined, imported = _bound_names(tree)
    expected = set(defined) | (set(imported) if path.name == "__init__.py" else set())
    assert not expected - set(declared), \
        f"{name}: public names missing from __all__: {sorted(expected - set(declared))}"
    assert not set(declared) - expected, (
        f"{name}: __all__ lists names the module does not define (imports go in a package "
        f"__init__): {sorted(set(declared) - expected)}")
    module = importlib.import_module(name)
    assert list(module.__all__) == list(declared)
    star: dict = {}
    exec(f"from {name} import *", star)  # raises on a name the module lacks
    assert set(star) - {"__builtins__"} == set(declared)
