"""``python -m bench design``: a damper's design against the grid an engineer would sweep instead (issue 26).

On one scene (default: assets/scenarios/pendulum_resonant.toml, the spring k and the pivot damper c_d) it runs, in
one process and one after the other, an N x N grid of full runs (physics.sweep) and physics.design over the same
bounds, both on the same workers, and records each one's runs, wall time and best decay time, with the machine and
the load average before and after each. Both run once untimed first (the compiled code loaded, the worker pool's
start paid by neither). Writes bench/results/design.csv (+ .meta.json) and docs/img/design.png: the grid's heat
map with the design's path over it, and the best value against runs made.
"""

from __future__ import annotations

import csv
import json
import math
import os
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

import physics
from bench.cli import bounded, study_parser
from bench.machine import machine
from physics.scenario.arguments import MAX_WORKERS

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "assets" / "scenarios" / "pendulum_resonant.toml"
VARY = {"pendulum.k": (20.0, 80.0), "pendulum.c_d": (1.0, 40.0)}


def _grid_specs(n: int) -> dict[str, str]:
    (k_lo, k_hi), (c_lo, c_hi) = VARY.values()
    return {"pendulum.k": f"{k_lo}:{k_hi}:{n}", "pendulum.c_d": f"log:{c_lo}:{c_hi}:{n}"}


def _best_positive(values: np.ndarray) -> tuple[int, float]:
    v = np.where(values > 0, values, np.inf)
    i = int(np.argmin(v))
    return i, float(v[i])


def run(n: int, workers: int, out: Path, img: Path) -> dict:
    sc = physics.Scenario.load(SCENE)
    full = sc.with_values(**{"run.fidelity": "full"})
    # untimed: both paths once, so neither pays for loading the compiled code or a first fork
    physics.sweep(full, _grid_specs(3), "decay_time", workers=workers)
    physics.design(sc, VARY, "decay_time", workers=workers, budget=40, references=False)

    load_before_grid = os.getloadavg()
    t0 = time.perf_counter()
    table = physics.sweep(full, _grid_specs(n), "decay_time", workers=workers)
    grid_s = time.perf_counter() - t0
    load_after_grid = os.getloadavg()
    t0 = time.perf_counter()
    result = physics.design(sc, VARY, "decay_time", workers=workers, references=False)
    design_s = time.perf_counter() - t0
    load_after_design = os.getloadavg()

    i, grid_best = _best_positive(table.column("decay_time"))
    rows = [
        {"method": f"grid {n}x{n}", "runs": len(table.rows), "wall_s": grid_s, "decay_time_s": grid_best,
         "pendulum.k": table.rows[i]["pendulum.k"], "pendulum.c_d": table.rows[i]["pendulum.c_d"],
         "load_before": load_before_grid[0], "load_after": load_after_grid[0]},
        {"method": "design", "runs": result.evaluations, "wall_s": design_s, "decay_time_s": result.value,
         "pendulum.k": result.best["pendulum.k"], "pendulum.c_d": result.best["pendulum.c_d"],
         "load_before": load_after_grid[0], "load_after": load_after_design[0]},
    ]
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    meta = {"command": f"python -m bench design --n {n} --workers {workers}", "scene": str(SCENE.relative_to(ROOT)),
            "vary": {k: list(v) for k, v in VARY.items()}, "objective": "decay_time",
            "design_over_grid_wall": design_s / grid_s, "design_method": result.method,
            "date": datetime.now(UTC).isoformat(timespec="seconds"), "machine": machine()}
    out.with_suffix(".meta.json").write_text(json.dumps(meta, indent=1) + "\n")
    _chart(table, result, rows, img)
    return {"rows": rows, "meta": meta}


def _chart(table, result, rows, img: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.6))
    k, c = np.array(table.axes[0]), np.array(table.axes[1])
    g = table.grid("decay_time")
    g = np.where(g > 0, g, np.nan)
    mesh = ax.pcolormesh(c, k, np.log10(g), shading="nearest", cmap="viridis_r")
    fig.colorbar(mesh, ax=ax, label="log10 decay time (s)")
    path_k, path_c = result.column("pendulum.k"), result.column("pendulum.c_d")
    ax.plot(path_c, path_k, ".", color="white", ms=4, mec="black", mew=0.3, label="design's runs")
    ax.plot([rows[0]["pendulum.c_d"]], [rows[0]["pendulum.k"]], "s", mfc="none", mec="red", ms=10,
            label=f"grid's best {rows[0]['decay_time_s']:.4g} s")
    ax.plot([result.best["pendulum.c_d"]], [result.best["pendulum.k"]], "*", color="orange", mec="black", ms=14,
            label=f"design's optimum {result.value:.4g} s")
    ax.set_xscale("log")
    ax.set_xlabel("pendulum.c_d (N m s/rad)")
    ax.set_ylabel("pendulum.k (N m/rad)")
    ax.legend(fontsize=8, loc="upper right")
    ax.set_title("pendulum_resonant: decay time over the grid", fontsize=10)
    objective = result.column("objective")
    best_so_far = np.minimum.accumulate(np.where(objective > 0, objective, np.inf))
    bx.plot(np.arange(1, len(best_so_far) + 1), best_so_far, label=f"design ({rows[1]['wall_s']:.2f} s)")
    bx.axhline(rows[0]["decay_time_s"], color="red", ls="--",
               label=f"{rows[0]['method']}: {rows[0]['runs']} runs ({rows[0]['wall_s']:.2f} s)")
    bx.set_yscale("log")
    bx.set_xlabel("runs made")
    bx.set_ylabel("best decay time so far (s)")
    ratio = rows[1]["wall_s"] / rows[0]["wall_s"]
    bx.set_title(f"design in {ratio:.2f} of the grid's wall time (one run, same workers)", fontsize=10)
    bx.legend(fontsize=8)
    fig.suptitle("python -m bench design: bench/results/design.csv", fontsize=9)
    fig.tight_layout()
    img.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(img, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("design", __doc__)
    ap.add_argument("--n", type=bounded(int, 2, 100), default=20, help="grid points per key (default 20: 400 runs)")
    ap.add_argument("--workers", type=bounded(int, 1, MAX_WORKERS), default=2,
                    help="local processes for both (default 2)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "design.csv")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img" / "design.png")
    args = ap.parse_args(argv)
    res = run(args.n, args.workers, args.out, args.img)
    for r in res["rows"]:
        print(f"{r['method']:>10}: {r['runs']:4d} runs, {r['wall_s']:6.2f} s, best decay time "
              f"{r['decay_time_s']:.6g} s at k = {r['pendulum.k']:.5g}, c_d = {r['pendulum.c_d']:.5g} "
              f"(load {r['load_before']:.2f} -> {r['load_after']:.2f})")
    print(f"design / grid wall time: {res['meta']['design_over_grid_wall']:.3f}")
    print(f"wrote {args.out}, {args.out.with_suffix('.meta.json')} and {args.img}")
    return 0 if math.isfinite(res["rows"][1]["decay_time_s"]) else 1
