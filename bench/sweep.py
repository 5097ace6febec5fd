"""``python -m bench sweep SCENARIO.toml --vary KEY=SPEC [--vary KEY=SPEC ...] [options]``: a parameter sweep.

    python -m bench sweep assets/scenarios/pendulum_resonant.toml --vary k=10:100:20 --vary c_d=1:20:20 \\
        --metric decay_time --out sweep.csv

Each point is a full simulation (physics.sweep). The CSV grows as points finish; running the same
command again skips the points already in it. With one varied parameter a curve, with two a heat map,
is drawn to the PNG next to the CSV (matplotlib, optional). ``--dask ADDRESS`` runs on an existing
dask.distributed scheduler, ``--dask local`` on a LocalCluster; the default is local worker processes.

``python -m bench sweep --scaling`` measures wall time against the number of workers and the
overhead per point on this machine (bench/results/sweep_scaling.csv and .meta.json, docs/sweeps.md).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

import physics
from app.argv import numbers_as_values
from physics.scenario import arguments

from .cli import bounded
from .machine import machine

ROOT = Path(__file__).resolve().parent.parent
REPEATS = 3  # the scaling study keeps the fastest of this many runs of each configuration
BAR_WIDTH = 30  # characters of the progress bar
LOG_COLOURS = 20.0  # a heat map of positive values spanning more than this ratio gets a logarithmic colour scale


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, status 2, like every other bad input
        self.exit(2, f"error: {message} (see 'python -m bench sweep --help')\n")


def _parser() -> argparse.ArgumentParser:
    ap = numbers_as_values(_Parser(prog="python -m bench sweep", description=__doc__.split("\n\n")[0],
                 formatter_class=argparse.RawDescriptionHelpFormatter,
                 epilog="SPEC: LO:HI:N (linear), log:LO:HI:N (geometric), or V1,V2,... . KEY: a dotted scenario "
                        "key (pendulum.k) or a short name unique in the scenario (k). Metrics: "
                        + ", ".join(f"{m.name} ({m.unit})" for m in physics.METRICS.values())))
    ap.add_argument("scenario", nargs="?", help="scenario TOML file")
    ap.add_argument("--vary", action="append", default=[], metavar="KEY=SPEC", help="a parameter and its values")
    ap.add_argument("--metric", action="append", default=[], metavar="NAME",
                    help="what to measure (repeat or comma-separate; the first is charted; default decay_time)")
    ap.add_argument("--out", default="sweep.csv", help="CSV to write or resume (default sweep.csv); the chart "
                    "goes next to it with the suffix .png")
    ap.add_argument("--workers", type=bounded(int, 1, arguments.MAX_WORKERS),
                    help="local worker processes, or LocalCluster workers (default: all cores)")
    ap.add_argument("--dask", metavar="ADDRESS", help='an existing dask.distributed scheduler (tcp://host:8786), '
                    'or "local" for a LocalCluster')
    ap.add_argument("--fidelity", choices=("auto", "full", "averaged", "closed"), help="override [run] fidelity")
    ap.add_argument("--no-chart", action="store_true", help="write the CSV only")
    ap.add_argument("--scaling", action="store_true", help="measure wall time against workers (no scenario needed)")
    ap.add_argument("--quick", action="store_true", help="with --scaling: fewer points (CI)")
    return ap


class ProgressBar:
    """``done/total`` as a bar on stderr: redrawn in place on a terminal, a line every 10% in a log."""

    def __init__(self, skipped: int = 0, stream=None):
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.start = time.perf_counter()
        self.skipped = skipped
        self.last = -1.0
        self.open = False  # a bar drawn in place and not yet ended by a newline

    def close(self) -> None:
        """End a bar left open (before an error message)."""
        if self.open:
            print(file=self.stream, flush=True)
            self.open = False

    def __call__(self, done: int, total: int) -> None:
        if total == 0:
            return  # every point was in the CSV already
        frac = done / total if total else 1.0
        elapsed = time.perf_counter() - self.start
        eta = elapsed / done * (total - done) if done else math.nan
        fill = int(round(BAR_WIDTH * frac))
        text = (f"sweep [{'#' * fill}{'.' * (BAR_WIDTH - fill)}] {done}/{total} points, {elapsed:.1f} s"
                + (f", {eta:.0f} s left" if done and done < total else ""))
        if self.tty:
            print("\r" + text, end="\n" if done >= total else "", file=self.stream, flush=True)
            self.open = done < total
        elif frac - self.last >= 0.1 or done >= total:
            self.last = frac
            print(text, file=self.stream, flush=True)


def parse_vary(items: list[str]) -> dict[str, str]:
    """["k=10:100:20", ...] -> {"k": "10:100:20", ...}; raises ScenarioError on a malformed item."""
    vary: dict[str, str] = {}
    for item in items:
        name, eq, spec = item.partition("=")
        if not eq or not name.strip() or not spec.strip():
            raise physics.ScenarioError("--vary", item, "must be KEY=SPEC, e.g. k=10:100:20 or c_d=log:1:20:20")
        if name.strip() in vary:
            raise physics.ScenarioError("--vary", item, f"gives {name.strip()} twice")
        vary[name.strip()] = spec.strip()
    return vary


# ---- charts ------------------------------------------------------------------------------------------

def chart(table: physics.SweepTable, path: Path, metric: str | None = None) -> Path | None:
    """A curve (one varied key) or a heat map (two) of ``metric`` to ``path``; None for more keys.
    Raises ImportError when matplotlib is absent."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    metric = metric or table.metric
    unit = physics.METRICS[metric].unit
    if len(table.keys) not in (1, 2):
        return None
    fig, ax = plt.subplots(figsize=(6.4, 4.8))
    z = table.grid(metric)
    if len(table.keys) == 1:
        ax.plot(table.axes[0], z, "o-")
        ax.set_xlabel(table.keys[0])
        ax.set_ylabel(f"{metric} ({unit})")
        if table.spacing[0] == "log":
            ax.set_xscale("log")
    else:
        x, y = np.asarray(table.axes[1]), np.asarray(table.axes[0])
        masked = np.ma.masked_invalid(z)
        finite = z[np.isfinite(z)]
        norm = None
        if finite.size and finite.min() > 0 and finite.max() > LOG_COLOURS * finite.min():
            from matplotlib.colors import LogNorm

            norm = LogNorm(finite.min(), finite.max())
        mesh = ax.pcolormesh(_edges(x, table.spacing[1] == "log"), _edges(y, table.spacing[0] == "log"), masked,
                             cmap="viridis", norm=norm)
        if finite.size:
            i, j = np.unravel_index(int(np.argmin(np.where(np.isfinite(z), z, np.inf))), z.shape)
            ax.plot(x[j], y[i], "w*", markersize=12, markeredgecolor="k", label=f"min {z[i, j]:.4g}")
            ax.legend(loc="upper right", fontsize=8)
        fig.colorbar(mesh, ax=ax, label=f"{metric} ({unit})")
        ax.set_xlabel(table.keys[1])
        ax.set_ylabel(table.keys[0])
        for axis, how in ((ax.set_xscale, table.spacing[1]), (ax.set_yscale, table.spacing[0])):
            if how == "log":
                axis("log")
    ax.set_title(f"{metric} over {len(table.rows)} runs")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _edges(centres: np.ndarray, log: bool) -> np.ndarray:
    """Cell edges around the grid values: midpoints (geometric on a log axis), the ends mirrored."""
    c = np.log(centres) if log else np.asarray(centres, float)
    if len(c) == 1:
        e = np.array([c[0] - 0.5, c[0] + 0.5]) if not log else np.array([c[0] - 0.1, c[0] + 0.1])
    else:
        mid = 0.5 * (c[1:] + c[:-1])
        e = np.concatenate([[2 * c[0] - mid[0]], mid, [2 * c[-1] - mid[-1]]])
    return np.exp(e) if log else e


def _summary(table: physics.SweepTable) -> list[str]:
    lines = []
    for m in table.metrics:
        v = table.column(m)
        ok = np.isfinite(v)
        if not ok.any():
            lines.append(f"{m}: no finite value")
            continue
        lo, hi = int(np.argmin(np.where(ok, v, np.inf))), int(np.argmax(np.where(ok, v, -np.inf)))
        where = [", ".join(f"{k} = {table.rows[i][k]:.6g}" for k in table.keys) for i in (lo, hi)]
        lines.append(f"{m} ({physics.METRICS[m].unit}): min {v[lo]:.6g} at {where[0]}; max {v[hi]:.6g} at {where[1]}")
    errors = [r["error"] for r in table.rows if r["error"]]
    if errors:
        lines.append(f"{len(errors)} point(s) failed, e.g. {errors[0]}")
    return lines


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.scaling:
        return scaling(args.quick, ROOT / "bench" / "results")
    if not args.scenario:
        print("error: scenario = (missing): give a scenario TOML file (see 'python -m bench sweep --help')",
              file=sys.stderr)
        return 2
    metrics = [m.strip() for item in (args.metric or ["decay_time"]) for m in item.split(",") if m.strip()]
    out = Path(args.out)
    bar = ProgressBar()
    try:
        sc = physics.Scenario.load(args.scenario)
        if args.fidelity:
            sc = sc.with_values(**{"run.fidelity": args.fidelity})
        vary = parse_vary(args.vary)
        if not vary:
            raise physics.ScenarioError("--vary", "(missing)", "give at least one KEY=SPEC, e.g. --vary k=10:100:20")
        workers = arguments.workers(args.workers, "--workers")
        if args.dask and args.dask != "local":
            try:
                import distributed  # noqa: F401
            except ImportError:
                raise physics.ScenarioError("--dask", args.dask, "needs dask.distributed: pip install "
                                            "'dask[distributed]'") from None
        print(f"scenario: {args.scenario}; executor: "
              + (f"dask {args.dask}" if args.dask else f"{workers} local worker process(es)"),
              flush=True)
        table = physics.sweep(sc, vary, metrics, out=out, workers=workers, dask=args.dask, progress=bar)
    except physics.ScenarioError as exc:
        bar.close()
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        bar.close()
        print(f"interrupted: the points finished so far are in {out}; run the same command again to resume",
              file=sys.stderr)
        return 130
    except OSError as exc:  # e.g. a dask scheduler that does not answer
        bar.close()
        print(f"error: --dask = {args.dask!r}: {exc}", file=sys.stderr)
        return 2
    print(f"wrote {out}: {len(table.rows)} points ({table.computed} computed now, {table.skipped} already there) "
          f"in {table.wall_s:.3g} s")
    for line in _summary(table):
        print(line)
    if not args.no_chart and len(table.keys) <= 2:
        png = out.with_suffix(".png")
        try:
            chart(table, png)
            print(f"chart: {png}")
        except ImportError:
            print("note: matplotlib is not installed, so no chart was drawn (pip install matplotlib)", file=sys.stderr)
    return 0


# ---- scaling study -----------------------------------------------------------------------------------

def _cpu() -> float:
    """CPU seconds of this process and of its finished children (pool workers, cluster processes)."""
    t = os.times()
    return t.user + t.system + t.children_user + t.children_system


def _workload(name: str) -> tuple[physics.Scenario, dict]:
    """light: the resonant pendulum over 20 s (milliseconds a point); heavy: the flat spin over 600 s."""
    if name == "light":
        sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml")
        return sc.with_values(**{"run.t_end": 20.0, "run.samples": 401}), {"pendulum.c_d": "log:2:20:{n}"}
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "prolate_flat_spin.toml")
    return sc.with_values(**{"run.t_end": 600.0, "run.samples": 601}), {"mass.chi": "3:9:{n}"}


def scaling(quick: bool, out: Path) -> int:
    """Wall time of the same sweep in this process (warm), on 1 and 2 local worker processes (fork, the
    default of a script; forkserver, the explorer's) and on a dask LocalCluster of 1 and 2 workers, each
    at two sizes N1 < N2, so that wall = start-up + N * per-point separates the start-up (pool or cluster,
    loading the compiled code in each worker) from the cost of a point."""
    sizes = {"light": (4, 12), "heavy": (4, 8)} if quick else {"light": (8, 40), "heavy": (8, 24)}
    configs = [("serial", None, 1), ("fork", None, 1), ("fork", None, 2), ("forkserver", None, 1),
               ("forkserver", None, 2), ("dask-local", "local", 1), ("dask-local", "local", 2)]
    rows, load = [], os.getloadavg()
    work = {name: _workload(name) for name in ("light", "heavy")}
    point_s = {}  # the cost of one point in a warm process: what every executor has to pay at least
    for name, (sc, vary_t) in work.items():
        physics.sweep(sc, {k: v.format(n=2) for k, v in vary_t.items()}, "theta_end", executor="serial")  # warm
        n = sizes[name][1]
        runs = []
        for _ in range(REPEATS):
            before = _cpu()
            physics.sweep(sc, {k: v.format(n=n) for k, v in vary_t.items()}, "theta_end", executor="serial")
            runs.append((_cpu() - before) / n)
        point_s[name] = min(runs)  # CPU s: unlike wall time, hardly touched by the machine's other users
    for label, dask, w in configs:  # fork first: once a LocalCluster has run, this process has threads
        for name, (sc, vary_t) in work.items():
            walls, cpus = [], []
            for n in sizes[name]:
                vary = {k: v.format(n=n) for k, v in vary_t.items()}
                runs = []
                for _ in range(REPEATS):
                    before = _cpu()
                    wall = physics.sweep(sc, vary, "theta_end", workers=w, dask=dask,
                                         executor="serial" if label == "serial" else "processes",
                                         start_method=label if label in ("fork", "forkserver") else None).wall_s
                    runs.append((wall, _cpu() - before))
                wall, cpu = min(runs)  # the run least disturbed by the other users of the machine
                walls.append(wall), cpus.append(cpu)
                print(f"{name:5s} {label:10s} workers={w} N={n:3d}: wall {wall:7.3f} s, cpu {cpu:7.3f} s",
                      file=sys.stderr, flush=True)
            n1, n2 = sizes[name]
            per_point = (walls[1] - walls[0]) / (n2 - n1)  # wall s per extra point
            if label == "forkserver":  # its workers are the fork server's children: os.times() cannot see them
                cpus = [math.nan, math.nan]
            cpu_point = (cpus[1] - cpus[0]) / (n2 - n1)  # CPU s (all processes) per extra point
            c = point_s[name]
            rows.append(dict(workload=name, executor=label, workers=w, n1=n1, wall1_s=walls[0], n2=n2,
                             wall2_s=walls[1], per_point_wall_s=per_point, startup_s=walls[0] - n1 * per_point,
                             compute_per_point_s=c, overhead_per_point_s=per_point * w - c, cpu1_s=cpus[0],
                             cpu2_s=cpus[1], cpu_startup_s=cpus[0] - n1 * cpu_point,
                             cpu_overhead_per_point_s=cpu_point - c))
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "sweep_scaling.csv", "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: f"{v:.4g}" if isinstance(v, float) else v for k, v in r.items()})
    meta = dict(command="python -m bench sweep --scaling" + (" --quick" if quick else ""),
                date=datetime.now(UTC).isoformat(timespec="seconds"), machine=machine(),
                load_average_before=load, load_average_after=os.getloadavg(),
                workloads={"light": "pendulum_resonant.toml, t_end 20 s, 401 samples, vary pendulum.c_d",
                           "heavy": "prolate_flat_spin.toml, t_end 600 s, 601 samples (full model), vary mass.chi"})
    (out / "sweep_scaling.meta.json").write_text(json.dumps(meta, indent=2) + "\n")
    for r in rows:
        print(f"{r['workload']:5s} {r['executor']:10s} w={r['workers']}: wall {r['wall2_s']:.3f} s for {r['n2']} "
              f"points; start-up {r['startup_s']:.3f} s; {r['per_point_wall_s'] * 1e3:.1f} ms wall per point; "
              f"compute {r['compute_per_point_s'] * 1e3:.1f} ms; overhead {r['overhead_per_point_s'] * 1e3:.1f} ms; "
              f"CPU: start-up {r['cpu_startup_s']:.3f} s, overhead {r['cpu_overhead_per_point_s'] * 1e3:.1f} ms/point")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
