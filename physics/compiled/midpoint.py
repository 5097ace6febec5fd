"""Structure-preserving integrator for long runs of the full moving-mass model: implicit midpoint
in momentum variables, with the attitude advanced by an exact rotation.

Why this method. In the variables z = (K, u, p_u) -- K the total angular momentum (body frame),
u the displacement of the mass, p_u = m_r (u' + w x d) its conjugate momentum -- the model of
docs/models.md A.2 without external torque is a Lie-Poisson system on so(3)* x T*R^3 with Hamiltonian

    H = 1/2 (K - d x p_u) . Jb^-1 (K - d x p_u) + |p_u|^2 / (2 m_r) + c |u|^2 / 2,   w = Jb^-1 (K - d x p_u),

    K' = K x w,   u' = p_u/m_r - w x d,   p_u' = p_u x w - c u - (delta + mu |u'|) u'.

(The relation w = Jb^-1 (K - d x p_u) is explicit: no 3x3 solve.) The implicit midpoint rule

* keeps every quadratic invariant exactly, so |K|^2 (the Casimir) is kept to rounding. We apply
  the K part as its closed form, the Cayley rotation K1 = cay(-h/2 w_mid) K0, so |K| is exact
  to rounding even when the fixed-point iteration stops short of full convergence;
* is symmetric (time-reversible), so for this reversible, near-integrable system the energy error
  stays bounded and oscillates instead of drifting (Hairer-Lubich-Wanner, Geometric Numerical
  Integration, ch. XI); for the bare rigid body (no mass) E is quadratic in K and kept exactly;
* with damping, dissipates through the same midpoint damper force, so W_int matches the lost energy
  to the method's order (2).

A splitting (rigid-body flow exactly, then the internal part) would also keep |K|, but the coupling
term d x p_u sits in the kinetic energy, so the pieces are not separately integrable in closed form;
the midpoint rule treats the coupling without splitting error. The attitude quaternion is advanced
by the exact rotation of angle h |w_mid| about w_mid, so it stays a unit quaternion.

The nonlinear midpoint equations are solved by fixed-point iteration, each iteration one evaluation
of the vector field (counted as nfev). It converges when h times the fastest rate (about Omega,
the mass's natural frequency) is below ~1; otherwise the run stops with status NO_CONVERGENCE.
Order 2. Supported: mass on spring/damper/quadratic friction, no cavity, no medium, no control.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

NO_CONVERGENCE = 6
STATUS_TEXT = ("implicit midpoint: the fixed-point iteration did not converge "
               "(run.dt too large for the mass's frequency)")
MAX_ITER = 60  # fixed-point iterations per step before giving up
ITER_TOL = 2e-15  # relative change of z at which the iteration has converged (a few ulps)
FLOOR_TOL = 1e-12  # below this, a change that stops shrinking is rounding noise: converged too


@njit(cache=True)
def _to_momentum(y, p, z):
    """(w, u, v) of the state y -> z = (K, u, p_u)."""
    mr = p[6]
    w1, w2, w3 = y[0], y[1], y[2]
    d1, d2, d3 = y[3], y[4], p[7] + y[5]
    p1 = mr * (y[6] + w2 * d3 - w3 * d2)
    p2 = mr * (y[7] + w3 * d1 - w1 * d3)
    p3 = mr * (y[8] + w1 * d2 - w2 * d1)
    z[0] = p[0] * w1 + d2 * p3 - d3 * p2
    z[1] = p[1] * w2 + d3 * p1 - d1 * p3
    z[2] = p[2] * w3 + d1 * p2 - d2 * p1
    z[3], z[4], z[5] = y[3], y[4], y[5]
    z[6], z[7], z[8] = p1, p2, p3


@njit(cache=True)
def _velocities(z, p, wv):
    """w (wv[0:3]) and u' (wv[3:6]) from z."""
    d1, d2, d3 = z[3], z[4], p[7] + z[5]
    p1, p2, p3 = z[6], z[7], z[8]
    w1 = (z[0] - (d2 * p3 - d3 * p2)) / p[0]
    w2 = (z[1] - (d3 * p1 - d1 * p3)) / p[1]
    w3 = (z[2] - (d1 * p2 - d2 * p1)) / p[2]
    wv[0], wv[1], wv[2] = w1, w2, w3
    wv[3] = p1 / p[6] - (w2 * d3 - w3 * d2)
    wv[4] = p2 / p[6] - (w3 * d1 - w1 * d3)
    wv[5] = p3 / p[6] - (w1 * d2 - w2 * d1)


@njit(cache=True)
def _step(z0, p, h, z1, zm, wv):
    """One implicit-midpoint step z0 -> z1; returns (iterations, converged, damping power at mid)."""
    c, delta, mu = p[8], p[9], p[10]
    for i in range(9):
        z1[i] = z0[i]
    it = 0
    converged = False
    power = 0.0
    prev = np.inf
    while it < MAX_ITER:
        for i in range(9):
            zm[i] = 0.5 * (z0[i] + z1[i])
        _velocities(zm, p, wv)
        it += 1
        w1, w2, w3 = wv[0], wv[1], wv[2]
        v1, v2, v3 = wv[3], wv[4], wv[5]
        vn = math.sqrt(v1 * v1 + v2 * v2 + v3 * v3)
        damp = delta + mu * vn
        power = damp * vn * vn
        # K: Cayley rotation, the midpoint rule for K' = -w x K, exactly a rotation
        a1, a2, a3 = -0.5 * h * w1, -0.5 * h * w2, -0.5 * h * w3
        K1, K2, K3 = z0[0], z0[1], z0[2]
        x1, x2, x3 = a2 * K3 - a3 * K2, a3 * K1 - a1 * K3, a1 * K2 - a2 * K1  # a x K
        xx1, xx2, xx3 = a2 * x3 - a3 * x2, a3 * x1 - a1 * x3, a1 * x2 - a2 * x1  # a x (a x K)
        f = 2.0 / (1.0 + a1 * a1 + a2 * a2 + a3 * a3)
        n0 = K1 + f * (x1 + xx1)
        n1 = K2 + f * (x2 + xx2)
        n2 = K3 + f * (x3 + xx3)
        pm1, pm2, pm3 = zm[6], zm[7], zm[8]
        n3 = z0[3] + h * v1
        n4 = z0[4] + h * v2
        n5 = z0[5] + h * v3
        n6 = z0[6] + h * (pm2 * w3 - pm3 * w2 - c * zm[3] - damp * v1)
        n7 = z0[7] + h * (pm3 * w1 - pm1 * w3 - c * zm[4] - damp * v2)
        n8 = z0[8] + h * (pm1 * w2 - pm2 * w1 - c * zm[5] - damp * v3)
        change = 0.0
        scale = 0.0
        new = (n0, n1, n2, n3, n4, n5, n6, n7, n8)
        for i in range(9):
            change = max(change, abs(new[i] - z1[i]))
            scale = max(scale, abs(new[i]))
            z1[i] = new[i]
        if not math.isfinite(change):
            break
        tol = max(scale, 1e-300)
        if change <= ITER_TOL * tol or (change >= prev and change <= FLOOR_TOL * tol):
            converged = True
            break
        prev = change
    # the w of the last midpoint moves the attitude; keep it in wv
    return it, converged, power


@njit(cache=True)
def _rotate_quaternion(q, w1, w2, w3, h):
    """q <- q (x) exp(h w / 2): the exact rotation by angle h|w| about the body axis w."""
    wn = math.sqrt(w1 * w1 + w2 * w2 + w3 * w3)
    ang = 0.5 * h * wn
    cs = math.cos(ang)
    sn = math.sin(ang) / wn if wn > 0.0 else 0.5 * h
    rw, rx, ry, rz = cs, sn * w1, sn * w2, sn * w3
    qw, qx, qy, qz = q[0], q[1], q[2], q[3]
    q[0] = qw * rw - qx * rx - qy * ry - qz * rz
    q[1] = qw * rx + qx * rw + qy * rz - qz * ry
    q[2] = qw * ry - qx * rz + qy * rw + qz * rx
    q[3] = qw * rz + qx * ry - qy * rx + qz * rw


@njit(cache=True)
def _to_state(z, q, W, p, y, wv):
    _velocities(z, p, wv)
    y[0], y[1], y[2] = wv[0], wv[1], wv[2]
    y[3], y[4], y[5] = z[3], z[4], z[5]
    y[6], y[7], y[8] = wv[3], wv[4], wv[5]
    y[9], y[10], y[11], y[12] = q[0], q[1], q[2], q[3]
    y[13] = W
    y[14] = 0.0


@njit(cache=True, nogil=True)
def integrate(y0, p, t_out, dt):
    """Implicit midpoint, step at most ``dt`` (s), from the full model's state y0 (15,) with
    parameters p (15,), storing the state at t_out. Returns (Y, n_filled, status, t_last, y_last,
    nfev, nsteps) like physics/compiled/fixed.integrate."""
    n_out = t_out.size
    Y = np.empty((n_out, 15))
    Y[0] = y0
    z = np.empty(9)
    z1 = np.empty(9)
    zm = np.empty(9)
    wv = np.empty(6)
    _to_momentum(y0, p, z)
    q = y0[9:13].copy()
    W = y0[13]
    y = y0.copy()
    t = t_out[0]
    nfev = 0
    nsteps = 0
    status = 0
    i_out = 1
    while i_out < n_out:
        t_target = t_out[i_out]
        gap = t_target - t
        m = max(1, int(math.ceil(gap / dt - 1e-9)))
        h = gap / m
        for _ in range(m):
            it, ok, power = _step(z, p, h, z1, zm, wv)
            nfev += it
            if not ok:
                status = NO_CONVERGENCE
                break
            _rotate_quaternion(q, wv[0], wv[1], wv[2], h)
            W += h * power
            for i in range(9):
                z[i] = z1[i]
            t += h
            nsteps += 1
        if status != 0:
            break
        t = t_target
        _to_state(z, q, W, p, y, wv)
        for i in range(15):
            Y[i_out, i] = y[i]
        i_out += 1
    _to_state(z, q, W, p, y, wv)
    return Y, i_out, status, t, y, nfev, nsteps
