"""Linearisation of any set of pendulum bobs about steady spin (docs/models.md Part B sections 2, 3, 7).

The full equations of docs/models.md B.2 are expanded to first order about omega = (0, 0, W) with every bob
at rest. They are linear in the perturbation, so the matrices are assembled column by column from
unit perturbations: no finite differences. For one spherical bob this reproduces the matrix of B.3
(``pendulum_linear.state_matrix``); for plane pendulums it gives the frequencies (15) and the
coupled exponents of the plane-pendulum damper (seed 002 (2), B.7).

State layout y = (delta omega (3), q (N), q' (N)), where q are the joint angles of all bobs in
order (alpha, beta for a spherical bob, one angle per plane pendulum).
"""

from __future__ import annotations

import math

import numpy as np

E3 = np.array([0.0, 0.0, 1.0])
EQUILIBRIUM_TOL = 1e-9  # relative: the rest state must be a steady spin for a linearisation about it


def bob_geometry(bob) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(r0 (3,), J (3, n), H (n, n, 3)) of a ``pendulum_system.Bob``: rest position from the carrier COM,
    dr/dq and d2r/dq_a dq_b at rest (docs/models.md B.1: e = (sin b, -sin a cos b, cos a cos b) for the spherical
    bob; r = p + l (cos a e0 + sin a (n x e0)) for a plane one)."""
    l = bob.l
    if bob.kind == "spherical":
        J = l * np.array([[0.0, 1.0], [-1.0, 0.0], [0.0, 0.0]])
        H = np.zeros((2, 2, 3))
        H[0, 0] = H[1, 1] = -l * E3
        return np.asarray(bob.rest, dtype=float), J, H
    t = np.cross(bob.axis, bob.arm)
    return np.asarray(bob.rest, dtype=float), (l * t)[:, None], (-l * np.asarray(bob.arm))[None, None, :]


class _Bobs:
    def __init__(self, system):
        self.system = system
        self.geo = [bob_geometry(b) for b in system.bobs]
        self.sizes = [g[1].shape[1] for g in self.geo]
        self.N = sum(self.sizes)
        self.offsets = np.cumsum([0] + self.sizes)
        self.m = np.array([b.m for b in system.bobs])
        self.Mtot = float(system.M)
        self.W = float(system.W)
        self.I = np.asarray(system.I_c, dtype=float)

    def residual(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """First-order residual of B.2 (carrier 3 rows, then one row per joint angle) for accelerations
        x = (delta omega', q'') and state y; linear in (x, y) once the zeroth order is subtracted."""
        W, N = self.W, self.N
        dwd, qdd = x[:3], x[3:]
        dw, q, qd = y[:3], y[3:3 + N], y[3 + N:]
        a0, a1, Jq = [], [], []
        for i, (r0, J, _) in enumerate(self.geo):
            sl = slice(self.offsets[i], self.offsets[i + 1])
            jq = J @ q[sl]
            a0.append(W**2 * np.cross(E3, np.cross(E3, r0)))
            a1.append(np.cross(dwd, r0) + W**2 * np.cross(E3, np.cross(E3, jq)) + np.cross(dw, W * np.cross(E3, r0))
                      + W * np.cross(E3, np.cross(dw, r0)) + 2 * W * np.cross(E3, J @ qd[sl]) + J @ qdd[sl])
            Jq.append(jq)
        Abar0 = sum(m * a for m, a in zip(self.m, a0, strict=True)) / self.Mtot
        Abar1 = sum(m * a for m, a in zip(self.m, a1, strict=True)) / self.Mtot
        I = self.I
        carrier = I @ dwd + W * (np.cross(E3, I @ dw) + np.cross(dw, I @ E3))
        joints = np.empty(N)
        for i, ((r0, J, H), bob) in enumerate(zip(self.geo, self.system.bobs, strict=True)):
            sl = slice(self.offsets[i], self.offsets[i + 1])
            A0, A1 = a0[i] - Abar0, a1[i] - Abar1
            carrier = carrier + bob.m * (np.cross(Jq[i], A0) + np.cross(r0, A1))
            joints[sl] = bob.m * (J.T @ A1 + np.einsum("abk,k,b->a", H, A0, q[sl])) + bob.k * q[sl] + bob.c_d * qd[sl]
        return np.concatenate([carrier, joints])

    def zeroth_order(self) -> np.ndarray:
        """Residual of the rest state itself (carrier torque, joint forces): zero for a steady spin."""
        W = self.W
        a0 = [W**2 * np.cross(E3, np.cross(E3, g[0])) for g in self.geo]
        Abar0 = sum(m * a for m, a in zip(self.m, a0, strict=True)) / self.Mtot
        carrier = W**2 * np.cross(E3, self.I @ E3)
        joints = []
        for (r0, J, _), m, a in zip(self.geo, self.m, a0, strict=True):
            carrier = carrier + m * np.cross(r0, a - Abar0)
            joints.append(m * J.T @ (a - Abar0))
        return np.concatenate([carrier, *joints])

    def momentum(self, y: np.ndarray) -> np.ndarray:
        """First-order angular momentum about O (body components) of state y, docs/models.md B.2's H."""
        W, N = self.W, self.N
        dw, q, qd = y[:3], y[3:3 + N], y[3 + N:]
        H = self.I @ dw
        R0 = V0 = R1 = V1 = np.zeros(3)
        for i, ((r0, J, _), m) in enumerate(zip(self.geo, self.m, strict=True)):
            sl = slice(self.offsets[i], self.offsets[i + 1])
            jq = J @ q[sl]
            v0 = W * np.cross(E3, r0)
            v1 = np.cross(dw, r0) + W * np.cross(E3, jq) + J @ qd[sl]
            H = H + m * (np.cross(jq, v0) + np.cross(r0, v1))
            R0, V0, R1, V1 = R0 + m * r0, V0 + m * v0, R1 + m * jq, V1 + m * v1
        return H - (np.cross(R1, V0) + np.cross(R0, V1)) / self.Mtot


def _check_equilibrium(b: _Bobs) -> None:
    res = b.zeroth_order()
    scale = b.W**2 * (np.trace(b.I) + sum(m * (g[0] @ g[0]) for m, g in zip(b.m, b.geo, strict=True)))
    if np.max(np.abs(res)) > EQUILIBRIUM_TOL * max(scale, 1e-300):
        raise ValueError("the bobs at rest are not a steady spin about e3 (centrifugal forces or torques "
                         f"remain: {np.array2string(res, precision=3)}); there is nothing to linearise about")


def linear_matrices(system) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(S, Q, H0): y' = S y with y = (delta omega, q, q') of size 3 + 2N; the first-order angular
    momentum H = H0 + Q y (body components, about O; H0 = (0, 0, C_frozen W))."""
    b = _Bobs(system)
    _check_equilibrium(b)
    n = 3 + 2 * b.N
    nx = 3 + b.N
    M = np.column_stack([b.residual(e, np.zeros(n)) for e in np.eye(nx)])
    F = np.column_stack([b.residual(np.zeros(nx), e) for e in np.eye(n)])
    acc = -np.linalg.solve(M, F)
    S = np.zeros((n, n))
    S[:3] = acc[:3]
    S[3:3 + b.N, 3 + b.N:] = np.eye(b.N)
    S[3 + b.N:] = acc[3:]
    Q = np.column_stack([b.momentum(e) for e in np.eye(n)])
    H0 = np.array([0.0, 0.0, float(np.asarray(system.J)[2]) * b.W])
    return S, Q, H0


def exponents(system) -> np.ndarray:
    """Eigenvalues of S without the one zero exponent of the conserved spin (1/s)."""
    S, _, _ = linear_matrices(system)
    lam = np.linalg.eigvals(S)
    return np.delete(lam, np.argmin(np.abs(lam)))


def slowest_decay_rate(system) -> float:
    """min over modes of -Re s (1/s); negative when a mode grows."""
    return float(-np.max(exponents(system).real))


def block_frequencies(system) -> np.ndarray:
    """Undamped frequencies (rad/s, ascending) of the bobs with the carrier held in steady spin:
    seed 002 (15)'s omega_k with the bobs' weak mutual coupling through the carrier's translation
    included (B.9.9)."""
    b = _Bobs(system)
    nx, n = 3 + b.N, 3 + 2 * b.N
    M = np.column_stack([b.residual(e, np.zeros(n)) for e in np.eye(nx)])[3:, 3:]
    F = np.column_stack([b.residual(np.zeros(nx), e) for e in np.eye(n)])[3:, 3:]
    K, G = F[:, :b.N], F[:, b.N:] - np.diag([c for bob in system.bobs for c in [bob.c_d] * (
        2 if bob.kind == "spherical" else 1)])
    Minv = np.linalg.inv(M)
    S = np.block([[np.zeros((b.N, b.N)), np.eye(b.N)], [-Minv @ K, -Minv @ G]])
    lam = np.linalg.eigvals(S)
    return np.sort(np.abs(lam.imag[lam.imag > 0])) if np.any(lam.imag > 0) else np.sort(np.abs(lam.imag))


def plane_frequency(bob, W: float, M_tot: float) -> float:
    """Seed 002 (15): omega_k of one plane pendulum with the carrier in steady spin W (rad/s),
    omega_k^2 = k/(mu l^2) + W^2 ((e0 . r0_xy)/l - |t_xy|^2), t = n x e0 the swing direction,
    mu = m (M_tot - m)/M_tot. This is docs/models.md B.7's table: in-plane W^2 R/l + k/(mu l^2), meridian
    W^2 (1 +/- R/l) + k/(mu l^2). Exact for a single bob; with several, it leaves out their coupling."""
    r0 = np.asarray(bob.rest, dtype=float)
    t = np.cross(bob.axis, bob.arm)
    mu = bob.m * (M_tot - bob.m) / M_tot
    w2 = bob.k / (mu * bob.l**2) + W**2 * ((np.asarray(bob.arm)[:2] @ r0[:2]) / bob.l - t[:2] @ t[:2])
    return math.sqrt(w2) if w2 >= 0 else -math.sqrt(-w2)  # negative: centrifugally unstable


def linear_nutation(system, w0, t: np.ndarray) -> np.ndarray:
    """Nutation angle (rad), tan theta = |H_perp|/H_z, of the linear system started with transverse
    rate w0 = (omega_x, omega_y) (rad/s) and the bobs at rest; t (n,) increasing, s."""
    return _nutation(*linear_matrices(system), w0, t)


def _nutation(S, Q, H0, w0, t) -> np.ndarray:
    from physics.systems.pendulum.propagate import propagate

    y = np.zeros(S.shape[0])
    y[:2] = w0[:2]
    H = propagate(S, y, t) @ Q.T
    return np.arctan2(np.hypot(H[:, 0], H[:, 1]), H0[2])


def e_folding_time(system, w0=(1e-3, 0.0)) -> float:
    """Time (s) for the linear nutation angle started from w0 (bobs at rest) to fall (or, if a mode
    grows, rise) by a factor e."""
    from physics.systems.pendulum.linear import first_e_crossing

    S, Q, H0 = linear_matrices(system)  # once: building them costs far more than one evaluation
    lam = np.linalg.eigvals(S)
    lam = np.delete(lam, np.argmin(np.abs(lam)))
    return first_e_crossing(lambda t: _nutation(S, Q, H0, w0, t), float(-np.max(lam.real)),
                            float(np.max(np.abs(lam.imag))))


# ---- what ``python -m physics info`` prints for the pendulum systems -------------------------------

def pendulum_derived(sc) -> dict[str, float | str]:
    """Linear-theory quantities of a pendulum scenario: frequencies (6)/(15), omega_0, the tuned and
    resolved k, the slowest decay rate (1/s, negative when the nutation grows) and the time for the
    nutation angle to fall (or grow) by a factor e. Raises
    ScenarioError when the scenario cannot be resolved (a prolate carrier asked to tune "resonant")."""
    from physics.core.errors import ScenarioError
    from physics.scenario.initial import initial_G
    from physics.systems.pendulum import linear as pl
    from physics.systems.pendulum.geometry import pendulum_system, resonant_stiffness

    w0, G0, theta0 = initial_G(sc)
    system = pendulum_system(sc)
    A, B, C = (float(x) for x in np.diag(system.I_c))
    out: dict[str, float | str] = {"W": system.W, "theta0": theta0, "K0": G0, "A_carrier": A, "B_carrier": B,
                                   "C_carrier": C, "M_carrier": system.M0}
    transverse = np.asarray(w0[:2], dtype=float)
    small = 1e-6 * (transverse / np.linalg.norm(transverse) if np.any(transverse) else np.array([1.0, 0.0]))
    if sc.system == "spherical_pendulum":
        p = pl.spherical_linear(system)
        lam1, lam2 = p.lambdas
        mode1 = pl.pendulum_modes(p.omega0, p.W)[0]
        out.update(mu=p.mu, D=p.D, coupling_muD2_over_A=p.coupling, omega_0=p.omega0, lambda_1=lam1, lambda_2=lam2,
                   mode_1=mode1.sense, ct=p.ct)
        try:
            out["Omega"] = p.Omega
        except ValueError as exc:
            out["Omega"] = str(exc)
        tuning = sc.pendulum.k
        if isinstance(tuning, str):
            out["k_tuning"] = tuning
        out["k"] = p.k
        out["c_d"] = p.c_d
        try:
            out["k_resonant"] = resonant_stiffness(system, system.bobs[0])
        except ScenarioError as exc:
            out["k_resonant"] = "none: " + exc.allowed.split(":")[0]
        if p.B is None:
            roots = pl.classify_roots(p)
            for name in pl.ROOT_NAMES:
                out["s_" + name.replace(" ", "_")] = f"{roots[name].real:.10g} {roots[name].imag:+.10g}i"
        rate = pl.slowest_decay_rate(p)
        tau = pl.e_folding_time(p, tuple(small))
    else:
        for i, bob in enumerate(system.bobs, start=1):
            out[f"omega_{i}"] = plane_frequency(bob, system.W, system.M)
        out["Omega"] = pl.nutation_frequency(0.5 * (A + B), C, system.W) if abs(A - B) <= 1e-9 * A else (
            pl.free_precession_frequency(A, B, C, system.W))
        rate = slowest_decay_rate(system)
        tau = e_folding_time(system, small)
    out["decay_rate_linear"] = rate
    out["nutation"] = "decays" if rate > 0 else ("grows" if rate < 0 else "neutral")
    out["tau_e_linear"] = tau
    return out
