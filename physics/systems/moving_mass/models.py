"""The moving-mass system (docs/models.md Part A) at the full and averaged fidelities.

Both give the attitude, so a scene can draw the body in the inertial frame (the averaged model from K's fixed
inertial direction, not by integrating a quaternion: see its section below), and
start from the same body angular velocity w0 (from ``omega`` or from G0 = |J* w0| and theta0).
"""

from __future__ import annotations

import math

import numpy as np

from physics.compiled import dispatch as kernels
from physics.compiled import mass_full as mass_full_kernel
from physics.core.rotation import IDENTITY, normalize, nutation_angle, qconj, rotate
from physics.core.trajectory import Trajectory
from physics.registry import Chart, Model, register
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario
from physics.systems.moving_mass.coefficients import coefficients
from physics.systems.moving_mass.params import LAWS, THRUSTERS


def _torques(sc: Scenario) -> tuple[float, float, float, float]:
    b = sc.control.b if sc.control else 0.0
    law = 0.0 if sc.control is None else float((LAWS + THRUSTERS).index(sc.control.law))
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


def stiff_advice(sc: Scenario) -> str:
    """Why a moving-mass run is stiff, in its keys: the spring-damper's rates against the motion that drives it.
    Short: it is shown under the slider that was changed, in the control panel's column."""
    fast = "mass.Omega, mass.chi" + (", mass.lam_q" if sc.mass.lam_q else "")
    return (f"the spring-damper ({fast}) outpaces the motion driving it (mass.rho, initial.G0, initial.theta0): "
            "lower the first or raise the second, or use the averaged or closed-form fidelity")


FULL = register(Model(
    name="moving_mass/full", system="moving_mass", fidelity="full",
    summary="carrier + point mass on a spring-damper, reduced-mass multibody equations (docs/models.md A.2)",
    state=("wx", "wy", "wz", "ux", "uy", "uz", "vx", "vy", "vz", "qw", "qx", "qy", "qz", "W_int", "W_ext"),
    kernel=kernels.MASS_FULL, pack=pack_full, initial_state=initial_full, observe=observe_full,
    invariants=invariants_full,
    columns=("ux", "uy", "uz", "vx", "vy", "vz", "W_int", "W_ext"), stiff_advice=stiff_advice,
))


# ---- averaged ---------------------------------------------------------------------------------
# The attitude follows from K: Q_K Rz(psi) Rx(theta) Rz(phi) (physics/compiled/averaged.py, docs/models.md A.3), with
# Q_K a constant frame whose e3 is K's inertial direction, (theta, phi) K's body-frame direction and psi the
# precession phase. The state is (w, psi, Q_K), or, for an axisymmetric body, (|w_perp|, w3, alpha, psi, Q_K); a
# carry reads both through their Chart as the (w, q) of the layout below.

ATTITUDE_LAYOUT = ("wx", "wy", "wz", "qw", "qx", "qy", "qz")
REDUCTION = {"moving_mass/averaged": "none: w and the precession phase psi, K's frame fixed",
             "moving_mass/averaged (axisymmetric)": "axisymmetric: |w_perp|, w3 and the phases alpha, psi by "
                                                     "quadrature of their slow rates, K's frame fixed"}


def pack_averaged(sc: Scenario) -> np.ndarray:
    co = coefficients(sc)
    b, _, lam, kc = _torques(sc)
    return np.array([sc.body.A, sc.body.B, sc.body.C, co.A, co.F, co.D, 0.0, 0.0, lam, b, co.Bq0, kc])


def _qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of quaternion rows (n, 4) or single ones (4,), written out: the averaged model's rows are
    rebuilt at every output, where numpy's general product costs more than the integration."""
    a0, a1, a2, a3 = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    b0, b1, b2, b3 = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3
    out[..., 1] = a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2
    out[..., 2] = a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1
    out[..., 3] = a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0
    return out


def _tilt(psi, theta) -> np.ndarray:
    """Rz(psi) (x) Rx(theta) as quaternions (..., 4)."""
    cp, sp = np.cos(0.5 * np.asarray(psi, dtype=float)), np.sin(0.5 * np.asarray(psi, dtype=float))
    ct, st = np.cos(0.5 * np.asarray(theta, dtype=float)), np.sin(0.5 * np.asarray(theta, dtype=float))
    return np.stack([cp * ct, cp * st, sp * st, sp * ct], -1)


def _euler(QK: np.ndarray, psi, theta, spin: np.ndarray) -> np.ndarray:
    """The attitude Q_K (x) Rz(psi) (x) Rx(theta) (x) spin, (..., 4), normalised; ``spin`` the quaternions of
    Rz(phi)."""
    q = _qmul(QK, _qmul(_tilt(psi, theta), spin))
    return q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))


def _about_z(phi) -> np.ndarray:
    h = 0.5 * np.asarray(phi, dtype=float)
    z = np.zeros_like(h)
    return np.stack([np.cos(h), z, z, np.sin(h)], -1)


def _spin(alpha) -> np.ndarray:
    """Rz(phi) for phi = pi/2 - alpha, from the half angles of alpha rather than from pi/2 - alpha: alpha grows
    to thousands of rad, where pi/2 - alpha would round by 1e-12 rad and tilt the attitude against w by as much.
    cos(pi/4 - alpha/2) = (cos(alpha/2) + sin(alpha/2))/sqrt(2), sin(pi/4 - alpha/2) = (cos - sin)/sqrt(2)."""
    h = 0.5 * np.asarray(alpha, dtype=float)
    c, s = np.cos(h), np.sin(h)
    z = np.zeros_like(h)
    return np.stack([c + s, z, z, c - s], -1) * math.sqrt(0.5)


def _body_angles(w: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(theta, phi) of K's body-frame direction G/|G| = (sin theta sin phi, sin theta cos phi, cos theta)."""
    G = w * p[0:3]
    return nutation_angle(G), np.arctan2(G[..., 0], G[..., 1])


def _frame(q: np.ndarray, theta: float, spin: np.ndarray) -> np.ndarray:
    """Q_K with Q_K (x) Rx(theta) (x) spin = q (psi = 0): the frame of K's inertial direction."""
    QK = _qmul(np.asarray(q, dtype=float), qconj(_qmul(_tilt(0.0, theta), spin)))
    return QK / math.sqrt(float(QK @ QK))


def _general_from(Y: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    w = Y[:, 0:3]
    theta, phi = _body_angles(w, p)
    # phi unwrapped along the rows: a jump of 2 pi would flip the quaternion's sign from one row to the next
    return w, _euler(Y[:, 4:8], Y[:, 3], theta, _about_z(np.unwrap(phi)))


def _general_to(yc: np.ndarray, p: np.ndarray) -> np.ndarray:
    w = np.asarray(yc[0:3], dtype=float)
    theta, phi = _body_angles(w, p)
    return np.concatenate([w, [0.0], _frame(yc[3:7], theta, _about_z(phi))])


def _reduced_angles(Y: np.ndarray, p: np.ndarray):
    """(omega (n, 3), theta, Rz(phi)) of reduced states; a |w_perp| that an integrator took below zero reads as
    its modulus at the opposite phase (the rates are odd in it, so nothing else changes)."""
    wp, w3, alpha = Y[:, 0], Y[:, 1], Y[:, 2]
    if np.any(wp < 0):
        alpha = np.where(wp < 0, alpha + np.pi, alpha)
        wp = np.abs(wp)
    omega = np.column_stack([wp * np.cos(alpha), wp * np.sin(alpha), w3])
    return omega, np.arctan2(p[0] * wp, p[2] * w3), _spin(alpha)


def _reduced_from(Y: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    omega, theta, spin = _reduced_angles(Y, p)
    return omega, _euler(Y[:, 4:8], Y[:, 3], theta, spin)


def _reduced_to(yc: np.ndarray, p: np.ndarray) -> np.ndarray:
    w = np.asarray(yc[0:3], dtype=float)
    wp, alpha = math.hypot(w[0], w[1]), math.atan2(w[1], w[0])
    theta = math.atan2(p[0] * wp, p[2] * w[2])
    return np.concatenate([[wp, w[2], alpha, 0.0], _frame(yc[3:7], theta, _spin(alpha))])


def _chart(native_from, native_to) -> Chart:
    def from_native(Y, p):
        w, q = native_from(np.atleast_2d(np.asarray(Y, dtype=float)), p)
        return np.column_stack([w, q])

    return Chart(state=ATTITUDE_LAYOUT, from_native=from_native, to_native=native_to)


def _observer(native_from, name: str):
    def observe(t, Y, p, sc) -> Trajectory:
        w, q = native_from(np.atleast_2d(Y), p)
        G = w * p[0:3]
        return Trajectory(t=t, theta=nutation_angle(G), K=np.linalg.norm(G, axis=1), E=0.5 * np.sum(w * G, axis=1),
                          omega=w, quat=q, info={"reduction": REDUCTION[name]})

    def invariants(Y, p):
        w, q = native_from(np.atleast_2d(Y), p)
        G = w * p[0:3]
        return rotate(q, G), 0.5 * np.sum(w * G, axis=1)

    return observe, invariants


def _initial(chart: Chart):
    def initial_state(sc: Scenario, p: np.ndarray) -> np.ndarray:
        w0, _, _ = initial_G(sc)
        return chart.to_native(np.concatenate([w0, IDENTITY]), p)

    return initial_state


def reduce_averaged(sc: Scenario) -> Model | None:
    """The axisymmetric reduction where it is exact: J*1 = J*2 (body.A = body.B)."""
    return AXISYMMETRIC if sc.body.A == sc.body.B else None


_GENERAL_CHART = _chart(_general_from, _general_to)
_REDUCED_CHART = _chart(_reduced_from, _reduced_to)
observe_averaged, invariants_averaged = _observer(_general_from, "moving_mass/averaged")
observe_axisymmetric, invariants_axisymmetric = _observer(_reduced_from, "moving_mass/averaged (axisymmetric)")
_SUMMARY = "quasi-rigid body: seed 004 eq. (1) with seed 000 (2.5) friction terms (docs/models.md A.3)"

AVERAGED = register(Model(
    name="moving_mass/averaged", system="moving_mass", fidelity="averaged", summary=_SUMMARY,
    state=("wx", "wy", "wz", "psi", "Kw", "Kx", "Ky", "Kz"),
    kernel=kernels.MASS_AVERAGED, pack=pack_averaged, initial_state=_initial(_GENERAL_CHART),
    observe=observe_averaged, invariants=invariants_averaged, chart=_GENERAL_CHART, reduce=reduce_averaged,
))

# Not registered: the averaged model runs in this form, under its name, wherever ``reduce_averaged`` says so.
AXISYMMETRIC = Model(
    name="moving_mass/averaged", system="moving_mass", fidelity="averaged", summary=_SUMMARY + ", axisymmetric form",
    state=("w_perp", "wz", "alpha", "psi", "Kw", "Kx", "Ky", "Kz"),
    kernel=kernels.MASS_AVERAGED_AXISYMMETRIC, pack=pack_averaged, initial_state=_initial(_REDUCED_CHART),
    observe=observe_axisymmetric, invariants=invariants_axisymmetric, chart=_REDUCED_CHART,
)
