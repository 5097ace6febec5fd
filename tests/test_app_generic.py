"""The explorer names no system (issue 22): a system brings its picture, controls and words (physics.figure,
its conditions' sentences), and the app draws, labels, offers and explains them without knowing which it is.

The names come from physics.SYSTEMS: every table (its TOML name and its Scenario attribute) and every parameter
key. An app file that names one in code (an attribute ``sc.mass``; a string that is a table's name, holds a
key, "pendulum.k", or starts with a table's, "pendulum.") knows a system. Comments and docstrings may name one
as an example; they are left out. No file is exempt: the explorer's own scenes are scenario files too
(assets/scenarios/explorer).
"""

from __future__ import annotations

import ast
from pathlib import Path

import physics

APP = Path(__file__).resolve().parents[1] / "app"


def _names() -> tuple[set[str], set[str]]:
    """(attributes, strings) that name a system's table or key."""
    attributes, strings = set(), set()
    for s in physics.SYSTEMS.values():
        for t in s.tables:
            attributes.add(t.attribute)
            strings |= {t.name, t.attribute}
        strings |= {p.key for p in s.params}
    return attributes, strings


def _code_names(path: Path, attributes: set[str], strings: set[str]) -> list[str]:
    """What the file's code (not its docstrings and comments) names: attributes and string constants."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    docs = {id(n.body[0].value) for n in ast.walk(tree)
            if isinstance(n, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and n.body
            and isinstance(n.body[0], ast.Expr) and isinstance(n.body[0].value, ast.Constant)}
    keys = {s for s in strings if "." in s}  # "pendulum.k": a key anywhere in a string
    prefixes = tuple(f"{t}{c}" for t in strings if "." not in t for c in ".[")  # "pendulum." or "plane_pendulum["
    found = []
    for n in ast.walk(tree):
        if isinstance(n, ast.Attribute) and n.attr in attributes:
            found.append(f"{path.name}:{n.lineno} .{n.attr}")
        elif isinstance(n, ast.Constant) and isinstance(n.value, str) and id(n) not in docs:
            if n.value in strings or any(k in n.value for k in keys) or n.value.startswith(prefixes):
                found.append(f"{path.name}:{n.lineno} {n.value[:60]!r}")
    return found


def test_no_app_file_names_a_system_table_or_key():
    attributes, strings = _names()
    assert attributes and strings  # the systems are registered: the test looks for something
    found = [f for path in sorted(APP.rglob("*.py"))
             for f in _code_names(path, attributes, strings)]
    assert found == [], "app code names a system's tables or keys:\n" + "\n".join(found)


def test_the_check_finds_a_name_when_there_is_one(tmp_path):
    """The search itself: a file that reads a table and a key is caught, one that names them in words is not."""
    attributes, strings = _names()
    table = next(iter(physics.SYSTEMS.values())).tables[0]
    key = next(p.key for s in physics.SYSTEMS.values() for p in s.params)
    bad = tmp_path / "bad.py"
    bad.write_text(f"def f(sc, v):\n    return sc.{table.attribute}, v['{key}']\n", encoding="utf-8")
    assert len(_code_names(bad, attributes, strings)) == 2
    good = tmp_path / "good.py"
    good.write_text(f'"""Draws the {table.name}."""\n# {key}\nx = 1\n', encoding="utf-8")
    assert _code_names(good, attributes, strings) == []


def test_physics_sizes_a_figure_by_the_body_the_app_draws():
    """physics.figure.body_extent (what a system's sizes and the figure battery's bound are fractions of) is the
    extent of the solid the explorer draws for the body."""
    from app.engine.geometry import body_shape

    for A, B, C, M in [(1.0, 1.0, 1.4, 1.0), (1.0, 1.0, 0.5, 2.0), (1.5, 1.0, 2.0, 1.0), (2.0, 2.0, 2.0, 5e-324)]:
        assert physics.figure.body_extent(A, B, C, M) == body_shape(A, B, C, M).extent


def test_a_button_that_sets_sliders_sits_in_their_folder():
    """Each control sits where the guide puts it (issue 24): a system's button that sets parameters ("Tune to
    resonance" sets the spring k) is in the folder of the sliders it sets, under them, not in Model."""
    from app.engine import controls
    from app.engine.actions import system_actions

    checked = 0
    for s in physics.SYSTEMS.values():
        sc = physics.Scenario.from_toml(s.example)
        for a in system_actions(sc, "button"):
            if a.apply is None or not a.shown(sc):
                continue
            folders = {controls.BY_KEY[k.partition("#")[0]].folder for k in a.apply(sc) if k in controls.BY_KEY}
            assert folders <= {a.folder}, (s.name, a.label, a.folder, folders)
            checked += bool(folders)
    assert checked  # at least one such button exists: the test looks at something
