"""The wheel damper's closed form (linear.py), restarted from a running state with its K and attitude kept.

The closed form has no state: it starts at t = 0 with the attitude the identity, omega(0) the scenario's initial
rotation and the wheel at rest relative to the body, so its K starts at I omega(0) in the body frame, which at
t = 0 is also the inertial frame. Its linear theory starts as well from any state near the spin about e3 (the
wheel turning too): omega = (x, y, n) and Omega_w. So to go on from a state at t0 whose attitude is q, the state
is carried to the full model (``physics.carry``: K, the attitude, the wheel's angle and rate kept, omega solved),
and the closed form is evaluated from that omega and Omega_w at s = t - t0, with its attitude after q:

    omega(t) = omega_cl(s),    quat(t) = q (x) quat_cl(s).

At s = 0 the closed form's state is the carried state itself, so its K (exact at its state, I omega + J Omega_w
a) is R(q)^-1 K to rounding and E is the carried state's: a fidelity switch changes neither, and the bearing's c
enters neither. The wheel's angle and the dissipated work go on from where they were.
``restart_closed`` is the closed Model's ``restart`` hook (physics/systems/restart.py); the Model's ``solve``
(linear.solve_linear) takes the wheel's initial rate.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from physics.core.rotation import IDENTITY
from physics.core.trajectory import Trajectory
from physics.kernels.build import pick
from physics.registry import Model, get_model
from physics.scenario.scenario import Scenario
from physics.systems.carry import Carried, carry_state, state_names
from physics.systems.restart import ClosedOrigin

COUNTERS = ("phi_w", "W_diss")  # what the closed form starts at zero but the run has accumulated


@dataclass(frozen=True)
class WheelOrigin(ClosedOrigin):
    """A ClosedOrigin whose closed form starts with the wheel turning at ``Omega_w0`` (rad/s)."""

    Omega_w0: float = 0.0

    def evaluate(self, model: Model, times: np.ndarray) -> Trajectory:
        return super().evaluate(replace(model, solve=partial(model.solve, Omega_w0=self.Omega_w0)), times)


def restart_closed(old_model: Model, old_p: np.ndarray, old_sc: Scenario, y_old: np.ndarray | None,
                   new_model: Model, new_sc: Scenario, t0: float,
                   last: Trajectory | None = None, K_keep: np.ndarray | None = None) -> tuple[ClosedOrigin, Carried]:
    """The closed form ``new_model`` of ``new_sc`` restarted at ``t0`` from the old state's K, attitude and wheel
    (``K_keep``: the K an old closed form shows, as in ``carry_state``), and the carry that gives them (the full
    model's state; ``E_before`` is the old state's energy). Raises CannotCarry or ScenarioError before anything is
    used."""
    full = get_model(new_sc.system, "full")
    p = np.asarray(full.pack(new_sc), dtype=float)
    carried = carry_state(old_model, old_p, old_sc, y_old, full, new_sc, new_p=p, last=last, K_keep=K_keep)
    y = carried.y
    names = state_names(full, y.size)
    q = y[names.index("qw"):names.index("qz") + 1].copy()
    K, _ = pick(full.invariants)(np.ascontiguousarray(y[None, :]), p)
    norm = float(np.linalg.norm(K[0]))
    origin = WheelOrigin(t0=float(t0), scenario=new_sc.with_values(**{"initial.omega": [float(w) for w in y[:3]]}),
                         q_left=q, q_right=IDENTITY, P=np.eye(3),
                         K_dir=np.asarray(K[0], dtype=float) / norm if norm > 0 else np.zeros(3),
                         offsets=tuple((n, float(y[names.index(n)])) for n in COUNTERS),
                         Omega_w0=float(y[names.index("Omega_w")]))
    origin.evaluate(new_model, np.array([float(t0)]))  # a closed form that cannot run says so before the switch
    return origin, carried


__all__ = ["WheelOrigin", "restart_closed"]
