"""A work-precision sweep of one scenario: error against cost for each compiled method, and the
cheapest setting that meets the scenario's requested accuracy (the app's "speed vs accuracy" panel).

``work_precision(scenario)`` runs the scenario's model (at its fidelity; ``auto`` resolved as
``simulate`` resolves it; a closed form has no integrator, so the ODE it solves is swept) over
a short horizon sized so the whole sweep takes seconds, against a reference by the compiled DOP853
at REFERENCE_RTOL on the same samples. Errors are max |theta - theta_ref| (rad), the quantity that
``run.accuracy`` requests.
"""

from __future__ import annotations

import dataclasses
import math
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from physics.core.errors import IntegrationFault, ScenarioError, ValidityWarning
from physics.scenario.scenario import Scenario
from physics.stepping.simulate import simulate
from physics.systems.choice import choose_fidelity

REFERENCE_RTOL = 1e-13  # the reference's rtol: ~1e3 below the tightest swept setting
SAMPLES = 201  # output samples of every run of the sweep (theta is compared at these)
REFERENCE_BUDGET_S = 0.6  # wall time the reference may take; sets the horizon
RUN_BUDGET_S = 1.5  # a fixed-step run predicted to take longer than this is skipped
PROBE_T = 1.0  # s: the first horizon tried (or t_end if shorter)
GROWTH = 10.0  # the horizon grows at most this much per try
DOP853_RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)
RK4_STEPS = (2.0, 1.0, 0.5, 0.25, 0.125, 0.0625)  # dt / mean DOP853 step at rtol 1e-8
RK8_STEPS = (8.0, 5.0, 3.0, 2.0, 1.4, 1.0)
MIDPOINT_STEPS = (1.0, 0.5, 0.25, 0.125)
REPEATS = 3  # at most, for runs shorter than REPEAT_UNDER_S
REPEAT_UNDER_S = 0.05
ACCURACY_FLOOR = 1e-11  # rad: a current setting finer than this is held to this (the reference's limit)


@dataclass(frozen=True)
class Row:
    """One run: ``method`` (a run.method value), its ``setting`` (rtol for adaptive, dt (s) for fixed
    step), theta error (rad), wall time (s), right-hand side evaluations and steps."""

    method: str
    setting: float
    error: float
    wall_s: float
    nfev: int
    steps: int

    @property
    def label(self) -> str:
        name = "DOP853 (compiled)" if self.method == "auto" else f"{self.method} (compiled)"
        key = "rtol" if self.method == "auto" else "dt"
        return f"{name} {key}={self.setting:.3g}"


@dataclass
class WorkPrecision:
    """The sweep's result. ``rows`` from all runs that finished; ``tolerance`` (rad) is what the
    recommendation must meet and ``tolerance_source`` says where it came from; ``recommended`` is the
    fastest row with error <= tolerance (None if none does); ``cancelled`` if stopped early."""

    fidelity: str
    model: str
    horizon: float
    tolerance: float
    tolerance_source: str
    rows: list[Row] = field(default_factory=list)
    recommended: Row | None = None
    reference_wall_s: float = 0.0
    cancelled: bool = False

    def methods(self) -> list[str]:
        return sorted({r.method for r in self.rows})

    def apply(self, sc: Scenario, row: Row | None = None) -> Scenario:
        """``sc`` with run.method and run.rtol or run.dt set to ``row`` (default: the recommendation)."""
        row = row or self.recommended
        if row is None:
            raise ValueError("no setting of the sweep meets the requested accuracy")
        if row.method == "auto":
            return sc.replace(run=dataclasses.replace(sc.run, method="auto", rtol=row.setting))
        return sc.replace(run=dataclasses.replace(sc.run, method=row.method, dt=min(row.setting, sc.run.t_end)))


def _run(sc: Scenario, fidelity: str, method: str, **run) -> tuple[object, float]:
    """simulate with [run] changes; (trajectory, wall s). A short run is repeated and its fastest
    time kept: on shared cores one timing of a few milliseconds is mostly noise."""
    sc = sc.replace(run=dataclasses.replace(sc.run, method=method, fidelity=fidelity, **run))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ValidityWarning)
        best = math.inf
        for _ in range(REPEATS):
            start = time.perf_counter()
            tr = simulate(sc)
            best = min(best, time.perf_counter() - start)
            if best > REPEAT_UNDER_S:
                break
        return tr, best


def _theta_error(tr, ref) -> float:
    """max |theta - theta_ref| over the samples both have at the same time: a run that braking ended
    early has its last sample at its own stop time, where theta is not comparable (|G| -> 0)."""
    n = min(len(tr.theta), len(ref.theta))
    same = tr.t[:n] == ref.t[:n]
    if np.count_nonzero(same) < 2:
        return math.inf
    return float(np.max(np.abs(tr.theta[:n][same] - ref.theta[:n][same])))


def _fidelity(sc: Scenario) -> str:
    """The fidelity to sweep: the scenario's (auto resolved); a model with no integrator (a closed
    form) is replaced by the ODE it solves, the averaged model, or else by the full model."""
    from physics.registry import REGISTRY

    fid = sc.run.fidelity
    if fid == "auto":
        fid, _ = choose_fidelity(sc)
    for candidate in (fid, "averaged", "full"):
        model = REGISTRY.get(f"{sc.system}/{candidate}")
        if model is not None and model.kernel is not None:
            return candidate
    raise ScenarioError("run.fidelity", fid, f"has no integrated model of {sc.system} to sweep")


def work_precision(scenario: Scenario, *, horizon: float | None = None,
                   progress: Callable[[float], None] | None = None, cancel=None) -> WorkPrecision:
    """Sweep the compiled methods on ``scenario`` and recommend the cheapest that meets its accuracy.

    ``horizon`` (s) defaults to what the reference can cover in about REFERENCE_BUDGET_S, at most
    ``run.t_end``. ``progress(fraction)`` is called after each run; ``cancel`` (anything with
    ``is_set()``, e.g. a threading.Event) stops the sweep between runs. The tolerance is
    ``run.accuracy`` when set, else the error of the scenario's own setting (run.method with its
    rtol or dt) on this horizon, at least ACCURACY_FLOOR: the recommendation is then as accurate as
    what the scene runs now, and cheaper or equal.
    """
    if not isinstance(scenario, Scenario):
        raise ScenarioError("scenario", type(scenario).__name__, "must be a physics.Scenario")
    fid = _fidelity(scenario)
    from physics.registry import get_model
    from physics.stepping.stepper import supports

    model = get_model(scenario.system, fid)
    midpoint_ok = supports(model, scenario, "midpoint")[0]  # the one rule simulate and LiveRun apply

    def report(fraction):
        if progress is not None:
            progress(min(1.0, fraction))

    def cancelled():
        return cancel is not None and cancel.is_set()

    base = scenario.replace(run=dataclasses.replace(scenario.run, t_eval=None, samples=SAMPLES, accuracy=None,
                                                    method="auto", dt=None))
    methods = ["auto", "RK8", "RK4"] + (["midpoint"] if midpoint_ok else [])
    tiny = min(1e-3, scenario.run.t_end)
    for method in methods:  # load (or compile) the kernels first: not a cost of any point of the sweep
        try:
            _run(base, fid, method, t_end=tiny, samples=2, dt=None if method == "auto" else tiny)
        except (IntegrationFault, ScenarioError):
            pass
    if horizon is None:  # grow the horizon until the reference takes a good part of its budget
        horizon = min(PROBE_T, scenario.run.t_end)
        while True:
            ref, ref_wall = _run(base, fid, "auto", rtol=REFERENCE_RTOL, t_end=horizon)
            if ref_wall >= REFERENCE_BUDGET_S / 3 or horizon >= scenario.run.t_end or ref.t[-1] < horizon:
                break
            horizon = min(scenario.run.t_end, horizon * min(GROWTH, REFERENCE_BUDGET_S / max(ref_wall, 1e-3)))
            if cancelled():
                break
    else:
        ref, ref_wall = _run(base, fid, "auto", rtol=REFERENCE_RTOL, t_end=float(horizon))
    base = base.replace(run=dataclasses.replace(base.run, t_end=float(horizon)))
    if ref.t[-1] < horizon:  # braking ended the run sooner: sample up to the braking time only
        horizon = float(ref.t[-1])
        base = base.replace(run=dataclasses.replace(base.run, t_end=horizon))
        ref, ref_wall = _run(base, fid, "auto", rtol=REFERENCE_RTOL)
    mean_step = float(ref.t[-1] - ref.t[0]) / max(1, _run(base, fid, "auto", rtol=1e-8)[0].info["steps"])

    plan: list[tuple[str, float]] = [("auto", r) for r in DOP853_RTOLS]
    fixed = [("RK8", RK8_STEPS), ("RK4", RK4_STEPS)] + ([("midpoint", MIDPOINT_STEPS)] if midpoint_ok else [])
    for method, factors in fixed:
        plan += [(method, f * mean_step) for f in factors]
    own = scenario.run
    own_setting = (own.method, own.dt) if own.method in ("RK4", "RK8", "midpoint") else ("auto", own.rtol)
    if own_setting[0] == "midpoint" and not midpoint_ok:
        own_setting = ("auto", own.rtol)
    if own_setting not in plan:
        plan.append(own_setting)

    result = WorkPrecision(fidelity=fid, model=model.name, horizon=float(horizon), tolerance=math.nan,
                           tolerance_source="", reference_wall_s=ref_wall)
    last_wall: dict[str, tuple[float, float]] = {}
    for i, (method, setting) in enumerate(plan):
        if cancelled():
            result.cancelled = True
            break
        if method in last_wall:  # fixed step: cost grows as 1/dt
            w, s = last_wall[method]
            if w * s / setting > RUN_BUDGET_S and (method, setting) != own_setting:
                report((i + 1) / len(plan))
                continue
        kwargs = dict(rtol=setting) if method == "auto" else dict(dt=min(setting, float(horizon)))
        try:
            tr, wall = _run(base, fid, method, **kwargs)
        except (IntegrationFault, ScenarioError):
            tr = None  # unstable at this step, or refused: no row
        if tr is not None:
            err = _theta_error(tr, ref)
            if method != "auto":
                last_wall[method] = (wall, setting)
            same_steps = any(r.method == method and r.steps == int(tr.info.get("steps") or 0) for r in result.rows)
            if math.isfinite(err) and not (method != "auto" and same_steps):  # output times capped the step
                result.rows.append(Row(method, float(setting), err, wall, int(tr.info["nfev"]),
                                       int(tr.info.get("steps") or 0)))
        report((i + 1) / len(plan))

    if scenario.run.accuracy is not None:
        result.tolerance = float(scenario.run.accuracy)
        result.tolerance_source = f"run.accuracy = {scenario.run.accuracy:g} rad"
    else:
        mine = [r for r in result.rows if (r.method, r.setting) == own_setting]
        name = f"{own_setting[0]} " + (f"rtol={own_setting[1]:g}" if own_setting[0] == "auto"
                                       else f"dt={own_setting[1]:g}")
        if mine:
            result.tolerance = max(mine[0].error, ACCURACY_FLOOR)
            result.tolerance_source = f"the error of the scene's own setting ({name}) on this horizon"
        else:
            result.tolerance = max(own.rtol, ACCURACY_FLOOR)
            result.tolerance_source = f"run.rtol = {own.rtol:g} (the scene's own setting {name} did not finish)"
    ok = [r for r in result.rows if r.error <= result.tolerance]
    result.recommended = min(ok, key=lambda r: r.wall_s) if ok else None
    return result
