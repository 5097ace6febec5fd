"""The spherical pendulum's averaged solution, restarted from a running state with its K and attitude kept.

The averaged solution (physics/systems/pendulum/averaged.py) has no state: it starts at t = 0 with the attitude the
identity, the bob at rest at its rest position (mode 1's amplitude Ut(0) = 0) and omega(0) = the scenario's
initial omega, so its K starts at J omega(0) (the frozen system's, J = diag(A, B, C)) in the body frame, which at
t = 0 is also the inertial frame. To go on from a state at t0 whose inertial momentum is K and whose attitude is
q, the state is carried to the full model (``physics.carry``), the bob is put at rest (its angles, rates and
Cardan chart as the full model starts them) and omega is solved again so that the full model's K is still K;
the averaged solution is evaluated from that omega at s = t - t0, with its attitude after q:

    omega(t) = omega_avg(s),    quat(t) = q (x) quat_avg(s).

At s = 0 the attitude is q and K is R(q) J omega = K to rounding (the full model's K with the bob at rest is the
frozen system's). The bob's swing at the switch is not kept: the averaged solution cannot start from it, and its
energy shows in the edit's change of E. The spring stays the one in force (a tuned k is resolved from the
scenario, not from the spin now), and the dissipated work goes on from where it was.
``carry_to_pendulum_averaged`` is the averaged Model's ``restart`` hook (physics/systems/restart.py).
"""

from __future__ import annotations

import numpy as np

from physics.core.rotation import IDENTITY
from physics.core.trajectory import Trajectory
from physics.kernels.build import pick
from physics.registry import Model, get_model
from physics.scenario.scenario import Scenario
from physics.systems.carry import OMEGA, QUAT, Carried, carry_state, solve_omega, state_names
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.restart import ClosedOrigin

COUNTERS = ("W_diss",)  # what the averaged solution starts at zero but the run has accumulated


def carry_to_pendulum_averaged(old_model: Model, old_p: np.ndarray, old_sc: Scenario, y_old: np.ndarray | None,
                               new_model: Model, new_sc: Scenario, t0: float,
                               last: Trajectory | None = None,
                               K_keep: np.ndarray | None = None) -> tuple[ClosedOrigin, Carried]:
    """The averaged solution ``new_model`` of ``new_sc`` restarted at ``t0`` from the old state's K and attitude,
    and the carry that gives them (the full model's state with the bob at rest; ``E_before`` is the old state's
    energy; ``K_keep`` the K an old closed form shows, as in ``carry_state``). Raises CannotCarry (no omega
    gives K) or ScenarioError (the averaged solution cannot run) before anything is used."""
    full = get_model(new_sc.system, "full")
    p = np.asarray(full.pack(new_sc), dtype=float)
    carried = carry_state(old_model, old_p, old_sc, y_old, full, new_sc, new_p=p, last=last, K_keep=K_keep)
    y = carried.y.copy()
    names = state_names(full, y.size)
    # the bob at rest as the full model starts it (angles, rates, and its Cardan chart where it has one)
    rest = [i for i, n in enumerate(names) if n not in OMEGA + QUAT + COUNTERS]
    y[rest] = np.asarray(full.initial_state(new_sc, p), dtype=float)[rest]
    y, iterations = solve_omega(full, y, p, carried.K_before)
    K, E = pick(full.invariants)(np.ascontiguousarray(y[None, :]), p)
    K_after, E_after = np.asarray(K[0], dtype=float), float(E[0])
    bob = pendulum_system(new_sc).bobs[0]  # k and c_d as in force now ("resonant" resolved from new_sc's spin)
    restart = new_sc.with_values(**{"initial.omega": [float(w) for w in y[:3]], "pendulum.k": float(bob.k),
                                    "pendulum.c_d": float(bob.c_d)})
    q = y[names.index("qw"):names.index("qz") + 1]
    norm = float(np.linalg.norm(K_after))
    origin = ClosedOrigin(t0=float(t0), scenario=restart, q_left=q.copy(), q_right=IDENTITY, P=np.eye(3),
                          K_dir=K_after / norm if norm > 0 else np.zeros(3),
                          offsets=tuple((n, float(y[names.index(n)])) for n in COUNTERS))
    origin.evaluate(new_model, np.array([float(t0)]))  # a solution that cannot run says so before the switch
    return origin, Carried(y=y, K_before=carried.K_before, K_after=K_after, E_before=carried.E_before,
                           E_after=E_after, iterations=carried.iterations + iterations)


__all__ = ["carry_to_pendulum_averaged"]
