"""The averaged equations of seeds 004 and 000 as plain numpy right-hand sides f(t, w, ...) for solve_ivp.

Written out from the papers as corrected in docs/models.md (A.3, A.6), independently of the model code in
physics/systems and physics/compiled, so that the closed forms and the averaged model can be checked against
a numerical integration of their own equations. w = (w1, w2, w3) is the body angular velocity, rad/s.
"""

from __future__ import annotations

import math


def rhs_004(t, w, A, C, F, D, L, H, lam, b):
    """Seed 004 eq. (1) with the control (8) M = -b J* w/|J* w| and the medium torque -lam J* w."""
    p, q, r = w
    G = math.sqrt(A * A * (p * p + q * q) + C * C * r * r)
    wp2 = p * p + q * q
    k = b / G if b else 0.0
    dp = (-(C - A) * q * r - k * A * p + L * p * r * r + F * G * G * q * r + D * r**4 * p - lam * A * p) / A
    dq = (-(A - C) * p * r - k * A * q + L * q * r * r - F * G * G * p * r + D * r**4 * q - lam * A * q) / A
    dr = (-k * C * r + H * wp2 * r - (A / C) * D * r**3 * wp2 - lam * C * r) / C
    return [dp, dq, dr]


def rhs_25(t, w, A, C, Ac_of, B_of):
    """Seed 000 eq. (2.5); A_c and B are functions of w (``coefficients_26`` gives eq. (2.6) as corrected),
    so that a test can put the printed (2.6) in their place."""
    w1, w2, w3 = w
    wp2 = w1 * w1 + w2 * w2
    d = 1.0 - C / A
    Ac, B = Ac_of(w), B_of(w)
    return [(d + Ac) * w2 * w3 + B * w1 * w3**6, -(d + Ac) * w1 * w3 + B * w2 * w3**6, -B * (A / C) ** 2 * wp2 * w3**5]


def coefficients_26(A, C, F, Bq0):
    """(A_c(w), B(w)) of seed 000 eq. (2.6) as corrected, quadratic friction: A_c = F K^2/A, B = Bq0 |w_perp|
    (docs/models.md A.3)."""

    def Ac_of(w):
        return F * (A * A * (w[0] * w[0] + w[1] * w[1]) + C * C * w[2] * w[2]) / A

    def B_of(w):
        return Bq0 * math.sqrt(w[0] * w[0] + w[1] * w[1])

    return Ac_of, B_of


def rhs_32(t, w, A, C, F, N, b, e12=4, e3=3):
    """Seed 000 eq. (3.2) with the control u = -K/|K| and A_c = F K^2/A (F = 0 drops A_c, which only turns
    (w1, w2) and does not enter theta). The exponents of w3 are those corrected in docs/models.md A.6 seed 000
    item 7 (4 and 3); a test passes the printed ones (2, 2) to show them wrong."""
    w1, w2, w3 = w
    wp2 = w1 * w1 + w2 * w2
    d = 1.0 - C / A
    K = math.sqrt(A * A * wp2 + C * C * w3 * w3)
    Ac = F * K * K / A
    control = b / K if b else 0.0
    return [(d + Ac) * w2 * w3 - control * w1 + N * w1 * w3**e12,
            -(d + Ac) * w1 * w3 - control * w2 + N * w2 * w3**e12,
            -control * w3 - N * (A / C) ** 2 * wp2 * w3**e3]
