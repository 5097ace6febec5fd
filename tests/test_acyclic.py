"""No import cycles inside physics or app, counting the imports written inside functions.

import-linter (tests/test_architecture.py) sees only the layers between packages; an import moved into a
function to dodge a cycle still ties two modules together, so this check reads every ``import`` and
``from ... import`` with ``ast``, wherever it is written (module level, functions, methods, try blocks), and
builds the module graph of one package.

How an import becomes edges (module names inside the package only; anything outside is ignored):

- ``import a.b.c`` is an edge to ``a.b.c``. Importing it also runs ``a/__init__`` and ``a/b/__init__``, but
  those are not counted: every module of physics would otherwise depend on physics/__init__.py, which imports
  the public API, and the graph would say nothing.
- ``from a.b import x``: an edge to ``a.b.x`` when that is a module (a submodule imported by name), else to
  ``a.b`` itself, because ``x`` is then a name that ``a/b/__init__`` must have defined: the submodule needs
  its package's ``__init__`` to have run, a real dependency. So a package's ``__init__`` that imports its
  submodules, one of which takes a name from that ``__init__``, is a cycle.
- ``from . import x`` and ``from ..a import x`` are resolved against the module's own package first, then
  follow the rule above.
- Imports under ``if TYPE_CHECKING:`` are left out: they never run.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def modules(root: Path, package: str) -> dict[str, Path]:
    """Dotted module name -> file, for every .py file of ``package`` under ``root``."""
    out = {}
    for path in sorted((root / package).rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _imports(tree: ast.AST):
    """Every Import/ImportFrom node, at any depth, except those under ``if TYPE_CHECKING:``."""
    stack = [tree]
    while stack:
        node = stack.pop()
        if isinstance(node, ast.If) and _is_type_checking(node):
            stack.extend(node.orelse)  # the else branch does run
            continue
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        stack.extend(ast.iter_child_nodes(node))


def edges(name: str, path: Path, known: dict[str, Path]) -> set[str]:
    """The modules of ``known`` that module ``name`` (file ``path``) imports."""
    out = set()
    is_package = path.name == "__init__.py"
    for node in _imports(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names if alias.name in known)
            continue
        if node.level:  # relative: from its own package, one level up per extra dot
            package = name.split(".") if is_package else name.split(".")[:-1]
            base = package[:len(package) - (node.level - 1)]
            source = ".".join(base + ([node.module] if node.module else []))
        else:
            source = node.module
        for alias in node.names:
            sub = f"{source}.{alias.name}"
            if sub in known:
                out.add(sub)
            elif source in known:
                out.add(source)
    out.discard(name)
    return out


def graph(root: Path, package: str) -> dict[str, set[str]]:
    known = modules(root, package)
    return {name: edges(name, path, known) for name, path in known.items()}


def find_cycle(g: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``g`` as [a, b, ..., a], or None (depth-first search, iterative)."""
    WHITE, GREY, BLACK = 0, 1, 2
    color = dict.fromkeys(g, WHITE)
    for start in sorted(g):
        if color[start] != WHITE:
            continue
        path, stack = [start], [iter(sorted(g[start]))]
        color[start] = GREY
        while stack:
            nxt = next(stack[-1], None)
            if nxt is None:
                color[path.pop()] = BLACK
                stack.pop()
            elif color.get(nxt, BLACK) == GREY:  # an edge out of g leads nowhere
                return path[path.index(nxt):] + [nxt]
            elif color.get(nxt, BLACK) == WHITE:
                color[nxt] = GREY
                path.append(nxt)
                stack.append(iter(sorted(g[nxt])))
    return None


@pytest.mark.parametrize("package", ["physics", "app"])
def test_no_import_cycle(package):
    cycle = find_cycle(graph(ROOT, package))
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_checker_finds_a_cycle_hidden_in_a_function(tmp_path):
    """A synthetic package whose cycle goes through an import inside a function, one through ``from . import``
    of a name its ``__init__`` defines, and an import under TYPE_CHECKING that must not count."""
    pkg = tmp_path / "toy"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from toy import b\n")
    (pkg / "b.py").write_text("def f():\n    from toy.a import g\n    return g\n")
    (pkg / "sub" / "__init__.py").write_text("from toy.sub.leaf import VALUE\nNAME = VALUE\n")
    (pkg / "sub" / "leaf.py").write_text("VALUE = 1\ndef f():\n    from . import NAME\n    return NAME\n")
    (pkg / "c.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from toy import d\n")
    (pkg / "d.py").write_text("import toy.c\n")
    g = graph(tmp_path, "toy")
    assert g["toy.a"] == {"toy.b"} and g["toy.b"] == {"toy.a"}
    assert g["toy.sub.leaf"] == {"toy.sub"} and g["toy.sub"] == {"toy.sub.leaf"}
    assert g["toy.c"] == set() and g["toy.d"] == {"toy.c"}
    cycle = find_cycle(g)
    assert cycle is not None and cycle[0] == cycle[-1] and len(cycle) == 3
    assert find_cycle({k: v for k, v in g.items() if k not in ("toy.a", "toy.sub")}) is None


if __name__ == "__main__":
    for package in sys.argv[1:] or ["physics", "app"]:
        print(package, find_cycle(graph(ROOT, package)))
