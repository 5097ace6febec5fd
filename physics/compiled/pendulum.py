"""Compiled right-hand sides of the full pendulum-damper models, docs/models.md Part B section 2.

A carrier of general inertia I_c (3x3 about its own COM G_B, symmetric positive definite, products
of inertia allowed) carries N point bobs. No external loads, so the system COM O is fixed and the
carrier's translation is eliminated exactly (the reduced Lagrangian of B.2):

    L = 1/2 w.I_c.w + 1/2 sum m_i |v_i|^2 - |sum m_i v_i|^2 / (2 M) - V,   v_i = w x r_i + J_i q_i'.

Its equations, linear in X = [w'; q''] and solved each call by Cholesky (the matrix is the SPD mass
matrix of L), are

    carrier:  I_c w' + w x (I_c w) + sum m_i r_i x A_i = 0
    joint i:  m_i J_i^T A_i = -k_i q_i - c_i q_i'
    A_i = a_i - sum_j m_j a_j / M,
    a_i = w' x r_i + w x (w x r_i) + 2 w x (J_i q_i') + sum_ab r_i,ab q_a' q_b' + J_i q_i''.

Geometries (``kind`` = p[0]):
- 0, spherical pendulum (Alger), one bob: q = (alpha, beta), arm e = R_x(alpha) R_y(beta) e3 =
  (sin b, -sin a cos b, cos a cos b), r = pivot + l e; spring k and damper c_d on both angles.
  The Cardan angles are singular at |beta| = 90 deg (e = +-e1). Without a spring (k = 0) the run goes
  on there by switching charts (``switch_chart``, after an accepted step): near e = +-e1 the angles
  become those of chart 1, e = R_y(alpha) R_x(beta) e3 = (sin a cos b, -sin b, cos a cos b), singular
  at e = +-e2 instead, with the damper on chart 1's angle rates (both charts' dampers dissipate
  c (|e'|^2 + sin^2 b alpha'^2) >= 0, so E + W stays conserved); the chart in use is the last state
  value. A spring acts on the Cardan angles themselves, which the bob's position does not determine
  at the pole: with k > 0 the run still stops there (``fault``), and a state in chart 1 (carried from a
  run with k = 0) is written in chart 0 before the first step (``switch_chart``, which the integrators
  call at the start too), so the spring acts on the gimbal angles wherever the bob is.
  The pivot model (``pendulum.pivot``, p[o+PIVOT], o = HEADER): CARDAN (0) is the above, the paper's (docs/models.md
  B.1). ISOTROPIC (1) puts the spring and the damper on the arm's direction e (body frame) instead of on the
  angles: V = k (1 - e.e3), R = c |e'|^2/2. Both charts have e_z = cos a cos b, |de/da| = cos b, |de/db| = 1
  and de/da . de/db = 0, so in either chart Q_alpha = -k sin a cos b - c cos^2 b alpha',
  Q_beta = -k cos a sin b - c beta', U = k (1 - cos a cos b) and the damper dissipates
  c (cos^2 b alpha'^2 + beta'^2) = c |e'|^2. To second order in the angles this is the Cardan model (linear
  theory and tuning are unchanged); being chart-free it goes on through the pole with k > 0 by the same
  chart switch, and ``fault`` never fires for it.
- 1, N plane pendulums (Taylor): q_i = a_i, r_i = hinge_i + l_i (cos a_i e0_i + sin a_i f_i),
  f_i = n_i x e0_i; spring k_i, damper c_i.

State (3 + 2 nq + 5, + 1 spherical), nq = 2 (spherical) or N (plane): w (3) carrier angular velocity, body
components, rad/s; q (nq) rad; q' (nq) rad/s; quaternion (4), scalar first, body -> inertial;
W (1) work dissipated by the dampers, J; the spherical pendulum's chart (0 or 1, index CHART = 12).

Parameters p (12 + 16 N), see ``physics.systems.pendulum.models.pack``:
    p[0]  kind (0 spherical, 1 plane)     p[1]  N, number of bobs     p[2]  M, total mass (kg)
    p[3:12]  I_c row-major (kg m^2, about G_B, body axes)
    bob i at o = 12 + 16 i:  p[o] m (kg), p[o+1] l (m), p[o+2] k (N m/rad), p[o+3] c (N m s/rad),
        p[o+4:o+7] pivot or hinge point from G_B (m), p[o+7:o+10] unit hinge axis n,
        p[o+10:o+13] unit arm direction at rest e0, p[o+13:o+16] f = n x e0.
    For the spherical pendulum the kernel reads the pivot point and p[o+7] (o + PIVOT), the pivot model
    (CARDAN 0, ISOTROPIC 1); p[o+8:o+16] are unused (0).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .attitude import quaternion_rate

HEADER = 12
BOB = 16
SPHERICAL, PLANE = 0, 1
GIMBAL_LIMIT = 1e-3  # |cos beta| below which the Cardan angles are given up (mass matrix ~ cos^2 beta)
CHART = 12  # the spherical pendulum's chart index in its state (after W)
PIVOT = 7  # the spherical pendulum's pivot model, p[HEADER + PIVOT] (a slot the plane pendulum uses for its axis)
CARDAN, ISOTROPIC = 0, 1  # spring and damper on the Cardan angles (the paper), or on the arm's direction
# |e_x| (= |sin beta| in chart 0) above which chart 0 gives way to chart 1 (beta past 60 deg), and below
# which chart 1 gives way to chart 0 again (45 deg): the band between them keeps a run from switching
# back and forth, and chart 1 never comes near its own pole (|beta_1| < 45 deg while in use).
CHART_OUT = math.sin(math.pi / 3.0)
CHART_BACK = math.sin(math.pi / 4.0)


def n_params(n_bobs: int) -> int:
    return HEADER + BOB * n_bobs


def n_coordinates(kind: int, n_bobs: int) -> int:
    return 2 if kind == SPHERICAL else n_bobs


def n_state(kind: int, n_bobs: int) -> int:
    return 3 + 2 * n_coordinates(kind, n_bobs) + 5 + (1 if kind == SPHERICAL else 0)


@njit(cache=True)
def _sizes(p):
    nb = int(p[1])
    nq = 2 if p[0] == SPHERICAL else nb
    return nb, nq


@njit(cache=True)
def _geometry(y, p, R, Jq, Cq):
    """Bob positions R (N, 3) from G_B, their Jacobians Jq (N, 3, nq) = dr_i/dq and the velocity-
    quadratic terms Cq (N, 3) = sum_ab d2 r_i/dq_a dq_b q_a' q_b'."""
    nb, nq = _sizes(p)
    Jq[:] = 0.0
    if p[0] == SPHERICAL:
        o = HEADER
        l = p[o + 1]
        a, b = y[3], y[4]
        ad, bd = y[5], y[6]
        sa, ca, sb, cb = math.sin(a), math.cos(a), math.sin(b), math.cos(b)
        if y.size <= CHART or y[CHART] < 0.5:  # chart 0, the Cardan angles of docs/models.md B.2 (a state without
            # the chart value, 12 long as before issue 17, is read as chart 0 rather than read past its end)
            e = (sb, -sa * cb, ca * cb)
            ea = (0.0, -ca * cb, -sa * cb)
            eb = (cb, sa * sb, -ca * sb)
            eaa = (0.0, sa * cb, -ca * cb)
            eab = (0.0, ca * sb, sa * sb)
            ebb = (-sb, sa * cb, -ca * cb)
        else:  # chart 1, near chart 0's pole
            e = (sa * cb, -sb, ca * cb)
            ea = (ca * cb, 0.0, -sa * cb)
            eb = (-sa * sb, -cb, -ca * sb)
            eaa = (-sa * cb, 0.0, -ca * cb)
            eab = (-ca * sb, 0.0, sa * sb)
            ebb = (-sa * cb, sb, -ca * cb)
        for j in range(3):
            R[0, j] = p[o + 4 + j] + l * e[j]
            Jq[0, j, 0] = l * ea[j]
            Jq[0, j, 1] = l * eb[j]
            Cq[0, j] = l * (eaa[j] * ad * ad + 2.0 * eab[j] * ad * bd + ebb[j] * bd * bd)
    else:
        for i in range(nb):
            o = HEADER + BOB * i
            l = p[o + 1]
            a, ad = y[3 + i], y[3 + nq + i]
            sa, ca = math.sin(a), math.cos(a)
            for j in range(3):
                u = ca * p[o + 10 + j] + sa * p[o + 13 + j]  # arm direction
                R[i, j] = p[o + 4 + j] + l * u
                Jq[i, j, i] = l * (ca * p[o + 13 + j] - sa * p[o + 10 + j])
                Cq[i, j] = -l * u * ad * ad


@njit(cache=True)
def _velocities(y, p, R, Jq, V):
    """Bob velocities relative to G_B, v_i = w x r_i + J_i q' (N, 3)."""
    nb, nq = _sizes(p)
    w1, w2, w3 = y[0], y[1], y[2]
    for i in range(nb):
        V[i, 0] = w2 * R[i, 2] - w3 * R[i, 1]
        V[i, 1] = w3 * R[i, 0] - w1 * R[i, 2]
        V[i, 2] = w1 * R[i, 1] - w2 * R[i, 0]
        for j in range(3):
            for a in range(nq):
                V[i, j] += Jq[i, j, a] * y[3 + nq + a]


@njit(cache=True)
def _state_geometry(y, p):
    nb, nq = _sizes(p)
    R = np.empty((nb, 3))
    Jq = np.empty((nb, 3, nq))
    Cq = np.empty((nb, 3))
    V = np.empty((nb, 3))
    _geometry(y, p, R, Jq, Cq)
    _velocities(y, p, R, Jq, V)
    return R, Jq, Cq, V


@njit(cache=True)
def momentum(y, p):
    """Angular momentum about the system COM O, body components (docs/models.md B.2 "Invariants"):
    H = I_c w + sum m_i r_i x v_i - (sum m_i r_i) x (sum m_i v_i) / M."""
    nb, _ = _sizes(p)
    R, _, _, V = _state_geometry(y, p)
    M = p[2]
    H = np.zeros(3)
    sr = np.zeros(3)
    sv = np.zeros(3)
    for j in range(3):
        for k in range(3):
            H[j] += p[3 + 3 * j + k] * y[k]
    for i in range(nb):
        m = p[HEADER + BOB * i]
        H[0] += m * (R[i, 1] * V[i, 2] - R[i, 2] * V[i, 1])
        H[1] += m * (R[i, 2] * V[i, 0] - R[i, 0] * V[i, 2])
        H[2] += m * (R[i, 0] * V[i, 1] - R[i, 1] * V[i, 0])
        for j in range(3):
            sr[j] += m * R[i, j]
            sv[j] += m * V[i, j]
    H[0] -= (sr[1] * sv[2] - sr[2] * sv[1]) / M
    H[1] -= (sr[2] * sv[0] - sr[0] * sv[2]) / M
    H[2] -= (sr[0] * sv[1] - sr[1] * sv[0]) / M
    return H


@njit(cache=True)
def energy(y, p):
    """Kinetic energy of carrier and bobs (translation of the carrier included) plus spring energy, J."""
    nb, nq = _sizes(p)
    R, _, _, V = _state_geometry(y, p)
    M = p[2]
    T = 0.0
    for j in range(3):
        for k in range(3):
            T += 0.5 * y[j] * p[3 + 3 * j + k] * y[k]
    sv = np.zeros(3)
    for i in range(nb):
        m = p[HEADER + BOB * i]
        for j in range(3):
            T += 0.5 * m * V[i, j] * V[i, j]
            sv[j] += m * V[i, j]
    T -= 0.5 * (sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]) / M
    return T + _spring_energy(y, p)


@njit(cache=True)
def _isotropic(p):
    """The spherical pendulum's spring and damper act on the arm's direction, not on the angles."""
    return p[0] == SPHERICAL and p[HEADER + PIVOT] == ISOTROPIC


@njit(cache=True)
def _spring_energy(y, p):
    """U, J: k (1 - cos a cos b) for the isotropic pivot (the same in both charts), else sum k q^2/2."""
    if _isotropic(p):
        return p[HEADER + 2] * (1.0 - math.cos(y[3]) * math.cos(y[4]))
    _, nq = _sizes(p)
    U = 0.0
    for a in range(nq):
        U += 0.5 * _spring(p, a) * y[3 + a] * y[3 + a]
    return U


@njit(cache=True)
def _joint_forces(y, p, Q):
    """The springs' and dampers' generalized forces Q (nq,) on the joint coordinates, N m."""
    _, nq = _sizes(p)
    if _isotropic(p):  # -dV/dq - dR/dq' with V = k (1 - e_z), R = c |e'|^2/2 (module docstring)
        k, c = p[HEADER + 2], p[HEADER + 3]
        sa, ca, sb, cb = math.sin(y[3]), math.cos(y[3]), math.sin(y[4]), math.cos(y[4])
        Q[0] = -k * sa * cb - c * cb * cb * y[5]
        Q[1] = -k * ca * sb - c * y[6]
        return
    for a in range(nq):
        Q[a] = -_spring(p, a) * y[3 + a] - _damper(p, a) * y[3 + nq + a]


@njit(cache=True)
def _dissipation(y, p):
    """The dampers' power, W' = 2 R >= 0, W."""
    _, nq = _sizes(p)
    if _isotropic(p):
        cb = math.cos(y[4])
        return p[HEADER + 3] * (cb * cb * y[5] * y[5] + y[6] * y[6])
    power = 0.0
    for a in range(nq):
        power += _damper(p, a) * y[3 + nq + a] * y[3 + nq + a]
    return power


@njit(cache=True)
def _spring(p, a):
    """k of coordinate a."""
    return p[HEADER + 2] if p[0] == SPHERICAL else p[HEADER + BOB * a + 2]


@njit(cache=True)
def _damper(p, a):
    """c of coordinate a."""
    return p[HEADER + 3] if p[0] == SPHERICAL else p[HEADER + BOB * a + 3]


@njit(cache=True)
def _cholesky_solve(Mm, x):
    """Solve Mm z = x in place (x <- z) for a symmetric positive-definite Mm (overwritten).
    A pivot that is not positive (only at the gimbal singularity, to rounding) gives z = NaN, which
    makes the integrator shrink its step instead of dividing by zero."""
    n = x.size
    for j in range(n):
        s = Mm[j, j]
        for k in range(j):
            s -= Mm[j, k] * Mm[j, k]
        if not s > 0.0:
            x[:] = np.nan
            return
        d = math.sqrt(s)
        Mm[j, j] = d
        for i in range(j + 1, n):
            s = Mm[i, j]
            for k in range(j):
                s -= Mm[i, k] * Mm[j, k]
            Mm[i, j] = s / d
    for i in range(n):
        s = x[i]
        for k in range(i):
            s -= Mm[i, k] * x[k]
        x[i] = s / Mm[i, i]
    for i in range(n - 1, -1, -1):
        s = x[i]
        for k in range(i + 1, n):
            s -= Mm[k, i] * x[k]
        x[i] = s / Mm[i, i]


@njit(cache=True)
def accelerations(y, p):
    """X = [w'; q''] of docs/models.md B.2: the mass matrix and right side are assembled from
    P_i = [e_j x r_i | J_i] (so v_i = P_i [w; q']) and solved."""
    nb, nq = _sizes(p)
    n = 3 + nq
    R, Jq, Cq, _ = _state_geometry(y, p)
    M = p[2]
    w = y[0:3]
    qd = y[3 + nq:3 + 2 * nq]
    Mm = np.zeros((n, n))
    rhs = np.zeros(n)
    S = np.zeros((3, n))  # sum_i m_i P_i
    sb = np.zeros(3)  # sum_i m_i b_i
    P = np.empty((3, n))
    bi = np.empty(3)
    Iw = np.zeros(3)
    for j in range(3):
        for k in range(3):
            Mm[j, k] = p[3 + 3 * j + k]
            Iw[j] += p[3 + 3 * j + k] * w[k]
    rhs[0] = -(w[1] * Iw[2] - w[2] * Iw[1])
    rhs[1] = -(w[2] * Iw[0] - w[0] * Iw[2])
    rhs[2] = -(w[0] * Iw[1] - w[1] * Iw[0])
    _joint_forces(y, p, rhs[3:])
    for i in range(nb):
        m = p[HEADER + BOB * i]
        r = R[i]
        # columns of P_i: e_j x r for the carrier, dr_i/dq for the joints
        P[0, 0], P[1, 0], P[2, 0] = 0.0, -r[2], r[1]
        P[0, 1], P[1, 1], P[2, 1] = r[2], 0.0, -r[0]
        P[0, 2], P[1, 2], P[2, 2] = -r[1], r[0], 0.0
        for j in range(3):
            for a in range(nq):
                P[j, 3 + a] = Jq[i, j, a]
        # b_i: the part of a_i without X, w x (w x r) + 2 w x (J q') + Cq
        wr0 = w[1] * r[2] - w[2] * r[1]
        wr1 = w[2] * r[0] - w[0] * r[2]
        wr2 = w[0] * r[1] - w[1] * r[0]
        g0 = g1 = g2 = 0.0
        for a in range(nq):
            g0 += Jq[i, 0, a] * qd[a]
            g1 += Jq[i, 1, a] * qd[a]
            g2 += Jq[i, 2, a] * qd[a]
        bi[0] = w[1] * wr2 - w[2] * wr1 + 2.0 * (w[1] * g2 - w[2] * g1) + Cq[i, 0]
        bi[1] = w[2] * wr0 - w[0] * wr2 + 2.0 * (w[2] * g0 - w[0] * g2) + Cq[i, 1]
        bi[2] = w[0] * wr1 - w[1] * wr0 + 2.0 * (w[0] * g1 - w[1] * g0) + Cq[i, 2]
        for u in range(n):
            for v in range(n):
                Mm[u, v] += m * (P[0, u] * P[0, v] + P[1, u] * P[1, v] + P[2, u] * P[2, v])
            rhs[u] -= m * (P[0, u] * bi[0] + P[1, u] * bi[1] + P[2, u] * bi[2])
            for j in range(3):
                S[j, u] += m * P[j, u]
        for j in range(3):
            sb[j] += m * bi[j]
    # the carrier COM accelerates at -Abar: subtract the bobs' common part (rank-3 update)
    for u in range(n):
        for v in range(n):
            Mm[u, v] -= (S[0, u] * S[0, v] + S[1, u] * S[1, v] + S[2, u] * S[2, v]) / M
        rhs[u] += (S[0, u] * sb[0] + S[1, u] * sb[1] + S[2, u] * sb[2]) / M
    _cholesky_solve(Mm, rhs)
    return rhs


@njit(cache=True)
def rhs(t, y, p, out):
    _, nq = _sizes(p)
    X = accelerations(y, p)
    w1, w2, w3 = y[0], y[1], y[2]
    out[0] = X[0]
    out[1] = X[1]
    out[2] = X[2]
    for a in range(nq):
        out[3 + a] = y[3 + nq + a]
        out[3 + nq + a] = X[3 + a]
    o = 3 + 2 * nq
    quaternion_rate(y, o, w1, w2, w3, out)
    out[o + 4] = _dissipation(y, p)
    if p[0] == SPHERICAL and out.size > CHART:
        out[CHART] = 0.0  # the chart changes only by switch_chart


@njit(cache=True)
def fault(y, p):
    """1 at the spherical pendulum's gimbal singularity (|cos beta| < GIMBAL_LIMIT) with a spring on the
    Cardan angles (k != 0, the Cardan pivot; without one, or with the isotropic pivot, the chart switches
    before), or in chart 1 with such a spring (``switch_chart`` leaves it there only at chart 0's pole), else 0."""
    if (p[0] == SPHERICAL and p[HEADER + 2] != 0.0 and p[HEADER + PIVOT] == CARDAN
            and (abs(math.cos(y[4])) < GIMBAL_LIMIT or (y.size > CHART and y[CHART] >= 0.5))):
        return 1
    return 0


@njit(cache=True)
def _direction(chart, a, b):
    """The arm direction e and its unit-speed tangents de/da, de/db of ``chart`` (|de/da| = cos b,
    |de/db| = 1, orthogonal)."""
    sa, ca, sb, cb = math.sin(a), math.cos(a), math.sin(b), math.cos(b)
    if chart == 0:
        return (np.array([sb, -sa * cb, ca * cb]), np.array([0.0, -ca * cb, -sa * cb]),
                np.array([cb, sa * sb, -ca * sb]))
    return (np.array([sa * cb, -sb, ca * cb]), np.array([ca * cb, 0.0, -sa * cb]),
            np.array([-sa * sb, -cb, -ca * sb]))


@njit(cache=True)
def switch_chart(y, p):
    """Re-express the spherical pendulum's bob in the other chart when it nears the pole of the one in use
    (k = 0, or the isotropic pivot, whose spring and damper do not depend on the chart): the same arm
    direction e and rate e' (so the same position, velocity, H and E), new angles and rates, in place.
    A spring on the Cardan angles acts on chart 0's angles, so a state in chart 1 (carried from a run without
    one: the app's k raised while the bob is past 60 deg) goes back to chart 0 at once, wherever chart 0 is
    defined; at its pole it stays, and ``fault`` stops the run. Returns 1 when it switched, else 0."""
    if p[0] != SPHERICAL or y.size <= CHART:
        return 0
    chart = 0 if y[CHART] < 0.5 else 1
    ex = abs(math.sin(y[4]) if chart == 0 else math.sin(y[3]) * math.cos(y[4]))  # |e_x|
    if p[HEADER + 2] != 0.0 and not _isotropic(p):
        if chart == 1 and math.sqrt(max(0.0, 1.0 - ex * ex)) >= GIMBAL_LIMIT:  # chart 0's |cos beta|
            to_chart(y, 0)
            return 1
        return 0
    if chart == 0 and ex > CHART_OUT:
        to_chart(y, 1)
        return 1
    if chart == 1 and ex < CHART_BACK:
        to_chart(y, 0)
        return 1
    return 0


@njit(cache=True)
def to_chart(y, new):
    """Write the spherical pendulum's angles and rates of ``y`` in chart ``new``, in place: the same arm
    direction e and rate e'. (Exact away from the new chart's pole, where its alpha' would divide by 0.)"""
    e, ea, eb = _direction(0 if y[CHART] < 0.5 else 1, y[3], y[4])
    if new == 1:
        b = math.atan2(-e[1], math.hypot(e[0], e[2]))
        a = math.atan2(e[0], e[2])
    else:
        b = math.atan2(e[0], math.hypot(e[1], e[2]))
        a = math.atan2(-e[1], e[2])
    ed = ea * y[5] + eb * y[6]
    _, fa, fb = _direction(new, a, b)
    cb = math.cos(b)
    y[3], y[4] = a, b
    y[5] = (ed[0] * fa[0] + ed[1] * fa[1] + ed[2] * fa[2]) / (cb * cb)
    y[6] = ed[0] * fb[0] + ed[1] * fb[1] + ed[2] * fb[2]
    y[CHART] = float(new)


@njit(cache=True, nogil=True)
def observe(Y, p):
    """Total H (n, 3, body components, about O) and energy E (n,) along a trajectory Y (n, ny)."""
    n = Y.shape[0]
    H = np.empty((n, 3))
    E = np.empty(n)
    for i in range(n):
        H[i] = momentum(Y[i], p)
        E[i] = energy(Y[i], p)
    return H, E
