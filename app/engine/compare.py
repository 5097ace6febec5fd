"""Compare mode: a second live run of the same scene with one difference the user picked (another value of
one slider's parameter, several sliders' values at once (a design's optimum), or another fidelity), stepped
on the engine's clock. No viser here: the engine owns
a ``Comparison`` (``engine.compare``, None when off) and calls it from four places: ``_restarted`` (the
first run started again: so does the second, from the same state, K and attitude, with the difference carried
onto it), ``_note_edit`` (an
edit went on with the state kept: the second run is retuned the same way, its own K kept), ``_advance``
(the same simulated dt, timed with the first run's, so the clock's budget counts both) and the "compare"
action (``set_compare``). If one run faults or brakes, it shows its own status and the other goes on.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

import physics

from . import controls, edits
from . import frame as frames
from .buffers import PLOT_POINTS, RECENT, SAMPLES_PER_FRAME, TRAIL_POINTS, WHOLE_RUN_POINTS
from .geometry import E3, Ring, align
from .history import DecimatingStore

PLACES = ("beside", "superimposed")  # where the second body is drawn (app.scene.compare_view)
CHALLENGE = "challenge"  # a Difference's key for the braking challenge's optimal law (app.engine.challenge)
SLIDERS = "sliders"  # a request's key for several sliders at once: ("sliders", ((key, value), ...)), a design's optimum


@dataclass(frozen=True)
class Difference:
    """What the second run changes: ``key`` a slider's key and ``value`` its other value, or ``key`` None and
    ``value`` another fidelity, or ``key`` SLIDERS and ``value`` several (slider key, value) pairs."""

    key: str | None
    value: float | str | tuple[tuple[str, float], ...]

    def label(self) -> str:
        """The second run's name, as the plots' legend and the readouts say it ("m = 0 kg")."""
        if self.key is None:
            return f"fidelity {self.value}"
        if self.key == CHALLENGE:
            return "the optimal law -b K/|K|"
        return ", ".join(_named(k, float(v)) for k, v in self.pairs())

    def own_label(self, scenario: physics.Scenario) -> str:
        """The first run's name for the same difference ("m = 0.2 kg")."""
        if self.key is None:
            return f"fidelity {scenario.run.fidelity}"
        if self.key == CHALLENGE:
            return "your thrusters"
        values = controls.values_of(scenario)
        return ", ".join(_named(k, values[k]) for k, _ in self.pairs())

    def pairs(self) -> tuple[tuple[str, float], ...]:
        """The (slider key, value) pairs it sets: one, or several."""
        return self.value if self.key == SLIDERS else ((self.key, float(self.value)),)


def _named(key: str, value: float) -> str:
    p = controls.BY_KEY[key]
    return f"{p.label} = {controls.fmt(value)}" + (f" {p.unit}" if p.unit else "")


def parse(spec) -> Difference | None:
    """A GUI's request: None or "off"; ("fidelity", name); (key, value). Bad input raises ValueError naming
    what was given and what is allowed."""
    if spec is None or spec == "off":
        return None
    try:
        key, value = spec
    except (TypeError, ValueError):
        raise ValueError(f"compare: {spec!r} is not a difference; expected (parameter key, value) or "
                         f"('fidelity', one of {', '.join(controls.FIDELITIES)})") from None
    if key == "fidelity":
        if value not in controls.FIDELITIES:
            raise ValueError(f"compare: fidelity {value!r} is not one of {', '.join(controls.FIDELITIES)}")
        return Difference(None, value)
    if key == SLIDERS:
        try:
            pairs = tuple(_pair(k, v) for k, v in value)
        except (TypeError, ValueError) as exc:
            raise ValueError(str(exc) if str(exc).startswith("compare:") else f"compare: {str(value)[:80]!r} is "
                             "not a list of (parameter key, value) pairs") from None
        if not 1 <= len(pairs) <= len(controls.BY_KEY) or len({k for k, _ in pairs}) != len(pairs):
            raise ValueError(f"compare: {str(value)[:80]!r} must name one or more different sliders")
        return Difference(SLIDERS, pairs)
    key, value = _pair(key, value)
    return Difference(key, value)


def _pair(key, value) -> tuple[str, float]:
    if key not in controls.BY_KEY:
        raise ValueError(f"compare: {key!r} is not a slider's parameter (one of {', '.join(controls.BY_KEY)})")
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"compare: {controls.BY_KEY[key].label} = {value!r} is not a finite number")
    return key, value


def second_scenario(engine, diff: Difference) -> physics.Scenario:
    """The first run's scene with the difference: its base and slider changes plus the other value (or its
    scenario under the other fidelity). Raises ScenarioError naming the parameter when that cannot run."""
    sc = engine.scenario
    if diff.key is None:
        return sc.replace(run=dataclasses.replace(sc.run, fidelity=diff.value))
    if diff.key == CHALLENGE:
        if getattr(engine, "challenge", None) is None:
            raise physics.ScenarioError("compare", diff.value, "races a braking challenge, and none is running")
        return engine.challenge.optimal
    for key, value in diff.pairs():
        if sc.system not in controls.BY_KEY[key].systems:
            raise physics.ScenarioError(key, value, f"is not a parameter of a {sc.system} scene "
                                        f"(compare another of its sliders, or the fidelity)")
    changes = controls.merge_changes(engine.changes, dict(diff.pairs()))
    return controls.apply_changes(engine.base, changes).replace(run=sc.run)


class Comparison:
    """The second run, its plot buffers and what its frame needs (``frame``: drawn in the first run's view,
    with its arrows' scales)."""

    def __init__(self, engine, diff: Difference):
        self.diff = diff
        self.seq = 0
        self.applied_seq = 0
        self.trail = Ring(TRAIL_POINTS, 3)  # kept empty: one trail (the first body's) is enough to read
        self.error = ""  # why the second run could not follow the last edit (it goes on as it was)
        self.restart(engine)
        # the first run's undo snapshots (app.engine.edits) -> this run's state then; None: from before compare mode
        self._undo: dict[int, dict | None] = {id(s): None for s in engine.guard.undo}

    # ---- following the first run ---------------------------------------------------------------
    def restart(self, engine) -> None:
        """From t = 0, as the first run just did, from the first run's start: the same inertial K (size and
        direction) and the same attitude, so the same theta(0), with the difference carried onto it
        (physics.LiveRun.retune); a difference in the start itself (a parameter that restarts: G0, theta0) starts
        the second run from its own start. Raises ScenarioError when the scene with the difference cannot run
        (the caller turns compare mode off and says why)."""
        second = second_scenario(engine, self.diff)
        run = physics.LiveRun(second)  # validates it; and the start it has of its own
        if self.diff.key in (None, CHALLENGE) or not any(controls.BY_KEY[k].restarts for k, _ in self.diff.pairs()):
            start = physics.LiveRun(engine.scenario)  # the first run's start: its K and attitude at t = 0
            if start.retune(second, keep_state=True):
                run = start
        self._save_for_undo(engine)
        self.run = run
        self.error = ""
        self.plot = Ring(PLOT_POINTS, 4)
        self.plot_all = DecimatingStore(WHOLE_RUN_POINTS, 4)
        self.shape = engine._shape(self.scenario)
        K0 = self.run.momentum()
        self.world_wxyz = align(K0, E3) if np.linalg.norm(K0) > 0 else np.array([1.0, 0, 0, 0])
        self._record(self.run.last)

    def follow(self, engine) -> None:
        """The first run went on under edited parameters: the second goes on under the same edit (its state,
        K included, carried by physics.LiveRun.retune), the difference kept."""
        self._save_for_undo(engine)
        try:
            kept = self.run.retune(second_scenario(engine, self.diff), keep_state=True)
        except physics.ScenarioError as exc:
            self.error = f"the second run goes on unedited: {exc}"
            return
        self.error = ""
        self.shape = engine._shape(self.scenario)
        if kept:
            self._record(self.run.last)
        else:  # a closed form cannot carry the state: it restarts at 0 while the first run goes on
            self.plot = Ring(PLOT_POINTS, 4)
            self.plot_all = DecimatingStore(WHOLE_RUN_POINTS, 4)
            self._record(self.run.last)

    def _save_for_undo(self, engine) -> None:
        """The first run's guard has just saved a change for undo (app.engine.edits.Snapshot): save this run's state
        before the change too, under the same snapshot, so that an undo brings both back to one t."""
        if not hasattr(self, "run"):
            return
        undo = engine.guard.undo
        live = {id(s) for s in undo}
        self._undo = {k: v for k, v in self._undo.items() if k in live}
        if undo and id(undo[-1]) not in self._undo:
            self._undo[id(undo[-1])] = {k: (v.copy() if isinstance(v, np.ndarray) else v)
                                        for k, v in vars(self.run).items()}

    def undo_to(self, snap, engine) -> bool:
        """The first run went back to ``snap``: so does this one (False when it has no state from then: the
        change was made before compare mode was turned on)."""
        state = self._undo.pop(id(snap), None)
        if state is None:
            return False
        vars(self.run).clear()
        vars(self.run).update(state)
        self.shape = engine._shape(self.scenario)
        for buffer in (self.plot, self.plot_all):
            edits.rewind(buffer, self.run.t)
        self._record(self.run.last)
        return True

    def advance(self, dt: float) -> None:
        """The same simulated dt the first run is given; a model error becomes this run's fault."""
        if self.run.ended or dt <= 0:
            return
        try:
            tr = self.run.advance(dt, samples=SAMPLES_PER_FRAME)
        except Exception as exc:
            self.run.status, self.run.message = "fault", f"{type(exc).__name__}: {exc}"
            return
        if len(tr):
            self._record(tr)

    def _record(self, tr: physics.Trajectory) -> None:
        rows = np.column_stack([tr.t, tr.theta, tr.K, tr.E])
        self.plot.extend(rows)
        self.plot_all.extend(rows)

    @property
    def scenario(self) -> physics.Scenario:
        return self.run.scenario

    def frame(self, view: str, view_values: dict[str, float], K_ref: float, w_ref: float) -> frames.Frame:
        """This run's frame in the first run's ``view`` and ``view_values``, its arrows scaled by the first's
        ``K_ref`` and ``w_ref``."""
        self.seq += 1
        return frames.make_frame(self.run, seq=self.seq, applied=self.applied_seq, view=view,
                                 world_wxyz=self.world_wxyz, K_ref=K_ref, w_ref=w_ref, extent=self.shape.extent,
                                 view_values=view_values, trail=self.trail.values(), polhode=None)

    # ---- what the panel shows --------------------------------------------------------------------
    def series(self, span: str, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(theta, |K|, E) of the second run at the first run's plotted times ``t``; past its end (a fault,
        a brake) its last values."""
        rows = (self.plot if span == RECENT else self.plot_all).values()
        if not len(rows) or not len(t):
            return np.zeros(len(t)), np.zeros(len(t)), np.zeros(len(t))
        return tuple(np.interp(t, rows[:, 0], rows[:, i]) for i in (1, 2, 3))

    def readouts(self) -> dict[str, str]:
        last = self.run.last
        d = {"t": f"{self.run.t:.4g} s", "theta": f"{last.theta[0]:.6f} rad", "|K|": f"{last.K[0]:.6g} kg m^2/s",
             "E": f"{last.E[0]:.6g} J"}
        if self.run.status != "running":
            d["status"] = self.run.status + (f": {self.run.message[:100]}" if self.run.message else "")
        if self.error:
            d["note"] = self.error[:160]
        return d


def set_compare(engine, spec) -> None:
    """The "compare" action: turn compare mode on with a difference, or off (None / "off"). Turned on, both
    runs start at t = 0 from the same state (the first restarts): one clock from one start."""
    diff = parse(spec)
    engine.compare_note = ""
    if diff is None:
        engine.compare = None
    else:
        engine.compare = Comparison(engine, diff)  # raises ScenarioError before anything changes
        engine.run.reset()
        engine._restarted()  # restarts the second run too (restart_compare)
    engine.scene_changed = engine.plots_changed = True


def restart_compare(engine) -> None:
    """Called by Engine._restarted: the second run starts again with the first; a difference the new scene
    cannot take (a mass value in a pendulum scene) turns compare mode off, saying why."""
    if engine.compare is None:
        return
    try:
        engine.compare.restart(engine)
    except physics.ScenarioError as exc:  # said under the readouts (a new scene clears engine.error)
        engine.compare = None
        engine.compare_note = f"compare mode off: {exc}"


def undo_compare(engine, snap) -> None:
    """Called by the "undo" action after the first run went back to ``snap``."""
    if engine.compare is not None and not engine.compare.undo_to(snap, engine):
        engine.compare = None
        engine.compare_note = "compare mode off: the undo went back to before it was turned on"


def frame_of(engine):
    """The second run's frame (app.engine.frame.Frame), in the first's view and with its arrows' scales, so that
    arrow lengths compare."""
    return engine.compare.frame(engine.view, engine.view_values, engine.K_ref, engine.w_ref)


def readout_md(engine) -> str:
    """Both runs' theta, |K| and E, one line each, named by the difference ("" when compare mode is off)."""
    c = engine.compare
    if c is None:
        return getattr(engine, "compare_note", "")
    first = {k: v for k, v in engine.readouts().items() if k in ("theta", "|K|", "E")}
    if engine.run.status != "running":
        first["status"] = engine.run.status
    lines = [f"**compare** · run 1: {c.diff.own_label(engine.scenario)} · run 2: {c.diff.label()}",
             "run 1: " + " · ".join(f"{k} = {v}" for k, v in first.items()),
             "run 2: " + " · ".join(f"{k} = {v}" for k, v in c.readouts().items() if k != "t")]
    return "  \n".join(lines)
