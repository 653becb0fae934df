"""Figure functions are named after the ids they draw, so that grepping an id finds its drawing
function as well as its registry entry (pedalrepro.figures.registry):

- a registered function that draws one id is named that id (``fig_3_8``, ``real_run_panel``);
- one that draws several ids is named ``figs_<topic>`` and lists every id it draws, literally,
  in its docstring's first paragraph;
- no other function of the figure modules (public or private) is named ``fig_...``/``figs_...``.
"""

from __future__ import annotations

import ast
import inspect
import re
from collections import defaultdict
from pathlib import Path

import pytest

from pedalrepro.figures import registry

FIGURES_DIR = Path(registry.__file__).resolve().parent


def functions_by_ids() -> dict[str, list[str]]:
    """``"module.function"`` -> the ids registered with it, in registry order."""
    out: dict[str, list[str]] = defaultdict(list)
    for fid, spec in registry.FIGURES.items():
        out[spec.function].append(fid)
    return dict(out)


def name_problems(function: str, fids: list[str], doc: str | None) -> list[str]:
    """What breaks the naming rule for the registered ``function`` drawing ``fids``."""
    name = function.rsplit(".", 1)[1]
    if len(fids) == 1:
        return [] if name == fids[0] else [f"{function} draws only {fids[0]}: name it {fids[0]}"]
    problems = []
    if not name.startswith("figs_"):
        problems.append(f"{function} draws {len(fids)} ids: name it figs_<topic>")
    first = (inspect.cleandoc(doc or "")).split("\n\n")[0]
    missing = [f for f in fids if not re.search(rf"(?<!\w){re.escape(f)}(?!\w)", first)]
    if missing:
        problems.append(f"{function}'s docstring (first paragraph) does not list {missing}")
    return problems


def figure_like_definitions() -> list[tuple[str, str]]:
    """``(module, name)`` of every function or class defined in a module of
    ``pedalrepro.figures`` whose name, leading underscores stripped, starts with ``fig_`` or
    ``figs_`` (nested definitions included)."""
    found = []
    for path in sorted(FIGURES_DIR.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef) and \
                    re.match(r"figs?_", node.name.lstrip("_")):
                found.append((path.stem, node.name))
    return found


def test_registered_functions_are_named_after_their_ids():
    problems = []
    for function, fids in functions_by_ids().items():
        spec = registry.spec(fids[0])
        problems += name_problems(function, fids, spec.callable().__doc__)
    assert not problems, "\n".join(problems)


def test_no_unregistered_function_is_named_like_a_figure():
    registered = set(functions_by_ids())
    stray = [f"{m}.{n}" for m, n in figure_like_definitions() if f"{m}.{n}" not in registered]
    assert not stray, (f"{stray}: named like a figure function but not registered in "
                       "pedalrepro.figures.registry; register it or give it a name without "
                       "the fig_/figs_ prefix")


def test_every_registered_function_is_found_by_the_scan():
    """The scan above sees the registered functions (it would pass vacuously otherwise)."""
    scanned = {f"{m}.{n}" for m, n in figure_like_definitions()}
    figure_named = {f for f in functions_by_ids() if re.match(r"figs?_", f.rsplit(".", 1)[1])}
    assert figure_named and figure_named <= scanned


@pytest.mark.parametrize(("function", "fids", "doc", "expected"), [
    ("linear.fig_gear_grid", ["fig_3_8"], "", "name it fig_3_8"),
    ("linear.fig_ps_time", ["fig_3_10", "fig_3_11"], "fig_3_10, fig_3_11", "figs_<topic>"),
    ("linear.figs_x", ["fig_3_10", "fig_3_11"], "fig_3_10.\n\nfig_3_11", "['fig_3_11']"),
    ("linear.figs_x", ["fig_3_1", "fig_3_11"], "fig_3_11", "['fig_3_1']"),
])
def test_the_rule_fails_on_a_wrong_name(function, fids, doc, expected):
    problems = name_problems(function, fids, doc)
    assert problems and expected in " ".join(problems)
    assert not name_problems("linear.figs_x", ["fig_3_1", "fig_3_11"], "``fig_3_1``, fig_3_11")
