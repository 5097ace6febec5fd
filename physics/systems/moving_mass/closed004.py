"""Closed forms of seed 004 (Zinkevich, Kozachenko, Rachinskaya & Leshchenko): optimal braking of a
symmetric body carrying a viscoelastic point mass and a viscous-fluid cavity in a resisting medium.

All functions take plain floats (the coefficients of docs/models.md A.3, seed 004 eq. (4)) and numpy arrays
of times, and return arrays of the same length as ``t``. Units: SI; times in s, angles in rad, moments
of inertia in kg m^2, angular momenta in kg m^2/s. Times must be >= 0; times after the braking time T
give the values at T (the body is at rest and nothing moves any more).

Notation (docs/models.md A.1, A.4): G = |J* w| with J* = diag(A, A, C); theta is the angle between G and e3;
E = lam G0 + b; I_n(t) = int_0^t G^n ds. The small private solvers at the end are shared with
``closed000``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import numpy as np

from physics.core.guarded import guarded

# Taylor terms of G(s) used by momentum_power_integral for lam t < 1: the coefficient of s^j in G^n,
# scaled by t^j, is below n^j / j! times G0^n, so 60 terms leave < 1e-30 for n <= 6.
_TAYLOR_TERMS = 60
_MAX_POWER = 6
_ODE_ATOL = 1e-14
# right sides the integration of (13) may take: every shipped scene takes 92-941 (fidelity closed). Not the run's
# step budget: in u = ln|tan theta| (13) is slow and smooth, and a run that crawls here (body.C = 1e-100 makes its
# rates 1e100 times the scene's) took 0.69 s for 100000 calls, so about 2.3 minutes to reach the budget's 2e7
_MAX_CALLS = 100_000


def _times(t) -> np.ndarray:
    t = np.asarray(t, dtype=float)
    if t.ndim != 1:
        t = np.atleast_1d(t)
        if t.ndim != 1:
            raise ValueError(f"t must be a 1-D array of times, got shape {t.shape}")
    if np.any(~np.isfinite(t)) or np.any(t < 0):
        raise ValueError("t must hold finite times >= 0")
    return t


# ---- modulus of the angular momentum ----------------------------------------------------------------

def braking_time(G0: float, b: float, lam: float) -> float:
    """Time-optimal braking time T, s: seed 004 eq. (10), T = (1/lam) ln(1 + G0 lam / b).

    Evaluated as (G0/b) log1p(x)/x with x = G0 lam / b (docs/models.md A.4) so that lam -> 0 tends smoothly
    to T = G0/b, seed 000 eq. (3.4); a series is used for |x| < 1e-8, where log1p(x)/x loses digits to
    the division. b = 0 (no control) gives inf.
    """
    if b < 0 or lam < 0 or G0 < 0:
        raise ValueError(f"braking_time needs G0, b, lam >= 0, got {G0!r}, {b!r}, {lam!r}")
    if b == 0:
        return math.inf
    x = G0 * lam / b
    if abs(x) < 1e-8:
        return (G0 / b) * (1.0 - x / 2.0 + x * x / 3.0)
    return (G0 / b) * math.log1p(x) / x


def momentum_modulus(t, G0: float, b: float, lam: float) -> np.ndarray:
    """G(t) = G0 e^{-lam t} - b (1 - e^{-lam t})/lam, kg m^2/s, seed 004 eq. (10); shape of t.

    Written with expm1 so lam -> 0 is exact (lam = 0 gives G0 - b t, seed 000 eq. (3.4)). G = 0 from the
    braking time T on (the control switches off when the body stops).
    """
    t = _times(t)
    T = braking_time(G0, b, lam)
    if lam == 0:
        G = G0 - b * t
    else:
        G = G0 * np.exp(-lam * t) + b * np.expm1(-lam * t) / lam
    return np.where(t >= T, 0.0, np.maximum(G, 0.0))


def _momentum_scalar(s: float, G0: float, b: float, lam: float) -> float:
    if lam == 0:
        G = G0 - b * s
    else:
        G = G0 * math.exp(-lam * s) + b * math.expm1(-lam * s) / lam
    return G if G > 0 else 0.0


def momentum_power_integral(t, G0: float, b: float, lam: float, n: int) -> np.ndarray:
    """I_n(t) = int_0^t G(s)^n ds, units (kg m^2/s)^n s, for integer 1 <= n <= 6; shape of t.

    Closed forms of docs/models.md A.4 (I2, I4; the general n comes from the binomial expansion of
    G = (E e^{-lam s} - b)/lam). These cancel catastrophically when lam t is small, so there:
    - lam = 0: I_n = (G0^{n+1} - G^{n+1}) / ((n+1) b), evaluated as t sum_j G0^{n-j} G^j / (n+1),
      a sum of positive terms (also covers b = 0);
    - b = 0: I_n = -G0^n expm1(-n lam t) / (n lam);
    - lam t < 1: the Taylor series of G(s) (g_0 = G0, g_k = -E (-lam)^{k-1}/k!) raised to the n-th power
      by polynomial multiplication and integrated term by term.
    Accurate to ~1e-15 relative; times after the braking time give I_n(T).
    """
    if int(n) != n or not 1 <= n <= _MAX_POWER:
        raise ValueError(f"n must be an integer in 1..{_MAX_POWER}, got {n!r}")
    n = int(n)
    t = np.minimum(_times(t), braking_time(G0, b, lam))
    if lam == 0:
        G = G0 - b * t
        return t * sum(G0 ** (n - j) * G**j for j in range(n + 1)) / (n + 1)
    if b == 0:
        return -(G0**n) * np.expm1(-n * lam * t) / (n * lam)
    E = lam * G0 + b
    out = np.empty_like(t)
    near = lam * t < 1.0
    if np.any(near):
        g = np.empty(_TAYLOR_TERMS + 1)
        g[0], g[1] = G0, -E
        for k in range(2, _TAYLOR_TERMS + 1):
            g[k] = g[k - 1] * (-lam) / k
        p = np.ones(1)
        for _ in range(n):
            p = np.convolve(p, g)[: _TAYLOR_TERMS + 1]
        c = p / np.arange(1, p.size + 1)
        s = t[near]
        acc = np.zeros_like(s)
        for cj in c[::-1]:
            acc = acc * s + cj
        out[near] = acc * s
    far = ~near
    if np.any(far):
        s = t[far]
        acc = (-b) ** n * s
        for k in range(1, n + 1):
            acc = acc + math.comb(n, k) * E**k * (-b) ** (n - k) * (-np.expm1(-k * lam * s)) / (k * lam)
        out[far] = acc / lam**n
    return out


# ---- nutation angle ---------------------------------------------------------------------------------

def nutation_rate_13(theta, G, A: float, C: float, H: float, D: float):
    """d theta/dt, rad/s: right side of seed 004 eq. (13),
    (G^2 sin cos /(A C)) [-H/A + D G^2 cos^2(theta)/C^3].

    The braces contain cos^2(theta), not the printed cos(theta) (docs/models.md A.6 seed 004 item 1). theta
    and G broadcast together.
    """
    theta, G = np.asarray(theta, float), np.asarray(G, float)
    c = np.cos(theta)
    return G * G * np.sin(theta) * c / (A * C) * (-H / A + D * G * G * c * c / C**3)


def _along_13(t, theta0, G0, b, lam, A, C, H, D, rates: Sequence[Callable] = (), rtol=1e-12):
    """Integrate eq. (13) in u = ln|tan theta| together with quadratures int rate(G, cos, sin) ds.

    Returns (theta, Q) with theta of shape t and Q of shape (len(rates), len(t)). The variable u removes
    the factor sin cos, so theta stays accurate in relative terms near 0 and pi/2 and the right side is
    not stiff there; theta0 in (pi/2, pi) is handled by the mirror symmetry theta -> pi - theta of (13).
    """
    t = _times(t)
    T = braking_time(G0, b, lam)
    tt = np.minimum(t, T)
    s0, c0 = math.sin(theta0), math.cos(theta0)
    fixed = s0 == 0.0 or c0 == 0.0  # the poles of (13): theta never moves
    sign = 1.0 if c0 >= 0 else -1.0
    u0 = 0.0 if fixed else math.log(abs(s0 / c0))
    k = len(rates)
    te = np.unique(tt)
    if te[-1] > 0:
        # imported here: scipy.integrate costs the explorer's start 0.4 s, and few runs need this
        from scipy.integrate import solve_ivp
        from scipy.special import expit

        def rhs(s, y):
            G = _momentum_scalar(s, G0, b, lam)
            if fixed:
                cs2, sn = c0 * c0, abs(s0)
                du = 0.0
            else:
                cs2, sn = expit(-2.0 * y[0]), math.sqrt(expit(2.0 * y[0]))
                du = G * G / (A * C) * (-H / A + D * G * G * cs2 / C**3)
            cs = sign * math.sqrt(cs2)
            return [du] + [f(G, cs, sn) for f in rates]

        # guarded: a right side that overflows (initial.G0 = 1e300, body.C = 1e-300) made solve_ivp loop for good
        sol = solve_ivp(guarded(rhs, _MAX_CALLS, "seed 004 eq. (13)"), (0.0, te[-1]), [u0] + [0.0] * k,
                        method="DOP853", t_eval=te, rtol=rtol, atol=_ODE_ATOL)
        if sol.status != 0:
            raise RuntimeError(f"integration of seed 004 eq. (13) failed: {sol.message}")
        Y = sol.y
    else:
        Y = np.array([[u0] + [0.0] * k]).T
    Y = Y[:, np.searchsorted(te, tt)]
    if fixed:
        theta = np.full(t.shape, float(theta0))
    else:
        theta = np.arctan(np.exp(Y[0]))
        if sign < 0:
            theta = math.pi - theta
    return theta, Y[1:]


def nutation_angle_13(t, theta0: float, G0: float, b: float, lam: float, A: float, C: float, H: float, D: float,
                      rtol: float = 1e-12) -> np.ndarray:
    """theta(t), rad, shape of t: seed 004 eq. (13) (corrected cos^2, docs/models.md A.6 seed 004 item 1)
    with G(t) from eq. (10), control b constant.

    H == 0 or D == 0 use the exact forms (nutation_angle_H0 / nutation_angle_D0); otherwise the scalar
    ODE is integrated (DOP853, relative tolerance rtol) in ln|tan theta|. theta0 in [0, pi]; 0, pi/2 and pi
    are equilibria; after the braking time theta stays at theta(T).
    """
    if H == 0 and D == 0:
        return np.full(_times(t).shape, float(theta0))
    if H == 0:
        return nutation_angle_H0(t, theta0, G0, b, lam, A, C, D)
    if D == 0:
        return nutation_angle_D0(t, theta0, G0, b, lam, A, C, H)
    return _along_13(t, theta0, G0, b, lam, A, C, H, D, rtol=rtol)[0]


def nutation_angle_24(tau, theta0: float, Gamma1: float, Gamma2: float, k_star: float) -> np.ndarray:
    """theta(tau), rad, of the dimensionless seed 004 eq. (24), tau = lam t:
    d theta/d tau = -Gamma1 sin cos f^2 + Gamma2 sin cos^3 f^4,  f = (1 + k*) e^{-tau} - k*.

    Gamma1 = H G0^2/(lam A^2 C) and Gamma2 = D G0^4/(lam A C^4) carry the powers of G0 that the print
    lacks (docs/models.md A.6 seed 004 item 7); k* = b/(lam G0). The body stops at tau_T = ln(1 + 1/k*)
    (inf for k* = 0), after which theta stays at theta(tau_T). Solved as eq. (13) with G0 = lam = A = C = 1,
    b = k*, H = Gamma1, D = Gamma2, which is the same equation.
    """
    if k_star < 0:
        raise ValueError(f"k_star must be >= 0, got {k_star!r}")
    return nutation_angle_13(tau, theta0, 1.0, k_star, 1.0, 1.0, 1.0, Gamma1, Gamma2)


def braking_tau_24(k_star: float) -> float:
    """Dimensionless braking time tau_T = lam T = ln(1 + 1/k*) of eq. (24) (``braking_time`` with
    k* = b/(lam G0)); inf for k* = 0 (no control: the body never stops)."""
    if not k_star >= 0:
        raise ValueError(f"k_star must be >= 0, got {k_star!r}")
    return math.inf if k_star == 0 else math.log1p(1.0 / k_star)


def nutation_curve_24(theta0: float, Gamma1: float, Gamma2: float, k_star: float,
                      n: int = 301) -> tuple[np.ndarray, np.ndarray]:
    """(tau, theta(tau)) of eq. (24) at n evenly spaced tau from 0 to the stop tau_T (``braking_tau_24``),
    the curves of seed 004 Figs. 1-4; theta in rad. Needs k* > 0, so that the body stops."""
    if not k_star > 0:
        raise ValueError(f"k_star must be > 0 for the curve to end where the body stops, got {k_star!r}")
    if n < 2:
        raise ValueError(f"n must be >= 2 samples, got {n!r}")
    tau = np.linspace(0, braking_tau_24(k_star), n)
    return tau, nutation_angle_24(tau, theta0, Gamma1, Gamma2, k_star)


def nutation_angle_H0(t, theta0: float, G0: float, b: float, lam: float, A: float, C: float, D: float) -> np.ndarray:
    """theta(t), rad, for H = 0 (point mass only, no cavity), exact (docs/models.md A.4):
    ln tan theta + tan^2 theta / 2 = [same at theta0] + (D/(A C^4)) I4(t).

    Inverted with a bracketed Newton solve of y + e^y = x in y = ln tan^2 theta. theta0 in (0, pi/2); the
    mirror image is used for (pi/2, pi); 0, pi/2 and pi are equilibria.
    """
    t = _times(t)
    s0, c0 = math.sin(theta0), math.cos(theta0)
    if s0 == 0 or c0 == 0 or D == 0:
        return np.full(t.shape, float(theta0))
    y0 = 2.0 * math.log(abs(s0 / c0))
    x = y0 + math.exp(y0) + 2.0 * D / (A * C**4) * momentum_power_integral(t, G0, b, lam, 4)
    theta = np.arctan(np.exp(0.5 * _solve_y_plus_exp_y(x)))
    return theta if c0 > 0 else math.pi - theta


def nutation_angle_D0(t, theta0: float, G0: float, b: float, lam: float, A: float, C: float, H: float) -> np.ndarray:
    """theta(t), rad, for D = 0 (cavity only, or a mass without damper), exact (docs/models.md A.4):
    tan theta = tan theta0 exp(-(H/(A^2 C)) I2(t)).
    """
    k = -(H / (A * A * C)) * momentum_power_integral(t, G0, b, lam, 2)
    with np.errstate(over="ignore"):
        return np.arctan2(math.sin(theta0) * np.exp(k), math.cos(theta0))


# ---- linearisations -----------------------------------------------------------------------------------

def nutation_exponent_15(t, G0: float, b: float, lam: float, A: float, C: float, H: float, D: float) -> np.ndarray:
    """K(t) of seed 004 eq. (15), dimensionless: K = (A C)^-1 [-(H/A) I2 + (D/C^3) I4].

    This is the printed bracket with the factor lam^-2 on every D term (docs/models.md A.6 seed 004 item 2),
    regrouped through I2, I4 so it stays exact as lam -> 0.
    """
    I2 = momentum_power_integral(t, G0, b, lam, 2)
    I4 = momentum_power_integral(t, G0, b, lam, 4)
    return (-(H / A) * I2 + (D / C**3) * I4) / (A * C)


def nutation_linear_15(t, dtheta0: float, G0: float, b: float, lam: float, A: float, C: float, H: float,
                       D: float) -> np.ndarray:
    """delta theta(t), rad, near theta = 0: seed 004 eq. (15), |dtheta| = |dtheta0| e^{K(t)}.

    Returns dtheta0 e^{K(t)} (the sign of dtheta0 is kept: the linear equation (14) cannot change it);
    K from nutation_exponent_15 (corrected, docs/models.md A.6 seed 004 item 2).
    """
    return dtheta0 * np.exp(nutation_exponent_15(t, G0, b, lam, A, C, H, D))


def nutation_linear_16(t, dtheta0: float, G0: float, b: float, lam: float, A: float, C: float,
                       H: float) -> np.ndarray:
    """delta theta(t), rad, near theta = pi/2 (theta = pi/2 + delta theta): seed 004 eq. (16) integrated,
    delta theta = delta theta0 exp((H/(A^2 C)) I2(t)).

    The printed integral has (G0 lam + b) in its first term where (G0 lam + b)^2 belongs (docs/models.md A.6
    seed 004 item 4); I2 is the exact integral. The mass does not enter, as the paper notes.
    """
    return dtheta0 * np.exp((H / (A * A * C)) * momentum_power_integral(t, G0, b, lam, 2))


def nutation_first_iterate_17(t, theta0: float, G0: float, b: float, lam: float, A: float, C: float, H: float,
                              D: float) -> np.ndarray:
    """theta0 + S(t), rad: seed 004 eq. (17), the first Picard iterate of eq. (13) from theta0,
    S = sin theta0 cos theta0 (A C)^-1 [-(H/A) I2 + (D cos^2 theta0 / C^3) I4].

    Equal to the printed bracket with the sign of its secular term flipped to
    +lam(-H/A + b^2 D cos^2(theta0)/(C^3 lam^2)) b^2 t (docs/models.md A.6 seed 004 item 5). It approximates
    theta to O(S^2).
    """
    I2 = momentum_power_integral(t, G0, b, lam, 2)
    I4 = momentum_power_integral(t, G0, b, lam, 4)
    s, c = math.sin(theta0), math.cos(theta0)
    return theta0 + s * c * (-(H / A) * I2 + (D * c * c / C**3) * I4) / (A * C)


# ---- equatorial part ---------------------------------------------------------------------------------

def equatorial_decay_rate(theta, G, b: float, lam: float, A: float, C: float, L: float, D: float):
    """mu, 1/s, of seed 004 eq. (18): mu = b/G + lam - r^2 (D r^2 + L)/A with r = G cos(theta)/C.

    Not always positive, contrary to the text after (18): a passive prolate body has mu < 0 (docs/models.md A.6
    seed 004 item 6). Singular at G = 0 when b > 0.
    """
    theta, G = np.asarray(theta, float), np.asarray(G, float)
    r = G * np.cos(theta) / C
    with np.errstate(divide="ignore", invalid="ignore"):
        control = np.where(b == 0, 0.0, b / G)
    return control + lam - r * r * (D * r * r + L) / A


def equatorial_modulus(t, theta0: float, G0: float, b: float, lam: float, A: float, C: float, H: float, D: float,
                       L: float | None = None, rtol: float = 1e-12) -> np.ndarray:
    """N(t) = A |(p, q)|, kg m^2/s, shape of t: seed 004 eqs. (18)-(19), N = N0 exp(-int_0^t mu),
    N0 = G0 |sin theta0|.

    The part b/G + lam of mu is -G'/G by eq. (10), so it integrates exactly to ln(G0/G); only
    int r^2 (D r^2 + L)/A is a quadrature, done along the solution of (13). This keeps N finite up to the
    braking time, where b/G diverges. L defaults to -C H/A (A L + C H = 0, eq. (4)); with that L the result
    equals eqs. (20)-(21), N = G |sin theta|.
    """
    if L is None:
        L = -C * H / A

    def rate(G, c, s):
        r = G * c / C
        return r * r * (D * r * r + L) / A

    _, Q = _along_13(t, theta0, G0, b, lam, A, C, H, D, rates=(rate,), rtol=rtol)
    return momentum_modulus(t, G0, b, lam) * abs(math.sin(theta0)) * np.exp(Q[0])


def equatorial_phase(t, theta0: float, G0: float, b: float, lam: float, A: float, C: float, F: float, H: float,
                     D: float, rtol: float = 1e-12) -> np.ndarray:
    """sigma(t) = int_0^t g ds, rad, seed 004 eq. (23), with g = r (A - C + F G^2)/A, r = G cos(theta)/C
    (eq. (22)); a quadrature along the solution of (13)."""
    def rate(G, c, s):
        return G * c / C * (A - C + F * G * G) / A

    return _along_13(t, theta0, G0, b, lam, A, C, H, D, rates=(rate,), rtol=rtol)[1][0]


def rotation_23(sigma) -> np.ndarray:
    """Pi(sigma) of seed 004 eq. (23), shape sigma.shape + (2, 2): ((cos, sin), (-sin, cos)).

    Its sense follows from eq. (1): without dissipation p' = g q, q' = -g p, i.e. (p, q) turns clockwise
    about e3 when g > 0.
    """
    sigma = np.asarray(sigma, float)
    c, s = np.cos(sigma), np.sin(sigma)
    return np.stack([np.stack([c, s], -1), np.stack([-s, c], -1)], -2)


def equatorial_direction(t, n0, theta0: float, G0: float, b: float, lam: float, A: float, C: float, F: float,
                         H: float, D: float, rtol: float = 1e-12) -> np.ndarray:
    """n(t) = Pi(sigma(t)) n0, shape (len(t), 2): the unit direction of (p, q), seed 004 eqs. (22)-(23).

    n0 is the initial direction (normalised here). The text's "d(t) defined in (18)" is mu(t) and its
    "equation (20)" is (22) (docs/models.md A.6 seed 004 item 6).
    """
    n0 = np.asarray(n0, float)
    n0 = n0 / np.linalg.norm(n0)
    sigma = equatorial_phase(t, theta0, G0, b, lam, A, C, F, H, D, rtol=rtol)
    return rotation_23(sigma) @ n0


# ---- shared numerics -----------------------------------------------------------------------------------

def _solve_increasing(fun, dfun, target, lo, hi, x0, max_iter: int = 200):
    """Vectorised Newton for fun(x) = target, fun increasing, kept inside the bracket [lo, hi] by bisection.

    A Newton step that leaves the bracket, or that is not under half the step before it, is replaced by bisection:
    on an S-shaped fun (seed 000's (2.11) in asinh form, where theta crosses Phi = 0) plain Newton can bounce
    between two points near either end of the bracket, shrinking it by ~1e-4 a step, and stop 0.3 rad from the
    root after max_iter (issue 23 found this in a quadratic-friction run). Stops when every step is below 1e-14
    relative: the residual of fun is then at its rounding level.
    """
    target = np.asarray(target, float)
    x = np.broadcast_to(np.asarray(x0, float), target.shape).copy()
    lo = np.broadcast_to(np.asarray(lo, float), target.shape).copy()
    hi = np.broadcast_to(np.asarray(hi, float), target.shape).copy()
    done = np.zeros(target.shape, bool)
    last = np.full(target.shape, np.inf)  # the size of the step before
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        for _ in range(max_iter):
            r = fun(x) - target
            lo = np.where(r < 0, x, lo)
            hi = np.where(r > 0, x, hi)
            xn = x - r / dfun(x)
            bad = ~np.isfinite(xn) | (xn < lo) | (xn > hi) | (np.abs(xn - x) > 0.5 * last)
            xn = np.where(done | (r == 0), x, np.where(bad, 0.5 * (lo + hi), xn))
            last = np.abs(xn - x)
            scale = np.maximum(1.0, np.abs(x))
            done |= (np.abs(xn - x) <= 1e-14 * scale) | (hi - lo <= 4 * np.finfo(float).eps * scale)
            x = xn
            if np.all(done):
                break
    return x


def _solve_y_plus_exp_y(x):
    """y with y + e^y = x (so e^y = W(e^x), Lambert W), for any real x, without overflow."""
    x = np.asarray(x, float)
    big = x > 1
    # the root is below x (e^y > 0) and, for x > 1, between 0 and ln x
    lo = np.where(big, 0.0, x - 3.0)
    hi = np.where(big, np.log(np.where(big, x, 2.0)), x)
    return _solve_increasing(lambda y: y + np.exp(y), lambda y: 1.0 + np.exp(y), x, lo, hi, hi)


_GL10 = np.polynomial.legendre.leggauss(10)
_GL20 = np.polynomial.legendre.leggauss(20)


def _cumulative_quadrature(f, t, rtol: float = 1e-13, max_rounds: int = 50) -> np.ndarray:
    """int_{t[0]}^{t[i]} f(s) ds for each i, shape (k, len(t)); f maps an array of s to shape (k, len(s)).

    Adaptive Gauss-Legendre: each panel between output times is bisected until its 10- and 20-point rules
    agree to rtol times the larger of the panel's int |f| and its share (by length) of int |f| over the whole
    range, then the 20-point value is kept. The share keeps panels where f is tiny and noisy (G -> 0 at the
    stop) from being split without end; the error stays below rtol of int |f| overall. Meant for smooth,
    slowly varying integrands.
    """
    t = np.asarray(t, float)
    a, bb, owner = t[:-1].copy(), t[1:].copy(), np.arange(t.size - 1)
    k = np.atleast_2d(f(t[:1])).shape[0]
    acc = np.zeros((k, max(t.size - 1, 0)))
    span = t[-1] - t[0] if t.size > 1 else 0.0
    density = None  # int |f| per unit length over the whole range, from the first round
    for round_ in range(max_rounds):
        if a.size == 0:
            break
        half, mid = 0.5 * (bb - a), 0.5 * (bb + a)
        s10 = (mid[:, None] + half[:, None] * _GL10[0][None, :]).ravel()
        s20 = (mid[:, None] + half[:, None] * _GL20[0][None, :]).ravel()
        y10 = np.atleast_2d(f(s10)).reshape(k, a.size, _GL10[0].size)
        y20 = np.atleast_2d(f(s20)).reshape(k, a.size, _GL20[0].size)
        i10 = (y10 @ _GL10[1]) * half
        i20 = (y20 @ _GL20[1]) * half
        iabs = (np.abs(y20) @ _GL20[1]) * half
        if density is None:
            density = iabs.sum(axis=1, keepdims=True) / span if span > 0 else np.zeros((k, 1))
        scale = np.maximum(iabs, density * 2.0 * half)
        ok = np.all(np.abs(i20 - i10) <= rtol * scale, axis=0)
        # give up splitting at the resolution of the times, or when the panels get too many to afford
        ok |= (half <= 1e-13 * np.maximum(np.abs(mid), span)) | (round_ == max_rounds - 1) | (a.size > 100_000)
        np.add.at(acc.T, owner[ok], i20[:, ok].T)
        keep = ~ok
        a, bb, owner, mid = a[keep], bb[keep], owner[keep], mid[keep]
        a, bb, owner = np.concatenate([a, mid]), np.concatenate([mid, bb]), np.concatenate([owner, owner])
    return np.concatenate([np.zeros((k, 1)), np.cumsum(acc, axis=1)], axis=1)
