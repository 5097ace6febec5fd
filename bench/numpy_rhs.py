"""Plain numpy right-hand sides: what a user of scipy would write for the same equations.

They are the "scipy with a numpy right-hand side" peer of the benchmark: 3-vectors in numpy
arrays (with a small ``cross``: np.cross is slow on 3-vectors), one Python call per evaluation.
MODELS.md A.2, state as physics/compiled/mass_full.py (w, u, v, q, W_int, W_ext), no cavity,
medium or control.
"""

from __future__ import annotations

import numpy as np


def cross(a, b):
    """a x b for 3-vectors: np.cross is general and ~10x slower on length-3 arrays."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def moving_mass_rhs(p: np.ndarray):
    """f(t, y) of the full moving-mass model for solve_ivp; p as physics.models.moving_mass.pack_full."""
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
