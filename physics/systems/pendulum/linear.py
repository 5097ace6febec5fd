"""Linear theory of the spherical-pendulum nutation damper (seed 002, docs/models.md Part B sections 3-5, 9).

Pure functions on plain floats. The carrier's own moments ``A, B, C`` about its own COM, the spin
rate ``W`` (rad/s), the bob's reduced mass ``mu`` (kg), arm ``l`` (m), the rest distance ``D`` (m)
of the bob from the carrier COM, spring ``k`` (N m/rad) and pivot damping ``c_d`` (N m s/rad) are
gathered in ``SphericalLinear``. Exponents ``s`` are body-frame: a mode goes as ``e^{s t}``, and
``Im s > 0`` turns with the spin. Corrections of docs/models.md B.9 are named where they are used.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from physics.systems.pendulum.frequencies import (  # noqa: F401  (re-exported: the linear theory in one namespace)
    PendulumMode,
    distribution_coefficients,
    free_precession_frequency,
    frequencies_eq6,
    natural_frequency,
    nutation_frequency,
    pendulum_frequencies,
    pendulum_modes,
    precession_amplitude_ratio,
    precession_amplitude_ratio_printed,
    precession_coefficients,
    reduced_mass,
    resonant_omega0,
)

ROOT_NAMES = ("nutation", "pendulum 1", "pendulum 2")


@dataclass(frozen=True)
class SphericalLinear:
    """The parameters of docs/models.md B.3 (carrier-only moments A, B, C in kg m^2; SI units)."""

    A: float
    C: float
    W: float
    mu: float
    l: float
    D: float
    k: float
    c_d: float
    B: float | None = None  # None: symmetric carrier, B = A

    @property
    def Bm(self) -> float:
        return self.A if self.B is None else self.B

    @property
    def omega0(self) -> float:
        """Spring frequency omega_0 = sqrt(k/(mu l^2)), rad/s (B.9.1: the paper writes m for mu)."""
        return natural_frequency(self.k, self.mu, self.l)

    @property
    def omega_n2(self) -> float:
        """Reduced frequency squared omega_n^2 = omega_0^2 - W^2 of seed 002 (1), rad^2/s^2."""
        return self.omega0**2 - self.W**2

    @property
    def ct(self) -> float:
        """Damping rate ct = c_d/(mu l^2), 1/s."""
        return self.c_d / (self.mu * self.l**2)

    @property
    def Omega(self) -> float:
        """Free-nutation frequency in the body frame, seed 002 (4) / rho of (10) when A != B, rad/s (signed)."""
        if self.B is None:
            return nutation_frequency(self.A, self.C, self.W)
        return free_precession_frequency(self.A, self.B, self.C, self.W)

    @property
    def lambdas(self) -> tuple[float, float]:
        return pendulum_frequencies(self.omega0, self.W)

    @property
    def coupling(self) -> float:
        """mu D^2 / A, the small parameter of the coupling (B.10)."""
        return self.mu * self.D**2 / self.A

    @property
    def A_frozen(self) -> float:
        """Frozen-system equatorial moment A + mu D^2 (B.8)."""
        return self.A + self.mu * self.D**2


def spherical_linear(system) -> SphericalLinear:
    """The linear parameters of a ``PendulumSystem`` with one spherical bob (k resolved)."""
    bob = system.bobs[0]
    if bob.kind != "spherical" or len(system.bobs) != 1:
        raise ValueError("spherical_linear needs one spherical pendulum")
    A, B, C = (float(x) for x in np.diag(system.I_c))
    return SphericalLinear(A=A, B=None if abs(A - B) <= 1e-12 * A else B, C=C, W=system.W, mu=system.mu,
                           l=bob.l, D=float(bob.rest[2]), k=float(bob.k), c_d=bob.c_d)


# ---- the coupled linear system (B.3) -------------------------------------------------------------

def characteristic_coefficients(p: SphericalLinear) -> np.ndarray:
    """Coefficients (highest power first, complex) of docs/models.md B.3's exact characteristic polynomial

    P(s) = (s^2 + (2iW + ct)s + omega_n^2)(A s - i(C - A)W) + mu D^2 (s + iW)(omega_0^2 + ct s)

    of the symmetric carrier + pendulum linearised about steady spin, w = omega_x + i omega_y ~ e^{st}."""
    A, W, ct, w02, q = p.A, p.W, p.ct, p.omega0**2, p.mu * p.D**2
    E = (p.C - A) * W
    wn2 = w02 - W**2
    b = 2j * W + ct
    return np.array([A + 0j, A * b - 1j * E + q * ct, A * wn2 - 1j * E * b + q * (w02 + 1j * W * ct),
                     -1j * E * wn2 + 1j * q * W * w02])


def characteristic_roots(p: SphericalLinear) -> np.ndarray:
    """The three roots of P(s) (1/s, body frame), polished by two Newton steps. Their complex
    conjugates are the other three exponents of the real system; omega_z adds a zero exponent."""
    co = characteristic_coefficients(p)
    r = np.roots(co)
    d = np.polyder(co)
    for _ in range(2):
        dr = np.polyval(co, r) / np.polyval(d, r)
        r = np.where(np.isfinite(dr), r - dr, r)
    return r


def carrier_share(p: SphericalLinear, s: complex) -> float:
    """Share of a mode's energy in the carrier wobble: A|w|^2 against the pendulum's
    mu l^2 (omega_0^2 + |s + iW|^2)|z|^2 (spring plus inertial swing), for the eigenvector of root s."""
    muD = p.mu * p.D
    if muD == 0:  # uncoupled: only the nutation root moves the carrier
        return 1.0 if abs(p.A * s - 1j * (p.C - p.A) * p.W) < 1e-9 * p.A * max(abs(s), 1.0) else 0.0
    z_over_w = (p.A * s - 1j * (p.C - p.A) * p.W) / (muD * p.l * (p.omega0**2 + p.ct * s))
    pend = p.mu * p.l**2 * (p.omega0**2 + abs(s + 1j * p.W) ** 2) * abs(z_over_w) ** 2
    return p.A / (p.A + pend)


def classify_roots(p: SphericalLinear, roots=None) -> dict[str, complex]:
    """Name the roots of P(s): "pendulum 2" turns fastest against the spin (Im s most negative, since
    lambda_2 > W > |Omega|); of the other two, "nutation" carries the larger carrier share and
    "pendulum 1" the smaller (at exact resonance they share it about equally)."""
    r = characteristic_roots(p) if roots is None else np.asarray(roots)
    order = np.argsort(r.imag)
    two, rest = r[order[0]], r[order[1:]]
    shares = [carrier_share(p, s) for s in rest]
    nut, pen = (rest[0], rest[1]) if shares[0] >= shares[1] else (rest[1], rest[0])
    return {"nutation": complex(nut), "pendulum 1": complex(pen), "pendulum 2": complex(two)}


def state_matrix(p: SphericalLinear) -> np.ndarray:
    """The real 6x6 matrix of docs/models.md B.3 for state (omega_x, omega_y, alpha, beta, alpha', beta'),
    any A, B: omega_z' = 0 at first order, so these six are the coupled block of the full model's
    Jacobian about steady spin."""
    A, B, C, W, mu, l, D = p.A, p.Bm, p.C, p.W, p.mu, p.l, p.D
    ct, wn2 = p.ct, p.omega_n2
    # unknowns x = (wx', wy', alpha'', beta''); M x = f(state)
    M = np.array([[A + mu * D**2, 0, mu * D * l, 0],
                  [0, B + mu * D**2, 0, mu * D * l],
                  [D / l, 0, 1, 0],
                  [0, D / l, 0, 1]], dtype=float)
    # right-hand sides as rows acting on (wx, wy, alpha, beta, alpha', beta')
    F = np.array([[0, -(C - B - mu * D**2) * W, mu * D * l * W**2, 0, 0, 2 * mu * D * l * W],
                  [(C - A - mu * D**2) * W, 0, 0, mu * D * l * W**2, -2 * mu * D * l * W, 0],
                  [0, D / l * W, -wn2, 0, -ct, 2 * W],
                  [-D / l * W, 0, 0, -wn2, -2 * W, -ct]], dtype=float)
    S = np.zeros((6, 6))
    acc = np.linalg.solve(M, F)
    S[0:2] = acc[0:2]
    S[2:4, 4:6] = np.eye(2)
    S[4:6] = acc[2:4]
    return S


def transverse_momentum_matrix(p: SphericalLinear) -> np.ndarray:
    """H_perp = (H_x, H_y) = Q y for the state y of ``state_matrix``, to first order:
    H_x = (A + mu D^2) omega_x + mu D l (alpha' - W beta), H_y = (B + mu D^2) omega_y + mu D l (beta' + W alpha)."""
    mdl = p.mu * p.D * p.l
    return np.array([[p.A + p.mu * p.D**2, 0, 0, -mdl * p.W, mdl, 0],
                     [0, p.Bm + p.mu * p.D**2, mdl * p.W, 0, 0, mdl]])


def exponents(p: SphericalLinear) -> np.ndarray:
    """All six exponents of the coupled block (1/s): the roots of P(s) and their conjugates for a
    symmetric carrier, the eigenvalues of ``state_matrix`` otherwise."""
    if p.B is None:
        r = characteristic_roots(p)
        return np.concatenate([r, r.conj()])
    return np.linalg.eigvals(state_matrix(p))


def slowest_decay_rate(p: SphericalLinear) -> float:
    """min over modes of -Re s, 1/s: what optimal tuning maximises (docs/models.md B.5); < 0 means growth."""
    return float(-np.max(exponents(p).real))


def linear_response(p: SphericalLinear, y0, t: np.ndarray) -> np.ndarray:
    """States (n, 6) of ``state_matrix`` at times t (n,), increasing, from y0 at t = 0: exact matrix
    exponentials (no eigenvectors, so it stays accurate at the double root of the optimum)."""
    from physics.systems.pendulum.propagate import propagate

    return propagate(state_matrix(p), y0, t)


def linear_nutation(p: SphericalLinear, w0: tuple[float, float], t: np.ndarray) -> np.ndarray:
    """Nutation angle (rad) of the linear theory, tan theta = |H_perp|/(C W), for the carrier started
    at transverse rate w0 = (omega_x, omega_y) with the pendulum at rest; t (n,) increasing, s."""
    Y = linear_response(p, [w0[0], w0[1], 0, 0, 0, 0], t)
    H = Y @ transverse_momentum_matrix(p).T
    return np.arctan2(np.hypot(H[:, 0], H[:, 1]), p.C * p.W)


def first_e_crossing(theta, rate: float, fastest: float) -> float:
    """First time (s) the nutation angle theta(t) (a function of an increasing time array) falls to
    theta(0)/e when rate > 0, or rises to e theta(0) when rate < 0. The grid resolves the fastest
    exponent (``fastest``, rad/s) and the horizon doubles from 4/|rate| up to 60/|rate|; inf if no crossing."""
    if rate == 0 or not math.isfinite(rate):
        return math.inf
    th0 = float(theta(np.array([0.0]))[0])
    target = th0 / math.e if rate > 0 else th0 * math.e
    dt = 0.05 * 2 * math.pi / max(fastest, 1e-12)
    horizon = 4.0 / abs(rate)
    while True:
        t = np.linspace(0.0, horizon, int(min(max(horizon / dt, 100), 200_000)) + 1)
        th = theta(t)
        hit = np.nonzero(th <= target if rate > 0 else th >= target)[0]
        if hit.size:
            i = hit[0]
            if i == 0:
                return 0.0

            def gap(tt: float) -> float:
                return float(theta(np.array([tt]))[0]) - target

            # theta at one time and on the grid may differ in the last bits, so where the crossing lies within
            # rounding of a grid point the bracket's ends can show the same sign: that end is the crossing
            ga, gb = gap(t[i - 1]), gap(t[i])
            if not ga * gb < 0:
                return float(t[i] if abs(gb) <= abs(ga) else t[i - 1])
            from scipy.optimize import brentq  # here: scipy.optimize adds 0.2 s to the app's start

            return brentq(gap, t[i - 1], t[i], xtol=1e-12)
        if horizon >= 60.0 / abs(rate):
            return math.inf
        horizon *= 2


def e_folding_time(p: SphericalLinear, w0: tuple[float, float] = (1e-3, 0.0)) -> float:
    """Time (s) for the linear nutation angle started from w0 (pendulum at rest) to fall by a factor e
    (first crossing of theta0/e), or to grow by e when the damper destabilises."""
    lam = exponents(p)
    return first_e_crossing(lambda t: linear_nutation(p, w0, t), float(-np.max(lam.real)),
                            float(np.max(np.abs(lam.imag))))


# ---- optimal tuning (B.5) ------------------------------------------------------------------------

def _tuned(p: SphericalLinear, omega0: float, ct: float) -> SphericalLinear:
    ml2 = p.mu * p.l**2
    return replace(p, k=ml2 * omega0**2, c_d=ml2 * ct)


def recipe_tuning(p: SphericalLinear) -> tuple[float, float]:
    """The averaged theory's starting point (docs/models.md B.5): omega_0 from (14) and critical coupling
    gamma_1 = 2g, i.e. ct = 4 g omega_0/lambda_1 with g^2 = mu D^2 C W omega_0/(2 A^2). (omega_0, ct)."""
    w0 = resonant_omega0(p.A, p.Bm, p.C, p.W)
    lam1 = w0 - p.W
    g = math.sqrt(p.mu * p.D**2 * p.C * p.W * w0 / (2 * p.A**2))
    return w0, 4 * g * w0 / lam1


def _double_root(p: SphericalLinear, x: np.ndarray, s: complex) -> tuple[np.ndarray, complex] | None:
    """Refine (omega_0, ct) to where two roots of P(s) coincide (P = P' = 0): at the optimum the two
    near-resonant roots meet, which is why the optimum is non-smooth (B.5)."""

    def eqs(v):
        q = _tuned(p, v[0], v[1])
        co = characteristic_coefficients(q)
        ss = complex(v[2], v[3])
        f, d = np.polyval(co, ss), np.polyval(np.polyder(co), ss)
        scale = p.A * max(abs(ss), 1.0) ** 3
        return [f.real / scale, f.imag / scale, d.real / scale, d.imag / scale]

    from scipy.optimize import root  # here: scipy.optimize adds 0.2 s to the app's start

    sol = root(eqs, [x[0], x[1], s.real, s.imag], method="hybr", options=dict(xtol=1e-14))
    converged = sol.success or np.max(np.abs(sol.fun)) < 1e-12  # hybr "no progress" at round-off
    if not converged or sol.x[0] <= p.W or sol.x[1] <= 0:
        return None
    return sol.x[:2], complex(sol.x[2], sol.x[3])


def optimal_parameters(p: SphericalLinear) -> tuple[float, float, float]:
    """(omega_0*, ct*, rate*) maximising the slowest decay rate of the linear system (docs/models.md B.5).

    The optimum is non-smooth: there two roots meet. A coarse Nelder-Mead on (omega_0, ct) from the
    recipe tuning gets near it; for a symmetric carrier, Newton onto the double root of P(s) then pins
    it down, and is kept when it is at least as good; otherwise a fine Nelder-Mead finishes the job.
    Reference set R: omega_0* = 3.00372753, c_d* = ct* mu l^2 = 8.54877461, rate 0.139836998 1/s."""
    if p.C <= max(p.A, p.Bm):
        raise ValueError("no stable tuning exists for a prolate carrier (docs/models.md B.5)")
    x0 = np.array(recipe_tuning(p))
    if p.B is None:
        A, W, q = p.A, p.W, p.mu * p.D**2
        E = (p.C - A) * W

        def neg_rate(x):
            w0, ct = x
            if w0 <= W or ct <= 0:
                return 1e3
            w02, b = w0 * w0, 2j * W + ct
            co = [A, A * b - 1j * E + q * ct, A * (w02 - W * W) - 1j * E * b + q * (w02 + 1j * W * ct),
                  -1j * E * (w02 - W * W) + 1j * q * W * w02]
            return float(np.max(np.roots(co).real))
    else:
        def neg_rate(x):
            if x[0] <= p.W or x[1] <= 0:
                return 1e3
            return -slowest_decay_rate(_tuned(p, x[0], x[1]))

    from scipy.optimize import minimize  # here: scipy.optimize adds 0.2 s to the app's start

    simplex = [x0, x0 * [1.02, 1.0], x0 * [1.0, 1.2]]
    coarse = minimize(neg_rate, x0, method="Nelder-Mead",
                      options=dict(xatol=1e-6, fatol=1e-10, maxiter=600, initial_simplex=simplex))
    x, rate = coarse.x, -coarse.fun
    if p.B is None:
        roots = characteristic_roots(_tuned(p, *x))
        near = roots[np.argsort(-roots.real)[:2]]
        ref = _double_root(p, x, complex(near.mean()))
        if ref is not None:
            # at a double root np.roots is only sqrt(eps) accurate: take its rate from the Newton
            # solution, and the third root (pendulum 2) from the polynomial
            third = max(characteristic_roots(_tuned(p, *ref[0])), key=lambda r: abs(r - ref[1]))
            rate_ref = min(-ref[1].real, -third.real)
            if rate_ref >= rate - 1e-9 * abs(rate):
                return float(ref[0][0]), float(ref[0][1]), float(rate_ref)
    fine = minimize(neg_rate, x, method="Nelder-Mead",
                    options=dict(xatol=1e-9, fatol=1e-13, maxiter=4000, initial_simplex=[
                        x, x * [1 + 1e-4, 1.0], x * [1.0, 1 + 1e-4]]))
    return float(fine.x[0]), float(fine.x[1]), float(-fine.fun)


def optimal_tuning(system) -> tuple[float, float]:
    """(k, c_d) of the spherical pendulum that maximise the slowest decay rate of the linear system
    (docs/models.md B.5), for a ``PendulumSystem`` whose single bob is a spherical pendulum (its k, c_d ignored).
    Raises ScenarioError for a prolate carrier."""
    from physics.core.errors import ScenarioError

    bob = system.bobs[0]
    p = spherical_linear(system if not isinstance(bob.k, str) else replace(
        system, bobs=(replace(bob, k=1.0),)))
    if p.C <= max(p.A, p.Bm):
        raise ScenarioError("pendulum.k", "optimal", f"cannot be tuned for a prolate carrier (its C = {p.C:.6g} <= "
                            f"A = {p.A:.6g}: body.C, body.A and body.B less the bobs'): every damper with "
                            "omega_0 > W makes the nutation grow "
                            "(docs/models.md B.5)")
    if p.D == 0:
        raise ScenarioError("pendulum.h", -bob.l, "puts the bob level with the system COM (D = 0): the pendulum "
                            "is not coupled to the nutation at first order, so no tuning damps it")
    w0, ct, _ = _optimal_cached(p.A, p.B, p.C, p.W, p.mu, p.l, p.D)
    ml2 = p.mu * p.l**2
    return ml2 * w0**2, ml2 * ct


@lru_cache(maxsize=64)
def _optimal_cached(A, B, C, W, mu, l, D) -> tuple[float, float, float]:
    """optimal_parameters memoised: a scenario is resolved several times per run (pack, auto, info)."""
    return optimal_parameters(SphericalLinear(A=A, B=B, C=C, W=W, mu=mu, l=l, D=D, k=1.0, c_d=0.0))
