"""A closed form restarted from a running state: where it starts (``ClosedOrigin``) and the dispatch to its
model's own ``restart`` hook.

A closed form has no state: it starts at t = 0 from its scenario. To go on from a running state at t0 (a viewer
switched the fidelity, or moved a slider, while it ran) a system's closed form says, by its Model's ``restart``
hook, how to evaluate itself from the state then: from which scenario (its initial values taken from the
state's K) and with which constant rotations of its attitude and angular velocity. The hooks live in each
system's own folder (the moving mass's closed form, the spherical pendulum's averaged solution); a closed form
without one cannot go on from a state (``CannotCarry``), and the run restarts from t = 0.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from physics.core.rotation import normalize, qmul, rotate
from physics.core.trajectory import Trajectory
from physics.registry import Model
from physics.scenario.scenario import Scenario
from physics.systems.carry import CannotCarry, Carried


@dataclass(frozen=True)
class ClosedOrigin:
    """Where a restarted closed form starts: time ``t0`` (s), the ``scenario`` it is evaluated from
    (G0, theta0 of the present K), the constant rotations (quaternions) on the left and right of its
    attitude, and P (3, 3) on its omega. ``K_dir``: K's fixed inertial direction when the solution's is not
    G0's (sin theta0, 0, cos theta0) turned by q_left; ``offsets``: (column, value) added to internal columns,
    counters such as the dissipated work that went on before the restart."""

    t0: float
    scenario: Scenario
    q_left: np.ndarray
    q_right: np.ndarray
    P: np.ndarray
    K_dir: np.ndarray | None = None
    offsets: tuple[tuple[str, float], ...] = ()

    def evaluate(self, model: Model, times: np.ndarray) -> Trajectory:
        """The closed form at absolute times ``times`` (>= t0, increasing)."""
        s = np.maximum(np.asarray(times, dtype=float) - self.t0, 0.0)
        first = s[0] > 0
        tr = model.solve(self.scenario, np.concatenate([[0.0], s]) if first else s)
        if first:
            tr = tr.slice(1)
        info = dict(tr.info)
        if info.get("t_stop") is not None:
            info["t_stop"] = float(info["t_stop"]) + self.t0
        quat = normalize(qmul(qmul(self.q_left, tr.quat), self.q_right))
        internal = dict(tr.internal)
        for name, value in self.offsets:
            internal[name] = internal[name] + value
        return Trajectory(t=tr.t + self.t0, theta=tr.theta, K=tr.K, E=tr.E, omega=tr.omega @ self.P.T, quat=quat,
                          internal=internal, info=info)

    def momentum(self, G: float) -> np.ndarray:
        """Inertial K (3,) when the closed form's |G| is ``G``: fixed in direction, as the closed form has it."""
        if self.K_dir is not None:
            return G * self.K_dir
        th0 = self.scenario.initial.theta0
        return G * rotate(self.q_left, np.array([math.sin(th0), 0.0, math.cos(th0)]))


def carry_to_closed(old_model: Model, old_p: np.ndarray, old_sc: Scenario, y_old: np.ndarray | None,
                    new_model: Model, new_sc: Scenario, t0: float,
                    last: Trajectory | None = None, K_keep: np.ndarray | None = None) -> tuple[ClosedOrigin, Carried]:
    """The closed form ``new_model`` restarted at ``t0`` from the old state (``y_old``, or an old closed form's
    ``last`` row and the K it shows, ``K_keep``: see ``carry_state``), by the model's ``restart`` hook; the
    Carried says what the change did (its ``E_before`` is the old state's energy). Raises CannotCarry when the
    closed form has no hook or the state cannot be carried."""
    if new_model.restart is None:
        raise CannotCarry(f"the {new_model.fidelity} model of the {new_model.system.replace('_', ' ')} is a "
                          "closed form that starts with its parts at rest, with no state to carry")
    return new_model.restart(old_model, old_p, old_sc, y_old, new_model, new_sc, t0, last=last, K_keep=K_keep)


__all__ = ["ClosedOrigin", "carry_to_closed"]
