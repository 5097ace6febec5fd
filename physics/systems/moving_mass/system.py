"""The moving-mass system registered: its tables, parameters, fidelity choice, derived quantities and example.

A point mass on a spring-damper (seed 004, seed 000), with the fluid cavity, the resisting medium and the
braking torque that the same papers treat. A bare body (no internal part) runs here too: every part
switched off is the free rigid body.
"""

from __future__ import annotations

import math
from importlib import resources

import numpy as np

from physics.core.errors import ScenarioError
from physics.core.rotation import rotate
from physics.registry import Param, System, Table, register_system
from physics.scenario.initial import initial_G
from physics.systems.end_state import EndLocked
from physics.systems.moving_mass import closed_model, models  # noqa: F401  (registers the models)
from physics.systems.moving_mass.accuracy import METHOD, auto_conditions, averaged_error_bound, cheapest_first, choose
from physics.systems.moving_mass.figure import ACTIONS, figure
from physics.systems.moving_mass.models import quasi_static_displacement
from physics.systems.moving_mass.params import THRUSTERS, Cavity, Control, Mass, Medium, check_mass_state
from physics.systems.moving_mass.quantities import QUANTITIES
from physics.systems.moving_mass.start import PART, STATE, start_part
from physics.systems.moving_mass.validity import closed_form_available, thruster

NAME = "moving_mass"
MASS_FOLDER, FRICTION_FOLDER = "Moving mass, medium, braking", "Friction and cavity"
# Values a part is switched on with when a slider turns it on (its other keys then have sliders too)
MASS_DEFAULTS = {"m": 0.1, "rho": 1.5, "Omega": 8.0, "chi": 8.0}
CAVITY_DEFAULTS = {"beta": 1000.0, "nu": 20.0, "a0": 0.1}

PARAMS = (
    # the six of the braking paper (docs/models.md A.1): the moving mass, the medium and the brake
    Param("mass.m", "m", "kg", "mass of the small body moving inside on a spring-damper; 0 = none; must stay below "
          "the total mass M", 0.0, 1.0, 0.001, "seed 004 eq. (4)", MASS_FOLDER),
    Param("mass.rho", "rho", "m", "distance from the centre of mass to the moving mass's rest point, on the "
          "symmetry axis", 0.0, 3.0, 0.01, "seed 004 eq. (4)", MASS_FOLDER),
    Param("mass.Omega", "Omega", "rad/s", "natural frequency of the mass on its spring (Omega^2 = stiffness / m): "
          "a stiffer spring, a higher Omega", 0.5, 60.0, 0.1, "seed 004 eq. (4): Omega^2 = c/m", MASS_FOLDER),
    Param("mass.chi", "chi", "1/s", "damping of the mass's spring: damper force per unit mass and speed "
          "(chi = delta/m); it turns the wobble into heat", 0.0, 60.0, 0.1, "seed 004 eq. (4): chi = delta/m",
          MASS_FOLDER),
    Param("medium.lambda", "lambda", "1/s", "resistance of the surrounding medium: a torque -lambda J* w against "
          "the rotation; 0 = no medium", 0.0, 0.01, 1e-5, "seed 004 eq. (2)", MASS_FOLDER, adds=True),
    Param("control.b", "b", "N m", "strength of the braking torque, always against K; 0 = no braking; the readout T "
          "shows when it stops the spin", 0.0, 0.02, 1e-5, "seed 004 eq. (8)", MASS_FOLDER, adds=True),
    Param("mass.lam_q", "lam_q", "1/m", "drag-like friction of the mass, growing with the square of its speed: "
          "force -m lam_q |u'| u'", 0.0, 20000.0, 10.0, "seed 000 (1.1): lam_q = mu/m", FRICTION_FOLDER),
    Param("cavity.beta", "beta", "kg/m^3", "density of the fluid in the spherical cavity; 0 = no cavity", 0.0,
          2000.0, 1.0, "seed 004 eq. (4)", FRICTION_FOLDER),
    Param("cavity.nu", "nu", "m^2/s", "kinematic viscosity of the fluid (Stokes flow needs Re = a0^2 w/nu small)",
          0.1, 100.0, 0.1, "seed 004 eq. (4)", FRICTION_FOLDER),
    Param("cavity.a0", "a0", "m", "radius of the spherical cavity", 0.01, 0.5, 0.005, "seed 004: P = 8 pi a0^7/525",
          FRICTION_FOLDER),
)


def check(sc) -> None:
    check_mass_state(sc)
    if sc.mass is not None and sc.mass.m >= sc.body.M:
        raise ScenarioError("mass.m", sc.mass.m, f"must be less than body.M = {sc.body.M:g} (M is the total mass)")


def check_carrier(sc) -> None:
    """The carrier's equatorial moments A - m rho^2/(1 - m/M) must stay positive at every fidelity (the full
    model's pack checks it too; the closed and averaged forms failed deep inside, e.g. rho = 1e100). Run before
    a run (``System.check_run``), not when the scenario is read."""
    if sc.mass is not None:
        ms = sc.mass
        share = ms.m * ms.rho * ms.rho / (1.0 - ms.m / sc.body.M)  # a product: inf, not OverflowError
        if not share < min(sc.body.A, sc.body.B):
            raise ScenarioError("mass.rho", ms.rho, "is too large: m rho^2/(1 - m/M) must be less than A and B")


def torque_direction(sc, q, K):
    """The control torque's inertial unit direction: a thruster's body axis turned by the attitude ``q``, else the
    brake's -K/|K| (None at K = 0)."""
    if thruster(sc):
        i = THRUSTERS.index(sc.control.law)
        axis = np.zeros(3)
        axis[i // 2] = 1.0 if i % 2 == 0 else -1.0
        return rotate(np.asarray(q, dtype=float), axis)
    n = float(np.linalg.norm(K))
    return -np.asarray(K, dtype=float) / n if n > 0 else None


def braking_time(G: float, b: float, lam: float) -> float:
    """Seed 004 eq. (11): when the braking torque b brings |G| to zero against the medium lam."""
    from physics.systems.moving_mass.closed import braking_time as T

    return T(G, b, lam)


def end_locked(sc) -> EndLocked | str:
    """The end state's coordinates (docs/models.md, "The energy sink's end state"): the mass's displacement u
    (state entries 3-5, rates 6-8), on the scale of its centrifugal stretch; a cavity alone locks nothing."""
    ms = sc.mass
    friction = ms is not None and (ms.chi > 0 or ms.lam_q > 0)
    if not friction and sc.cavity is None:
        return ("no dissipation (" + ("mass.chi = 0, mass.lam_q = 0" if ms else "no mass") +
                ", no cavity): the motion never settles, no end state")
    if ms is None:
        return EndLocked()  # the cavity's fluid turns with the body at the end: nothing else moves
    w0, _, _ = initial_G(sc)
    stretch = max(ms.rho, 1e-3) * max(float(w0 @ w0) / ms.Omega**2, 1e-6)
    return EndLocked(coords=(3, 4, 5), rates=(6, 7, 8), scale=(stretch,) * 3, names=("ux", "uy", "uz"))


def available(sc, fidelity: str) -> tuple[bool, str]:
    if fidelity == "averaged" and thruster(sc):
        return False, "a thruster fixed in the body has no averaged form (the averaged model brakes along G)"
    return closed_form_available(sc) if fidelity == "closed" else (True, "")


def derived(sc) -> dict[str, float | str]:
    """The papers' coefficients F, D, L, H, P, Gamma1, Gamma2, k*, the braking time T, G0, theta0, eps and Re."""
    from physics.systems.moving_mass.closed import braking_time
    from physics.systems.moving_mass.coefficients import coefficients

    co = coefficients(sc)
    out: dict[str, float | str] = dict(F=co.F, D=co.D, L=co.L, H=co.H, P=co.P)
    out.update(Gamma1=co.Gamma1, Gamma2=co.Gamma2, k_star=co.k_star)
    out["T"] = braking_time(co.G0, co.b, co.lam) if co.b > 0 else math.inf
    out["G0"] = co.G0
    out["theta0"] = co.theta0
    out["eps"] = co.omega0 / sc.mass.Omega if sc.mass else 0.0
    out["Re"] = sc.cavity.a0 * sc.cavity.a0 * co.omega0 / sc.cavity.nu if sc.cavity else 0.0
    return out


def error_bounds(sc, fidelity: str) -> float | None:
    """Estimated max |theta_full - theta| (rad) over [0, t_end] of the averaged and closed models (they agree to
    rounding where both exist); inf where the estimate makes no claim."""
    if fidelity not in ("averaged", "closed"):
        return None
    if fidelity == "closed" and not closed_form_available(sc)[0]:
        return None
    return averaged_error_bound(sc)


def edit(data: dict, key: str, value) -> None:
    """One slider value into the scenario dict. A zero m, lambda, b or beta removes the mass, the medium,
    the control or the cavity; a positive one adds it (with MASS_DEFAULTS / CAVITY_DEFAULTS for the rest)."""
    table, _, name = key.partition(".")
    if table == "mass":
        if name == "m" and value == 0:
            data.pop("mass", None)
            return
        section = data.setdefault("mass", dict(MASS_DEFAULTS))
        section[name] = value
        for k, x in MASS_DEFAULTS.items():
            section.setdefault(k, x)
    elif table == "medium":
        if value == 0:
            data.pop("medium", None)
        else:
            data["medium"] = {"lambda": value}
    elif table == "control":
        if value == 0:
            data.pop("control", None)
        else:
            data.setdefault("control", {"law": "K"})["b"] = value
    elif table == "cavity":
        if name == "beta" and value == 0:
            data.pop("cavity", None)
        elif "cavity" in data or name == "beta":  # nu, a0 of an absent cavity wait until beta switches it on
            data.setdefault("cavity", dict(CAVITY_DEFAULTS))[name] = value


def values(sc, item=None) -> dict[str, float]:
    """The slider values describing ``sc``: 0 for an absent part's switch, the default for its other keys."""
    ms, cav = sc.mass, sc.cavity
    return {"mass.m": ms.m if ms else 0.0, "mass.rho": ms.rho if ms else MASS_DEFAULTS["rho"],
            "mass.Omega": ms.Omega if ms else MASS_DEFAULTS["Omega"], "mass.chi": ms.chi if ms else 0.0,
            "mass.lam_q": ms.lam_q if ms else 0.0,
            "cavity.beta": cav.beta if cav else 0.0, "cavity.nu": cav.nu if cav else CAVITY_DEFAULTS["nu"],
            "cavity.a0": cav.a0 if cav else CAVITY_DEFAULTS["a0"],
            "medium.lambda": sc.medium.lambda_ if sc.medium else 0.0,
            "control.b": sc.control.b if sc.control else 0.0}


def amplitude(tr, sc) -> float:
    """max |u|, m: the mass's displacement from its rest point O1. The averaged and closed models carry no u,
    so there it is |u| of the forced (slow-manifold) motion they assume (docs/models.md A.3), at each output's omega."""
    inn = tr.internal
    if "ux" in inn:
        return float(np.max(np.sqrt(inn["ux"] ** 2 + inn["uy"] ** 2 + inn["uz"] ** 2)))
    if sc.mass is not None:
        return float(max(np.linalg.norm(quasi_static_displacement(sc, w)[0]) for w in np.asarray(tr.omega)))
    return math.nan


SYSTEM = register_system(System(
    name=NAME, label="moving mass",
    summary="a point mass on a spring-damper, with a fluid cavity, a resisting medium and a braking torque "
            "(seeds 004 and 000, docs/models.md Part A)",
    tables=(Table("mass", Mass), Table("cavity", Cavity), Table("medium", Medium, renamed=(("lambda", "lambda_"),)),
            Table("control", Control)),
    example=resources.files("physics").joinpath("data/default.toml").read_text(encoding="utf-8"),
    params=PARAMS, folders=(MASS_FOLDER, FRICTION_FOLDER), default=True,
    check=check, conditions=auto_conditions, choose=choose, cheapest_first=cheapest_first, available=available,
    derived=derived,
    error_bounds=error_bounds, error_method=METHOD, edit=edit, values=values, amplitude=amplitude,
    parts={PART: STATE}, start_part=start_part, check_run=check_carrier, braking_time=braking_time,
    torque_direction=torque_direction,
    end_locked=end_locked,
    quantities=QUANTITIES, initial_keys={"mass_state": "rest"}, figure=figure, actions=ACTIONS,
))
