"""How far the wheel damper's closed form (the linear theory about steady spin, linear.py) strays from the full
model: an estimate of max |theta_closed - theta_full| over [0, t_end] (rad), from the terms it neglects.

With omega = n e3 + v and the wheel's rate Omega_w, u = (v, Omega_w), the full equations (docs/models.md C.1)
are exactly quadratic: Mm u' = F u - (v x (I v + J Omega_w a), 0), with Mm and F the linear theory's
(``linear.matrix``). The linear theory drops the quadratic term q(u) = -v x (I v + J Omega_w a) and nothing else.
So the full solution is u_lin + delta2 + delta3 + ..., delta2' = L delta2 + Mm^-1 (q(u_lin), 0) the
second-order response to the dropped term along the linear solution, delta3 the third-order one.

- ``second``: max |theta(u_lin + delta2) - theta(u_lin)|. delta2 is in closed form: u_lin is a sum of modes
  e^{s_k t}, so the forcing is a sum over pairs e^{(s_i + s_j) t}, each answered by every mode. It is what makes
  the error second order in theta0 when the wheel's axis leans towards e3 (then z and J a3 Omega_w y are first
  order) or the body is triaxial, and it holds the spin-up (the dropped quadratic terms feed z by a steady
  n theta0^2 / 2 as the nutation decays: the pair s + conj(s)).
- ``third``: the spin-up's effect on the nutation itself (third order: it moves the frequency and the decay
  rate by O(theta0^2) relative, so theta drifts by theta0^3 times the turns and e-folds the run sees). Measured
  the same way the pendulum's estimate measures its detuning: the linear theory again, from the spin it ends at
  (n / cos theta0) instead of n, over the run's horizon; max |theta_lin' - theta_lin|.

  Near the separatrix of a triaxial body (B close to C) the polhode's own frequency moves with the amplitude
  faster than the spin-up moves it, by ~1/sin^2 theta_s (theta_s the angle of the separatrix to e3,
  sin^2 theta_s = A (C - B) / (B (C - A)) for A <= B; 1 for A = B): ``third`` is scaled by that.

estimate = SAFETY (second + third / sin^2 theta_s) + FLOOR. The constants and the domain (``domain``) come from
the calibration study (``python -m bench fidelity --system wheel``, docs/models.md C.4); outside the domain the
estimate claims nothing (None: auto runs the full model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from physics.core.rotation import nutation_angle
from physics.registry import Condition
from physics.scenario.initial import initial_G
from physics.systems.wheel import linear

SAFETY = 2.0
FLOOR = 1e-8  # rad: the full model's own error at its default tolerance, over the study's longest runs
# The domain the study covers (each a Condition; the estimate claims nothing outside it)
DOMAIN_THETA0 = 0.1  # rad (the closed form's own validity limit, THETA_MAX)
DOMAIN_SEPARATRIX = 0.3  # theta0 / theta_s: a triaxial body's nutation stays well inside the separatrix
DOMAIN_TURNS = 3000.0  # nutation periods over the run
POINTS_PER_TURN = 16  # grid points per nutation period: theta's ripple peaks are seen
MIN_POINTS, MAX_POINTS = 1001, 40001
COND_MAX = 1e8  # the modes' eigenvector matrix above this condition: near-defective, no closed form here


@dataclass(frozen=True)
class Parts:
    """The estimate's parts (module docstring), rad."""

    second: float
    third: float
    sin2_separatrix: float  # sin^2 theta_s (module docstring), 1 for a symmetric body

    @property
    def bound(self) -> float:
        b = SAFETY * (self.second + self.third / self.sin2_separatrix) + FLOOR
        return b if math.isfinite(b) else math.inf


def _modes(L: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    lam, V = np.linalg.eig(L)
    if not np.linalg.cond(V) < COND_MAX:
        raise np.linalg.LinAlgError("near-defective modes")
    return lam, V, np.linalg.inv(V)


def _mode_integral(mu: complex, lam: np.ndarray, t: np.ndarray) -> np.ndarray:
    """int_0^t e^{lam (t - s)} e^{mu s} ds (n, m): (e^{mu t} - e^{lam t}) / (mu - lam), its series where
    (mu - lam) t is small (a resonance: the response grows like t)."""
    d = mu - lam[None, :]
    x = d * t[:, None]
    small = np.abs(x) < 1e-3
    el = np.exp(lam[None, :] * t[:, None])
    series = el * t[:, None] * (1 + x / 2 + x * x / 6 + x ** 3 / 24)
    safe = np.where(small, 1.0, d)
    return np.where(small, series, (np.exp(mu * t)[:, None] - el) / safe)


def _quadratic(u: np.ndarray, w: np.ndarray, I: np.ndarray, J: float, a: np.ndarray) -> np.ndarray:
    """The dropped term's symmetric bilinear form: q(u, w) with q(u, u) = -v x (I v + J Omega_w a), (3,)."""
    ku = I * u[:3] + J * u[3] * a
    kw = I * w[:3] + J * w[3] * a
    return -0.5 * (np.cross(u[:3], kw) + np.cross(w[:3], ku))


def second_order(b, wh, n: float, u0: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(u_lin, delta2) (n, 4) at times t: the linear solution from u0 and the second-order response to the dropped
    quadratic term along it, delta2(0) = 0."""
    I = np.array([b.A, b.B, b.C])
    a = np.array(wh.axis, dtype=float)
    L = linear.matrix(b.A, b.B, b.C, wh.J, wh.c, wh.axis, n)
    Mm = np.array([[b.A, 0, 0, wh.J * a[0]], [0, b.B, 0, wh.J * a[1]], [0, 0, b.C, wh.J * a[2]],
                   [*(wh.J * a), wh.J]])
    lam, V, Vi = _modes(L)
    coef = Vi @ u0.astype(complex)
    u_lin = np.real(np.exp(np.outer(t, lam)) * coef @ V.T)
    Mi = np.linalg.inv(Mm)
    delta = np.zeros((len(t), 4), dtype=complex)
    m = len(lam)
    for i in range(m):
        for j in range(i, m):
            vi, vj = coef[i] * V[:, i], coef[j] * V[:, j]
            f = (1.0 if i == j else 2.0) * (Mi @ np.append(_quadratic(vi, vj, I, wh.J, a), 0.0))
            g = Vi @ f
            delta += (_mode_integral(lam[i] + lam[j], lam, t) * g) @ V.T
    return u_lin, np.real(delta)


def _theta(u: np.ndarray, b, wh, n: float) -> np.ndarray:
    I = np.array([b.A, b.B, b.C])
    K = np.column_stack([u[:, 0], u[:, 1], n + u[:, 2]]) * I + wh.J * u[:, 3:4] * np.array(wh.axis)
    return nutation_angle(K)


def grid(sc, lam_max: float) -> np.ndarray:
    t_end = float(sc.run.t_end)
    n = int(np.clip(t_end * lam_max / (2 * math.pi) * POINTS_PER_TURN, MIN_POINTS, MAX_POINTS))
    return np.linspace(0.0, t_end, n)


@lru_cache(maxsize=128)  # auto's choice and derived ask for the same scenario's parts
def _parts(sc) -> Parts:
    b, wh = sc.body, sc.wheel
    w0, _, theta0 = initial_G(sc)
    n = float(w0[2])
    u0 = np.array([w0[0], w0[1], 0.0, 0.0])
    s = linear.exponents(sc)
    t = grid(sc, float(np.max(np.abs(s.imag))))
    u_lin, d2 = second_order(b, wh, n, u0, t)
    th = _theta(u_lin, b, wh, n)
    second = float(np.max(np.abs(_theta(u_lin + d2, b, wh, n) - th)))
    # the linear theory from the spin it ends at: the whole initial rotation scaled by 1/cos theta0
    f = 1.0 / math.cos(theta0)
    L = linear.matrix(b.A, b.B, b.C, wh.J, wh.c, wh.axis, n * f)
    d, _ = linear.perturbation(L, u0 * f, t)
    third = float(np.max(np.abs(_theta(d, b, wh, n * f) - th)))
    return Parts(second=second, third=third, sin2_separatrix=sin2_separatrix(sc))


def parts(sc) -> Parts:
    """The estimate's parts for a wheel scenario; inf where the modes are near-defective or overflow."""
    try:
        with np.errstate(all="ignore"):
            try:
                q = _parts(sc)
            except TypeError:  # a scenario that cannot be hashed (an array in it): computed afresh
                q = _parts.__wrapped__(sc)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        return Parts(math.inf, math.inf, 1.0)
    if not (math.isfinite(q.second) and math.isfinite(q.third)):
        return Parts(math.inf, math.inf, 1.0)
    return q


def sin2_separatrix(sc) -> float:
    """sin^2 of the separatrix's angle to e3 for spin about e3 (module docstring); <= 0 when C is not the
    largest moment (no separatrix around e3: the spin is not the one the sink leads to)."""
    A, B, C = sc.body.A, sc.body.B, sc.body.C
    lo, hi = min(A, B), max(A, B)
    return lo * (C - hi) / (hi * (C - lo)) if C > lo else -1.0


def turns(sc) -> float:
    """Nutation periods over [0, t_end] in the linear theory (0 when no mode oscillates)."""
    s = linear.exponents(sc)
    return float(np.max(np.abs(s.imag))) * float(sc.run.t_end) / (2 * math.pi)


def domain(sc) -> list[Condition]:
    """Where the estimate was calibrated: each a Condition (``holds`` inside)."""
    _, _, theta0 = initial_G(sc)
    s2 = sin2_separatrix(sc)
    theta_s = math.asin(math.sqrt(s2)) if s2 > 0 else 0.0
    return [Condition("theta0 (rad)", theta0, DOMAIN_THETA0),
            Condition("theta0 / separatrix angle", theta0 / theta_s if theta_s > 0 else math.inf,
                      DOMAIN_SEPARATRIX),
            Condition("nutation turns over t_end", turns(sc), DOMAIN_TURNS)]


def closed_error_bound(sc) -> float | None:
    """Estimated max |theta_closed - theta_full| (rad) over [0, t_end]; None outside the domain. The closed
    form's own conditions are the caller's to check (system.error_bounds)."""
    if any(not c.holds for c in domain(sc)):
        return None
    b = parts(sc).bound
    return b if math.isfinite(b) else None


METHOD = ("the closed form's second-order response to the quadratic terms it drops, plus the spin-up's third-"
          "order drift of the nutation over [0, t_end], x" f"{SAFETY:g} safety; calibrated against the full model "
          "(python -m bench fidelity --system wheel, docs/models.md C.4)")
