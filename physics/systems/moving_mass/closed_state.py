"""The "closed" fidelity: the whole state (angular velocity and attitude) from the papers' closed forms.

Only the angles of the motion need quadratures; see closed_form_state.
"""

from __future__ import annotations

import math

import numpy as np

from physics.core.rotation import qmul
from physics.systems.moving_mass.closed000 import (
    quadratic_friction_coefficients,
    quadratic_friction_phi,
    quadratic_friction_theta,
)
from physics.systems.moving_mass.closed004 import (
    _along_13,
    _cumulative_quadrature,
    braking_time,
    momentum_modulus,
    momentum_power_integral,
    nutation_angle_13,
)


def closed_form_state(t, coeffs) -> dict:
    """State over the times t (1-D, non-decreasing, >= 0, s) from the closed forms; coeffs is a
    physics.coefficients.Coefficients.

    Two models have closed forms:
    (a) seed 004 (Bq0 == 0): mass with damper (F, D), cavity (L, H), medium lam, control b. G(t) from
        eq. (10), theta(t) from eq. (13) (or its exact forms for H = 0 or D = 0), the equatorial phase
        sigma = int g of eqs. (22)-(23) by quadrature along theta(t).
    (b) seed 000 section 2, quadratic friction alone (Bq0 != 0 and D = L = H = lam = b = 0; F may be
        nonzero): G = G0, theta from (2.11), the body-frame angle phi of (w1, w2) from (2.9); sigma = -phi.
    Any other combination with Bq0 != 0 raises ValueError: no closed form exists.

    Returns a dict of arrays over the output times:
    - t (n,): the input times, cut at the braking time T when T <= t[-1]; the last sample is then exactly T;
    - t_stop: T when it is <= t[-1] (the run ends there), else None;
    - theta (n,) rad, angle between G = J* w and e3; G (n,) = |J* w|, kg m^2/s;
    - omega (n, 3) rad/s, body frame: the closed-form w = (G sin(theta) n / A, G cos(theta) / C) with
      n = Pi(sigma) (1, 0), eqs. (20)-(23) (seed 000: eq. (2.8)); omega(0) = (G0 sin th0/A, 0, G0 cos th0/C);
    - quat (n, 4), scalar first, body -> inertial, quat(0) = (1, 0, 0, 0);
    - E (n,) J, = 1/2 w.J* w.

    Attitude: 3-1-3 Euler angles about the inertial direction of G, taken as fixed and equal to
    (sin th0, 0, cos th0) (the body's initial G direction, since quat(0) is the identity): precession phi_p,
    nutation theta, spin psi = pi/2 + sigma, so that psi' = g = G cos(theta)(1/C - 1/A) + F G^3 cos(theta)/(A C),
    the torque-free rate plus the phase rate that keeps the body-frame direction of G equal to that of
    J* omega. By construction R(quat) J* omega = G (sin th0, 0, cos th0) to rounding.
    Precession rate: phi_p' = G/A - F G^3 cos^2(theta)/(A C), not the rigid-body G/A. The mass's
    conservative angular momentum k (docs/models.md A.3) makes the conserved vector K = J* w + k, and e3 turns
    about K at |w_perp| |K|/|K_perp|, which is this rate to first order in F. With G/A alone the attitude of
    the averaged equations (1) drifts away secularly (0.84 rad after 100 s at F G^2/C = 0.036); with the
    correction the difference stays at the size of the wobble of G below.
    Approximation: in the averaged equations G is not exactly fixed in space. The internal torques (F, D,
    L, H terms) are normal to G and turn with the body, so G wobbles about a fixed mean by an angle of the
    order of F G^2/C and of |theta'| A/G, both O(eps^2) or smaller (docs/models.md A.5); the Euler-angle rates of
    this attitude differ from omega by the same orders (their theta' terms, and F terms on the axis). With
    no internal torque (only medium and control, which are parallel to G) the attitude is exact.
    """
    t = np.asarray(t, dtype=float)
    if t.ndim != 1 or t.size == 0:
        raise ValueError(f"t must be a non-empty 1-D array of times, got shape {t.shape}")
    if np.any(~np.isfinite(t)) or np.any(t < 0) or np.any(np.diff(t) < 0):
        raise ValueError("t must hold finite, non-decreasing times >= 0")
    c = coeffs
    A, C, G0, th0 = float(c.A), float(c.C), float(c.G0), float(c.theta0)
    if c.Bq0 != 0:
        others = {"D": c.D, "L": c.L, "H": c.H, "lam": c.lam, "b": c.b}
        bad = [f"{k} = {v:g}" for k, v in others.items() if v != 0]
        if bad:
            raise ValueError(f"no closed form for quadratic friction (Bq0 = {c.Bq0:g}) combined with {', '.join(bad)}: "
                             "seed 000 section 2 solves quadratic friction alone (D = L = H = lam = b = 0)")
        beta, gamma = quadratic_friction_coefficients(A, C, c.F, c.Bq0, G0)
        t_stop = None
        theta = quadratic_friction_theta(t, th0, gamma)
        sigma = -quadratic_friction_phi(t, th0, gamma, beta)
        G = np.full(t.shape, G0)
        precession = G0 * t / A
        if c.F != 0:
            ts = np.unique(np.concatenate([[0.0], t]))
            cos2 = _cumulative_quadrature(lambda s: np.cos(quadratic_friction_theta(s, th0, gamma))[None, :] ** 2, ts)
            precession = precession - c.F * G0**3 / (A * C) * cos2[0, np.searchsorted(ts, t)]
    else:
        T = braking_time(G0, c.b, c.lam)
        t_stop = T if T <= t[-1] else None
        if t_stop is not None:
            t = np.concatenate([t[t < T], [T]])

        def g(Gs, cs, sn):
            return Gs * cs / C * (A - C + c.F * Gs * Gs) / A

        def precession_rate(Gs, cs, sn):
            return Gs / A - c.F * Gs**3 * cs * cs / (A * C)

        rates = (g, precession_rate) if c.F != 0 else (g,)
        theta, Q = _along_13(t, th0, G0, c.b, c.lam, A, C, c.H, c.D, rates=rates)
        if c.H == 0 or c.D == 0:
            theta = nutation_angle_13(t, th0, G0, c.b, c.lam, A, C, c.H, c.D)
        sigma = Q[0]
        G = momentum_modulus(t, G0, c.b, c.lam)
        precession = Q[1] if c.F != 0 else momentum_power_integral(t, G0, c.b, c.lam, 1) / A
    st, ct = np.sin(theta), np.cos(theta)
    omega = np.column_stack([G * st * np.cos(sigma) / A, -G * st * np.sin(sigma) / A, G * ct / C])
    E = 0.5 * (A * (omega[:, 0] ** 2 + omega[:, 1] ** 2) + C * omega[:, 2] ** 2)
    frame = _conj(qmul(_qx(np.array(th0)), _qz(np.array(math.pi / 2))))  # G frame -> inertial frame
    quat = qmul(frame, qmul(_qz(precession), qmul(_qx(theta), _qz(math.pi / 2 + sigma))))
    quat /= np.linalg.norm(quat, axis=-1, keepdims=True)
    return {"t": t, "theta": theta, "G": G, "omega": omega, "quat": quat, "E": E, "t_stop": t_stop}


def _qz(a):
    a = np.asarray(a, float)
    z = np.zeros_like(a)
    return np.stack([np.cos(a / 2), z, z, np.sin(a / 2)], -1)


def _qx(a):
    a = np.asarray(a, float)
    z = np.zeros_like(a)
    return np.stack([np.cos(a / 2), np.sin(a / 2), z, z], -1)


def _conj(q):
    return q * np.array([1.0, -1.0, -1.0, -1.0])


