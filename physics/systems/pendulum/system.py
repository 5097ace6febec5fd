"""The two pendulum-damper systems registered: Alger's spherical pendulum and Taylor's plane pendulums
(seed 002, docs/models.md Part B). They share the geometry (``geometry``), the compiled kernel and the linear
theory; only the spherical pendulum has an averaged model."""

from __future__ import annotations

import math

import numpy as np

from physics.core.errors import ScenarioError
from physics.registry import Param, System, Table, register_system
from physics.systems.end_state import EndLocked
from physics.systems.pendulum import averaged, models, validity  # noqa: F401  (registers the models)
from physics.systems.pendulum.figure import PLANE_ACTIONS, SPHERICAL_ACTIONS, plane_figure, spherical_figure
from physics.systems.pendulum.geometry import pendulum_system, resonant_stiffness
from physics.systems.pendulum.linear import optimal_tuning
from physics.systems.pendulum.params import Pendulum, PlanePendulum
from physics.systems.pendulum.quantities import QUANTITIES, quantity

FOLDER = "Pendulum damper"
MAX_PLANE_PENDULUMS = 24  # a ring damper has a handful; each one adds 2 states and a rigid-body coupling


def _params(systems: str) -> tuple[Param, ...]:
    common = (
        Param("pendulum.m", "bob m", "kg", "mass of each pendulum bob", 0.001, 0.3, 0.001, "seed 002", FOLDER),
        Param("pendulum.l", "arm l", "m", "pendulum arm length from pivot to bob", 0.01, 1.0, 0.005, "seed 002",
              FOLDER),
    )
    pivot = (Param("pendulum.h", "pivot h", "m", "height of the spherical pendulum's pivot above O on the spin axis",
                   -1.0, 1.0, 0.01, "seed 002", FOLDER),) if systems == "spherical" else ()
    return common + pivot + (
        Param("pendulum.k", "spring k", "N m/rad", "torsional spring at the pivot; 'tune to resonance' matches the "
              "free nutation", 0.0, 2.0, 0.001, "seed 002; docs/models.md B.5 (tuning)", FOLDER),
        Param("pendulum.c_d", "damper c_d", "N m s/rad", "pivot damper", 0.0, 0.2, 0.0005, "seed 002", FOLDER),
    )


def _bob_reaches(sc):
    """(key prefix, bob, the key placing its pivot, a bound |pivot| + l on its distance from O) per pendulum."""
    if sc.pendulum is not None:
        yield "pendulum", sc.pendulum, "h", abs(sc.pendulum.h) + sc.pendulum.l
    for i, pp in enumerate(sc.plane_pendulums):
        if pp.preset is None:
            yield f"plane_pendulum[{i}]", pp, "hinge", max(abs(x) for x in pp.hinge) * math.sqrt(3.0) + pp.l
        else:
            yield f"plane_pendulum[{i}]", pp, "R" if pp.R >= abs(pp.z_p) else "z_p", pp.R + abs(pp.z_p) + pp.l


def check(sc) -> None:
    """The bobs' moments about O must be finite, their total mass below M, and they start at rest."""
    for where, bob, place, reach in _bob_reaches(sc):
        if not math.isfinite(bob.m * reach * reach):
            field = "l" if bob.l >= reach / 2 else place
            raise ScenarioError(f"{where}.{field}", getattr(bob, field), "is too large: the bob's moment about "
                                f"O, m (|r| + l)^2 = {bob.m:.3g} * ({reach:.3g})^2, must stay finite")
    if len(sc.plane_pendulums) > MAX_PLANE_PENDULUMS:
        raise ScenarioError("plane_pendulum", f"{len(sc.plane_pendulums)} tables",
                            f"at most {MAX_PLANE_PENDULUMS} plane pendulums (a damper has a few; 200 made each "
                            "frame of the explorer take seconds)")
    bobs = ([sc.pendulum] if sc.pendulum else []) + list(sc.plane_pendulums)
    total = sum(b.m for b in bobs)
    if total >= sc.body.M:
        table = "pendulum" if sc.pendulum else "plane_pendulum"
        raise ScenarioError(table + ".m", total, f"(all bobs) must be less than body.M = {sc.body.M:g}")


def derived(sc) -> dict[str, float | str]:
    from physics.systems.pendulum.linear_general import pendulum_derived

    return pendulum_derived(sc)


def edit(data: dict, key: str, value) -> None:
    """A pendulum slider sets every bob, or with ``pendulum.k#i`` plane pendulum i (0-based) only."""
    key, _, which = key.partition("#")
    name = key.partition(".")[2]
    if "pendulum" in data:
        data["pendulum"][name] = value
        return
    bobs = data["plane_pendulum"]
    if which:
        if not which.isdigit() or int(which) >= len(bobs):
            raise ScenarioError(f"{key}#{which}", value, f"names no bob: this scene has {len(bobs)}, "
                                f"numbered 0 to {len(bobs) - 1}")
        bobs = [bobs[int(which)]]
    for pp in bobs:
        pp[name] = value


# What the pendulum sliders show while the scene has no bob (a moving-mass scene): the spherical example's bob
ABSENT = {"pendulum.m": 0.05, "pendulum.l": 0.3, "pendulum.h": 0.5, "pendulum.k": 0.0, "pendulum.c_d": 0.01}


def _values(sc, bob) -> dict[str, float]:
    if bob is None:
        return dict(ABSENT)

    def stiffness() -> float:
        if isinstance(bob.k, str):  # a tuned spring ("resonant", "optimal") as physics resolves it
            from physics.systems.pendulum.geometry import resolved_stiffness

            i = 0 if sc.pendulum is not None else sc.plane_pendulums.index(bob)
            return resolved_stiffness(sc)[i]
        return bob.k

    return {"pendulum.m": bob.m, "pendulum.l": bob.l, "pendulum.h": sc.pendulum.h if sc.pendulum else 0.5,
            "pendulum.k": stiffness(), "pendulum.c_d": bob.c_d}


def spherical_amplitude(tr, sc) -> float:
    """The largest angle between the arm and its rest direction e3, arccos(cos alpha cos beta), rad."""
    inn = tr.internal
    if "alpha" not in inn:  # the averaged model: the bob's angle is not among its outputs
        return math.nan
    c = np.clip(np.cos(inn["alpha"]) * np.cos(inn["beta"]), -1.0, 1.0)
    return float(np.max(np.arccos(c)))


def plane_amplitude(tr, sc) -> float:
    """max |a_i| over the pendulums, rad."""
    angles = [v for k, v in tr.internal.items() if k.startswith("a") and k[1:].isdigit()]
    return float(np.max(np.abs(np.vstack(angles)))) if angles else math.nan


END_SWING = 0.1  # rad: the scale of a bob's swing away from its rest, for the end state's search


def spherical_tunings(sc) -> dict[str, dict[str, float]]:
    """The tuning rules for this carrier, named for a reader of the explorer: seed 002's resonance (14), which sets
    k alone, and the exact linear optimum of docs/models.md B.5 (the fastest decay of the linearised motion), which
    sets k and c_d. ScenarioError for a prolate carrier, which neither can tune."""
    system = pendulum_system(sc)
    k_opt, c_opt = optimal_tuning(system)
    return {"resonance (Grobov 1968, eq. 14)": {"pendulum.k": resonant_stiffness(system, system.bobs[0])},
            "linear optimum (fastest linear decay)": {"pendulum.k": float(k_opt), "pendulum.c_d": float(c_opt)}}


def spherical_end(sc) -> EndLocked | str:
    """The end state's coordinates (docs/models.md, "The energy sink's end state"): the gimbal angles alpha,
    beta (state entries 3, 4; rates 5, 6), in the Cardan chart the run starts in."""
    if sc.pendulum.c_d <= 0:
        return "no dissipation (pendulum.c_d = 0): the motion never settles, no end state"
    return EndLocked(coords=(3, 4), rates=(5, 6), scale=(END_SWING, END_SWING), names=("alpha", "beta"))


def plane_end(sc) -> EndLocked | str:
    """The end state's coordinates: each hinge's angle a_i (state entries 3 .. 2 + N; their rates follow)."""
    n = len(sc.plane_pendulums)
    if all(b.c_d <= 0 for b in sc.plane_pendulums):
        return "no dissipation (every plane_pendulum.c_d = 0): the motion never settles, no end state"
    return EndLocked(coords=tuple(range(3, 3 + n)), rates=tuple(range(3 + n, 3 + 2 * n)), scale=(END_SWING,) * n,
                     names=tuple(f"a{i + 1}" for i in range(n)))


SPHERICAL_EXAMPLE = """\
# preset: Spherical pendulum damper, resonant
# Alger's spherical pendulum damper on an oblate body, its spring tuned to the free nutation (seed 002).
[body]
A = 1.0
C = 1.4
M = 1.0

[pendulum]
m = 0.05
l = 0.3
h = 0.5
k = "resonant"
c_d = 0.01

[initial]
G0 = 2.0
theta0 = 0.3

[run]
fidelity = "full"
t_end = 60.0
"""

PLANE_EXAMPLE = """\
# preset: Plane pendulums (three, in the spin plane)
# Taylor's plane pendulums: three in the spin plane, 120 degrees apart (seed 002, docs/models.md B.7).
[body]
A = 1.0
C = 1.4
M = 1.0
""" + "".join(f"""
[[plane_pendulum]]
preset = "in_plane"
m = 0.03
l = 0.2
k = 0.5
c_d = 0.01
R = 0.5
azimuth = {a!r}
""" for a in (0.0, 2 * math.pi / 3, 4 * math.pi / 3)) + """
[initial]
G0 = 2.0
theta0 = 0.3

[run]
fidelity = "full"
t_end = 60.0
"""

SPHERICAL = register_system(System(
    name="spherical_pendulum", label="spherical pendulum",
    summary="Alger's spherical pendulum on a two-gimbal pivot with a torsional spring and damper (docs/models.md B.1)",
    tables=(Table("pendulum", Pendulum),), example=SPHERICAL_EXAMPLE, params=_params("spherical"), folders=(FOLDER,),
    check=check, conditions=validity.averaged_conditions, choose=validity.choose, derived=derived, edit=edit,
    error_bounds=validity.error_bounds, error_method=validity.METHOD,
    values=lambda sc, item=None: _values(sc, sc.pendulum), amplitude=spherical_amplitude,
    quantities=QUANTITIES, quantity=quantity, figure=spherical_figure, actions=SPHERICAL_ACTIONS,
    end_locked=spherical_end, tunings=spherical_tunings,
))

PLANE = register_system(System(
    name="plane_pendulums", label="plane pendulums",
    summary="Taylor's plane pendulums, each on a hinge with a torsional spring and damper (docs/models.md B.1, B.7)",
    tables=(Table("plane_pendulum", PlanePendulum, array=True, field="plane_pendulums"),), example=PLANE_EXAMPLE,
    params=_params("plane"), borrows=("pendulum",), folders=(FOLDER,), check=check,
    choose=lambda sc: ("full", "plane pendulums have only the full model"), derived=derived, edit=edit,
    values=lambda sc, item=None: _values(
        sc, sc.plane_pendulums[item if item is not None and 0 <= item < len(sc.plane_pendulums) else 0]
        if sc.plane_pendulums else None),
    amplitude=plane_amplitude, quantities=QUANTITIES, quantity=quantity, figure=plane_figure, actions=PLANE_ACTIONS,
    end_locked=plane_end,
))
