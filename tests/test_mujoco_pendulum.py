"""The project's full spherical-pendulum model (docs/models.md B.2) against an independent engine:
MuJoCo's multibody model of the same free carrier and Cardan-hung bob (physics/reference/mujoco_pendulum.py),
with the carrier's translation explicit. MuJoCo's RK4 step is chosen so that halving it moves
MuJoCo's own theta by less than MUJOCO_SELF_TOL; the finer of the two runs is the reference.
"""

import math

import numpy as np
import pytest

mujoco = pytest.importorskip("mujoco")

from test_pendulum_full import set_R  # noqa: E402

import physics  # noqa: E402
from physics.reference import mujoco_pendulum as mp  # noqa: E402
from physics.systems.pendulum.geometry import pendulum_system  # noqa: E402

ANGLE_TOL = 1e-7  # rad, theta project vs MuJoCo
MUJOCO_SELF_TOL = 1e-9  # rad, theta change when MuJoCo's step is halved
REL_TOL = 1e-9  # relative, for |H| and E
GIMBAL_TOL = 1e-8  # rad, alpha and beta (they swing to ~0.2 rad)
POSITION_TOL = 1e-12  # m, the system COM stays at the origin
DT = 1e-3  # s, MuJoCo's RK4 step (the half step is the reference)
T_END = 40.0  # s: theta falls from 10 deg to about 0.2 deg on set R


def test_mujoco_joint_composition_is_cardan():
    """The bob's body frame is R_x(alpha) R_y(beta): the bob sits at pivot + l e (docs/models.md B.1)."""
    sc = set_R()
    s = pendulum_system(sc)
    b = s.bobs[0]
    model = mujoco.MjModel.from_xml_string(mp.build_model_xml(s.M0, s.I_c, b.m, b.l, b.k, b.c_d, b.pivot))
    data = mujoco.MjData(model)
    for a, be in ((0.3, -0.4), (-1.1, 0.7), (2.0, 1.2)):
        mp.initial_state(model, data, s.M0, b.m, b.l, b.pivot, [0.1, 0.2, 2.0], alpha0=a, beta0=be)
        o = mp.observe(model, data)
        rel = o["carrier_mat"].T @ (o["bob"] - o["carrier_pos"])
        assert np.allclose(rel, b.pivot + b.l * mp.arm(a, be), rtol=0, atol=1e-14)
        assert np.allclose(o["com"], 0.0, atol=1e-14)


def test_full_model_agrees_with_mujoco_on_set_R():
    """Set R (docs/models.md B.8), 10 deg nutation, resonant spring and pivot damper c_d = 8."""
    sc = set_R(10 * math.pi / 180, t_end=T_END, samples=int(T_END / 0.1) + 1)
    tr = physics.simulate(sc)
    s = pendulum_system(sc)
    b = s.bobs[0]
    coarse = mp.run(s.M0, s.I_c, b.m, b.l, b.k, b.c_d, b.pivot, tr.omega[0], tr.t, DT)
    fine = mp.run(s.M0, s.I_c, b.m, b.l, b.k, b.c_d, b.pivot, tr.omega[0], tr.t, DT / 2)
    assert np.max(np.abs(fine["theta"] - coarse["theta"])) < MUJOCO_SELF_TOL
    assert tr.theta[0] == pytest.approx(10 * math.pi / 180, rel=1e-12)
    assert tr.theta[-1] < 0.05 * tr.theta[0]  # the damper has done its work
    assert np.max(np.abs(tr.theta - fine["theta"])) <= ANGLE_TOL
    assert np.max(np.abs(tr.K - np.linalg.norm(fine["H_world"], axis=1))) <= REL_TOL * tr.K[0]
    assert np.max(np.abs(tr.E - fine["E"])) <= REL_TOL * tr.E[0]
    assert np.max(np.abs(tr.internal["alpha"] - fine["alpha"])) <= GIMBAL_TOL
    assert np.max(np.abs(tr.internal["beta"] - fine["beta"])) <= GIMBAL_TOL
    assert np.max(np.abs(fine["com"])) <= POSITION_TOL
