"""Compiled right-hand side of the viscous wheel damper's full model, docs/models.md Part C.

A wheel of axial moment J turns about the body-fixed unit axis a in a viscous bearing (torque -c Omega_w on the
wheel, its reaction on the body). I = diag(A, B, C) are the principal moments of the frozen system (the wheel
locked, so they include it). With Omega_w the wheel's rate relative to the body, the total angular momentum in
body axes and the energy are

    K = I w + J Omega_w a,        T = 1/2 w.I.w + J (a.w) Omega_w + 1/2 J Omega_w^2,

and the motion is  K' + w x K = 0  (no external torque),  J (a.w' + Omega_w') = -c Omega_w  (the wheel).
Eliminating Omega_w' gives (I - J a a^T) w' = -w x K + c Omega_w a, solved by Sherman-Morrison with
g = I^-1 a:  w' = u + J g (a.u) / (1 - J a.g),  u = I^-1 (-w x K + c Omega_w a). 1 - J a.g > 0 is the
scenario's check on J (the body without the wheel's axial share keeps a positive inertia).
Along the motion T' = -c Omega_w^2: W' = c Omega_w^2 keeps E + W = E0.

State (10): w (3) body angular velocity, rad/s; phi_w (1) the wheel's angle relative to the body, rad (for
drawing); Omega_w (1) its relative rate, rad/s; quaternion (4), scalar first, body -> inertial; W (1) work
dissipated in the bearing, J.

Parameters (8), see ``physics.systems.wheel.models.pack``: A, B, C (kg m^2), J (kg m^2), c (N m s), a (3, unit).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .attitude import quaternion_rate

NY = 10
NP = 8


@njit(cache=True)
def momentum(y, p):
    """Total angular momentum K (body components), kg m^2/s."""
    h = p[3] * y[4]
    return p[0] * y[0] + h * p[5], p[1] * y[1] + h * p[6], p[2] * y[2] + h * p[7]


@njit(cache=True)
def energy(y, p):
    """Kinetic energy of body and wheel, J."""
    w1, w2, w3, Om = y[0], y[1], y[2], y[4]
    aw = p[5] * w1 + p[6] * w2 + p[7] * w3
    return 0.5 * (p[0] * w1 * w1 + p[1] * w2 * w2 + p[2] * w3 * w3) + p[3] * Om * (aw + 0.5 * Om)


@njit(cache=True)
def rhs(t, y, p, out):
    w1, w2, w3, Om = y[0], y[1], y[2], y[4]
    A, B, C, J, c = p[0], p[1], p[2], p[3], p[4]
    a1, a2, a3 = p[5], p[6], p[7]
    K1, K2, K3 = momentum(y, p)
    torque = c * Om  # the bearing's reaction on the body, along a
    u1 = (-(w2 * K3 - w3 * K2) + torque * a1) / A
    u2 = (-(w3 * K1 - w1 * K3) + torque * a2) / B
    u3 = (-(w1 * K2 - w2 * K1) + torque * a3) / C
    g1, g2, g3 = a1 / A, a2 / B, a3 / C
    au = a1 * u1 + a2 * u2 + a3 * u3
    s = J * au / (1.0 - J * (a1 * g1 + a2 * g2 + a3 * g3))
    out[0] = u1 + s * g1
    out[1] = u2 + s * g2
    out[2] = u3 + s * g3
    out[3] = Om
    out[4] = -torque / J - (a1 * out[0] + a2 * out[1] + a3 * out[2])
    quaternion_rate(y, 5, w1, w2, w3, out)
    out[9] = torque * Om


@njit(cache=True, nogil=True)
def observe(Y, p):
    """Total K (n, 3, body frame) and energy E (n,) along a trajectory Y (n, 10)."""
    n = Y.shape[0]
    K = np.empty((n, 3))
    E = np.empty(n)
    for i in range(n):
        K[i, 0], K[i, 1], K[i, 2] = momentum(Y[i], p)
        E[i] = energy(Y[i], p)
    return K, E
