"""``python -m physics design``: a design from the command line, its progress on stderr, its optimum with units.

Ctrl-C ends the design after the runs in flight; what it found is printed and written (--out, --save) as if it
had finished, marked stopped.
"""

from __future__ import annotations

import json
import math
import signal
import sys
import time
from pathlib import Path

from physics.core.errors import ScenarioError
from physics.scenario.scenario import Scenario
from physics.studies.design import OBJECTIVES, DesignResult, DesignStopped, Evaluation, design, score, unit, write_csv


def parse_vary(items: list[str]) -> dict[str, str]:
    """{"k": "10:80", ...} from ["k=10:80", ...]."""
    out: dict[str, str] = {}
    for item in items:
        name, sep, bounds = item.partition("=")
        if not sep or not name.strip() or not bounds.strip():
            raise ScenarioError("--vary", item, "must be KEY=LO:HI, e.g. k=10:80 or pendulum.c_d=1:40")
        if name.strip() in out:
            raise ScenarioError("--vary", item, f"names {name.strip()} twice")
        out[name.strip()] = bounds.strip()
    return out


class _Progress:
    """'design: 37/120 runs, best decay_time 6.9': in place on a terminal; in a log the first run, then every tenth
    of the budget."""

    def __init__(self, objective: str, goal: str, budget: int):
        self.objective, self.goal, self.budget = objective, goal, budget
        self.tty = sys.stderr.isatty()
        self.best = math.nan
        self.shown = 0
        self.start = time.perf_counter()

    def __call__(self, done: int, budget: int, e: Evaluation) -> None:
        ranked = score(self.goal, e.objective)
        if math.isfinite(ranked) and (math.isnan(self.best) or ranked < score(self.goal, self.best)):
            self.best = e.objective
        line = f"design: {done}/{budget} runs, best {self.objective} {self.best:.6g}"
        if self.tty:
            print("\r" + line, end="", file=sys.stderr, flush=True)
        elif done == 1 or done - self.shown >= max(budget // 10, 1):  # the first at once: it has begun
            self.shown = done
            print(line, file=sys.stderr, flush=True)

    def end(self) -> None:
        if self.tty:
            print(file=sys.stderr, flush=True)


def _fmt(v: float) -> str:
    return f"{v:.6g}"


def _keys(result: DesignResult, values: dict[str, float], sc: Scenario) -> str:
    return ", ".join(f"{k} = {_fmt(v)} {unit(sc, k)}".rstrip() for k, v in values.items())


def as_json(result: DesignResult) -> str:
    def number(v):
        return float(v) if math.isfinite(v) else ("nan" if math.isnan(v) else ("inf" if v > 0 else "-inf"))

    return json.dumps({
        "objective": result.objective, "unit": result.unit, "goal": result.goal,
        "best": {k: number(v) for k, v in result.best.items()}, "value": number(result.value),
        "cheap_value": number(result.cheap_value), "model": result.best_model, "evaluations": result.evaluations,
        "bounds": {k: list(b) for k, b in zip(result.keys, result.bounds, strict=True)}, "method": result.method,
        "references": {name: {"values": {k: number(v) for k, v in vals.items()}, "value": number(val)}
                       for name, (vals, val) in result.references.items()},
        "stopped": result.stopped, "wall_s": result.wall_s,
    }, indent=1, allow_nan=False)


class _CtrlC:
    """The design's ``stop`` and its SIGINT handler. The first Ctrl-C only sets a flag, which the design looks at
    between runs and in its own runs' progress callbacks: a KeyboardInterrupt raised wherever the signal lands can
    be lost in fork's hooks while the pool starts (the design runs on) or escape between the design's handlers
    (nothing kept). A second Ctrl-C raises KeyboardInterrupt, the way out of a run that does not end (the workers
    leave when the design's process does: physics/studies/pool.py). A plain attribute, not a threading.Event: a
    handler that took a lock the interrupted code holds would deadlock."""

    def __init__(self):
        self.flag = False

    def is_set(self) -> bool:
        return self.flag

    def set(self) -> None:
        self.flag = True

    def __call__(self, signum, frame):
        if self.flag:
            raise KeyboardInterrupt
        self.flag = True


def run_design(sc: Scenario, args) -> int:
    vary = parse_vary(args.vary)
    progress = _Progress(args.objective, OBJECTIVES[args.objective], args.budget)
    stop = _CtrlC()
    try:
        previous, installed = signal.signal(signal.SIGINT, stop), True
    except ValueError:  # not the main thread (an embedding program): its own handling applies
        previous, installed = None, False
    try:
        result = design(sc, vary, args.objective, budget=args.budget, accuracy=args.accuracy, workers=args.workers,
                        dask=args.dask, progress=progress, stop=stop)
    except DesignStopped as exc:  # Ctrl-C before any run ended: interrupted, with nothing to print
        print(f"design stopped: {exc.allowed}", file=sys.stderr)
        return 130
    finally:
        if installed:
            signal.signal(signal.SIGINT, previous)
        progress.end()
    if args.out:
        try:
            write_csv(result, args.out)
        except OSError as exc:
            raise ScenarioError("--out", Path(args.out), f"cannot be written ({exc.strerror})") from None
    if args.save:
        try:
            with open(args.save, "w", encoding="utf-8") as fh:
                fh.write(f"# the optimum of python -m physics design ({result.objective}, {result.evaluations} "
                         "runs)\n" + result.scenario().to_toml())
        except OSError as exc:
            raise ScenarioError("--save", Path(args.save), f"cannot be written ({exc.strerror})") from None
    if args.json:
        print(as_json(result))
        return 0
    u = f" {result.unit}" if result.unit else ""
    bounds = ", ".join(f"{k} in [{_fmt(lo)}, {_fmt(hi)}] {unit(sc, k)}".rstrip()
                       for k, (lo, hi) in zip(result.keys, result.bounds, strict=True))
    words = {"min_positive": "smallest positive", "max": "largest", "min": "smallest"}[result.goal]
    print(f"design: {result.objective} ({words}) over {bounds}")
    if result.stopped:
        print("stopped: the best point so far follows" + ("" if math.isfinite(result.value) else
                                                          "; the full model's check did not run"))
    print(f"runs: {result.evaluations} in {result.wall_s:.3g} s")
    print(f"optimum: {_keys(result, result.best, sc)}")
    if math.isfinite(result.value) or not result.stopped:
        chose = ("" if result.best_model.endswith("/full") else
                 f"; the run that chose it, {result.best_model}: {_fmt(result.cheap_value)}{u}")
        print(f"{result.objective} = {_fmt(result.value)}{u} (full model{chose})")
    else:
        print(f"{result.objective} = {_fmt(result.cheap_value)}{u} ({result.best_model}, not checked on the full "
              "model)")
    for name, (values, value) in result.references.items():
        print(f"  {name}: {_keys(result, values, sc)} -> {result.objective} = {_fmt(value)}{u} (full model)")
    print(f"method: {result.method}")
    if args.out:
        print(f"wrote {result.evaluations} runs to {args.out}")
    if args.save:
        print(f"wrote the optimum to {args.save}")
    return 0
