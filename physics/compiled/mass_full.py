"""Compiled right-hand side of the full moving-mass model, docs/models.md Part A section 2.

State (15): w (3) body angular velocity; u (3) displacement of the mass from O1; v = u' (3);
q (4) attitude quaternion, scalar first, body -> inertial; W_int (1) work dissipated inside
(damper and quadratic friction); W_ext (1) work taken out by external torques and the cavity.

Parameters (15), see ``pack``: carrier inertia about its own COM Jb, frozen inertia J*, reduced
mass m_r, carrier COM -> O1 distance d0, spring c, damper delta, quadratic friction mu, control
bound b, control law (0: G = K, 1: G = J* w; 2 + 2 i + s: a thruster, the torque b along body axis i + 1,
positive for s = 0, negative for s = 1), medium lambda, cavity coupling kc = beta P / nu.

The cavity is its asymptotic Stokes torque: the fluid carries the relative momentum
k_f = -kc f(w), where f(w) = -J*^-1 (w x J* w) is the torque-free Euler acceleration (docs/models.md A.3).
We put k_f into the total momentum and differentiate it along the *actual* motion, so the torque on
the solid is -(k_f' + w x k_f) with k_f' = -kc Df(w) w'. To leading order this is exactly the
L, H law of seed 004 eq. (1) (w' = f(w) + O(eps)), and it keeps the total K = K_mech + k_f exactly
constant when there is no external torque, as an internal exchange must. The Df w' term makes the
carrier's inertia matrix Jb - kc Df(w), solved explicitly by Cramer's rule.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .attitude import quaternion_rate

NY = 15
NP = 15


@njit(cache=True)
def momentum(y, p):
    """Total angular momentum K (body components) about the system COM, including the cavity's."""
    w1, w2, w3 = y[0], y[1], y[2]
    d1, d2, d3 = y[3], y[4], p[7] + y[5]
    v1, v2, v3 = y[6], y[7], y[8]
    mr, kc = p[6], p[14]
    s1 = w2 * d3 - w3 * d2 + v1
    s2 = w3 * d1 - w1 * d3 + v2
    s3 = w1 * d2 - w2 * d1 + v3
    # the cavity's relative momentum k_f = -kc f(w), f_i = a_i w_j w_k
    a1 = (p[4] - p[5]) / p[3]
    a2 = (p[5] - p[3]) / p[4]
    a3 = (p[3] - p[4]) / p[5]
    K1 = p[0] * w1 + mr * (d2 * s3 - d3 * s2) - kc * a1 * w2 * w3
    K2 = p[1] * w2 + mr * (d3 * s1 - d1 * s3) - kc * a2 * w3 * w1
    K3 = p[2] * w3 + mr * (d1 * s2 - d2 * s1) - kc * a3 * w1 * w2
    return K1, K2, K3


@njit(cache=True)
def energy(y, p):
    """Kinetic energy of carrier and mass plus spring energy, docs/models.md A.2 (J)."""
    w1, w2, w3 = y[0], y[1], y[2]
    d1, d2, d3 = y[3], y[4], p[7] + y[5]
    s1 = w2 * d3 - w3 * d2 + y[6]
    s2 = w3 * d1 - w1 * d3 + y[7]
    s3 = w1 * d2 - w2 * d1 + y[8]
    return 0.5 * (p[0] * w1 * w1 + p[1] * w2 * w2 + p[2] * w3 * w3
                  + p[6] * (s1 * s1 + s2 * s2 + s3 * s3)
                  + p[8] * (y[3] * y[3] + y[4] * y[4] + y[5] * y[5]))


@njit(cache=True)
def braking_norm(y, p):
    """|G| of the control law: |K| (law 0, and a thruster's, whose run ends too if it brings K to rest) or
    |J* w| (law 1)."""
    if p[12] != 1.0:
        K1, K2, K3 = momentum(y, p)
        return math.sqrt(K1 * K1 + K2 * K2 + K3 * K3)
    return math.sqrt((p[3] * y[0]) ** 2 + (p[4] * y[1]) ** 2 + (p[5] * y[2]) ** 2)


@njit(cache=True)
def rhs(t, y, p, out):
    w1, w2, w3 = y[0], y[1], y[2]
    u1, u2, u3 = y[3], y[4], y[5]
    v1, v2, v3 = y[6], y[7], y[8]
    d1, d2, d3 = u1, u2, p[7] + u3
    mr, c, delta, mu, b, lam, kc = p[6], p[8], p[9], p[10], p[11], p[13], p[14]
    A, B, C = p[3], p[4], p[5]

    K1, K2, K3 = momentum(y, p)
    # external torque: bounded braking along -G/|G| and the medium's -lambda J* w
    M1 = -lam * A * w1
    M2 = -lam * B * w2
    M3 = -lam * C * w3
    if b > 0.0 and p[12] >= 2.0:  # a thruster fixed in the body
        axis = int(p[12] - 2.0)
        push = b if axis % 2 == 0 else -b
        if axis < 2:
            M1 += push
        elif axis < 4:
            M2 += push
        else:
            M3 += push
    elif b > 0.0:
        if p[12] == 0.0:
            G1, G2, G3 = K1, K2, K3
        else:
            G1, G2, G3 = A * w1, B * w2, C * w3
        Gn = math.sqrt(G1 * G1 + G2 * G2 + G3 * G3)
        if Gn > 0.0:
            M1 -= b * G1 / Gn
            M2 -= b * G2 / Gn
            M3 -= b * G3 / Gn

    # spring, damper and quadratic friction on the mass (relative velocity v)
    vn = math.sqrt(v1 * v1 + v2 * v2 + v3 * v3)
    damp = delta + mu * vn
    F1 = -c * u1 - damp * v1
    F2 = -c * u2 - damp * v2
    F3 = -c * u3 - damp * v3
    wd1 = w2 * d3 - w3 * d2
    wd2 = w3 * d1 - w1 * d3
    wd3 = w1 * d2 - w2 * d1
    wv1 = w2 * v3 - w3 * v2
    wv2 = w3 * v1 - w1 * v3
    wv3 = w1 * v2 - w2 * v1
    R1 = F1 - mr * (2.0 * wv1 + (w2 * wd3 - w3 * wd2))
    R2 = F2 - mr * (2.0 * wv2 + (w3 * wd1 - w1 * wd3))
    R3 = F3 - mr * (2.0 * wv3 + (w1 * wd2 - w2 * wd1))

    # right side of (Jb - kc Df) w' = M - w x K - m_r v x (w x d) - m_r d x (w x v) - d x R2
    r1 = M1 - (w2 * K3 - w3 * K2) - mr * (v2 * wd3 - v3 * wd2) - mr * (d2 * wv3 - d3 * wv2) - (d2 * R3 - d3 * R2)
    r2 = M2 - (w3 * K1 - w1 * K3) - mr * (v3 * wd1 - v1 * wd3) - mr * (d3 * wv1 - d1 * wv3) - (d3 * R1 - d1 * R3)
    r3 = M3 - (w1 * K2 - w2 * K1) - mr * (v1 * wd2 - v2 * wd1) - mr * (d1 * wv2 - d2 * wv1) - (d1 * R2 - d2 * R1)

    if kc == 0.0:
        a1 = r1 / p[0]
        a2 = r2 / p[1]
        a3 = r3 / p[2]
        tcav = 0.0
    else:
        c1 = kc * (B - C) / A
        c2 = kc * (C - A) / B
        c3 = kc * (A - B) / C
        # M = diag(Jb) - kc Df(w); Df rows: (0, a1 w3, a1 w2), (a2 w3, 0, a2 w1), (a3 w2, a3 w1, 0)
        m11, m12, m13 = p[0], -c1 * w3, -c1 * w2
        m21, m22, m23 = -c2 * w3, p[1], -c2 * w1
        m31, m32, m33 = -c3 * w2, -c3 * w1, p[2]
        det = m11 * (m22 * m33 - m23 * m32) - m12 * (m21 * m33 - m23 * m31) + m13 * (m21 * m32 - m22 * m31)
        a1 = (r1 * (m22 * m33 - m23 * m32) - m12 * (r2 * m33 - m23 * r3) + m13 * (r2 * m32 - m22 * r3)) / det
        a2 = (m11 * (r2 * m33 - m23 * r3) - r1 * (m21 * m33 - m23 * m31) + m13 * (m21 * r3 - r2 * m31)) / det
        a3 = (m11 * (m22 * r3 - r2 * m32) - m12 * (m21 * r3 - r2 * m31) + r1 * (m21 * m32 - m22 * m31)) / det
        # power of the cavity torque kc (Df w' + w x f) on the solid: the w x f part does no work
        tcav = w1 * (c1 * (w3 * a2 + w2 * a3)) + w2 * (c2 * (w3 * a1 + w1 * a3)) + w3 * (c3 * (w2 * a1 + w1 * a2))

    out[0] = a1
    out[1] = a2
    out[2] = a3
    out[3] = v1
    out[4] = v2
    out[5] = v3
    out[6] = R1 / mr + (d2 * a3 - d3 * a2)
    out[7] = R2 / mr + (d3 * a1 - d1 * a3)
    out[8] = R3 / mr + (d1 * a2 - d2 * a1)
    quaternion_rate(y, 9, w1, w2, w3, out)
    out[13] = damp * vn * vn
    out[14] = -(M1 * w1 + M2 * w2 + M3 * w3 + tcav)


@njit(cache=True, nogil=True)
def observe(Y, p):
    """Total K (n, 3, body frame) and energy E (n,) along a trajectory Y (n, 15)."""
    n = Y.shape[0]
    K = np.empty((n, 3))
    E = np.empty(n)
    for i in range(n):
        K[i, 0], K[i, 1], K[i, 2] = momentum(Y[i], p)
        E[i] = energy(Y[i], p)
    return K, E
