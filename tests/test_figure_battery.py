"""Every registered system's picture, actions and condition words (physics.figure), from its own example.

The explorer draws whatever a system's ``figure`` returns and offers whatever its ``actions`` are, without
knowing the system (issue 22), so each system must hand it something drawable: for a short run at each of its
fidelities, at several rows and on an empty state, every primitive is finite, named once, coloured from the
palette and inside the scene the explorer frames; what it calls static does not move; each action applies to
its own example and gives a scenario physics accepts; each validity condition has its sentence. A system
registered later (the wheel damper) is picked up by the parametrisation alone.

The bound on a drawn point: the explorer scales the body so that its drawn extent (``figure.body_extent``, the
uniform solid of the body's inertia) spans a fixed size, frames the K arrow of length 1 x extent from the centre,
and draws the inertia ellipsoid at 0.6 x extent. A part drawn within REACH x extent of the centre is in that
frame. It is a bound on the picture, not on physics: a moving mass's true displacement may exceed it; its
drawn one is exaggerated and capped so that it does not, which this checks at the largest exaggeration.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

import physics
from physics.core import figure as fig

REACH = 1.0  # x the body's drawn extent: the K arrow's length, which the explorer's camera frames
SHORT_RUN = 1.0  # s: a few frames of motion, enough to move every part off its start
SAMPLES = 21
ROWS = (0, SAMPLES // 2, -1)
SCENARIOS = sorted((Path(__file__).resolve().parents[1] / "assets" / "scenarios").glob("*.toml"))


def _systems():
    return sorted(physics.SYSTEMS)


def _example(name: str) -> physics.Scenario:
    return physics.Scenario.from_toml(physics.SYSTEMS[name].example)


def _extent(sc) -> float:
    b = sc.body
    return fig.body_extent(b.A, b.B, b.C, b.M)


def _short(sc, fidelity: str):
    run = dataclasses.replace(sc.run, fidelity=fidelity, t_end=SHORT_RUN, samples=SAMPLES, t_eval=None)
    return sc.replace(run=run)


def _views(system, sc, extent: float) -> list[fig.View]:
    """The view at rest, and at each end of every view action's range (the largest exaggeration tests the cap)."""
    views = [fig.View(extent=extent)]
    for a in system.actions:
        if a.kind == "view":
            views += [fig.View(**{"extent": extent, a.key: v}) for v in (a.lo, a.hi)]
    return views


@functools.cache
def _states(name: str) -> list[tuple[str, physics.Scenario, dict]]:
    """(what, scenario, state): the example on an empty state, then rows of a short run at each fidelity that
    covers it."""
    sc = _example(name)
    system = physics.SYSTEMS[name]
    out = [("empty state", sc, {})]
    for fidelity in system.fidelities[1:]:
        if not system.available(sc, fidelity)[0]:
            continue
        run = _short(sc, fidelity)
        with warnings.catch_warnings():  # a cheaper model outside its conditions still draws a picture
            warnings.simplefilter("ignore", physics.ValidityWarning)
            tr = physics.simulate(run)
        out += [(f"{fidelity} row {row}", run, fig.row_state(tr.internal, row)) for row in ROWS]
    return out


def _check_primitive(p, extent: float, where: str) -> None:
    assert isinstance(p, fig.Primitive), f"{where}: {p!r} is not a figure primitive"
    assert p.colour in fig.COLOURS, f"{where}: {p.name} colour {p.colour!r}"
    assert not p.role or p.label, f"{where}: {p.name} has a legend role {p.role!r} and no words for it"
    pts = p.points()
    assert pts.ndim == 2 and pts.shape[1] == 3 and np.all(np.isfinite(pts)), f"{where}: {p.name} at {pts}"
    reach = float(np.max(np.linalg.norm(pts, axis=1)))
    assert reach <= REACH * extent, f"{where}: {p.name} reaches {reach:.3g} m > {REACH} x extent {extent:.3g} m"
    sizes = {"Ball": ("radius", "size"), "Segment": ("thickness",), "Disk": ("radius", "size"), "Text": ()}
    for f in sizes[type(p).__name__]:
        v = getattr(p, f)
        assert math.isfinite(v) and v >= 0, f"{where}: {p.name}.{f} = {v}"
    if isinstance(p, fig.Ball):
        assert p.radius <= REACH * extent and p.size < 1, f"{where}: {p.name} is bigger than the scene"
    if isinstance(p, fig.Disk):
        n, r = np.array(p.normal), np.array(p.ref)
        assert abs(np.linalg.norm(n) - 1) < 1e-12 and abs(np.linalg.norm(r) - 1) < 1e-12 and abs(n @ r) < 1e-12
        assert math.isfinite(p.angle)
    if isinstance(p, fig.Text):
        assert p.text, f"{where}: {p.name} has no words"


@pytest.mark.parametrize("name", _systems())
def test_the_figure_is_finite_named_once_and_inside_the_scene(name):
    system = physics.SYSTEMS[name]
    drawn = 0
    static: dict[str, object] = {}
    for what, sc, state in _states(name):
        extent = _extent(sc)
        for view in _views(system, sc, extent):
            where = f"{name}, {what}, {view}"
            parts = system.figure(sc, state, view)
            assert isinstance(parts, tuple), f"{where}: figure returns {type(parts).__name__}, not a tuple"
            names = [p.name for p in parts]
            assert len(set(names)) == len(names), f"{where}: names drawn twice in {names}"
            for p in parts:
                _check_primitive(p, extent, where)
                if not p.moves and view == fig.View(extent=extent):
                    # a static part is drawn once per parameter set: the same in every state of one scenario
                    assert static.setdefault(p.name, p) == p, f"{where}: static {p.name} moved"
            drawn += len(parts)
    if system.figure is not physics.System.__dataclass_fields__["figure"].default:
        assert drawn > 0, f"{name} has a figure hook that draws nothing for its own example"


@pytest.mark.parametrize("name", _systems())
def test_a_role_has_one_kind_and_one_colour(name):
    """One legend line per role: its mark (the primitive's kind) and colour must stand for every part in it."""
    system = physics.SYSTEMS[name]
    sc = _example(name)
    for what, run, state in _states(name)[:2]:
        roles: dict[str, tuple] = {}
        for p in system.figure(run, state, fig.View(extent=_extent(sc))):
            if p.role:
                look = (type(p).__name__, p.colour, p.opacity < 1, p.label)
                assert roles.setdefault(p.role, look) == look, f"{name}, {what}: role {p.role} drawn two ways"


def _apply(sc, edits: dict) -> physics.Scenario:
    """The edits as the explorer applies a slider's: through the system's own ``edit``, else physics'."""
    system = physics.get_system(sc.system)
    data = sc.to_dict()
    for key, value in edits.items():
        if system.edit is not None and key.partition(".")[0] in {t.name for t in system.tables}:
            system.edit(data, key, value)
        else:
            physics.edit_dict(data, key, value, sc)
    return physics.Scenario.from_dict(data)


@pytest.mark.parametrize("name", _systems())
def test_each_action_applies_to_its_own_example(name):
    system = physics.SYSTEMS[name]
    sc = _example(name)
    names = [a.name for a in system.actions]
    assert len(set(names)) == len(names), f"{name}: actions {names}"
    for a in system.actions:
        assert isinstance(a, fig.Action) and a.label and a.folder and a.hint
        assert a.shown(sc) is True, f"{name}: {a.name} is hidden on its own example"
        if a.kind == "button":
            edits = a.apply(sc)
            assert edits and all(isinstance(k, str) for k in edits)
            physics.LiveRun(_apply(sc, edits))  # physics accepts the edits, and a run starts from them
        elif a.kind == "choice":
            assert a.value_of(sc) in a.options
            for option in a.options:
                chosen = _apply(sc, {a.key: option})
                assert a.value_of(chosen) == option, f"{name}: {a.name} set to {option} reads {a.value_of(chosen)}"
        elif a.kind == "item":
            items = sum(len(getattr(sc, t.attribute)) for t in system.tables if t.array)
            options = a.options_of(sc)
            assert len(options) == items > 0 and len(set(options)) == items, f"{name}: {a.name} offers {options}"
            for i in range(items):  # each item's slider values are the system's values for that item
                assert system.values(sc, i)
        else:  # view
            run = physics.LiveRun(sc)
            value = a.initial(sc, _extent(sc), run.last.omega[0]) if a.initial is not None else a.lo
            assert a.lo <= value <= a.hi, f"{name}: {a.name} starts at {value}, outside [{a.lo}, {a.hi}]"
            assert hasattr(fig.View(), a.key)


def test_an_action_hidden_where_its_part_is_absent():
    """An action for a part the scene lacks is not offered: a pendulum's on the moving mass's example."""
    mass = _example("moving_mass")
    for name, system in physics.SYSTEMS.items():
        if name == mass.system:
            continue
        for a in system.actions:
            assert a.shown(mass) is False, f"{name}'s {a.name} is offered on a {mass.system} scene"


def _condition_scenarios():
    out = [(f"{n} example", _example(n)) for n in _systems()]
    for path in SCENARIOS:
        try:
            out.append((path.name, physics.Scenario.load(path)))
        except physics.ScenarioError:  # a file written for a system not registered in this tree
            continue
    return out


@pytest.mark.parametrize("what,sc", _condition_scenarios(), ids=lambda v: v if isinstance(v, str) else "")
def test_every_condition_has_its_sentence(what, sc):
    """The explorer shows a condition's sentence, never its formula as a fallback: each has one."""
    for c in physics.validity_conditions(sc):
        assert c.sentence and c.sentence != c.name, f"{what}: {c.name} has no sentence"


def test_the_drawn_extent_of_a_symmetric_body():
    """body_extent against the solid it stands for: a disk of radius R, height h has C = M R^2/2, A = M (3 R^2
    + h^2)/12, so its largest size is 2R; a box's is its longest side."""
    R, h, M = 0.5, 0.2, 3.0
    A, C = M * (3 * R * R + h * h) / 12, M * R * R / 2
    assert fig.body_extent(A, A, C, M) == pytest.approx(2 * R, rel=1e-12)
    a, b, c = 0.3, 0.5, 1.2
    moments = M / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    assert fig.body_extent(*moments, M) == pytest.approx(c, rel=1e-12)
