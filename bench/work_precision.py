"""``python -m bench work-precision [--quick]``: error against cost for every method on P1-P4.

Writes ``<out>/work_precision.csv`` (problem,method,setting,error,wall_s,nfev,steps), a companion
``work_precision.meta.json`` (machine, versions, command, date, the targets of issue 5 as ratios
measured in this run) and ``<out>/targets.csv``, and draws error against wall time and against
function evaluations in ``<img>/work_precision_wall.png`` and ``<img>/work_precision_nfev.png``.

Errors: P1 max |w - w_exact| (rad/s); P2 and P4 max |theta - theta_ref| (rad) over the samples;
P3 max(max |G - G_exact| / G0, |T_stop - T| / T). A method that blows up at a step has no row.

The scipy + numpy peer on P2: a Python right-hand side costs ~1e3 times the compiled one, so the
whole 4000-revolution run would take hours per point. It runs on the first PEER_PREFIX of the
horizon; its wall time per evaluation times the evaluations the compiled DOP853 needs on the whole
horizon at the same rtol (the same algorithm and step control, so the same steps: checked on the
prefix, ``nfev_match`` in the metadata) gives its P2 row, marked "extrapolated" in ``setting``.
On P4 (40 s) the numpy peer (``physics/reference/numpy_rhs.spherical_pendulum_rhs``) runs the whole horizon.
"""

from __future__ import annotations

import csv
import json
import math
import sys
import time
from datetime import UTC, datetime
from pathlib import Path

import numpy as np

import physics
from physics.compiled import dispatch
from physics.reference import problems as P
from physics.reference.numpy_rhs import moving_mass_rhs, spherical_pendulum_rhs

from . import runners as R
from .cli import quick_out_img_parser
from .machine import machine

COLUMNS = ("problem", "method", "setting", "error", "wall_s", "nfev", "steps")
PEER_PREFIX = 1 / 40  # fraction of P2's horizon the numpy peer actually runs
THETA_TARGET = 1e-6  # rad, issue 5: P2 accuracy the speed targets are measured at
REPEATS_UNDER = 0.5  # s: runs shorter than this are repeated and the fastest kept (shared cores)


def _best(fn, repeats=3, under=REPEATS_UNDER):
    """The fastest of ``repeats`` calls of ``fn`` (returning (..., wall_s)) when a call takes less
    than ``under`` seconds, else the one call."""
    out = fn()
    if out[-1] < under:
        for _ in range(repeats - 1):
            again = fn()
            if again[-1] < out[-1]:
                out = again
    return out


class Table:
    def __init__(self):
        self.rows: list[dict] = []

    def add(self, problem, method, setting, error, wall, nfev, steps):
        row = dict(problem=problem, method=method, setting=setting, error=float(error), wall_s=float(wall),
                   nfev=int(nfev), steps=int(steps))
        if not math.isfinite(row["error"]):
            R.log(f"  {problem} {method} {setting}: unstable, no row")
            return
        self.rows.append(row)
        R.log(f"  {problem:3s} {method:28s} {setting:26s} err {error:9.2e}  {wall:8.3f} s  nfev {nfev}")


# ---- problems ---------------------------------------------------------------------------------

def run_p1(tab: Table, quick: bool):
    R.log("P1 free rigid body (exact: Jacobi elliptic functions)")
    t = np.linspace(0.0, P.P1_T, 101)
    y0, p = P.p1_initial(), P.p1_params()
    exact = P.rigid_body_exact(t)

    def err(Y):
        return np.max(np.abs(Y[:, :3] - exact))

    for rtol in ((1e-6, 1e-9, 1e-12) if quick else (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12)):
        Y, nfev, steps, wall = _best(lambda rtol=rtol: R.compiled_dop853(dispatch.MASS_FULL, y0, p, t, rtol))
        tab.add("P1", "DOP853 (compiled)", f"rtol={rtol:g}", err(Y), wall, nfev, steps)
    for method, dts in (("RK4", (0.1, 0.03, 0.01)), ("RK8", (0.4, 0.2, 0.1)), ("midpoint", (0.1, 0.01))):
        if not quick:
            dts = tuple(np.geomspace(dts[0], dts[-1] / 2, 6))
        for dt in dts:
            Y, nfev, steps, wall = _best(lambda dt=dt, method=method: R.compiled_fixed(
                method, dispatch.MASS_FULL, y0, p, t, dt))
            tab.add("P1", f"{method} (compiled)", f"dt={dt:.4g}", err(Y), wall, nfev, steps)
    f = moving_mass_rhs(p)
    for method in ("DOP853", "RK45"):
        for rtol in ((1e-6, 1e-9) if quick else (1e-5, 1e-7, 1e-9, 1e-11)):
            Y, nfev, steps, wall = R.scipy_run(f, t, y0, method, rtol, R.atol_for(rtol, y0))
            tab.add("P1", f"scipy {method} (numpy rhs)", f"rtol={rtol:g}", err(Y), wall, nfev, steps)


def run_p2(tab: Table, quick: bool, meta: dict):
    horizon = P.P2_T / 20 if quick else P.P2_T
    R.log(f"P2 full moving mass, eps = 0.1, T = {horizon:g} s (reference: compiled DOP853, rtol 1e-13)")
    sc = P.p2(horizon)
    model = physics.get_model("moving_mass", "full")
    p = model.pack(sc)
    y0 = model.initial_state(sc, p)
    t = sc.run.times()
    Yref, *_ = R.compiled_dop853(model.kernel, y0, p, t, 1e-13)
    theta_ref = model.observe(t, Yref, p, sc).theta

    def err(Y):
        return np.max(np.abs(model.observe(t, Y, p, sc).theta - theta_ref))

    auto = {}
    for rtol in ((1e-5, 1e-7, 1e-9) if quick else (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)):
        Y, nfev, steps, wall = _best(lambda rtol=rtol: R.compiled_dop853(model.kernel, y0, p, t, rtol))
        auto[rtol] = (err(Y), nfev)
        tab.add("P2", "DOP853 (compiled)", f"rtol={rtol:g}", err(Y), wall, nfev, steps)
    for method, dts in (("RK4", (0.1, 0.05, 0.025)), ("RK8", (0.25, 0.2, 0.15, 0.1)),
                        ("midpoint", (0.05, 0.02))):
        if not quick and method != "midpoint":
            dts = dts + (dts[-1] / 2,)
        for dt in dts:
            Y, nfev, steps, wall = _best(lambda dt=dt, method=method: R.compiled_fixed(
                method, model.kernel, y0, p, t, dt))
            tab.add("P2", f"{method} (compiled)", f"dt={dt:g}", err(Y), wall, nfev, steps)
    # scipy peers: measured on a prefix, extrapolated to the horizon (module docstring). A user would
    # pass a plain atol = rtol; that is also the cheapest setting that still reaches 1e-6 here.
    t_pre = t[: max(2, int(round(len(t) * (PEER_PREFIX / 4 if quick else PEER_PREFIX))))]
    frac = (t_pre[-1] - t_pre[0]) / (t[-1] - t[0])
    buf = np.empty_like(y0)

    def compiled_fun(tt, y):
        dispatch.rhs(model.kernel, tt, y, p, buf)
        return buf.copy()

    match = {}
    for label, fun, rtols in (("scipy DOP853 (numpy rhs)", moving_mass_rhs(p),
                               (1e-7,) if quick else (1e-5, 1e-6, 1e-7, 1e-8, 1e-9)),
                              ("scipy DOP853 (compiled rhs)", compiled_fun, () if quick else (1e-6, 1e-8))):
        for rtol in rtols:
            Yp, nfev_p, steps_p, wall_p = R.scipy_run(fun, t_pre, y0, "DOP853", rtol, rtol)
            _, nfev_c, _, _ = R.compiled_dop853(model.kernel, y0, p, t_pre, rtol, rtol)
            match[f"{label} rtol={rtol:g}"] = nfev_p / nfev_c
            Yc, nfev_full, steps_full, _ = R.compiled_dop853(model.kernel, y0, p, t, rtol, rtol)
            tab.add("P2", label, f"rtol=atol={rtol:g} extrapolated from {frac:.3g} of T",
                    err(Yc), wall_p / nfev_p * nfev_full, nfev_full, steps_full)
    meta["numpy_peer_nfev_match"] = match
    # MuJoCo RK4 on the same model (physics/reference/mujoco_moving_mass.py)
    from physics.reference import mujoco_moving_mass as mm

    ms, body = sc.mass, sc.body
    gap = t[1] - t[0]
    for dt_want in ((0.04, 0.02) if quick else (0.05, 0.04, 0.03, 0.02, 0.01)):
        k = max(1, round(gap / dt_want))  # a whole number of MuJoCo steps between outputs
        start = time.perf_counter()
        out = mm.run(body.A, body.B, body.C, body.M, ms.m, ms.rho, ms.Omega, ms.chi, y0[0:3], t, gap / k,
                     u0=y0[3:6], v0=y0[6:9])
        wall = time.perf_counter() - start
        tab.add("P2", "MuJoCo RK4", f"dt={gap / k:.4g}", np.max(np.abs(out["theta"] - theta_ref)), wall,
                4 * out["steps"], out["steps"])


def run_p3(tab: Table, quick: bool):
    R.log("P3 braking with cavity and medium, averaged model (exact: seed 004 eq. (10))")
    sc = P.p3(samples=41)  # sparse output: the step control, not the output grid, sets the steps
    G_exact, T = P.p3_exact(sc.run.times())

    def err(tr):
        G, _ = P.p3_exact(tr.t)
        return max(np.max(np.abs(tr.K - G)), abs(tr.t[-1] - T) / T)

    for rtol in ((1e-6, 1e-9, 1e-12) if quick else (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12)):
        tr, nfev, steps, wall = _best(lambda rtol=rtol: R.simulate_run(sc, "auto", rtol=rtol))
        tab.add("P3", "DOP853 (compiled)", f"rtol={rtol:g}", err(tr), wall, nfev, steps)
    for method, dts in (("RK4", (0.5, 0.1, 0.02)), ("RK8", (1.0, 0.5, 0.2))):
        for dt in dts:
            tr, nfev, steps, wall = _best(lambda dt=dt, method=method: R.simulate_run(sc, method, dt=dt))
            tab.add("P3", f"{method} (compiled)", f"dt={dt:g}", err(tr), wall, nfev, steps)
    for method in ("DOP853", "RK45", "LSODA"):
        for rtol in ((1e-6, 1e-9) if quick else (1e-6, 1e-8, 1e-10)):
            tr, nfev, steps, wall = R.simulate_run(sc, method, rtol=rtol)
            tab.add("P3", f"scipy {method} (compiled rhs)", f"rtol={rtol:g}", err(tr), wall, nfev, steps)


def run_p4(tab: Table, quick: bool):
    horizon = P.P4_T / 4 if quick else P.P4_T
    R.log(f"P4 spherical-pendulum damper, set R, T = {horizon:g} s (reference: compiled DOP853, rtol 1e-13)")
    sc = P.p4(horizon, samples=41)  # sparse output: the step control, not the output grid, sets the steps
    ref = R.simulate_run(sc, "auto", rtol=1e-13)[0]

    def err(tr):
        return np.max(np.abs(tr.theta - ref.theta))

    for rtol in ((1e-6, 1e-9) if quick else (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)):
        tr, nfev, steps, wall = _best(lambda rtol=rtol: R.simulate_run(sc, "auto", rtol=rtol))
        tab.add("P4", "DOP853 (compiled)", f"rtol={rtol:g}", err(tr), wall, nfev, steps)
    for method, dts in (("RK4", (0.04, 0.02, 0.01, 0.005)), ("RK8", (0.2, 0.1, 0.05, 0.025))):
        for dt in dts:
            tr, nfev, steps, wall = _best(lambda dt=dt, method=method: R.simulate_run(sc, method, dt=dt))
            tab.add("P4", f"{method} (compiled)", f"dt={dt:g}", err(tr), wall, nfev, steps)
    for rtol in ((1e-6,) if quick else (1e-6, 1e-8, 1e-10)):
        tr, nfev, steps, wall = R.simulate_run(sc, "DOP853", rtol=rtol)
        tab.add("P4", "scipy DOP853 (compiled rhs)", f"rtol={rtol:g}", err(tr), wall, nfev, steps)
    # the numpy peer: the whole horizon (P4 is short), with the project's atol rule
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    y0 = model.initial_state(sc, p)
    for rtol in ((1e-6,) if quick else (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)):
        Y, nfev, steps, wall = R.scipy_run(spherical_pendulum_rhs(p), ref.t, y0, "DOP853", rtol, R.atol_for(rtol, y0))
        tab.add("P4", "scipy DOP853 (numpy rhs)", f"rtol={rtol:g}",
                np.max(np.abs(model.observe(ref.t, Y, p, sc).theta - ref.theta)), wall, nfev, steps)
    from physics.reference import mujoco_pendulum as mp
    from physics.systems.pendulum.geometry import pendulum_system

    s = pendulum_system(sc)
    b = s.bobs[0]
    gap = ref.t[1] - ref.t[0]
    for k in ((25, 50) if quick else (25, 50, 100, 200, 400)):
        start = time.perf_counter()
        out = mp.run(s.M0, s.I_c, b.m, b.l, b.k, b.c_d, b.pivot, ref.omega[0], ref.t, gap / k)
        wall = time.perf_counter() - start
        tab.add("P4", "MuJoCo RK4", f"dt={gap / k:.4g}", np.max(np.abs(out["theta"] - ref.theta)), wall,
                4 * out["steps"], out["steps"])


# ---- targets ----------------------------------------------------------------------------------

def _fastest(rows, problem, pred, tol):
    ok = [r for r in rows if r["problem"] == problem and pred(r["method"]) and r["error"] <= tol]
    return min(ok, key=lambda r: r["wall_s"]) if ok else None


def _rhs_loop_ratio(quick: bool) -> dict:
    """Fast path cost per evaluation (compiled DOP853 on P2) against the bare rhs in a tight loop."""
    from .overhead import bare_rhs_seconds

    sc = P.p2(P.P2_T / (40 if quick else 4))
    model = physics.get_model("moving_mass", "full")
    p = model.pack(sc)
    y0 = model.initial_state(sc, p)
    # both sides the fastest of three timings (bare_rhs_seconds does the same): one timing on shared
    # cores can be several times slower than the machine's speed
    Y, nfev, steps, wall = _best(lambda: R.compiled_dop853(model.kernel, y0, p, sc.run.times(), 1e-8),
                                 under=math.inf)
    bare = bare_rhs_seconds(model.kernel, y0, p, 200_000 if quick else 2_000_000)
    Yf, nfev_f, _, wall_f = _best(lambda: R.compiled_fixed("RK8", model.kernel, y0, p, sc.run.times(), 0.1),
                                  under=math.inf)
    return dict(per_eval_dop853_s=wall / nfev, per_eval_rk8_s=wall_f / nfev_f, bare_rhs_s=bare,
                ratio_dop853=(wall / nfev) / bare, ratio_rk8=(wall_f / nfev_f) / bare, goal=3.0)


def _averaged_vs_full(quick: bool) -> dict:
    """Averaged against full on P2's slow horizon at eps = 0.05 (8x the eps = 0.1 horizon), every
    model at the same rtol, timed the same way (one call from scenario to theta), errors in theta
    against the full model over the same 401 samples.

    Two forms of the averaged model: the product's (``physics.simulate`` at fidelity averaged, which for this
    axisymmetric body runs the slow reduction with the phases as quadratures, docs/models.md A.3); the closed
    forms.
    """
    eps = 0.05
    rtol = 1e-9
    horizon = P.P2_T * (0.1 / eps) ** 3 * (0.05 if quick else 1.0)
    sc = P.moving_mass(eps, t_end=horizon, samples=401, rtol=rtol)
    avg_sc = sc.with_values(**{"run.fidelity": "averaged"})
    closed_sc = sc.with_values(**{"run.fidelity": "closed"})
    short = {"run.t_end": 1.0, "run.samples": 3}
    for warm in (sc, avg_sc, closed_sc):  # compile or load every path first: not a cost of either side
        R.simulate_run(warm.with_values(**short), "auto")
    # every side timed once, the same way (the full model takes minutes: no best-of-three for anyone)
    full, _, _, wall_full = R.simulate_run(sc, "auto")
    avg, _, _, wall_avg = R.simulate_run(avg_sc, "auto")
    closed, _, _, wall_closed = R.simulate_run(closed_sc, "auto")
    err = float(np.max(np.abs(full.theta - avg.theta)))
    err_closed = float(np.max(np.abs(full.theta - closed.theta)))
    bound = 0.1 * eps**2  # docs/models.md A.7(a): 1.881e-4 at eps = 0.05 (prolate), i.e. 0.075 eps^2

    def met(wall, e):
        return bool(wall_full / wall >= 1000 and e <= bound)

    return dict(horizon_s=horizon, rtol=rtol, wall_full_s=wall_full, bound=bound, goal=1000.0,
                wall_averaged_s=wall_avg, ratio=wall_full / wall_avg, theta_error=err, met=met(wall_avg, err),
                reduction=avg.info.get("reduction", ""),
                wall_closed_s=wall_closed, ratio_closed=wall_full / wall_closed, theta_error_closed=err_closed,
                met_closed=met(wall_closed, err_closed))


AVERAGED_P2_GOAL = 5000.0  # issue 23 point 6: full / averaged wall on P2, physics.simulate both
AVERAGED_REPEATS = 5  # the averaged run takes milliseconds: the fastest of five, as _best does for short runs


def _product_averaged_on_p2(quick: bool) -> dict:
    """The product's averaged model (``physics.simulate`` at fidelity averaged) against the full model on P2 as
    bench sets it up (``physics.reference.problems.p2``: prolate, eps = 0.1, 13,333 s, 401 samples, rtol 1e-11),
    in this one process: the full model timed once (tens of seconds), the averaged one the fastest of
    AVERAGED_REPEATS calls (milliseconds, where one call on shared cores can be ten times slower than the machine).
    Also theta against the whole averaged model (w and the precession phase integrated over every free-body
    revolution, at rtol 1e-12), which the reduction must reproduce to 1e-9 rad."""
    from physics.stepping.simulate import integrate
    from physics.systems.moving_mass.models import AVERAGED

    sc = P.p2(P.P2_T / 20 if quick else P.P2_T)
    avg_sc = sc.with_values(**{"run.fidelity": "averaged"})
    short = {"run.t_end": 1.0, "run.samples": 3}
    for warm in (sc, avg_sc):
        R.simulate_run(warm.with_values(**short), "auto")
    full, _, full_steps, wall_full = R.simulate_run(sc, "auto")
    avg, _, avg_steps, wall_avg = _best(lambda: R.simulate_run(avg_sc, "auto"), repeats=AVERAGED_REPEATS)
    whole = integrate(AVERAGED, avg_sc.with_values(**{"run.rtol": 1e-12}), avg_sc.run.times())
    ratio = wall_full / wall_avg
    return dict(horizon_s=float(sc.run.t_end), rtol=float(sc.run.rtol), wall_full_s=wall_full, steps_full=full_steps,
                wall_averaged_s=wall_avg, steps_averaged=avg_steps, ratio=ratio, goal=AVERAGED_P2_GOAL,
                met=bool(ratio >= AVERAGED_P2_GOAL), reduction=avg.info.get("reduction", ""),
                theta_error=float(np.max(np.abs(full.theta - avg.theta))),
                theta_vs_whole_averaged=float(np.max(np.abs(whole.theta - avg.theta))),
                steps_whole_averaged=int(whole.info["steps"]))


def targets(rows: list[dict], quick: bool) -> tuple[list[dict], dict]:
    out = []
    ours = _fastest(rows, "P2", lambda m: "compiled)" in m and "scipy" not in m, THETA_TARGET)
    for peer_name, goal in (("scipy DOP853 (numpy rhs)", 30.0), ("MuJoCo RK4", 10.0)):
        peer = _fastest(rows, "P2", lambda m, n=peer_name: m == n, THETA_TARGET)
        if ours and peer:
            ratio = peer["wall_s"] / ours["wall_s"]
            out.append(dict(target=f"P2 theta <= {THETA_TARGET:g}: {peer_name} / fastest project method",
                            ours=f"{ours['method']} {ours['setting']}", ours_wall_s=ours["wall_s"],
                            peer=f"{peer['method']} {peer['setting']}", peer_wall_s=peer["wall_s"],
                            ratio=ratio, goal=goal, met=ratio >= goal))
    R.log("targets: the product's averaged model vs full on P2 ...")
    p2 = _product_averaged_on_p2(quick)
    out.append(dict(target=f"averaged (physics.simulate) vs full on P2, eps = 0.1, {p2['horizon_s']:g} s "
                           "(full / averaged wall)",
                    ours=f"averaged, {p2['reduction'].split(':')[0]} form, DOP853 (compiled) rtol={p2['rtol']:g}, "
                         f"theta error {p2['theta_error']:.3g}, against the whole averaged model "
                         f"{p2['theta_vs_whole_averaged']:.2g}",
                    ours_wall_s=p2["wall_averaged_s"], peer=f"full DOP853 (compiled) rtol={p2['rtol']:g}",
                    peer_wall_s=p2["wall_full_s"], ratio=p2["ratio"], goal=p2["goal"], met=p2["met"]))
    R.log("targets: averaged vs full at eps = 0.05 ...")
    av = _averaged_vs_full(quick)
    out.append(dict(target="averaged (physics.simulate) vs full, P2 slow horizon, eps = 0.05",
                    ours=f"averaged, {av['reduction'].split(':')[0]} form, DOP853 (compiled) rtol=1e-9, theta error "
                         f"{av['theta_error']:.3g} (bound {av['bound']:.3g})",
                    ours_wall_s=av["wall_averaged_s"], peer="full DOP853 (compiled) rtol=1e-9",
                    peer_wall_s=av["wall_full_s"], ratio=av["ratio"], goal=1000.0, met=av["met"]))
    out.append(dict(target="closed-form (averaged, integrated analytically) vs full, P2 slow horizon, eps = 0.05",
                    ours=f"closed, theta error {av['theta_error_closed']:.3g} (bound {av['bound']:.3g})",
                    ours_wall_s=av["wall_closed_s"], peer="full DOP853 (compiled) rtol=1e-9",
                    peer_wall_s=av["wall_full_s"], ratio=av["ratio_closed"], goal=1000.0, met=av["met_closed"]))
    R.log("targets: cost per evaluation vs the bare rhs ...")
    ov = _rhs_loop_ratio(quick)
    out.append(dict(target="fast path cost per evaluation / bare rhs in a tight loop (P2)",
                    ours="DOP853 (compiled) rtol=1e-8", ours_wall_s=ov["per_eval_dop853_s"], peer="bare rhs loop",
                    peer_wall_s=ov["bare_rhs_s"], ratio=ov["ratio_dop853"], goal=3.0, met=ov["ratio_dop853"] <= 3.0))
    out.append(dict(target="fast path cost per evaluation / bare rhs in a tight loop (P2)",
                    ours="RK8 (compiled) dt=0.1", ours_wall_s=ov["per_eval_rk8_s"], peer="bare rhs loop",
                    peer_wall_s=ov["bare_rhs_s"], ratio=ov["ratio_rk8"], goal=3.0, met=ov["ratio_rk8"] <= 3.0))
    return out, dict(averaged_p2=p2, averaged_vs_full=av, overhead=ov)


# ---- output -----------------------------------------------------------------------------------

def charts(rows: list[dict], img: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    img.mkdir(parents=True, exist_ok=True)
    problems = sorted({r["problem"] for r in rows})
    paths = []
    for xkey, label, name in (("wall_s", "wall time (s)", "work_precision_wall.png"),
                              ("nfev", "right-hand side evaluations", "work_precision_nfev.png")):
        fig, axes = plt.subplots(2, 2, figsize=(12, 9))
        for ax, prob in zip(axes.flat, problems, strict=False):
            sub = [r for r in rows if r["problem"] == prob]
            for method in sorted({r["method"] for r in sub}):
                pts = sorted((r[xkey], max(r["error"], 1e-16)) for r in sub if r["method"] == method)
                style = "--" if ("scipy" in method or "MuJoCo" in method) else "-"
                ax.loglog([x for x, _ in pts], [e for _, e in pts], style, marker="o", ms=4, label=method)
            ax.set_title(prob)
            ax.set_xlabel(label)
            ax.set_ylabel("error")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
        path = img / name
        R.save_figure(fig, path, f"Work-precision: error against {label} (solid: project, dashed: peers)")
        paths.append(path)
    return paths


def main(argv: list[str] | None = None) -> int:
    """``python -m bench work-precision [--quick] [--out DIR] [--img DIR]``."""
    argv = sys.argv[1:] if argv is None else list(argv)
    a = quick_out_img_parser("work-precision", __doc__).parse_args(argv)
    run(a.quick, a.out, a.img, command=" ".join(["python -m bench work-precision", *argv]))
    return 0


def run(quick: bool, out: Path, img: Path, command: str = "python -m bench work-precision") -> dict:
    """Every problem, the targets, the CSVs, the metadata (``command`` is recorded in it) and the charts."""
    start = time.perf_counter()
    R.log("warming up compiled code ...")
    R.warm_up()
    tab = Table()
    meta: dict = dict(command=command, quick=quick, date=datetime.now(UTC).isoformat(timespec="seconds"),
                      machine=machine())
    run_p1(tab, quick)
    run_p2(tab, quick, meta)
    run_p3(tab, quick)
    run_p4(tab, quick)
    tgt, extra = targets(tab.rows, quick)
    out.mkdir(parents=True, exist_ok=True)
    with open(out / "work_precision.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        for r in tab.rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    with open(out / "targets.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(tgt[0]))
        w.writeheader()
        for r in tgt:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})
    meta.update(targets=tgt, details=extra, wall_total_s=time.perf_counter() - start)
    paths = charts(tab.rows, img)
    meta["charts"] = [str(p) for p in paths]
    (out / "work_precision.meta.json").write_text(json.dumps(meta, indent=2, default=str))
    for r in tgt:
        R.log(f"TARGET {r['target']}: {r['ratio']:.3g} (goal {r['goal']:g}) {'met' if r['met'] else 'NOT met'}")
    R.log(f"done in {time.perf_counter() - start:.1f} s")
    return meta
