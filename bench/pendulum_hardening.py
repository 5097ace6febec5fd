"""``python -m bench pendulum-hardening``: would the spherical pendulum's averaged model come nearer the full model
if its detuning followed the bob's swing? A measurement for issue 23's open share, not a model of the product.

The product's averaged model (docs/models.md B.6) keeps the detuning sigma = lambda_1 - Omega fixed. The full model
has two amplitude effects the averaging drops: the pivot hardens (the bob's mode-1 frequency rises by SWING_SHIFT
omega_0 a^2 with its swing a, physics/systems/pendulum/accuracy.py), and the spin rate rises as the nutation
decays, moving sigma by -(C/A) W (theta0^2 - theta^2)/2. The error estimate brackets both as fixed shifts of sigma
over the whole run, which is what makes it 3x to 30x the actual error on weakly damped, exactly tuned bobs (issue
23: the share auto takes there). Here the same averaged equations are integrated with sigma(t) following the swing
and theta, each effect alone and both, and each variant's theta is compared with the full model's over the rows of
a fidelity study (default: the check seed's, bench/results/fidelity.csv).

Writes bench/results/pendulum_hardening.csv (+ .meta.json: machine, command, summary) and
docs/img/pendulum_hardening.png (each variant's error against the product's, per scenario).
"""

from __future__ import annotations

import csv
import json
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import physics
from bench.cli import bounded, study_parser
from bench.fidelity import max_theta_error
from bench.results_file import write_results
from physics.scenario.initial import initial_G
from physics.systems.pendulum.accuracy import SWING_SHIFT, scenario_parts
from physics.systems.pendulum.averaged import AveragedCoefficients
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.pendulum.linear import spherical_linear

ROOT = Path(__file__).resolve().parent.parent
STUDY = ROOT / "bench" / "results" / "fidelity.csv"
VARIANTS = {"both": (1.0, 1.0), "swing": (0.0, 1.0), "spin": (1.0, 0.0)}  # (spin-up, hardening) switched on
COLUMNS = ("index", "pivot", "theta0", "swing", "shift_over_width", "estimate", "error_averaged",
           *(f"error_{v}" for v in VARIANTS))


def averaged_run(p, co: AveragedCoefficients, w0, t: np.ndarray, coefficients) -> np.ndarray:
    """theta at times t from the averaged equations of B.6, Phihat' = kappa1 Ut, Ut' = (i sigma - gamma1) Ut -
    kappa2 Phihat, for linear parameters p (coefficients co), started as the product's averaged model starts (the
    carrier at the initial rate w0, the pendulum at rest), with (kappa1, kappa2, sigma, gamma1) = coefficients(P,
    U, theta, theta0) at every step, so they may follow the amplitudes; theta read as the averaged model reads it,
    tan theta = |H_perp|/(C W). DOP853 at rtol 1e-9; NaN where the integration stops early."""
    W = float(w0[2])
    u0 = np.array([w0[0] + 1j * w0[1], 0j])
    Ab, cu = co.A + p.mu * p.D**2, 1j * p.mu * p.D * p.l * p.omega0  # H1 + i H2 = Ab Phihat + cu Ut

    def angle(P, U):
        return np.arctan2(np.abs(Ab * P + cu * U), p.C * W)

    theta0 = float(angle(u0[0], u0[1]))

    def rhs(_, y):
        P, U = y[0] + 1j * y[1], y[2] + 1j * y[3]
        kappa1, kappa2, sigma, gamma1 = coefficients(P, U, float(angle(P, U)), theta0)
        dP, dU = kappa1 * U, (1j * sigma - gamma1) * U - kappa2 * P
        return [dP.real, dP.imag, dU.real, dU.imag]

    sol = solve_ivp(rhs, (0.0, float(t[-1])), [u0[0].real, u0[0].imag, 0.0, 0.0], t_eval=t, method="DOP853",
                    rtol=1e-9, atol=1e-13 * abs(u0[0]) + 1e-300)
    if sol.y.shape[1] != len(t):
        return np.full(len(t), math.nan)
    return angle(sol.y[0] + 1j * sol.y[1], sol.y[2] + 1j * sol.y[3])


def detuned_theta(sc, t: np.ndarray, spin: float, swing: float) -> np.ndarray:
    """theta at times t from the averaged equations of B.6 with sigma(t) = sigma + swing SWING_SHIFT omega_0 |Ut|^2
    - spin (C/A) W (theta0^2 - theta^2)/2 (``averaged_run``)."""
    p = spherical_linear(pendulum_system(sc))
    co = AveragedCoefficients(p)
    w0, _, _ = initial_G(sc)
    W = float(w0[2])
    hard = SWING_SHIFT[sc.pendulum.pivot] * p.omega0

    def coefficients(_, U, theta, theta0):
        sigma = co.sigma + swing * hard * abs(U) ** 2 - spin * (p.C / co.A) * W * (theta0**2 - theta**2) / 2
        return co.kappa1, co.kappa2, sigma, co.gamma1

    return averaged_run(p, co, w0, t, coefficients)


def measure(sc) -> dict:
    """One scenario's row: the full model's theta against the product's averaged model and each variant's."""
    full = physics.simulate(sc, fidelity="full")
    avg = physics.simulate(sc, fidelity="averaged")
    q = scenario_parts(sc)
    row = dict(pivot=sc.pendulum.pivot, theta0=float(full.theta[0]), swing=q.a,
               shift_over_width=q.shift / q.width if q.width > 0 else math.inf, estimate=q.bound,
               error_averaged=max_theta_error(full.t, full.theta, avg.t, avg.theta)[0])
    for name, (spin, swing) in VARIANTS.items():
        row[f"error_{name}"] = float(np.max(np.abs(detuned_theta(sc, full.t, spin, swing) - full.theta)))
    return row


def summary(rows: list[dict]) -> dict:
    base = np.array([r["error_averaged"] for r in rows])
    out = {"scenarios": len(rows)}
    for name in VARIANTS:
        err = np.array([r[f"error_{name}"] for r in rows])
        ratio = err / base
        out[name] = dict(median_ratio=float(np.median(ratio)), p10=float(np.percentile(ratio, 10)),
                         p90=float(np.percentile(ratio, 90)), worst=float(np.max(ratio)),
                         nearer=int(np.sum(ratio < 0.9)), farther=int(np.sum(ratio > 1.1)),
                         **{f"within_{acc:g}": [int(np.sum(base <= acc)), int(np.sum(err <= acc))]
                            for acc in (1e-2, 1e-3)})
    return out


def chart(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    base = np.array([max(r["error_averaged"], 1e-9) for r in rows])
    err = np.array([max(r["error_both"], 1e-9) for r in rows])
    tone = np.log10(np.clip([r["shift_over_width"] for r in rows], 1e-3, 1e3))
    s = ax.scatter(base, err, c=tone, cmap="viridis", s=18)
    lo, hi = min(base.min(), err.min()) / 2, max(base.max(), err.max()) * 2
    ax.plot([lo, hi], [lo, hi], color="0.4", lw=0.8, label="no change")
    for acc in (1e-2, 1e-3):
        ax.axvline(acc, color="0.8", lw=0.6)
        ax.axhline(acc, color="0.8", lw=0.6)
    ax.set(xscale="log", yscale="log", xlim=(lo, hi), ylim=(lo, hi),
           xlabel="product's averaged model: max |dtheta| (rad)",
           ylabel="detuning following swing and spin: max |dtheta| (rad)",
           title="Spherical pendulum, averaged vs full: a swing-following detuning")
    fig.colorbar(s, label="log10 (nonlinear shift / resonance width)")
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = study_parser("pendulum-hardening", __doc__)
    ap.add_argument("--study", type=Path, default=STUDY, help="a fidelity study's CSV whose pendulum rows to rerun")
    ap.add_argument("--limit", type=bounded(int, 0, 1_000_000), default=0, help="at most this many rows (0: all)")
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results")
    ap.add_argument("--img", type=Path, default=ROOT / "docs" / "img")
    args = ap.parse_args(argv)
    if not args.study.is_file():
        ap.error(f"--study {args.study}: no such file (a CSV written by python -m bench fidelity)")
    with open(args.study, newline="") as f:
        picked = [r for r in csv.DictReader(f) if r["system"] == "spherical_pendulum" and r["status"] == "ok"]
    if not picked:
        ap.error(f"--study {args.study}: no spherical-pendulum row with status ok to rerun")
    if args.limit:
        picked = picked[:args.limit]
    rows = []
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        for n, r in enumerate(picked, 1):
            sc = physics.Scenario.from_dict(json.loads(r["scenario"]))
            rows.append(dict(index=r["index"], **measure(sc)))
            print(f"\r{n}/{len(picked)} scenarios", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)
    result = summary(rows)
    write_results(args.out, "pendulum_hardening", COLUMNS, rows,
                  command=" ".join(["python -m bench pendulum-hardening", *(sys.argv[1:] if argv is None else argv)]),
                  study=str(args.study.resolve().relative_to(ROOT)) if args.study.resolve().is_relative_to(ROOT)
                  else str(args.study), wall_s=time.perf_counter() - t0, summary=result)
    args.img.mkdir(parents=True, exist_ok=True)
    chart(rows, args.img / "pendulum_hardening.png")
    for name in VARIANTS:
        s = result[name]
        print(f"{name:6s}: error / product's median {s['median_ratio']:.2f} (10-90 % {s['p10']:.2f}-{s['p90']:.2f}, "
              f"worst {s['worst']:.2f}); nearer in {s['nearer']}, farther in {s['farther']}; within 1e-2: "
              f"{s['within_0.01'][0]} -> {s['within_0.01'][1]}, within 1e-3: {s['within_0.001'][0]} -> "
              f"{s['within_0.001'][1]}")
    return 0
