"""Damper design: the parameters, within bounds, that make one metric of a run best (issue 26).

    result = physics.design(sc, vary={"pendulum.k": (20, 80), "pendulum.c_d": (1, 40)}, objective="decay_time")
    result.best     # {"pendulum.k": 44.1, "pendulum.c_d": 9.3}
    result.value    # the objective there, from a run of the full model

A grid is the slow way to an optimum: 400 runs for two parameters, and the optimum still falls between its points.
Here a coarse grid (START_LEVELS points per key, a few dozen runs) finds the basin, and scipy's bounded Nelder-Mead
refines the best STARTS of its points. Nelder-Mead compares values only, so a fitted metric's small jumps (a
sample leaving the fit window) and a point that fails (inf) do not mislead it as they would a gradient.
Each key is searched on [0, 1], linear in the key, or logarithmic where its bounds span a factor of LOG_SPAN or
more (a damping coefficient over decades).

A point runs on fidelity "auto" at an accuracy set from the objective's sensitivity to theta (``accuracy_for``):
the cheapest model whose stated error is small against what the objective reads. The optimum is then run on the
full model, and that run gives ``value``: a cheaper model chose the point, the full one states it.

The refinements run side by side (one thread each, their runs on local processes or a Dask cluster). Every run
depends on nothing but its inputs and each refinement's sequence of points on nothing but its own runs, so any
executor gives the same result bit for bit. ``stop`` (or Ctrl-C in the command line) ends the design after the
runs in flight: what was found is kept, with ``stopped`` set.
"""

from __future__ import annotations

import csv
import itertools
import math
import threading
import time
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from physics.core.errors import ScenarioError
from physics.registry import get_system
from physics.scenario import arguments
from physics.scenario.initial import initial_G
from physics.scenario.meta import BASE_PARAMS
from physics.scenario.scenario import Scenario
from physics.stepping.simulate import simulate
from physics.studies.metrics import FIT_BAND, METRICS
from physics.studies.pool import (
    NEEDS_DISTRIBUTED,
    DaskHalt,
    HaltingPool,
    Stopped,
    scheduler_client,
    set_dask_halt,
    stopper,
    worker_halt,
)
from physics.studies.sweep import point_scenario, resolve_key

# objective -> "min", "max" or "min_positive" (a decay time: the smallest positive; a growing nutation is worst)
OBJECTIVES = {"decay_time": "min_positive", "braking_time": "min", "theta_end": "min",
              "energy_dissipated": "max", "max_displacement": "min"}
MAX_KEYS = 4
START_LEVELS = {1: 8, 2: 5, 3: 3, 4: 2}  # coarse points per key: 8, 25, 27, 16 runs
STARTS = 2  # refinements, from the best distinct coarse points
STOP_POLL_S = 0.05  # s: how often a wait for a run looks at ``stop``
BUDGET = 120  # runs per design by default, the coarse start, the refinements and the full model's check included
MAX_BUDGET = 10_000
LOG_SPAN = 20.0  # hi/lo from which a key is searched on a log scale
XATOL = 1e-3  # Nelder-Mead's step tolerance, in the unit cube: 0.1 % of each key's range
FATOL = 1e-4  # and its value tolerance, relative to the best coarse value
# the share of what the objective reads that a point's stated theta error may take (accuracy_for)
SENSITIVITY_SHARE = 0.05


@dataclass(frozen=True)
class Evaluation:
    """One run of the design: the keys' values, the objective (NaN when the run failed), the model that ran,
    its stated theta error against the full model (rad; 0 for the full model itself), the phase ("start",
    "refine 1", "refine 2", "check" for the full model's run of the optimum), the failure's message and the run's
    own time (s, where it ran)."""

    values: tuple[float, ...]
    objective: float
    model: str
    error_bound: float
    phase: str
    error: str = ""
    compute_s: float = 0.0


@dataclass
class DesignResult:
    """``best``: key -> value at the optimum; ``value``: the objective there from the full model's run;
    ``cheap_value``: the objective of the run that chose it; ``evaluations``: runs made (the check included);
    ``path``: every Evaluation in the order the design made them (per refinement); ``method``: how the optimum
    was found; ``references``: the papers' tunings of this system, name -> (key -> value, objective from the
    full model); ``stopped``: the design was stopped before it finished."""

    base: Scenario
    keys: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]
    objective: str
    unit: str
    goal: str
    best: dict[str, float]
    value: float
    cheap_value: float
    best_model: str
    evaluations: int
    path: list[Evaluation]
    method: str
    accuracy: float | None
    references: dict[str, tuple[dict[str, float], float]] = field(default_factory=dict)
    stopped: bool = False
    wall_s: float = 0.0

    def scenario(self) -> Scenario:
        """The base scenario with the optimum's values (fidelity as the base had it)."""
        return point_scenario(self.base, self.best)

    def column(self, key: str) -> np.ndarray:
        """One key's values (or "objective") over the path, in order."""
        if key == "objective":
            return np.array([e.objective for e in self.path])
        i = self.keys.index(key)
        return np.array([e.values[i] for e in self.path])


class DesignStopped(ScenarioError):
    """The design was stopped before its first run ended: no point ran, so there is no optimum to keep."""

    def __init__(self):
        super().__init__("design", "(stopped)", "no run had ended when it was stopped, so there is no optimum to show; "
                         "start it again and let its first run finish")


def _result(future, stop) -> dict:
    """The future's row, waited for in short looks so that ``stop`` (Ctrl-C in the command line) ends the wait."""
    while not future.done():
        if stop.is_set():
            raise Stopped
        time.sleep(STOP_POLL_S)
    return future.result()


# ---- one run ---------------------------------------------------------------------------------------------

def evaluate(base: Scenario, keys: tuple[str, ...], values: tuple[float, ...], objective, fidelity: str,
             accuracy: float | None, stop=None) -> dict:
    """Run one point and read the objective: {"objective", "model", "error_bound", "error"}. Never raises for a
    bad point (a scenario the values make invalid, a failed run): its objective is NaN and ``error`` says why.
    ``stop`` (in this process only): the run ends between compiled calls once it is set, raising Stopped."""
    row = {"objective": math.nan, "model": "", "error_bound": math.nan, "error": "", "compute_s": 0.0}
    start = time.perf_counter()
    try:
        sc = point_scenario(base, dict(zip(keys, values, strict=True)))
        sc = sc.with_values(**{"run.fidelity": fidelity, "run.accuracy": accuracy})
        tr = simulate(sc, progress=None if stop is None else stopper(stop))
        row["model"] = str(tr.info.get("model", ""))
        row["error_bound"] = float(tr.info.get("error_bound", math.nan))
        fn = METRICS[objective] if isinstance(objective, str) else objective
        row["objective"] = float(fn(tr, sc))
    except SystemError as exc:  # Ctrl-C landing while a compiled call returned (physics/__main__.py)
        if isinstance(exc.__context__, KeyboardInterrupt):
            raise KeyboardInterrupt from None
        row["error"] = f"{type(exc).__name__}: {exc}"
    except Stopped:
        raise
    except Exception as exc:  # noqa: BLE001 - one bad point must not end a design
        row["error"] = f"{type(exc).__name__}: {exc}"
    row["compute_s"] = time.perf_counter() - start
    return row


def accuracy_for(sc: Scenario, objective) -> float | None:
    """The theta accuracy (rad) auto's points run at: SENSITIVITY_SHARE of the smallest theta the objective
    reads. decay_time fits ln theta down to theta0/FIT_BAND, so an error d there moves the fit by d/theta: the
    share is of theta0/FIT_BAND. theta_end and energy_dissipated read theta at its scale, theta0. braking_time
    reads |K|, which every model keeps or brakes alike, and a callable reads what it likes: both get auto's default
    (None)."""
    theta0 = initial_G(sc)[2]
    if not (math.isfinite(theta0) and theta0 > 0) or not isinstance(objective, str):
        return None
    if objective == "decay_time":
        return SENSITIVITY_SHARE * theta0 / FIT_BAND
    if objective in ("theta_end", "energy_dissipated", "max_displacement"):
        return SENSITIVITY_SHARE * theta0
    return None


def score(goal: str, value: float) -> float:
    """What the search minimises: inf where the point failed or (decay time) the nutation does not decay."""
    if not math.isfinite(value) and not (goal == "max" and value == math.inf):
        return math.inf if goal != "min" or math.isnan(value) else value
    if goal == "min_positive":
        return value if value > 0 else math.inf
    return -value if goal == "max" else value


# ---- executors -------------------------------------------------------------------------------------------

def _evaluate_in_worker(*args) -> dict:
    """evaluate in a local worker, ended once the design sets its halt: a stopped design does not wait for runs
    whose results it will not keep (a full run may take minutes), and a second Ctrl-C, which ends the design's
    process at once, leaves no worker running on (they held the terminal's output until their runs ended)."""
    return evaluate(*args, stop=worker_halt())


def _evaluate_on_dask(*args, halt: str) -> dict:
    """evaluate on a dask worker, ended once the design sets its halt (``pool.DaskHalt``)."""
    return evaluate(*args, stop=DaskHalt(halt))


class _Runner:
    """submit(values, phase) -> Future of an Evaluation, on local processes, in this process, or on Dask."""

    def __init__(self, base, keys, objective, fidelity, accuracy, executor, workers, dask, stop):
        self.args = (base, keys)
        self.stop = stop  # in this process a run ends once it is set (raising Stopped from submit)
        self.tail = (objective, fidelity, accuracy)
        self.pool = self.client = self.cluster = None
        self.halt = DaskHalt.new_name()
        self.lock = threading.Lock()
        if dask is not None:
            try:
                from distributed import Client, LocalCluster
            except ImportError:
                raise ScenarioError("dask", dask, NEEDS_DISTRIBUTED) from None

            if isinstance(dask, str) and dask == "local":
                import logging

                self.cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                            dashboard_address=None, silence_logs=logging.ERROR)
                self.client = Client(self.cluster)
                self.own = True
            elif isinstance(dask, str):
                self.client, self.own = scheduler_client(dask), True
            else:
                self.client, self.own = dask, False
        elif executor == "processes" and workers > 1:
            self.pool = HaltingPool(workers)

    def submit(self, values: tuple[float, ...]) -> Future:
        if self.client is not None:
            return self.client.submit(_evaluate_on_dask, *self.args, values, *self.tail, halt=self.halt, pure=False)
        if self.pool is not None:
            return self.pool.submit(_evaluate_in_worker, *self.args, values, *self.tail)
        f: Future = Future()
        with self.lock:  # in this process: one run at a time, whichever refinement asks
            f.set_result(evaluate(*self.args, values, *self.tail, self.stop))
        return f

    def close(self) -> None:
        """Ends the workers' runs still going (their results are not waited for) and the pool or the client."""
        if self.pool is not None:
            self.pool.close()
        if self.client is not None:
            set_dask_halt(self.client, self.halt)  # a cancelled future's run would go on to its end
            if self.own:
                self.client.close()
        if self.cluster is not None:
            self.cluster.close()


# ---- the design ------------------------------------------------------------------------------------------

def _bounds(scenario: Scenario, vary) -> tuple[list[str], list[tuple[float, float]]]:
    example = '{"pendulum.k": (10, 80), "pendulum.c_d": (1, 40)}'
    if isinstance(vary, Mapping) and not vary:
        raise ScenarioError("vary", vary, "give one to four parameters with bounds, e.g. " + example)
    arguments.mapping(vary, "vary", example)
    if len(vary) > MAX_KEYS:
        raise ScenarioError("vary", ", ".join(map(str, vary)), f"names {len(vary)} parameters; a design varies "
                            f"one to {MAX_KEYS}")
    keys, bounds = [], []
    for name, spec in vary.items():
        key = resolve_key(scenario, name)
        if key in keys:
            raise ScenarioError("vary", name, f"names {key} twice")
        lo, hi = _pair(key, spec)
        for v in (lo, hi):
            try:
                point_scenario(scenario, {key: v})
            except ScenarioError as exc:
                raise ScenarioError(f"vary {key}", f"{lo:g}:{hi:g}", f"reaches outside what {key} allows: "
                                    f"{exc}") from None
        keys.append(key)
        bounds.append((lo, hi))
    return keys, bounds


def _pair(key: str, spec) -> tuple[float, float]:
    """Bounds (lo, hi) from "LO:HI" or a pair."""
    why = "must be bounds LO:HI (or a pair (lo, hi)) with finite LO < HI"
    if isinstance(spec, str):
        parts = spec.split(":")
    elif isinstance(spec, (tuple, list)):
        parts = list(spec)
    else:
        raise ScenarioError(f"vary {key}", spec, why)
    if len(parts) != 2:
        raise ScenarioError(f"vary {key}", spec, why)
    try:
        lo, hi = float(parts[0]), float(parts[1])
    except (TypeError, ValueError):
        raise ScenarioError(f"vary {key}", spec, why) from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ScenarioError(f"vary {key}", spec, why)
    if not lo < hi:
        raise ScenarioError(f"vary {key}", spec, why + ("; these are reversed" if lo > hi else "; the range is "
                                                        "empty"))
    return lo, hi


class _Scale:
    """The unit cube <-> the keys' values: linear, or log where hi/lo >= LOG_SPAN (lo > 0)."""

    def __init__(self, bounds):
        self.bounds = bounds
        self.log = [lo > 0 and hi / lo >= LOG_SPAN for lo, hi in bounds]

    def values(self, x) -> tuple[float, ...]:
        out = []
        for xi, (lo, hi), log in zip(np.clip(x, 0.0, 1.0), self.bounds, self.log, strict=True):
            # in logarithms, and the line as a weighted mean: hi/lo and hi - lo overflow for bounds such as
            # (5e-324, 80) or (-1e308, 1e308), which put every point at hi (or nan)
            v = math.exp((1 - xi) * math.log(lo) + xi * math.log(hi)) if log else (1 - xi) * lo + xi * hi
            out.append(float(min(max(v, lo), hi)))
        return tuple(out)


def design(scenario: Scenario, vary: Mapping[str, object], objective: str | Callable = "decay_time", *,
           maximize: bool | None = None, budget: int = BUDGET, accuracy: float | None = None,
           fidelity: str = "auto", executor: str = "processes", workers: int | None = None, dask=None,
           progress: Callable[[int, int, Evaluation], None] | None = None, stop: threading.Event | None = None,
           references: bool = True) -> DesignResult:
    """The point within ``vary``'s bounds where ``objective`` is best (module docstring).

    ``vary``: {name: (lo, hi) or "LO:HI"}, one to four keys (dotted, or short names unique in the scenario).
    ``objective``: a metric name (OBJECTIVES: decay_time is made smallest positive, energy_dissipated largest,
    the rest smallest) or a callable ``fn(trajectory, scenario) -> float``, made smallest unless ``maximize``.
    ``budget``: the most runs, the full model's check of the optimum included. ``accuracy``: the theta accuracy
    (rad) auto's points run at (default ``accuracy_for``); ``fidelity``: "auto", or a fidelity every point runs.
    ``executor``/``workers``/``dask`` as physics.sweep takes them. ``progress(done, budget, evaluation)`` is
    called once per run: from the calling thread for the start, from the refinements' threads after it.
    ``references``: also run the papers' tunings of this system (System.tunings) on the full model, for comparison
    (not counted in ``evaluations``).
    """
    start_time = time.perf_counter()
    arguments.scenario(scenario)
    keys, bounds = _bounds(scenario, vary)
    if isinstance(objective, str):
        if objective not in OBJECTIVES:
            raise ScenarioError("objective", objective, "must be one of " + ", ".join(OBJECTIVES) +
                                " or a function (trajectory, scenario) -> float")
        goal = OBJECTIVES[objective] if maximize is None else ("max" if maximize else "min")
        name, unit = objective, METRICS[objective].unit
    elif callable(objective):
        goal = "max" if maximize else "min"
        name, unit = getattr(objective, "__name__", "objective"), ""
    else:
        raise ScenarioError("objective", objective, "must be one of " + ", ".join(OBJECTIVES) +
                            " or a function (trajectory, scenario) -> float")
    if isinstance(budget, bool) or not isinstance(budget, int) or not 1 <= budget <= MAX_BUDGET:
        raise ScenarioError("budget", budget, f"must be a whole number of runs from 1 to {MAX_BUDGET}")
    n_levels = START_LEVELS[len(keys)]
    coarse = n_levels ** len(keys)
    if budget < coarse + 1 + 2 * (len(keys) + 1):
        keys_word = f"{len(keys)} key" + ("s" if len(keys) > 1 else "")
        raise ScenarioError("budget", budget, f"is too small for {keys_word}: the coarse start alone takes "
                            f"{coarse} runs and each refinement at least {len(keys) + 1}; give at least "
                            f"{coarse + 1 + 2 * (len(keys) + 1)}")
    if accuracy is not None:
        accuracy = arguments.number(accuracy, "accuracy")
        if not 0 < accuracy < math.inf:
            raise ScenarioError("accuracy", accuracy, "must be a finite number > 0 rad (or None: set from the "
                                                      "objective)")
    else:
        accuracy = accuracy_for(scenario, objective) if fidelity == "auto" else None
    arguments.choice(executor, "executor", ("processes", "serial"))
    arguments.callback(progress, "progress")
    if stop is not None and not callable(getattr(stop, "is_set", None)):
        raise ScenarioError("stop", stop, "must be a threading.Event (or None)")
    workers = arguments.workers(workers)
    point_scenario(scenario, {}).with_values(**{"run.fidelity": fidelity})  # an unknown fidelity fails here
    stop = stop or threading.Event()
    scale = _Scale(bounds)
    lock = threading.Lock()
    paths: dict[str, list[Evaluation]] = {}
    count = {"runs": 0}

    levels = [(i + 0.5) / n_levels for i in range(n_levels)]
    grid = [np.array(x) for x in itertools.product(levels, repeat=len(keys))]
    # the first point runs here: it loads the compiled code once, and forked workers inherit it (as sweeps do). It
    # too ends once stop is set: a first point of minutes left Stop (and a first Ctrl-C) doing nothing until it ended
    try:
        first = evaluate(scenario, tuple(keys), scale.values(grid[0]), objective, fidelity, accuracy, stop)
    except Stopped:
        raise DesignStopped() from None
    runner = _Runner(scenario, tuple(keys), objective, fidelity, accuracy, executor, workers, dask, stop)

    def record(phase: str, values, row) -> Evaluation:
        e = Evaluation(values=values, objective=row["objective"], model=row["model"],
                       error_bound=row["error_bound"], phase=phase, error=row["error"], compute_s=row["compute_s"])
        with lock:
            paths.setdefault(phase, []).append(e)
            count["runs"] += 1
            done = count["runs"]
        if progress is not None:
            progress(done, budget, e)
        return e

    try:
        # the coarse start: all at once
        start_points = [(score(goal, record("start", scale.values(grid[0]), first).objective), grid[0])]
        try:
            futures = [(x, runner.submit(scale.values(x))) for x in grid[1:]]
            for x, f in futures:
                e = record("start", scale.values(x), _result(f, stop))
                start_points.append((score(goal, e.objective), x))
        except (KeyboardInterrupt, Stopped):  # keep what ran; no refinement starts
            stop.set()
        # auto's choice costs a cost probe and an error estimate per run: where it chose the full model at every
        # start point, the refinements run the full model directly
        all_full = fidelity == "auto" and all(e.model.endswith("/full") or e.error for e in paths["start"])
        if all_full:
            runner.tail = (objective, "full", None)
        # refinements from the best distinct start points, side by side
        ranked = sorted((p for p in start_points if math.isfinite(p[0])), key=lambda p: p[0])
        scale_f = abs(ranked[0][0]) if ranked and ranked[0][0] != 0 else 1.0
        per_start = (budget - len(start_points) - 1) // max(min(STARTS, len(ranked)), 1)
        threads, failures = [], []

        def refine(*args):
            try:
                _refine(*args)
            except BaseException as exc:  # noqa: BLE001 - raised again below, in the caller's thread
                failures.append(exc)
                stop.set()

        for j, (_, x0) in enumerate(ranked[:STARTS]):
            phase = f"refine {j + 1}"
            t = threading.Thread(target=refine, args=(runner, scale, x0, 1.0 / n_levels, per_start, goal, scale_f,
                                                      phase, record, stop), daemon=True)
            threads.append(t)
            t.start()
        try:
            for t in threads:
                while t.is_alive():
                    t.join(0.1)
        except KeyboardInterrupt:
            stop.set()
            for t in threads:
                t.join()
        if failures:  # a fault in a refinement (a progress callback's, say) is the caller's, not a thread's traceback
            raise failures[0]
        ordered = [e for phase in ["start", *(f"refine {j + 1}" for j in range(len(threads)))]
                   for e in paths.get(phase, [])]
        best = min(ordered, key=lambda e: score(goal, e.objective), default=None)
        if best is None or not math.isfinite(score(goal, best.objective)):
            raise ScenarioError("objective", name, "is not finite at any point the design ran (every run failed or, "
                                "for a decay time, the nutation grew): " + _first_error(ordered))
        check = None
        if not stop.is_set():  # the full model states the optimum's value
            try:
                check = record("check", best.values, evaluate(scenario, tuple(keys), best.values, objective, "full",
                                                              None, stop))
            except (KeyboardInterrupt, Stopped):  # stopped during the check: the optimum found is kept, unchecked
                stop.set()
    finally:
        runner.close()
    ordered.extend(paths.get("check", []))
    best_values = dict(zip(keys, best.values, strict=True))
    value = check.objective if check is not None else math.nan
    try:
        refs = _references(scenario, keys, objective, stop) if references and not stop.is_set() else {}
    except (KeyboardInterrupt, Stopped):  # the papers' tunings are a comparison: stopping skips them, keeps the rest
        stop.set()
        refs = {}
    # a stopped design says what ran, not what a whole one would have: refinements that took no step, and auto's
    # choice read off a partial start, are not named
    started = len(paths.get("start", []))
    refined = sum(1 for j in range(len(threads)) if paths.get(f"refine {j + 1}"))
    method = (f"coarse start of {n_levels}^{len(keys)} = {len(grid)} points"
              + (f" ({started} ran before the stop)" if started < len(grid) else "")
              + (f", then scipy.optimize.minimize (Nelder-Mead, bounded) from the best {refined}" if refined else "")
              + ", on " + ", ".join(f"{k} ({'log' if lg else 'linear'})" for k, lg in zip(keys, scale.log, strict=True))
              + f"; points on fidelity {fidelity}" + (f" at accuracy {accuracy:.3g} rad" if accuracy else "")
              + ("; auto ran the full model at every start point, so the refinements ran it directly"
                 if all_full and refined and started == len(grid) else "")
              + ("; the optimum's value from the full model" if check is not None else "; stopped before the "
                 "full model's check"))
    return DesignResult(base=scenario, keys=tuple(keys), bounds=tuple(bounds), objective=name, unit=unit, goal=goal,
                        best=best_values, value=value, cheap_value=best.objective, best_model=best.model,
                        evaluations=len(ordered), path=ordered, method=method, accuracy=accuracy, references=refs,
                        stopped=stop.is_set(), wall_s=time.perf_counter() - start_time)


def _first_error(path: list[Evaluation]) -> str:
    errors = [e.error for e in path if e.error]
    return errors[0] if errors else "the values were " + ", ".join(f"{e.objective:.3g}" for e in path[:5])


def _refine(runner: _Runner, scale: _Scale, x0: np.ndarray, step: float, maxfev: int, goal: str, scale_f: float,
            phase: str, record, stop: threading.Event) -> None:
    """One bounded Nelder-Mead from x0, its simplex a coarse cell wide, each run recorded under ``phase``."""
    from scipy.optimize import minimize

    seen: dict[tuple[float, ...], float] = {}

    def f(x):
        values = scale.values(x)
        if values in seen:
            return seen[values]
        if stop.is_set() or len(seen) >= maxfev:
            raise Stopped
        e = record(phase, values, _result(runner.submit(values), stop))
        seen[values] = score(goal, e.objective) / scale_f
        return seen[values]

    simplex = [x0]
    for i in range(len(x0)):
        x = x0.copy()
        x[i] = x0[i] + step / 2 if x0[i] + step / 2 <= 1 else x0[i] - step / 2
        simplex.append(x)
    try:
        minimize(f, x0, method="Nelder-Mead", bounds=[(0.0, 1.0)] * len(x0),
                 options={"initial_simplex": np.array(simplex), "xatol": XATOL, "fatol": FATOL,
                          "maxfev": 10 * maxfev})
    except Stopped:
        pass


def _references(scenario: Scenario, keys, objective, stop) -> dict[str, tuple[dict[str, float], float]]:
    """The papers' tunings of this system (System.tunings), each run on the full model."""
    tunings = get_system(scenario.system).tunings
    out = {}
    try:
        named = tunings(scenario) if tunings is not None else {}
    except ScenarioError:
        return out
    for label, values in named.items():
        row = evaluate(scenario, tuple(values), tuple(values.values()), objective, "full", None, stop)
        out[label] = (dict(values), row["objective"])
    return out


def unit(scenario: Scenario, key: str) -> str:
    """The SI unit of a dotted key (its Param's), or "" where no Param describes it."""
    for param in (*BASE_PARAMS, *get_system(scenario.system).params):
        if param.key == key:
            return param.unit
    return ""


def write_csv(result: DesignResult, path: str | Path) -> None:
    """The design's path as CSV: the keys, the objective, the model, its stated error, the phase, the error, the
    run's own time."""
    with open(path, "w", newline="", encoding="utf-8") as fh:
        w = csv.writer(fh)
        w.writerow([*result.keys, result.objective, "model", "error_bound", "phase", "error", "compute_s"])
        for e in result.path:
            w.writerow([*(repr(v) for v in e.values), repr(e.objective), e.model, repr(e.error_bound), e.phase,
                        e.error, f"{e.compute_s:.6f}"])


__all__ = ["OBJECTIVES", "DesignResult", "Evaluation", "accuracy_for", "design", "evaluate", "score", "unit",
           "write_csv"]
