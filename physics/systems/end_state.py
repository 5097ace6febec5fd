"""Where the energy sink leads: the end state a dissipative scene without braking or medium settles in
(docs/models.md, "The energy sink's end state").

No external torque acts, so the inertial angular momentum K, and with it G = |K|, is fixed; the internal
dissipation only lowers the energy. The motion stops dissipating only in a relative equilibrium: the part at
rest relative to the body, the whole turning as one rigid body about a principal axis of its locked inertia
J(q). Of the states with momentum G, the one the sink leads to is the least energy,

    E(q) = G^2 / (2 I_max(J(q))) + V(q),

(the amended potential: the kinetic energy of the locked system spinning about its axis of largest moment,
plus the part's spring energy V), minimised over the part's coordinates q starting from their rest. Each
system says which entries of its full model's state are its coordinates (``System.end_locked``); J(q) and
V(q) are read from that model's own momentum and energy with the rates set to zero, so the end state uses the
very inertia the model integrates.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize

from physics.core.errors import ScenarioError
from physics.registry import get_model, get_system
from physics.scenario import arguments
from physics.systems.cost import brake_and_medium

# The minimiser works in q / scale; these are in those units (the scale is a coordinate's typical excursion).
SIMPLEX = 0.05  # first simplex's size: off the rest point, so an unstable symmetric rest is left
X_TOL = 1e-11  # converged coordinates
DEGENERATE_RTOL = 1e-9  # two principal moments this close (relative) are one: the end axis is then not fixed


@dataclass(frozen=True)
class EndLocked:
    """A system's answer to "what is locked at the end": ``coords`` are the indices in its full model's state of
    the part's coordinates (varied), ``rates`` those of their rates (zero in the end state), ``scale`` a
    typical excursion per coordinate (its unit), ``names`` the coordinates' names."""

    coords: tuple[int, ...] = ()
    rates: tuple[int, ...] = ()
    scale: tuple[float, ...] = ()
    names: tuple[str, ...] = ()


@dataclass(frozen=True)
class EndState:
    """The end state of a dissipative scene.

    axis: unit vector (3,), body frame, the final spin axis (sign: the initial K's side of it);
    spin: the final spin rate G / I_max (rad/s); G: |K| (kg m^2/s), unchanged; I_max: the largest principal
    moment of the locked system in its end configuration (kg m^2); E0 and E_end: the initial and final energy
    (J); energy_to_lose = E0 - E_end (J); config: the part's coordinates at the end, by name;
    axis_fixed: False when the largest moment is repeated (a prolate body of revolution: any axis of the
    transverse plane, ``axis`` is the initial K's projection on it); sign_fixed: the start lies below the
    separatrix, E0 < G^2/(2 I_mid) with the locked inertia at the start, so the motion stays on the initial K's
    side of the axis; above it (a start near the axis of least moment) the end is +axis or -axis. Not detected:
    an end configuration free along a symmetry (a bob swung off the axis of a body of revolution, at any
    azimuth) fixes the axis only up to that symmetry (its angle to e3, docs/models.md D.2).
    """

    axis: np.ndarray
    spin: float
    G: float
    I_max: float
    E0: float
    E_end: float
    config: dict = field(default_factory=dict)
    axis_fixed: bool = True
    sign_fixed: bool = True

    @property
    def energy_to_lose(self) -> float:
        return self.E0 - self.E_end

    def __bool__(self) -> bool:
        return True


@dataclass(frozen=True)
class NoEndState:
    """A scene with no fixed end state, and why (braking, a medium, no dissipation)."""

    reason: str

    def __bool__(self) -> bool:
        return False


def end_state(sc, K: np.ndarray | None = None, E: float | None = None) -> EndState | NoEndState:
    """The end state the scene ``sc`` settles in (EndState), or NoEndState with the reason it has none.

    It settles from the scenario's initial state, or from a running one: ``K`` its total angular momentum in
    body axes now (kg m^2/s, (3,): |K| and the side of the axis), ``E`` its energy now (J, E0 of the result).
    """
    sc = arguments.scenario(sc)
    if K is not None:
        try:
            K = np.asarray(K, dtype=float).reshape(3)
        except Exception:  # noqa: BLE001 - a caller's object may raise anything from __float__
            raise ScenarioError("K", K, "must be three numbers (the angular momentum in body axes)") from None
        if not np.all(np.isfinite(K)):
            raise ScenarioError("K", K.tolist(), "must be finite")
    if E is not None and not (isinstance(E, numbers.Real) and not isinstance(E, bool) and math.isfinite(E)):
        raise ScenarioError("E", E, "must be a finite number (J)")
    b, lam = brake_and_medium(sc)
    if b > 0:
        return NoEndState(f"control.b = {b:g} N m: the braking torque takes |K| to zero, no fixed end state")
    if lam > 0:
        return NoEndState(f"medium.lambda = {lam:g} 1/s: the medium takes |K| away, no fixed end state")
    hook = get_system(sc.system).end_locked
    if hook is None:
        return NoEndState(f"the system {sc.system!r} states no end state")
    locked = hook(sc)
    if isinstance(locked, str):
        return NoEndState(locked)
    return _settle(sc, locked, K, E)


def _settle(sc, locked: EndLocked, K_now, E_now) -> EndState:
    model = get_model(sc.system, "full")
    p = model.pack(sc)
    y0 = np.asarray(model.initial_state(sc, p), dtype=float)
    K0, E0 = model.invariants(y0[None, :], p)
    K0, E0 = np.asarray(K0[0], dtype=float), float(E0[0])
    if K_now is not None:
        K0 = np.asarray(K_now, dtype=float).reshape(3)
    if E_now is not None:
        E0 = float(E_now)
    G = float(np.linalg.norm(K0))
    q0 = y0[list(locked.coords)] if locked.coords else np.zeros(0)
    scale = np.asarray(locked.scale, dtype=float)

    # rows: omega = e1, e2, e3 (the locked inertia's columns, as the model's body-frame K with identity attitude;
    # the initial state's attitude is the identity) and omega = 0 (the spring energy V)
    base = np.repeat(y0[None, :], 4, axis=0)
    base[:, 0:3] = np.vstack([np.eye(3), np.zeros(3)])
    if locked.rates:
        base[:, list(locked.rates)] = 0.0

    def inertia_and_V(q: np.ndarray) -> tuple[np.ndarray, float]:
        Y = base.copy()
        if locked.coords:
            Y[:, list(locked.coords)] = q
        K, E = model.invariants(Y, p)
        K = np.asarray(K, dtype=float)
        J = K[0:3].T  # column i is J e_i
        return 0.5 * (J + J.T), float(E[3])

    def amended(x: np.ndarray) -> float:
        J, V = inertia_and_V(q0 + x * scale)
        return G * G / (2.0 * float(np.linalg.eigvalsh(J)[-1])) + V

    separatrix = G * G / (2.0 * float(np.linalg.eigvalsh(inertia_and_V(q0)[0])[1]))
    x = np.zeros(len(q0))
    if len(q0):
        simplex = np.vstack([np.zeros(len(q0)), SIMPLEX * np.eye(len(q0))]) - SIMPLEX / (len(q0) + 1)
        res = minimize(amended, x, method="Nelder-Mead",
                       options=dict(initial_simplex=simplex, xatol=X_TOL, fatol=1e-15 * max(E0, 1e-300),
                                    maxiter=20000, maxfev=40000, adaptive=True))
        x = res.x
    q = q0 + x * scale
    J, V = inertia_and_V(q)
    lam, vec = np.linalg.eigh(J)
    I_max = float(lam[-1])
    top = lam >= I_max * (1.0 - DEGENERATE_RTOL)
    space = vec[:, top]
    axis = space @ (space.T @ K0)  # the initial K's side of the axis (its projection on the eigenspace)
    if np.linalg.norm(axis) < 1e-12 * max(G, 1e-300):
        axis = space[:, 0]
    axis = axis / np.linalg.norm(axis)
    E_end = G * G / (2.0 * I_max) + V
    return EndState(axis=axis, spin=G / I_max if I_max > 0 else math.nan, G=G, I_max=I_max, E0=E0, E_end=E_end,
                    config=dict(zip(locked.names, map(float, q), strict=True)), axis_fixed=int(top.sum()) == 1,
                    sign_fixed=E0 < separatrix)
