"""The single entry point: ``simulate(scenario) -> Trajectory`` at any fidelity.

An ODE model is stepped by the stepper LiveRun uses too (physics/stepping/stepper.py, whose docstring is the
stepping contract); this module is its loop over a whole run: the output and step budgets, progress, and calls
short enough for Ctrl-C. Every end of the stepper's but braking is raised here as its IntegrationFault.
"""

from __future__ import annotations

import math
import time

import numpy as np

from physics.compiled import fixed  # noqa: F401 - tests replace fixed.run through this module's name
from physics.core.blame import guarded, outlier
from physics.core.budget import MAX_STEPS
from physics.core.errors import ScenarioError
from physics.core.trajectory import Trajectory
from physics.registry import Model, get_system
from physics.scenario import arguments
from physics.scenario.meta import BASE_PARAMS
from physics.scenario.params import FIDELITIES, FIXED_STEP_METHODS, METHODS
from physics.scenario.scenario import Scenario
from physics.stepping.stepper import ATOL_FACTOR, BRAKED, OK, STATUS_TEXT, STIFF, Piece, Stepper
from physics.stepping.stepper import MAX_STEPS as MAX_STEPS_STATUS
from physics.systems.choice import resolve
from physics.systems.cost import estimated_steps

__all__ = ["ATOL_FACTOR", "MAX_STEPS", "check_output_budget", "integrate", "simulate"]
# Budgets every run gets, so that no input can hold the machine: steps (MAX_STEPS, physics/core/budget.py, which
# auto reads too), steps per compiled call (Ctrl-C and the checks below run between calls: a fraction of a second
# each), outputs per call, the memory of the output, and the right-hand side evaluations of scipy's methods.
STEPS_PER_CALL = 5_000
OUTPUTS_PER_CALL = 20_000
MAX_OUTPUT_BYTES = 256_000_000
MAX_SCIPY_EVALS = 1_000_000
CHUNKS = 50  # with a progress callback, at least this many calls: the bar moves in 2 % steps
# A run whose estimated steps exceed this many times MAX_STEPS is refused before its first step (check_reachable):
# the estimate is the run's steps to within a few times (tests/test_auto_budget.py, STEPS_FACTOR = 4), so a run
# estimated nearer the budget starts and its pace check decides
REFUSE_FACTOR = 4.0


def simulate(scenario: Scenario, *, fidelity: str | None = None, method: str | None = None,
             progress=None) -> Trajectory:
    """Run ``scenario`` and return its Trajectory.

    ``fidelity`` and ``method`` override the scenario's [run] values. ``auto`` picks the cheapest
    model whose error estimate meets ``run.accuracy`` and says why in ``trajectory.info`` (with
    ``error_bound``, the estimate the run states, and ``error_bound_method``).
    A model asked for outside its conditions runs anyway, with a ValidityWarning naming them.
    Braking (b > 0) ends the run when |G| reaches zero, at the braking time T.
    ``progress(fraction)``, if given, is called as the compiled integrator finishes each of its
    calls (STEPS_PER_CALL steps at most). Every run has budgets (MAX_STEPS, MAX_OUTPUT_BYTES,
    MAX_SCIPY_EVALS): a run that would exceed one is refused (ScenarioError naming the key) or stopped
    (IntegrationFault), and a problem too stiff for DOP853 stops with a fault as LiveRun's does.
    Arithmetic and linear-algebra failures come out as NumericalFault naming the most extreme value.
    """
    arguments.scenario(scenario)
    if fidelity is not None:  # a system may register fidelities of its own: resolve names what this one has
        arguments.choice(fidelity, "fidelity", (*FIDELITIES, *get_system(scenario.system).fidelities))
    if method is not None:  # refused as input here, not left to fail inside the stepper as a numerical fault
        arguments.choice(method, "method", METHODS)
    arguments.callback(progress, "progress")
    with guarded(scenario, "the run", spans(scenario)):
        return _simulate(scenario, fidelity, method, progress)


def spans(sc: Scenario) -> dict[str, tuple[float, float]]:
    """The span each key usually takes (its slider's range), by which a fault's blame judges what is extreme."""
    return {p.key: (p.lo, p.hi) for p in (*BASE_PARAMS, *get_system(sc.system).params)}


def _simulate(scenario: Scenario, fidelity, method, progress) -> Trajectory:
    meth = method or scenario.run.method
    res = resolve(scenario, fidelity, warn=True)
    model, fid, reason = _fields(res)
    t = scenario.run.times()
    lead = t[0] > 0  # output starts later than the initial state: integrate from 0, drop that row
    if lead:
        t = np.concatenate([[0.0], t])
    check_output_budget(model, len(t), "run.t_eval" if scenario.run.t_eval is not None else "run.samples",
                        _state_size(model, scenario))
    check_run = get_system(scenario.system).check_run  # what only a run needs (a carrier left with A > 0)
    if check_run is not None:
        check_run(scenario)
    if model.solve is None and meth == "auto":
        check_reachable(scenario, fid, res.steps)
    start = time.perf_counter()
    if model.solve is not None:
        tr = model.solve(scenario, t)
    else:
        tr = integrate(model, scenario, t, meth, progress)
    if lead:
        tr = tr.slice(1)
    tr.info.update(model=model.name, fidelity=fid, reason=reason, wall_s=time.perf_counter() - start)
    tr.info.update(stated_error(scenario, fid))
    if res.steps is not None:  # auto weighed the models' costs: the picked one's and, over budget, the full model's
        tr.info.update(estimated_steps=res.steps[fid], full_estimated_steps=res.steps.get("full"))
    return tr


def check_reachable(sc: Scenario, fid: str, steps: dict | None = None) -> None:
    """Refuse, before a step, a run whose estimated steps (physics/systems/cost.py, a probe of milliseconds;
    ``steps``: auto's, when it weighed them) exceed REFUSE_FACTOR x MAX_STEPS: it could not reach run.t_end,
    and the pace check would say so only after integrating for seconds. Within that factor the estimate may be
    high (it is the run's steps to within a few times), so the run starts and its pace check decides."""
    est = steps[fid] if steps and fid in steps else estimated_steps(sc, fid)
    if est is not None and est > REFUSE_FACTOR * MAX_STEPS:
        t_end = float(sc.run.t_end)
        odd = outlier(sc, spans(sc))
        cause = f" (the most extreme value is {odd[0]} = {odd[1]!r})" if odd and odd[0] != "run.t_end" else ""
        raise ScenarioError("run.t_end", t_end, f"the {fid} model would need about {est:.3g} steps (estimated "
                            f"before the run), more than the budget of {MAX_STEPS} steps per run{cause}: t_end at "
                            f"most about {t_end * MAX_STEPS / est:.3g} s")


def stated_error(sc: Scenario, fid: str) -> dict:
    """``error_bound``: the max |theta - theta_full| (rad) the system states for this fidelity over the run (0 for
    the full model, the reference; inf where the cheaper model makes no claim), and how it was obtained."""
    system = get_system(sc.system)
    bound = 0.0 if fid == "full" else system.error_bounds(sc, fid)
    return dict(error_bound=math.inf if bound is None else float(bound),
                error_bound_method=system.error_method or "none stated")


def _fields(res):
    return res.model, res.fidelity, res.reason


def _state_size(model: Model, sc: Scenario) -> int | None:
    """The length of the model's state for ``sc`` (None for a closed form)."""
    if model.pack is None or model.initial_state is None:
        return None
    if model.layout is None and model.state:  # a fixed layout: its length, without making the state twice
        return len(model.state)
    return len(model.initial_state(sc, model.pack(sc)))


def check_output_budget(model: Model, rows: int, key: str, n_state: int | None = None) -> None:
    """Refuse output that would need more than MAX_OUTPUT_BYTES: rows x (state + trajectory columns) in
    float64, twice (the states and the Trajectory made from them). ``n_state``: the state's length when it
    depends on the scenario (its internal coordinates are trajectory columns too)."""
    names = model.state_names(n_state)
    internal = len(names) - len(model.state)  # coordinates beyond the fixed layout (N plane pendulums' a_i)
    per_row = 2 * 8 * (len(names) + 11 + len(model.columns) + internal)
    if rows * per_row > MAX_OUTPUT_BYTES:
        raise ScenarioError(key, rows if key == "run.samples" else f"({rows} times)",
                            f"needs about {rows * per_row / 1e6:.3g} MB of output for {model.name}; at most "
                            f"{MAX_OUTPUT_BYTES // per_row} samples ({MAX_OUTPUT_BYTES / 1e6:.0f} MB) per run")


def integrate(model: Model, sc: Scenario, t: np.ndarray, method: str = "auto", progress=None):
    """Step ``model`` over the output times ``t`` with the shared stepper (physics/stepping/stepper.py): the
    whole run, in calls short enough that Ctrl-C, progress and the run's budgets are checked between them."""
    p = model.pack(sc)
    y0 = np.asarray(model.initial_state(sc, p), dtype=float)
    stepper = Stepper(model, sc, y0, method=method, p=p)
    if method == "auto" or method in FIXED_STEP_METHODS:
        Y, t_out, info = _stepped(stepper, y0, t, progress)
    else:
        Y, t_out, info = stepper.solve_ivp(y0, t, method, MAX_SCIPY_EVALS, progress)
    tr = model.observe(t_out, Y, stepper.p, sc)
    tr.info.update(info)
    return tr


def _stepped(stepper: Stepper, y0: np.ndarray, t: np.ndarray, progress):
    """The run's loop over ``stepper.step``: an adaptive call takes at most STEPS_PER_CALL steps and the run's
    pace is checked against MAX_STEPS at each stiffness check; a fixed step's total is known, so a run that
    would exceed MAX_STEPS is refused before a single step. Every end but braking raises its IntegrationFault."""
    fixed_step = stepper.method in FIXED_STEP_METHODS
    if fixed_step:
        dt = stepper.dt
        steps = float(np.sum(np.ceil(np.diff(t) / dt)))
        if steps > MAX_STEPS:  # refused before a single step: t_end/dt is known
            raise ScenarioError("run.dt", dt, f"needs {steps:.3g} steps of {stepper.method} over [0, {t[-1]:g}] s, "
                                f"more than the budget of {MAX_STEPS} steps per run: use dt >= "
                                f"{(t[-1] - t[0]) / MAX_STEPS:.3g} s, a shorter t_end or an adaptive method")

    def step(y, seg, steps_done):
        piece = stepper.step(y, seg, min(STEPS_PER_CALL, MAX_STEPS - steps_done))
        if piece.status == STIFF:
            raise piece.fault()
        if piece.checked:
            _check_pace(steps_done + piece.nsteps, piece.t_last, t,
                        f"at the step size this problem takes ({stepper.h:.3g} s)")
        return piece

    reach = stepper.reach(STEPS_PER_CALL) if fixed_step else None
    Y, t_out, last, nfev, nsteps = _sliced(step, y0, t, progress, reach)
    if last.status not in (OK, BRAKED):
        raise last.fault()
    info = dict(method=stepper.label, nfev=int(nfev), steps=int(nsteps))
    if fixed_step:
        info["dt"] = float(stepper.dt)
    info.update(stop_reason=STATUS_TEXT[last.status], t_stop=float(t_out[-1]))
    return Y, t_out, info


def _check_pace(steps: int, t_now: float, t: np.ndarray, how: str) -> None:
    """Refuse a run whose pace so far would need more than MAX_STEPS steps to reach the end."""
    done = (t_now - t[0]) / (t[-1] - t[0])
    if done > 0 and steps / done > MAX_STEPS:
        raise ScenarioError("run.t_end", float(t[-1]), f"would need about {steps / done:.3g} steps {how}, more than "
                            f"the budget of {MAX_STEPS} steps per run: shorten t_end (this pace reaches about "
                            f"{t[0] + (t[-1] - t[0]) * MAX_STEPS * done / steps:.3g} s)")


def _sliced(step, y0, t, progress, reach=None):
    """Run ``step(y, times, steps_done) -> Piece`` from t[0] over the output times in calls short enough that
    Ctrl-C and the budgets are checked within a fraction of a second: at most OUTPUTS_PER_CALL outputs a call,
    and, for a fixed step, at most ``reach`` seconds (a longer gap between outputs gets a checkpoint that is not
    output). A call that runs out of its step budget (status MAX_STEPS) is continued from its last accepted
    state. An early stop keeps its last accepted state at its own time. Returns (Y, t_out, last piece, nfev,
    steps)."""
    Ys, y, tc, i = [y0[None, :]], y0, float(t[0]), 0  # t[i]: the last output reached
    nfev, nsteps = 0, 0
    piece = None
    last = len(t) - 1
    per_call = min(OUTPUTS_PER_CALL, -(-last // CHUNKS)) if progress else OUTPUTS_PER_CALL
    while i < last:
        j = min(last, i + per_call)
        if reach is not None:
            j = min(j, int(np.searchsorted(t, tc + reach, side="right")) - 1)
        checkpoint = j <= i
        seg = np.array([tc, tc + reach]) if checkpoint else np.concatenate([[tc], t[i + 1:j + 1]])
        piece = step(y, np.ascontiguousarray(seg, dtype=float), nsteps)
        Y, n = piece.Y, piece.n
        nfev, nsteps = nfev + piece.nfev, nsteps + piece.nsteps
        if not checkpoint:
            Ys.append(Y[1:n])
            i += n - 1
        if piece.status == MAX_STEPS_STATUS and nsteps < MAX_STEPS:
            y, tc = piece.y_last.copy(), piece.t_last  # out of this call's steps, not of the run's: go on
        elif piece.status != OK:
            if piece.t_last > t[i]:  # the last accepted state, at its own time
                Ys.append(piece.y_last[None, :])
            Y = np.vstack(Ys)
            t_out = t[: len(Y)].copy()
            t_out[-1] = piece.t_last
            return Y, t_out, piece, nfev, nsteps
        else:
            y, tc = Y[n - 1].copy(), float(seg[n - 1])
        if progress:
            progress((tc - t[0]) / (t[-1] - t[0]))
    Y = np.vstack(Ys)
    if piece is None:  # one output time: nothing to step
        piece = _reached(y0, t[-1])
    return Y, t[: len(Y)].copy(), piece, nfev, nsteps


def _reached(y, t_end) -> Piece:
    empty = np.empty((0, y.size))
    return Piece(empty, 0, OK, float(t_end), y, 0, 0, np.empty(0), empty)
