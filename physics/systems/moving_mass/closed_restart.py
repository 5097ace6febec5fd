"""The moving mass's closed form, restarted from a running state with its K and attitude kept.

The closed form (closed_state.py, beside this file) has no state: it starts at t = 0 from G0 and theta0 with the
attitude the identity, omega(0) = (G0 sin theta0/A, 0, G0 cos theta0/C) and K inertially along
G0 (sin theta0, 0, cos theta0). To go on from a state at t0 whose body-frame momentum is K_b and whose
attitude is q, we evaluate it from G0 = |K_b|, theta0 = the angle of K_b to e3 at s = t - t0, and map
its solution by two constant rotations: P = Rz(psi) about the symmetry axis (psi the azimuth of K_b in
the body), which turns its omega and its initial K direction onto the present ones, and q (x) p on the
left, which puts the body where it is:

    omega(t) = P omega_cl(s),    quat(t) = q (x) p (x) quat_cl(s) (x) p^-1.

At s = 0 the attitude is q exactly and K is R(q) K_b exactly; for a symmetric body (A = B, which the
averaged theory assumes) P maps the closed-form motion onto a motion of the same body, so the rest is
the closed form's own. The state's K_b is the averaged model's J* omega (``physics.carry``'s proxy for
the closed form), so a full model's state is first carried to the averaged one. ``restart_closed`` is the
closed Model's ``restart`` hook (physics/systems/restart.py dispatches to it).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from physics.core.rotation import normalize, qmul, rotate
from physics.core.trajectory import Trajectory
from physics.registry import Model, get_model
from physics.scenario.scenario import Scenario
from physics.systems.carry import CannotCarry, Carried, carried_layout, carry_state
from physics.systems.restart import ClosedOrigin


def origin_at(scenario: Scenario, K: np.ndarray, q: np.ndarray, t0: float) -> ClosedOrigin:
    """The closed form of ``scenario`` restarted at ``t0`` with inertial momentum ``K`` and attitude ``q``."""
    q = normalize(np.asarray(q, dtype=float))
    q_inv = q * np.array([1.0, -1.0, -1.0, -1.0])
    Kb = rotate(q_inv, np.asarray(K, dtype=float))
    G0 = float(np.linalg.norm(Kb))
    if not G0 > 0:
        raise CannotCarry("the closed form needs a nonzero angular momentum to start from")
    theta0 = math.atan2(math.hypot(Kb[0], Kb[1]), Kb[2])
    psi = math.atan2(Kb[1], Kb[0])
    p = np.array([math.cos(psi / 2), 0.0, 0.0, math.sin(psi / 2)])
    c, s = math.cos(psi), math.sin(psi)
    P = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    initial = replace(scenario.initial, omega=None, G0=G0, theta0=theta0)
    return ClosedOrigin(t0=float(t0), scenario=scenario.replace(initial=initial), q_left=qmul(q, p),
                        q_right=p * np.array([1.0, -1.0, -1.0, -1.0]), P=P)


def restart_closed(old_model: Model, old_p: np.ndarray, old_sc: Scenario, y_old: np.ndarray | None,
                   new_model: Model, new_sc: Scenario, t0: float,
                   last: Trajectory | None = None, K_keep: np.ndarray | None = None) -> tuple[ClosedOrigin, Carried]:
    """The closed form ``new_model`` restarted at ``t0`` from the old state's K and attitude, and the
    carry to the averaged model that gives them (its ``E_before`` is the old state's energy). ``K_keep``:
    the K an old closed form shows (``carry_state``)."""
    averaged = get_model(new_sc.system, "averaged")
    carried = carry_state(old_model, old_p, old_sc, y_old, averaged, new_sc, last=last, K_keep=K_keep)
    attitude = carried_layout(averaged, carried.y, averaged.pack(new_sc))[3:7]
    return origin_at(new_sc, carried.K_after, attitude, t0), carried


__all__ = ["origin_at", "restart_closed"]
