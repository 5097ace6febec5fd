"""The spherical-pendulum damper at the averaged fidelity: docs/models.md Part B section 6.

Resonant first-order averaging that keeps the slow phase chi = Psi_1 - Theta (the paper's (12)-(13)
average it away and predict no damping at all, B.9.5). In complex Cartesian variables relative to
the free nutation e^{i Omega t}:

    Phihat' = kappa1 Ut,        Ut' = (i sigma - gamma1) Ut - kappa2 Phihat,

    kappa1 = (mu D l/A)(omega_0^2 + i ct lambda_1),  kappa2 = D C W/(2 l omega_0 A),
    gamma_j = ct lambda_j/(2 omega_0),  sigma = lambda_1 - Omega,

with w = omega_x + i omega_y = Phihat e^{i Omega t} and the pendulum's mode 1
z = alpha + i beta = Ut e^{i Omega t}. Mode 2 decays on its own (a_2' = -gamma_2 a_2) and is never
excited from rest, so a_2 = 0 here. The system is linear and solved exactly by the 2x2 matrix
exponential; the attitude is the only thing integrated (its kinematics, with the closed-form omega).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from physics.core.errors import ScenarioError
from physics.core.trajectory import Trajectory
from physics.registry import Model, register
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.pendulum.linear import SphericalLinear, spherical_linear
from physics.systems.pendulum.restart import carry_to_pendulum_averaged

# Where the model may run and its error estimate: validity.py and accuracy.py (issue 15).
QUAT_STEP = 0.05  # rad of rotation per Magnus step of the attitude: error ~1e-10 over 100 turns
MAX_SUBSTEPS = 2e6  # Magnus steps per run (about 400 MB of work arrays), as simulate bounds its own steps


class AveragedCoefficients:
    """kappa1, kappa2, gamma1, gamma2, sigma, Omega, lambda1 of B.6 for linear parameters p."""

    def __init__(self, p: SphericalLinear):
        A = 0.5 * (p.A + p.Bm)
        w0 = p.omega0
        self.p = p
        self.A = A
        self.Omega = (p.C - A) * p.W / A
        self.lambda1 = w0 - p.W  # signed: mode 1 co-rotates only when omega_0 > W
        self.lambda2 = w0 + p.W
        self.sigma = self.lambda1 - self.Omega
        self.gamma1 = p.ct * self.lambda1 / (2 * w0)
        self.gamma2 = p.ct * self.lambda2 / (2 * w0)
        self.kappa1 = p.mu * p.D * p.l / A * (w0**2 + 1j * p.ct * self.lambda1)
        self.kappa2 = p.D * p.C * p.W / (2 * p.l * w0 * A)

    @property
    def matrix(self) -> np.ndarray:
        """d/dt (Phihat, Ut) = matrix @ (Phihat, Ut)."""
        return np.array([[0.0, self.kappa1], [-self.kappa2, 1j * self.sigma - self.gamma1]])

    def exponents(self) -> np.ndarray:
        """Roots of s^2 - (i sigma - gamma1) s + kappa1 kappa2 = 0 (1/s, relative to e^{i Omega t})."""
        return np.roots([1.0, -(1j * self.sigma - self.gamma1), self.kappa1 * self.kappa2])

    def slowest_rate(self) -> float:
        """The averaged theory's slowest nutation decay rate, 1/s (mode 2 decays at gamma2 apart)."""
        return float(min(-self.exponents().real))

    def propagator(self, t: np.ndarray) -> np.ndarray:
        """e^{M t} for t (n,), shape (n, 2, 2), in closed form (stays exact at the double root):
        e^{Mt} = e^{tau t/2} [cosh(q t) I + sinh(q t)/q (M - tau/2 I)], q^2 = tau^2/4 - det M.
        e^{tau t/2} cosh(q t) is formed as (e^{(tau/2 + q) t} + e^{(tau/2 - q) t})/2, never as the product:
        with strong damping (Re q ~ -Re tau/2) the factors under- and overflow at long t (0 * inf = NaN) while
        the product is the slow mode's finite e^{(tau/2 + q) t}."""
        M = self.matrix
        tau = np.trace(M)
        q = np.sqrt(tau**2 / 4 - np.linalg.det(M) + 0j)
        if q.real < 0:
            q = -q  # the same e^{Mt}; Re q >= 0 keeps e^{(tau/2 - q) t} the decaying one
        t = np.asarray(t, dtype=float)
        x = q * t
        small = np.abs(x) < 1e-3
        with np.errstate(over="ignore", under="ignore", invalid="ignore"):  # a growing mode: inf, as it should
            up, down = np.exp((tau / 2 + q) * t), np.exp((tau / 2 - q) * t)
            e = np.exp(tau * t / 2)
            ch = np.where(small, e * (1 + x**2 / 2 + x**4 / 24), (up + down) / 2)
            sh = np.where(small, e * t * (1 + x**2 / 6 + x**4 / 120), (up - down) / (2 * np.where(small, 1.0, q)))
            N = M - tau / 2 * np.eye(2)
            return ch[:, None, None] * np.eye(2)[None] + sh[:, None, None] * N[None]


def _dissipated(co: AveragedCoefficients, u0: np.ndarray, U: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Work c_d int_0^t (alpha'^2 + beta'^2) = c_d lambda_1^2 int_0^t |Ut|^2 dt (J), exactly: with
    M^H X + X M = -e2 e2^H, d/dt (u^H X u) = -|Ut|^2."""
    p = co.p
    if p.c_d == 0 or not np.any(u0):
        return np.zeros(len(t))
    P = np.diag([0.0, 1.0]).astype(complex)
    try:
        from scipy.linalg import solve_continuous_lyapunov  # here: scipy.linalg adds 0.2 s to the app's start

        X = solve_continuous_lyapunov(co.matrix.conj().T, -P)
    except (np.linalg.LinAlgError, ValueError):
        X = None
    if X is None or not np.all(np.isfinite(X)):
        from scipy.integrate import cumulative_trapezoid

        return p.c_d * co.lambda1**2 * cumulative_trapezoid(np.abs(U[:, 1]) ** 2, t, initial=0.0)
    quad = np.real(np.einsum("ni,ij,nj->n", U.conj(), X, U))
    work = p.c_d * co.lambda1**2 * (np.real(u0.conj() @ X @ u0) - quad)
    # the integral from 0 to 0 is zero: set so, not left to the difference of two evaluations of the quadratic form
    # (einsum and @ round differently, by machine), so a restart's carried work goes on bit for bit
    work[np.asarray(t) == 0.0] = 0.0
    return work


@njit(cache=True)
def _chain(steps: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """Products q_0 (x) steps[0] (x) steps[1] ..., q_0 = identity, kept after step ends[i] - 1."""
    out = np.empty((len(ends), 4))
    q0, q1, q2, q3 = 1.0, 0.0, 0.0, 0.0
    j = 0
    for i in range(len(ends)):
        while j < ends[i]:
            a0, a1, a2, a3 = steps[j]
            q0, q1, q2, q3 = (q0 * a0 - q1 * a1 - q2 * a2 - q3 * a3, q0 * a1 + q1 * a0 + q2 * a3 - q3 * a2,
                              q0 * a2 - q1 * a3 + q2 * a0 + q3 * a1, q0 * a3 + q1 * a2 - q2 * a1 + q3 * a0)
            j += 1
        n = math.sqrt(q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
        out[i, 0], out[i, 1], out[i, 2], out[i, 3] = q0 / n, q1 / n, q2 / n, q3 / n
    return out


def _attitude(co: AveragedCoefficients, u0: np.ndarray, W: float, t: np.ndarray) -> np.ndarray:
    """Integrate q' = q (x) (0, omega)/2 with the closed-form omega(t) by the fourth-order Magnus
    method on Gauss points (exact for a constant omega, so only the slow wobble limits the step);
    identity at t = 0, t (n,) increasing from 0."""
    Phi = np.abs(np.einsum("nij,j->ni", co.propagator(np.array([0.0])), u0))[0, 0]
    rate = math.hypot(W, Phi) + abs(co.Omega) + abs(co.sigma) + 1e-300
    dt = np.diff(t, prepend=0.0)
    n_float = np.maximum(np.ceil(dt * rate / QUAT_STEP), 1)
    if not float(np.sum(n_float)) <= MAX_SUBSTEPS:  # each sub-step holds a few arrays' rows: bound the memory
        raise ScenarioError("run.t_end", float(t[-1]), f"needs {float(np.sum(n_float)):.3g} attitude steps of "
                            f"{QUAT_STEP} rad in the averaged model, more than its budget of {MAX_SUBSTEPS:.0f}: "
                            "shorten t_end")
    n_sub = n_float.astype(np.int64)
    n_sub[dt == 0] = 0
    starts = np.repeat(t - dt, n_sub)
    h = np.repeat(np.where(n_sub > 0, dt / np.maximum(n_sub, 1), 0.0), n_sub)
    k = np.arange(len(h)) - np.repeat(np.cumsum(n_sub) - n_sub, n_sub)
    t0 = starts + k * h
    g = math.sqrt(3) / 6
    ws = []
    for tg in (t0 + (0.5 - g) * h, t0 + (0.5 + g) * h):
        w = np.einsum("nij,j->ni", co.propagator(tg), u0)[:, 0] * np.exp(1j * co.Omega * tg)
        ws.append(np.column_stack([w.real, w.imag, np.full(len(tg), W)]))
    v = h[:, None] / 4 * (ws[0] + ws[1]) - (math.sqrt(3) / 24) * h[:, None] ** 2 * np.cross(ws[1], ws[0])
    a = np.linalg.norm(v, axis=1)
    sinc = np.where(a > 0, np.sin(a) / np.where(a > 0, a, 1.0), 1.0)
    steps = np.column_stack([np.cos(a), v * sinc[:, None]])
    return _chain(np.ascontiguousarray(steps), np.cumsum(n_sub))


def averaged_theta(co: AveragedCoefficients, u0: np.ndarray, W: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(theta (n,), U (n, 2) = (Phihat, Ut)) at times t from u0 = (Phihat(0), Ut(0)): tan theta =
    |(A + mu D^2) Phihat + i mu D l omega_0 Ut|/(C W) (B.6). No attitude: what the error estimate samples."""
    p = co.p
    U = np.einsum("nij,j->ni", co.propagator(t), u0)
    Hp = (co.A + p.mu * p.D**2) * U[:, 0] + 1j * p.mu * p.D * p.l * p.omega0 * U[:, 1]
    return np.arctan2(np.abs(Hp), p.C * W), U


def solve_averaged(sc: Scenario, t: np.ndarray) -> Trajectory:
    """The averaged trajectory at times t (s): theta from tan phi = |(A + mu D^2) Phihat +
    i mu D l omega_0 Ut|/(C W) (B.6), K = |H(0)| (conserved), E = E(0) minus the dissipated work."""
    t = np.asarray(t, dtype=float)
    system = pendulum_system(sc)
    p = spherical_linear(system)
    if not p.omega0 > 0:
        raise ScenarioError("pendulum.k", sc.pendulum.k, "must be > 0 for the averaged fidelity: it averages about "
                            "the spring's frequency omega_0, which k = 0 does not have; use the full fidelity")
    co = AveragedCoefficients(p)
    w0, G0, _ = initial_G(sc)
    W = float(w0[2])
    u0 = np.array([w0[0] + 1j * w0[1], 0.0 + 0j])  # the pendulum starts at rest: Ut(0) = 0, a_2 = 0
    theta, U = averaged_theta(co, u0, W, t)
    rot = np.exp(1j * co.Omega * t)
    w, z = U[:, 0] * rot, U[:, 1] * rot
    zd = 1j * co.lambda1 * z
    work = _dissipated(co, u0, U, t)
    E0 = 0.5 * float(w0 @ (np.asarray(system.J) * w0))
    omega = np.column_stack([w.real, w.imag, np.full(len(t), W)])
    internal = {"alpha": z.real, "beta": z.imag, "alpha_dot": zd.real, "beta_dot": zd.imag, "W_diss": work}
    info = {"method": "closed form (2x2 matrix exponential); attitude by 4th-order Magnus", "nfev": 0, "steps": 0,
            "stop_reason": "reached t_end", "t_stop": float(t[-1])}
    return Trajectory(t=t, theta=theta, K=np.full(len(t), G0), E=E0 - work, omega=omega,
                      quat=_attitude(co, u0, W, t), internal=internal, info=info)


def initial_momentum(sc: Scenario, G: float) -> np.ndarray:
    """The inertial K (3,) at t = 0 when |K| = G: it starts as J w0 in the body (the bob at rest), which at
    t = 0 is the inertial frame."""
    w0, _, _ = initial_G(sc)
    body = sc.body
    Jw = np.array([body.A, body.B, body.C]) * w0
    return G * Jw / np.linalg.norm(Jw)


AVERAGED = register(Model(
    name="spherical_pendulum/averaged", system="spherical_pendulum", fidelity="averaged",
    summary="resonant first-order averaging keeping the slow phase (docs/models.md B.6), solved exactly",
    solve=solve_averaged,
    columns=("alpha", "beta", "alpha_dot", "beta_dot", "W_diss"),
    proxy="full",  # its rows (omega, attitude, the bob's angles and rates) read as the full model's state
    restart=carry_to_pendulum_averaged,  # with the bob put at rest
    initial_momentum=initial_momentum,
))
