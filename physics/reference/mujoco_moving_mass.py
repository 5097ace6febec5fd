"""An independent MuJoCo model of docs/models.md Part A.2: a free rigid body carrying a point mass on an
isotropic spring-damper. A reference, not product: it cross-checks the project's full model with another engine.

Geometry (body frame = carrier frame, origin at the carrier COM, axes principal):
- the carrier: mass M0 = M - m at its own COM, inertia Jb = J* - (m rho^2/(1-eta)) diag(1,1,0);
- the point mass: mass m, at O1 + u, where O1 = d0 = rho/(1-eta) e3 from the carrier COM, i.e.
  rho e3 from the system COM O; u is held by three slide joints along the carrier's x, y, z with
  stiffness c = m Omega^2 and joint-space damping delta = m chi. Joint damping is a force
  -delta u' in the relative velocity, the Rayleigh function of docs/models.md A.2; its reaction acts on
  the carrier, so it cannot change the total angular momentum.

Conventions checked in MuJoCo 4.0.0 (tests/test_mujoco_engine.py tests each one):
- free joint qvel = [v, w]: v is the world-frame linear velocity of the body frame origin (here
  the carrier COM); w is the angular velocity in BODY (local) components, the papers' w.
- data.subtree_angmom[body] is the world-frame angular momentum of that body's subtree about the
  subtree COM (mjdata.h: "angular momentum about subtree com"); for the carrier's subtree that is
  the whole system about the system COM, i.e. K. It is filled by mj_subtreeVel, not mj_forward.
- data.energy = (potential, kinetic) is computed by mj_forward only with the energy flag
  (<flag energy="enable"/>, mjENBL_ENERGY); the potential includes 1/2 c |u|^2 (springref = 0).
"""

from __future__ import annotations

import mujoco
import numpy as np

from .mujoco_common import POINT_INERTIA, fmt, momentum_and_nutation, options, sample


def carrier_inertia(A, B, C, M, m, rho):
    """Jb, the carrier's central principal moments (kg m^2) from the frozen-system J* (docs/models.md A.2)."""
    eta = m / M
    s = m * rho**2 / (1.0 - eta)
    return np.array([A - s, B - s, C])


def build_model_xml(A, B, C, M, m, rho, Omega, chi, dt=1e-3, integrator="RK4", point_inertia=POINT_INERTIA) -> str:
    """MJCF of the carrier (free joint) and the point mass (three slide joints), gravity off.

    The bodies start with the system COM at the world origin: the carrier frame (its COM) at
    -(m rho/M0) e3, the point mass at O1 = rho e3. The point mass's child body only slides, so it
    turns with the carrier and its rotational inertia ``point_inertia`` adds to the carrier's
    exactly; it is subtracted from Jb, so the model is exact for any value MuJoCo accepts.
    """
    M0 = M - m
    Jb = carrier_inertia(A, B, C, M, m, rho) - point_inertia
    if np.any(Jb <= 0) or M0 <= 0:
        raise ValueError("the carrier must keep a positive mass and inertia (m, rho too large for J*)")
    c = m * Omega**2
    delta = m * chi
    zc = -m * rho / M0  # carrier COM on the axis, so that M0 zc + m rho = 0
    d0 = rho * M / M0  # = rho/(1-eta), carrier COM -> O1
    f = fmt
    joint = '<joint name="u{0}" type="slide" axis="{1}" stiffness="{2}" damping="{3}" springref="0"/>'
    joints = "\n        ".join(
        joint.format(n, ax, f(c), f(delta)) for n, ax in (("x", "1 0 0"), ("y", "0 1 0"), ("z", "0 0 1"))
    )
    pi = f(point_inertia)
    return f"""<mujoco model="moving_mass">
  {options(dt, integrator)}
  <worldbody>
    <body name="carrier" pos="0 0 {f(zc)}">
      <freejoint name="carrier"/>
      <inertial pos="0 0 0" mass="{f(M0)}" diaginertia="{f(Jb[0])} {f(Jb[1])} {f(Jb[2])}"/>
      <body name="mass" pos="0 0 {f(d0)}">
        {joints}
        <inertial pos="0 0 0" mass="{f(m)}" diaginertia="{pi} {pi} {pi}"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def initial_state(model, data, M, m, rho, omega0, u0=None, v0=None):
    """Set qpos, qvel: identity attitude, mass at O1 + u0 moving with u' = v0 relative to the
    carrier, carrier angular velocity omega0 (body components), and zero total linear momentum
    with the system COM at the origin.

    With the mass at d = d0 + u from the carrier COM, moving at w x d + u' relative to it, the
    momentum M0 v_c + m (v_c + w x d + u') = 0 gives v_c = -(m/M)(w x d + u'), and the COM
    condition gives the carrier position -(m/M) d. With u = u' = 0 this is v_c = w x (-(m rho/M0) e3):
    the carrier COM turns rigidly about O together with the mass. The attitude is the identity, so
    body and world components coincide at t = 0.
    """
    M0 = M - m
    u = np.zeros(3) if u0 is None else np.asarray(u0, float)
    v = np.zeros(3) if v0 is None else np.asarray(v0, float)
    w = np.asarray(omega0, float)
    d = np.array([0.0, 0.0, rho * M / M0]) + u
    mujoco.mj_resetData(model, data)
    data.qpos[0:3] = -(m / M) * d
    data.qpos[3:7] = (1.0, 0.0, 0.0, 0.0)
    data.qpos[7:10] = u
    data.qvel[0:3] = -(m / M) * (np.cross(w, d) + v)
    data.qvel[3:6] = w  # free joint: angular velocity in body components
    data.qvel[6:9] = v
    mujoco.mj_forward(model, data)


def observe(model, data) -> dict:
    """Quantities of the current state (calls mj_forward and mj_subtreeVel)."""
    mujoco.mj_forward(model, data)
    K, theta = momentum_and_nutation(model, data)
    return {
        "theta": theta,
        "K_world": K,
        "E": float(data.energy[0] + data.energy[1]),
        "omega_body": data.qvel[3:6].copy(),
        "u": data.qpos[7:10].copy(),
        "com": data.subtree_com[1].copy(),
        "quat": data.qpos[3:7].copy(),
    }


def run(
    A, B, C, M, m, rho, Omega, chi, omega0, t_out, dt, integrator="RK4", u0=None, v0=None, point_inertia=POINT_INERTIA
) -> dict:
    """Step the MuJoCo model from t = 0 and sample it at the times ``t_out`` (s, increasing, >= 0).

    Every gap between output times (and t_out[0] itself) must be a whole number of steps dt.
    Returns arrays over t_out: t (n,), theta (n,) rad, the angle between K and the carrier's e3;
    K_world (n, 3) total angular momentum about the system COM, world frame; E (n,) kinetic plus
    spring energy; omega_body (n, 3) body components; u (n, 3) slide positions (body frame);
    com (n, 3) system COM, world frame; quat (n, 4) carrier attitude, scalar first, body -> world;
    and steps, the number of MuJoCo steps taken.
    """
    model = mujoco.MjModel.from_xml_string(
        build_model_xml(A, B, C, M, m, rho, Omega, chi, dt, integrator, point_inertia)
    )
    data = mujoco.MjData(model)
    initial_state(model, data, M, m, rho, omega0, u0, v0)
    return sample(model, data, t_out, dt, observe)
