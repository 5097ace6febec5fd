"""Compiled right-hand sides of the averaged ("quasi-rigid") moving-mass model.

Seed 004 eq. (1) with F, D, L, H, lambda and the control law (8), plus the quadratic-friction
terms of seed 000 eq. (2.5) (B with C^4 A^-5, corrected per docs/models.md A.6 seed 000 item 4), all
written as torques on the fictitious body J* w' + w x J* w = M.
The cavity torque is written in its general form kc (Df(w) f(w) + w x f(w)), f(w) = -J*^-1(w x J* w),
which for A = B is exactly (L p r^2, L q r^2, H (p^2 + q^2) r) of eq. (1).

The attitude is not integrated as a quaternion: the inertial K is fixed, so the attitude is the 3-1-3 rotation
Q_K Rz(psi) Rx(theta) Rz(phi) (docs/models.md A.3, the attitude), where Q_K is a constant frame whose e3 is K's
inertial direction, theta and phi give K's body-frame direction G/|G| and only the precession phase psi is
integrated. The state's Q_K has a zero rate, so every integrator keeps it bit for bit, and K's inertial direction
holds to rounding however long the run.

State of ``rhs`` (8): w (3), psi, Q_K (4). State of ``rhs_axisymmetric`` (8), J*1 = J*2 only: |w_perp|, w3, the
body-frame phase alpha of w_perp (w = (|w_perp| cos alpha, |w_perp| sin alpha, w3)), psi, Q_K (4).
Parameters (12): J* (3), A used by the mass terms (the mean equatorial moment), F, D, unused, unused, lambda, b,
Bq0 (seed 000 B without its factor w_perp), kc.
"""

from __future__ import annotations

import math

from numba import njit

NY = 8
NP = 12


@njit(cache=True)
def braking_norm(y, p):
    return math.sqrt((p[0] * y[0]) ** 2 + (p[1] * y[1]) ** 2 + (p[2] * y[2]) ** 2)


@njit(cache=True, inline="always")  # inlined into both right-hand sides: a call per evaluation costs ~2x
def torques(w1, w2, w3, p):
    """The torque M (body frame, N m) on the fictitious body at w: J* w' + w x J* w = M."""
    J1, J2, J3 = p[0], p[1], p[2]
    A, F, D, lam, b, Bq0, kc = p[3], p[4], p[5], p[8], p[9], p[10], p[11]
    C = J3
    G1, G2, G3 = J1 * w1, J2 * w2, J3 * w3
    G2n = G1 * G1 + G2 * G2 + G3 * G3
    Gn = math.sqrt(G2n)
    wp2 = w1 * w1 + w2 * w2
    r4 = w3 ** 4

    # viscoelastic mass, seed 004 eq. (1): F G^2 (q r, -p r, 0) + D r^4 (p, q, -(A/C) (p^2+q^2)/r)
    T1 = F * G2n * w2 * w3 + D * r4 * w1
    T2 = -F * G2n * w1 * w3 + D * r4 * w2
    T3 = -(A / C) * D * w3 ** 3 * wp2
    # quadratic friction, seed 000 eq. (2.5) times the moments: B = Bq0 w_perp
    if Bq0 != 0.0:
        Bq = Bq0 * math.sqrt(wp2)
        r6 = w3 ** 6
        T1 += A * Bq * w1 * r6
        T2 += A * Bq * w2 * r6
        T3 -= Bq * (A * A / C) * wp2 * w3 ** 5
    # medium and control
    T1 -= lam * G1
    T2 -= lam * G2
    T3 -= lam * G3
    if b > 0.0 and Gn > 0.0:
        T1 -= b * G1 / Gn
        T2 -= b * G2 / Gn
        T3 -= b * G3 / Gn
    # viscous cavity
    if kc != 0.0:
        c1 = (J2 - J3) / J1
        c2 = (J3 - J1) / J2
        c3 = (J1 - J2) / J3
        f1 = c1 * w2 * w3
        f2 = c2 * w3 * w1
        f3 = c3 * w1 * w2
        T1 += kc * (c1 * (w3 * f2 + w2 * f3) + (w2 * f3 - w3 * f2))
        T2 += kc * (c2 * (w3 * f1 + w1 * f3) + (w3 * f1 - w1 * f3))
        T3 += kc * (c3 * (w2 * f1 + w1 * f2) + (w1 * f2 - w2 * f1))

    return T1, T2, T3


@njit(cache=True, inline="always")
def omega_dot(w1, w2, w3, p):
    """w' (body frame, rad/s^2) of the averaged model at w; the attitude does not enter."""
    J1, J2, J3 = p[0], p[1], p[2]
    G1, G2, G3 = J1 * w1, J2 * w2, J3 * w3
    T1, T2, T3 = torques(w1, w2, w3, p)
    return ((T1 - (w2 * G3 - w3 * G2)) / J1, (T2 - (w3 * G1 - w1 * G3)) / J2,
            (T3 - (w1 * G2 - w2 * G1)) / J3)


@njit(cache=True, inline="always")
def precession_rate(w1, w2, w3, M1, M2, p):
    """psi' (rad/s): the rate of the 3-1-3 precession angle about K's fixed inertial direction.

    The attitude that keeps R G fixed turns with w_K = w + (M x G)/|G|^2 (the torque's part normal to G turns
    G in the body; the body turns the other way so that K does not), and psi' = (w_K1 k1 + w_K2 k2)/(1 - k3^2)
    with k = G/|G|; as w_K.k = w.k, psi' = |G| (w1 G1 + w2 G2 - d3 G3)/(G1^2 + G2^2), d3 = (M1 G2 - M2 G1)/|G|^2.
    On the axis (G1 = G2 = 0) phi stays 0 and the body turns about K at psi' = w3 |G|/G3."""
    G1, G2, G3 = p[0] * w1, p[1] * w2, p[2] * w3
    Gp2 = G1 * G1 + G2 * G2
    G2n = Gp2 + G3 * G3
    if G2n == 0.0:
        return 0.0
    Gn = math.sqrt(G2n)
    if Gp2 == 0.0:
        return w3 * Gn / G3
    d3 = (M1 * G2 - M2 * G1) / G2n
    return Gn * (w1 * G1 + w2 * G2 - d3 * G3) / Gp2


@njit(cache=True)
def rhs(t, y, p, out):
    w1, w2, w3 = y[0], y[1], y[2]
    J1, J2, J3 = p[0], p[1], p[2]
    G1, G2, G3 = J1 * w1, J2 * w2, J3 * w3
    M1, M2, M3 = torques(w1, w2, w3, p)
    out[0] = (M1 - (w2 * G3 - w3 * G2)) / J1
    out[1] = (M2 - (w3 * G1 - w1 * G3)) / J2
    out[2] = (M3 - (w1 * G2 - w2 * G1)) / J3
    out[3] = precession_rate(w1, w2, w3, M1, M2, p)
    for i in range(4, 8):
        out[i] = 0.0  # Q_K: K's inertial frame, fixed


@njit(cache=True)
def braking_norm_axisymmetric(y, p):
    return math.sqrt((p[0] * y[0]) ** 2 + (p[2] * y[1]) ** 2)


@njit(cache=True)
def rhs_axisymmetric(t, y, p, out):
    """The averaged model of an axisymmetric body (J*1 = J*2) reduced to its slow form, state (8):
    |w_perp|, w3 (rad/s), the phases alpha and psi (rad), Q_K (4).

    Every torque of ``omega_dot`` is equivariant under rotations about e3 when J*1 = J*2 (the mass
    terms, friction, medium and control act along or across w_perp by its modulus alone; the
    cavity's c3 vanishes), so the phase alpha of (w1, w2) does not feed back: at the phase alpha = 0, where
    w = (|w_perp|, 0, w3), |w_perp|' is w1', w3' is w3' and alpha' = w2'/|w_perp|. Every rate depends on
    (|w_perp|, w3) alone and varies on the slow time scale, so the steps are not bound to the free-body
    revolutions: the phases are quadratures of slowly varying rates. psi' is ``precession_rate`` at alpha = 0,
    written with alpha' so that it has no 0/0 on the axis: psi' = |G|/A + C w3 (A alpha' + (A - C) w3)/(A |G|).
    Not valid for J*1 != J*2.
    """
    wp, w3 = y[0], y[1]
    A, C = p[0], p[2]
    d1, d2, d3 = omega_dot(wp, 0.0, w3, p)
    out[0] = d1
    out[1] = d3
    if wp > 0.0:
        alpha_dot = d2 / wp
    else:  # on the axis: the limit of w2'/|w_perp|, which is linear in |w_perp| there (rounding at 1e-8 |w3|)
        s = 1e-8 * abs(w3) if w3 != 0.0 else 1.0
        alpha_dot = omega_dot(s, 0.0, w3, p)[1] / s
    out[2] = alpha_dot
    Gn = math.hypot(A * wp, C * w3)
    out[3] = 0.0 if Gn == 0.0 else Gn / A + C * w3 * (A * alpha_dot + (A - C) * w3) / (A * Gn)
    for i in range(4, 8):
        out[i] = 0.0  # Q_K: K's inertial frame, fixed
