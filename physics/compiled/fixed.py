"""Fixed-step explicit Runge-Kutta methods in compiled code; a method is its Butcher tableau.

Two methods, each a frozen ``ButcherTableau`` (its ``__post_init__`` checks that the weights sum to
one and that each row of A sums to its node c):

- ``RK4``: the classical 4-stage, order 4 method (what MuJoCo's RK4 integrator is).
- ``RK8``: the 12-stage, order 8 solution of Dormand-Prince 8(5,3) (Hairer's DOP853 coefficients,
  as shipped by scipy), used with a fixed step and no error estimate.

The compiled loop steps exactly onto the output times: each gap between outputs is cut into
``ceil(gap/dt)`` equal steps, so the step used is at most ``dt``. Braking (b > 0) ends the run as the
adaptive integrator does (physics/compiled/dop853.py): near the end steps are capped at half the time
|G| needs to vanish, so they close in on the braking time T geometrically, and the run stops when
|G|/G0 <= BRAKE_END. Statuses and their texts are dop853's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from .dispatch import braking_norm, fault, rhs, switch_chart
from .dop853 import BRAKE_END
from .tableau import DOP853 as _dop

WEIGHT_TOL = 1e-14  # the tableau's consistency conditions hold to rounding


@dataclass(frozen=True)
class ButcherTableau:
    """Explicit RK method: ``a`` (s, s) strictly lower triangular, weights ``b`` (s,), nodes ``c`` (s,)."""

    name: str
    order: int
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray

    def __post_init__(self):
        a, b, c = (np.ascontiguousarray(x, dtype=float) for x in (self.a, self.b, self.c))
        s = b.size
        if a.shape != (s, s) or c.shape != (s,):
            raise ValueError(f"{self.name}: a must be ({s}, {s}) and c ({s},)")
        if abs(b.sum() - 1.0) > WEIGHT_TOL:
            raise ValueError(f"{self.name}: weights sum to {b.sum()!r}, not 1")
        if np.any(np.abs(a.sum(axis=1) - c) > 1e3 * WEIGHT_TOL):
            raise ValueError(f"{self.name}: the rows of a do not sum to c")
        if np.any(np.triu(a) != 0):
            raise ValueError(f"{self.name}: a must be strictly lower triangular (explicit method)")
        object.__setattr__(self, "a", a)
        object.__setattr__(self, "b", b)
        object.__setattr__(self, "c", c)

    @property
    def stages(self) -> int:
        return self.b.size


RK4 = ButcherTableau(
    name="RK4", order=4,
    a=np.array([[0, 0, 0, 0], [0.5, 0, 0, 0], [0, 0.5, 0, 0], [0, 0, 1, 0]], dtype=float),
    b=np.array([1 / 6, 1 / 3, 1 / 3, 1 / 6]),
    c=np.array([0, 0.5, 0.5, 1.0]),
)

RK8 = ButcherTableau(
    name="RK8", order=8,
    a=_dop.A[:_dop.N_STAGES, :_dop.N_STAGES],
    b=_dop.B,
    c=_dop.C[:_dop.N_STAGES],
)

TABLEAUS = {t.name: t for t in (RK4, RK8)}


@njit(cache=True, nogil=True)
def integrate(model, y0, p, t_out, dt, A, Bw, C, b, lam, G0):
    """Fixed-step explicit RK with tableau (A, Bw, C), step at most ``dt`` (s), storing y at t_out.

    Returns (Y, n_filled, status, t_last, y_last, nfev, nsteps), as dop853.integrate without h.
    """
    n = y0.size
    n_out = t_out.size
    s = Bw.size
    Y = np.empty((n_out, n))
    y = y0.copy()
    switch_chart(model, y, p)  # a carried state in the coordinates this model's forces act on (pendulum.py)
    Y[0] = y
    t = t_out[0]
    K = np.empty((s, n))
    ys = np.empty(n)
    nfev = 0
    nsteps = 0
    status = 5 if fault(model, y, p) > 0 else 0  # a carried state where this model is undefined: no step
    i_out = 1
    while i_out < n_out and status == 0:
        t_target = t_out[i_out]
        gap = t_target - t
        m = max(1, int(math.ceil(gap / dt - 1e-9)))
        remaining = m
        while remaining > 0:
            h = (t_target - t) / remaining
            capped = False
            if b > 0.0:
                g = braking_norm(model, y, p)
                if g <= BRAKE_END * G0:
                    status = 1
                    break
                h_brake = 0.5 * g / (b + lam * g)
                if h_brake < h:
                    h = h_brake
                    capped = True
            if h <= 1e-14 * max(1.0, abs(t)):
                status = 3
                break
            for j in range(s):
                for i in range(n):
                    acc = 0.0
                    for k in range(j):
                        acc += A[j, k] * K[k, i]
                    ys[i] = y[i] + h * acc
                rhs(model, t + C[j] * h, ys, p, K[j])
            nfev += s
            finite = True
            for i in range(n):
                acc = 0.0
                for j in range(s):
                    acc += Bw[j] * K[j, i]
                y[i] += h * acc
                if not math.isfinite(y[i]):
                    finite = False
            t += h
            nsteps += 1
            if not capped:
                remaining -= 1
            if not finite:
                status = 2
                break
            switch_chart(model, y, p)  # the spherical pendulum near its gimbal pole: the other chart
            if fault(model, y, p) > 0:
                status = 5
                break
        if status != 0:
            break
        t = t_target
        for i in range(n):
            Y[i_out, i] = y[i]
        i_out += 1
    return Y, i_out, status, t, y, nfev, nsteps


def run(tableau: ButcherTableau, model: int, y0, p, t_out, dt: float, b: float = 0.0, lam: float = 0.0,
        G0: float = 1.0):
    """Python-facing wrapper: the tableau's arrays into the compiled loop."""
    return integrate(model, np.ascontiguousarray(y0, dtype=float), p, np.ascontiguousarray(t_out, dtype=float),
                     float(dt), tableau.a, tableau.b, tableau.c, float(b), float(lam), float(G0))
