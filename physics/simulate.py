"""The single entry point: ``simulate(scenario) -> Trajectory`` at any fidelity."""

from __future__ import annotations

import time
import warnings

import numpy as np

from .blame import guarded
from .compiled import dispatch as kernels
from .compiled import dop853, fixed, midpoint
from .errors import IntegrationFault, ScenarioError, ValidityWarning
from .models.base import REGISTRY, Model, get_model
from .params import FIXED_STEP_METHODS
from .scenario import Scenario
from .trajectory import Trajectory
from .validity import choose_fidelity, closed_form_available, conditions

SYSTEM = "moving_mass"  # the closed forms' availability check is this system's
ATOL_FACTOR = 1e-6  # atol = rtol * ATOL_FACTOR * max|y0|: keeps the small mass displacement resolved
# Budgets every run gets, so that no input can hold the machine: steps (a few minutes of the slowest model),
# steps per compiled call (Ctrl-C and the checks below run between calls: a fraction of a second each),
# outputs per call, the memory of the output, and the right-hand side evaluations of scipy's methods.
MAX_STEPS = 20_000_000
STEPS_PER_CALL = 5_000
OUTPUTS_PER_CALL = 20_000
MAX_OUTPUT_BYTES = 256_000_000
MAX_SCIPY_EVALS = 1_000_000
CHUNKS = 50  # with a progress callback, at least this many calls: the bar moves in 2 % steps


def simulate(scenario: Scenario, *, fidelity: str | None = None, method: str | None = None,
             progress=None) -> Trajectory:
    """Run ``scenario`` and return its Trajectory.

    ``fidelity`` and ``method`` override the scenario's [run] values. ``auto`` picks the cheapest
    model whose validity conditions hold (MODELS A.5) and says why in ``trajectory.info``.
    A model asked for outside its conditions runs anyway, with a ValidityWarning naming them.
    Braking (b > 0) ends the run when |G| reaches zero, at the braking time T.
    ``progress(fraction)``, if given, is called as the compiled integrator finishes each of its
    calls (STEPS_PER_CALL steps at most). Every run has budgets (MAX_STEPS, MAX_OUTPUT_BYTES,
    MAX_SCIPY_EVALS): a run that would exceed one is refused (ScenarioError naming the key) or stopped
    (IntegrationFault), and a problem too stiff for DOP853 stops with a fault as LiveRun's does.
    Arithmetic and linear-algebra failures come out as NumericalFault naming the most extreme value.
    """
    if not isinstance(scenario, Scenario):
        raise ScenarioError("scenario", type(scenario).__name__, "must be a physics.Scenario")
    with guarded(scenario, "the run"):
        return _simulate(scenario, fidelity, method, progress)


def _simulate(scenario: Scenario, fidelity, method, progress) -> Trajectory:
    fid = fidelity or scenario.run.fidelity
    meth = method or scenario.run.method
    reason = "requested"
    if fid == "auto":
        fid, reason = choose_fidelity(scenario)
    elif fid in ("averaged", "closed"):
        failed = [str(c) for c in conditions(scenario) if not c.holds]
        if failed:
            warnings.warn(f"the {fid} model is outside its validity conditions: " + "; ".join(failed),
                          ValidityWarning, stacklevel=2)
        if fid == "closed" and scenario.system == SYSTEM:
            ok, why = closed_form_available(scenario)
            if not ok:
                raise ScenarioError("run.fidelity", "closed", f"is not available for this scenario: {why}")
    try:
        model = get_model(scenario.system, fid)
    except KeyError:
        have = sorted(m.fidelity for m in REGISTRY.values() if m.system == scenario.system)
        raise ScenarioError("run.fidelity", fid, f"is not available for {scenario.system}; it has: "
                            + ", ".join(have)) from None
    t = scenario.run.times()
    lead = t[0] > 0  # output starts later than the initial state: integrate from 0, drop that row
    if lead:
        t = np.concatenate([[0.0], t])
    check_output_budget(model, len(t), "run.t_eval" if scenario.run.t_eval is not None else "run.samples")
    check_carrier(scenario)
    start = time.perf_counter()
    if model.solve is not None:
        tr = model.solve(scenario, t)
    else:
        tr = integrate(model, scenario, t, meth, progress)
    if lead:
        tr = tr.slice(1)
    tr.info.update(model=model.name, fidelity=fid, reason=reason, wall_s=time.perf_counter() - start)
    return tr


def check_carrier(sc: Scenario) -> None:
    """The carrier's equatorial moments A - m rho^2/(1 - m/M) must stay positive at every fidelity (the full
    model's pack checks it too; the closed and averaged forms failed deep inside, e.g. rho = 1e100)."""
    if sc.mass is not None:
        ms = sc.mass
        share = ms.m * ms.rho * ms.rho / (1.0 - ms.m / sc.body.M)  # a product: inf, not OverflowError
        if not share < min(sc.body.A, sc.body.B):
            raise ScenarioError("mass.rho", ms.rho, "is too large: m rho^2/(1 - m/M) must be less than A and B")


def check_output_budget(model: Model, rows: int, key: str) -> None:
    """Refuse output that would need more than MAX_OUTPUT_BYTES: rows x (state + trajectory columns) in
    float64, twice (the states and the Trajectory made from them)."""
    per_row = 2 * 8 * (len(model.state) + 11 + len(model.columns))
    if rows * per_row > MAX_OUTPUT_BYTES:
        raise ScenarioError(key, rows if key == "run.samples" else f"({rows} times)",
                            f"needs about {rows * per_row / 1e6:.3g} MB of output for {model.name}; at most "
                            f"{MAX_OUTPUT_BYTES // per_row} samples ({MAX_OUTPUT_BYTES / 1e6:.0f} MB) per run")


def integrate(model: Model, sc: Scenario, t: np.ndarray, method: str = "auto", progress=None):
    p = model.pack(sc)
    y0 = model.initial_state(sc, p)
    rtol = sc.run.rtol
    atol = rtol * ATOL_FACTOR * max(1.0, float(np.max(np.abs(y0))))
    b = float(sc.control.b) if sc.control else 0.0
    lam = float(sc.medium.lambda_) if sc.medium else 0.0
    if method == "auto":
        Y, t_out, info = _compiled(model, p, y0, t, rtol, atol, b, lam, progress)
    elif method in FIXED_STEP_METHODS:
        Y, t_out, info = _fixed(model, sc, p, y0, t, method, b, lam, progress)
    else:
        Y, t_out, info = _scipy(model, p, y0, t, method, rtol, atol, b, progress)
    tr = model.observe(t_out, Y, p, sc)
    tr.info.update(info)
    return tr


def _compiled(model, p, y0, t, rtol, atol, b, lam, progress):
    """The compiled DOP853 in calls of at most STEPS_PER_CALL steps, checked for stiffness and for the
    run's step budget as it goes (as LiveRun is)."""
    from .live import MAX_STEPS_PER_CALL, STIFF_H_LAMBDA, spectral_radius  # here: live imports this module

    G0 = float(kernels.braking_norm(model.kernel, y0, p)) if b > 0 else 1.0
    h = 0.0  # the step size carried from call to call
    unchecked = 0

    def step(y, seg, steps_done):
        nonlocal h, unchecked
        Y, n, status, t_last, y_last, fe, st, h = dop853.integrate(
            model.kernel, y, p, seg, rtol, atol, b, lam, min(STEPS_PER_CALL, MAX_STEPS - steps_done), h, G0)
        unchecked += st
        if status in (dop853.OK, dop853.MAX_STEPS) and unchecked >= MAX_STEPS_PER_CALL:
            unchecked = 0
            h_lambda = h * spectral_radius(model.kernel, float(t_last), y_last, p)
            if h_lambda > STIFF_H_LAMBDA:
                raise IntegrationFault(
                    f"too stiff for the explicit integrator (DOP853): {steps_done + st} steps covered "
                    f"{float(t_last) - t[0]:.3g} s, each held at the stability limit (h |lambda| = {h_lambda:.2g}, "
                    "fastest mode faster than the motion); lower Omega or chi, or use the averaged fidelity",
                    float(t_last))
            _check_pace(steps_done + st, float(t_last), t, f"at the step size this problem takes ({h:.3g} s)")
        return Y, n, status, t_last, y_last, fe, st

    Y, t_out, status, t_last, nfev, nsteps = _sliced(step, y0, t, progress)
    _raise_on_fault(status, t_last)
    return Y, t_out, dict(method="DOP853 (compiled)", nfev=int(nfev), steps=int(nsteps),
                          stop_reason=dop853.STATUS_TEXT[status], t_stop=float(t_out[-1]))


def _check_pace(steps: int, t_now: float, t: np.ndarray, how: str) -> None:
    """Refuse a run whose pace so far would need more than MAX_STEPS steps to reach the end."""
    done = (t_now - t[0]) / (t[-1] - t[0])
    if done > 0 and steps / done > MAX_STEPS:
        raise ScenarioError("run.t_end", float(t[-1]), f"would need about {steps / done:.3g} steps {how}, more than "
                            f"the budget of {MAX_STEPS} steps per run: shorten t_end (this pace reaches about "
                            f"{t[0] + (t[-1] - t[0]) * MAX_STEPS * done / steps:.3g} s)")


def _sliced(step, y0, t, progress, reach=None):
    """Run ``step(y, times, steps_done) -> (Y, n, status, t_last, y_last, nfev, steps)`` from t[0] over the
    output times in calls short enough that Ctrl-C and the budgets are checked within a fraction of a
    second: at most OUTPUTS_PER_CALL outputs a call, and, for a fixed step, at most ``reach`` seconds (a
    longer gap between outputs gets a checkpoint that is not output). A call that runs out of its step
    budget (status MAX_STEPS) is continued from its last accepted state. An early stop keeps its last
    accepted state at its own time. Returns (Y, t_out, status, t_last, nfev, steps)."""
    Ys, y, tc, i = [y0[None, :]], y0, float(t[0]), 0  # t[i]: the last output reached
    nfev, nsteps = 0, 0
    status, t_last = dop853.OK, t[0]
    last = len(t) - 1
    per_call = min(OUTPUTS_PER_CALL, -(-last // CHUNKS)) if progress else OUTPUTS_PER_CALL
    while i < last:
        j = min(last, i + per_call)
        if reach is not None:
            j = min(j, int(np.searchsorted(t, tc + reach, side="right")) - 1)
        checkpoint = j <= i
        seg = np.array([tc, tc + reach]) if checkpoint else np.concatenate([[tc], t[i + 1:j + 1]])
        Y, n, status, t_last, y_last, fe, st = step(y, np.ascontiguousarray(seg, dtype=float), nsteps)
        nfev, nsteps = nfev + fe, nsteps + st
        if not checkpoint:
            Ys.append(Y[1:n])
            i += n - 1
        if status == dop853.MAX_STEPS and nsteps < MAX_STEPS:
            y, tc = y_last.copy(), float(t_last)  # out of this call's steps, not of the run's: go on
        elif status != dop853.OK:
            if t_last > t[i]:  # the last accepted state, at its own time
                Ys.append(y_last[None, :])
            Y = np.vstack(Ys)
            t_out = t[: len(Y)].copy()
            t_out[-1] = t_last
            return Y, t_out, status, t_last, nfev, nsteps
        else:
            y, tc = Y[n - 1].copy(), float(seg[n - 1])
        if progress:
            progress((tc - t[0]) / (t[-1] - t[0]))
    Y = np.vstack(Ys)
    return Y, t[: len(Y)].copy(), dop853.OK, t[-1], nfev, nsteps


class _OutOfBudget(Exception):
    def __init__(self, t: float):
        self.t = float(t)


def _raise_on_fault(status, t_last):
    if status in (dop853.NONFINITE, dop853.UNDERFLOW, dop853.MAX_STEPS, dop853.MODEL_FAULT):
        raise IntegrationFault(dop853.STATUS_TEXT[status], float(t_last))


def _scipy(model, p, y0, t, method, rtol, atol, b, progress=None):
    """scipy's solve_ivp on the compiled right-hand side: the baselines of the speed study."""
    from scipy.integrate import solve_ivp  # here: importing scipy.integrate costs the explorer's start 0.4 s

    out = np.empty_like(y0)
    evaluations = 0

    def fun(tt, y):
        nonlocal evaluations
        evaluations += 1
        if evaluations > MAX_SCIPY_EVALS:  # scipy has no step budget of its own
            raise _OutOfBudget(tt)
        if progress and evaluations % 1000 == 0:
            progress(min(1.0, (tt - t[0]) / (t[-1] - t[0])))
        kernels.rhs(model.kernel, tt, y, p, out)
        return out.copy()

    events = None
    if b > 0:
        G0 = kernels.braking_norm(model.kernel, y0, p)

        def brake(tt, y):
            return kernels.braking_norm(model.kernel, y, p) - 1e-9 * G0

        brake.terminal = True
        events = brake
    try:
        sol = solve_ivp(fun, (t[0], t[-1]), y0, method=method, t_eval=t, rtol=rtol, atol=atol, events=events)
    except _OutOfBudget as stop:
        raise IntegrationFault(f"scipy {method}: more than {MAX_SCIPY_EVALS} evaluations of the right-hand side "
                               '(the budget of a run); use method "auto"', stop.t) from None
    if sol.status == -1:
        raise IntegrationFault(f"{method}: {sol.message}", float(sol.t[-1]) if sol.t.size else float(t[0]))
    Y, t_out = sol.y.T, sol.t
    reason = dop853.STATUS_TEXT[dop853.OK]
    if sol.status == 1:
        t_out, Y = np.append(t_out, sol.t_events[0][0]), np.vstack([Y, sol.y_events[0][0]])
        reason = dop853.STATUS_TEXT[dop853.BRAKED]
    steps = getattr(sol, "nsteps", None)
    return Y, t_out, dict(method=f"scipy {method}", nfev=int(sol.nfev), steps=steps, stop_reason=reason,
                          t_stop=float(t_out[-1]))


def check_fixed_method(model, sc, method: str, b: float, lam: float) -> None:
    """Raise ScenarioError when the fixed-step ``method`` cannot run ``model`` on ``sc``: the implicit
    midpoint covers only the full moving-mass model without cavity, medium or control."""
    if method != "midpoint":
        return
    unsupported = [name for name, present in (("a cavity", sc.cavity is not None), ("a medium", lam > 0),
                                              ("a control", b > 0)) if present]
    if model.kernel != kernels.MASS_FULL or unsupported:
        why = "the full moving-mass model" + (" without " + ", ".join(unsupported) if unsupported else "")
        raise ScenarioError("run.method", "midpoint", f"covers only the full moving-mass model with no cavity, "
                            f"medium or control (this run has {why if unsupported else model.name}); "
                            'use "auto" or "RK8"')


def _fixed(model, sc, p, y0, t, method, b, lam, progress):
    """The compiled fixed-step methods: RK4 and RK8 (physics/compiled/fixed.py) on any compiled
    model, and the structure-preserving implicit midpoint (physics/compiled/midpoint.py) on the full
    moving-mass model without external torques or cavity."""
    dt = sc.run.dt
    if dt is None:
        raise ScenarioError("run.dt", None, f'is required by the fixed-step method "{method}" (the largest step, s)')
    check_fixed_method(model, sc, method, b, lam)
    steps = float(np.sum(np.ceil(np.diff(t) / dt)))
    if steps > MAX_STEPS:  # refused before a single step: t_end/dt is known
        raise ScenarioError("run.dt", dt, f"needs {steps:.3g} steps of {method} over [0, {t[-1]:g}] s, more than the "
                            f"budget of {MAX_STEPS} steps per run: use dt >= {(t[-1] - t[0]) / MAX_STEPS:.3g} s, "
                            "a shorter t_end or an adaptive method")
    G0 = float(kernels.braking_norm(model.kernel, y0, p)) if b > 0 else 1.0

    def step(y, seg, steps_done):
        if method == "midpoint":
            return midpoint.integrate(np.ascontiguousarray(y), p, seg, float(dt))
        return fixed.run(fixed.TABLEAUS[method], model.kernel, y, p, seg, dt, b, lam, G0)

    Y, t_out, status, t_last, nfev, nsteps = _sliced(step, y0, t, progress, reach=STEPS_PER_CALL * dt)
    if status == midpoint.NO_CONVERGENCE:
        raise IntegrationFault(midpoint.STATUS_TEXT, float(t_last))
    if status == dop853.NONFINITE:  # a fixed step beyond the method's stability limit, most likely
        raise IntegrationFault(f"{method} with dt = {dt:g} s: state became non-finite (NaN or infinity); the step is "
                               "beyond the method's stability limit for this problem (stiff): use a smaller run.dt "
                               "or an adaptive method", float(t_last))
    _raise_on_fault(status, t_last)
    name = "implicit midpoint (compiled, structure-preserving)" if method == "midpoint" else f"{method} (compiled)"
    return Y, t_out, dict(method=name, nfev=int(nfev), steps=int(nsteps), dt=float(dt),
                          stop_reason=dop853.STATUS_TEXT[status], t_stop=float(t_out[-1]))
