"""Closed forms of seed 000 (Akulenko & Leshchenko 1978): a symmetric body with a point mass on a spring,
(section 2) with quadratic friction and no control, (section 3) with a viscous damper and a braking
torque of bounded magnitude b.

Plain floats and numpy arrays of times in, arrays out; SI units, angles in rad. Seed 000 writes K, I, I*
for what docs/models.md calls G (here K), A, C; N = D/A and A_c = F K^2/A (docs/models.md A.3). All formulas are
the corrected ones of docs/models.md A.6 (seed 000 items 3-5, 7-11).
"""

from __future__ import annotations

import math

import numpy as np

from physics.systems.moving_mass.closed004 import (
    _cumulative_quadrature,
    _solve_increasing,
    _solve_y_plus_exp_y,
    _times,
    braking_time,
    momentum_modulus,
    momentum_power_integral,
)

# ---- section 2: quadratic friction ------------------------------------------------------------------


def quadratic_friction_coefficients(A: float, C: float, F: float, Bq0: float, K: float) -> tuple[float, float]:
    """(beta, gamma), both 1/s, of seed 000 eq. (2.10), corrected (docs/models.md A.6 seed 000 item 5):
    beta = -(d + A_c) K/C and gamma = Bq0 K^7/(A C^6) = m rho^3 Lambda d|d| K^7/(Omega^3 A^6 C^2),
    with d = 1 - C/A, A_c = F K^2/A (eq. (2.6), item 4) and Bq0 = B/w_perp.
    """
    d = 1.0 - C / A
    return -(d + F * K * K / A) * K / C, Bq0 * K**7 / (A * C**6)


def quadratic_friction_invariant(theta):
    """Left side of seed 000 eq. (2.11) (correct as printed), dimensionless, for theta in (0, pi/2):
    2 sec^4 cosec + 5[(sec^2 - 3) cosec + 3 ln tan(pi/4 + theta/2)].

    Written in u = tan theta as sqrt(1+u^2)(2u^4 + 9u^2 - 8)/u + 15 asinh(u), which has no cancellation
    between the cosec terms near theta = 0. Its theta-derivative is 8/(sin^2 cos^5).
    """
    u = np.tan(np.asarray(theta, float))
    return _invariant_211(u)


def _invariant_211(u):
    return np.sqrt(1.0 + u * u) * (2.0 * u**4 + 9.0 * u * u - 8.0) / u + 15.0 * np.arcsinh(u)


def quadratic_friction_theta(t, theta0: float, gamma: float) -> np.ndarray:
    """theta(t), rad, shape of t: seed 000 eq. (2.9) theta' = gamma sin|sin| cos^5, by inverting (2.11),
    Phi(theta) = Phi(theta0) + 8 gamma t.

    The root is found by a bracketed Newton solve in s = ln tan theta. theta0 in (0, pi/2), its mirror image
    for (pi/2, pi); 0, pi/2, pi are equilibria. gamma > 0 (prolate) drives theta to pi/2, gamma < 0 to 0.
    """
    t = _times(t)
    s0, c0 = math.sin(theta0), math.cos(theta0)
    if s0 == 0 or c0 == 0 or gamma == 0:
        return np.full(t.shape, float(theta0))
    x0 = math.log(abs(s0 / c0))
    # Newton on asinh(Phi), which is close to linear in s = ln tan theta in both tails (Phi ~ 2 tan^4 near
    # pi/2 and ~ -8/tan near 0), so the iteration converges in a few steps from theta0
    target = np.arcsinh(_invariant_211(math.exp(x0)) + 8.0 * gamma * t)

    def phi(x):
        return np.arcsinh(_invariant_211(np.exp(x)))

    def dphi(x):
        u = np.exp(x)
        return 8.0 * (1.0 + u * u) ** 2.5 / u / np.hypot(1.0, _invariant_211(u))

    # ln tan theta is within [-700, 60] for any theta whose tangent or cotangent is a normal double
    x = _solve_increasing(phi, dphi, target, -700.0, 60.0, np.full(t.shape, x0))
    theta = np.arctan(np.exp(x))
    return theta if c0 > 0 else math.pi - theta


def quadratic_friction_phi(t, theta0: float, gamma: float, beta: float, phi0: float = 0.0) -> np.ndarray:
    """phi(t), rad, shape of t: seed 000 eq. (2.9) phi' = beta cos(theta), phi the angle of (w1, w2) in the
    body frame (eq. (2.8)); beta corrected as in quadratic_friction_coefficients.

    A quadrature along theta(t) of (2.11) (adaptive Gauss-Legendre), not the closed phi(theta): the latter is
    multiplied by beta/gamma and loses digits when theta moves little.
    """
    t = _times(t)
    ts = np.unique(np.concatenate([[0.0], t]))
    Q = _cumulative_quadrature(lambda s: np.cos(quadratic_friction_theta(s, theta0, gamma))[None, :], ts)[0]
    return phi0 + beta * Q[np.searchsorted(ts, t)]


def quadratic_friction_omega(t, theta0: float, phi0: float, K: float, A: float, C: float, gamma: float,
                             beta: float) -> np.ndarray:
    """w(t), rad/s, shape (len(t), 3), body frame: seed 000 eq. (2.8),
    A w1 = K sin theta cos phi, A w2 = K sin theta sin phi, C w3 = K cos theta (K constant, eq. (2.7))."""
    th = quadratic_friction_theta(t, theta0, gamma)
    ph = quadratic_friction_phi(t, theta0, gamma, beta, phi0)
    return np.column_stack([K * np.sin(th) * np.cos(ph) / A, K * np.sin(th) * np.sin(ph) / A, K * np.cos(th) / C])


# ---- section 3: viscous damper and bounded control ---------------------------------------------------

def braking_momentum_34(t, K0: float, b: float) -> np.ndarray:
    """K(t) = K0 - b t, kg m^2/s, seed 000 eq. (3.4) for constant b (0 after T* = K0/b)."""
    return momentum_modulus(t, K0, b, 0.0)


def braking_time_34(K0: float, b: float) -> float:
    """T* = K0/b, s: seed 000 eq. (3.4) for constant b."""
    return braking_time(K0, b, 0.0)


def axial_rate_35(w3, K, b: float, C: float, N: float):
    """w3', rad/s^2: seed 000 eq. (3.5), -w3 (b/K + N K^2 w3^2/C^2 - N w3^4) (correct as printed)."""
    w3, K = np.asarray(w3, float), np.asarray(K, float)
    return -w3 * (b / K + N * K * K * w3 * w3 / C**2 - N * w3**4)


def r_squared_rate_36(R, K, C: float, N: float):
    """(R^2)' with R = w3/K, (kg m^2)^-2 s^-1: seed 000 eq. (3.6), -2 N K^4 R^4 (C^-2 - R^2).

    The printed left side R'' is (R^2)' (docs/models.md A.6 seed 000 item 8).
    """
    R, K = np.asarray(R, float), np.asarray(K, float)
    return -2.0 * N * K**4 * R**4 * (C**-2 - R * R)


def nutation_invariant_37(theta, theta0: float):
    """Left side of seed 000 eq. (3.7): sec^2 theta - sec^2 theta0 + ln(tan^2 theta / tan^2 theta0)."""
    theta = np.asarray(theta, float)
    return (np.tan(theta) ** 2 - math.tan(theta0) ** 2
            + 2.0 * (np.log(np.abs(np.tan(theta))) - math.log(abs(math.tan(theta0)))))


def nutation_angle_37(t, theta0: float, K0: float, b: float, C: float, N: float) -> np.ndarray:
    """theta(t), rad, shape of t: seed 000 eq. (3.7) corrected (docs/models.md A.6 seed 000 item 9),
    sec^2 theta - sec^2 theta0 + ln(tan^2 theta / tan^2 theta0) = +(2N/C^4) int_0^t K^4,
    inverted for theta; here b is constant so K = K0 - b t (for a varying b only int K^4 changes).

    The print has -2N/(I* I^3), with the wrong sign and inertia factor. theta0 in (0, pi/2) (mirror image for
    (pi/2, pi)); theta stays at theta(T*) after the stop.
    """
    t = _times(t)
    s0, c0 = math.sin(theta0), math.cos(theta0)
    if s0 == 0 or c0 == 0 or N == 0:
        return np.full(t.shape, float(theta0))
    y0 = 2.0 * math.log(abs(s0 / c0))
    x = y0 + math.exp(y0) + 2.0 * N / C**4 * momentum_power_integral(t, K0, b, 0.0, 4)
    theta = np.arctan(np.exp(0.5 * _solve_y_plus_exp_y(x)))
    return theta if c0 > 0 else math.pi - theta


def braking_sigma_38(K0: float, b: float, C: float, N: float) -> float:
    """sigma of seed 000 eq. (3.8), dimensionless: 5 b C^4/(2 N K0^5) = (5/2) b C A^4 Omega^4/(m rho^2 chi d K0^5)."""
    return 5.0 * b * C**4 / (2.0 * N * K0**5) if N != 0 else math.inf


def braking_nutation_38(tau, theta0: float, sigma: float) -> np.ndarray:
    """theta(tau), rad, shape of tau: seed 000 eq. (3.8) corrected (docs/models.md A.6 seed 000 item 10) and
    solved for theta, tau = t/T* in [0, 1]:
    tan^2 theta - tan^2 theta0 + ln(tan^2 theta/tan^2 theta0) = (1 - (1 - tau)^5)/sigma.

    sigma = +-inf (no damper) leaves theta at theta0. tau > 1 gives theta(1).
    """
    tau = np.clip(np.asarray(tau, float), 0.0, 1.0)
    s0, c0 = math.sin(theta0), math.cos(theta0)
    if s0 == 0 or c0 == 0 or math.isinf(sigma):
        return np.full(tau.shape, float(theta0))
    if sigma == 0:
        raise ValueError("sigma = 0 means b = 0: there is no braking and tau = t/T* is undefined")
    y0 = 2.0 * math.log(abs(s0 / c0))
    x = y0 + math.exp(y0) - np.expm1(5.0 * np.log1p(-tau)) / sigma
    theta = np.arctan(np.exp(0.5 * _solve_y_plus_exp_y(x)))
    return theta if c0 > 0 else math.pi - theta


def braking_tau_38(theta, theta0: float, sigma: float):
    """tau = t/T* at which the nutation angle is theta: seed 000 eq. (3.8) corrected (exponent 1/5, logarithm
    of tan^2 theta0/tan^2 theta; docs/models.md A.6 seed 000 item 10),
    tau = 1 - [1 + sigma(tan^2 theta0 - tan^2 theta + ln(tan^2 theta0/tan^2 theta))]^(1/5).

    nan where theta is not reached before the stop (negative bracket).
    """
    theta = np.asarray(theta, float)
    inner = 1.0 - sigma * nutation_invariant_37(theta, theta0)
    with np.errstate(invalid="ignore"):
        return -np.expm1(np.log(inner) / 5.0)


def braking_omega_39(t, w0, b: float, A: float, C: float, F: float, N: float) -> np.ndarray:
    """w(t), rad/s, shape (len(t), 3), body frame, from the initial w0 = (w10, w20, w30): seed 000 eq. (3.9)
    in its general form (docs/models.md A.6 seed 000 item 11),
    w1 + i w2 = (w10 + i w20)(K/K0) e^{alpha} e^{-i psi},  alpha = N int w3^4,  psi = int (d + A_c) w3,
    with w3 = K cos(theta)/C, theta from (3.8), K from (3.4), A_c = F K^2/A.

    The printed w1 = w10 .. cos psi, w2 = -w20 .. sin psi holds only for w20 = 0 with w20 read as w_perp0.
    alpha and psi are adaptive Gauss-Legendre quadratures along theta(t); w = 0 from T* on.
    """
    t = _times(t)
    if not b > 0:
        raise ValueError(f"braking_omega_39 needs a braking torque b > 0, got {b!r}")
    w10, w20, w30 = (float(x) for x in w0)
    K0 = math.sqrt(A * A * (w10 * w10 + w20 * w20) + C * C * w30 * w30)
    theta0 = math.atan2(A * math.hypot(w10, w20), C * w30)
    T = braking_time_34(K0, b)
    sigma = braking_sigma_38(K0, b, C, N)
    d = 1.0 - C / A

    def rates(s):
        K = K0 - b * s
        w3 = K * np.cos(braking_nutation_38(s / T, theta0, sigma)) / C
        return np.vstack([N * w3**4, (d + F * K * K / A) * w3])

    tt = np.minimum(t, T)
    ts = np.unique(np.concatenate([[0.0], tt]))
    Q = _cumulative_quadrature(rates, ts)[:, np.searchsorted(ts, tt)]
    K = braking_momentum_34(t, K0, b)
    z = complex(w10, w20) * (K / K0) * np.exp(Q[0] - 1j * Q[1])
    th = braking_nutation_38(tt / T, theta0, sigma)
    return np.column_stack([z.real, z.imag, K * np.cos(th) / C])
