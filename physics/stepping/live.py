"""Stepping a scenario piece by piece, for an interactive viewer.

``LiveRun(scenario)`` holds the model, its parameter vector, the state y, the time t and the
compiled DOP853's step size. ``advance(dt)`` integrates [t, t + dt] and returns the rows reached as a
Trajectory; the step size carries over, so pieces cost what one long run costs and agree with
``simulate`` to the integrator's tolerance. ``retune(scenario)`` swaps the parameters (and the model, when
the fidelity changes) and carries the state over. The end of braking and integration faults (a non-finite state,
step-size underflow, the gimbal singularity, and a problem too stiff for the explicit integrator: a call
that runs out of steps while they are held at the stability limit, or, first after a (re)start, one that would,
seen after EARLY_STEPS) are recorded in ``status`` and
``message``, never raised: a viewer shows them and keeps the last good state. ``retune`` keeps the inertial
angular momentum K and the attitude across a change (``physics.carry``) and reports the change of E.

The closed fidelity has no state to step: its rows are evaluated from its start (t = 0, or where a retune
restarted it from the state then, ``origin``) at the times asked for.
A scenario's ``run.method`` RK4, RK8 or midpoint (with ``run.dt``) steps with that compiled fixed-step
method instead of DOP853, as ``simulate`` does: both loop over the same stepper (physics/stepping/stepper.py,
whose docstring is the stepping contract); ``advance`` is its loop in pieces, at most MAX_STEPS_PER_CALL steps
a call, turning the stepper's ending statuses into ``status`` and ``message``.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from contextlib import contextmanager

import numpy as np

from physics.core.blame import NUMERICAL, input_fault, most_extreme, plain_words
from physics.core.errors import IntegrationFault, NumericalFault, ScenarioError
from physics.core.trajectory import Trajectory
from physics.kernels.build import pick
from physics.registry import get_system
from physics.scenario.params import FIXED_STEP_METHODS
from physics.scenario.scenario import Scenario
from physics.stepping.simulate import spans
from physics.stepping.stepper import BRAKED as BRAKED_STATUS
from physics.stepping.stepper import (
    MAX_STEPS,
    STATUS_TEXT,
    STIFF,
    STIFFNESS_CHECK_STEPS,
    Piece,
    Stepper,
    brake_and_medium,
    check_method,
)
from physics.systems.carry import CannotCarry, carry_state
from physics.systems.choice import Resolved, resolve
from physics.systems.restart import ClosedOrigin, carry_to_closed

RUNNING, BRAKED, FAULT = "running", "braked", "fault"
# bounds the wall time of one advance(); the rest waits for the next call. One stiffness check's worth, so that a
# stiff problem is found by the call that runs out of steps
MAX_STEPS_PER_CALL = STIFFNESS_CHECK_STEPS
# A (re)started run's first call stops after this many steps to look whether the step is held at the stability
# limit too far short of the call's end to get there within its budget: a stiff scene (pendulum.c_d = 1e12) was
# found only after the call's 200 000 steps, 1.9 s of its tab for every restart and every fuzzed change
EARLY_STEPS = 2_000


class LiveRun:
    """One scenario integrated in pieces. Not thread-safe: one owner thread calls its methods.

    Attributes: ``scenario``, ``model``, ``fidelity`` (resolved), ``reason`` (why auto chose it),
    ``p``, ``y`` (state at ``t``), ``h`` (next step size, 0 before the first step), ``status``
    (RUNNING, BRAKED or FAULT), ``message`` (why it stopped), ``last`` (one-row Trajectory at t),
    ``nsteps`` and ``nfev`` (totals), ``stepper`` (physics.stepping.stepper.Stepper: the method, tolerances,
    step size and stiffness count; None for a closed form).

    A shallow copy of ``vars(run)`` is a snapshot of the run (the explorer's undo restores one): every attribute
    is replaced, never changed in place, the stepper included (a call steps a copy of it).
    """

    def __init__(self, scenario: Scenario, fidelity: str | None = None):
        with _numerical_refused(scenario):
            self._start(scenario, fidelity)

    # ---- set-up -------------------------------------------------------------------------
    def _start(self, scenario: Scenario, fidelity: str | None) -> None:
        res = resolve(scenario, fidelity)
        self.scenario = scenario
        self.requested = fidelity or scenario.run.fidelity
        self.model, self.fidelity, self.reason = res.model, res.fidelity, res.reason
        self.t = 0.0
        self.stepper: Stepper | None = None  # None for a closed form
        self._early = True  # the first call looks for stiffness early (EARLY_STEPS)
        self.nsteps = 0
        self.nfev = 0
        self.status = RUNNING
        self.message = ""
        self.energy_change: float | None = None  # what the last retune did to E (J); None after a (re)start
        self.edit = None  # the last retune's physics.carry.Carried
        self.edit_note = ""  # why the last retune could not keep the state
        self.origin: ClosedOrigin | None = None  # where a closed form was restarted with the state kept
        self._set_params(scenario)
        if self.model.solve is not None:
            self.p = np.zeros(0)
            self.y = np.zeros(0)
            self.last = self._closed(np.array([0.0]))
            self._require_finite_row("the closed form's theta, K and E at t = 0")
            return
        self.p = np.asarray(self.model.pack(scenario), dtype=float)
        check_method(self.model, scenario, _method(scenario))
        self.y = np.asarray(self.model.initial_state(scenario, self.p), dtype=float).copy()
        _require_finite(scenario, self.y, "the initial state")
        self.stepper = Stepper(self.model, scenario, self.y, method=_method(scenario), p=self.p, kernels=pick)
        self.last = self._observe(np.array([0.0]), self.y[None, :])
        self._require_finite_row("theta, |K| and E at t = 0")

    def _require_finite_row(self, what: str) -> None:
        """ScenarioError naming the extreme value when the last row (theta, |K|, E, omega, the attitude) or the
        inertial K vector is not finite: a closed form's start is checked as a state is (G0 = 1e-300 on the
        pendulum's averaged solution gave K's direction as NaN)."""
        with np.errstate(all="ignore"):
            K = np.atleast_1d(self.momentum())
        row_ok = bool(_finite_rows(self.last)[-1])
        _require_finite(self.scenario, np.append(K, 0.0 if row_ok else np.nan), what)

    @contextmanager
    def _as_it_was_if_refused(self, scenario: Scenario):
        """On ScenarioError inside the block, or an arithmetic failure with ``scenario`` (refused as
        ``_numerical_refused`` says), every attribute back as it was before it (then re-raised)."""
        before = dict(self.__dict__)
        try:
            with _numerical_refused(scenario):
                yield
        except ScenarioError:
            self.__dict__.update(before)
            raise

    def _set_params(self, scenario: Scenario) -> None:
        """The readouts of the scenario's run: rtol, the braking torque b and the medium's lambda."""
        self.rtol = scenario.run.rtol
        self.b, self.lam = brake_and_medium(scenario)

    @property
    def p(self) -> np.ndarray:
        """The parameter vector the run steps with (empty for a closed form)."""
        return self._p

    @p.setter
    def p(self, value) -> None:
        self._p = value
        if getattr(self, "stepper", None) is not None:
            self.stepper = copy.copy(self.stepper)  # never changed in place: see the class docstring
            self.stepper.p = value

    @property
    def h(self) -> float:
        """The step size the next call starts with (0: the integrator guesses; 0 for a closed form)."""
        return self.stepper.h if self.stepper is not None else 0.0

    @property
    def atol(self) -> float:
        return self.stepper.atol if self.stepper is not None else 0.0

    def reset(self) -> None:
        """Back to t = 0 with the current scenario. Raises ScenarioError, with the run as it was, when the
        scenario cannot start there (a value carried into a running state may make t = 0 non-finite)."""
        with self._as_it_was_if_refused(self.scenario):  # refused: the run goes on as it was, never half started
            self._start(self.scenario, self.requested)

    def retune(self, scenario: Scenario, fidelity: str | None = None, *, keep_state: bool = True) -> bool:
        """Run ``scenario`` from now on. Returns True when the current state was carried over, False when
        it restarted from t = 0. Raises ScenarioError (before changing anything) when the scenario cannot run.

        With ``keep_state`` the state is carried (``physics.carry``): the attitude, the internal coordinates
        that still exist and the inertial angular momentum K are kept, omega is solved for, t goes on, and
        ``energy_change`` is what the edit did to E (J). A closed form has no state: one whose Model has a
        ``restart`` hook is restarted at t from the present K and attitude (physics/systems/restart.py; the
        spherical pendulum's averaged solution with its bob put at rest). When the state cannot be kept the run
        restarts from t = 0 and ``edit_note`` says why; ``energy_change`` is then None."""
        with self._as_it_was_if_refused(scenario):  # the arithmetic of the new values too: refused, nothing changed
            return self._retune(scenario, fidelity, keep_state)

    def _retune(self, scenario: Scenario, fidelity: str | None, keep_state: bool) -> bool:
        res = resolve(scenario, fidelity)
        if res.model.solve is None:
            check_method(res.model, scenario, _method(scenario))
        carried, origin, note = None, None, ""
        if keep_state and self.status != FAULT:
            y_old = self.y if self.model.solve is None else None
            K_shown = None if self.model.solve is None else self.momentum()  # a closed form's K, not its row's
            try:
                if res.model.solve is None:
                    carried = carry_state(self.model, self.p, self.scenario, y_old, res.model, scenario, last=self.last,
                                          K_keep=K_shown)
                else:
                    origin, carried = carry_to_closed(self.model, self.p, self.scenario, y_old, res.model, scenario,
                                                      self.t, last=self.last, K_keep=K_shown)
            except CannotCarry as exc:
                note = f"state not kept: {exc}; restarted from t = 0"
        if carried is None:  # a refusal from here on leaves the run as it was: retune's block restores it
            self._start(scenario, fidelity)
            self.energy_change, self.edit, self.edit_note = None, None, note
            return False
        _require_finite(scenario, carried.y, "the state carried over")
        if origin is not None:
            return self._go_on_closed(scenario, fidelity, res, origin, carried)
        return self._go_on_state(scenario, fidelity, res, carried)

    def _go_on_state(self, scenario: Scenario, fidelity: str | None, res: Resolved, carried) -> bool:
        """Go on from now with the carried state under ``scenario`` (ScenarioError if its row is not finite)."""
        p = np.asarray(res.model.pack(scenario), dtype=float)
        if res.model is self.model and self.stepper is not None:
            stepper = copy.copy(self.stepper)  # never changed in place: see the class docstring
            stepper.retune(scenario, carried.y, method=_method(scenario), p=p)  # atol and the count kept
            self.stepper = stepper
        else:  # a new model: its own atol and stiffness count; the braking law's G0 is the run's, if measured
            G0 = self.stepper.G0 if self.stepper is not None else None
            self.stepper = Stepper(res.model, scenario, carried.y, method=_method(scenario), p=p, G0=G0,
                                   kernels=pick)
        self._early = True  # new parameters may be stiff where the old were not
        self.origin = None
        self.model, self.fidelity = res.model, res.fidelity
        self.p = p
        self.y = carried.y
        self.energy_change, self.edit, self.edit_note = carried.dE, carried, ""
        self.scenario = scenario
        self.requested = fidelity or scenario.run.fidelity
        self.reason = res.reason
        self._set_params(scenario)
        if self.status == BRAKED and self.b == 0.0:
            self.status, self.message = RUNNING, ""
        self.last = self._observe(np.array([self.t]), self.y[None, :])
        self._require_finite_row("theta, |K| and E of the state carried over")
        return True

    def _go_on_closed(self, scenario: Scenario, fidelity: str | None, res: Resolved, origin: ClosedOrigin,
                      carried) -> bool:
        """Go on from now with a closed form restarted at the present K and attitude (physics/systems/restart.py);
        ScenarioError when the closed form is not finite there."""
        self.scenario, self.requested = scenario, fidelity or scenario.run.fidelity
        self.model, self.fidelity, self.reason = res.model, res.fidelity, res.reason
        self.stepper, self.p, self.y = None, np.zeros(0), np.zeros(0)
        self._set_params(scenario)
        self.origin = origin
        if self.status == BRAKED and self.b == 0.0:
            self.status, self.message = RUNNING, ""
        self.last = self._closed(np.array([self.t]))
        self._require_finite_row("the closed form's theta, K and E where it starts")
        self.energy_change = float(self.last.E[0]) - carried.E_before
        self.edit, self.edit_note = carried, ""
        return True

    def momentum(self) -> np.ndarray:
        """The inertial angular momentum K (3,) now, kg m^2/s. A closed form keeps K's direction fixed in space:
        along G0 (sin theta0, 0, cos theta0) from its start (or where its Model's ``initial_momentum`` says),
        turned by where it was restarted."""
        if self.model.solve is None:
            return np.asarray(pick(self.model.invariants)(self.y[None, :], self.p)[0][0], dtype=float)
        G = float(self.last.K[0])
        if self.origin is not None:
            return self.origin.momentum(G)
        if self.model.initial_momentum is not None:
            return self.model.initial_momentum(self.scenario, G)
        from physics.scenario.initial import initial_G

        _, _, th0 = initial_G(self.scenario)
        return G * np.array([math.sin(th0), 0.0, math.cos(th0)])

    # ---- stepping -----------------------------------------------------------------------
    @np.errstate(all="ignore")  # a non-finite row ends the run with a message (_cut_at_nonfinite), not a warning
    def advance(self, dt: float, samples: int = 1) -> Trajectory:
        """Integrate over [t, t + dt] and return the rows reached at ``samples`` evenly spaced times
        in (t, t + dt] (fewer if the run stops or the per-call step budget runs out first).
        Returns an empty Trajectory once the run has ended."""
        if self.status != RUNNING or not dt > 0:
            return self._empty()
        samples = max(1, int(samples))
        if self.stepper is None:
            return self._advance_closed(self.t + dt * np.arange(1, samples + 1) / samples)
        # a fixed step has no step budget of its own: at most MAX_STEPS_PER_CALL steps a call, so a tiny run.dt
        # (1e-12 s) slows the run instead of freezing its caller (a tab's loop) for hours
        dt = min(dt, self.stepper.reach(MAX_STEPS_PER_CALL))
        t_out = np.concatenate([[self.t], self.t + dt * np.arange(1, samples + 1) / samples])
        # compiled, or its interpreted twin while the compiled kernels are being built (physics.kernels.build)
        self.stepper = copy.copy(self.stepper)  # never changed in place: see the class docstring
        piece = self._step(t_out)
        self.nfev += piece.nfev
        self.nsteps += piece.nsteps
        if piece.status == BRAKED_STATUS:
            self.status = BRAKED
            self.message = f"{STATUS_TEXT[piece.status]} at t = {piece.t_last:.6g} s"
        elif piece.ended:  # recorded, never raised: the viewer shows it and keeps the last good state
            self.status = FAULT
            fault = piece.fault()
            # at the run's start it is the input's, and the user must learn which value (as physics.simulate says)
            self.message = str(input_fault(self.scenario, fault, spans(self.scenario)) or fault)
        if not len(piece.rows_t):
            return self._empty()
        tr = self._cut_at_nonfinite(self._observe(piece.rows_t, piece.rows_y))
        if not len(tr):
            return self._empty()
        self.t = float(tr.t[-1])
        self.y = piece.rows_y[len(tr) - 1].copy()
        self.last = tr.slice(len(tr) - 1)
        return tr

    def _step(self, t_out: np.ndarray) -> Piece:
        """One call's piece: the stepper's call, or, first after a (re)start, EARLY_STEPS steps, the early look
        for stiffness, and the rest of the call's budget."""
        if not self._early or self.stepper.method != "auto":
            return self.stepper.step(self.y, t_out, MAX_STEPS_PER_CALL)
        self._early = False
        first = self.stepper.step(self.y, t_out, EARLY_STEPS)
        if first.status != MAX_STEPS:
            return first
        left = MAX_STEPS_PER_CALL - first.nsteps
        why = self.stepper.stiff_short_of(first.t_last, first.y_last, first.nsteps, first.t_last - float(t_out[0]),
                                          float(t_out[-1]), left)
        if why:
            return dataclasses.replace(first, status=STIFF, what=why)
        reached = first.n - 1  # the output rows; a last accepted state beyond them is where the rest starts
        rest = self.stepper.step(first.y_last, np.concatenate([[first.t_last], t_out[first.n:]]), left)
        return dataclasses.replace(rest, nfev=first.nfev + rest.nfev, nsteps=first.nsteps + rest.nsteps,
                                   rows_t=np.concatenate([first.rows_t[:reached], rest.rows_t]),
                                   rows_y=np.vstack([first.rows_y[:reached], rest.rows_y]))

    def _cut_at_nonfinite(self, tr: Trajectory, after: float = math.inf) -> Trajectory:
        """``tr`` up to its first row with a non-finite theta, |K|, E, omega or attitude (before ``after``),
        which stops the run as a fault: a finite state can still give E = inf (M = 1e308), and a viewer must
        never show NaN as a running value."""
        ok = _finite_rows(tr) | (tr.t > after)
        if ok.all():
            return tr
        bad = int(np.argmin(ok))
        self.status = FAULT
        self.message = f"theta, |K| or E became non-finite (NaN or infinity) at t = {tr.t[bad]:.6g} s"
        return tr.slice(0, bad)

    def _advance_closed(self, times: np.ndarray) -> Trajectory:
        try:
            tr = self._closed(times)
        except NUMERICAL as exc:  # the closed forms' own integrations raise RuntimeError (seed 004 eq. (13))
            self.status, self.message = FAULT, f"closed form failed: {plain_words(exc)}"
            return self._empty()
        stop = tr.info.get("t_stop")
        braked = "braking" in str(tr.info.get("stop_reason", "")) and stop is not None
        # what follows the end of the spin is the braking's, not a fault
        tr = self._cut_at_nonfinite(tr, after=stop if braked else math.inf)
        if braked and self.status != FAULT:
            self.status = BRAKED
            self.message = f"braking brought |G| to zero at t = {stop:.6g} s"
        if len(tr):
            self.t = float(tr.t[-1])
            self.last = tr.slice(len(tr) - 1)
        return tr

    def _closed(self, times: np.ndarray) -> Trajectory:
        if self.origin is not None:
            return self.origin.evaluate(self.model, times)
        t_all = np.concatenate([[0.0], times]) if times[0] > 0 else times
        tr = self.model.solve(self.scenario, t_all)
        if times[0] > 0:
            tr = tr.slice(1)
        return tr

    def _observe(self, t: np.ndarray, Y: np.ndarray) -> Trajectory:
        return pick(self.model.observe)(np.asarray(t, dtype=float), np.ascontiguousarray(Y), self.p, self.scenario)

    def _empty(self) -> Trajectory:
        return self.last.slice(0, 0)

    # ---- readouts -----------------------------------------------------------------------
    @property
    def ended(self) -> bool:
        return self.status != RUNNING

    def torque_direction(self) -> np.ndarray | None:
        """The inertial unit direction of the control torque now (the brake's -K/|K|, or where the system's
        ``torque_direction`` says: a thruster's body axis), None when none acts (b = 0, the run over, K = 0)."""
        if self.b <= 0 or self.ended or not len(self.last):
            return None
        K = self.momentum()
        hook = get_system(self.scenario.system).torque_direction
        if hook is not None:
            return hook(self.scenario, self.last.quat[0], K)
        n = float(np.linalg.norm(K))
        # from K, not from the torque: b = 1e-300 underflows b K/|K| to a norm of 0
        return -K / n if n > 0 else None

    def remaining_braking_time(self) -> float:
        """Time left until |G| reaches zero under braking (the system's ``braking_time`` from the current |G|:
        the moving mass's seed 004 eq. (11), whose averaged G' = -b - lambda G gives it from |G| alone), inf
        without braking or when the system has no such law."""
        braking_time = get_system(self.scenario.system).braking_time
        if self.b <= 0 or braking_time is None:
            return math.inf
        if self.status == BRAKED:
            return 0.0
        G = float(self.last.K[-1]) if len(self.last) else 0.0
        return float(braking_time(G, self.b, self.lam)) if G > 0 else 0.0


__all__ = ["BRAKED", "FAULT", "RUNNING", "LiveRun", "Resolved", "resolve"]


def _method(scenario: Scenario) -> str:
    """The stepper's method for a live run: the scenario's fixed-step method, else the compiled DOP853 (scipy's
    methods run whole runs only)."""
    return scenario.run.method if scenario.run.method in FIXED_STEP_METHODS else "auto"


@contextmanager
def _numerical_refused(scenario: Scenario):
    """An arithmetic or linear-algebra failure (or an integration fault) while a scenario is being started or
    carried over is a refusal of the scenario: ScenarioError naming its most extreme value and what failed in
    plain words. Found by a fuzz of retune: mass.Omega = 1.7e100 raised OverflowError from the quasi-static
    displacement, which the explorer showed as "OverflowError: (34, 'Numerical result out of range')"."""
    try:
        # numpy's overflow warnings would only print to the server's console: what went wrong is said in the
        # ScenarioError, or the values are checked for being finite (_require_finite) before anything is shown
        with np.errstate(all="ignore"):
            yield
    except ScenarioError:
        raise
    except NumericalFault as exc:  # already names its key
        raise ScenarioError(exc.key, exc.value, f"the run cannot start from it: {exc.what}; choose a value nearer "
                            "the scenario's other scales") from exc
    except (*NUMERICAL, IntegrationFault) as exc:
        key, value = most_extreme(scenario)
        raise ScenarioError(key, value, f"the run cannot start from it: {plain_words(exc)}; choose a value nearer "
                            "the scenario's other scales") from exc


def _finite_rows(tr: Trajectory) -> np.ndarray:
    """Per row: whether theta, |K|, E, omega and the attitude are all finite."""
    return (np.isfinite(tr.theta) & np.isfinite(tr.K) & np.isfinite(tr.E)
            & np.all(np.isfinite(tr.omega), axis=1) & np.all(np.isfinite(tr.quat), axis=1))


def _require_finite(scenario: Scenario, values: np.ndarray, what: str) -> None:
    """ScenarioError, naming the scenario's most extreme value, when ``values`` are not all finite: a run must
    never start (or go on) from NaN or inf (G0 = 1e200 gave E = inf and theta = NaN that a viewer showed)."""
    if np.all(np.isfinite(values)):
        return
    key, value = most_extreme(scenario)
    raise ScenarioError(key, value, f"makes {what} non-finite (overflow or underflow): choose a value nearer 1 in size")
