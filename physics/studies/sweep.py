"""Parameter sweeps: one full ``simulate`` per grid point, on local worker processes or a Dask cluster.

    table = physics.sweep(sc, vary={"pendulum.k": "10:100:20", "pendulum.c_d": "log:1:20:20"},
                          metric="decay_time", out="sweep.csv")
    table.grid("decay_time")          # (20, 20) array, first key along axis 0

A point is ``simulate(point_scenario(base, {key: value, ...}))`` followed by the metrics of
physics/studies/metrics.py, computed wherever the point runs. It depends on nothing but its inputs, so any
executor gives the same numbers bit for bit. With ``out`` each finished point is appended to a CSV at
once (floats as ``repr``, which round-trips exactly), and a rerun skips the points already there, keyed
by the exact parameter values. A point whose scenario is invalid or whose integration fails is a row
with NaN metrics and the message in ``error``: it is done, and is not retried.
"""

from __future__ import annotations

import csv
import dataclasses
import hashlib
import itertools
import logging
import math
import os
import threading
import time
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import FIRST_COMPLETED, wait
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from physics.core.errors import ScenarioError
from physics.registry import REGISTRY, get_system
from physics.scenario import arguments
from physics.scenario.scenario import Scenario, _toml_names, sections
from physics.stepping.simulate import simulate
from physics.studies.metrics import METRICS
from physics.studies.pool import (
    NEEDS_DISTRIBUTED,
    DaskHalt,
    HaltingPool,
    Stopped,
    context,
    scheduler_client,
    set_dask_halt,
    stopper,
    worker_halt,
)
from physics.systems.choice import available

NOT_NUMERIC = {"run.samples"}  # a number, but a count of outputs, not a parameter of the motion
# after the varied keys and the metrics in the CSV: error_bound is the run's stated max |theta - theta_full| (rad;
# 0 for the full model, inf where its cheaper model makes no claim), as tr.info["error_bound"] gives it
TAIL_COLUMNS = ("error_bound", "model", "error", "scenario")
NOT_RUN = "(not run: the sweep was stopped)"
# The largest grid a sweep takes, and so the most values one axis may have. Each point is a full simulation:
# at the lightest measured (6 ms of CPU, docs/sweeps.md) this many take ten minutes of one core, and their
# rows (a dict of a dozen numbers each) about 100 MB; a typo such as 1e9 for 1e2 is refused before a
# single value is made, rather than exhausting the machine's memory.
MAX_POINTS = 100_000
SPEC_HELP = ('must be LO:HI:N (N values, linear), log:LO:HI:N (N values, geometric, LO and HI > 0), '
             'V1,V2,... (these values), a tuple (LO, HI, N) or ("log", LO, HI, N), or a list of values')


# ---- what to vary ---------------------------------------------------------------------------------

def axis_values(spec, name: str = "vary") -> tuple[list[float], str]:
    """The values of one varied parameter and their spacing ("linear", "log" or "list").

    ``spec``: "LO:HI:N" (numpy.linspace), "log:LO:HI:N" (numpy.geomspace), "V1,V2,..." or one number,
    a tuple (LO, HI, N) or ("log", LO, HI, N), or a list/array of values; at most MAX_POINTS values, refused
    before any is made. Raises ScenarioError naming ``name``.
    """
    def bad(why: str = SPEC_HELP):
        return ScenarioError(name, spec, why)

    def too_many():  # the spec shown with the message says how many
        return bad(f"asks for more than {MAX_POINTS} values, the most a sweep takes (each point is a full "
                   "simulation)")

    if isinstance(spec, str):
        text = spec.strip()
        parts = [p.strip() for p in text.split(":")]
        if len(parts) == 1:
            if text.count(",") >= MAX_POINTS:
                raise too_many()
            try:
                return [float(v) for v in text.split(",")], "list"
            except ValueError:
                raise bad() from None
        if parts[0].lower() == "log":
            parts = ["log", *parts[1:]]
        spec_t = tuple(parts)
    elif isinstance(spec, tuple):
        spec_t = spec
    elif isinstance(spec, (list, np.ndarray)):
        if (spec.size if isinstance(spec, np.ndarray) else len(spec)) > MAX_POINTS:
            raise too_many()
        try:
            flat = np.ravel(spec)
            if flat.size > MAX_POINTS:  # a nested list: the caller holds it already, but no more is made
                raise too_many()
            values = [float(v) for v in flat]
        except ScenarioError:
            raise
        except Exception:  # noqa: BLE001 - any element float() refuses (a caller's object may raise anything)
            raise bad() from None
        if not values or not all(math.isfinite(v) for v in values):
            raise bad("must hold at least one value, all finite")
        return values, "list"
    else:
        raise bad()
    log = len(spec_t) == 4 and isinstance(spec_t[0], str) and spec_t[0].lower() == "log"
    if len(spec_t) != (4 if log else 3):
        raise bad()
    try:
        lo, hi = float(spec_t[-3]), float(spec_t[-2])
        n = _count(spec_t[-1])
    except Exception:  # noqa: BLE001 - what float() refuses (a caller's object may raise anything)
        raise bad() from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or n < 1:
        raise bad("needs finite LO, HI and a whole N >= 1")
    if n > MAX_POINTS:
        raise too_many()
    if log:
        if lo <= 0 or hi <= 0:
            raise bad("log spacing needs LO > 0 and HI > 0")
        return [float(v) for v in np.geomspace(lo, hi, n)], "log"
    if not math.isfinite(hi - lo):  # e.g. -1e308:1e308: linspace's step overflows to nan and inf points
        t = np.linspace(0.0, 1.0, n)
        return [float(v) for v in (1 - t) * lo + t * hi], "linear"
    return [float(v) for v in np.linspace(lo, hi, n)], "linear"


def _count(raw) -> int:
    """N of a range: a whole number, also as text written with an exponent ("1e3"); -1 when it is none."""
    if isinstance(raw, bool):
        return -1
    if isinstance(raw, (int, np.integer)):
        return int(raw)
    if not isinstance(raw, str):
        return -1
    try:
        return int(raw)
    except ValueError:
        x = float(raw)  # "1e3": people write counts so too; a ValueError here means no number at all
        return int(x) if math.isfinite(x) and x == int(x) else -1


def numeric_keys(scenario: Scenario) -> list[str]:
    """Dotted keys a sweep may vary in ``scenario``: numeric keys of its tables (plus the tables it may
    switch on, e.g. medium.lambda), in the tables' order."""
    data = arguments.scenario(scenario).to_dict()
    out = []
    for table, cls in sections().items():
        if table not in data:
            continue
        types = {f.name: str(f.type) for f in dataclasses.fields(cls)}
        for key, name in _toml_names(table).items():
            dotted = f"{table}.{key}"
            if "float" in types[name] and "tuple" not in types[name] and dotted not in NOT_NUMERIC:
                out.append(dotted)
    for param in get_system(scenario.system).params:
        if param.adds and param.key not in out:
            out.append(param.key)
    return out


def resolve_key(scenario: Scenario, name: str) -> str:
    """The dotted scenario key meant by ``name``: a dotted key as is (checked), or a short name such as
    ``k`` when exactly one varied-able key of this scenario ends in it. Raises ScenarioError otherwise."""
    allowed = numeric_keys(scenario)
    if not isinstance(name, str):
        raise ScenarioError("vary", name, "must be a key (text) such as mass.chi; allowed: " + ", ".join(allowed))
    if "." in name:
        table, key = name.split(".", 1)
        if table not in sections() or key not in _toml_names(table):
            raise ScenarioError("vary", name, "is not a scenario key; this scenario allows: " + ", ".join(allowed))
        if name not in allowed:
            kind = str(next(f.type for f in dataclasses.fields(sections()[table]) if f.name == _toml_names(table)[key]))
            numeric = "float" in kind and "tuple" not in kind and name not in NOT_NUMERIC
            why = ("is not a number" if not numeric else
                   f"belongs to [{table}], which this {scenario.system} scenario does not have")
            raise ScenarioError("vary", name, f"cannot be swept: it {why}; allowed: " + ", ".join(allowed))
        return name
    hits = [k for k in allowed if k.split(".", 1)[1] == name]
    if len(hits) == 1:
        return hits[0]
    if not hits:
        raise ScenarioError("vary", name, f"is not a key of this {scenario.system} scenario; allowed: "
                            + ", ".join(allowed))
    raise ScenarioError("vary", name, "is ambiguous here; give one of " + ", ".join(hits))


def point_scenario(base: Scenario, values: dict[str, float]) -> Scenario:
    """``base`` with the dotted keys set to numbers (validated again; physics/scenario/edit.py): a key of
    [[plane_pendulum]] sets every pendulum; initial.G0 or theta0 on a scenario given by omega first rewrites
    omega as G0, theta0."""
    arguments.scenario(base, "base")
    values = arguments.mapping(values, "values", '{"mass.chi": 5.0}')
    return base.with_values(**{k: arguments.number(v, k) for k, v in values.items()})


def check_point(base: Scenario, values: dict[str, float]) -> Scenario:
    """``point_scenario(base, values)`` plus the checks a run makes before it integrates: the model's
    parameter vector and initial state (e.g. m rho^2/(1 - m/M) < A, which only the moving-mass models
    check). With fidelity "auto" every model of the system is checked, since the run may pick any.
    Raises the ScenarioError the point's run would raise; integrates nothing (microseconds)."""
    sc = point_scenario(base, values)
    fid = sc.run.fidelity
    if fid not in ("auto", "full"):
        ok, why = available(sc, fid)
        if not ok:
            raise ScenarioError("run.fidelity", fid, f"is not available for this scenario: {why}")
    models = [m for m in REGISTRY.values() if m.system == sc.system and (fid == "auto" or m.fidelity == fid)]
    for model in models:
        if model.pack is not None:
            p = model.pack(sc)
            if model.initial_state is not None:
                model.initial_state(sc, p)
    return sc


# ---- one point --------------------------------------------------------------------------------------

def run_point(base: Scenario, keys: Sequence[str], values: Sequence[float], metrics: Sequence[str],
              stop=None) -> dict:
    """Simulate one grid point and measure it: {key: value, metric: float, "model", "error", "compute_s"}.

    Never raises for a bad point: an invalid scenario or a failed integration gives NaN metrics and
    ``error`` = "ExceptionType: message". Runs in the worker, so only picklable things go in and out.
    ``stop``: the run ends between compiled calls once it is set, raising pool.Stopped (no row: it was not run).
    """
    start = time.perf_counter()
    row: dict = dict(zip(keys, (float(v) for v in values), strict=True))
    row.update({m: math.nan for m in metrics})
    row["model"], row["error"], row["error_bound"] = "", "", math.nan
    try:
        sc = point_scenario(base, dict(zip(keys, values, strict=True)))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a ValidityWarning per point would drown the progress bar
            tr = simulate(sc, progress=None if stop is None else stopper(stop))
        row["model"] = str(tr.info.get("model", ""))
        row["error_bound"] = float(tr.info.get("error_bound", math.nan))
        for m in metrics:
            row[m] = METRICS[m](tr, sc)
    except Stopped:
        raise
    except Exception as exc:  # noqa: BLE001 - one bad point must not end a sweep of hundreds
        row["error"] = f"{type(exc).__name__}: {exc}"
    row["compute_s"] = time.perf_counter() - start
    return row


# ---- the table ---------------------------------------------------------------------------------------

@dataclass
class SweepTable:
    """A finished (or stopped) sweep, one row per grid point in grid order (last key fastest).

    ``keys``: the varied dotted keys; ``axes``: their values; ``spacing``: "linear", "log" or "list" per key;
    ``metrics``: the metric columns; ``metric``: the one charts show. ``rows``: dicts with the keys, the
    metrics, ``error_bound`` (the run's stated theta error against the full model, rad; ``info`` says how it
    was obtained), ``model`` and ``error``. ``computed``/``skipped``: points run now / found in the CSV;
    ``wall_s``: wall time of this call; ``compute_s``: sum of the points' own times (in the workers).
    """

    base: Scenario
    keys: tuple[str, ...]
    axes: tuple[tuple[float, ...], ...]
    spacing: tuple[str, ...]
    metrics: tuple[str, ...]
    metric: str
    rows: list[dict]
    computed: int = 0
    skipped: int = 0
    wall_s: float = 0.0
    compute_s: float = 0.0
    out: Path | None = None
    stopped: bool = False
    info: dict = field(default_factory=dict)

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a) for a in self.axes)

    def not_run(self, row: dict) -> bool:
        """The point was not run because the sweep was stopped (not a failure of the point)."""
        return row["error"] == NOT_RUN

    @property
    def failed(self) -> int:
        """Points run that failed (an invalid scenario, a fault), the ones a stop left unrun not counted."""
        return sum(1 for r in self.rows if r["error"] and not self.not_run(r))

    def column(self, name: str) -> np.ndarray:
        """One column over all points, grid order (floats; "model" and "error" as object arrays)."""
        if name in ("model", "error"):
            return np.array([r[name] for r in self.rows], dtype=object)
        return np.array([r[name] for r in self.rows], dtype=float)

    def grid(self, name: str | None = None) -> np.ndarray:
        """A metric as an array of shape ``self.shape`` (first key along axis 0)."""
        return self.column(name or self.metric).reshape(self.shape)

    def scenario(self, i: int) -> Scenario:
        """The scenario of row ``i`` (what its point simulated)."""
        return point_scenario(self.base, {k: self.rows[i][k] for k in self.keys})


# ---- CSV ---------------------------------------------------------------------------------------------

def _fingerprint(sc: Scenario) -> str:
    return hashlib.sha256(sc.to_toml().encode()).hexdigest()[:16]


def _fmt(v) -> str:
    return repr(float(v)) if isinstance(v, (float, int, np.floating)) else str(v)


def _ends_with_newline(path: Path) -> bool:
    with open(path, "rb") as fh:
        fh.seek(-1, os.SEEK_END)
        return fh.read(1) == b"\n"


def _point_key(values: Iterable[float]) -> tuple[str, ...]:
    return tuple(repr(float(v)) for v in values)


def _read_done(path: Path, header: list[str], keys: Sequence[str], metrics: Sequence[str], tag: str) -> dict:
    """Rows already in ``path`` for this scenario: point key -> row. Raises ScenarioError when the file
    holds another sweep (other columns or another base scenario), so it is never mixed up."""
    done: dict = {}
    with open(path, newline="", encoding="utf-8") as fh:
        reader = csv.reader(fh)
        first = next(reader, None)
        if first is None:
            return done
        if first != header:
            raise ScenarioError("out", Path(path), f"holds a sweep with the columns {','.join(first)}, not "
                                f"{','.join(header)}; give another --out or delete the file")
        for line in reader:
            if len(line) != len(header):
                continue  # a line cut short by an interruption: the point runs again
            row = dict(zip(header, line, strict=True))
            if len(row["scenario"]) != len(tag):
                continue  # cut inside its last column
            if row["scenario"] != tag:
                raise ScenarioError("out", Path(path), "holds a sweep of another scenario (its fingerprint "
                                    f"{row['scenario']} is not {tag}); give another --out or delete the file")
            parsed = {k: float(row[k]) for k in keys}
            parsed.update({m: float(row[m]) for m in metrics})
            parsed["model"], parsed["error"] = row["model"], row["error"]
            parsed["error_bound"] = float(row["error_bound"])
            done[_point_key(parsed[k] for k in keys)] = parsed
    return done


# ---- executors ---------------------------------------------------------------------------------------

def _run_point_in_worker(*args) -> dict:
    """run_point in a worker of a pool.HaltingPool: it ends once the sweep closes the pool."""
    return run_point(*args, stop=worker_halt())


def _run_point_on_dask(*args, halt: str) -> dict:
    """run_point on a dask worker: it ends once the sweep sets its halt (``pool.DaskHalt``)."""
    return run_point(*args, stop=DaskHalt(halt))


def _run_processes(tasks, workers, on_result, stop, start_method=None):
    ctx = context(start_method)
    if ctx.get_start_method() == "fork":
        # The first point runs here: it loads the compiled code once, and the forked workers inherit it
        # instead of each loading it again.
        try:
            on_result(run_point(*tasks[0], stop=stop))
        except Stopped:
            return
        tasks = tasks[1:]
        if not tasks or (stop is not None and stop.is_set()):
            return
    pool = HaltingPool(min(workers, len(tasks)), ctx)
    pending = {pool.submit(_run_point_in_worker, *t) for t in tasks}
    try:
        while pending:
            finished, pending = wait(pending, timeout=0.2, return_when=FIRST_COMPLETED)
            for f in finished:
                on_result(f.result())
            if stop is not None and stop.is_set():
                break
    finally:
        # stopped (or failed): the runs still going end at their next progress callback, not after minutes
        pool.close()


def _run_dask(tasks, dask, workers, on_result, stop):
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:  # a plain install has no dask: said as the design says it, not as a bare ImportError
        raise ScenarioError("dask", dask, NEEDS_DISTRIBUTED) from None

    own_cluster = own_client = None
    if isinstance(dask, str):
        if dask == "local":
            own_cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=None, silence_logs=logging.ERROR)
            own_client = client = Client(own_cluster)
        else:
            own_client = client = scheduler_client(dask)
    else:
        client = dask
    halt, futures = DaskHalt.new_name(), []
    try:
        futures = [client.submit(_run_point_on_dask, *t, halt=halt, pure=False) for t in tasks]
        for fut in as_completed(futures):
            on_result(fut.result())
            if stop is not None and stop.is_set():
                break
    finally:
        if not all(f.done() for f in futures):  # stopped (or failed): the runs going end, the rest never start
            set_dask_halt(client, halt)
            client.cancel(futures)
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()


# ---- the sweep ---------------------------------------------------------------------------------------

def sweep(scenario: Scenario, vary: dict[str, object], metric: str | Sequence[str] = "decay_time", *,
          out: str | Path | None = None, workers: int | None = None, executor: str = "processes",
          dask=None, progress: Callable[[int, int], None] | None = None,
          stop: threading.Event | None = None, start_method: str | None = None) -> SweepTable:
    """Run ``scenario`` over the grid ``vary`` and return a SweepTable.

    ``vary``: {name: spec}; a name is a dotted scenario key or a short name unique in this scenario
    (resolve_key); a spec is what axis_values takes. The grid is the product of the axes, first key
    outermost. ``metric``: a name of physics.metrics.METRICS or a list of names (the first is charted).
    ``out``: CSV appended as points finish; a rerun with the same file skips the points it holds.
    ``executor``: "processes" (default: ``workers`` local processes, 1 to MAX_WORKERS, all cores when None) or "serial"
    (in this process). ``dask``: "local" (a LocalCluster of ``workers`` processes), a scheduler address,
    or a distributed.Client; it overrides ``executor``. ``progress(done, total)`` is called in this
    thread as points finish (points skipped from the CSV are not counted). Setting ``stop`` ends the
    sweep and the points still running (their runs end at the next progress callback); they and the rest are rows
    with NaN and error = NOT_RUN.
    ``start_method``: "fork", "forkserver" or "spawn" for the local processes (default: fork when
    this process runs no other thread, else forkserver; see pool.context).
    """
    start = time.perf_counter()
    arguments.scenario(scenario)
    example = '{"mass.chi": "1:20:5"}'
    if isinstance(vary, Mapping) and not vary:
        raise ScenarioError("vary", vary, "give at least one parameter to vary, e.g. " + example)
    arguments.mapping(vary, "vary", example)
    if not isinstance(metric, (str, list, tuple)):
        raise ScenarioError("metric", metric, "must be a metric's name or a list of names: " + ", ".join(METRICS))
    metrics = (metric,) if isinstance(metric, str) else tuple(metric)
    for m in metrics:
        if not isinstance(m, str) or m not in METRICS:
            raise ScenarioError("metric", m, "must be one of " + ", ".join(METRICS))
    if not metrics or len(set(metrics)) != len(metrics):
        raise ScenarioError("metric", metric, "give one or more different metric names")
    keys, axes, spacing = [], [], []
    for name, spec in vary.items():
        key = resolve_key(scenario, name)
        if key in keys:
            raise ScenarioError("vary", name, f"names {key} twice")
        values, how = axis_values(spec, f"vary {name}")
        point_scenario(scenario, {key: values[0]})  # a key the scenario cannot take fails here, once
        keys.append(key), axes.append(tuple(values)), spacing.append(how)
    total = math.prod(len(a) for a in axes)
    if total > MAX_POINTS:
        grid = " x ".join(f"{len(a)} {k}" for k, a in zip(keys, axes, strict=True))
        raise ScenarioError("vary", f"({grid} = {total} points)",
                            f"a sweep takes at most {MAX_POINTS} points (each a full simulation): use fewer values")
    arguments.choice(executor, "executor", ("processes", "serial"))
    arguments.callback(progress, "progress")
    if stop is not None and not callable(getattr(stop, "is_set", None)):
        raise ScenarioError("stop", stop, "must be a threading.Event (or None)")
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise ScenarioError("out", out, "must be a file path (or None)")
    workers = arguments.workers(workers)

    points = list(itertools.product(*axes))
    header = [*keys, *metrics, *TAIL_COLUMNS]
    tag = _fingerprint(scenario)
    results: dict[tuple[str, ...], dict] = {}
    path = Path(out) if out is not None else None
    if path is not None and path.exists() and path.stat().st_size > 0:
        results.update(_read_done(path, header, keys, metrics, tag))
    wanted = {_point_key(p) for p in points}
    skipped = len(wanted & results.keys())
    todo = [p for p in points if _point_key(p) not in results]
    tasks = [(scenario, tuple(keys), p, metrics) for p in todo]
    state = {"done": 0, "compute_s": 0.0}

    fh = writer = None
    if path is not None:
        fresh = not path.exists() or path.stat().st_size == 0
        try:
            fh = open(path, "a", newline="", encoding="utf-8")
        except OSError as exc:
            raise ScenarioError("out", Path(path), f"cannot be written ({exc.strerror})") from None
        writer = csv.writer(fh)
        if fresh:
            writer.writerow(header)
            fh.flush()
        elif not _ends_with_newline(path):
            fh.write("\r\n")  # end a line cut by an interruption, so the next row starts on its own line
            fh.flush()

    def on_result(row: dict) -> None:
        state["done"] += 1
        state["compute_s"] += row.pop("compute_s", 0.0)
        results[_point_key(row[k] for k in keys)] = row
        if writer is not None:
            numbers = [_fmt(row[c]) for c in (*keys, *metrics, "error_bound")]
            writer.writerow(numbers + [row["model"], row["error"], tag])
            fh.flush()
        if progress is not None:
            progress(state["done"], len(tasks))

    try:
        if progress is not None:
            progress(0, len(tasks))
        if not tasks:
            pass  # everything was in the CSV already
        elif dask is not None:
            _run_dask(tasks, dask, workers, on_result, stop)
        elif executor == "serial":
            for t in tasks:
                try:
                    on_result(run_point(*t, stop=stop))
                except Stopped:
                    break
                if stop is not None and stop.is_set():
                    break
        else:
            _run_processes(tasks, workers, on_result, stop, start_method)
    finally:
        if fh is not None:
            fh.close()

    rows = []
    for p in points:
        row = results.get(_point_key(p))
        if row is None:
            row = dict(zip(keys, p, strict=True)) | {m: math.nan for m in metrics} | {"model": "", "error": NOT_RUN,
                                                                                       "error_bound": math.nan}
        rows.append({c: row[c] for c in header[:-1]})
    return SweepTable(base=scenario, keys=tuple(keys), axes=tuple(axes), spacing=tuple(spacing), metrics=metrics,
                      metric=metrics[0], rows=rows, computed=state["done"], skipped=skipped,
                      wall_s=time.perf_counter() - start, compute_s=state["compute_s"], out=path,
                      stopped=len(results.keys() & wanted) < len(points),
                      info={"workers": 1 if executor == "serial" and dask is None else workers,
                            "executor": "dask" if dask is not None else executor,
                            "error_bound_method": get_system(scenario.system).error_method})


__all__ = ["MAX_POINTS", "SweepTable", "axis_values", "check_point", "numeric_keys", "point_scenario", "resolve_key",
           "run_point", "sweep"]
