"""Stepping a scenario piece by piece, for an interactive viewer.

``LiveRun(scenario)`` holds the model, its parameter vector, the state y, the time t and the
compiled DOP853's step size. ``advance(dt)`` integrates [t, t + dt] and returns the rows reached as a
Trajectory; the step size carries over, so pieces cost what one long run costs and agree with
``simulate`` to the integrator's tolerance. ``retune(scenario)`` swaps the parameters (and the model, when
the fidelity changes) and carries the state over. The end of braking and integration faults (a non-finite state,
step-size underflow, the gimbal singularity, and a problem too stiff for the explicit integrator: a call
that runs out of steps while they are held at the stability limit) are recorded in ``status`` and
``message``, never raised: a viewer shows them and keeps the last good state. ``retune`` keeps the inertial
angular momentum K and the attitude across a change (``physics.carry``) and reports the change of E.

The closed fidelity has no state to step: its rows are evaluated from its start (t = 0, or where a retune
restarted it from the state then, ``origin``) at the times asked for.
A scenario's ``run.method`` RK4, RK8 or midpoint (with ``run.dt``) steps with that compiled fixed-step
method instead of DOP853, as ``simulate`` does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .carry import CannotCarry, carry_state
from .closed_restart import ClosedOrigin, carry_to_closed
from .compiled import dispatch as kernels
from .compiled import dop853, fixed, midpoint
from .errors import IntegrationFault, ScenarioError
from .kernel_build import pick
from .models.base import Model, get_model
from .params import FIXED_STEP_METHODS
from .scenario import Scenario
from .simulate import ATOL_FACTOR, check_fixed_method
from .trajectory import Trajectory
from .validity import choose_fidelity

RUNNING, BRAKED, FAULT = "running", "braked", "fault"
MAX_STEPS_PER_CALL = 200_000  # bounds the wall time of one advance(); the rest waits for the next call
# h |lambda| above which a step is held by stability, not accuracy: an 8th-order method resolving a mode
# to rtol <= 1e-2 needs h |lambda| under 1; DOP853's stability region reaches about 6 on the real axis
# and 4 on the imaginary one, where the step controller parks a stiff problem's step. The estimate
# below reads up to a few times high (measured: 0.43 for an accuracy-held step, 19 for a stiff one).
STIFF_H_LAMBDA = 3.0
POWER_ITERATIONS = 30  # for the Jacobian's spectral radius (finite differences of the right-hand side)


def spectral_radius(kernel: int, t: float, y: np.ndarray, p: np.ndarray) -> float:
    """Largest |eigenvalue| of the right-hand side's Jacobian at (t, y), 1/s, by power iteration on
    finite differences (2 evaluations per iteration). Used only when a call runs out of steps."""
    y = np.ascontiguousarray(y, dtype=float)
    f0, f1 = np.empty_like(y), np.empty_like(y)
    rhs = pick(kernels.rhs)
    rhs(kernel, t, y, p, f0)
    v = np.random.default_rng(0).standard_normal(y.size)
    v /= np.linalg.norm(v)
    eps = 1e-7 * max(1.0, float(np.linalg.norm(y)))
    radius, previous = 0.0, None
    for _ in range(POWER_ITERATIONS):
        rhs(kernel, t, y + eps * v, p, f1)
        w = (f1 - f0) / eps
        norm = float(np.linalg.norm(w))
        if not math.isfinite(norm) or norm == 0.0:
            break
        # |J v| with |v| = 1 tends to the spectral radius for a real dominant eigenvalue; for an oscillator
        # (u' = v, v' = -Omega^2 u) it alternates between Omega^2 and 1, whose geometric mean is Omega
        radius = norm if previous is None else math.sqrt(norm * previous)
        previous = norm
        v = w / norm
    return radius


@dataclass(frozen=True)
class Resolved:
    """Which model runs a scenario live, and why."""

    model: Model
    fidelity: str
    reason: str


def resolve(scenario: Scenario, fidelity: str | None = None) -> Resolved:
    """The model that ``simulate`` would run (``auto`` resolved), raising ScenarioError if absent."""
    fid = fidelity or scenario.run.fidelity
    reason = "requested"
    if fid == "auto":
        fid, reason = choose_fidelity(scenario)
    try:
        model = get_model(scenario.system, fid)
    except KeyError:
        raise ScenarioError("run.fidelity", fid, f"is not available for {scenario.system}") from None
    if fid == "closed":
        from .validity import closed_form_available

        ok, why = closed_form_available(scenario)
        if not ok:
            raise ScenarioError("run.fidelity", "closed", f"is not available for this scenario: {why}")
    return Resolved(model, fid, reason)


class LiveRun:
    """One scenario integrated in pieces. Not thread-safe: one owner thread calls its methods.

    Attributes: ``scenario``, ``model``, ``fidelity`` (resolved), ``reason`` (why auto chose it),
    ``p``, ``y`` (state at ``t``), ``h`` (next step size, 0 before the first step), ``status``
    (RUNNING, BRAKED or FAULT), ``message`` (why it stopped), ``last`` (one-row Trajectory at t),
    ``nsteps`` and ``nfev`` (totals).
    """

    def __init__(self, scenario: Scenario, fidelity: str | None = None):
        self._start(scenario, fidelity)

    # ---- set-up -------------------------------------------------------------------------
    def _start(self, scenario: Scenario, fidelity: str | None) -> None:
        res = resolve(scenario, fidelity)
        self.scenario = scenario
        self.requested = fidelity or scenario.run.fidelity
        self.model, self.fidelity, self.reason = res.model, res.fidelity, res.reason
        self.t = 0.0
        self.h = 0.0
        self.nsteps = 0
        self.unchecked_steps = 0  # adaptive steps since the last stiffness check
        self.nfev = 0
        self.status = RUNNING
        self.message = ""
        self.energy_change: float | None = None  # what the last retune did to E (J); None after a (re)start
        self.edit = None  # the last retune's physics.carry.Carried
        self.edit_note = ""  # why the last retune could not keep the state
        self.origin: ClosedOrigin | None = None  # where a closed form was restarted with the state kept
        self.rtol = scenario.run.rtol
        self.b = float(scenario.control.b) if scenario.control else 0.0
        self.lam = float(scenario.medium.lambda_) if scenario.medium else 0.0
        if self.model.solve is not None:
            self.p = np.zeros(0)
            self.y = np.zeros(0)
            self.G0 = 1.0
            self._G0_known = False
            self.atol = 0.0
            self.last = self._closed(np.array([0.0]))
            return
        self._set_params(scenario)
        if scenario.run.method in FIXED_STEP_METHODS:
            check_fixed_method(self.model, scenario, scenario.run.method, self.b, self.lam)
        self.y = np.asarray(self.model.initial_state(scenario, self.p), dtype=float).copy()
        _require_finite(scenario, self.y, "the initial state")
        self.atol = self.rtol * ATOL_FACTOR * max(1.0, float(np.max(np.abs(self.y))))
        self._G0_known = self.b > 0
        self.G0 = float(pick(kernels.braking_norm)(self.model.kernel, self.y, self.p)) if self.b > 0 else 1.0
        self.last = self._observe(np.array([0.0]), self.y[None, :])
        _require_finite(scenario, np.array([self.last.theta[0], self.last.K[0], self.last.E[0]]),
                        "theta, |K| and E at t = 0")

    def _set_params(self, scenario: Scenario) -> None:
        self.p = np.asarray(self.model.pack(scenario), dtype=float)
        self.rtol = scenario.run.rtol
        self.b = float(scenario.control.b) if scenario.control else 0.0
        self.lam = float(scenario.medium.lambda_) if scenario.medium else 0.0

    def reset(self) -> None:
        """Back to t = 0 with the current scenario."""
        self._start(self.scenario, self.requested)

    def retune(self, scenario: Scenario, fidelity: str | None = None, *, keep_state: bool = True) -> bool:
        """Run ``scenario`` from now on. Returns True when the current state was carried over, False when
        it restarted from t = 0. Raises ScenarioError (before changing anything) when the scenario cannot run.

        With ``keep_state`` the state is carried (``physics.carry``): the attitude, the internal coordinates
        that still exist and the inertial angular momentum K are kept, omega is solved for, t goes on, and
        ``energy_change`` is what the edit did to E (J). The moving mass's closed form has no state: it is
        restarted at t from the present K and attitude (``physics.closed_restart``); so is the spherical
        pendulum's averaged solution, with its bob put at rest (``physics.pendulum_restart``). When the state
        cannot be kept the run restarts from t = 0 and ``edit_note`` says why; ``energy_change`` is then None."""
        res = resolve(scenario, fidelity)
        if scenario.run.method in FIXED_STEP_METHODS and res.model.solve is None:
            check_fixed_method(res.model, scenario, scenario.run.method,
                               float(scenario.control.b) if scenario.control else 0.0,
                               float(scenario.medium.lambda_) if scenario.medium else 0.0)
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
        if carried is None:
            before = dict(self.__dict__)
            try:
                self._start(scenario, fidelity)
            except ScenarioError:
                self.__dict__.update(before)  # refused: the run goes on as it was
                raise
            self.energy_change, self.edit, self.edit_note = None, None, note
            return False
        _require_finite(scenario, carried.y, "the state carried over")
        if origin is not None:
            return self._go_on_closed(scenario, fidelity, res, origin, carried)
        self.origin = None
        if res.model is not self.model:
            self.model, self.fidelity = res.model, res.fidelity
            self.unchecked_steps = 0
            self.atol = scenario.run.rtol * ATOL_FACTOR * max(1.0, float(np.max(np.abs(carried.y))))
        self.y = carried.y
        self.energy_change, self.edit, self.edit_note = carried.dE, carried, ""
        self.scenario = scenario
        self.requested = fidelity or scenario.run.fidelity
        self.reason = res.reason
        self._set_params(scenario)
        if self.b > 0 and not self._G0_known:  # braking switched on now: measure its end from here
            self._G0_known = True
            self.G0 = float(pick(kernels.braking_norm)(self.model.kernel, self.y, self.p))
        if self.status == BRAKED and self.b == 0.0:
            self.status, self.message = RUNNING, ""
        self.h = 0.0  # the old step size may not suit the new parameters; let the integrator guess
        self.last = self._observe(np.array([self.t]), self.y[None, :])
        return True

    def _go_on_closed(self, scenario: Scenario, fidelity: str | None, res: Resolved, origin: ClosedOrigin,
                      carried) -> bool:
        """Go on from now with a closed form restarted at the present K and attitude (physics.closed_restart)."""
        self.scenario, self.requested = scenario, fidelity or scenario.run.fidelity
        self.model, self.fidelity, self.reason = res.model, res.fidelity, res.reason
        self.p, self.y, self.h, self.atol = np.zeros(0), np.zeros(0), 0.0, 0.0
        self.rtol = scenario.run.rtol
        self.b = float(scenario.control.b) if scenario.control else 0.0
        self.lam = float(scenario.medium.lambda_) if scenario.medium else 0.0
        self.G0, self._G0_known = 1.0, False
        self.origin = origin
        if self.status == BRAKED and self.b == 0.0:
            self.status, self.message = RUNNING, ""
        self.last = self._closed(np.array([self.t]))
        self.energy_change = float(self.last.E[0]) - carried.E_before
        self.edit, self.edit_note = carried, ""
        return True

    def momentum(self) -> np.ndarray:
        """The inertial angular momentum K (3,) now, kg m^2/s. A closed form keeps K's direction fixed in space:
        along G0 (sin theta0, 0, cos theta0) from its start, turned by where it was restarted."""
        if self.model.solve is None:
            return np.asarray(pick(self.model.invariants)(self.y[None, :], self.p)[0][0], dtype=float)
        G = float(self.last.K[0])
        if self.origin is not None:
            return self.origin.momentum(G)
        from .coefficients import initial_G

        w0, _, th0 = initial_G(self.scenario)
        if self.model.name == "spherical_pendulum/averaged":  # K starts as J w0 in the body, inertial at t = 0
            body = self.scenario.body
            Jw = np.array([body.A, body.B, body.C]) * w0
            return G * Jw / np.linalg.norm(Jw)
        return G * np.array([math.sin(th0), 0.0, math.cos(th0)])

    # ---- stepping -----------------------------------------------------------------------
    def advance(self, dt: float, samples: int = 1) -> Trajectory:
        """Integrate over [t, t + dt] and return the rows reached at ``samples`` evenly spaced times
        in (t, t + dt] (fewer if the run stops or the per-call step budget runs out first).
        Returns an empty Trajectory once the run has ended."""
        if self.status != RUNNING or not dt > 0:
            return self._empty()
        samples = max(1, int(samples))
        if self.model.solve is None and self.scenario.run.method in FIXED_STEP_METHODS:
            # a fixed step has no step budget of its own: at most MAX_STEPS_PER_CALL steps a call, so a tiny
            # run.dt (1e-12 s) slows the run instead of freezing its caller (a tab's loop) for hours
            dt = min(dt, MAX_STEPS_PER_CALL * float(self.scenario.run.dt))
        times = self.t + dt * np.arange(1, samples + 1) / samples
        if self.model.solve is not None:
            return self._advance_closed(times)
        t_out = np.concatenate([[self.t], times])
        method = self.scenario.run.method
        if method in FIXED_STEP_METHODS:
            dt_step = float(self.scenario.run.dt)
            if method == "midpoint":
                out = pick(midpoint.integrate)(np.ascontiguousarray(self.y), self.p, t_out, dt_step)
            else:
                out = pick(fixed.run)(fixed.TABLEAUS[method], self.model.kernel, self.y, self.p, t_out, dt_step,
                                      self.b, self.lam, self.G0)
            Y, n, status, t_last, y_last, nfev, nsteps = out
            h = dt_step
            if status == midpoint.NO_CONVERGENCE and method == "midpoint":
                status = dop853.MODEL_FAULT  # reported as a fault below, with the midpoint's own words
                self.message = str(IntegrationFault(midpoint.STATUS_TEXT, float(t_last)))
        else:
            # compiled, or its interpreted twin while the compiled kernels are being built (physics.kernel_build)
            Y, n, status, t_last, y_last, nfev, nsteps, h = pick(dop853.integrate)(
                self.model.kernel, self.y, self.p, t_out, self.rtol, self.atol, self.b, self.lam,
                MAX_STEPS_PER_CALL, self.h, self.G0)
        self.nfev += int(nfev)
        self.nsteps += int(nsteps)
        rows_t, rows_y = t_out[1:n], Y[1:n]
        if method not in FIXED_STEP_METHODS:
            self.unchecked_steps += int(nsteps)
        if status in (dop853.OK, dop853.MAX_STEPS):
            # out of budget is not a fault: keep the progress and the step size, unless the step is held at
            # the explicit method's stability limit (a stiff problem): that never ends. The check runs when
            # a call runs out of steps, and every MAX_STEPS_PER_CALL adaptive steps however they were split
            # into calls (the explorer asks for a few milliseconds' worth at a time).
            self.h = float(h)
            if t_last > (rows_t[-1] if len(rows_t) else self.t):
                rows_t, rows_y = np.append(rows_t, t_last), np.vstack([rows_y, y_last[None, :]])
            if status == dop853.MAX_STEPS or self.unchecked_steps >= MAX_STEPS_PER_CALL:
                self.unchecked_steps = 0
                h_lambda = self.h * spectral_radius(self.model.kernel, float(t_last), y_last, self.p)
                if h_lambda > STIFF_H_LAMBDA:
                    self.status = FAULT
                    self.message = str(IntegrationFault(
                        f"too stiff for the explicit integrator (DOP853): {int(nsteps)} steps covered "
                        f"{float(t_last) - self.t:.3g} s, each held at the stability limit (h |lambda| = "
                        f"{h_lambda:.2g}, fastest mode faster than the motion); lower Omega or chi, or use the "
                        "averaged fidelity", float(t_last)))
        else:
            if t_last > (rows_t[-1] if len(rows_t) else self.t):
                rows_t, rows_y = np.append(rows_t, t_last), np.vstack([rows_y, y_last[None, :]])
            if status == dop853.BRAKED:
                self.status = BRAKED
                self.message = f"{dop853.STATUS_TEXT[status]} at t = {t_last:.6g} s"
            else:
                self.status = FAULT
                self.message = self.message or str(IntegrationFault(dop853.STATUS_TEXT[status], float(t_last)))
        if not len(rows_t):
            return self._empty()
        good = np.all(np.isfinite(rows_y), axis=1)
        if not np.all(good):  # never hand a viewer a non-finite state
            rows_t, rows_y = rows_t[good], rows_y[good]
            self.status = FAULT
            self.message = self.message or "state became non-finite"
            if not len(rows_t):
                return self._empty()
        self.t = float(rows_t[-1])
        self.y = rows_y[-1].copy()
        tr = self._observe(rows_t, rows_y)
        self.last = tr.slice(len(tr) - 1)
        return tr

    def _advance_closed(self, times: np.ndarray) -> Trajectory:
        try:
            tr = self._closed(times)
        except (ValueError, FloatingPointError) as exc:
            self.status, self.message = FAULT, f"closed form failed: {exc}"
            return self._empty()
        stop = tr.info.get("t_stop")
        if "braking" in str(tr.info.get("stop_reason", "")) and stop is not None:
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

    def remaining_braking_time(self) -> float:
        """Time left until |G| reaches zero under braking (seed 004 eq. (11) from the current |G|),
        inf without braking. The averaged theory's G' = -b - lambda G gives it from |G| alone."""
        if self.b <= 0:
            return math.inf
        if self.status == BRAKED:
            return 0.0
        from .closed import braking_time

        G = float(self.last.K[-1]) if len(self.last) else 0.0
        return float(braking_time(G, self.b, self.lam)) if G > 0 else 0.0


__all__ = ["BRAKED", "FAULT", "RUNNING", "LiveRun", "Resolved", "resolve"]


def _require_finite(scenario: Scenario, values: np.ndarray, what: str) -> None:
    """ScenarioError, naming the scenario's most extreme value, when ``values`` are not all finite: a run must
    never start (or go on) from NaN or inf (G0 = 1e200 gave E = inf and theta = NaN that a viewer showed)."""
    if np.all(np.isfinite(values)):
        return
    from .blame import most_extreme

    key, value = most_extreme(scenario)
    raise ScenarioError(key, value, f"makes {what} non-finite (overflow): choose a value nearer 1 in size")
