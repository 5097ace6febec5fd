"""The viscous wheel damper at the full fidelity: the compiled kernel physics/compiled/wheel.py (docs/models.md C.1).

It starts from the scenario's initial rotation of the frozen system (``initial_G``: the wheel at rest relative to
the body, so K = I w0), the wheel's angle 0, identity attitude and no dissipated work.
"""

from __future__ import annotations

import numpy as np

from physics.compiled import dispatch as kernels
from physics.compiled import wheel as kernel
from physics.core.rotation import IDENTITY, normalize, nutation_angle, rotate
from physics.core.trajectory import Trajectory
from physics.registry import Model, register
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario

STATE = ("wx", "wy", "wz", "phi_w", "Omega_w", "qw", "qx", "qy", "qz", "W_diss")
WHEEL = ("phi_w", "Omega_w")  # the wheel's own entries (System.parts)
Q = STATE.index("qw")


def pack(sc: Scenario) -> np.ndarray:
    """The kernel's parameters: A, B, C, J, c, the unit axis (physics/compiled/wheel.py)."""
    b, w = sc.body, sc.wheel
    return np.array([b.A, b.B, b.C, w.J, w.c, *w.axis])


def initial_state(sc: Scenario, p: np.ndarray) -> np.ndarray:
    w0, _, _ = initial_G(sc)
    return np.concatenate([w0, [0.0, 0.0], IDENTITY, [0.0]])


def observe(t, Y, p, sc) -> Trajectory:
    """theta is the angle between the total K and body e3 (the docs/models.md conventions' nutation angle)."""
    K, E = kernel.observe(np.ascontiguousarray(Y), p)
    internal = {name: Y[:, STATE.index(name)].copy() for name in ("phi_w", "Omega_w", "W_diss")}
    return Trajectory(t=t, theta=nutation_angle(K), K=np.linalg.norm(K, axis=1), E=E, omega=Y[:, 0:3].copy(),
                      quat=normalize(Y[:, Q:Q + 4]), internal=internal)


def invariants(Y, p):
    """Inertial angular momentum (n, 3) and energy (n,)."""
    K, E = kernel.observe(np.ascontiguousarray(Y), p)
    return rotate(Y[:, Q:Q + 4], K), E


def stiff_advice(sc: Scenario) -> str:
    """Why a wheel run is stiff, in its keys: the bearing's relaxation rate c / J against the body's motion."""
    return (f"the bearing (wheel.c / wheel.J = {sc.wheel.c / sc.wheel.J:.3g} 1/s) outpaces the body's motion: lower "
            "wheel.c or raise wheel.J")


FULL = register(Model(
    name="wheel/full", system="wheel", fidelity="full",
    summary="body + wheel in a viscous bearing, exact equations K' + w x K = 0, J (a.w' + Omega_w') = -c Omega_w "
            "(docs/models.md C.1)",
    state=STATE, kernel=kernels.WHEEL_FULL, pack=pack, initial_state=initial_state, observe=observe,
    invariants=invariants, columns=("phi_w", "Omega_w", "W_diss"), stiff_advice=stiff_advice,
))
