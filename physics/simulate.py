"""The single entry point: ``simulate(scenario) -> Trajectory`` at any fidelity."""

from __future__ import annotations

import time
import warnings

import numpy as np

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
MAX_STEPS = 200_000_000
CHUNKS = 50  # progress granularity; each chunk restarts the compiled loop with the last step size


def simulate(scenario: Scenario, *, fidelity: str | None = None, method: str | None = None,
             progress=None) -> Trajectory:
    """Run ``scenario`` and return its Trajectory.

    ``fidelity`` and ``method`` override the scenario's [run] values. ``auto`` picks the cheapest
    model whose validity conditions hold (MODELS A.5) and says why in ``trajectory.info``.
    A model asked for outside its conditions runs anyway, with a ValidityWarning naming them.
    Braking (b > 0) ends the run when |G| reaches zero, at the braking time T.
    ``progress(fraction)``, if given, is called as the compiled integrator finishes each of
    CHUNKS pieces of the run.
    """
    if not isinstance(scenario, Scenario):
        raise ScenarioError("scenario", type(scenario).__name__, "must be a physics.Scenario")
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
    start = time.perf_counter()
    if model.solve is not None:
        tr = model.solve(scenario, t)
    else:
        tr = integrate(model, scenario, t, meth, progress)
    if lead:
        tr = tr.slice(1)
    tr.info.update(model=model.name, fidelity=fid, reason=reason, wall_s=time.perf_counter() - start)
    return tr


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
        Y, t_out, info = _scipy(model, p, y0, t, method, rtol, atol, b)
    tr = model.observe(t_out, Y, p, sc)
    tr.info.update(info)
    return tr


def _compiled(model, p, y0, t, rtol, atol, b, lam, progress):
    """The compiled DOP853, in CHUNKS pieces when someone is watching the progress."""
    G0 = float(kernels.braking_norm(model.kernel, y0, p)) if b > 0 else 1.0
    h = 0.0  # the step size carried from chunk to chunk

    def step(y, seg, steps_done):
        nonlocal h
        Y, n, status, t_last, y_last, fe, st, h = dop853.integrate(
            model.kernel, y, p, seg, rtol, atol, b, lam, MAX_STEPS - steps_done, h, G0)
        return Y, n, status, t_last, y_last, fe, st

    Y, t_out, status, t_last, nfev, nsteps = _chunked(step, y0, t, progress)
    _raise_on_fault(status, t_last)
    return Y, t_out, dict(method="DOP853 (compiled)", nfev=int(nfev), steps=int(nsteps),
                          stop_reason=dop853.STATUS_TEXT[status], t_stop=float(t_out[-1]))


def _chunked(step, y0, t, progress):
    """Run ``step(y, times, steps_done) -> (Y, n, status, t_last, y_last, nfev, steps)`` over the
    output times in CHUNKS pieces when someone watches the progress (else in one), joining the
    pieces; an early stop keeps its last accepted state at its own time."""
    edges = np.unique(np.linspace(0, len(t) - 1, CHUNKS + 1 if progress else 2).astype(int))
    Ys, y, nfev, nsteps = [y0[None, :]], y0, 0, 0
    status, t_last = dop853.OK, t[0]
    for i0, i1 in zip(edges[:-1], edges[1:], strict=True):
        seg = np.ascontiguousarray(t[i0:i1 + 1], dtype=float)
        Y, n, status, t_last, y_last, fe, st = step(y, seg, nsteps)
        nfev, nsteps = nfev + fe, nsteps + st
        Ys.append(Y[1:n])
        if status != dop853.OK:
            if t_last > (seg[n - 1] if n else -np.inf):
                Ys.append(y_last[None, :])
            break
        y = Y[n - 1].copy()
        if progress:
            progress((t[i1] - t[0]) / (t[-1] - t[0]))
    Y = np.vstack(Ys)
    t_out = t[: len(Y)].copy()
    if status != dop853.OK:
        t_out[-1] = t_last
    return Y, t_out, status, t_last, nfev, nsteps


def _raise_on_fault(status, t_last):
    if status in (dop853.NONFINITE, dop853.UNDERFLOW, dop853.MAX_STEPS, dop853.MODEL_FAULT):
        raise IntegrationFault(dop853.STATUS_TEXT[status], float(t_last))


def _scipy(model, p, y0, t, method, rtol, atol, b):
    """scipy's solve_ivp on the compiled right-hand side: the baselines of the speed study."""
    from scipy.integrate import solve_ivp  # here: importing scipy.integrate costs the explorer's start 0.4 s

    out = np.empty_like(y0)

    def fun(tt, y):
        kernels.rhs(model.kernel, tt, y, p, out)
        return out.copy()

    events = None
    if b > 0:
        G0 = kernels.braking_norm(model.kernel, y0, p)

        def brake(tt, y):
            return kernels.braking_norm(model.kernel, y, p) - 1e-9 * G0

        brake.terminal = True
        events = brake
    sol = solve_ivp(fun, (t[0], t[-1]), y0, method=method, t_eval=t, rtol=rtol, atol=atol, events=events)
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
    G0 = float(kernels.braking_norm(model.kernel, y0, p)) if b > 0 else 1.0

    def step(y, seg, steps_done):
        if method == "midpoint":
            return midpoint.integrate(np.ascontiguousarray(y), p, seg, float(dt))
        return fixed.run(fixed.TABLEAUS[method], model.kernel, y, p, seg, dt, b, lam, G0)

    Y, t_out, status, t_last, nfev, nsteps = _chunked(step, y0, t, progress)
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
