"""One way to run each method on each problem, timed, returning (Y or trajectory, nfev, steps, wall_s).

Every runner takes the output times and returns states at them. Compiled code is warmed up
(``warm_up``) before anything is timed, so numba's compile and cache load are not counted.
"""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np
from scipy.integrate import BDF, DOP853, LSODA, RK45, Radau

import physics
from physics.compiled import dispatch, dop853, fixed, midpoint
from physics.stepping.simulate import ATOL_FACTOR

SCIPY = {"DOP853": DOP853, "RK45": RK45, "Radau": Radau, "BDF": BDF, "LSODA": LSODA}


def log(msg: str) -> None:
    """Progress on stderr, so a long run shows where it is."""
    print(msg, file=sys.stderr, flush=True)


def save_figure(fig, path, title: str | None = None) -> None:
    """Title, tidy, write at the charts' common resolution, and free the figure."""
    import matplotlib.pyplot as plt

    if title:
        fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def atol_for(rtol: float, y0: np.ndarray) -> float:
    """The project's absolute tolerance rule (physics.simulate), used for every peer too."""
    return rtol * ATOL_FACTOR * max(1.0, float(np.max(np.abs(y0))))


def scipy_run(fun, t, y0, method: str, rtol: float, atol: float):
    """scipy's OdeSolver stepped by hand (as solve_ivp does), to count steps as well as nfev.
    Returns (Y (n, ny), nfev, steps, wall_s)."""
    start = time.perf_counter()
    solver = SCIPY[method](fun, t[0], y0, t[-1], rtol=rtol, atol=atol)
    Y = np.empty((len(t), len(y0)))
    Y[0] = y0
    i = 1
    steps = 0
    while solver.status == "running" and i < len(t):
        solver.step()
        steps += 1
        if solver.status == "failed":
            raise RuntimeError(f"scipy {method}: {solver.status}")
        if solver.t >= t[i]:
            dense = solver.dense_output()
            while i < len(t) and t[i] <= solver.t:
                Y[i] = dense(t[i])
                i += 1
    return Y, solver.nfev, steps, time.perf_counter() - start


def compiled_dop853(kernel: int, y0, p, t, rtol: float, atol: float | None = None):
    start = time.perf_counter()
    atol = atol_for(rtol, y0) if atol is None else atol
    Y, n, status, *_, nfev, steps, _h = dop853.integrate(kernel, y0, p, t, rtol, atol, 0.0, 0.0, 10**9, 0.0, 1.0)
    if status != dop853.OK:
        raise RuntimeError(dop853.STATUS_TEXT[status])
    return Y, int(nfev), int(steps), time.perf_counter() - start


def compiled_fixed(method: str, kernel: int, y0, p, t, dt: float):
    start = time.perf_counter()
    if method == "midpoint":
        Y, n, status, _, _, nfev, steps = midpoint.integrate(y0, p, t, dt)
    else:
        Y, n, status, _, _, nfev, steps = fixed.run(fixed.TABLEAUS[method], kernel, y0, p, t, dt)
    wall = time.perf_counter() - start
    if status != dop853.OK or n < len(t):
        Y = np.full((len(t), len(y0)), np.nan)  # unstable: no error to report
    return Y, int(nfev), int(steps), wall


def simulate_run(sc: physics.Scenario, method: str, **run):
    """physics.simulate with [run] overrides; returns (trajectory, nfev, steps, wall_s)."""
    sc = sc.with_values(**{f"run.{k}": v for k, v in run.items()}, **{"run.method": method})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", physics.ValidityWarning)
        start = time.perf_counter()
        tr = physics.simulate(sc)
        wall = time.perf_counter() - start
    return tr, int(tr.info["nfev"]), int(tr.info["steps"] or 0), wall


def warm_up() -> None:
    """Compile (or load from numba's cache) every kernel path the benchmark times."""
    from physics.reference import problems as P

    t = np.linspace(0.0, 1.0, 3)
    y0, p = P.p1_initial(), P.p1_params()
    compiled_dop853(dispatch.MASS_FULL, y0, p, t, 1e-8)
    for m in ("RK4", "RK8", "midpoint"):
        compiled_fixed(m, dispatch.MASS_FULL, y0, p, t, 0.1)
    for sc in (P.p2(1.0), P.p4(1.0, samples=3)):
        for m, extra in (("auto", {}), ("RK4", {"dt": 0.1}), ("RK8", {"dt": 0.1})):
            simulate_run(sc, m, **extra)
    simulate_run(P.p3(samples=3), "auto")
    simulate_run(P.p3(samples=3), "RK4", dt=1.0)
