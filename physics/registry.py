"""What a system and a model are, and the one registry every consumer reads.

A **System** is one kind of internal part (the moving mass with its cavity, medium and brake; the
spherical pendulum; the plane pendulums). It owns the scenario tables that describe it, their
parameters' metadata, its models by fidelity, its validity conditions and ``auto``'s choice among them,
its derived quantities and error estimates, and an example scenario. ``simulate``, ``LiveRun``, the
sweeps, ``physics info``, the explorer's lists and sliders and the shared test battery all read
``SYSTEMS`` and ``REGISTRY``; none of them names a system.

A **Model** is a system at one fidelity: either an ODE (a right-hand side, its state layout, how its
states become a Trajectory) or a closed form (``solve``).

It sits below the scenario machinery (which reads the systems' tables from it) and the systems (which
register here). Systems register themselves with ``register_system`` from their own folder's ``system`` module;
``load_builtin`` imports every folder of this package that has one, so adding a folder is enough.

Registration is checked. At ``register_system``: every Param's table (its key before the dot) is one of the
system's tables or a shared one (``SHARED_TABLES``). Models and systems may register in either order, so a
system without a full model waits outside ``SYSTEMS`` (nothing lists it as runnable) until its full model comes;
when loading completes and whenever the registry is read (``systems``, ``get_system``, ``get_model``,
``tables``), a system still waiting or a model whose system never came raises RegistrationError naming it.
"""

from __future__ import annotations

import importlib
import pkgutil
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from physics.compiled.dispatch import KERNELS
from physics.compiled.dispatch import rhs as compiled_rhs
from physics.core.trajectory import Trajectory

if TYPE_CHECKING:
    from physics.scenario.scenario import Scenario

FIDELITY_ORDER = ("full", "averaged", "closed")  # dearest first; "auto" chooses among them
# The cheaper models by wall time, cheapest first, unless a system says otherwise (System.cheapest_first): a closed
# form evaluates where the averaged model integrates
CHEAPEST_FIRST = ("closed", "averaged")
SHARED_TABLES = ("body", "initial", "run")  # every scenario's tables (physics/scenario/params.py), no system's own


class RegistrationError(ValueError):
    """A system or model registered incompletely: names the system and what it lacks."""


@dataclass(frozen=True)
class Param:
    """One scenario key's metadata: what a slider, a sweep axis or the docs say about it.

    ``key`` is the dotted TOML key ("mass.m"); ``label`` the short name the papers use; ``unit`` SI;
    ``meaning`` one line for a person; ``lo``, ``hi``, ``step`` the explorer's slider range (a scenario may
    hold any value the table's validation accepts); ``equation`` where the papers define it;
    ``folder`` the explorer's group for it; ``restarts``: a change means something only from t = 0; ``adds``:
    a sweep may set it on a scenario without its table (one key completes the table)."""

    key: str
    label: str
    unit: str
    meaning: str
    lo: float
    hi: float
    step: float
    equation: str = ""
    folder: str = ""
    restarts: bool = False
    adds: bool = False  # setting it on a scenario without its table adds the table (the key completes it)

    @property
    def text(self) -> str:
        return f"{self.label} ({self.unit})" if self.unit else self.label


@dataclass(frozen=True)
class Table:
    """A scenario table a system owns: ``[name]`` parsed into the frozen dataclass ``cls``.

    ``array``: written ``[[name]]``, one table per item (a tuple on the Scenario). ``field``: the Scenario
    attribute, when it differs from ``name``. ``selects``: its presence alone picks the system (a
    ``[cavity]`` with no mass still runs the moving mass; a table with ``selects=False`` only says that it
    belongs to the system, and is refused with any other)."""

    name: str
    cls: type
    array: bool = False
    field: str | None = None
    selects: bool = True
    renamed: tuple[tuple[str, str], ...] = ()  # (TOML key, dataclass field) where the paper's name is a keyword

    @property
    def attribute(self) -> str:
        return self.field or self.name


@dataclass(frozen=True)
class Condition:
    """One validity condition: a number compared with a limit (``value <= limit`` holds). ``name`` is its
    formula as the papers write it; ``sentence`` what it means for the motion, in words for a person (the
    explorer shows it; every condition a system gives has one, which the figure battery checks)."""

    name: str
    value: float
    limit: float
    sentence: str = ""

    @property
    def holds(self) -> bool:
        return self.value <= self.limit

    def __str__(self) -> str:
        sign = "<=" if self.holds else ">"
        return f"{self.name} = {self.value:.3g} {sign} {self.limit:g}"


@dataclass(frozen=True)
class Chart:
    """How a model whose state is not laid out as (omega, internal, attitude, ...) reads as one that is.

    A carry across models (physics/systems/carry.py) matches states by name and solves for omega at a kept
    attitude; a model that integrates other coordinates (the moving mass's averaged model: K's fixed inertial
    frame and the precession phase, so that K cannot turn) gives its ``state`` in that layout (``"wx" ... "qz"``)
    and the two maps: ``from_native(Y (n, m), p) -> (n, len(state))`` and ``to_native(y, p) -> y`` (one state,
    the attitude and omega as given)."""

    state: tuple[str, ...]
    from_native: Callable[[np.ndarray, np.ndarray], np.ndarray]
    to_native: Callable[[np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Model:
    """A system at one fidelity.

    ``pack(scenario) -> p`` makes the parameter vector; ``initial_state(scenario, p) -> y0``;
    ``observe(t, Y, p, scenario) -> Trajectory`` turns states into output; ``invariants(Y, p)``
    gives the inertial angular momentum (n, 3) and energy (n,) that conservation tests check.
    An ODE model gives its right-hand side either as a compiled kernel id (``kernel``, dispatched in
    physics/compiled/dispatch.py so that numba can cache the integrators) or as a Python function
    ``py_rhs(t, y, p, out)`` (stepped by the interpreted twin of the same integrators: slower, no
    compilation; a new system can start this way). ``state`` names the state's entries; ``layout(n)``
    names a state of length n when the length depends on the parameters (N plane pendulums). A closed form gives
    ``solve(scenario, t) -> Trajectory`` instead. ``columns`` are the extra Trajectory columns.

    A closed form's hooks, for a viewer that changes a slider while it runs (physics/stepping/live.py):
    ``proxy`` is the fidelity of the stateful model whose state its rows read as (its K is what a carry keeps);
    ``restart(old_model, old_p, old_sc, y_old, new_model, new_sc, t0, last=None, K_keep=None) -> (ClosedOrigin,
    Carried)`` restarts it at t0 from a running state (physics/systems/restart.py; without it the run restarts
    from t = 0); ``initial_momentum(scenario, G) -> K (3,)`` is its inertial K at t = 0 when |K| = G, if not
    G (sin theta0, 0, cos theta0).

    ``chart``: how its state reads as (omega, internal, attitude) for a carry (``Chart``), when it is not laid out
    so. ``reduce(scenario) -> Model | None``: an exact cheaper form of the same equations for this scenario (the
    moving mass's averaged model of an axisymmetric body), run in its place under the same name and fidelity;
    ``for_scenario`` applies it.

    ``stiff_advice(scenario) -> str``: what sets the fastest rate of this model's internal part and what to
    change, naming the keys, for the refusal of a run too stiff for the explicit integrator.
    """

    name: str
    system: str
    fidelity: str
    summary: str
    state: tuple[str, ...] = ()
    kernel: int | None = None
    py_rhs: Callable | None = None
    pack: Callable | None = None
    initial_state: Callable | None = None
    observe: Callable | None = None
    invariants: Callable | None = None
    solve: Callable[[Scenario, np.ndarray], Trajectory] | None = None
    columns: tuple[str, ...] = field(default=())
    layout: Callable[[int], tuple[str, ...]] | None = None
    proxy: str | None = None
    restart: Callable | None = None
    initial_momentum: Callable[[Scenario, float], np.ndarray] | None = None
    chart: Chart | None = None
    reduce: Callable[[Scenario], Model | None] | None = None
    stiff_advice: Callable[[Scenario], str] | None = None

    def for_scenario(self, sc: Scenario) -> Model:
        """The model that runs ``sc``: its ``reduce`` hook's form where it applies, else this one."""
        if self.reduce is not None:
            return self.reduce(sc) or self
        return self

    def state_names(self, n: int | None = None) -> tuple[str, ...]:
        """The names of the entries of a state of length ``n`` (``state`` when the length is fixed)."""
        if self.layout is not None and n is not None:
            return tuple(self.layout(n))
        return self.state

    def slices(self, n: int | None = None) -> dict[str, slice]:
        """Named parts of the state: ``omega`` (body angular velocity), ``quat`` (attitude, scalar first),
        ``internal`` (the part's own coordinates and rates, possibly empty) and ``work`` (the rest: dissipated
        work, a chart index)."""
        names = self.state_names(n)
        q = names.index("qw")
        return dict(omega=slice(0, 3), internal=slice(3, q), quat=slice(q, q + 4), work=slice(q + 4, len(names)))

    def rhs(self, t: float, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """dy/dt as a new array (a convenience for tests and scipy; the integrators call the kernel)."""
        out = np.empty_like(np.asarray(y, dtype=float))
        if self.py_rhs is not None:
            self.py_rhs(t, np.asarray(y, dtype=float), p, out)
            return out
        compiled_rhs(self.kernel, t, np.asarray(y, dtype=float), p, out)
        return out


def _none(sc, item=None) -> dict:
    return {}


@dataclass
class System:
    """One kind of internal part, with everything that depends on which part it is.

    Hooks (each takes the Scenario): ``check(sc)`` raises ScenarioError for combinations its tables' own
    validation cannot see (a mass heavier than the body); ``conditions(sc)`` lists the averaged model's
    validity conditions; ``choose(sc) -> (fidelity, reason)`` is ``auto``'s pick; ``available(sc, fidelity)
    -> (ok, why)`` says whether a registered model covers this scenario; ``derived(sc)`` the papers'
    quantities by name; ``error_bounds(sc, fidelity)`` the estimated max |theta - theta_full| (rad) of a
    cheaper fidelity, or None (``error_method`` says how they were obtained); ``edit(data, key, value)``
    applies one slider value to a scenario's dict
    (a zero mass removes the mass); ``values(sc, item=None)`` the slider values describing a scenario (item
    picks one of an array table's items).
    ``amplitude(tr, sc)`` is the internal part's largest excursion over a run (the sweeps' max_displacement).
    ``initial_keys``: keys of the shared [initial] table that belong to its part (the moving mass's
    ``mass_state``), each with the value meaning what every other system does (``"rest"``: the part starts at
    rest relative to the body). A scenario of another system drops that value (files written before the key was
    the moving mass's carry it) and refuses any other, naming the owner.
    ``example`` is a scenario (TOML text) that shows the part at work. ``borrows``: tables of a system registered
    before it whose Params it uses as its own sliders (the plane pendulums' ``pendulum.k`` sets every
    [[plane_pendulum]], so one slider serves both pendulum systems); its ``edit`` maps them onto its tables.

    For a state carried across a change (physics/systems/carry.py): ``parts`` maps an optional table (its
    Scenario attribute) to the state entries that belong to it, dropped when the table is absent and started
    afresh when it appears; ``start_part(part, model, sc, y, p, K, idx) -> (y, iterations)`` says how such a part
    starts (its entries ``y[idx]``, omega solved so that the model's inertial K stays ``K``); without it, or
    when it returns ``y`` unchanged, the part starts at rest relative to the body.
    ``check_run(sc)`` raises ScenarioError before a run (any fidelity) for what only a run needs.
    ``braking_time(G, b, lam)``: the time a braking torque b brings |G| to zero against a medium lam, or None
    when the system has no law for it. ``torque_direction(sc, q, K)``: the inertial unit direction of its control
    torque at attitude ``q`` and inertial momentum ``K`` (without it, the brake's -K/|K|; the moving mass's
    thrusters are fixed in the body). ``end_locked(sc)``: where its energy sink can lead, for
    physics/systems/end_state.py: an ``EndLocked`` (which entries of its full model's state are the part's
    coordinates, varied to find the relative equilibrium, and which are their rates, zero there), or a sentence
    saying why its scene has no fixed end state (no dissipation); None: the system states no end state.
    ``tunings(sc)``: the papers' tuning rules for its part, name -> {dotted key: value} (what a design is
    compared with); a rule the scenario cannot take raises ScenarioError.
    ``cheapest_first(sc)``: its cheaper models by wall time on ``sc``, cheapest first (CHEAPEST_FIRST unless a
    closed form costs more there), the order ``auto`` tries them in, by its own rule and under the step budget.
    ``quantities``: (unit, meaning) of ``derived``'s keys for ``physics info``; ``quantity(name)`` the same for
    keys built at run time (one per pendulum), or None.
    ``figure(sc, state, view)`` the part's picture as plain primitives in body coordinates
    (physics/core/figure.py; ``state`` a run's internal coordinates at one row, ``view`` a ``figure.View``);
    ``actions`` the controls it adds beyond its sliders (``figure.Action``).
    """

    name: str
    label: str
    summary: str
    tables: tuple[Table, ...]
    example: str
    params: tuple[Param, ...] = ()
    folders: tuple[str, ...] = ()  # the explorer's slider groups, in order (Param.folder names them)
    borrows: tuple[str, ...] = ()  # another system's tables its Params name (see above)
    initial_keys: dict[str, Any] = field(default_factory=dict)  # [initial] keys it owns -> the others' value
    default: bool = False  # runs a scenario that has none of the systems' selecting tables (a bare body)
    check: Callable[[Any], None] | None = None
    conditions: Callable[[Any], list[Condition]] = lambda sc: []
    choose: Callable[[Any], tuple[str, str]] | None = None
    available: Callable[[Any, str], tuple[bool, str]] = lambda sc, fidelity: (True, "")
    derived: Callable[[Any], dict] = _none
    error_bounds: Callable[[Any, str], float | None] = lambda sc, fidelity: None
    error_method: str = ""  # how error_bounds were obtained (derived's ``error_bound_method``, the badge)
    edit: Callable[[dict, str, Any], None] | None = None
    values: Callable[..., dict[str, float]] = _none
    amplitude: Callable[[Trajectory, Any], float] | None = None
    parts: dict[str, tuple[str, ...]] = field(default_factory=dict)
    start_part: Callable | None = None
    check_run: Callable[[Any], None] | None = None
    braking_time: Callable[[float, float, float], float] | None = None
    tunings: Callable[[Any], dict[str, dict[str, float]]] | None = None
    cheapest_first: Callable[[Any], tuple[str, ...]] = lambda sc: CHEAPEST_FIRST
    torque_direction: Callable[[Any, Any, Any], Any] | None = None
    end_locked: Callable[[Any], Any] | None = None
    quantities: dict[str, tuple[str, str]] = field(default_factory=dict)
    quantity: Callable[[str], tuple[str, str] | None] = lambda name: None
    figure: Callable[[Any, dict, Any], tuple] = lambda sc, state, view: ()
    actions: tuple = ()
    models: dict[str, Model] = field(default_factory=dict)

    @property
    def fidelities(self) -> tuple[str, ...]:
        """"auto" and the registered fidelities, dearest first."""
        known = [f for f in FIDELITY_ORDER if f in self.models]
        return ("auto", *known, *sorted(set(self.models) - set(known)))

    def pick(self, sc) -> tuple[str, str]:
        """``auto``'s fidelity and reason: the system's chooser, else the cheapest registered model (by
        ``cheapest_first``, then any fidelity it does not name) whose conditions hold and that is available, else
        the full model."""
        if self.choose is not None:
            return self.choose(sc)
        failed = [c for c in self.conditions(sc) if not c.holds]
        if failed:
            return "full", "conditions fail: " + "; ".join(map(str, failed))
        named = [f for f in self.cheapest_first(sc) if f in self.models and f != "full"]
        rest = [f for f in reversed(self.fidelities[1:]) if f not in named and f != "full"]
        for fid in (*named, *rest):
            if self.available(sc, fid)[0]:
                return fid, "conditions hold"
        return "full", "no cheaper model"


SYSTEMS: dict[str, System] = {}  # the runnable systems: each has its full model
REGISTRY: dict[str, Model] = {}  # "system/fidelity" -> Model
_WAITING: dict[str, System] = {}  # registered, its full model not yet
_LOADING = threading.RLock()
_LOADED = False
# Bumped by every registration change: a view built from the registry (the scenario's table maps) is kept
# until it changes, so reading a scenario's attribute costs a dict lookup, not a walk of every system's tables.
_VERSION = 0
_CHECKED = -1  # the version check_complete last passed
_TABLES: tuple[int, list] = (-1, [])


def version() -> int:
    """The registry's version: it changes whenever a system or model is registered or removed."""
    return _VERSION


def _changed() -> None:
    global _VERSION
    _VERSION += 1


def _check_params(system: System) -> None:
    owned = {t.name for t in system.tables}
    others = {t.name for s in (*SYSTEMS.values(), *_WAITING.values()) for t in s.tables}
    for table in system.borrows:
        if table not in others:
            raise RegistrationError(f"system {system.name!r} borrows the table [{table}], which no system registered "
                                    "before it has")
    for param in system.params:
        table = param.key.partition(".")[0]
        if table not in owned and table not in SHARED_TABLES and table not in system.borrows:
            raise RegistrationError(
                f"system {system.name!r}: Param {param.key!r} names the table [{table}], which is neither one of its "
                f"tables ({', '.join(sorted(owned)) or 'none'}) nor a shared one ({', '.join(SHARED_TABLES)})")


def _place(system: System) -> None:
    """In SYSTEMS once it has its full model, else waiting for it."""
    if "full" in system.models:
        _WAITING.pop(system.name, None)
        SYSTEMS[system.name] = system
    else:
        _WAITING[system.name] = system


def register_system(system: System) -> System:
    if system.name in SYSTEMS or system.name in _WAITING:
        raise ValueError(f"system {system.name!r} registered twice")
    _check_params(system)
    for model in [m for m in REGISTRY.values() if m.system == system.name]:  # models registered first
        system.models[model.fidelity] = model
    _place(system)
    _changed()
    return system


def unregister_system(name: str) -> None:
    """Remove a system and its models (for tests that register a toy system)."""
    SYSTEMS.pop(name, None)
    _WAITING.pop(name, None)
    for key in [k for k, m in REGISTRY.items() if m.system == name]:
        del REGISTRY[key]
    _changed()


def register(model: Model) -> Model:
    if model.name in REGISTRY:
        raise ValueError(f"model {model.name!r} registered twice")
    if model.kernel is not None and model.kernel not in KERNELS:
        raise RegistrationError(f"model {model.name!r} of the system {model.system!r}: kernel id {model.kernel!r} is "
                                f"not one physics/compiled/dispatch.py knows ({', '.join(map(str, KERNELS))})")
    REGISTRY[model.name] = model
    system = SYSTEMS.get(model.system) or _WAITING.get(model.system)
    if system is not None:
        system.models[model.fidelity] = model
        _place(system)
    _changed()
    return model


def check_complete() -> None:
    """Raise RegistrationError if a registered system has no full model or a model's system was never registered."""
    if len(REGISTRY) == sum(len(s.models) for s in SYSTEMS.values()) and not _WAITING:
        return  # every model sits in a runnable system (the common case, counted without a walk)
    problems = [f"system {name!r} has no full model (registered: {', '.join(s.models) or 'none'})"
                for name, s in _WAITING.items()]
    problems += [f"model {m.name!r} belongs to the system {m.system!r}, which is not registered"
                 for m in REGISTRY.values() if m.system not in SYSTEMS and m.system not in _WAITING]
    if problems:
        raise RegistrationError("; ".join(problems))


def load_builtin() -> None:
    """Import the ``system`` module of every folder of physics/systems (each registers its system)."""
    global _LOADED
    if _LOADED:
        return
    with _LOADING:
        if _LOADED:
            return
        package = importlib.import_module("physics.systems")  # discovery, at run time: the systems sit above

        for info in sorted(pkgutil.iter_modules(package.__path__), key=lambda i: i.name):
            if info.ispkg:
                try:
                    importlib.import_module(f"{package.__name__}.{info.name}.system")
                except ModuleNotFoundError as exc:
                    if exc.name != f"{package.__name__}.{info.name}.system":
                        raise
        _LOADED = True


def _ready() -> None:
    """Loaded, and every registration complete (checked again after any change: a toy registered later too)."""
    global _CHECKED
    if _CHECKED == _VERSION and _LOADED:
        return
    load_builtin()
    check_complete()
    _CHECKED = _VERSION


def systems() -> dict[str, System]:
    _ready()
    return SYSTEMS


def get_system(name: str) -> System:
    _ready()
    return SYSTEMS[name]


def get_model(system: str, fidelity: str) -> Model:
    _ready()
    return REGISTRY[f"{system}/{fidelity}"]


def tables() -> list[tuple[System, Table]]:
    """Every registered system's tables, in registration order (built once per registry version)."""
    global _TABLES
    _ready()
    if _TABLES[0] != _VERSION:
        _TABLES = (_VERSION, [(s, t) for s in SYSTEMS.values() for t in s.tables])
    return _TABLES[1]
