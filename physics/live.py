"""Stepping a scenario piece by piece, for an interactive viewer.

``LiveRun(scenario)`` holds the model, its parameter vector, the state y, the time t and the
compiled DOP853's step size. ``advance(dt)`` integrates [t, t + dt] and returns the rows reached as a
Trajectory; the step size carries over, so pieces cost what one long run costs and agree with
``simulate`` to the integrator's tolerance. ``retune(scenario)`` swaps the parameters and keeps the
state when the state layout allows it. The end of braking and integration faults (a non-finite state,
step-size underflow, the gimbal singularity, and a problem too stiff for the explicit integrator: a call
that runs out of steps while they are held at the stability limit) are recorded in ``status`` and
``message``, never raised: a viewer shows them and keeps the last good state.

The closed fidelity has no state to step: its rows are evaluated from t = 0 at the times asked for.
A scenario's ``run.method`` RK4, RK8 or midpoint (with ``run.dt``) steps with that compiled fixed-step
method instead of DOP853, as ``simulate`` does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .compiled import dispatch as kernels
from .compiled import dop853, fixed, midpoint
from .errors import IntegrationFault, ScenarioError
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
    kernels.rhs(kernel, t, y, p, f0)
    v = np.random.default_rng(0).standard_normal(y.size)
    v /= np.linalg.norm(v)
    eps = 1e-7 * max(1.0, float(np.linalg.norm(y)))
    radius, previous = 0.0, None
    for _ in range(POWER_ITERATIONS):
        kernels.rhs(kernel, t, y + eps * v, p, f1)
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
        self.atol = self.rtol * ATOL_FACTOR * max(1.0, float(np.max(np.abs(self.y))))
        self._G0_known = self.b > 0
        self.G0 = float(kernels.braking_norm(self.model.kernel, self.y, self.p)) if self.b > 0 else 1.0
        self.last = self._observe(np.array([0.0]), self.y[None, :])

    def _set_params(self, scenario: Scenario) -> None:
        self.p = np.asarray(self.model.pack(scenario), dtype=float)
        self.rtol = scenario.run.rtol
        self.b = float(scenario.control.b) if scenario.control else 0.0
        self.lam = float(scenario.medium.lambda_) if scenario.medium else 0.0

    def reset(self) -> None:
        """Back to t = 0 with the current scenario."""
        self._start(self.scenario, self.requested)

    def retune(self, scenario: Scenario, fidelity: str | None = None, *, keep_state: bool = True) -> bool:
        """Run ``scenario`` from now on. Returns True when the current state was kept (same model,
        same state layout, ``keep_state``), False when it restarted from t = 0. Raises
        ScenarioError (before changing anything) when the scenario cannot run."""
        res = resolve(scenario, fidelity)
        if scenario.run.method in FIXED_STEP_METHODS and res.model.solve is None:
            check_fixed_method(res.model, scenario, scenario.run.method,
                               float(scenario.control.b) if scenario.control else 0.0,
                               float(scenario.medium.lambda_) if scenario.medium else 0.0)
        same = (keep_state and res.model is self.model and self.model.solve is None
                and self.status != FAULT)
        if same:
            p = np.asarray(self.model.pack(scenario), dtype=float)
            y0 = self.model.initial_state(scenario, p)
            same = p.shape == self.p.shape and np.shape(y0) == self.y.shape
        if not same:
            self._start(scenario, fidelity)
            return False
        self.scenario = scenario
        self.requested = fidelity or scenario.run.fidelity
        self.reason = res.reason
        self._set_params(scenario)
        if self.b > 0 and not self._G0_known:  # braking switched on now: measure its end from here
            self._G0_known = True
            self.G0 = float(kernels.braking_norm(self.model.kernel, self.y, self.p))
        if self.status == BRAKED and self.b == 0.0:
            self.status, self.message = RUNNING, ""
        self.h = 0.0  # the old step size may not suit the new parameters; let the integrator guess
        self.last = self._observe(np.array([self.t]), self.y[None, :])
        return True

    # ---- stepping -----------------------------------------------------------------------
    def advance(self, dt: float, samples: int = 1) -> Trajectory:
        """Integrate over [t, t + dt] and return the rows reached at ``samples`` evenly spaced times
        in (t, t + dt] (fewer if the run stops or the per-call step budget runs out first).
        Returns an empty Trajectory once the run has ended."""
        if self.status != RUNNING or not dt > 0:
            return self._empty()
        samples = max(1, int(samples))
        times = self.t + dt * np.arange(1, samples + 1) / samples
        if self.model.solve is not None:
            return self._advance_closed(times)
        t_out = np.concatenate([[self.t], times])
        method = self.scenario.run.method
        if method in FIXED_STEP_METHODS:
            dt_step = float(self.scenario.run.dt)
            if method == "midpoint":
                out = midpoint.integrate(np.ascontiguousarray(self.y), self.p, t_out, dt_step)
            else:
                out = fixed.run(fixed.TABLEAUS[method], self.model.kernel, self.y, self.p, t_out, dt_step, self.b,
                                self.lam, self.G0)
            Y, n, status, t_last, y_last, nfev, nsteps = out
            h = dt_step
            if status == midpoint.NO_CONVERGENCE and method == "midpoint":
                status = dop853.MODEL_FAULT  # reported as a fault below, with the midpoint's own words
                self.message = str(IntegrationFault(midpoint.STATUS_TEXT, float(t_last)))
        else:
            Y, n, status, t_last, y_last, nfev, nsteps, h = dop853.integrate(
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
        t_all = np.concatenate([[0.0], times]) if times[0] > 0 else times
        tr = self.model.solve(self.scenario, t_all)
        if times[0] > 0:
            tr = tr.slice(1)
        return tr

    def _observe(self, t: np.ndarray, Y: np.ndarray) -> Trajectory:
        return self.model.observe(np.asarray(t, dtype=float), np.ascontiguousarray(Y), self.p, self.scenario)

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
