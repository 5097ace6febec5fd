"""The single entry point: ``simulate(scenario) -> Trajectory`` at any fidelity."""

from __future__ import annotations

import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp

from .compiled import dispatch as kernels
from .compiled import dop853
from .errors import IntegrationFault, ScenarioError, ValidityWarning
from .models.base import Model, get_model
from .scenario import Scenario
from .trajectory import Trajectory
from .validity import averaged_conditions, choose_fidelity, closed_form_available

SYSTEM = "moving_mass"
ATOL_FACTOR = 1e-6  # atol = rtol * ATOL_FACTOR * max|y0|: keeps the small mass displacement resolved
MAX_STEPS = 200_000_000


def simulate(scenario: Scenario, *, fidelity: str | None = None, method: str | None = None) -> Trajectory:
    """Run ``scenario`` and return its Trajectory.

    ``fidelity`` and ``method`` override the scenario's [run] values. ``auto`` picks the cheapest
    model whose validity conditions hold (MODELS A.5) and says why in ``trajectory.info``.
    A model asked for outside its conditions runs anyway, with a ValidityWarning naming them.
    Braking (b > 0) ends the run when |G| reaches zero, at the braking time T.
    """
    if not isinstance(scenario, Scenario):
        raise ScenarioError("scenario", type(scenario).__name__, "must be a physics.Scenario")
    fid = fidelity or scenario.run.fidelity
    meth = method or scenario.run.method
    reason = "requested"
    if fid == "auto":
        fid, reason = choose_fidelity(scenario)
    elif fid in ("averaged", "closed"):
        failed = [str(c) for c in averaged_conditions(scenario) if not c.holds]
        if failed:
            warnings.warn(f"the {fid} model is outside its validity conditions: " + "; ".join(failed),
                          ValidityWarning, stacklevel=2)
        if fid == "closed":
            ok, why = closed_form_available(scenario)
            if not ok:
                raise ScenarioError("run.fidelity", "closed", f"is not available for this scenario: {why}")
    model = get_model(SYSTEM, fid)
    t = scenario.run.times()
    start = time.perf_counter()
    if model.solve is not None:
        tr = model.solve(scenario, t)
    else:
        tr = integrate(model, scenario, t, meth)
    tr.info.update(model=model.name, fidelity=fid, reason=reason, wall_s=time.perf_counter() - start)
    return tr


def integrate(model: Model, sc: Scenario, t: np.ndarray, method: str = "auto"):
    p = model.pack(sc)
    y0 = model.initial_state(sc, p)
    rtol = sc.run.rtol
    atol = rtol * ATOL_FACTOR * max(1.0, float(np.max(np.abs(y0))))
    b = float(sc.control.b) if sc.control else 0.0
    lam = float(sc.medium.lambda_) if sc.medium else 0.0
    if method == "auto":
        Y, n, status, t_last, y_last, nfev, nsteps = dop853.integrate(
            model.kernel, y0, p, np.ascontiguousarray(t, dtype=float), rtol, atol, b, lam, MAX_STEPS)
        t_out, Y = t[:n], Y[:n]
        if status != dop853.OK and t_last > t_out[-1]:
            t_out, Y = np.append(t_out, t_last), np.vstack([Y, y_last])
        info = dict(method="DOP853 (compiled)", nfev=int(nfev), steps=int(nsteps),
                    stop_reason=dop853.STATUS_TEXT[status], t_stop=float(t_out[-1]))
        if status in (dop853.NONFINITE, dop853.UNDERFLOW, dop853.MAX_STEPS):
            raise IntegrationFault(dop853.STATUS_TEXT[status], float(t_last))
    else:
        Y, t_out, info = _scipy(model, p, y0, t, method, rtol, atol, b)
    tr = model.observe(t_out, Y, p, sc)
    tr.info.update(info)
    return tr


def _scipy(model, p, y0, t, method, rtol, atol, b):
    """scipy's solve_ivp on the compiled right-hand side: the baselines of the speed study."""
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

