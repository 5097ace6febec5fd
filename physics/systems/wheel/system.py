"""The viscous wheel damper registered: its table, parameters, checks, derived quantities, picture and example
(docs/models.md Part C)."""

from __future__ import annotations

import math

import numpy as np

from physics.core.errors import ScenarioError
from physics.registry import Condition, Param, System, Table, register_system
from physics.scenario.initial import initial_G
from physics.systems.choice import cheapest_within
from physics.systems.end_state import EndLocked
from physics.systems.wheel import accuracy, linear, models  # noqa: F401  (registers the models)
from physics.systems.wheel.figure import figure
from physics.systems.wheel.params import Wheel

NAME = "wheel"
FOLDER = "Wheel damper"
THETA_MAX = 0.1  # rad: the linear theory's largest initial nutation angle (its error grows as theta0^2)
GROWTH_MAX = 0.5  # e-folds the linear nutation may grow over the run and still be small

PARAMS = (
    Param("wheel.J", "J", "kg m^2", "the wheel's moment of inertia about its own axis (A, B, C include it, "
          "locked)", 0.005, 0.3, 0.001, "docs/models.md C.1", FOLDER),
    Param("wheel.c", "c", "N m s", "viscous coefficient of the wheel's bearing: torque -c Omega_w on the wheel, "
          "its reaction on the body; it turns the nutation into heat", 0.0, 2.0, 0.005, "docs/models.md C.1",
          FOLDER),
)
ABSENT = {"wheel.J": 0.06, "wheel.c": 0.5}  # what the sliders show on another system's scene (the example's)


def axial_share(sc) -> float:
    """J a.I^-1.a: the wheel's share of the locked body's inertia along its axis; < 1 for a physical body."""
    b, w = sc.body, sc.wheel
    a = np.array(w.axis)
    return float(w.J * (a[0] ** 2 / b.A + a[1] ** 2 / b.B + a[2] ** 2 / b.C))


def check(sc) -> None:
    """The body without the wheel's axial inertia must keep a positive inertia (I - J a a^T positive definite,
    i.e. J a.I^-1.a < 1). (The moving mass's initial.mass_state is refused by the scenario itself.)"""
    share = axial_share(sc)
    if not share < 1.0:
        limit = sc.wheel.J / share
        raise ScenarioError("wheel.J", sc.wheel.J, f"must be less than 1/(a.I^-1.a) = {limit:.6g} kg m^2 for this "
                            "body and axis: A, B, C include the locked wheel, so the body without its axial share "
                            "J a a^T must keep a positive inertia (J < min(A, B, C) always is)")


def conditions(sc) -> list[Condition]:
    """The linear theory's conditions: a small nutation angle, and a nutation that does not grow far."""
    _, _, theta0 = initial_G(sc)
    s = linear.exponents(sc)
    growth = float(np.max(s.real)) * sc.run.t_end
    return [Condition("theta0 (rad)", theta0, THETA_MAX, "the start is close to a pure spin (small nutation)"),
            Condition("linear growth max Re(s) t_end", growth, GROWTH_MAX,
                      "the nutation grows only a little over the run")]


def error_bounds(sc, fidelity: str) -> float | None:
    """The closed form's estimated max |theta - theta_full| over [0, t_end] (rad, ``accuracy``), None for any
    other fidelity, outside the calibrated domain or where the closed form's conditions fail."""
    if fidelity != "closed" or any(not c.holds for c in conditions(sc)):
        return None
    return accuracy.closed_error_bound(sc)


def choose(sc) -> tuple[str, str]:
    """``auto``'s pick: the closed form when its conditions hold and its error estimate meets run.accuracy
    (physics.systems.choice.DEFAULT_ACCURACY when unset), else the full model, and why."""
    return cheapest_within(sc, [c for c in conditions(sc) if not c.holds])


def derived(sc) -> dict[str, float | str]:
    """The wheel's share of the inertia, its relaxation time, K and E at the start and at the end the energy sink
    leads to (pure spin about the axis of the largest moment), and the linear theory's nutation mode."""
    b, w = sc.body, sc.wheel
    w0, _, theta0 = initial_G(sc)
    I = np.array([b.A, b.B, b.C])
    K0 = float(np.linalg.norm(I * w0))
    share = axial_share(sc)
    out: dict[str, float | str] = dict(J_share=share, n=float(w0[2]), theta0=theta0, K0=K0,
                                       E0=0.5 * float(w0 @ (I * w0)), E_end=K0 * K0 / (2.0 * float(I.max())))
    out["tau_wheel"] = w.J * (1.0 - share) / w.c if w.c > 0 else math.inf
    mode = linear.nutation_mode(sc)
    if mode is None:
        out["nutation"] = "no oscillating mode: the spin about e3 is unstable in the linear theory"
        return out
    out["nutation_frequency_linear"] = mode.imag
    out["decay_rate_linear"] = -mode.real
    out["tau_e_linear"] = 1.0 / -mode.real if mode.real < 0 else math.inf
    out["nutation"] = "decays" if mode.real < 0 else ("grows" if mode.real > 0 else "neither grows nor decays")
    return out


QUANTITIES = {
    "J_share": ("1", "the wheel's axial share J a.I^-1.a of the locked inertia along its axis (< 1)"),
    "n": ("rad/s", "initial spin rate about e3"),
    "theta0": ("rad", "initial nutation angle"),
    "K0": ("kg m^2/s", "angular momentum |K|, kept"),
    "E0": ("J", "initial kinetic energy"),
    "E_end": ("J", "energy at the end the bearing leads to: |K|^2/(2 I_max), pure spin about the largest moment"),
    "tau_wheel": ("s", "the wheel's relaxation time relative to the body, J (1 - J a.I^-1.a)/c"),
    "nutation_frequency_linear": ("rad/s", "nutation frequency in the body frame, linear theory about the spin"),
    "decay_rate_linear": ("1/s", "decay rate of the nutation angle, linear theory (< 0: grows)"),
    "tau_e_linear": ("s", "time for the nutation angle to fall by a factor e, linear theory"),
    "nutation": ("", "what the linear theory predicts"),
}


def available(sc, fidelity: str) -> tuple[bool, str]:
    if fidelity == "closed" and linear.nutation_mode(sc) is None:
        return False, "the linear theory has no nutation mode here (the spin about e3 is unstable)"
    return True, ""


def values(sc, item=None) -> dict[str, float]:
    w = sc.wheel
    return {"wheel.J": w.J, "wheel.c": w.c} if w is not None else dict(ABSENT)


def end_locked(sc) -> EndLocked | str:
    """The end state's coordinates (docs/models.md C.2): none, the wheel's angle moves no mass; its rate
    Omega_w (state entry 4) is zero at the end."""
    if sc.wheel.c <= 0:
        return "no dissipation (wheel.c = 0): the motion never settles, no end state"
    return EndLocked(rates=(models.STATE.index("Omega_w"),))


def amplitude(tr, sc) -> float:
    """The wheel's largest rate relative to the body, max |Omega_w| (rad/s)."""
    Om = tr.internal.get("Omega_w")
    return float(np.max(np.abs(Om))) if Om is not None and len(Om) else math.nan


EXAMPLE = """\
# preset: Viscous wheel damper
# A wheel turning in a viscous bearing about a transverse axis of an oblate body: the bearing turns the
# nutation into heat and the body settles into pure spin about its axis of largest moment (docs/models.md C).
[body]
A = 1.0
C = 1.5
M = 1.0

[wheel]
J = 0.2
c = 0.25
axis = [1.0, 0.0, 0.0]

[initial]
G0 = 3.0
theta0 = 0.4

[run]
fidelity = "full"
t_end = 30.0
"""

SYSTEM = register_system(System(
    name=NAME, label="viscous wheel",
    summary="a wheel turning about a body-fixed axis in a viscous bearing (docs/models.md Part C)",
    tables=(Table("wheel", Wheel),), example=EXAMPLE, params=PARAMS, folders=(FOLDER,),
    check=check, conditions=conditions, choose=choose, available=available, derived=derived, values=values,
    error_bounds=error_bounds, error_method=accuracy.METHOD,
    amplitude=amplitude, parts={"wheel": models.WHEEL}, quantities=QUANTITIES, figure=figure, end_locked=end_locked,
))
