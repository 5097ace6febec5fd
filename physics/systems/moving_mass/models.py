"""The moving-mass system (docs/models.md Part A) at the full and averaged fidelities.

Both integrate the attitude with the rest, so a scene can draw the body in the inertial frame, and
start from the same body angular velocity w0 (from ``omega`` or from G0 = |J* w0| and theta0).
"""

from __future__ import annotations

import numpy as np

from physics.compiled import dispatch as kernels
from physics.compiled import mass_full as mass_full_kernel
from physics.core.rotation import IDENTITY, normalize, nutation_angle, rotate
from physics.core.trajectory import Trajectory
from physics.registry import Model, register
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario
from physics.systems.moving_mass.coefficients import coefficients


def _torques(sc: Scenario) -> tuple[float, float, float, float]:
    b = sc.control.b if sc.control else 0.0
    law = 0.0 if (sc.control is None or sc.control.law == "K") else 1.0
    lam = sc.medium.lambda_ if sc.medium else 0.0
    kc = sc.cavity.coupling if sc.cavity else 0.0
    return b, law, lam, kc


# ---- full -------------------------------------------------------------------------------------

def pack_full(sc: Scenario) -> np.ndarray:
    body = sc.body
    J = np.array([body.A, body.B, body.C])
    if sc.mass is None:
        m = rho = c = delta = mu = 0.0
        eta, mr, d0 = 0.0, 1.0, 0.0  # m_r only divides a zero force: any positive value will do
    else:
        ms = sc.mass
        m, rho = ms.m, ms.rho
        eta = m / body.M
        mr = m * (1.0 - eta)
        d0 = rho / (1.0 - eta)
        c, delta, mu = m * ms.Omega**2, m * ms.chi, m * ms.lam_q
    Jb = J - (m * rho**2 / (1.0 - eta)) * np.array([1.0, 1.0, 0.0])
    if np.any(Jb <= 0):
        from physics.core.errors import ScenarioError

        raise ScenarioError("mass.rho", rho, "is too large: m rho^2/(1 - m/M) must be less than A and B")
    b, law, lam, kc = _torques(sc)
    return np.array([*Jb, *J, mr, d0, c, delta, mu, b, law, lam, kc])


def quasi_static_displacement(sc: Scenario, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Forced (slow-manifold) displacement u and velocity u' of the mass, docs/models.md A.3:
    u = -a/Omega^2 + chi a'/Omega^4 + lam_q |a'| a'/Omega^6, u' = -a'/Omega^2, with
    a = w x (w x r) + w' x r evaluated along torque-free motion of the frozen body."""
    ms = sc.mass
    J = np.array([sc.body.A, sc.body.B, sc.body.C])
    r = np.array([0.0, 0.0, ms.rho])

    def euler(w):
        return -np.cross(w, J * w) / J

    wd = euler(w)
    # w'' = Df(w) w' along the torque-free motion, by an exact-enough central difference of f
    hstep = 1e-6 * max(1.0, np.linalg.norm(w))
    wdd = (euler(w + hstep * wd) - euler(w - hstep * wd)) / (2 * hstep)
    a = np.cross(w, np.cross(w, r)) + np.cross(wd, r)
    ad = np.cross(wd, np.cross(w, r)) + np.cross(w, np.cross(wd, r)) + np.cross(wdd, r)
    O2 = ms.Omega**2
    u = -a / O2 + ms.chi * ad / O2**2 + ms.lam_q * np.linalg.norm(ad) * ad / O2**3
    return u, -ad / O2


def initial_full(sc: Scenario, p: np.ndarray) -> np.ndarray:
    w0, _, _ = initial_G(sc)
    u = v = np.zeros(3)
    if sc.mass is not None and sc.initial.mass_state == "quasistatic":
        u, v = quasi_static_displacement(sc, w0)
    return np.concatenate([w0, u, v, IDENTITY, [0.0, 0.0]])


def observe_full(t, Y, p, sc) -> Trajectory:
    Kb, E = mass_full_kernel.observe(np.ascontiguousarray(Y), p)
    internal = {name: Y[:, i] for i, name in enumerate(("ux", "uy", "uz", "vx", "vy", "vz"), start=3)}
    internal["W_int"] = Y[:, 13]
    internal["W_ext"] = Y[:, 14]
    return Trajectory(t=t, theta=nutation_angle(Kb), K=np.linalg.norm(Kb, axis=1), E=E, omega=Y[:, 0:3].copy(),
                      quat=normalize(Y[:, 9:13]), internal=internal)


def invariants_full(Y, p):
    Kb, E = mass_full_kernel.observe(np.ascontiguousarray(Y), p)
    return rotate(Y[:, 9:13], Kb), E


FULL = register(Model(
    name="moving_mass/full", system="moving_mass", fidelity="full",
    summary="carrier + point mass on a spring-damper, reduced-mass multibody equations (docs/models.md A.2)",
    state=("wx", "wy", "wz", "ux", "uy", "uz", "vx", "vy", "vz", "qw", "qx", "qy", "qz", "W_int", "W_ext"),
    kernel=kernels.MASS_FULL, pack=pack_full, initial_state=initial_full, observe=observe_full,
    invariants=invariants_full,
    columns=("ux", "uy", "uz", "vx", "vy", "vz", "W_int", "W_ext"),
))


# ---- averaged ---------------------------------------------------------------------------------

def pack_averaged(sc: Scenario) -> np.ndarray:
    co = coefficients(sc)
    b, _, lam, kc = _torques(sc)
    return np.array([sc.body.A, sc.body.B, sc.body.C, co.A, co.F, co.D, 0.0, 0.0, lam, b, co.Bq0, kc])


def initial_averaged(sc: Scenario, p: np.ndarray) -> np.ndarray:
    w0, _, _ = initial_G(sc)
    return np.concatenate([w0, IDENTITY])


def observe_averaged(t, Y, p, sc) -> Trajectory:
    w = Y[:, 0:3].copy()
    G = w * p[0:3]
    return Trajectory(t=t, theta=nutation_angle(G), K=np.linalg.norm(G, axis=1), E=0.5 * np.sum(w * G, axis=1),
                      omega=w, quat=normalize(Y[:, 3:7]))


def invariants_averaged(Y, p):
    G = Y[:, 0:3] * p[0:3]
    return rotate(Y[:, 3:7], G), 0.5 * np.sum(Y[:, 0:3] * G, axis=1)


AVERAGED = register(Model(
    name="moving_mass/averaged", system="moving_mass", fidelity="averaged",
    summary="quasi-rigid body: seed 004 eq. (1) with seed 000 (2.5) friction terms (docs/models.md A.3)",
    state=("wx", "wy", "wz", "qw", "qx", "qy", "qz"),
    kernel=kernels.MASS_AVERAGED, pack=pack_averaged, initial_state=initial_averaged, observe=observe_averaged,
    invariants=invariants_averaged,
))
