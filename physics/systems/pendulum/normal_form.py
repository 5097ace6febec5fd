"""The full spherical-pendulum equations averaged numerically: a prediction of the full model's nutation angle that
the averaged model's error estimate reads (physics/systems/pendulum/accuracy.py, docs/models.md B.10).

The averaged model of B.6 is linear in the amplitudes, and what it misses beyond exact linear theory (the spin-up,
the pivot's hardening, the arm's shortening, the Cardan kinematics...) is nonlinear. Rather than model each effect,
the full equations themselves (the compiled right-hand side of physics/compiled/pendulum.py) are averaged:

1. Linearise the full equations about steady spin (central differences, the carrier's transverse rates and the
   bob's angles and rates: six states) and take their three oscillating modes, exponents ``lam_k`` and vectors
   ``v_k``; the two nearest in frequency (the carrier's nutation and the bob's tuned mode) turn with one common
   phase ``phi`` at their mean frequency, the third with its own phase ``psi``.
2. With the state ``x = 2 Re((b_0 v_0 + b_1 v_1) e^{i phi} + b_2 v_2 e^{i psi})`` and the spin ``w``, the slow
   amplitudes obey ``b_k' = (lam_k - i rot_k) b_k + <L_k N(x, w) e^{-i phase_k}>``, ``w' = <f_w(x, w)>``, where
   ``N = f - J x`` is what the full equations add to their linearisation and ``< >`` averages over a grid of both
   phases (first-order averaging; the near-resonant pair keeps its slow beat).
3. That averaged field is sampled at PROBES_PER_TERM x (number of terms) random slow states spanning the run's
   amplitudes and fitted (least squares) by every monomial of degree 3 and 5 that the phases let through (``b_i
   b_j conj(b_l)``, ``... |b_2|^2``, ``... (w - W)``, ...). A cubic alone misses up to 20 % of the nonlinear part at
   a swing of 0.2 rad; the quintic fit reproduces the sampled field to ~1e-3 and its prediction to ~1 %.
4. The polynomial system is integrated (Dormand-Prince 5(4), compiled) and the state rebuilt at the linear phases,
   so the prediction keeps linear theory's ripple; theta is the angle between the body's e3 and the momentum the
   compiled model computes, as the full model reports it.

With its fitted terms left out it is exact linear theory, and its nonlinear part scales with theta0^3 as the full
model's does: on calibration scenario 191 (python -m bench fidelity, seed 15), a bob hung near the centre of mass,
at a quarter of its theta0 both depart from linear theory by 3.64 theta0^3
(tests/test_pendulum_normal_form.py), where the averaged equations with following coefficients
(bench/pendulum_prediction.py) gave about half the full model's departure (1.9 against 3.5 theta0^3, read their way).

``predict`` returns None where it does not apply: no three oscillating modes (an overdamped bob), eigenvectors
nearly parallel (a coalescing resonance), a fit that does not reproduce the sampled field, amplitudes that leave the
fitted range, or more than MAX_STEPS steps.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from physics.compiled import pendulum as kernel

TRANSVERSE = (0, 1, 3, 4, 5, 6)  # the full state's carrier rates w1, w2 and the bob's angles and rates; 2 is the spin
N_PHASE, N_PHASE_3 = 8, 6  # grid of the common phase and of the third mode's: no degree-5 term aliases onto the mean
DEGREES = (3, 5)
PROBES_PER_TERM = 3
RANGE = 1.3  # the probes reach this many times each mode's starting amplitude
FLOOR = 0.3  # ... and at least this share of the largest, for a mode that starts near zero
FIT_MAX = 5e-3  # the largest relative residual of the fit that is trusted (module docstring)
CONDITION_MAX = 1e6  # the eigenvector matrix's largest condition number that is trusted
RTOL = 1e-7  # the predicted gaps move by under 1 % from 1e-8 (python -m bench fidelity's rows), in 2/3 of the steps
MAX_STEPS = 200_000  # about a second of the compiled integrator


def _exponents(degrees, harmonic_common: int, harmonic_third: int) -> np.ndarray:
    """Rows (n0, n1, n2, m0, m1, m2, k): b0^n0 b1^n1 b2^n2 conj(b0)^m0 conj(b1)^m1 conj(b2)^m2 (w - W)^k, every
    monomial of a degree in ``degrees`` (k counts twice: w - W is of second order) whose phases average through."""
    rows = []
    top = max(degrees)
    for e in itertools.product(range(top + 1), repeat=6):
        for k in range(top // 2 + 1):
            n0, n1, n2, m0, m1, m2 = e
            if (sum(e) + 2 * k in degrees and n0 + n1 - m0 - m1 == harmonic_common
                    and n2 - m2 == harmonic_third):
                rows.append((*e, k))
    return np.array(rows, dtype=np.int64)


TERMS_PAIR = _exponents(DEGREES, 1, 0)  # the near-resonant pair's amplitudes b_0, b_1
TERMS_THIRD = _exponents(DEGREES, 0, 1)  # the third mode's b_2
TERMS_SPIN = _exponents(tuple(d - 1 for d in DEGREES), 0, 0)  # the spin's rate, real


@njit(cache=True)
def _full_rates(x7, p, y, out):
    for i in range(7):
        y[i] = x7[i]
    kernel.rhs(0.0, y, p, out)


@njit(cache=True)
def _state(b0, b1, b2, w, V, e1, e3, x7):
    for r in range(6):
        z = (b0 * V[r, 0] + b1 * V[r, 1]) * e1 + b2 * V[r, 2] * e3
        x7[TRANSVERSE[r]] = 2.0 * z.real
    x7[2] = w


@njit(cache=True)
def _averaged_field(b, w, p, J, V, L, E1, E3, out):
    """The phase average of what the full equations add to their linearisation, projected on the modes: out[0:3]
    complex for b, and the spin's rate (returned)."""
    y = np.zeros(13)
    y[7] = 1.0  # the attitude's quaternion: the rates do not depend on it
    f = np.zeros(13)
    x7 = np.zeros(7)
    spin = 0.0
    for k in range(3):
        out[k] = 0.0
    n = E1.size
    for g in range(n):
        _state(b[0], b[1], b[2], w, V, E1[g], E3[g], x7)
        _full_rates(x7, p, y, f)
        spin += f[2]
        for r in range(6):
            lin = 0.0
            for c in range(6):
                lin += J[r, c] * x7[TRANSVERSE[c]]
            extra = f[TRANSVERSE[r]] - lin
            out[0] += L[0, r] * extra * E1[g].conjugate()
            out[1] += L[1, r] * extra * E1[g].conjugate()
            out[2] += L[2, r] * extra * E3[g].conjugate()
    for k in range(3):
        out[k] /= n
    return spin / n


@njit(cache=True)
def _monomials(E, b0, b1, b2, dw, out):
    for r in range(E.shape[0]):
        v = complex(1.0, 0.0)
        for _ in range(E[r, 0]):
            v *= b0
        for _ in range(E[r, 1]):
            v *= b1
        for _ in range(E[r, 2]):
            v *= b2
        for _ in range(E[r, 3]):
            v *= b0.conjugate()
        for _ in range(E[r, 4]):
            v *= b1.conjugate()
        for _ in range(E[r, 5]):
            v *= b2.conjugate()
        for _ in range(E[r, 6]):
            v *= dw
        out[r] = v


@njit(cache=True)
def _sample(B, dW, W, p, J, V, L, E1, E3):
    """The averaged field at each probe (B[q] the three amplitudes, W + dW[q] the spin) and the monomials there."""
    n = B.shape[0]
    G = np.empty((n, 3), np.complex128)
    GS = np.empty(n)
    MP = np.empty((n, TERMS_PAIR.shape[0]), np.complex128)
    M3 = np.empty((n, TERMS_THIRD.shape[0]), np.complex128)
    MS = np.empty((n, TERMS_SPIN.shape[0]), np.complex128)
    field = np.zeros(3, np.complex128)
    for q in range(n):
        GS[q] = _averaged_field(B[q], W + dW[q], p, J, V, L, E1, E3, field)
        G[q] = field
        _monomials(TERMS_PAIR, B[q, 0], B[q, 1], B[q, 2], dW[q], MP[q])
        _monomials(TERMS_THIRD, B[q, 0], B[q, 1], B[q, 2], dW[q], M3[q])
        _monomials(TERMS_SPIN, B[q, 0], B[q, 1], B[q, 2], dW[q], MS[q])
    return G, GS, MP, M3, MS


@njit(cache=True)
def _rates(y, mu, W, C0, C1, C2, CW, mp, m3, ms, out):
    b0, b1, b2, dw = complex(y[0], y[3]), complex(y[1], y[4]), complex(y[2], y[5]), y[6] - W
    _monomials(TERMS_PAIR, b0, b1, b2, dw, mp)
    _monomials(TERMS_THIRD, b0, b1, b2, dw, m3)
    _monomials(TERMS_SPIN, b0, b1, b2, dw, ms)
    d0, d1, d2 = mu[0] * b0, mu[1] * b1, mu[2] * b2
    for i in range(mp.size):
        d0 += C0[i] * mp[i]
        d1 += C1[i] * mp[i]
    for i in range(m3.size):
        d2 += C2[i] * m3[i]
    s = 0.0
    for i in range(ms.size):
        s += (CW[i] * ms[i]).real
    out[0], out[1], out[2] = d0.real, d1.real, d2.real
    out[3], out[4], out[5] = d0.imag, d1.imag, d2.imag
    out[6] = s


@njit(cache=True)
def _integrate(y0, t_out, mu, W, C0, C1, C2, CW, reach, spin_reach, rtol, atol, max_steps):
    """Dormand-Prince 5(4) with cubic Hermite output at t_out. Returns (Y (7, n), status, steps): status 0 done, 1 out
    of steps, 2 an amplitude or the spin left the fitted range."""
    n, m = y0.size, t_out.size
    mp = np.empty(TERMS_PAIR.shape[0], np.complex128)
    m3 = np.empty(TERMS_THIRD.shape[0], np.complex128)
    ms = np.empty(TERMS_SPIN.shape[0], np.complex128)
    Y = np.full((n, m), np.nan)
    Y[:, 0] = y0
    k1, k2, k3, k4 = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    k5, k6, k7 = np.empty(n), np.empty(n), np.empty(n)
    y = y0.copy()
    t = t_out[0]
    h = (t_out[-1] - t_out[0]) * 1e-4
    _rates(y, mu, W, C0, C1, C2, CW, mp, m3, ms, k1)
    j, steps = 1, 0
    while j < m:
        if steps >= max_steps:
            return Y, 1, steps
        if t + h > t_out[-1]:
            h = t_out[-1] - t
        _rates(y + h * (k1 / 5), mu, W, C0, C1, C2, CW, mp, m3, ms, k2)
        _rates(y + h * (3 / 40 * k1 + 9 / 40 * k2), mu, W, C0, C1, C2, CW, mp, m3, ms, k3)
        _rates(y + h * (44 / 45 * k1 - 56 / 15 * k2 + 32 / 9 * k3), mu, W, C0, C1, C2, CW, mp, m3, ms, k4)
        _rates(y + h * (19372 / 6561 * k1 - 25360 / 2187 * k2 + 64448 / 6561 * k3 - 212 / 729 * k4),
               mu, W, C0, C1, C2, CW, mp, m3, ms, k5)
        _rates(y + h * (9017 / 3168 * k1 - 355 / 33 * k2 + 46732 / 5247 * k3 + 49 / 176 * k4 - 5103 / 18656 * k5),
               mu, W, C0, C1, C2, CW, mp, m3, ms, k6)
        yn = y + h * (35 / 384 * k1 + 500 / 1113 * k3 + 125 / 192 * k4 - 2187 / 6784 * k5 + 11 / 84 * k6)
        _rates(yn, mu, W, C0, C1, C2, CW, mp, m3, ms, k7)
        err = h * (71 / 57600 * k1 - 71 / 16695 * k3 + 71 / 1920 * k4 - 17253 / 339200 * k5 + 22 / 525 * k6
                   - 1 / 40 * k7)
        scale = atol + rtol * np.maximum(np.abs(y), np.abs(yn))
        e = math.sqrt(np.mean((err / scale) ** 2))
        steps += 1
        if e <= 1.0:
            for k in range(3):
                if math.hypot(yn[k], yn[3 + k]) > reach[k]:
                    return Y, 2, steps
            if abs(yn[6] - W) > spin_reach:
                return Y, 2, steps
            tn = t + h
            while j < m and t_out[j] <= tn:
                s = (t_out[j] - t) / h
                Y[:, j] = ((2 * s ** 3 - 3 * s ** 2 + 1) * y + (s ** 3 - 2 * s ** 2 + s) * h * k1
                           + (3 * s ** 2 - 2 * s ** 3) * yn + (s ** 3 - s ** 2) * h * k7)
                j += 1
            t, y = tn, yn
            k1[:] = k7
        h *= min(5.0, max(0.2, 0.9 * e ** -0.2 if e > 0 else 5.0))
    return Y, 0, steps


@njit(cache=True)
def _thetas(Y, t, p, V, rot):
    """The nutation angle of the rebuilt full state at each time: the angle between e3 and the momentum."""
    out = np.empty(t.size)
    y = np.zeros(13)
    y[7] = 1.0
    x7 = np.zeros(7)
    for k in range(t.size):
        e1 = complex(math.cos(rot[0] * t[k]), math.sin(rot[0] * t[k]))
        e3 = complex(math.cos(rot[2] * t[k]), math.sin(rot[2] * t[k]))
        _state(complex(Y[0, k], Y[3, k]), complex(Y[1, k], Y[4, k]), complex(Y[2, k], Y[5, k]), Y[6, k], V, e1, e3,
               x7)
        for i in range(7):
            y[i] = x7[i]
        H = kernel.momentum(y, p)
        out[k] = math.atan2(math.hypot(H[0], H[1]), H[2])
    return out


@dataclass(frozen=True)
class Prediction:
    """The predicted full-model theta (rad) at the times asked, and how it was obtained: the fit's relative residual
    and the integrator's steps."""

    theta: np.ndarray
    fit_residual: float
    steps: int


def _rates_at(x7: np.ndarray, p: np.ndarray) -> np.ndarray:
    y = np.zeros(13)
    y[7] = 1.0
    out = np.zeros(13)
    _full_rates(np.asarray(x7, dtype=float), p, y, out)
    return out[:7]


def predict(p: np.ndarray, w0, t: np.ndarray, seed: int = 0, terms: bool = True) -> Prediction | None:
    """The full model's theta at times ``t`` (s, increasing from 0) for the compiled parameters ``p`` of one spherical
    pendulum (physics/systems/pendulum/models.py ``pack``), the carrier started at body rates ``w0`` with the bob at
    rest on its axis; None where the prediction does not apply (module docstring). ``seed`` draws the probes;
    ``terms=False`` leaves the fitted terms out: exact linear theory, read through the same steps."""
    W = float(w0[2])
    if not W or not all(map(math.isfinite, (float(w0[0]), float(w0[1]), W))):
        return None
    rest = np.array([0.0, 0.0, W, 0.0, 0.0, 0.0, 0.0])
    if not np.all(np.abs(_rates_at(rest, p)) <= 1e-9 * W * W):  # steady spin must be a rest point of the equations
        return None
    scale = np.array([abs(W)] * 3 + [1.0, 1.0] + [abs(W)] * 2)
    J7 = np.empty((7, 7))
    for j in range(7):
        h = 1e-5 * scale[j]
        e = np.zeros(7)
        e[j] = h
        J7[:, j] = (_rates_at(rest + e, p) - _rates_at(rest - e, p)) / (2 * h)
    J = np.ascontiguousarray(J7[np.ix_(TRANSVERSE, TRANSVERSE)])
    lam, V = np.linalg.eig(J)
    if not np.all(np.isfinite(lam)) or np.linalg.cond(V) > CONDITION_MAX:
        return None
    L = np.linalg.inv(V)
    turning = np.flatnonzero(lam.imag > 1e-9 * np.abs(lam))
    if turning.size != 3:
        return None
    lam, V, L = lam[turning], V[:, turning], L[turning]
    pair = min(((0, 1, 2), (0, 2, 1), (1, 2, 0)), key=lambda q: abs(lam[q[0]].imag - lam[q[1]].imag))
    lam, V, L = lam[list(pair)], np.ascontiguousarray(V[:, list(pair)]), np.ascontiguousarray(L[list(pair)])
    common = 0.5 * (lam[0].imag + lam[1].imag)
    rot = np.array([common, common, lam[2].imag])
    mu = lam - 1j * rot
    c0 = L @ np.array([float(w0[0]), float(w0[1]), 0.0, 0.0, 0.0, 0.0])
    size = np.abs(c0)
    if not size.max() > 0:
        return None
    reach = np.maximum(RANGE * size, FLOOR * size.max())
    theta0 = math.atan2(math.hypot(float(w0[0]), float(w0[1])), abs(W))  # the order of the nutation
    spin_reach = 2.0 * abs(W) * max(1.0 - math.cos(theta0), 1e-12)
    g1 = np.exp(2j * np.pi * np.arange(N_PHASE) / N_PHASE)
    g3 = np.exp(2j * np.pi * np.arange(N_PHASE_3) / N_PHASE_3)
    E1, E3 = np.repeat(g1, N_PHASE_3), np.tile(g3, N_PHASE)
    t = np.ascontiguousarray(t, dtype=float)
    y0 = np.concatenate([c0.real, c0.imag, [W]])
    if not terms:
        zero = np.zeros(len(TERMS_PAIR), complex)
        Y, status, steps = _integrate(y0, t, mu, W, zero, zero, np.zeros(len(TERMS_THIRD), complex),
                                      np.zeros(len(TERMS_SPIN), complex), reach * 1.05, spin_reach, RTOL,
                                      1e-12 * float(size.max()), MAX_STEPS)
        return Prediction(theta=_thetas(Y, t, p, V, rot), fit_residual=0.0, steps=int(steps)) if status == 0 else None
    n = PROBES_PER_TERM * max(len(TERMS_PAIR), len(TERMS_THIRD), len(TERMS_SPIN))
    u = np.random.default_rng(seed).random((n, 7))  # per probe: three magnitudes, three phases, the spin
    B = reach * np.sqrt(u[:, :3]) * np.exp(2j * np.pi * u[:, 3:6])
    dW = -spin_reach + 2.0 * spin_reach * u[:, 6]
    G, GS, MP, M3, MS = _sample(B, dW, W, p, J, V, L, E1, E3)
    if not (np.all(np.isfinite(G)) and np.all(np.isfinite(GS))):
        return None
    C01 = np.linalg.lstsq(MP, G[:, :2], rcond=None)[0]  # one factorisation for the pair's two amplitudes
    C0, C1 = np.ascontiguousarray(C01[:, 0]), np.ascontiguousarray(C01[:, 1])
    C2 = np.linalg.lstsq(M3, G[:, 2], rcond=None)[0]
    real = np.linalg.lstsq(np.hstack([MS.real, -MS.imag]), GS, rcond=None)[0]  # Re(c m) with c complex, m complex
    CW = real[:len(TERMS_SPIN)] + 1j * real[len(TERMS_SPIN):]
    residual = max(_relative(MP @ C0, G[:, 0]), _relative(MP @ C1, G[:, 1]), _relative(M3 @ C2, G[:, 2]),
                   _relative((MS @ CW).real, GS))
    if not residual <= FIT_MAX:
        return None
    Y, status, steps = _integrate(y0, t, mu, W, C0, C1, C2, CW, reach * 1.05, spin_reach, RTOL,
                           1e-12 * float(size.max()), MAX_STEPS)
    if status != 0:
        return None
    theta = _thetas(Y, t, p, V, rot)
    return Prediction(theta=theta, fit_residual=float(residual), steps=int(steps)) if np.all(
        np.isfinite(theta)) else None


def _relative(fit: np.ndarray, data: np.ndarray) -> float:
    size = float(np.linalg.norm(data))
    return float(np.linalg.norm(fit - data)) / size if size > 0 else 0.0
