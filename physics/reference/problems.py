"""The benchmark problems P1-P4 of issue 5, and their exact or reference solutions.

P1  free rigid body, I = (2, 1, 2/3), omega0 = (cos 1.1, 0, sin 1.1), T = 100 (Hairer-Lubich-Wanner's
    test body). This inertia breaks the triangle inequality (2 > 1 + 2/3), so physics.Scenario
    rejects it as unphysical; P1 drives the compiled full-model kernel directly with no mass.
    Exact solution: ``rigid_body_exact`` (Jacobi elliptic functions).
P2  full moving-mass model, prolate, eps = 0.1, docs/models.md A.7(a) (tests/conftest.reference(0.1, 0.5,
    0.3, 13333.3)), about 4000 revolutions, mass on its slow manifold; reference: compiled DOP853 at
    rtol 1e-13.
P3  braking with a cavity and a medium on the averaged model: |G|(t) and the braking time T are
    exact (physics.systems.moving_mass.closed004, seed 004 eq. (10)).
P4  resonant spherical-pendulum damper, set R of docs/models.md B.8, 10 deg nutation, 40 s; reference:
    compiled DOP853 at rtol 1e-13.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ellipj, ellipk

import physics
from physics.systems.moving_mass import closed004

# ---- P1 ---------------------------------------------------------------------------------------

P1_INERTIA = np.array([2.0, 1.0, 2.0 / 3.0])
P1_OMEGA0 = np.array([math.cos(1.1), 0.0, math.sin(1.1)])
P1_T = 100.0


def p1_params() -> np.ndarray:
    """Parameter vector of physics/compiled/mass_full.py for a bare rigid body (no mass, no torque)."""
    Jb = P1_INERTIA
    return np.array([*Jb, *Jb, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])


def p1_initial() -> np.ndarray:
    y0 = np.zeros(15)
    y0[0:3] = P1_OMEGA0
    y0[9] = 1.0
    return y0


def rigid_body_exact(t, I=P1_INERTIA, w0=P1_OMEGA0) -> np.ndarray:
    """Body angular velocity (n, 3) of the torque-free body, I1 > I2 > I3, started with w2(0) = 0,
    w1(0), w3(0) > 0 and K^2 > 2 E I2 (rotation about the axis of largest moment).

    From Euler's equations and the two integrals K^2 = sum I_i^2 w_i^2, 2E = sum I_i w_i^2
    (Landau-Lifshitz, Mechanics, section 37, with their axes 1, 3 swapped, which flips the sign of w2):

        w1 = sqrt((K^2 - 2E I3) / (I1 (I1 - I3))) dn(tau, m)
        w2 = -sqrt((2E I1 - K^2) / (I2 (I1 - I2))) sn(tau, m)
        w3 = sqrt((2E I1 - K^2) / (I3 (I1 - I3))) cn(tau, m)
        tau = t sqrt((I1 - I2)(K^2 - 2E I3) / (I1 I2 I3)),
        m = k^2 = (I2 - I3)(2E I1 - K^2) / ((I1 - I2)(K^2 - 2E I3)).

    At t = 0, sn = 0 and cn = dn = 1 give back w0 (the integrals fix the amplitudes), and
    I2 w2' = (I3 - I1) w3 w1 < 0 fixes the sign of w2.
    """
    I1, I2, I3 = I
    K2 = float(np.sum((I * w0) ** 2))
    E2 = float(np.sum(I * w0**2))
    if not (I1 > I2 > I3 and K2 > E2 * I2 and w0[1] == 0 and w0[0] > 0 and w0[2] > 0):
        raise ValueError("rigid_body_exact covers I1 > I2 > I3, K^2 > 2E I2, w0 = (+, 0, +)")
    lam = math.sqrt((I1 - I2) * (K2 - E2 * I3) / (I1 * I2 * I3))
    m = (I2 - I3) * (E2 * I1 - K2) / ((I1 - I2) * (K2 - E2 * I3))
    sn, cn, dn, _ = ellipj(lam * np.asarray(t, float), m)
    return np.stack([math.sqrt((K2 - E2 * I3) / (I1 * (I1 - I3))) * dn,
                     -math.sqrt((E2 * I1 - K2) / (I2 * (I1 - I2))) * sn,
                     math.sqrt((E2 * I1 - K2) / (I3 * (I1 - I3))) * cn], axis=-1)


def rigid_body_period(I=P1_INERTIA, w0=P1_OMEGA0) -> float:
    """Period of w(t), s: 4 K(m) / tau-rate."""
    I1, I2, I3 = I
    K2 = float(np.sum((I * w0) ** 2))
    E2 = float(np.sum(I * w0**2))
    lam = math.sqrt((I1 - I2) * (K2 - E2 * I3) / (I1 * I2 * I3))
    m = (I2 - I3) * (E2 * I1 - K2) / ((I1 - I2) * (K2 - E2 * I3))
    return 4.0 * float(ellipk(m)) / lam


# ---- P2 ---------------------------------------------------------------------------------------

P2_T = 13333.3  # s, docs/models.md A.7(a) horizon at eps = 0.1 (about 4000 revolutions)
P2_SAMPLES = 401


def moving_mass(eps: float, C: float = 0.5, theta0: float = 0.3, t_end: float = P2_T, *,
                samples: int = P2_SAMPLES, rtol: float = 1e-11, chi: float | None = None,
                mass_state: str = "quasistatic", extra: dict | None = None) -> physics.Scenario:
    """docs/models.md A.7(a): A = 1, m = 0.1, m/M = 0.1, rho = 1.5, Omega = 1/eps, chi = Omega, G0 = 1
    (the same builder as tests/conftest.reference)."""
    Om = 1.0 / eps
    data = {
        "body": {"A": 1.0, "C": C, "M": 1.0},
        "mass": {"m": 0.1, "rho": 1.5, "Omega": Om, "chi": Om if chi is None else chi},
        "initial": {"G0": 1.0, "theta0": theta0, "mass_state": mass_state},
        "run": {"t_end": t_end, "samples": samples, "rtol": rtol, "fidelity": "full"},
    }
    data.update(extra or {})
    return physics.Scenario.from_dict(data)


def p2(t_end: float = P2_T) -> physics.Scenario:
    return moving_mass(0.1, t_end=t_end)


# ---- P3 ---------------------------------------------------------------------------------------

P3_B = 0.01  # N m, braking bound
P3_LAMBDA = 0.005  # 1/s, medium
P3_CAVITY = {"beta": 1000.0, "nu": 1.0, "a0": 0.3}  # Re = a0^2 w / nu ~ 0.1


def p3(samples: int = 401, rtol: float = 1e-10) -> physics.Scenario:
    """Averaged model, prolate eps = 0.1 body, cavity + medium + time-optimal braking (law G = K);
    runs to the end of braking (t_end past T)."""
    T = closed004.braking_time(1.0, P3_B, P3_LAMBDA)
    return moving_mass(0.1, t_end=1.2 * T, samples=samples, rtol=rtol, extra={
        "cavity": dict(P3_CAVITY), "medium": {"lambda": P3_LAMBDA}, "control": {"b": P3_B},
        "run": {"t_end": 1.2 * T, "samples": samples, "rtol": rtol, "fidelity": "averaged"}})


def p3_exact(t):
    """|G|(t) (kg m^2/s) and T (s), seed 004 eq. (10)."""

    return closed004.momentum_modulus(t, 1.0, P3_B, P3_LAMBDA), closed004.braking_time(1.0, P3_B, P3_LAMBDA)


# ---- P4 ---------------------------------------------------------------------------------------

P4_T = 40.0


def set_R(theta0: float = math.pi / 180, *, k: float | str = "resonant", c_d: float = 8.0, t_end: float = 60.0,
          samples: int = 1201, h: float = -0.7, A_carrier: float = 100.0, rtol: float = 1e-11) -> physics.Scenario:
    """docs/models.md B.8's reference set R (carrier A = B = 100, C = 150, M0 = 500; bob m = 5, l = 1, pivot h = -0.7;
    W = 2), in frozen-system moments, started at nutation theta0 (rad) with the pendulum at rest; full model.
    The seed 002 figures (bench/figures.py) vary its spring, damper, pivot and carrier."""
    M0, m, l, W, C = 500.0, 5.0, 1.0, 2.0, 150.0
    mu = m * M0 / (M0 + m)
    D = (M0 + m) * (h + l) / M0
    A = A_carrier + mu * D**2
    return physics.Scenario.from_dict({
        "body": {"A": A, "B": A, "C": C, "M": M0 + m},
        "pendulum": {"m": m, "l": l, "h": h, "k": k, "c_d": c_d},
        "initial": {"omega": [C * W * math.tan(theta0) / A, 0.0, W]},
        "run": {"t_end": t_end, "samples": samples, "rtol": rtol, "fidelity": "full"}})


def p4(t_end: float = P4_T, samples: int = 401, rtol: float = 1e-12, theta0: float = 10 * math.pi / 180):
    """Set R (``set_R``: resonant spring, pivot damper c_d = 8) at 10 deg nutation over 40 s."""
    return set_R(theta0, t_end=t_end, samples=samples, rtol=rtol)
