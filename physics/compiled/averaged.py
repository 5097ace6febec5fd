"""Compiled right-hand side of the averaged ("quasi-rigid") moving-mass model.

Seed 004 eq. (1) with F, D, L, H, lambda and the control law (8), plus the quadratic-friction
terms of seed 000 eq. (2.5) (B with C^4 A^-5, corrected per docs/models.md A.6 seed 000 item 4), all
written as torques on the fictitious body J* w' + w x J* w = M.
The cavity torque is written in its general form kc (Df(w) f(w) + w x f(w)), f(w) = -J*^-1(w x J* w),
which for A = B is exactly (L p r^2, L q r^2, H (p^2 + q^2) r) of eq. (1).

State (7): w (3), q (4). Parameters (12): J* (3), A used by the mass terms (the mean equatorial
moment), F, D, unused, unused, lambda, b, Bq0 (seed 000 B without its factor w_perp), kc.
"""

from __future__ import annotations

import math

from numba import njit

from .attitude import quaternion_rate

NY = 7
NP = 12


@njit(cache=True)
def braking_norm(y, p):
    return math.sqrt((p[0] * y[0]) ** 2 + (p[1] * y[1]) ** 2 + (p[2] * y[2]) ** 2)


@njit(cache=True, inline="always")  # inlined into both right-hand sides: a call per evaluation costs ~2x
def omega_dot(w1, w2, w3, p):
    """w' (body frame, rad/s^2) of the averaged model at w; the attitude does not enter."""
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

    return ((T1 - (w2 * G3 - w3 * G2)) / J1, (T2 - (w3 * G1 - w1 * G3)) / J2,
            (T3 - (w1 * G2 - w2 * G1)) / J3)


@njit(cache=True)
def rhs(t, y, p, out):
    w1, w2, w3 = y[0], y[1], y[2]
    out[0], out[1], out[2] = omega_dot(w1, w2, w3, p)
    quaternion_rate(y, 3, w1, w2, w3, out)


@njit(cache=True)
def braking_norm_axisymmetric(y, p):
    return math.sqrt((p[0] * y[0]) ** 2 + (p[2] * y[1]) ** 2)


@njit(cache=True)
def rhs_axisymmetric(t, y, p, out):
    """The slow part of the averaged model of an axisymmetric body (J*1 = J*2), state (2):
    w_perp = |(w1, w2)| and w3 (rad/s).

    Every torque of ``omega_dot`` is equivariant under rotations about e3 when J*1 = J*2 (the mass
    terms, friction, medium and control act along or across w_perp by its modulus alone; the
    cavity's c3 vanishes), so the phase of (w1, w2) does not feed back: w_perp' is the radial part of
    w', which is w1' at the phase where w = (w_perp, 0, w3). Theta, |G| and E follow from this
    state exactly; the phase and the attitude, which turn on the fast free-body time scale, are
    left out. Not valid for J*1 != J*2.
    """
    d1, _, d3 = omega_dot(y[0], 0.0, y[1], p)
    out[0] = d1
    out[1] = d3
