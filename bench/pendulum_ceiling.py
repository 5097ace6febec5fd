"""``python -m bench pendulum-ceiling``: how much of the oracle's cheap runs could auto take with the spherical
pendulum's estimate as it is built, whatever its safety factors? A measurement for issue 23's open point, not a
model of the product.

The estimate here is the bracket (physics/systems/pendulum/accuracy.py ``Parts.bracket``, the whole estimate until
issue 23's prediction): SAFETY_LINEAR (linear_gap + polhode_gap) + SAFETY max(detuning_gap, rate_gap); the
``estimate`` column is it, and "the product's" below means it. Here its parts are computed for every
spherical-pendulum row with an actual error in the fidelity studies' CSVs (the averaged model's error against the
full model, already measured there), and the two nonlinear parts are given their own factors, s_d and s_r, each
from 1 to 2.5: the pair that lets auto take the most cheap runs while no row's actual error exceeds its estimate is
the ceiling of this form of estimate, fitted with no margin on the very rows it is scored on.
If the ceiling is below issue 23's 80 %, no choice of factors
meets it: the parts themselves must come nearer the actual error (or the model nearer the full one).

One other form is measured beside it, the first candidate for such a part: ``hardening`` = how far the averaged
theta moves when sigma follows the bob's own swing, self-consistently, either way (sigma + or - SWING_SHIFT omega_0
|Ut|^2: bench/pendulum_hardening.py's model), in place of the detuning gap's fixed shift. The summary's
``hardening_form`` gives, for each factor S, the violations and shares of SAFETY_LINEAR (linear_gap +
polhode_gap) + S max(hardening, rate_gap).

A second candidate follows both amplitude effects: ``following`` = how far the averaged theta moves when sigma
follows the swing and the spin-up together (sigma + s_w SWING_SHIFT omega_0 |Ut|^2 - s_s (C/A) W (theta0^2 -
theta^2)/2, the largest over the four signs s_w, s_s = +-1), and the resonance is kept as the product reads it
(``resonance``: the detuning gap's part at sigma = 0, where the swing can reach it). The summary's
``following_form`` gives, for each factor S from 1 to 4, the violations and shares of SAFETY_LINEAR (linear_gap +
polhode_gap) + S max(following, rate_gap, resonance).

Writes bench/results/pendulum_ceiling.csv (+ .meta.json: machine, command, summary) and
docs/img/pendulum_ceiling.png (the share auto takes against one common factor, and the best pair).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys
import time
import warnings
from collections.abc import Iterable
from pathlib import Path

import numpy as np

import physics
from bench.cli import study_parser
from bench.pendulum_hardening import detuned_theta
from bench.results_file import write_results
from physics.systems.pendulum.accuracy import SAFETY, SAFETY_LINEAR, scenario_parts

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "bench" / "results"
ACCURACIES = (1e-2, 1e-3)
FACTORS = np.round(np.arange(1.0, 2.5001, 0.05), 2)
FOLLOWING_FACTORS = np.round(np.arange(1.0, 4.0001, 0.1), 2)
COLUMNS = ("study", "index", "actual", "linear", "detuning", "rate", "estimate", "hardening", "following", "resonance")
HARDENING_POINTS = 4001  # grid of the hardening form's theta over [0, t_end]


def study_rows(paths: list[Path]) -> list[dict]:
    """The averaged spherical-pendulum rows with a measured error, each scenario once."""
    seen, rows = set(), []
    for path in paths:
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                if (r.get("system") != "spherical_pendulum" or r.get("fidelity") != "averaged"
                        or r.get("status") != "ok" or not r.get("actual_error") or r["scenario"] in seen):
                    continue
                seen.add(r["scenario"])
                rows.append(dict(study=path.name, index=r["index"], actual=float(r["actual_error"]),
                                 scenario=r["scenario"]))
    return rows


def measure(row: dict) -> dict | None:
    """The row with its estimate's parts; None where the estimate has none (outside its conditions' reach)."""
    sc = physics.Scenario.from_dict(json.loads(row["scenario"]))
    q = scenario_parts(sc)
    parts = (q.linear_gap + q.polhode_gap, q.detuning_gap, q.rate_gap)
    if not all(map(math.isfinite, parts)):
        return None
    return dict(study=row["study"], index=row["index"], actual=row["actual"], linear=parts[0], detuning=parts[1],
                rate=parts[2], estimate=q.bracket, hardening=hardening_gap(sc), following=following_gap(sc),
                resonance=q.resonance_gap)


def hardening_gap(sc) -> float:
    """max |theta - theta_averaged| over [0, t_end] (rad) with sigma following the bob's swing either way
    (module docstring); the same integrator for both, so the difference is the detuning's alone."""
    t = np.linspace(0.0, float(sc.run.t_end), HARDENING_POINTS)
    with np.errstate(all="ignore"):
        base = detuned_theta(sc, t, 0.0, 0.0)
        gap = max(float(np.max(np.abs(detuned_theta(sc, t, 0.0, sign) - base))) for sign in (1.0, -1.0))
    return gap if math.isfinite(gap) else math.inf


def following_gap(sc) -> float:
    """max |theta - theta_averaged| over [0, t_end] (rad) with sigma following both the swing and the spin-up, the
    largest over their four pairs of signs (module docstring)."""
    t = np.linspace(0.0, float(sc.run.t_end), HARDENING_POINTS)
    with np.errstate(all="ignore"):
        base = detuned_theta(sc, t, 0.0, 0.0)
        gap = max(float(np.max(np.abs(detuned_theta(sc, t, spin, swing) - base)))
                  for spin in (1.0, -1.0) for swing in (1.0, -1.0))
    return gap if math.isfinite(gap) else math.inf


def add_study_options(ap: argparse.ArgumentParser) -> None:
    """--study, --out and --img, as the pendulum studies over the fidelity studies' rows take them."""
    ap.add_argument("--study", type=Path, nargs="*", default=None,
                    help="fidelity studies' CSVs (default: every bench/results/fidelity*.csv)")
    ap.add_argument("--out", type=Path, default=RESULTS)
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img")


def picked_rows(ap: argparse.ArgumentParser, study: list[Path] | None) -> tuple[list[Path], list[dict]]:
    """The studies' paths (default: every bench/results/fidelity*.csv) and their rows (``study_rows``); a path
    that is no file, or no row at all, is the parser's error."""
    paths = study if study else sorted(RESULTS.glob("fidelity*.csv"))
    missing = [str(p) for p in paths if not p.is_file()]
    if missing:
        ap.error(f"--study {' '.join(missing)}: no such file (a CSV written by python -m bench fidelity)")
    picked = study_rows(paths)
    if not picked:
        ap.error("no averaged spherical-pendulum row with a measured error in " + ", ".join(map(str, paths)))
    return paths, picked


def measured(results: Iterable[dict | None], total: int) -> list[dict]:
    """The rows of a study's ``results`` (None where a scenario gives none), counted on stderr as they come."""
    rows = []
    for n, m in enumerate(results, 1):
        if m is not None:
            rows.append(m)
        print(f"\r{n}/{total} scenarios", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    return rows


def write_study(args: argparse.Namespace, argv: list[str] | None, stem: str, columns, rows: list[dict],
                paths: list[Path], t0: float, result: dict) -> None:
    """``stem``.csv and .meta.json (command, studies, wall time, summary) in --out, and --img made for the chart."""
    command = f"python -m bench {stem.replace('_', '-')}"
    write_results(args.out, stem, columns, rows, command=" ".join([command, *(sys.argv[1:] if argv is None else argv)]),
                  studies=[p.name for p in paths], wall_s=time.perf_counter() - t0, summary=result)
    args.img.mkdir(parents=True, exist_ok=True)


def shares(actual: np.ndarray, estimate: np.ndarray) -> dict:
    """Per accuracy: the oracle's cheap runs (actual <= accuracy), auto's among them, and auto's share."""
    out = {}
    for acc in ACCURACIES:
        oracle = actual <= acc
        auto = oracle & (estimate <= acc)
        out[f"{acc:g}"] = dict(oracle=int(oracle.sum()), auto=int(auto.sum()),
                               share=float(auto.sum() / oracle.sum()) if oracle.any() else math.nan)
    return out


def summary(rows: list[dict]) -> dict:
    actual = np.array([r["actual"] for r in rows])
    lin = SAFETY_LINEAR * np.array([r["linear"] for r in rows])
    det, rate = np.array([r["detuning"] for r in rows]), np.array([r["rate"] for r in rows])
    product = np.array([r["estimate"] for r in rows])

    def fitted(sd: float, sr: float) -> np.ndarray:
        return lin + np.maximum(sd * det, sr * rate)

    best = None
    for sd in FACTORS:
        for sr in FACTORS:
            est = fitted(sd, sr)
            if np.any(actual > est):
                continue
            s = shares(actual, est)
            total = sum(v["share"] for v in s.values())
            if best is None or total > best[0]:
                best = (total, float(sd), float(sr), s, float(np.max(actual / est)))
    common = []
    for f in FACTORS:
        est = fitted(f, f)
        common.append(dict(factor=float(f), violations=int(np.sum(actual > est)), **{
            f"share_{k}": v["share"] for k, v in shares(actual, est).items()}))
    hard = np.array([r["hardening"] for r in rows])
    hardening_form = []
    for f in FACTORS:
        est = lin + f * np.maximum(hard, rate)
        hardening_form.append(dict(factor=float(f), violations=int(np.sum(actual > est)),
                                   worst=float(np.max(actual / est)),
                                   **{f"share_{k}": v["share"] for k, v in shares(actual, est).items()}))
    follow = np.maximum.reduce([np.array([r["following"] for r in rows]), rate,
                                np.array([r["resonance"] for r in rows])])
    following_form = []
    for f in FOLLOWING_FACTORS:
        est = lin + f * follow
        following_form.append(dict(factor=float(f), violations=int(np.sum(actual > est)),
                                   worst=float(np.max(actual / est)),
                                   **{f"share_{k}": v["share"] for k, v in shares(actual, est).items()}))
    out = dict(scenarios=len(rows), product=dict(factor=SAFETY, violations=int(np.sum(actual > product)),
                                                   worst=float(np.max(actual / product)), **shares(actual, product)),
               common=common, hardening_form=hardening_form, following_form=following_form)
    if best is not None:
        out["ceiling"] = dict(s_detuning=best[1], s_rate=best[2], worst=best[4], **best[3])
    return out


def form_line(name: str, form: list[dict]) -> str:
    """The least factor of a candidate form with no violation and what it takes; or, where every factor leaves
    some, how many at the largest tried."""
    clean = [x for x in form if x["violations"] == 0]
    shown = clean[0] if clean else form[-1]
    taken = ", ".join(f"{a:g} rad {shown[f'share_{a:g}']:.0%}" for a in ACCURACIES)
    if clean:
        return f"{name} form: factor {shown['factor']:g} is the least with no violation: {taken}"
    return (f"{name} form: every factor from {form[0]['factor']:g} to {shown['factor']:g} leaves rows above their "
            f"estimate ({shown['violations']} at {shown['factor']:g}, worst actual/estimate {shown['worst']:.2f}; "
            f"there it takes {taken})")


def chart(result: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    f = [c["factor"] for c in result["common"]]
    for acc, style in zip(ACCURACIES, ("-", "--"), strict=True):
        key = f"share_{acc:g}"
        ax.plot(f, [c[key] for c in result["common"]], style, color="C0", label=f"one factor on both, {acc:g} rad")
        for name, color in (("hardening", "C2"), ("following", "C4")):
            form = result[f"{name}_form"]
            bound = any(c["violations"] == 0 for c in form)
            ax.plot([c["factor"] for c in form], [c[key] for c in form], style, color=color, lw=0.9,
                    label=f"{name} form{'' if bound else ' (never a bound here)'}, {acc:g} rad")
        if "ceiling" in result:
            ax.axhline(result["ceiling"][f"{acc:g}"]["share"], color="C1", ls=style, lw=0.9,
                       label=f"best pair with no violation, {acc:g} rad")
    bad = [c["factor"] for c in result["common"] if c["violations"]]
    if bad:
        ax.axvspan(min(f), max(bad), color="0.85", label="one factor: a row's actual error above its estimate")
    ax.axhline(0.8, color="C3", lw=0.8, label="issue 23's goal, 80 %")
    ax.axvline(result["product"]["factor"], color="0.4", lw=0.8, ls=":", label="the product's SAFETY")
    ax.set(xlabel="safety factor on the nonlinear parts", ylabel="auto's share of the oracle's cheap runs",
           ylim=(0, 1), title=f"Spherical pendulum's estimate: its ceiling ({result['scenarios']} scenarios)")
    ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("pendulum-ceiling", __doc__)
    add_study_options(ap)
    args = ap.parse_args(argv)
    paths, picked = picked_rows(ap, args.study)
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        rows = measured(map(measure, picked), len(picked))
    result = summary(rows)
    write_study(args, argv, "pendulum_ceiling", COLUMNS, rows, paths, t0, result)
    chart(result, args.img / "pendulum_ceiling.png")
    p = result["product"]
    print(f"{len(rows)} scenarios with an estimate (of {len(picked)}); the product's (SAFETY {SAFETY:g}): "
          + ", ".join(f"{k} rad {v['auto']}/{v['oracle']} = {v['share']:.0%}" for k, v in p.items()
                      if isinstance(v, dict)) + f", {p['violations']} violations")
    for name in ("hardening", "following"):
        print(form_line(name, result[f"{name}_form"]))
    c = result.get("ceiling")
    if c is None:
        print("no pair of factors from 1 to 2.5 leaves every actual error within its estimate")
    else:
        print(f"ceiling (s_detuning {c['s_detuning']:g}, s_rate {c['s_rate']:g}, worst actual/estimate "
              f"{c['worst']:.2f}): " + ", ".join(f"{k} rad {v['auto']}/{v['oracle']} = {v['share']:.0%}"
                                                  for k, v in c.items() if isinstance(v, dict)))
    return 0
