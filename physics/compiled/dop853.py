"""Adaptive Dormand-Prince 8(5,3) in compiled code, stepping exactly onto the output times.

The tableau is data (scipy ships the coefficients of Hairer's DOP853); the step-size control is
scipy's (the same error norm and factors), so ``method="auto"`` and scipy's DOP853 make the same
accuracy promise at a fraction of the cost of a Python right-hand side.

The run stops early, with a status, when the braking law's |G| reaches zero (the end of
time-optimal braking: steps are capped at half the time |G| needs to vanish, so they close in on
T geometrically), when the state stops being finite, or when the step size underflows.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .dispatch import braking_norm, fault, rhs, switch_chart
from .tableau import DOP853 as _dop

N_STAGES = _dop.N_STAGES
A_TAB = np.ascontiguousarray(_dop.A[:N_STAGES, :N_STAGES])
B_TAB = np.ascontiguousarray(_dop.B)
C_TAB = np.ascontiguousarray(_dop.C[:N_STAGES])
E3 = np.ascontiguousarray(_dop.E3)
E5 = np.ascontiguousarray(_dop.E5)

SAFETY = 0.9  # scipy's: keeps the next step comfortably inside the error bound
MIN_FACTOR = 0.2  # never shrink a step by more than 5x at once
MAX_FACTOR = 10.0  # nor grow it by more than 10x
ERROR_EXPONENT = -1.0 / 8.0  # error estimator order 7
BRAKE_END = 1e-13  # |G|/G0 at which braking has ended (relative)

OK, BRAKED, NONFINITE, UNDERFLOW, MAX_STEPS, MODEL_FAULT = 0, 1, 2, 3, 4, 5
STATUS_TEXT = {
    OK: "reached t_end",
    BRAKED: "braking brought |G| to zero",
    NONFINITE: "state became non-finite (NaN or infinity)",
    UNDERFLOW: "step size underflow",
    MAX_STEPS: "too many steps",
    MODEL_FAULT: "the spherical pendulum with a spring (k > 0) reached the gimbal singularity of its Cardan angles, "
                 'where a spring on them is undefined: set pendulum.pivot = "isotropic" (spring and damper on the '
                 "arm's direction) to go on through the pole (|beta| -> 90 deg)",
}


@njit(cache=True, nogil=True)
def integrate(model, y0, p, t_out, rtol, atol, b, lam, max_steps, h0, G0):
    """Integrate from t_out[0] and store the state at each t_out.

    ``h0`` > 0 continues with a known step size (a run split into chunks), otherwise a first step
    is guessed. ``G0`` is the initial |G| that the braking end is measured against.
    Returns (Y, n_filled, status, t_last, y_last, nfev, nsteps, h): Y[:n_filled] are valid; on an
    early stop, (t_last, y_last) is the last accepted state; h is the step size to continue with.
    """
    n = y0.size
    n_out = t_out.size
    Y = np.empty((n_out, n))
    y = y0.copy()
    switch_chart(model, y, p)  # a carried state in the coordinates this model's forces act on (pendulum.py)
    Y[0] = y
    t = t_out[0]
    K = np.empty((N_STAGES + 1, n))
    ys = np.empty(n)
    y_new = np.empty(n)
    f = np.empty(n)
    rhs(model, t, y, p, f)
    nfev = 1
    nsteps = 0
    status = 5 if fault(model, y, p) > 0 else 0  # a carried state where this model is undefined: no step

    # initial step from the size of y and f (Hairer's first guess, simplified)
    d0 = 0.0
    d1 = 0.0
    for i in range(n):
        sc = atol + abs(y[i]) * rtol
        d0 += (y[i] / sc) ** 2
        d1 += (f[i] / sc) ** 2
    d0 = math.sqrt(d0 / n)
    d1 = math.sqrt(d1 / n)
    h = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    if h0 > 0.0:
        h = h0
    span = t_out[n_out - 1] - t
    h = min(h, span) if span > 0 else h

    i_out = 1
    nonfinite = 0
    while i_out < n_out and status == 0:
        if nsteps >= max_steps:
            status = 4
            break
        t_target = t_out[i_out]
        h_try = min(h, t_target - t)
        if b > 0.0:
            g = braking_norm(model, y, p)
            if g <= BRAKE_END * G0:
                status = 1
                break
            h_try = min(h_try, 0.5 * g / (b + lam * g))
        if h_try <= 1e-14 * max(1.0, abs(t)):
            status = 3
            break
        # stages
        for i in range(n):
            K[0, i] = f[i]
        for s in range(1, N_STAGES):
            for i in range(n):
                acc = 0.0
                for j in range(s):
                    acc += A_TAB[s, j] * K[j, i]
                ys[i] = y[i] + h_try * acc
            rhs(model, t + C_TAB[s] * h_try, ys, p, K[s])
        for i in range(n):
            acc = 0.0
            for j in range(N_STAGES):
                acc += B_TAB[j] * K[j, i]
            y_new[i] = y[i] + h_try * acc
        rhs(model, t + h_try, y_new, p, K[N_STAGES])
        nfev += N_STAGES
        # error estimate (scipy's DOP853 norm)
        e5 = 0.0
        e3 = 0.0
        for i in range(n):
            sc = atol + max(abs(y[i]), abs(y_new[i])) * rtol
            a5 = 0.0
            a3 = 0.0
            for j in range(N_STAGES + 1):
                a5 += E5[j] * K[j, i]
                a3 += E3[j] * K[j, i]
            e5 += (a5 / sc) ** 2
            e3 += (a3 / sc) ** 2
        if e5 == 0.0 and e3 == 0.0:
            err = 0.0
        else:
            err = h_try * e5 / math.sqrt((e5 + 0.01 * e3) * n)
        if not math.isfinite(err):
            # a non-finite trial: shrink hard; if even tiny steps blow up, the model has
            nonfinite += 1
            if nonfinite >= 40:
                status = 2
                break
            h = h_try * MIN_FACTOR
            continue
        nonfinite = 0
        if err < 1.0:
            clipped = h_try < h
            t = t + h_try
            for i in range(n):
                y[i] = y_new[i]
                f[i] = K[N_STAGES, i]
            nsteps += 1
            factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** ERROR_EXPONENT)
            if not clipped:
                h = h_try * factor
            if switch_chart(model, y, p) > 0:  # same motion, new coordinates: f of the first stage afresh
                rhs(model, t, y, p, f)
                nfev += 1
            if fault(model, y, p) > 0:
                status = 5
                break
            if t >= t_target - 1e-14 * max(1.0, abs(t_target)):
                t = t_target
                for i in range(n):
                    Y[i_out, i] = y[i]
                i_out += 1
        else:
            h = h_try * max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT)
    return Y, i_out, status, t, y, nfev, nsteps, h
