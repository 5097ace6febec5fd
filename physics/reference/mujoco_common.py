"""What the two MuJoCo peers (a moving mass, a spherical pendulum) share: the MJCF options block,
the step schedule that lands exactly on the output times, and the reading of the total angular
momentum and nutation angle. Conventions verified for MuJoCo 4.0.0 in mujoco_moving_mass.py."""

from __future__ import annotations

import math

import mujoco
import numpy as np

POINT_INERTIA = 1e-12  # kg m^2; MuJoCo rejects a moving body with zero inertia
STEP_MATCH = 1e-6  # relative slack allowed when an output spacing must be a whole number of steps
fmt = "{:.17g}".format  # every number at full precision, so the MJCF loses nothing


def options(dt: float, integrator: str) -> str:
    """Compiler and option elements: radians, explicit inertias, no gravity or contact, energy on."""
    return f"""<compiler angle="radian" inertiafromgeom="false" autolimits="true"/>
  <option timestep="{fmt(dt)}" integrator="{integrator}" gravity="0 0 0">
    <flag energy="enable" contact="disable"/>
  </option>"""


def momentum_and_nutation(model, data) -> tuple[np.ndarray, float]:
    """Total angular momentum about the system COM (world frame; subtree_angmom of the carrier,
    filled only by mj_subtreeVel) and its angle to the carrier's e3, rad. Call after mj_forward."""
    mujoco.mj_subtreeVel(model, data)
    K = data.subtree_angmom[1].copy()
    e3 = data.xmat[1].reshape(3, 3)[:, 2]
    return K, math.atan2(np.linalg.norm(np.cross(K, e3)), float(K @ e3))


def sample(model, data, t_out, dt: float, observe) -> dict:
    """Step from t = 0 and collect ``observe(model, data)`` (a dict) at each output time; every gap
    between output times (and t_out[0] itself) must be a whole number of steps dt. Returns arrays
    keyed as observe's dict, plus t and steps."""
    t_out = np.asarray(t_out, float)
    gaps = np.diff(np.concatenate([[0.0], t_out]))
    if np.any(gaps < 0):
        raise ValueError("t_out must be non-negative and increasing")
    nsteps = np.rint(gaps / dt).astype(np.int64)
    if np.any(np.abs(nsteps * dt - gaps) > STEP_MATCH * np.maximum(gaps, dt)):
        raise ValueError(f"every output spacing must be a whole number of steps dt = {dt:g}")
    rows = []
    for n in nsteps:
        if n:
            mujoco.mj_step(model, data, nstep=int(n))
        rows.append(observe(model, data))
    out = {key: np.array([r[key] for r in rows]) for key in rows[0]}
    out["t"] = t_out
    out["steps"] = int(nsteps.sum())
    return out
