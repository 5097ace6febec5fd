"""``python -m bench pendulum-prediction``: can the spherical pendulum's nonlinear error be predicted, sign and
size, rather than bracketed? A measurement for issue 23's open point 4, not a model of the product.

``python -m bench pendulum-ceiling`` showed that no factor on today's brackets lets auto take 80 % of the oracle's
cheap pendulum runs: the detuning and rate gaps say how far the averaged theta could move, not which way it does.
Here the full model's departure from exact linear theory is predicted by the averaged equations of B.6 with their
coefficients following the amplitudes, and the prediction is compared with the error the fidelity studies measured.

Three amplitude effects are followed, each in every coefficient (sigma, gamma1, kappa1, kappa2), not in sigma alone:

- the spin-up: K is fixed, so omega_z = K cos(theta)/C rises as the nutation decays; the coefficients take
  W (1 + (theta0^2 - theta^2)/2). At resonance sigma moves only at second order, but gamma1 = ct lambda1/(2
  omega_0) with lambda1 = omega_0 - W moves at first order by -dW/lambda1, large where lambda1 << W;
- the pivot's hardening: the bob's mode-1 frequency rises by SWING_SHIFT omega_0 a^2 with its swing a = |Ut|
  (physics/systems/pendulum/accuracy.py), taken as k (1 + SWING_SHIFT a^2)^2;
- the arm: a bob swinging at a sits l (1 - cos a) nearer its pivot along the axis, so the coupling's lever D (the
  bob's rest height over the system's centre of mass, along e3) becomes D - l (1 - cos a). The linear coupling is
  proportional to D, its change to l a^2/2: a relative change of (l/D) a^2/2, large for a bob hung near the
  centre of mass (|D| << l).

The predicted full theta is theta_linear + (theta_following - theta_fixed) (the same integrator, coefficients
following or fixed), read in the K-fixed mapping sin(theta) = |H_perp|/K where the averaged model and linear theory
use tan(theta) = |H_perp|/(C W); the predicted error is its largest distance from the product's averaged theta over
[0, t_end]. ``sigma_only`` is the same with sigma alone following the spin-up and the swing
(bench/pendulum_hardening.py's model); ``no_arm`` follows every coefficient but leaves D fixed. ``spread`` is how
far the prediction moves when the hardening is taken 30 % weaker or stronger.

The summary gives, for each prediction, the distribution of actual / predicted and, for an estimate S x
prediction, the violations (actual above it) and auto's share of the oracle's cheap runs at 1e-2 and 1e-3 rad;
and the best estimate of the form S_p prediction + S_n max(detuning_gap, rate_gap) + S_s spread with no violation,
fitted with no margin on these rows (the frontier the bracket parts still impose).

Two more views ask what point 4 needs of any prediction. The ``ceiling`` is, for a precision S, the share of the
oracle's cheap runs whose actual error is at most accuracy / S: what an estimate that is never below the actual
error and at most S times it could take, however it is obtained. The ``envelope`` decision takes a cheap run where
the product's estimate allows it or where S times the envelope (the largest of the three predictions, plus the
spread) is within the accuracy, and counts its shares and the cheap runs whose actual error exceeds the accuracy:
a decision rule that is not a bound, the best use of these predictions short of one.

``branches`` counts the bob's steady swings at the start: the following equations' forced response, x ((sigma +
SWING_SHIFT omega_0 x)^2 + gamma1^2) = |kappa2 Phihat_0|^2 in x = a^2, has one root or three. With three, the
hardening bob can settle on its upper branch, which the following equations, started at rest, do not reach.

The product's own prediction since (issue 23), the full equations averaged numerically
(physics/systems/pendulum/normal_form.py), is the ``normal_form`` column (accuracy.py's ``predicted_gap``, inf where
it does not apply) beside the ``bracket``; the ``estimate`` column is the product's, the smaller of the two where
the bob has one steady swing. The summary's ``normal_form`` gives actual / predicted over those rows, and the shares
the bracket alone would take.

Writes bench/results/pendulum_prediction.csv (+ .meta.json: machine, command, summary) and
docs/img/pendulum_prediction.png (actual error against the prediction and against the product's estimate).
"""

from __future__ import annotations

import itertools
import json
import math
import time
import warnings
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

import physics
from bench.cli import bounded, study_parser
from bench.pendulum_ceiling import ACCURACIES, add_study_options, measured, picked_rows, shares, write_study
from bench.pendulum_hardening import averaged_run, detuned_theta
from physics.scenario.arguments import MAX_WORKERS
from physics.scenario.initial import initial_G
from physics.systems.pendulum.accuracy import SAFETY_PREDICTED, SWING_SHIFT, scenario_parts
from physics.systems.pendulum.accuracy import steady_branches as accuracy_branches  # the bench's own takes sc
from physics.systems.pendulum.averaged import AveragedCoefficients, averaged_theta
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.pendulum.linear import linear_nutation, spherical_linear

POINTS = 4001  # grid over [0, t_end]: the studies' runs last at most a few e-folding times of the slow mode
PREDICTIONS = ("sigma_only", "no_arm", "prediction")
HARDENING_SPREAD = 0.3  # the hardening taken this much weaker and stronger for ``spread``
S_PREDICTION = (1.05, 1.1, 1.2, 1.3, 1.5, 2.0)
S_BRACKET = (0.0, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0)
S_SPREAD = (0.0, 0.5, 1.0, 2.0)
PRECISIONS = (1.1, 1.25, 1.5, 2.0)  # the ceiling's S: an estimate at most this many times the actual error
S_ENVELOPE = (1.0, 1.1, 1.25, 1.5, 2.0)
COLUMNS = ("study", "index", "actual", "estimate", "linear", "detuning", "rate", *PREDICTIONS, "spread",
           "swing", "shift_over_width", "D_over_l", "branches", "bracket", "normal_form")


def following_theta(sc, t: np.ndarray, spin: float, hardening: float, arm: float) -> np.ndarray:
    """theta (tan mapping, as the averaged model reads it) at times t from the averaged equations of B.6 with every
    coefficient computed at W (1 + spin (theta0^2 - theta^2)/2), k (1 + hardening SWING_SHIFT a^2)^2 and D - arm l
    (1 - cos a), a = |Ut| (module docstring; ``averaged_run``)."""
    p = spherical_linear(pendulum_system(sc))
    w0, _, _ = initial_G(sc)
    rise = hardening * SWING_SHIFT[sc.pendulum.pivot]

    def coefficients(_, U, theta, theta0):
        a = min(abs(U), math.pi)
        c = AveragedCoefficients(replace(p, W=p.W * (1 + spin * (theta0**2 - theta**2) / 2),
                                         k=p.k * (1 + rise * a * a) ** 2, D=p.D - arm * p.l * (1 - math.cos(a))))
        return c.kappa1, c.kappa2, c.sigma, c.gamma1

    return averaged_run(p, AveragedCoefficients(p), w0, t, coefficients)


def steady_branches(sc) -> int:
    """How many steady swings the following equations' bob has at the start (module docstring): 1 or 3; the
    product's own count (physics/systems/pendulum/accuracy.py ``steady_branches``)."""
    p = spherical_linear(pendulum_system(sc))
    w0, _, _ = initial_G(sc)
    return accuracy_branches(p, w0, SWING_SHIFT[sc.pendulum.pivot])


def measure(row: dict) -> dict | None:
    """The row's predictions; None where the product's estimate has none."""
    sc = physics.Scenario.from_dict(json.loads(row["scenario"]))
    q = scenario_parts(sc)
    if not math.isfinite(q.bound):
        return None
    p = spherical_linear(pendulum_system(sc))
    w0, _, _ = initial_G(sc)
    t = np.linspace(0.0, float(sc.run.t_end), POINTS)
    th_lin = linear_nutation(p, (w0[0], w0[1]), t)
    co = AveragedCoefficients(p)
    th_avg, _ = averaged_theta(co, np.array([w0[0] + 1j * w0[1], 0j]), p.W, t)
    c0 = math.cos(float(th_lin[0]))

    def k_fixed(th):  # tan(theta) = |H_perp|/(C W)  ->  sin(theta) = |H_perp|/K, K = C W / cos(theta0)
        return np.arcsin(np.clip(np.tan(th) * c0, -1.0, 1.0))

    with np.errstate(all="ignore"):
        fixed = following_theta(sc, t, 0.0, 0.0, 0.0)
        moved = dict(sigma_only=detuned_theta(sc, t, 1.0, 1.0) - detuned_theta(sc, t, 0.0, 0.0),
                     no_arm=following_theta(sc, t, 1.0, 1.0, 0.0) - fixed,
                     prediction=following_theta(sc, t, 1.0, 1.0, 1.0) - fixed)
        spread = max(float(np.max(np.abs(following_theta(sc, t, 1.0, h, 1.0) - fixed - moved["prediction"])))
                     for h in (1 - HARDENING_SPREAD, 1 + HARDENING_SPREAD))
    out = dict(study=row["study"], index=row["index"], actual=row["actual"], estimate=q.bound,
               linear=q.linear_gap + q.polhode_gap, detuning=q.detuning_gap, rate=q.rate_gap,
               spread=spread if math.isfinite(spread) else math.inf, swing=q.a,
               shift_over_width=q.shift / q.width if q.width > 0 else math.inf, D_over_l=p.D / p.l,
               branches=q.branches, bracket=q.bracket,
               normal_form=q.predicted_gap)
    for name, d in moved.items():
        e = float(np.max(np.abs(k_fixed(th_lin + d) - th_avg)))
        out[name] = e if math.isfinite(e) else math.inf
    return out


def decision(actual: np.ndarray, estimate: np.ndarray, predicted: np.ndarray) -> dict:
    """Per accuracy: cheap where the estimate or the predicted error is within it; the oracle's cheap runs, auto's
    among them, its share, and auto's cheap runs whose actual error exceeds the accuracy."""
    out = {}
    for acc in ACCURACIES:
        taken = (estimate <= acc) | (predicted <= acc)
        oracle = actual <= acc
        out[f"{acc:g}"] = dict(oracle=int(oracle.sum()), auto=int(np.sum(taken & oracle)),
                               share=float(np.sum(taken & oracle) / oracle.sum()) if oracle.any() else math.nan,
                               over_accuracy=int(np.sum(taken & ~oracle)))
    return out


def summary(rows: list[dict]) -> dict:
    col = {k: np.array([r[k] for r in rows], dtype=float) for k in COLUMNS[2:]}
    actual = col["actual"]
    out = dict(scenarios=len(rows), product=dict(violations=int(np.sum(actual > col["estimate"])),
                                                  worst=float(np.max(actual / col["estimate"])),
                                                  **shares(actual, col["estimate"])))
    for name in PREDICTIONS:
        ratio = actual / col[name]
        out[name] = dict(
            ratio_percentiles={str(q): float(np.percentile(ratio, q)) for q in (1, 5, 25, 50, 75, 95, 99, 100)},
            within_10_percent=int(np.sum(np.abs(ratio - 1) <= 0.1)),
            scaled=[dict(S=s, violations=int(np.sum(actual > s * col[name])),
                         **{f"share_{k}": v["share"] for k, v in shares(actual, s * col[name]).items()})
                    for s in S_PREDICTION])
    bracket = np.maximum(col["detuning"], col["rate"])
    best = None
    for sp, sn, ss in itertools.product(S_PREDICTION, S_BRACKET, S_SPREAD):
        est = sp * col["prediction"] + sn * bracket + ss * col["spread"]
        if np.any(actual > est):
            continue
        s = shares(actual, est)
        low = min(v["share"] for v in s.values())
        if best is None or low > best["lowest_share"]:
            best = dict(S_prediction=sp, S_bracket=sn, S_spread=ss, lowest_share=low,
                        worst=float(np.max(actual / est)), **s)
    out["best_bound"] = best
    out["ceiling"] = {f"{s:g}": shares(actual, s * actual) for s in PRECISIONS}
    envelope = np.maximum.reduce([col[name] for name in PREDICTIONS]) + col["spread"]
    out["envelope_decision"] = [dict(S=s, **decision(actual, col["estimate"], s * envelope)) for s in S_ENVELOPE]
    usable = np.isfinite(col["normal_form"]) & (col["branches"] == 1)
    ratio = actual[usable] / col["normal_form"][usable]
    out["normal_form"] = dict(
        rows=int(usable.sum()), without=int(np.sum(~np.isfinite(col["normal_form"]))),
        ratio_percentiles={str(q): float(np.percentile(ratio, q)) for q in (0, 1, 5, 25, 50, 75, 95, 99, 100)}
        if usable.any() else {}, within_10_percent=int(np.sum(np.abs(ratio - 1) <= 0.1)),
        bracket_only=shares(actual, col["bracket"]))
    ratio = actual / col["prediction"]
    out["branches"] = {str(b): dict(rows=int(np.sum(col["branches"] == b)),
                                    ratio_percentiles={str(q): float(np.percentile(ratio[col["branches"] == b], q))
                                                       for q in (50, 95, 100)})
                       for b in (1, 3) if np.any(col["branches"] == b)}
    return out


def chart(rows: list[dict], result: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    actual = np.array([r["actual"] for r in rows])
    fig, axes = plt.subplots(1, 2, figsize=(10.5, 4.6), sharey=True)
    for ax, key, title in ((axes[0], "prediction", "the prediction (coefficients following spin-up, swing, arm)"),
                           (axes[1], "estimate",
                            f"the product's estimate (min of bracket, {SAFETY_PREDICTED:g} x normal form)")):
        x = np.array([r[key] for r in rows])
        ax.loglog(x, actual, ".", ms=3, alpha=0.6, color="C0" if key == "prediction" else "C1")
        lo, hi = 1e-7, 1.0
        ax.plot([lo, hi], [lo, hi], color="k", lw=0.8, label="actual = x")
        ax.plot([lo, hi], [1.5 * lo, 1.5 * hi], color="0.5", lw=0.8, ls="--", label="actual = 1.5 x")
        for acc in ACCURACIES:
            ax.axhline(acc, color="C3", lw=0.5, ls=":")
            ax.axvline(acc, color="C3", lw=0.5, ls=":")
        ax.set(xlim=(lo, hi), ylim=(lo, hi), xlabel=f"{key} (rad)", title=title)
        ax.title.set_fontsize(9)
        ax.legend(fontsize=7, loc="upper left")
    axes[0].set_ylabel("actual max |theta_averaged - theta_full| (rad)")
    p = result["prediction"]["ratio_percentiles"]
    fig.suptitle(f"Spherical pendulum, {result['scenarios']} scenarios: actual/prediction median {p['50']:.2f}, "
                 f"5-95 % {p['5']:.2f}-{p['95']:.2f}, worst {p['100']:.1f}", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _measure_quietly(row: dict) -> dict | None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return measure(row)


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("pendulum-prediction", __doc__)
    add_study_options(ap)
    ap.add_argument("--workers", type=bounded(int, 1, MAX_WORKERS), default=2, help="processes (default 2)")
    args = ap.parse_args(argv)
    paths, picked = picked_rows(ap, args.study)
    t0 = time.perf_counter()
    with ProcessPoolExecutor(args.workers) as pool:
        rows = measured(pool.map(_measure_quietly, picked, chunksize=4), len(picked))
    result = summary(rows)
    write_study(args, argv, "pendulum_prediction", COLUMNS, rows, paths, t0, result)
    chart(rows, result, args.img / "pendulum_prediction.png")
    pr = result["product"]
    print(f"{len(rows)} scenarios; the product's estimate: {pr['violations']} violations, "
          + ", ".join(f"{a:g} rad {pr[f'{a:g}']['share']:.0%}" for a in ACCURACIES))
    for name in PREDICTIONS:
        q = result[name]["ratio_percentiles"]
        print(f"{name}: actual/predicted median {q['50']:.2f}, 5-95 % {q['5']:.2f}-{q['95']:.2f}, 99 % {q['99']:.2f},"
              f" worst {q['100']:.2f}; within 10 %: {result[name]['within_10_percent']}")
    nf = result["normal_form"]
    if nf["ratio_percentiles"]:
        q = nf["ratio_percentiles"]
        print(f"normal form ({nf['rows']} rows with one steady swing and a prediction; {nf['without']} without): "
              f"actual/predicted median {q['50']:.2f}, 1-99 % {q['1']:.2f}-{q['99']:.2f}, range {q['0']:.2f}-"
              f"{q['100']:.2f}; the bracket alone: " + ", ".join(
                  f"{a:g} rad {nf['bracket_only'][f'{a:g}']['share']:.0%}" for a in ACCURACIES))
    b = result["best_bound"]
    if b is None:
        print("no estimate of the form S_p prediction + S_n bracket + S_s spread tried leaves every row within it")
    else:
        print(f"best with no violation: {b['S_prediction']:g} prediction + {b['S_bracket']:g} max(detuning, rate) + "
              f"{b['S_spread']:g} spread: " + ", ".join(f"{a:g} rad {b[f'{a:g}']['share']:.0%}" for a in ACCURACIES))
    for s, c in result["ceiling"].items():
        print(f"ceiling of an estimate at most {s}x the actual error: "
              + ", ".join(f"{a:g} rad {c[f'{a:g}']['share']:.0%}" for a in ACCURACIES))
    for b, v in result["branches"].items():
        q = v["ratio_percentiles"]
        print(f"{v['rows']} rows with {b} steady swing(s) at the start: actual/predicted median {q['50']:.2f}, "
              f"95 % {q['95']:.2f}, worst {q['100']:.2f}")
    for d in result["envelope_decision"]:
        print(f"cheap where the estimate or {d['S']:g} x envelope allows: " + ", ".join(
            f"{a:g} rad {d[f'{a:g}']['share']:.0%} ({d[f'{a:g}']['over_accuracy']} over the accuracy)"
            for a in ACCURACIES))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
