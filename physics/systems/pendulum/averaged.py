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
exponential; the attitude follows from K, whose inertial direction is fixed: the body-frame direction of H and
the precession phase psi, a quadrature of a slowly varying rate (``_attitude``).
"""

from __future__ import annotations

import math

import numpy as np

from physics.core.errors import ScenarioError
from physics.core.rotation import qconj, qmul
from physics.core.trajectory import Trajectory
from physics.registry import Model, register
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.pendulum.linear import SphericalLinear, spherical_linear
from physics.systems.pendulum.restart import carry_to_pendulum_averaged

# Where the model may run and its error estimate: validity.py and accuracy.py (issue 15).
QUAT_STEP = 0.05  # rad of the slow exponents' phase per quadrature step of the precession phase psi
DETUNED = 10.0  # slow rate / Omega beyond which a step-budget refusal names the pendulum's keys as the cause
MAX_SUBSTEPS = 2e6  # quadrature steps per run (about 400 MB of work arrays), as simulate bounds its own steps


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
    X = None
    try:
        ev = co.exponents()  # the matrix's eigenvalues
        # the Lyapunov equation has no unique solution when two eigenvalues' sum vanishes (an undamped mode: the
        # carrier's at G0 = 1e-300); scipy then perturbs M and warns, so such a M takes the quadrature below
        if np.abs(ev[:, None].conj() + ev[None, :]).min() > 1e-12 * np.abs(ev).max():
            from scipy.linalg import solve_continuous_lyapunov  # here: scipy.linalg adds 0.2 s to the app's start

            X = solve_continuous_lyapunov(co.matrix.conj().T, -P)
    except (np.linalg.LinAlgError, ValueError):
        pass
    if X is None or not np.all(np.isfinite(X)):
        from scipy.integrate import cumulative_trapezoid

        return p.c_d * co.lambda1**2 * cumulative_trapezoid(np.abs(U[:, 1]) ** 2, t, initial=0.0)
    quad = np.real(np.einsum("ni,ij,nj->n", U.conj(), X, U))
    work = p.c_d * co.lambda1**2 * (np.real(u0.conj() @ X @ u0) - quad)
    # the integral from 0 to 0 is zero: set so, not left to the difference of two evaluations of the quadratic form
    # (einsum and @ round differently, by machine), so a restart's carried work goes on bit for bit
    work[np.asarray(t) == 0.0] = 0.0
    return work


def _momentum_parts(co: AveragedCoefficients, U: np.ndarray) -> tuple[np.ndarray, float]:
    """(h (n,), H3): the body-frame momentum of the averaged solution relative to the free nutation,
    H1 + i H2 = h e^{i Omega t}, h = (A + mu D^2) Phihat + i mu D l omega_0 Ut, and H3 = C W (B.6)."""
    p = co.p
    return (co.A + p.mu * p.D**2) * U[:, 0] + 1j * p.mu * p.D * p.l * p.omega0 * U[:, 1], p.C * p.W


def _precession_rate(co: AveragedCoefficients, u0: np.ndarray, s: np.ndarray) -> np.ndarray:
    """psi' (rad/s) at times s: the rate of the precession phase about K's fixed direction (docs/models.md B.6,
    the attitude), psi' = w.k + cos(theta) d arg(H1 + i H2)/dt with k = H/|H|; every term varies slowly (the
    free nutation's e^{i Omega t} enters arg only as the constant rate Omega)."""
    U = np.einsum("nij,j->ni", co.propagator(s), u0)
    dU = U @ co.matrix.T  # U' = M U
    h, H3 = _momentum_parts(co, U)
    dh, _ = _momentum_parts(co, dU)
    h2 = np.abs(h) ** 2
    Hn = np.sqrt(h2 + H3 * H3)
    w_along = (np.real(np.conj(U[:, 0]) * h) + co.p.W * H3) / Hn
    with np.errstate(invalid="ignore", divide="ignore"):
        turn = co.Omega + np.imag(np.conj(h) * dh) / h2
    # on the axis (h = 0: no nutation at all) phi stays 0 and the body turns about K at w3 |H|/H3
    return np.where(h2 > 0, w_along + H3 / Hn * turn, co.p.W * Hn / H3)


def _attitude(co: AveragedCoefficients, u0: np.ndarray, W: float, t: np.ndarray, U: np.ndarray,
              spring: str = "") -> np.ndarray:
    """The attitude at times t (n,) increasing from 0 (the identity at t = 0), from K, which does not turn:
    Q_K Rz(psi) Rx(theta) Rz(phi), with (theta, phi) the body-frame direction of H (``U`` the solution at t) and
    psi the quadrature of ``_precession_rate`` by two-point Gauss-Legendre on sub-steps of QUAT_STEP rad of the
    slow exponents. R H is then fixed in space to rounding, which the attitude integrated with the averaged
    omega (until issue 23) was not: the averaged torques turn H in the body, and omega does not turn the body
    back. ``spring`` names the spring's keys and values, for a refusal whose cause is the detuning."""
    rate = float(np.max(np.abs(co.exponents()))) + abs(co.sigma) + 1e-300
    dt = np.diff(t, prepend=0.0)
    n_float = np.maximum(np.ceil(dt * rate / QUAT_STEP), 1)
    if not float(np.sum(n_float)) <= MAX_SUBSTEPS:  # each sub-step holds a few arrays' rows: bound the memory
        raise ScenarioError("run.t_end", float(t[-1]), f"needs {float(np.sum(n_float)):.3g} attitude steps of "
                            f"{QUAT_STEP} rad in the averaged model, more than its budget of {MAX_SUBSTEPS:.0f}"
                            + _detuning_cause(co, spring, rate))
    n_sub = n_float.astype(np.int64)
    n_sub[dt == 0] = 0
    starts = np.repeat(t - dt, n_sub)
    h = np.repeat(np.where(n_sub > 0, dt / np.maximum(n_sub, 1), 0.0), n_sub)
    k = np.arange(len(h)) - np.repeat(np.cumsum(n_sub) - n_sub, n_sub)
    t0 = starts + k * h
    g = math.sqrt(3) / 6
    steps = 0.5 * h * (_precession_rate(co, u0, t0 + (0.5 - g) * h) + _precession_rate(co, u0, t0 + (0.5 + g) * h))
    psi = np.concatenate([[0.0], np.cumsum(steps)])[np.cumsum(n_sub)]
    hp, H3 = _momentum_parts(co, U)
    Hp = hp * np.exp(1j * co.Omega * t)  # the same e^{i Omega t} as omega's, so phi and omega agree to rounding
    # phi unwrapped: a jump of 2 pi would flip the quaternion's sign between rows (the same rotation, but not the
    # continuous attitude a chart or a comparison expects)
    theta, phi = np.arctan2(np.abs(Hp), H3), np.unwrap(np.arctan2(Hp.real, Hp.imag))
    tilt = _tilt(psi, theta, phi)
    q = qmul(qconj(_initial_tilt(co, u0)), tilt)  # the identity at t = 0
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _detuning_cause(co: AveragedCoefficients, spring: str, rate: float) -> str:
    """Why the slow phase turns fast, when it turns more than DETUNED x Omega: then the pendulum's own keys (a spring
    far off resonance, a damper far too strong, a bob too light) set the step count as much as t_end does, and the
    refusal names them."""
    if not spring or not rate > DETUNED * abs(co.Omega):
        return ": shorten t_end"
    return (f"; the pendulum's slow rates reach {rate:.3g} rad/s against the nutation's Omega = {co.Omega:.3g} rad/s "
            f"({spring}; omega_0 = {co.p.omega0:.3g} rad/s, detuning {abs(co.sigma):.3g} rad/s): bring the pendulum "
            "nearer resonance with a moderate damper, or shorten t_end")


def _tilt(psi: np.ndarray, theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """Rz(psi) (x) Rx(theta) (x) Rz(phi) as quaternions (n, 4)."""
    cp, sp, ct, st = np.cos(psi / 2), np.sin(psi / 2), np.cos(theta / 2), np.sin(theta / 2)
    cf, sf = np.cos(phi / 2), np.sin(phi / 2)
    a = np.stack([cp * ct, cp * st, sp * st, sp * ct], -1)  # Rz(psi) (x) Rx(theta)
    return qmul(a, np.stack([cf, 0 * cf, 0 * cf, sf], -1))


def _initial_tilt(co: AveragedCoefficients, u0: np.ndarray) -> np.ndarray:
    hp, H3 = _momentum_parts(co, u0[None, :])
    return _tilt(np.array([0.0]), np.arctan2(np.abs(hp), H3), np.arctan2(hp.real, hp.imag))


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
    info = {"method": "closed form (2x2 matrix exponential); attitude from K's fixed direction and the precession "
                      "phase by quadrature", "nfev": 0, "steps": 0,
            "stop_reason": "reached t_end", "t_stop": float(t[-1])}
    return Trajectory(t=t, theta=theta, K=np.full(len(t), G0), E=E0 - work, omega=omega,
                      quat=_attitude(co, u0, W, t, U, _spring_words(sc)), internal=internal, info=info)


def _spring_words(sc: Scenario) -> str:
    k = sc.pendulum.k
    k_words = f'"{k}"' if isinstance(k, str) else f"{k:.6g} N m/rad"  # a tuning's name, or the stiffness
    p = sc.pendulum
    return f"pendulum.k = {k_words}, pendulum.m = {p.m:.6g} kg, pendulum.c_d = {p.c_d:.6g} N m s/rad"


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
