"""The MuJoCo model of physics/reference/mujoco_moving_mass.py on its own: the conventions it relies on, its
conservation laws, a torque-free limit, and the order of MuJoCo's RK4. It is trusted as a
cross-check of the project's full model (tests/test_mujoco_agreement.py) only because these pass.
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

mujoco = pytest.importorskip("mujoco")

from physics.reference import mujoco_moving_mass as mm  # noqa: E402

# Prolate body of docs/models.md A.7 (a), eps = 0.1; one precession period is 2 pi A / G0 = 2 pi s.
A, B, C, M, m, rho, Omega, chi = 1.0, 1.0, 0.5, 1.0, 0.1, 1.5, 10.0, 10.0
J = np.array([A, B, C])
THETA0 = 0.3  # rad
OMEGA0 = np.array([math.sin(THETA0), 0.0, math.cos(THETA0)]) / J  # G0 = |J* w| = 1

K_REL_TOL = 1e-10  # relative drift of the world K vector
E_REL_TOL = 1e-9  # relative drift of the energy when nothing dissipates
COM_TOL = 1e-7  # m, system COM off the origin (rho = 1.5 m)
RATE_TOL = 1e-7  # rad/s
ROUNDOFF = 1e-12  # what is left when two runs should be the same map


def random_state(model, data, seed=1):
    """A state with the mass displaced and moving, a random attitude and a drifting COM, so that
    a wrong frame or a wrong reference point would show."""
    rng = np.random.default_rng(seed)
    mm.initial_state(model, data, M, m, rho, rng.normal(size=3), u0=0.05 * rng.normal(size=3), v0=rng.normal(size=3))
    q = rng.normal(size=4)
    data.qpos[3:7] = q / np.linalg.norm(q)
    data.qpos[0:3] += rng.normal(size=3)
    data.qvel[0:3] += rng.normal(size=3)
    mujoco.mj_forward(model, data)
    mujoco.mj_subtreeVel(model, data)


def body_velocity(model, data, body):
    """(angular, linear) world-frame velocity of a body at its COM, from MuJoCo's own kinematics."""
    v = np.zeros(6)
    mujoco.mj_objectVelocity(model, data, mujoco.mjtObj.mjOBJ_BODY, body, v, 0)
    return v[:3], v[3:]


@pytest.fixture(scope="module")
def model_data():
    model = mujoco.MjModel.from_xml_string(mm.build_model_xml(A, 0.8, C, M, m, rho, Omega, chi))
    return model, mujoco.MjData(model)


# ---- conventions -------------------------------------------------------------------------------


def test_model_is_the_one_asked_for(model_data):
    model, _ = model_data
    np.testing.assert_allclose(model.body_mass[1:], [M - m, m], rtol=1e-15)
    Jb = mm.carrier_inertia(A, 0.8, C, M, m, rho)
    np.testing.assert_allclose(model.body_inertia[1] + model.body_inertia[2], Jb, rtol=1e-14)
    np.testing.assert_allclose(model.jnt_stiffness[1:], m * Omega**2, rtol=1e-15)
    np.testing.assert_allclose(model.dof_damping[6:], m * chi, rtol=1e-15)
    np.testing.assert_array_equal(model.dof_damping[:6], 0.0)
    np.testing.assert_array_equal(model.opt.gravity, 0.0)
    # frozen system about its COM: Jb + carrier and mass offsets = J* (docs/models.md A.2)
    zc, d0 = model.body_pos[1][2], model.body_pos[2][2]
    frozen = Jb + ((M - m) * zc**2 + m * (zc + d0) ** 2) * np.array([1.0, 1.0, 0.0])
    np.testing.assert_allclose(frozen, [A, 0.8, C], rtol=1e-14)
    assert abs((M - m) * zc + m * (zc + d0)) < 1e-15


def test_free_joint_angular_velocity_is_in_body_components(model_data):
    model, data = model_data
    random_state(model, data)
    R = data.xmat[1].reshape(3, 3)
    w_world, v_world = body_velocity(model, data, 1)
    np.testing.assert_allclose(R @ data.qvel[3:6], w_world, rtol=0, atol=1e-14)
    np.testing.assert_allclose(data.cvel[1][:3], w_world, rtol=0, atol=1e-14)
    assert np.abs(data.qvel[3:6] - w_world).max() > 0.1  # the attitude is far from the identity
    # the linear part is the world velocity of the carrier frame origin, which is its COM
    np.testing.assert_allclose(data.qvel[0:3], v_world, rtol=0, atol=1e-14)


def test_subtree_angmom_is_K_about_the_system_com(model_data):
    model, data = model_data
    random_state(model, data, seed=2)
    R = data.xmat[1].reshape(3, 3)
    w = R @ data.qvel[3:6]
    x = [data.xipos[b] for b in (1, 2)]
    v = [body_velocity(model, data, b)[1] for b in (1, 2)]
    masses = model.body_mass[1:]
    com = (masses[0] * x[0] + masses[1] * x[1]) / M
    vcom = (masses[0] * v[0] + masses[1] * v[1]) / M
    inertia = R @ np.diag(model.body_inertia[1] + model.body_inertia[2]) @ R.T  # both turn with the carrier
    K = inertia @ w + sum(mk * np.cross(xk - com, vk - vcom) for mk, xk, vk in zip(masses, x, v, strict=True))
    about_origin = inertia @ w + sum(mk * np.cross(xk, vk) for mk, xk, vk in zip(masses, x, v, strict=True))
    np.testing.assert_allclose(data.subtree_com[1], com, rtol=0, atol=1e-14)
    np.testing.assert_allclose(data.subtree_angmom[1], K, rtol=0, atol=1e-13)
    assert np.abs(about_origin - K).max() > 0.1  # the two reference points are told apart


def test_energy_needs_the_flag_and_includes_the_spring(model_data):
    model, data = model_data
    random_state(model, data, seed=3)
    R = data.xmat[1].reshape(3, 3)
    w = R @ data.qvel[3:6]
    inertia = model.body_inertia[1] + model.body_inertia[2]
    kinetic = 0.5 * (R.T @ w) @ (inertia * (R.T @ w))
    kinetic += sum(
        0.5 * model.body_mass[b] * body_velocity(model, data, b)[1] @ body_velocity(model, data, b)[1] for b in (1, 2)
    )
    spring = 0.5 * m * Omega**2 * data.qpos[7:10] @ data.qpos[7:10]
    assert data.energy[0] == pytest.approx(spring, rel=1e-14)
    assert data.energy[1] == pytest.approx(kinetic, rel=1e-14)
    flagless = mujoco.MjModel.from_xml_string(
        mm.build_model_xml(A, 0.8, C, M, m, rho, Omega, chi).replace('energy="enable" ', "")
    )
    d2 = mujoco.MjData(flagless)
    d2.qpos[:], d2.qvel[:] = data.qpos, data.qvel
    mujoco.mj_forward(flagless, d2)
    np.testing.assert_array_equal(d2.energy, 0.0)


def test_initial_state_has_zero_momentum_and_com_at_origin(model_data):
    model, data = model_data
    for u0, v0 in ((None, None), ([0.01, -0.02, 0.03], [0.3, 0.1, -0.2])):
        mm.initial_state(model, data, M, m, rho, [0.4, -0.3, 1.1], u0=u0, v0=v0)
        mujoco.mj_subtreeVel(model, data)
        np.testing.assert_allclose(data.subtree_com[1], 0.0, rtol=0, atol=1e-16)
        np.testing.assert_allclose(data.subtree_linvel[1], 0.0, rtol=0, atol=1e-16)
    # mass at rest at O1: the carrier COM turns rigidly with the body about O
    mm.initial_state(model, data, M, m, rho, [0.4, -0.3, 1.1])
    mujoco.mj_subtreeVel(model, data)
    np.testing.assert_allclose(data.qvel[0:3], np.cross([0.4, -0.3, 1.1], data.qpos[0:3]), rtol=1e-15)
    np.testing.assert_allclose(data.subtree_angmom[1], [A, 0.8, C] * np.array([0.4, -0.3, 1.1]), rtol=1e-14)


def test_point_inertia_does_not_matter():
    t = np.arange(0.0, 60.0 + 1e-9, 1.0)
    runs = [mm.run(A, B, C, M, m, rho, Omega, chi, OMEGA0, t, 0.02, point_inertia=pi) for pi in (1e-12, 1e-6)]
    # compensated in Jb, so exactly the same system; uncompensated it would move theta by
    # 0.28 rad per kg m^2 of point inertia (measured), 3e-13 rad at 1e-12
    assert np.abs(runs[0]["theta"] - runs[1]["theta"]).max() < ROUNDOFF


def test_output_spacing_must_be_whole_steps():
    with pytest.raises(ValueError, match="whole number"):
        mm.run(A, B, C, M, m, rho, Omega, chi, OMEGA0, [0.0, 0.5], 0.08)


# ---- conservation (a), (b) -------------------------------------------------------------------


@pytest.fixture(scope="module")
def damped_run():
    t = np.linspace(0.0, 628.0, 6281)  # every 0.1 s, about 100 revolutions
    return mm.run(A, B, C, M, m, rho, Omega, chi, OMEGA0, t, 0.005)


def test_damped_K_is_constant_and_energy_decreases(damped_run):
    r = damped_run
    K0 = r["K_world"][0]
    np.testing.assert_allclose(K0, J * OMEGA0, rtol=1e-14)
    assert np.abs(r["K_world"] - K0).max() / np.linalg.norm(K0) < K_REL_TOL
    dE = np.diff(r["E"])
    assert np.all(dE < 0)
    assert r["E"][0] - r["E"][-1] > 1e-2  # it does dissipate: theta drifts, the mass rings down
    assert r["theta"][-1] - THETA0 > 0.03  # prolate: the nutation grows (Chernousko)


def test_undamped_energy_is_constant():
    t = np.linspace(0.0, 628.0, 629)
    r = mm.run(A, B, C, M, m, rho, Omega, 0.0, OMEGA0, t, 0.0025)
    assert np.abs(r["E"] / r["E"][0] - 1).max() < E_REL_TOL
    assert np.abs(r["K_world"] - r["K_world"][0]).max() / np.linalg.norm(r["K_world"][0]) < K_REL_TOL
    assert np.abs(r["u"]).max() > 1e-3  # the mass does move


def test_com_stays_at_origin(damped_run):
    assert np.abs(damped_run["com"]).max() < COM_TOL
    # MuJoCo integrates the carrier's world position, so the COM drifts by RK4's own error, of
    # fourth order; a wrong initial velocity would drift linearly whatever the step
    t = np.arange(0.0, 100.0 + 1e-9, 10.0)
    drift = [np.abs(mm.run(A, B, C, M, m, rho, Omega, chi, OMEGA0, t, dt)["com"]).max() for dt in (0.04, 0.02)]
    assert drift[0] / drift[1] > 12


# ---- torque-free limit (c) ------------------------------------------------------------------


def test_tiny_mass_follows_euler_equations():
    Jt = np.array([1.0, 0.8, 0.5])  # triaxial, so all three Euler equations are exercised
    w0 = np.array([0.3, 0.5, 1.2])
    t = np.arange(0.0, 60.0 + 1e-9, 0.5)
    sol = solve_ivp(
        lambda _, w: -np.cross(w, Jt * w) / Jt, (0.0, t[-1]), w0, t_eval=t, method="DOP853", rtol=1e-12, atol=1e-14
    )
    r = mm.run(*Jt, M, 1e-9, rho, Omega, chi, w0, t, 0.005)
    err = np.abs(r["omega_body"] - sol.y.T).max()
    assert err < RATE_TOL
    assert np.abs(sol.y.T - w0).max() > 0.1  # the body does tumble


# ---- RK4 order (d) -----------------------------------------------------------------------------


def test_rk4_order_of_theta():
    # triaxial: for a symmetric body the dt^4 term of the theta error cancels (measured order 5)
    Jt = np.array([1.0, 0.8, 0.5])
    w0 = np.array([math.sin(THETA0), 0.0, math.cos(THETA0)]) / Jt
    t = np.arange(0.0, 60.0 + 1e-9, 0.8)
    dts = np.array([0.08, 0.04, 0.02])
    ref = mm.run(*Jt, M, m, rho, Omega, chi, w0, t, dts[-1] / 8)["theta"]
    errs = [np.abs(mm.run(*Jt, M, m, rho, Omega, chi, w0, t, dt)["theta"] - ref).max() for dt in dts]
    order = np.polyfit(np.log(dts), np.log(errs), 1)[0]
    assert 3.6 <= order <= 4.4, (errs, order)
