"""``python -m bench stability [--quick]``: where methods fail, in four studies (issue 5).

1. stiffness: the largest stable step of each explicit fixed-step method as the mass's frequency
   Omega = 1/eps grows, against the cost (evaluations) of the adaptive explicit and the implicit
   (scipy Radau, BDF) methods on the same problems;
2. drift: |K| and E over 10^4 revolutions of the undamped moving mass for each method, with
   MuJoCo's implicitfast integrator as the known failing peer (docs/models.md A.7);
3. validity: the averaged model's theta error against the full model over (eps, theta0);
4. braking: how each method copes with the discontinuous control at |G| -> 0, and where it stops,
   against the exact braking time T (seed 004 eq. (10)).

Each study writes ``<out>/stability_<name>.csv``; charts go to ``<img>/stability_<name>.png``;
``<out>/stability.meta.json`` records the machine, versions and command.
"""

from __future__ import annotations

import csv
import json
import math
import sys
import time
import warnings
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

import physics
from physics.compiled import dispatch
from physics.reference import problems as P

from . import runners as R
from .cli import quick_out_img_parser
from .machine import machine

STABLE_THETA = 0.05  # rad: a run whose theta strays further than this from the reference has failed
NO_END_NFEV = 200_000  # evaluations after which a run that has no end at |G| = 0 is given up
BISECTIONS = 10  # halvings of the log-step bracket when searching the largest stable step


def _write(out: Path, name: str, rows: list[dict]) -> None:
    with open(out / f"stability_{name}.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


# ---- 1. stiffness -----------------------------------------------------------------------------

def stiffness(quick: bool, out: Path, img: Path) -> list[dict]:
    R.log("stability 1/4: largest stable explicit step against Omega")
    eps_list = (0.3, 0.1, 0.03) if quick else (0.3, 0.1, 0.03, 0.01, 0.003)
    horizon = 10.0 if quick else 20.0
    model = physics.get_model("moving_mass", "full")
    rows = []
    for eps in eps_list:
        sc = P.moving_mass(eps, t_end=horizon, samples=11, rtol=1e-6, mass_state="rest")
        p = model.pack(sc)
        y0 = model.initial_state(sc, p)
        t = sc.run.times()
        Yref, *_ = R.compiled_dop853(model.kernel, y0, p, t, 1e-11)
        theta_ref = model.observe(t, Yref, p, sc).theta
        Om = sc.mass.Omega

        def stable(method, dt, p=p, y0=y0, t=t, sc=sc, theta_ref=theta_ref):
            Y, *_ = R.compiled_fixed(method, model.kernel, y0, p, t, dt)
            if not np.all(np.isfinite(Y)):
                return False
            return bool(np.max(np.abs(model.observe(t, Y, p, sc).theta - theta_ref)) < STABLE_THETA)

        for method, stages in (("RK4", 4), ("RK8", 12)):
            lo, hi = 1e-4, 2.0
            if stable(method, hi):
                lo = hi
            else:
                for _ in range(BISECTIONS):
                    mid = math.sqrt(lo * hi)
                    if stable(method, mid):
                        lo = mid
                    else:
                        hi = mid
            rows.append(dict(eps=eps, Omega=Om, method=method, dt_max=lo, dt_max_Omega=lo * Om,
                             nfev=int(math.ceil(horizon / lo)) * stages, wall_s=float("nan")))
        for method in ("auto", "Radau", "BDF"):
            tr, nfev, steps, wall = R.simulate_run(sc, method, rtol=1e-6)
            name = "DOP853 (compiled, adaptive)" if method == "auto" else f"scipy {method} (implicit)"
            mean = horizon / steps if steps else float("nan")  # scipy does not report its steps here
            rows.append(dict(eps=eps, Omega=Om, method=name, dt_max=mean, dt_max_Omega=mean * Om, nfev=nfev,
                             wall_s=wall))
        R.log(f"  eps = {eps:g}: " + ", ".join(f"{r['method']} dt {r['dt_max']:.3g} nfev {r['nfev']}"
                                                for r in rows if r["eps"] == eps))
    _write(out, "stiffness", rows)
    plt = _plt()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.5))
    for method in ("RK4", "RK8"):
        sub = [r for r in rows if r["method"] == method]
        a1.loglog([r["Omega"] for r in sub], [r["dt_max"] for r in sub], "o-", label=f"{method}: largest stable step")
    sub = [r for r in rows if r["method"].startswith("DOP853")]
    a1.loglog([r["Omega"] for r in sub], [r["dt_max"] for r in sub], "s--", label="DOP853 adaptive: mean step")
    Om = np.array(sorted({r["Omega"] for r in rows}))
    a1.loglog(Om, 2.8 / Om, "k:", label="2.8 / Omega (RK4's real-axis limit)")
    a1.set_xlabel("Omega = 1/eps (rad/s)")
    a1.set_ylabel("step (s)")
    a1.legend(fontsize=8)
    a1.grid(True, which="both", alpha=0.3)
    for method in sorted({r["method"] for r in rows}):
        sub = [r for r in rows if r["method"] == method]
        a2.loglog([r["Omega"] for r in sub], [r["nfev"] for r in sub], "o-", label=method)
    a2.set_xlabel("Omega = 1/eps (rad/s)")
    a2.set_ylabel(f"evaluations over {horizon:g} s")
    a2.legend(fontsize=8)
    a2.grid(True, which="both", alpha=0.3)
    R.save_figure(fig, img / "stability_stiffness.png",
                  "Stiffness: explicit steps shrink like 1/Omega; implicit methods step over the damped fast mode")
    return rows


# ---- 2. long-time drift -----------------------------------------------------------------------

def drift(quick: bool, out: Path, img: Path) -> list[dict]:
    revolutions = 200 if quick else 10_000
    sc0 = P.moving_mass(0.1, t_end=1.0, chi=0.0, mass_state="rest")
    model = physics.get_model("moving_mass", "full")
    p = model.pack(sc0)
    y0 = model.initial_state(sc0, p)
    period = 2 * math.pi / float(np.linalg.norm(y0[0:3]))
    horizon = revolutions * period
    samples = 201
    sc = P.moving_mass(0.1, t_end=horizon, samples=samples, chi=0.0, mass_state="rest", rtol=1e-8)
    R.log(f"stability 2/4: |K| and E drift, undamped mass, {revolutions} revolutions ({horizon:.0f} s)")
    runs = {}
    for label, method, extra in (("DOP853 (compiled) rtol=1e-8", "auto", {}),
                                 ("RK4 (compiled) dt=0.05", "RK4", {"dt": 0.05}),
                                 ("RK8 (compiled) dt=0.1", "RK8", {"dt": 0.1}),
                                 ("midpoint (compiled) dt=0.05", "midpoint", {"dt": 0.05})):
        tr, nfev, steps, wall = R.simulate_run(sc, method, **extra)
        runs[label] = (tr.t, tr.K, tr.E, nfev, wall)
        R.log(f"  {label}: {wall:.2f} s")
    from physics.reference import mujoco_moving_mass as mm

    ms, body = sc.mass, sc.body
    t = sc.run.times()
    for integ, dt in (("implicitfast", 0.002 if not quick else 0.001), ("RK4", 0.05)):
        dt = (t[1] - t[0]) / round((t[1] - t[0]) / dt)
        start = time.perf_counter()
        o = mm.run(body.A, body.B, body.C, body.M, ms.m, ms.rho, ms.Omega, ms.chi, y0[0:3], t, dt, integrator=integ)
        wall = time.perf_counter() - start
        runs[f"MuJoCo {integ} dt={dt:.3g}"] = (t, np.linalg.norm(o["K_world"], axis=1), o["E"], 4 * o["steps"]
                                                if integ == "RK4" else o["steps"], wall)
        R.log(f"  MuJoCo {integ}: {wall:.2f} s")
    rows = []
    for label, (_tt, K, E, nfev, wall) in runs.items():
        dK = np.abs(K / K[0] - 1)
        dE = np.abs(E / E[0] - 1)
        rows.append(dict(method=label, revolutions=revolutions, max_rel_K_drift=float(np.max(dK)),
                         max_rel_E_drift=float(np.max(dE)), final_rel_K=float(K[-1] / K[0] - 1),
                         final_rel_E=float(E[-1] / E[0] - 1), nfev=int(nfev), wall_s=float(wall)))
    _write(out, "drift", rows)
    plt = _plt()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.5))
    for label, (tt, K, E, _, _) in runs.items():
        rev = tt / period
        a1.semilogy(rev[1:], np.maximum(np.abs(K[1:] / K[0] - 1), 1e-17), label=label)
        a2.semilogy(rev[1:], np.maximum(np.abs(E[1:] / E[0] - 1), 1e-17), label=label)
    for ax, q in ((a1, "|K|"), (a2, "E")):
        ax.set_xlabel("revolutions")
        ax.set_ylabel(f"relative change of {q}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    R.save_figure(fig, img / "stability_drift.png",
                  f"Long-time drift, undamped moving mass (eps = 0.1), {revolutions} revolutions")
    return rows


# ---- 3. validity map --------------------------------------------------------------------------

def validity(quick: bool, out: Path, img: Path) -> list[dict]:
    eps_list = (0.3, 0.2, 0.1) if quick else (0.3, 0.2, 0.1, 0.05)
    thetas = (0.3, 1.0) if quick else (0.3, 0.6, 1.0, 1.3)
    frac = 0.02 if quick else 0.25  # of docs/models.md A.7(a)'s slow horizon, 13333 (0.1/eps)^3 s
    R.log(f"stability 3/4: averaged model's error over eps x theta0 ({frac:g} of the slow horizon)")
    rows = []
    for eps in eps_list:
        for th in thetas:
            horizon = frac * P.P2_T * (0.1 / eps) ** 3
            sc = P.moving_mass(eps, theta0=th, t_end=horizon, samples=201, rtol=1e-9)
            full, nf_full, _, w_full = R.simulate_run(sc, "auto")
            avg, nf_avg, _, w_avg = R.simulate_run(sc.with_values(**{"run.fidelity": "averaged"}), "auto")
            err = float(np.max(np.abs(full.theta - avg.theta)))
            rows.append(dict(eps=eps, theta0=th, horizon_s=horizon, theta_error=err, error_over_eps2=err / eps**2,
                             wall_full_s=w_full, wall_averaged_s=w_avg))
            R.log(f"  eps {eps:g} theta0 {th:g}: error {err:.3g} ({err / eps**2:.3g} eps^2)")
    _write(out, "validity", rows)
    plt = _plt()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.5))
    grid = np.array([[next(r["theta_error"] for r in rows if r["eps"] == e and r["theta0"] == th) for th in thetas]
                     for e in eps_list])
    im = a1.imshow(np.log10(grid), origin="lower", aspect="auto", cmap="viridis")
    a1.set_xticks(range(len(thetas)), [f"{th:g}" for th in thetas])
    a1.set_yticks(range(len(eps_list)), [f"{e:g}" for e in eps_list])
    for i in range(len(eps_list)):
        for j in range(len(thetas)):
            a1.text(j, i, f"{grid[i, j]:.1e}", ha="center", va="center", color="w", fontsize=8)
    a1.set_xlabel("theta0 (rad)")
    a1.set_ylabel("eps = |w|/Omega")
    fig.colorbar(im, ax=a1, label="log10 max |theta_full - theta_averaged| (rad)")
    for th in thetas:
        sub = [r for r in rows if r["theta0"] == th]
        a2.loglog([r["eps"] for r in sub], [r["theta_error"] for r in sub], "o-", label=f"theta0 = {th:g}")
    e = np.array(eps_list)
    a2.loglog(e, 0.1 * e**2, "k:", label="0.1 eps^2 (the O(eps^2) bound used by the targets)")
    a2.set_xlabel("eps")
    a2.set_ylabel("theta error (rad)")
    a2.grid(True, which="both", alpha=0.3)
    a2.legend(fontsize=8)
    R.save_figure(fig, img / "stability_validity.png",
                  "Averaged model's validity: error against eps and theta0 (prolate, docs/models.md A.7(a))")
    return rows


# ---- 4. end of braking ------------------------------------------------------------------------

def braking(quick: bool, out: Path, img: Path) -> list[dict]:
    R.log("stability 4/4: end of braking (discontinuous control at |G| -> 0)")
    sc = P.p3(samples=41, rtol=1e-9)
    _, T = P.p3_exact(0.0)
    rows = []
    traces = {}
    for label, method, extra in (("DOP853 (compiled, project end)", "auto", {}),
                                 ("RK4 (compiled) dt=0.1", "RK4", {"dt": 0.1}),
                                 ("RK8 (compiled) dt=0.5", "RK8", {"dt": 0.5}),
                                 ("scipy DOP853 + event", "DOP853", {}),
                                 ("scipy RK45 + event", "RK45", {}),
                                 ("scipy LSODA + event", "LSODA", {})):
        tr, nfev, steps, wall = R.simulate_run(sc, method, **extra)
        rows.append(dict(method=label, t_stop=float(tr.t[-1]), T_exact=T, rel_T_error=abs(tr.t[-1] - T) / T,
                         G_end=float(tr.K[-1]), nfev=nfev, wall_s=wall, stop_reason=tr.info["stop_reason"]))
        R.log(f"  {label}: stops at T {'+' if tr.t[-1] >= T else '-'} {abs(tr.t[-1] - T):.2e} s, nfev {nfev}")
    # what happens without an end: scipy runs through T, the control chattering around |G| = 0
    model = physics.get_model("moving_mass", "averaged")
    p = model.pack(sc)
    y0 = model.initial_state(sc, p)
    buf = np.empty_like(y0)

    def fun(tt, y):
        dispatch.rhs(model.kernel, tt, y, p, buf)
        return buf.copy()

    t_dense = np.linspace(0.9 * T, 1.2 * T, 601)
    for method in ("DOP853", "RK45"):
        start = time.perf_counter()
        solver = R.SCIPY[method](fun, 0.0, y0, 1.2 * T, rtol=1e-9, atol=1e-12)
        tt, GG = [], []
        while solver.status == "running" and solver.nfev < NO_END_NFEV:
            t_prev = solver.t
            solver.step()
            if solver.t > t_dense[0]:
                dense = solver.dense_output()
                sel = t_dense[(t_dense > t_prev) & (t_dense <= solver.t)]
                for ts in sel:
                    tt.append(ts)
                    GG.append(float(np.linalg.norm(dense(ts)[0:3] * p[0:3])))
        wall = time.perf_counter() - start
        tt, GG = np.array(tt), np.array(GG)
        traces[f"scipy {method}, no end"] = (tt, GG)
        after = GG[tt > T]
        gave_up = solver.status == "running"
        rows.append(dict(method=f"scipy {method}, no end (runs through T)", t_stop=float(solver.t), T_exact=T,
                         rel_T_error=float("nan"), G_end=float(np.max(after)) if after.size else float("nan"),
                         nfev=int(solver.nfev), wall_s=wall,
                         stop_reason=(f"gave up after {NO_END_NFEV} evaluations at t - T = {solver.t - T:.3g} s"
                                      if gave_up else f"reached 1.2 T; max |G| after T = G_end ({solver.status})")))
        R.log(f"  scipy {method} through T: {rows[-1]['stop_reason']}, nfev {solver.nfev}")
    _write(out, "braking", rows)
    plt = _plt()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(12, 4.5))
    ended = [r for r in rows if math.isfinite(r["rel_T_error"])]
    a1.barh([r["method"] for r in ended], [max(r["rel_T_error"], 1e-17) for r in ended])
    a1.set_xscale("log")
    a1.set_xlabel("|t_stop - T| / T")
    a1.set_title("where each method ends the braking run")
    G_exact, _ = P.p3_exact(t_dense)
    a2.plot(t_dense - T, G_exact, "k-", lw=2, label="exact |G|, seed 004 eq. (10)")
    for label, (tt, G) in traces.items():
        a2.plot(tt - T, G, ".", ms=2, label=label)
    a2.set_yscale("symlog", linthresh=1e-8)
    a2.set_xlabel("t - T (s)")
    a2.set_ylabel("|G| (kg m^2/s)")
    a2.legend(fontsize=8)
    a2.set_title("without an end the control chatters at |G| = 0")
    R.save_figure(fig, img / "stability_braking.png")
    return rows


def main(argv: list[str] | None = None) -> int:
    """``python -m bench stability [--quick] [--out DIR] [--img DIR]``."""
    argv = sys.argv[1:] if argv is None else list(argv)
    a = quick_out_img_parser("stability", __doc__).parse_args(argv)
    run(a.quick, a.out, a.img, command=" ".join(["python -m bench stability", *argv]))
    return 0


def run(quick: bool, out: Path, img: Path, command: str = "python -m bench stability") -> dict:
    """The four studies, their CSVs and charts, and the metadata (``command`` is recorded in it)."""
    start = time.perf_counter()
    out.mkdir(parents=True, exist_ok=True)
    img.mkdir(parents=True, exist_ok=True)
    R.log("warming up compiled code ...")
    R.warm_up()
    meta = dict(command=command, quick=quick,
                date=datetime.now(UTC).isoformat(timespec="seconds"), machine=machine())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        for study in (stiffness, drift, validity, braking):
            t0 = time.perf_counter()
            study(quick, out, img)
            meta[f"{study.__name__}_wall_s"] = time.perf_counter() - t0
    meta["wall_total_s"] = time.perf_counter() - start
    (out / "stability.meta.json").write_text(json.dumps(meta, indent=2, default=str))
    R.log(f"done in {meta['wall_total_s']:.1f} s")
    return meta
