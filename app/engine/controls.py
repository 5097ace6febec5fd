"""The control panel: which parameters have sliders, their units and the papers' meaning, and how
slider values become a scenario. Plain Python: the panel (app.panel.panel) makes the sliders from these.

Every change goes through physics (Scenario.from_dict), so a bad combination raises the same
ScenarioError, naming the key and the allowed range, that a scenario file would.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import physics


@dataclass(frozen=True)
class Slider:
    """One slider: a scenario key's metadata from physics (``physics.Param``) and the systems it applies to.
    ``hint`` is the Param's meaning; ``base``: the body or the start, which every system has."""

    key: str
    label: str
    unit: str
    hint: str
    lo: float
    hi: float
    step: float
    systems: tuple[str, ...]
    folder: str
    restarts: bool = False
    base: bool = False

    @property
    def text(self) -> str:
        return f"{self.label} ({self.unit})" if self.unit else self.label


@dataclass(frozen=True)
class Registry:
    """What the panel offers, read from physics' registered systems (``physics.SYSTEMS``): sliders, the
    System dropdown (label -> system name), the fidelities and the slider folders in the panel's order."""

    params: tuple[Slider, ...]
    by_key: dict[str, Slider]
    system_labels: dict[str, str]
    fidelities: tuple[str, ...]
    folders: tuple[tuple[str, tuple[str, ...]], ...]


_CACHE: dict[tuple, Registry] = {}


def _systems() -> list[physics.System]:
    """The registered systems, the default one (a bare body runs it) first, then in registration order."""
    systems = list(physics.SYSTEMS.values())
    return sorted(systems, key=lambda s: not s.default)


def registry() -> Registry:
    """The panel's lists for the systems registered now (a system registered later, a test's toy, shows too)."""
    systems = _systems()
    signature = tuple((s.name, id(s), tuple(s.models)) for s in systems)
    reg = _CACHE.get(signature)
    if reg is None:  # built again only when a system or a model is (un)registered; any tab's thread may do it
        reg = _build(systems)
        _CACHE.clear()
        _CACHE[signature] = reg
    return reg


def _build(systems: list[physics.System]) -> Registry:
    names = tuple(s.name for s in systems)
    sliders: dict[str, Slider] = {}
    for p in physics.BASE_PARAMS:
        sliders[p.key] = Slider(p.key, p.label, p.unit, p.meaning, p.lo, p.hi, p.step, names, p.folder,
                                p.restarts, base=True)
    owners: dict[str, list[str]] = {}
    for s in systems:
        for p in s.params:
            owners.setdefault(p.key, []).append(s.name)
            if p.key not in sliders:  # a key two systems share (the pendulums' bob m): one slider for both
                sliders[p.key] = Slider(p.key, p.label, p.unit, p.meaning, p.lo, p.hi, p.step, (), p.folder or s.label,
                                        p.restarts)
    for key, systems_of in owners.items():
        sliders[key] = replace(sliders[key], systems=tuple(systems_of))
    # The default system's first folder opens the panel with the body under it; the start closes it.
    body, *rest = physics.BASE_FOLDERS
    own = list(dict.fromkeys(p.folder or s.label for s in systems for p in s.params))
    order = [*own[:1], body, *own[1:], *rest]
    folders = tuple((title, tuple(k for k, p in sliders.items() if p.folder == title)) for title in order)
    params = tuple(sliders[k] for _, keys in folders for k in keys)
    fidelities = tuple(dict.fromkeys(f for s in systems for f in s.fidelities))  # each starts with "auto"
    return Registry(params=params, by_key={p.key: p for p in params},
                    system_labels={s.label: s.name for s in systems}, fidelities=fidelities, folders=folders)


def __getattr__(name: str):
    """PARAMS, BY_KEY, SYSTEM_LABELS, FIDELITIES, FOLDERS and SIX (the first folder's keys: the braking paper's
    six), read from physics' registry at each use."""
    reg = registry()
    values = {"PARAMS": reg.params, "BY_KEY": reg.by_key, "SYSTEM_LABELS": reg.system_labels,
              "FIDELITIES": reg.fidelities, "FOLDERS": reg.folders, "SIX": reg.folders[0][1]}
    if name in values:
        return values[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def folders_of(system: str) -> set[str]:
    """The slider folders shown for a scene of ``system``: the body's, the start's and its own."""
    return set(physics.BASE_FOLDERS) | {p.folder for p in registry().params if system in p.systems}


def owns_table(system: str, key: str) -> bool:
    """Whether ``key``'s table (``pendulum`` of ``pendulum.k``) is one of ``system``'s own tables."""
    return key.partition(".")[0] in {t.name for t in physics.get_system(system).tables}


def per_item(key: str, system: str | None = None) -> bool:
    """Whether the slider ``key`` may edit one item of an array table (``pendulum.k#1``: plane pendulum 1): a
    system with sliders of its table (``system`` only, if given) keeps that table as an array of items."""
    owners = _table_owners(key)
    if system is not None:
        owners &= {system}
    return any(t.array for name in owners for t in physics.get_system(name).tables)


def _table_owners(key: str) -> set[str]:
    """The systems with sliders of ``key``'s table (``pendulum``: both pendulum systems); none for the body's
    and the start's or an unknown key."""
    params = registry().params
    if not any(p.key == key and not p.base for p in params):
        return set()
    table = key.partition(".")[0]
    return {s for p in params if not p.base and p.key.partition(".")[0] == table for s in p.systems}


def item_key(key: str, system: str, item: int | None) -> str:
    """The key a slider change is applied with: ``key#item`` when it edits one item of an array table."""
    return f"{key}#{item}" if item is not None and per_item(key, system) else key


def scenario_key(key: str, system: str) -> str:
    """The scenario key a slider stands for in ``system``: a slider of a table the system does not have (the
    pendulum sliders of plane pendulums) sets the system's one table (every [[plane_pendulum]])."""
    tables = physics.get_system(system).tables
    if system not in _table_owners(key) or owns_table(system, key) or len(tables) != 1:
        return key
    return f"{tables[0].name}.{key.partition('.')[2]}"


def values_of(sc: physics.Scenario, item: int | None = None) -> dict[str, float]:
    """Slider values that describe ``sc``: every system's (an absent part's defaults), the scene's own last, then
    the body and the start. The sliders of an array table show its item number ``item`` (0-based), or the first."""
    own = physics.get_system(sc.system)
    v: dict[str, float] = {}
    for system in [s for s in _systems() if s is not own] + [own]:
        v.update(system.values(sc, item))
    v.update(physics.base_values(sc))
    params = registry().params
    for p in params:
        v.setdefault(p.key, p.lo)  # a system that gives no values: its sliders start at their low end
    return {p.key: float(v[p.key]) for p in params}


def apply_changes(base: physics.Scenario, changes: dict[str, float | str]) -> physics.Scenario:
    """``base`` with the slider changes applied, validated by physics (raises ScenarioError).

    The body and the start go through ``physics.edit_dict`` (``initial.G0``/``theta0`` replace an ``omega`` given
    in the file); a part's keys through its system's ``edit`` (a zero ``lambda``, ``b``, ``beta`` or mass ``m``
    removes the medium, the control, the cavity or the mass; a positive one adds it). Pendulum values apply to
    every bob, or with a key ``pendulum.k#i`` to plane pendulum i (0-based) only; ``pendulum.k`` may be
    "resonant". A slider of another system than ``base``'s is kept for later, not applied.
    """
    data = base.to_dict()
    system = physics.get_system(base.system)
    by_key = registry().by_key
    for full_key, value in changes.items():
        key, _, which = full_key.partition("#")
        if key not in by_key or (which and not per_item(key)):
            raise physics.ScenarioError(full_key, value, "is not a parameter of the explorer")
        p = by_key[key]
        if system.name not in p.systems:
            # e.g. a mass slider while a pendulum scene runs: kept for later, not applied; but a table or a list
            # is no slider's value, and it would be kept unjudged
            if not isinstance(value, (int, float, str)) or isinstance(value, bool):
                raise physics.ScenarioError(full_key, value, "must be a number")
            continue
        if p.base or system.edit is None:
            table, _, name = key.partition(".")
            physics.edit_dict(data, f"{table}[{which}].{name}" if which.isdigit() else key, value, base)
        else:
            system.edit(data, full_key, value)
    return physics.Scenario.from_dict(data)


def merge_changes(changes: dict, pending: dict) -> dict:
    """``changes`` updated by ``pending``, latest last: a change to every bob (``pendulum.k``) drops the
    earlier per-bob ones (``pendulum.k#i``), so the order of application is the order of the user's moves."""
    out = {k: v for k, v in changes.items() if k not in pending and k.partition("#")[0] not in pending}
    out.update(pending)
    return out


def restarts(changed: dict) -> bool:
    """Whether a change only makes sense from t = 0 (the start: physics.Param.restarts)."""
    by_key = registry().by_key
    return any(by_key[k.partition("#")[0]].restarts for k in changed if k.partition("#")[0] in by_key)


def slider_range(p: Slider, value: float) -> tuple[float, float]:
    """The slider's range: the spec's, widened to hold a value beyond it (a preset's, a typed one) with room to
    move (twice a value above it, at 2 significant digits; a value below it is the low end)."""
    lo, hi = p.lo, p.hi
    if value > hi:
        wide = float(f"{2 * value:.2g}")
        hi = wide if math.isfinite(wide) else value  # 2 x 1e308 overflows: the value itself is the end
    if value < lo:
        lo = value
    return lo, hi


def fmt(x: float, digits: int = 4) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    if isinstance(x, float) and math.isinf(x):
        return "inf"
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return repr(x)[:40]  # what a raw client sent instead of a number, said as it came
    return f"{x:.{digits}g}"


# auto's accuracy (rad, on theta): the choices the panel offers; None is physics.DEFAULT_ACCURACY
ACCURACY_STEPS = (1e-4, None, 1e-2, 1e-1)


def accuracy_label(value: float | None) -> str:
    return f"{physics.DEFAULT_ACCURACY:g} rad (default)" if value is None else f"{value:g} rad"


def accuracy_options(current: float | None) -> dict[str, float | None]:
    """The dropdown's labels and values; a scene's own accuracy (a file's run.accuracy) is offered too."""
    out = {accuracy_label(v): v for v in ACCURACY_STEPS}
    out.setdefault(accuracy_label(current), current)
    return out
