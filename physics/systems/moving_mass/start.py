"""How the moving mass starts when a change switches it on in a running state (``System.start_part``).

At rest relative to the body (the carry's default), or, when the scenario asks for ``mass_state =
"quasistatic"``, at its forced (slow-manifold) displacement: the one the averaged theory assumes, so that
switching the mass on (or going from the averaged model to the full one) does not start a fresh wobble.
"""

from __future__ import annotations

import numpy as np

from physics.registry import Model
from physics.scenario.scenario import Scenario
from physics.systems.carry import solve_omega
from physics.systems.moving_mass.models import quasi_static_displacement

PART = "mass"
STATE = ("ux", "uy", "uz", "vx", "vy", "vz")  # the mass's entries in the full model's state
QUASI_STATIC_ITERATIONS = 60  # u depends on omega and omega on u: the rounds contract by about eps (0.44
# measured on the default scene, eps ~ 0.5), so 60 reach QUASI_STATIC_TOL even there
QUASI_STATIC_TOL = 1e-10  # m: far below the quasi-static formula's own O(eps^3) error


def start_part(part: str, model: Model, sc: Scenario, y: np.ndarray, p: np.ndarray, K: np.ndarray,
               idx: list[int]) -> tuple[np.ndarray, int]:
    """``y`` with the mass's entries ``y[idx]`` as it starts, and the Newton iterations spent. Quasi-static: u
    from omega, omega from K, repeated; the last step solves omega exactly, so K is kept however far the
    iteration got."""
    if part != PART or sc.mass is None or sc.initial.mass_state != "quasistatic":
        return y, 0  # at rest, as the carry left it
    total = 0
    for _ in range(QUASI_STATIC_ITERATIONS):
        u, v = quasi_static_displacement(sc, y[:3])
        before = y[idx].copy()
        y[idx] = np.concatenate([u, v])
        y, n = solve_omega(model, y, p, K)
        total += n
        if np.max(np.abs(y[idx] - before)) <= QUASI_STATIC_TOL:
            break
    return y, total
