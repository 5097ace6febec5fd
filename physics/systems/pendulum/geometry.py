"""The pendulum systems of seed 002 as the equations need them (docs/models.md Part B section 1).

A scenario gives the frozen system (carrier + bobs locked at rest) about the system COM O:
principal moments A, B, C and total mass M, with bob geometry measured from O. The multibody
equations work about the carrier's own COM G_B with the carrier's own inertia and mass; this
module converts once, validates that the carrier left over is physical, and resolves
k = "resonant" / "optimal" (docs/models.md B.5).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from physics.core.errors import ScenarioError
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario


def _shift(x: np.ndarray) -> np.ndarray:
    """Parallel-axis term |x|^2 I - x x^T of a unit point mass at x."""
    return float(x @ x) * np.eye(3) - np.outer(x, x)


@dataclass(frozen=True)
class Bob:
    """One pendulum, measured from the carrier's COM G_B. ``kind`` is "spherical" (pivot at
    ``pivot`` on the axis, arm along ``arm`` = e3 at rest) or "plane" (hinge at ``pivot``,
    unit hinge axis ``axis``, unit arm direction at rest ``arm``)."""

    kind: str
    m: float
    l: float
    k: float
    c_d: float
    pivot: np.ndarray
    axis: np.ndarray
    arm: np.ndarray

    @property
    def rest(self) -> np.ndarray:
        return self.pivot + self.l * self.arm


@dataclass(frozen=True)
class PendulumSystem:
    """Carrier mass M0 (kg) and inertia I_c (3x3, kg m^2, about G_B, body axes), the bobs, the
    total mass M, the frozen moments J (A, B, C) about O, the carrier COM c (from O, m) and the
    nominal spin rate W (rad/s, initial omega_z)."""

    M0: float
    I_c: np.ndarray
    bobs: tuple[Bob, ...]
    M: float
    J: np.ndarray
    c: np.ndarray
    W: float

    @property
    def mu(self) -> float:
        """Reduced mass of a single bob, m M0/(M0 + m) (docs/models.md B.9 item 1)."""
        m = self.bobs[0].m
        return m * self.M0 / (self.M0 + m)


def _geometry_from_O(sc: Scenario) -> list[tuple[str, object, np.ndarray, np.ndarray, np.ndarray]]:
    """(kind, params, pivot from O, axis, arm) of every bob."""
    e3 = np.array([0.0, 0.0, 1.0])
    if sc.pendulum is not None:
        p = sc.pendulum
        return [("spherical", p, p.h * e3, np.array([1.0, 0.0, 0.0]), e3)]
    return [("plane", pp, *pp.geometry()) for pp in sc.plane_pendulums]


def _placing_key(kind: str, bob, i: int, pivot: np.ndarray) -> tuple[str, object]:
    """The key that puts a bob far from O: its length, or what places its pivot (h; hinge, R or z_p)."""
    if kind == "spherical":
        return ("pendulum.l", bob.l) if bob.l >= abs(bob.h) else ("pendulum.h", bob.h)
    where = f"plane_pendulum[{i}]"
    if bob.l >= float(np.linalg.norm(pivot)):
        return f"{where}.l", bob.l
    if bob.preset is None:
        return f"{where}.hinge", list(bob.hinge)
    return (f"{where}.R", bob.R) if bob.R >= abs(bob.z_p) else (f"{where}.z_p", bob.z_p)


def pendulum_system(sc: Scenario, *, resolve: bool = True) -> PendulumSystem:
    """The scenario's pendulum system, with k resolved when ``resolve`` (tuning needs the rest)."""
    body = sc.body
    J = np.array([body.A, body.B, body.C])
    geo = _geometry_from_O(sc)
    masses = np.array([g[1].m for g in geo])
    M0 = body.M - masses.sum()
    rests = [pivot + g[1].l * arm for g, (_, _, pivot, _, arm) in zip(geo, geo, strict=True)]
    c = -sum(m * r for m, r in zip(masses, rests, strict=True)) / M0
    I_c = np.diag(J) - sum(m * _shift(r) for m, r in zip(masses, rests, strict=True)) - M0 * _shift(c)
    eig = np.linalg.eigvalsh(I_c)
    table = geo[0][0] == "spherical" and "pendulum" or "plane_pendulum"
    if eig[0] <= 0 or eig[2] > eig[0] + eig[1] + 1e-12 * eig[2]:
        moments = [m * float(r @ r) for m, r in zip(masses, rests, strict=True)]
        i = int(np.argmax(moments))
        if moments[i] > J.max():  # the bob sits so far out that no body could carry it: its placing key is at fault
            key, value = _placing_key(geo[i][0], geo[i][1], i, geo[i][2])
            raise ScenarioError(key, value, f"places a bob so far from O that its moment m |r|^2 = {moments[i]:.3g} "
                                f"kg m^2 exceeds the body's largest moment ({J.max():.4g}): no rigid carrier is left")
        placing = ("m", "l", "h") if table == "pendulum" else ("m", "l", "azimuth", "R", "z_p", "hinge")
        raise ScenarioError("body.A", body.A, f"with body.B and body.C, too small for the bobs of [{table}] as "
                            f"{', '.join(f'{table}.{k}' for k in placing)} place them: the carrier left over would "
                            f"have principal moments {np.array2string(eig, precision=4)}, not a rigid body")
    w0, _, _ = initial_G(sc)
    bobs = tuple(Bob(kind=kind, m=g.m, l=g.l, k=g.k, c_d=g.c_d, pivot=pivot - c, axis=axis, arm=arm)
                 for kind, g, pivot, axis, arm in geo)
    system = PendulumSystem(M0=M0, I_c=I_c, bobs=bobs, M=body.M, J=J, c=c, W=float(w0[2]))
    if resolve and any(isinstance(b.k, str) for b in bobs):
        system = _resolve_tuning(system, sc)
    return system


def resolved_stiffness(sc: Scenario) -> tuple[float, ...]:
    """Each bob's spring k (N m/rad), a tuned one ("resonant", "optimal") resolved as the models resolve it:
    cheap (no decay-rate analysis), for a viewer that shows the k a tuning chose. ScenarioError when a
    tuning has no solution (a prolate carrier asked to tune "resonant")."""
    return tuple(float(b.k) for b in pendulum_system(sc).bobs)


def resonant_stiffness(system: PendulumSystem, bob: Bob) -> float:
    """k that puts mode 1 of the spherical pendulum on the free nutation (docs/models.md B.5, seed 002 (14)):
    symmetric carrier k = mu l^2 (C W/A)^2; asymmetric k = mu l^2 W^2 (1 + sqrt(s1 s2))^2.
    Raises ScenarioError for a prolate carrier, which no stable damper can be tuned to."""
    A, B, C = np.diag(system.I_c)
    W = system.W
    mu = bob.m * system.M0 / (system.M0 + bob.m)
    if C <= max(A, B):
        raise ScenarioError(
            "pendulum.k", "resonant",
            f"cannot be tuned for a prolate carrier (its C = {C:.6g} <= A = {A:.6g}: body.C, body.A and body.B less "
            f"the bobs'): its nutation turns against the "
            "spin in the body frame, so resonance needs omega_0 = C W/A < W, where any pivot damping makes the "
            "pendulum whirl unstably, and every damper with omega_0 > W makes the nutation grow (energy-sink "
            "rule, docs/models.md B.4-B.5)")
    if abs(A - B) <= 1e-12 * A:
        return mu * bob.l**2 * (C * W / A) ** 2
    s1, s2 = (C - B) / A, (C - A) / B
    return mu * bob.l**2 * W**2 * (1.0 + math.sqrt(s1 * s2)) ** 2


def _resolve_tuning(system: PendulumSystem, sc: Scenario) -> PendulumSystem:
    from dataclasses import replace

    bobs = []
    for bob in system.bobs:
        if bob.k == "resonant":
            if bob.kind != "spherical":
                raise ScenarioError("plane_pendulum.k", "resonant", "tuning is provided for the spherical pendulum")
            bob = replace(bob, k=resonant_stiffness(system, bob))
        elif bob.k == "optimal":
            from physics.systems.pendulum.linear import optimal_tuning

            k, c_d = optimal_tuning(system)
            bob = replace(bob, k=k, c_d=c_d)
        bobs.append(bob)
    return replace(system, bobs=tuple(bobs))
