"""Plain numpy right-hand sides: what a user of scipy would write for the same equations.

They are the "scipy with a numpy right-hand side" peer of the benchmark: 3-vectors in numpy
arrays (with a small ``cross``: np.cross is slow on 3-vectors), one Python call per evaluation.
docs/models.md A.2, state as physics/compiled/mass_full.py (w, u, v, q, W_int, W_ext), no cavity,
medium or control.
"""

from __future__ import annotations

import numpy as np


def cross(a, b):
    """a x b for 3-vectors: np.cross is general and ~10x slower on length-3 arrays."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def moving_mass_rhs(p: np.ndarray):
    """f(t, y) of the full moving-mass model for solve_ivp; p as physics.systems.moving_mass.models.pack_full."""
    Jb = p[0:3]
    mr, d0, c, delta, mu = p[6], p[7], p[8], p[9], p[10]
    e3 = np.array([0.0, 0.0, 1.0])

    def f(t, y):
        w, u, v, q = y[0:3], y[3:6], y[6:9], y[9:13]
        d = d0 * e3 + u
        wd = cross(w, d)
        K = Jb * w + mr * cross(d, wd + v)
        vn = np.linalg.norm(v)
        F = -c * u - (delta + mu * vn) * v
        wv = cross(w, v)
        R = F - mr * (2.0 * wv + cross(w, wd))
        r = -cross(w, K) - mr * cross(v, wd) - mr * cross(d, wv) - cross(d, R)
        a = r / Jb
        vdot = R / mr + cross(d, a)
        qw, qv = q[0], q[1:]
        qdot = np.concatenate([[-0.5 * qv @ w], 0.5 * (qw * w + cross(qv, w))])
        return np.concatenate([a, v, vdot, qdot, [(delta + mu * vn) * vn * vn, 0.0]])

    return f


def spherical_pendulum_rhs(p: np.ndarray):
    """f(t, y) of the full spherical-pendulum damper (docs/models.md B.2, one bob, Cardan angles) for solve_ivp;
    p and the state (w, alpha, beta, alpha', beta', q, W_diss, chart) as physics/compiled/pendulum.py, in
    chart 0 (the Cardan angles; the kernel's chart 1 near their pole is not written out here). p[19], the pivot
    model: 0 the spring and damper on the angles (docs/models.md B.1), 1 on the arm's direction e, V = k (1 - e_z),
    R = c |e'|^2/2 (``pendulum.pivot = "isotropic"``).

    Written as a user would: the mass matrix and the right side of the Lagrange equations assembled
    with numpy from P = [e_j x r | dr/dq], solved with np.linalg.solve.
    """
    if p[0] != 0 or p[1] != 1:
        raise ValueError("spherical_pendulum_rhs covers the spherical pendulum (one bob)")
    M = p[2]
    Ic = p[3:12].reshape(3, 3)
    m, l, k, c = p[12], p[13], p[14], p[15]
    pivot = p[16:19]
    isotropic = p[19] == 1
    mu = m * (1.0 - m / M)  # the bob's reduced mass: the carrier's COM takes up its momentum

    def f(t, y):
        w, (a, b), qd, q = y[0:3], y[3:5], y[5:7], y[7:11]
        sa, ca, sb, cb = np.sin(a), np.cos(a), np.sin(b), np.cos(b)
        e = np.array([sb, -sa * cb, ca * cb])
        J = l * np.array([[0.0, cb], [-ca * cb, sa * sb], [-sa * cb, -ca * sb]])  # dr/d(alpha, beta)
        ad, bd = qd
        Cq = l * (np.array([0.0, sa * cb, -ca * cb]) * ad * ad + 2.0 * np.array([0.0, ca * sb, sa * sb]) * ad * bd
                  + np.array([-sb, sa * cb, -ca * cb]) * bd * bd)
        r = pivot + l * e
        rx = np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])
        P = np.hstack([-rx, J])  # v = P [w; q']
        Jqd = J @ qd
        bias = cross(w, cross(w, r)) + 2.0 * cross(w, Jqd) + Cq
        Mm = mu * P.T @ P
        Mm[0:3, 0:3] += Ic
        rhs = -mu * P.T @ bias
        rhs[0:3] -= cross(w, Ic @ w)
        if isotropic:  # -grad of k (1 - e_z) and of c |e'|^2/2, |e'|^2 = cos^2 b alpha'^2 + beta'^2
            rhs[3:5] -= k * np.array([sa * cb, ca * sb]) + c * np.array([cb * cb, 1.0]) * qd
        else:
            rhs[3:5] -= k * y[3:5] + c * qd
        power = c * (cb * cb * ad * ad + bd * bd) if isotropic else c * (qd @ qd)
        X = np.linalg.solve(Mm, rhs)
        qw, qv = q[0], q[1:]
        qdot = np.concatenate([[-0.5 * qv @ w], 0.5 * (qw * w + cross(qv, w))])
        return np.concatenate([X[0:3], qd, X[3:5], qdot, [power, 0.0]])  # the chart stays

    return f
