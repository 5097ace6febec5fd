"""The project's full model (docs/models.md A.2) against an independent engine: MuJoCo's multibody
model of the same carrier and point mass (physics/reference/mujoco_moving_mass.py, checked on its own in
tests/test_mujoco_engine.py). MuJoCo's RK4 step is chosen so that halving it moves MuJoCo's own
theta by less than MUJOCO_SELF_TOL; the finer of the two runs is the reference.
"""

import math

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

import physics  # noqa: E402
from physics.reference import mujoco_moving_mass as mm  # noqa: E402

ANGLE_TOL = 1e-7  # rad
MUJOCO_SELF_TOL = 1e-9  # rad, theta change when MuJoCo's step is halved
REL_TOL = 1e-9  # relative, for |K| and E
LENGTH_TOL = 1e-8  # m, mass displacement u (|u| ~ 5e-3 m here)
RATE_TOL = 1e-6  # rad/s, body angular velocity (carries the precession phase error)
ATTITUDE_TOL = 1e-6  # quaternion components

CASES = {
    # docs/models.md A.7 (a), eps = 0.1, mass released at rest at O1; the nutation grows
    "prolate_rest": dict(
        A=1.0,
        B=1.0,
        C=0.5,
        M=1.0,
        m=0.1,
        rho=1.5,
        Omega=10.0,
        chi=10.0,
        theta0=0.3,
        mass_state="rest",
        t_end=628.0,
        dt=0.01,
    ),
    # triaxial and oblate (K nearer the major axis e3), mass on its forced motion; the nutation decays
    "oblate_triaxial_quasistatic": dict(
        A=1.0,
        B=1.1,
        C=1.4,
        M=1.0,
        m=0.1,
        rho=1.5,
        Omega=10.0,
        chi=5.0,
        theta0=0.6,
        mass_state="quasistatic",
        t_end=300.0,
        dt=0.01,
    ),
}


def scenario(c, times):
    J = np.array([c["A"], c["B"], c["C"]])
    G0 = 1.0
    omega = G0 * np.array([math.sin(c["theta0"]), 0.0, math.cos(c["theta0"])]) / J
    return physics.Scenario.from_dict(
        {
            "body": {"A": c["A"], "B": c["B"], "C": c["C"], "M": c["M"]},
            "mass": {"m": c["m"], "rho": c["rho"], "Omega": c["Omega"], "chi": c["chi"]},
            "initial": {"omega": [float(x) for x in omega], "mass_state": c["mass_state"]},
            "run": {"fidelity": "full", "t_end": c["t_end"], "t_eval": [float(t) for t in times], "rtol": 1e-12},
        }
    ), omega


@pytest.mark.slow
@pytest.mark.parametrize("name", CASES)
def test_full_model_agrees_with_mujoco(name):
    c = CASES[name]
    t = np.linspace(0.0, c["t_end"], int(round(c["t_end"])) + 1)  # every second
    sc, omega0 = scenario(c, t)
    tr = physics.simulate(sc)
    assert np.array_equal(tr.t, t)
    # MuJoCo starts from the project's own initial mass state (rest, or the forced motion)
    u0 = [tr.internal[k][0] for k in ("ux", "uy", "uz")]
    v0 = [tr.internal[k][0] for k in ("vx", "vy", "vz")]
    args = [c[k] for k in ("A", "B", "C", "M", "m", "rho", "Omega", "chi")]
    coarse = mm.run(*args, omega0, t, c["dt"], u0=u0, v0=v0)
    ref = mm.run(*args, omega0, t, c["dt"] / 2, u0=u0, v0=v0)
    assert np.abs(coarse["theta"] - ref["theta"]).max() < MUJOCO_SELF_TOL

    assert np.abs(tr.theta - ref["theta"]).max() <= ANGLE_TOL
    K_ref = np.linalg.norm(ref["K_world"], axis=1)
    np.testing.assert_allclose(tr.K, K_ref, rtol=REL_TOL, atol=0)
    np.testing.assert_allclose(tr.E, ref["E"], rtol=REL_TOL, atol=0)
    u = np.column_stack([tr.internal[k] for k in ("ux", "uy", "uz")])
    np.testing.assert_allclose(u, ref["u"], rtol=0, atol=LENGTH_TOL)
    np.testing.assert_allclose(tr.omega, ref["omega_body"], rtol=0, atol=RATE_TOL)
    np.testing.assert_allclose(tr.quat, ref["quat"], rtol=0, atol=ATTITUDE_TOL)
    # the comparison is not vacuous: theta moves by far more than the tolerance
    assert np.ptp(ref["theta"]) > 1e4 * ANGLE_TOL
