"""The full pendulum-damper models (docs/models.md Part B.2): conservation, the energy balance, an
independent Lagrangian formulation, the reference numbers of B.6 and B.7, the gimbal singularity
and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest

import physics
from physics.compiled import pendulum as kernel
from physics.systems.pendulum.geometry import pendulum_system

deg = math.pi / 180
INVARIANT_TOL = 1e-9  # relative drift of the inertial H and of E
BALANCE_TOL = 1e-9  # |E(0) - E(t) - W(t)| relative to E(0)
RHS_TOL = 1e-10  # relative, kernel vs the independent Lagrangian
RATE_TOL = 0.02  # relative, decay rates of docs/models.md B.6 and decay times of B.7
ANGLE_TOL = 0.01 * deg  # the meridian pendulums' nutation angle at 400 s (B.7 quotes 9.30 deg)

SPHERICAL = physics.get_model("spherical_pendulum", "full")
PLANE = physics.get_model("plane_pendulums", "full")


# ---- scenarios ------------------------------------------------------------------------------------

def set_R(theta0: float = 10 * deg, *, c_d: float = 8.0, k="resonant", t_end: float = 60.0, samples: int = 1201,
          rtol: float = 1e-12, omega=None) -> physics.Scenario:
    """docs/models.md B.8: carrier A = B = 100, C = 150, M = 500; bob m = 5, l = 1, pivot h = -0.7 from O;
    W = 2. The scenario takes the frozen moments: A + mu D^2 (the bob at rest on the axis) and C."""
    M0, m, l, h, W = 500.0, 5.0, 1.0, -0.7, 2.0
    mu = m * M0 / (M0 + m)
    D = (M0 + m) * (h + l) / M0
    A, C = 100.0 + mu * D**2, 150.0
    w0 = [C * W * math.tan(theta0) / A, 0.0, W] if omega is None else omega  # phi(0) = theta0 exactly
    return physics.Scenario.from_dict({
        "body": {"A": A, "B": A, "C": C, "M": M0 + m},
        "pendulum": {"m": m, "l": l, "h": h, "k": k, "c_d": c_d},
        "initial": {"omega": w0},
        "run": {"t_end": t_end, "samples": samples, "rtol": rtol, "fidelity": "full"},
    })


def _shift(x: np.ndarray) -> np.ndarray:
    return float(x @ x) * np.eye(3) - np.outer(x, x)


def taylor(preset: str = "in_plane", *, k: float = 0.0, R: float = 1.0, t_end: float = 60.0, samples: int = 1201,
           rtol: float = 1e-11) -> physics.Scenario:
    """docs/models.md B.7: three plane pendulums at azimuths 0/120/240 deg, m = 2, l = 1, c = 2, hinge at
    height z_p = 0.5 above the carrier COM G_B; flat carrier A = B = 100, C = 200, M = 500; W = 2 and
    phi(0) = 10 deg. The scenario measures z_p from the system COM O, which sits o = 6 z_p'/506 above
    G_B (z_p' the bobs' common height), and takes the frozen moments about O."""
    Ac, Cc, M0, m, l, zp, W = 100.0, 200.0, 500.0, 2.0, 1.0, 0.5, 2.0
    az = [0.0, 2 * math.pi / 3, 4 * math.pi / 3]
    radial = [np.array([math.cos(a), math.sin(a), 0.0]) for a in az]
    rests = [R * u + zp * np.array([0.0, 0.0, 1.0]) + l * u for u in radial]  # both presets: arm radial out
    Mt = M0 + 3 * m
    o = sum(m * r for r in rests) / Mt
    J = np.diag([Ac, Ac, Cc]) + M0 * _shift(-o) + sum(m * _shift(r - o) for r in rests)
    A, B, C = np.diag(J)
    assert np.allclose(J, np.diag([A, B, C]), rtol=0, atol=1e-12)
    return physics.Scenario.from_dict({
        "body": {"A": A, "B": B, "C": C, "M": Mt},
        "plane_pendulum": [{"m": m, "l": l, "k": k, "c_d": 2.0, "preset": preset, "R": R, "z_p": zp - o[2],
                            "azimuth": a} for a in az],
        "initial": {"omega": [C * W * math.tan(10 * deg) / A, 0.0, W]},
        "run": {"t_end": t_end, "samples": samples, "rtol": rtol, "fidelity": "full"},
    })


def random_plane(seed: int = 3, *, c_d: float = 0.0, t_end: float = 320.0) -> physics.Scenario:
    """Three plane pendulums of random geometry (hinge, axis, arm, l, m, k) on a triaxial carrier."""
    rng = np.random.default_rng(seed)
    pends = []
    for _ in range(3):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        e = rng.normal(size=3)
        e -= (e @ n) * n
        e /= np.linalg.norm(e)
        pends.append({"m": float(rng.uniform(1, 3)), "l": float(rng.uniform(0.3, 1.0)), "k": float(rng.uniform(0, 20)),
                      "c_d": c_d, "hinge": [float(x) for x in rng.uniform(-1, 1, 3)], "axis": [float(x) for x in n],
                      "arm": [float(x) for x in e]})
    return physics.Scenario.from_dict({
        "body": {"A": 100.0, "B": 130.0, "C": 180.0, "M": 500.0 + sum(p["m"] for p in pends)},
        "plane_pendulum": pends,
        "initial": {"omega": [0.3, -0.2, 2.0]},
        "run": {"t_end": t_end, "samples": 2001, "rtol": 1e-12, "fidelity": "full"},
    })


def states(tr: physics.Trajectory) -> np.ndarray:
    """The model's state rows rebuilt from a trajectory: w, q, q', quaternion, W (and the spherical
    pendulum's chart)."""
    names = ("alpha", "beta", "alpha_dot", "beta_dot") if "alpha" in tr.internal else \
        tuple(k for k in tr.internal if k.startswith("a") and not k.endswith("_dot")) + \
        tuple(k for k in tr.internal if k.endswith("_dot"))
    cols = [tr.omega] + [tr.internal[k][:, None] for k in names] + [tr.quat, tr.internal["W_diss"][:, None]]
    cols += [tr.internal["chart"][:, None]] if "chart" in tr.internal else []
    return np.hstack(cols)


def decay_rate(t: np.ndarray, theta: np.ndarray, start: float = 0.8, stop: float = 0.01) -> float:
    """Least-squares slope of -log theta over the part of the run where theta has fallen below
    start * theta0 and not yet below stop * theta0, 1/s. (This window reproduces the B.6 numbers;
    theta of the coupled nutation-pendulum pair is not a single exponential.)"""
    below = np.cumsum(theta < stop * theta[0]) == 0
    sel = (theta <= start * theta[0]) & below
    return -float(np.polyfit(t[sel], np.log(theta[sel]), 1)[0])


# ---- conservation and the energy balance --------------------------------------------------------

CONSERVATIVE = {
    "spherical_R_undamped": lambda: set_R(c_d=0.0, t_end=320.0, samples=2001),
    "spherical_soft_triaxial": lambda: physics.Scenario.from_dict({
        "body": {"A": 90.0, "B": 110.0, "C": 150.0, "M": 505.0},
        "pendulum": {"m": 5.0, "l": 0.8, "h": 0.4, "k": 30.0},
        "initial": {"omega": [0.4, 0.3, 2.0]},
        "run": {"t_end": 320.0, "samples": 2001, "rtol": 1e-12, "fidelity": "full"}}),
    "plane_random_triaxial": random_plane,
}


@pytest.mark.parametrize("name", CONSERVATIVE)
def test_undamped_motion_conserves_H_and_E(name):
    sc = CONSERVATIVE[name]()
    tr = physics.simulate(sc)
    model = physics.get_model(sc.system, "full")
    assert tr.t[-1] * np.linalg.norm(tr.omega[0]) / (2 * math.pi) >= 100  # carrier revolutions
    Hi, E = model.invariants(states(tr), model.pack(sc))
    assert np.max(np.linalg.norm(Hi - Hi[0], axis=1)) <= INVARIANT_TOL * np.linalg.norm(Hi[0])
    assert np.max(np.abs(E - E[0])) <= INVARIANT_TOL * E[0]
    assert np.allclose(tr.E, E, rtol=0, atol=1e-13 * E[0]) and np.allclose(tr.K, np.linalg.norm(Hi, axis=1))
    # the pendulums really move: the test would be empty otherwise
    swing = max(np.max(np.abs(v)) for k, v in tr.internal.items() if k in ("alpha", "beta", "a1", "a2", "a3"))
    assert swing > 1 * deg


@pytest.mark.parametrize("make", [lambda: set_R(c_d=8.0, t_end=320.0, samples=2001),
                                  lambda: random_plane(c_d=3.0)], ids=["spherical_R", "plane_random"])
def test_damped_energy_falls_by_the_dissipated_work(make):
    sc = make()
    tr = physics.simulate(sc)
    E, W = tr.E, tr.internal["W_diss"]
    assert W[-1] > 1e-3 * E[0]  # a real amount was dissipated
    assert np.all(np.diff(E) <= 1e-13 * E[0])  # monotone, to rounding
    assert np.max(np.abs(E[0] - E - W)) <= BALANCE_TOL * E[0]
    model = physics.get_model(sc.system, "full")
    Hi, _ = model.invariants(states(tr), model.pack(sc))
    assert np.max(np.linalg.norm(Hi - Hi[0], axis=1)) <= INVARIANT_TOL * np.linalg.norm(Hi[0])


# ---- an independent formulation: the two-body Lagrangian with the carrier's translation explicit ----

def _cross_matrix(n):
    return np.array([[0, -n[2], n[1]], [n[2], 0, -n[0]], [-n[1], n[0], 0]])


def _rotation(n, angle):
    """Rodrigues; complex angles allowed (for the complex-step derivatives)."""
    K = _cross_matrix(np.asarray(n, float) / np.linalg.norm(n))
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * (K @ K)


def _bobs(system, q):
    """Bob positions from G_B (N, 3) and dr_i/dq (N, 3, nq) from rotations: the arm of a spherical
    pendulum is R_x(alpha) R_y(beta) e3 (B.1) and turns with alpha' e1 + beta' R_x(alpha) e2; a plane
    pendulum's arm is e0 turned by a about its hinge axis n."""
    e1, e2, e3 = np.eye(3)
    if system.bobs[0].kind == "spherical":
        b = system.bobs[0]
        Rx = _rotation(e1, q[0])
        e = Rx @ _rotation(e2, q[1]) @ e3
        J = np.stack([np.cross(e1, b.l * e), np.cross(Rx @ e2, b.l * e)], axis=1)
        return (b.pivot + b.l * e)[None, :], J[None, :, :]
    nq = len(system.bobs)
    r = np.zeros((nq, 3), dtype=np.result_type(q, float))
    J = np.zeros((nq, 3, nq), dtype=r.dtype)
    for i, b in enumerate(system.bobs):
        arm = _rotation(b.axis, q[i]) @ b.arm
        r[i] = b.pivot + b.l * arm
        J[i, :, i] = np.cross(b.axis, b.l * arm)
    return r, J


def _mass_matrix(system, q):
    """Mass matrix of T = 1/2 M0 |V|^2 + 1/2 w.I_c.w + 1/2 sum m_i |V + w x r_i + J_i q'|^2 in
    u = (V, w, q'), V the carrier COM velocity (body components), by polarisation of T."""
    r, J = _bobs(system, q)
    nq = J.shape[2]
    n = 6 + nq

    def T(u):
        V, w, qd = u[0:3], u[3:6], u[6:]
        out = 0.5 * system.M0 * (V @ V) + 0.5 * (w @ system.I_c @ w)
        for i, b in enumerate(system.bobs):
            v = V + np.cross(w, r[i]) + J[i] @ qd
            out = out + 0.5 * b.m * (v @ v)  # no conjugate: complex-step safe
        return out

    E = np.eye(n)
    Mm = np.zeros((n, n), dtype=r.dtype)
    for a in range(n):
        Mm[a, a] = 2 * T(E[a])
        for b in range(a):
            Mm[a, b] = Mm[b, a] = T(E[a] + E[b]) - T(E[a]) - T(E[b])
    return Mm


def lagrangian_accelerations(system, y):
    """(w', q'') from the Boltzmann-Hamel (Kirchhoff) equations of the free two-body system:
    d/dt dL/dV + w x dL/dV = 0, d/dt dL/dw + w x dL/dw + V x dL/dV = 0,
    d/dt dL/dq' - dL/dq = -c q', with V set by zero total linear momentum. The q-derivatives of the
    mass matrix are complex steps, exact to rounding."""
    spherical = system.bobs[0].kind == "spherical"
    nq = 2 if spherical else len(system.bobs)
    w, q, qd = y[0:3], y[3:3 + nq], y[3 + nq:3 + 2 * nq]
    k = np.array([system.bobs[0].k] * 2 if spherical else [b.k for b in system.bobs])
    c = np.array([system.bobs[0].c_d] * 2 if spherical else [b.c_d for b in system.bobs])
    Mm = _mass_matrix(system, q).real
    # zero linear momentum: the V rows of Mm u vanish
    V = -np.linalg.solve(Mm[0:3, 0:3], Mm[0:3, 3:] @ np.concatenate([w, qd]))
    u = np.concatenate([V, w, qd])
    step = 1e-30
    dM = [(_mass_matrix(system, q + 1j * step * np.eye(nq)[a]).imag / step) for a in range(nq)]
    Mdot = sum(qd[a] * dM[a] for a in range(nq))
    dTdq = np.array([0.5 * u @ dM[a] @ u for a in range(nq)])
    p = Mm @ u
    pV, pw = p[0:3], p[3:6]
    F = np.concatenate([-np.cross(w, pV), -np.cross(w, pw) - np.cross(V, pV), dTdq - k * q - c * qd])
    ud = np.linalg.solve(Mm, F - Mdot @ u)
    T = 0.5 * u @ Mm @ u
    return ud[3:], pw, T + 0.5 * np.sum(k * q**2)


@pytest.mark.parametrize("which", ["spherical", "plane"])
def test_rhs_agrees_with_the_two_body_lagrangian(which):
    rng = np.random.default_rng(11)
    sc = set_R() if which == "spherical" else random_plane(c_d=2.5)
    model = physics.get_model(sc.system, "full")
    system = pendulum_system(sc)
    p = model.pack(sc)
    nq = 2 if which == "spherical" else 3
    for _ in range(20):
        q = rng.uniform(-1.2, 1.2, nq)
        y = np.concatenate([rng.normal(0, 1, 3), q, rng.normal(0, 2, nq), [1.0, 0.0, 0.0, 0.0], [0.0]]
                           + ([[0.0]] if which == "spherical" else []))  # the spherical pendulum's chart 0
        ref, H_ref, E_ref = lagrangian_accelerations(system, y)
        f = model.rhs(0.0, y, p)
        got = np.concatenate([f[0:3], f[3 + nq:3 + 2 * nq]])
        assert np.max(np.abs(got - ref)) <= RHS_TOL * max(1.0, np.max(np.abs(ref)))
        assert np.array_equal(f[3:3 + nq], y[3 + nq:3 + 2 * nq])
        assert np.allclose(kernel.momentum(y, p), H_ref, rtol=0, atol=1e-12 * np.linalg.norm(H_ref))
        assert kernel.energy(y, p) == pytest.approx(E_ref, rel=1e-13)


# ---- reference numbers of docs/models.md B.6 and B.7 ------------------------------------------------------

@pytest.mark.parametrize("theta0, rate", [(1 * deg, 0.1261), (10 * deg, 0.1116)])
def test_set_R_nutation_decay_rate_matches_B6(theta0, rate):
    tr = physics.simulate(set_R(theta0, t_end=80.0, samples=1601))
    assert decay_rate(tr.t, tr.theta) == pytest.approx(rate, rel=RATE_TOL)


@pytest.mark.parametrize("c_d, t_end, peak, tol", [(8.0, 80.0, 11.6, 0.05), (0.0, 400.0, 27.0, 0.5)],
                         ids=["resonant", "undamped"])
def test_set_R_pendulum_swing_peaks_match_B10(c_d, t_end, peak, tol):
    """docs/models.md B.10: at 10 deg on set R the swings peak at 11.6 deg (resonant) and 27 deg (undamped)."""
    tr = physics.simulate(set_R(10 * deg, c_d=c_d, t_end=t_end, samples=int(20 * t_end) + 1))
    cone = np.arccos(np.cos(tr.internal["alpha"]) * np.cos(tr.internal["beta"]))  # arm angle from e3
    assert np.max(cone) == pytest.approx(peak * deg, abs=tol * deg)


@pytest.mark.parametrize("k, t_end, tau", [(0.0, 40.0, 4.97), (10.0, 300.0, 48.4)], ids=["resonant", "detuned"])
def test_in_plane_pendulums_decay_time_matches_B7(k, t_end, tau):
    tr = physics.simulate(taylor("in_plane", k=k, t_end=t_end, samples=int(20 * t_end) + 1))
    assert 1.0 / decay_rate(tr.t, tr.theta) == pytest.approx(tau, rel=RATE_TOL)


def test_meridian_pendulums_on_the_axis_barely_damp_B7():
    tr = physics.simulate(taylor("meridian_axis", R=0.0, t_end=400.0, samples=401))
    assert abs(tr.theta[-1] - 9.30 * deg) <= ANGLE_TOL


# ---- the gimbal singularity -----------------------------------------------------------------------

def gimbal_scenario(t_end: float = 100.0) -> physics.Scenario:
    """Set R turned about the transverse axis y (nutation angle ~90 deg) with a soft, undamped
    pendulum: the pivot is below O (h = -0.7), so the bob at rest is an unstable equilibrium of that
    rotation, and the slightest out-of-plane rate (1e-5 rad/s) sets it swinging in the x-z plane
    through beta = 90 deg, where the Cardan angles fail."""
    return set_R(c_d=0.0, k=0.5, omega=[1e-5, 1.0, 1e-5], t_end=t_end, samples=1001)


def test_gimbal_singularity_stops_the_run_cleanly():
    with pytest.raises(physics.IntegrationFault) as err:
        physics.simulate(gimbal_scenario())
    fault = err.value
    assert "gimbal singularity" in str(fault) and f"t = {fault.t:.17g}" in str(fault)
    assert 1.0 < fault.t < 100.0
    # up to just before the fault the run is finite, with beta closing in on 90 deg
    tr = physics.simulate(gimbal_scenario(t_end=fault.t - 0.05))
    assert np.all(np.isfinite(tr.table()))
    assert np.max(np.abs(tr.internal["beta"])) > 80 * deg


# ---- bad input --------------------------------------------------------------------------------------

def _spherical_dict(**pend):
    d = set_R().to_dict()
    d["pendulum"].update(pend)
    return d


def _plane_dict(**pend):
    d = {"body": {"A": 100.0, "C": 150.0, "M": 505.0},
         "plane_pendulum": [{"m": 2.0, "l": 1.0, "k": 0.0, "c_d": 2.0, "hinge": [1.0, 0.0, 0.5],
                             "axis": [0.0, 0.0, 1.0], "arm": [1.0, 0.0, 0.0]}],
         "initial": {"omega": [0.1, 0.0, 2.0]}, "run": {"t_end": 10.0}}
    d["plane_pendulum"][0].update(pend)
    return d


BAD = [
    (_spherical_dict(l=0.0), "pendulum.l"),
    (_spherical_dict(l=-1.0), "pendulum.l"),
    (_spherical_dict(m=0.0), "pendulum.m"),
    (_spherical_dict(m=-5.0), "pendulum.m"),
    (_spherical_dict(m=600.0), "pendulum.m"),
    (_spherical_dict(k=-1.0), "pendulum.k"),
    (_spherical_dict(k="soft"), "pendulum.k"),
    (_spherical_dict(c_d=-0.1), "pendulum.c_d"),
    (_spherical_dict(h=math.inf), "pendulum.h"),
    (_spherical_dict(l=math.nan), "pendulum.l"),
    (_spherical_dict(k=math.inf), "pendulum.k"),
    (_plane_dict(l=0.0), "plane_pendulum[0].l"),
    (_plane_dict(m=-2.0), "plane_pendulum[0].m"),
    (_plane_dict(k=-3.0), "plane_pendulum[0].k"),
    (_plane_dict(c_d=-2.0), "plane_pendulum[0].c_d"),
    (_plane_dict(axis=[0.0, 0.0, 0.0]), "plane_pendulum[0].axis"),
    (_plane_dict(arm=[1.0, 0.0, 0.1]), "plane_pendulum[0].arm"),
    (_plane_dict(hinge=[1.0, math.nan, 0.5]), "plane_pendulum[0].hinge[1]"),
    (_plane_dict(c_d=math.inf), "plane_pendulum[0].c_d"),
]


@pytest.mark.parametrize("data, key", BAD, ids=[f"{k}-{i}" for i, (_, k) in enumerate(BAD)])
def test_bad_pendulum_input_names_the_key(data, key):
    with pytest.raises(physics.ScenarioError) as err:
        physics.Scenario.from_dict(data)
    assert err.value.key == key
    assert str(err.value).startswith(key)
