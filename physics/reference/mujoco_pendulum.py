"""An independent MuJoCo model of docs/models.md Part B.2 for the spherical pendulum: a free carrier
carrying a point bob on a two-gimbal (Cardan) pivot. A reference, not product: it cross-checks the project's full
model with another engine, which keeps the carrier's translation explicit (no reduced mass).

Geometry (body frame = carrier frame, origin at the carrier COM G_B):
- the carrier: mass M0 and inertia I_c (3x3, about G_B) from ``physics.systems.pendulum.geometry.pendulum_system``;
- the bob's body sits at the pivot and hangs from two hinge joints at the pivot: the outer one about
  the carrier's x (alpha), the inner one about the gimbal's y (beta). MuJoCo composes the joints of
  one body in order, each about its axis turned by the joints before it, so the body frame is
  R_x(alpha) R_y(beta) and the bob, at (0, 0, l) in it, is at pivot + l e with
  e = R_x(alpha) R_y(beta) e3 (checked in tests/test_mujoco_pendulum.py). Joint ``stiffness`` k
  (springref 0) and ``damping`` c_d are the spring V = k (alpha^2 + beta^2)/2 and the Rayleigh
  function c_d (alpha'^2 + beta'^2)/2 of B.1; their reactions act on the carrier.
- the bob is a point mass: MuJoCo needs a positive inertia, so it gets the isotropic POINT_INERTIA,
  which is subtracted from the carrier's. An isotropic tensor is the same in every orientation, so
  the frozen system is exact and only the bob's spin relative to the carrier is left unmodelled,
  a relative error of about POINT_INERTIA / (m l^2) ~ 1e-13.

MuJoCo conventions (verified for MuJoCo 4.0.0 in mujoco_moving_mass.py and
tests/test_mujoco_engine.py): free joint qvel = [v, w], v the world velocity of the carrier COM, w in
body components; data.subtree_angmom[1] is the whole system's angular momentum about its COM (world
frame), filled by mj_subtreeVel; data.energy needs the energy flag.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from .mujoco_common import POINT_INERTIA, fmt, momentum_and_nutation, options, sample


def build_model_xml(M0, I_c, m, l, k, c_d, pivot, dt=1e-3, integrator="RK4", point_inertia=POINT_INERTIA) -> str:
    """MJCF of the carrier (free joint, COM at its frame origin) and the bob (two hinges), gravity off."""
    I = np.asarray(I_c, float) - point_inertia * np.eye(3)
    if np.any(np.linalg.eigvalsh(I) <= 0) or M0 <= 0:
        raise ValueError("the carrier must keep a positive mass and inertia")
    f = fmt
    full = " ".join(f(x) for x in (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))
    px, py, pz = (f(x) for x in pivot)
    pi = f(point_inertia)
    return f"""<mujoco model="spherical_pendulum">
  {options(dt, integrator)}
  <worldbody>
    <body name="carrier" pos="0 0 0">
      <freejoint name="carrier"/>
      <inertial pos="0 0 0" mass="{f(M0)}" fullinertia="{full}"/>
      <body name="bob" pos="{px} {py} {pz}">
        <joint name="alpha" type="hinge" axis="1 0 0" stiffness="{f(k)}" damping="{f(c_d)}" springref="0"/>
        <joint name="beta" type="hinge" axis="0 1 0" stiffness="{f(k)}" damping="{f(c_d)}" springref="0"/>
        <inertial pos="0 0 {f(l)}" mass="{f(m)}" diaginertia="{pi} {pi} {pi}"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def arm(alpha, beta):
    """docs/models.md B.1: e = R_x(alpha) R_y(beta) e3."""
    return np.array([math.sin(beta), -math.sin(alpha) * math.cos(beta), math.cos(alpha) * math.cos(beta)])


def initial_state(model, data, M0, m, l, pivot, omega0, alpha0=0.0, beta0=0.0):
    """Identity attitude, bob at rest relative to the carrier at (alpha0, beta0), carrier angular
    velocity omega0 (body components), system COM at the origin with zero total linear momentum:
    the carrier COM at -(m/M) r and moving at -(m/M) w x r, r the bob from G_B, M = M0 + m."""
    M = M0 + m
    r = np.asarray(pivot, float) + l * arm(alpha0, beta0)
    w = np.asarray(omega0, float)
    mujoco.mj_resetData(model, data)
    data.qpos[0:3] = -(m / M) * r
    data.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
    data.qpos[7:9] = (alpha0, beta0)
    data.qvel[0:3] = -(m / M) * np.cross(w, r)
    data.qvel[3:6] = w
    data.qvel[6:8] = 0.0
    mujoco.mj_forward(model, data)


def observe(model, data) -> dict:
    """Quantities of the current state (calls mj_forward and mj_subtreeVel)."""
    mujoco.mj_forward(model, data)
    H, theta = momentum_and_nutation(model, data)
    return {
        "theta": theta,
        "H_world": H,
        "E": float(data.energy[0] + data.energy[1]),
        "omega_body": data.qvel[3:6].copy(),
        "alpha": float(data.qpos[7]),
        "beta": float(data.qpos[8]),
        "com": data.subtree_com[1].copy(),
        "bob": data.xipos[2].copy(),
        "carrier_pos": data.xpos[1].copy(),
        "carrier_mat": data.xmat[1].reshape(3, 3).copy(),
    }


def run(M0, I_c, m, l, k, c_d, pivot, omega0, t_out, dt, integrator="RK4", point_inertia=POINT_INERTIA) -> dict:
    """Step the MuJoCo model from t = 0 and sample it at ``t_out`` (s, increasing, >= 0; every gap
    a whole number of steps dt). Returns arrays over t_out (theta rad, H_world, E, omega_body,
    alpha, beta, com, ...) and ``steps``."""
    model = mujoco.MjModel.from_xml_string(build_model_xml(M0, I_c, m, l, k, c_d, pivot, dt, integrator,
                                                           point_inertia))
    data = mujoco.MjData(model)
    initial_state(model, data, M0, m, l, pivot, omega0)
    return sample(model, data, t_out, dt, observe)
