"""Linear theory of the viscous wheel damper about steady spin about e3, and the closed-form model built on it
(docs/models.md C.3).

About the steady spin w = n e3, Omega_w = 0 (an equilibrium for any a: the bearing is idle), the perturbation
(x, y, z) of w and the wheel's rate Omega_w obey, to first order, Mm (x, y, z, Omega_w)' = F (x, y, z, Omega_w):

    Mm = [[A, 0, 0, J a1], [0, B, 0, J a2], [0, 0, C, J a3], [J a1, J a2, J a3, J]],
    F rows: (0, n (B - C), 0, n J a2), (n (C - A), 0, 0, -n J a1), 0, (0, 0, 0, -c).

z enters no right side: (x, y, Omega_w) is closed (``block``), z and the wheel's angle phi_w are its quadratures.
For an axisymmetric body (A = B) with a transverse axis (a = e1) the characteristic equation is the cubic

    J A (A - J) s^3 + c A^2 s^2 + J n^2 (C - A)(C - A + J) s + c n^2 (C - A)^2 = 0     (``cubic``)

(Routh-Hurwitz, a2 a1 - a3 a0 = c J^2 n^2 C (C - A): for c > 0 all roots have Re s < 0 iff C > A; for c = 0 the
nutation frequency is n sqrt((C - A)(C - A + J) / (A (A - J)))).
"""

from __future__ import annotations

import math

import numpy as np

from physics.core.errors import ScenarioError
from physics.core.rotation import IDENTITY, normalize, nutation_angle, qmul
from physics.core.trajectory import Trajectory
from physics.registry import Model, register
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario
from physics.systems.wheel.restart import restart_closed

BLOCK = (0, 1, 3)  # x, y, Omega_w: the closed part of (x, y, z, Omega_w)
QUAT_STEP = 0.05  # rad of rotation per Magnus step of the attitude (exact for constant w: the wobble sets it)
MAX_SUBSTEPS = 2_000_000  # attitude steps per solve: a few arrays of this many rows
COND_MAX = 1e8  # eigenvector matrix condition above which the modes are near-defective: e^{Lt} by expm instead


def matrix(A, B, C, J, c, a, n) -> np.ndarray:
    """L (4, 4): d/dt (x, y, z, Omega_w) = L (x, y, z, Omega_w), linearized about w = n e3, Omega_w = 0."""
    a1, a2, a3 = a
    Mm = np.array([[A, 0.0, 0.0, J * a1], [0.0, B, 0.0, J * a2], [0.0, 0.0, C, J * a3], [J * a1, J * a2, J * a3, J]])
    F = np.zeros((4, 4))
    F[0, 1], F[0, 3] = n * (B - C), n * J * a2
    F[1, 0], F[1, 3] = n * (C - A), -n * J * a1
    F[3, 3] = -c
    return np.linalg.solve(Mm, F)


def cubic(A, C, J, c, n) -> np.ndarray:
    """Coefficients (s^3 .. s^0) of the characteristic equation for A = B, a = e1 (module docstring)."""
    return np.array([J * A * (A - J), c * A * A, J * n * n * (C - A) * (C - A + J), c * n * n * (C - A) ** 2])


def scenario_matrix(sc: Scenario) -> tuple[np.ndarray, float]:
    """(L, n) for the scenario: n = the initial spin about e3."""
    w0, _, _ = initial_G(sc)
    b, w = sc.body, sc.wheel
    n = float(w0[2])
    return matrix(b.A, b.B, b.C, w.J, w.c, w.axis, n), n


def exponents(sc: Scenario) -> np.ndarray:
    """The eigenvalues of the closed (x, y, Omega_w) block, 1/s."""
    L, _ = scenario_matrix(sc)
    return np.linalg.eigvals(L[np.ix_(BLOCK, BLOCK)])


def nutation_mode(sc: Scenario) -> complex | None:
    """The nutation exponent -decay + i frequency (Im > 0) of the linear theory, or None when no mode
    oscillates (the spin is not a centre or a stable focus of the linear system)."""
    s = exponents(sc)
    osc = s[s.imag > 1e-12 * max(1.0, float(np.max(np.abs(s))))]
    return complex(osc[np.argmax(osc.imag)]) if len(osc) else None


def _phi_integral(lam: np.ndarray, t: np.ndarray) -> np.ndarray:
    """(e^{lam t} - 1)/lam (n, m), exact also as lam t -> 0."""
    x = lam[None, :] * t[:, None]
    small = np.abs(x) < 1e-4
    safe = np.where(small, 1.0, lam[None, :])
    series = t[:, None] * (1 + x / 2 + x * x / 6 + x ** 3 / 24)
    return np.where(small, series, np.expm1(x) / safe)


def perturbation(L: np.ndarray, u0: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(x, y, z, Omega_w) (n, 4) and phi_w (n,) at times t from (x, y, z, Omega_w)(0) = u0 and phi_w(0) = 0."""
    t = np.asarray(t, dtype=float)
    Lb = L[np.ix_(BLOCK, BLOCK)]
    lam, V = np.linalg.eig(Lb)
    out = np.empty((len(t), 4))
    if np.linalg.cond(V) < COND_MAX:
        coef = np.linalg.solve(V, u0[list(BLOCK)].astype(complex))
        with np.errstate(over="ignore", invalid="ignore"):
            u = np.real((np.exp(np.outer(t, lam)) * coef) @ V.T)
            I = np.real((_phi_integral(lam, t) * coef) @ V.T)  # int_0^t (x, y, Omega_w)
        out[:, [0, 1, 3]] = u
        out[:, 2] = u0[2] + I @ L[2, list(BLOCK)]
        return out, I[:, 2]
    from scipy.linalg import expm  # near-defective modes (a double root): the matrix exponential itself

    aug = np.zeros((5, 5))
    aug[:4, :4] = L
    aug[4, 3] = 1.0  # phi_w' = Omega_w
    y0 = np.append(u0, 0.0)
    Y = np.array([expm(aug * ti) @ y0 for ti in t])
    return Y[:, :4], Y[:, 4]


def _attitude(L: np.ndarray, u0: np.ndarray, n: float, t: np.ndarray) -> np.ndarray:
    """q' = q (x) (0, w)/2 with the linear w(t), by the fourth-order Magnus method on Gauss points; identity at 0."""
    omega_max = abs(n) + float(np.linalg.norm(u0)) * 10.0 + 1e-300
    dt = np.diff(t, prepend=0.0)
    n_float = np.maximum(np.ceil(dt * omega_max / QUAT_STEP), 1.0)
    if not float(np.sum(n_float)) <= MAX_SUBSTEPS:
        raise ScenarioError("run.t_end", float(t[-1]), f"needs {float(np.sum(n_float)):.3g} attitude steps of "
                            f"{QUAT_STEP} rad in the linear model, more than its budget of {MAX_SUBSTEPS}: shorten "
                            "t_end")
    n_sub = n_float.astype(np.int64)
    n_sub[dt == 0] = 0
    h = np.repeat(np.where(n_sub > 0, dt / np.maximum(n_sub, 1), 0.0), n_sub)
    k = np.arange(len(h)) - np.repeat(np.cumsum(n_sub) - n_sub, n_sub)
    t0 = np.repeat(t - dt, n_sub) + k * h
    g = math.sqrt(3.0) / 6.0
    ws = []
    for tg in (t0 + (0.5 - g) * h, t0 + (0.5 + g) * h):
        d, _ = perturbation(L, u0, tg)
        ws.append(np.column_stack([d[:, 0], d[:, 1], n + d[:, 2]]))
    v = h[:, None] / 4 * (ws[0] + ws[1]) - (math.sqrt(3.0) / 24) * h[:, None] ** 2 * np.cross(ws[1], ws[0])
    ang = np.linalg.norm(v, axis=1)
    sinc = np.where(ang > 0, np.sin(ang) / np.where(ang > 0, ang, 1.0), 1.0)
    q = np.column_stack([np.cos(ang), v * sinc[:, None]])
    step = 1  # prefix product q0 (x) q1 (x) ... by doubling (Hillis-Steele): log2(steps) vector passes
    while step < len(q):
        q[step:] = qmul(q[:-step], q[step:])
        step *= 2
    ends = np.cumsum(n_sub) - 1
    out = np.tile(IDENTITY, (len(t), 1))
    have = n_sub.cumsum() > 0
    out[have] = q[ends[have]]
    return normalize(out)


def solve_linear(sc: Scenario, t: np.ndarray, Omega_w0: float = 0.0) -> Trajectory:
    """The linear theory's trajectory at times t (s): w = n e3 + (x, y, z), the wheel's rate and angle from the
    modes of ``matrix``, the attitude by Magnus steps; K and E from the exact formulas at that state. The wheel
    starts at rest relative to the body, or at the rate ``Omega_w0`` (rad/s) where a run is restarted
    (restart.py)."""
    t = np.asarray(t, dtype=float)
    L, n = scenario_matrix(sc)
    w0, _, _ = initial_G(sc)
    u0 = np.array([w0[0], w0[1], 0.0, Omega_w0])
    d, phi = perturbation(L, u0, t)
    b, wh = sc.body, sc.wheel
    I = np.array([b.A, b.B, b.C])
    a = np.array(wh.axis)
    omega = np.column_stack([d[:, 0], d[:, 1], n + d[:, 2]])
    Om = d[:, 3]
    K = omega * I + wh.J * Om[:, None] * a
    E = 0.5 * np.sum(I * omega * omega, axis=1) + wh.J * Om * (omega @ a + 0.5 * Om)
    info = {"method": "closed form (linear modes about steady spin); attitude by 4th-order Magnus", "nfev": 0,
            "steps": 0, "stop_reason": "reached t_end", "t_stop": float(t[-1])}
    internal = {"phi_w": phi, "Omega_w": Om, "W_diss": E[0] - E}  # the energy the linear state has lost
    return Trajectory(t=t, theta=nutation_angle(K), K=np.linalg.norm(K, axis=1), E=E, omega=omega,
                      quat=_attitude(L, u0, n, t), internal=internal, info=info)


def initial_momentum(sc: Scenario, G: float) -> np.ndarray:
    """The inertial K (3,) at t = 0 when |K| = G: I w0 (the wheel at rest), the body frame being the inertial one."""
    w0, _, _ = initial_G(sc)
    Iw = np.array([sc.body.A, sc.body.B, sc.body.C]) * w0
    return G * Iw / np.linalg.norm(Iw)


CLOSED = register(Model(
    name="wheel/closed", system="wheel", fidelity="closed",
    summary="linear theory about steady spin about e3: the modes of the linearized equations, in closed form "
            "(docs/models.md C.3)",
    solve=solve_linear, columns=("phi_w", "Omega_w", "W_diss"),
    proxy="full",  # its rows (w, the wheel's angle and rate, the attitude) read as the full model's state
    initial_momentum=initial_momentum,
    restart=restart_closed,  # K, the attitude and the wheel's rate kept (restart.py)
))
