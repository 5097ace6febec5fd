"""Carrying a running state across a parameter or fidelity change, keeping what a lesson is about.

On a body with no external torque the inertial angular momentum K of the whole system is what the
motion conserves; a slider that changes a mass, an inertia or a fidelity must not change it. So
``carry_state`` maps a state of one model/scenario to another by keeping

- the attitude quaternion (the body does not jump),
- every internal coordinate that still exists (the mass's displacement u and velocity v, pendulum
  angles and rates, the dissipated-work counters), by name in the models' state layouts,
- K (inertial vector, magnitude and direction): the body angular velocity omega is solved for so that
  the new model's K at the new state equals the old model's K at the old state.

A part that appears (a mass switched on, the full model after the averaged one) starts at rest
relative to the body, or as its system's ``start_part`` hook says (the moving mass starts quasi-static when the
scenario asks for ``mass_state = "quasistatic"``); a part that disappears is dropped (``System.parts`` names the
state entries of each optional table). The energy E may change; ``Carried.dE`` says by how much.

K is affine in omega for fixed internal state (carrier, bobs), plus a quadratic term for the cavity's
fluid momentum (-kc f(omega)), so Newton's method with a central-difference Jacobian is exact in one
step for the affine case and converges quadratically with the cavity. The solve uses only the model's
own ``invariants``, so no system needs code of its own here. A model whose state is not laid out as (omega,
internal, attitude) (the moving mass's averaged model keeps K's inertial frame and a precession phase) is carried
in the layout its ``Chart`` reads it as, and its state is made from that at the end.

A closed form has no state to step from: ``carry_state`` refuses one as the target (``CannotCarry``). As the
source, its last row (omega, attitude, internal coordinates) is read as a state of the stateful model
it approximates (its Model's ``proxy`` fidelity), whose K is what is kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from physics.core.trajectory import Trajectory
from physics.kernels.build import pick
from physics.registry import Model, get_model, get_system
from physics.scenario.scenario import Scenario

OMEGA = ("wx", "wy", "wz")
QUAT = ("qw", "qx", "qy", "qz")
NEWTON_MAX = 30
K_RTOL = 1e-14  # Newton stops once |K_new - K_old| <= K_RTOL |K_old|: rounding, for a few-term sum


class CannotCarry(ValueError):
    """The state cannot be carried to the new model (a closed form, a singular K(omega))."""


@dataclass(frozen=True)
class Carried:
    """The new state ``y`` and what the change did: inertial K (3,) and energy E before and after."""

    y: np.ndarray
    K_before: np.ndarray
    K_after: np.ndarray
    E_before: float
    E_after: float
    iterations: int

    @property
    def dE(self) -> float:
        return self.E_after - self.E_before


def state_names(model: Model, n: int) -> tuple[str, ...]:
    """The names of a state vector of length ``n`` as carried (``Model.state_names``, or its Chart's layout)."""
    names = model.chart.state if model.chart is not None else model.state_names(n)
    if len(names) != n:
        raise CannotCarry(f"{model.name}: a state of {n} values does not match its layout {model.state}")
    return tuple(names)


def _has(sc: Scenario, part: str) -> bool:
    """Whether ``sc`` has the optional table ``part`` (an array table: at least one item)."""
    value = getattr(sc, part, None)
    return value is not None and value != ()


def _absent(sc: Scenario) -> set[str]:
    """Coordinates of the parts ``sc`` does not have (its system's ``parts``)."""
    out: set[str] = set()
    for part, names in get_system(sc.system).parts.items():
        if not _has(sc, part):
            out.update(names)
    return out


def carried_layout(model: Model, y: np.ndarray, p: np.ndarray) -> np.ndarray:
    """The model's state ``y`` as a carry reads it: itself, or through the model's Chart."""
    y = np.asarray(y, dtype=float)
    return model.chart.from_native(y[None, :], p)[0] if model.chart is not None else y


def _native(model: Model, y: np.ndarray, p: np.ndarray) -> np.ndarray:
    return np.asarray(model.chart.to_native(y, p), dtype=float) if model.chart is not None else y


def row_state(model: Model, p: np.ndarray, sc: Scenario, row: Trajectory) -> np.ndarray:
    """A state of ``model`` filled from a one-row Trajectory (omega, quat, internal columns by name);
    what the row does not give comes from the model's initial state (its rest values)."""
    y = carried_layout(model, model.initial_state(sc, p), p).copy()
    names = state_names(model, y.size)
    values = dict(zip(OMEGA, row.omega[-1], strict=True)) | dict(zip(QUAT, row.quat[-1], strict=True))
    values.update({k: float(v[-1]) for k, v in row.internal.items()})
    for i, name in enumerate(names):
        if name in values:
            y[i] = values[name]
    return _native(model, y, p)


def _K(model: Model, y: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, float]:
    """K and E of ``y`` in the carried layout (``carried_layout``)."""
    y = _native(model, y, p)
    K, E = pick(model.invariants)(np.ascontiguousarray(y[None, :]), p)  # interpreted while the kernels build
    return np.asarray(K[0], dtype=float), float(E[0])


def solve_omega(model: Model, y: np.ndarray, p: np.ndarray, K_target: np.ndarray) -> tuple[np.ndarray, int]:
    """``y`` (in the carried layout, ``carried_layout``) with omega (its first three values) changed so that the
    model's inertial K equals ``K_target``; the other values are kept. Returns (y, Newton iterations)."""
    y = y.copy()
    scale = max(float(np.linalg.norm(K_target)), 1e-300)
    for it in range(NEWTON_MAX + 1):
        K, _ = _K(model, y, p)
        r = K - K_target
        if np.linalg.norm(r) <= K_RTOL * scale:
            return y, it
        if it == NEWTON_MAX:
            break
        # central differences are exact for K quadratic in omega, whatever the step; a step of |omega|
        # keeps the rounding error of the difference at the level of K's own
        s = max(float(np.linalg.norm(y[:3])), 1e-3)
        Jac = np.empty((3, 3))
        for j in range(3):
            yp, ym = y.copy(), y.copy()
            yp[j] += s
            ym[j] -= s
            Jac[:, j] = (_K(model, yp, p)[0] - _K(model, ym, p)[0]) / (2 * s)
        try:
            y[:3] -= np.linalg.solve(Jac, r)
        except np.linalg.LinAlgError:
            raise CannotCarry(f"{model.name}: K does not determine omega at this state") from None
        if not np.all(np.isfinite(y[:3])):
            break
    raise CannotCarry(f"{model.name}: no omega gives the same K (residual {np.linalg.norm(r) / scale:.2g})")


def carry_state(old_model: Model, old_p: np.ndarray, old_sc: Scenario, y_old: np.ndarray | None,
          new_model: Model, new_sc: Scenario, new_p: np.ndarray | None = None,
          last: Trajectory | None = None, K_keep: np.ndarray | None = None) -> Carried:
    """The state of ``new_model`` under ``new_sc`` that keeps the old state's attitude, inertial K and
    surviving internal coordinates. ``y_old`` is the old model's state; for an old closed form pass
    ``y_old=None`` and its last row as ``last``, and the inertial K it shows as ``K_keep``: its row read as a
    state of its proxy has that K only to the theory's error (1 % for the spherical pendulum's averaged
    solution), and the K a viewer saw is the one to keep. Raises CannotCarry when the new model is a closed
    form or no omega gives the old K."""
    if new_model.solve is not None:
        raise CannotCarry(f"the {new_model.fidelity} model of the {new_model.system.replace('_', ' ')} is a closed "
                          "form, with no state to carry")
    if old_model.solve is not None:
        if last is None or not len(last) or old_model.proxy is None:
            raise CannotCarry(f"{old_model.name}: no state to carry from")
        old_model = get_model(old_sc.system, old_model.proxy)
        old_p = np.asarray(old_model.pack(old_sc), dtype=float)
        y_old = row_state(old_model, old_p, old_sc, last)
    y_old = carried_layout(old_model, y_old, old_p)
    if new_p is None:
        new_p = np.asarray(new_model.pack(new_sc), dtype=float)
    K_old, E_old = _K(old_model, y_old, old_p)
    if K_keep is not None:
        K_old = np.asarray(K_keep, dtype=float)

    template = carried_layout(new_model, new_model.initial_state(new_sc, new_p), new_p)
    names_new = state_names(new_model, template.size)
    old_values = dict(zip(state_names(old_model, y_old.size), y_old, strict=True))
    dropped = _absent(old_sc) | _absent(new_sc)  # a part switched off, on, or absent throughout
    y = np.zeros(template.size)
    fresh: list[int] = []  # coordinates of a part that starts now
    for i, name in enumerate(names_new):
        if name in old_values and name not in dropped:
            y[i] = old_values[name]
        elif name not in OMEGA + QUAT and not name.startswith("W_"):
            fresh.append(i)
    y[:3] = old_values["wx"], old_values["wy"], old_values["wz"]

    # keep omega bit for bit when the change leaves K at this state as it was (a damping, a spring)
    K_same, _ = _K(new_model, y, new_p)
    iterations = 0
    if np.linalg.norm(K_same - K_old) > K_RTOL * max(float(np.linalg.norm(K_old)), 1e-300):
        y, iterations = solve_omega(new_model, y, new_p, K_old)
    system = get_system(new_sc.system)
    for part, names in system.parts.items():
        idx = [i for i in fresh if names_new[i] in names]  # the part starts now: at rest, unless its hook says
        if idx and system.start_part is not None and _has(new_sc, part):
            y, n = system.start_part(part, new_model, new_sc, y, new_p, K_old, idx)
            iterations += n
    K_new, E_new = _K(new_model, y, new_p)
    return Carried(y=_native(new_model, y, new_p), K_before=K_old, K_after=K_new, E_before=E_old, E_after=E_new,
                   iterations=iterations)


__all__ = ["CannotCarry", "Carried", "carried_layout", "carry_state", "row_state", "solve_omega", "state_names"]
