"""The pendulum-damper systems of seed 002 (docs/models.md Part B) at the full fidelity.

Both start from the initial rotation of the frozen system (``initial_G``: the bobs at rest relative
to the carrier at their rest positions), identity attitude and no dissipated work. The equations
work about the carrier's own COM with its own mass and inertia (``physics.pendulum_system``).
"""

from __future__ import annotations

import numpy as np

from physics.compiled import dispatch as kernels
from physics.compiled import pendulum as kernel
from physics.core.rotation import IDENTITY, normalize, nutation_angle, rotate
from physics.core.trajectory import Trajectory
from physics.registry import Model, register
from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario
from physics.systems.pendulum.geometry import pendulum_system


def pack(sc: Scenario) -> np.ndarray:
    """The flat parameter vector of physics/compiled/pendulum.py (layout in its docstring). The spherical
    pendulum's ``pivot`` ("cardan" or "isotropic") goes in p[12 + 7] (kernel.PIVOT): 0 or 1."""
    system = pendulum_system(sc)
    kind = kernel.SPHERICAL if system.bobs[0].kind == "spherical" else kernel.PLANE
    p = np.zeros(kernel.n_params(len(system.bobs)))
    p[0], p[1], p[2] = kind, len(system.bobs), system.M
    p[3:12] = np.asarray(system.I_c, dtype=float).reshape(9)
    for i, bob in enumerate(system.bobs):
        o = kernel.HEADER + kernel.BOB * i
        p[o:o + 4] = bob.m, bob.l, float(bob.k), bob.c_d
        p[o + 4:o + 7] = bob.pivot
        if kind == kernel.SPHERICAL:  # p[o+7] the pivot model (pendulum.pivot); p[o+8:o+16] unused, 0
            p[o + kernel.PIVOT] = kernel.ISOTROPIC if sc.pendulum.pivot == "isotropic" else kernel.CARDAN
            continue
        n = np.asarray(bob.axis, dtype=float)
        e0 = np.asarray(bob.arm, dtype=float)
        p[o + 7:o + 10] = n
        p[o + 10:o + 13] = e0
        p[o + 13:o + 16] = np.cross(n, e0)
    return p


def _nq(p: np.ndarray) -> int:
    return kernel.n_coordinates(int(p[0]), int(p[1]))


def initial_state(sc: Scenario, p: np.ndarray) -> np.ndarray:
    w0, _, _ = initial_G(sc)
    nq = _nq(p)
    chart = [0.0] if p[0] == kernel.SPHERICAL else []  # the spherical pendulum starts in its Cardan chart
    return np.concatenate([w0, np.zeros(2 * nq), IDENTITY, [0.0], chart])


def _internal(Y: np.ndarray, p: np.ndarray) -> dict[str, np.ndarray]:
    nq = _nq(p)
    if p[0] == kernel.SPHERICAL:
        names = ("alpha", "beta", "alpha_dot", "beta_dot")
    else:
        names = tuple(f"a{i + 1}" for i in range(nq)) + tuple(f"a{i + 1}_dot" for i in range(nq))
    internal = {name: Y[:, 3 + i].copy() for i, name in enumerate(names)}
    internal["W_diss"] = Y[:, 3 + 2 * nq + 4].copy()
    if p[0] == kernel.SPHERICAL:  # alpha, beta and their rates are those of this chart (compiled/pendulum.py)
        internal["chart"] = Y[:, kernel.CHART].copy()
    return internal


def observe(t, Y, p, sc) -> Trajectory:
    """theta is the angle between the total H about O and body e3 (docs/models.md B.2 "Nutation angle")."""
    H, E = kernel.observe(np.ascontiguousarray(Y), p)
    o = 3 + 2 * _nq(p)
    return Trajectory(t=t, theta=nutation_angle(H), K=np.linalg.norm(H, axis=1), E=E, omega=Y[:, 0:3].copy(),
                      quat=normalize(Y[:, o:o + 4]), internal=_internal(Y, p))


def invariants(Y, p):
    """Inertial angular momentum about O (n, 3) and energy (n,)."""
    H, E = kernel.observe(np.ascontiguousarray(Y), p)
    o = 3 + 2 * _nq(p)
    return rotate(Y[:, o:o + 4], H), E


def stiff_advice(sc: Scenario) -> str:
    """Why a pendulum run is stiff, in its keys: the pivot's spring and damper against the bob they act on."""
    return ("the pivot's spring and damper (pendulum.k, pendulum.c_d) outpace the bob's motion (pendulum.m, "
            "pendulum.l, initial.G0): lower the first or raise the second, or use the averaged fidelity")


SPHERICAL_FULL = register(Model(
    name="spherical_pendulum/full", system="spherical_pendulum", fidelity="full",
    summary="carrier + spherical pendulum (Alger) on a Cardan pivot, exact reduced multibody equations "
            "(docs/models.md B.2)",
    state=("wx", "wy", "wz", "alpha", "beta", "alpha_dot", "beta_dot", "qw", "qx", "qy", "qz", "W_diss", "chart"),
    kernel=kernels.SPHERICAL_FULL, pack=pack, initial_state=initial_state, observe=observe, invariants=invariants,
    columns=("alpha", "beta", "alpha_dot", "beta_dot", "W_diss", "chart"), stiff_advice=stiff_advice,
))

def plane_layout(n: int) -> tuple[str, ...]:
    """The names of a plane-pendulum state of length n: omega, a1..aN, their rates, the attitude, W_diss."""
    nq = (n - 8) // 2
    return (("wx", "wy", "wz") + tuple(f"a{i + 1}" for i in range(nq)) + tuple(f"a{i + 1}_dot" for i in range(nq))
            + ("qw", "qx", "qy", "qz", "W_diss"))


PLANE_FULL = register(Model(
    name="plane_pendulums/full", system="plane_pendulums", fidelity="full",
    summary="carrier + N plane pendulums (Taylor), exact reduced multibody equations (docs/models.md B.2)",
    state=("wx", "wy", "wz", "qw", "qx", "qy", "qz", "W_diss"),  # with N = 0; ``plane_layout`` names the rest
    layout=plane_layout,
    kernel=kernels.PLANE_FULL, pack=pack, initial_state=initial_state, observe=observe, invariants=invariants,
    columns=("W_diss",),  # and a1..aN, a1_dot..aN_dot (see _internal)
    stiff_advice=stiff_advice,
))
