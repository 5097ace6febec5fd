"""When the averaged and closed-form models can be trusted: docs/models.md Part A section 5.

Each condition is a number compared with a limit. The limits turn "<<" into numbers: with them the
averaged model's theta is good to about 1e-3 rad (docs/models.md A.7(a): eps = 0.1 gives 4.4e-3 oblate,
7.9e-4 prolate), which is what a user choosing "auto" is promised.
"""

from __future__ import annotations

import math

from physics.registry import Condition
from physics.scenario.scenario import Scenario
from physics.systems.moving_mass import forced_response
from physics.systems.moving_mass.coefficients import _floats, _ieee, coefficients
from physics.systems.moving_mass.params import THRUSTERS

EPS_MAX = 0.1  # Omega^2 >> w^2
COUPLING_MAX = 0.1  # Omega^2 >> chi w
DECAY_MAX = 0.3  # chi w >> w^2: free oscillations die within a fraction of a revolution
DECAY = "|w0|/chi"
RE_MAX = 0.1  # Stokes flow in the cavity
SLOW_MAX = 0.1  # b/G and lambda small next to w
ASYM_MAX = 1e-9  # A = B
FAST_SPRING = "the spring is fast next to the spin"  # eps's words, here and in the error estimate's domain
SYMMETRIC = "the body is nearly symmetric (A close to B)"


THRUSTER = "control.law (a thruster fixed in the body)"


def thruster(sc: Scenario) -> bool:
    """The control is a thruster along a body axis (params.THRUSTERS): the averaged and closed forms brake along
    G only, so only the full model runs it."""
    return sc.control is not None and sc.control.law in THRUSTERS


@_ieee
def averaged_conditions(sc: Scenario) -> list[Condition]:
    co = coefficients(sc)
    w = co.omega0
    out = []
    if sc.mass is not None:
        ms = _floats(sc.mass)
        out.append(Condition("eps = |w0|/Omega", w / ms.Omega, EPS_MAX, FAST_SPRING))
        if ms.chi > 0:
            out.append(Condition("chi |w0| / Omega^2", ms.chi * w / ms.Omega**2, COUPLING_MAX,
                                 "the damping of the mass is light"))
        if sc.initial.mass_state != "quasistatic":  # "rest", or not given
            # the averaged model ignores the free oscillation a resting mass starts with
            decay = w / ms.chi if ms.chi > 0 else float("inf")
            out.append(Condition(f"{DECAY} (free oscillation decay)", decay, DECAY_MAX,
                                     "the mass's start-up wobble dies out quickly"))
    if sc.cavity is not None:
        out.append(Condition("Re = a0^2 |w0| / nu", sc.cavity.a0 * sc.cavity.a0 * w / sc.cavity.nu, RE_MAX,
                             "the fluid in the cavity flows slowly (viscous)"))
    if sc.medium is not None:
        out.append(Condition("lambda / |w0|", co.lam / w, SLOW_MAX, "the medium slows the spin only a little per turn"))
    if thruster(sc):
        out.append(Condition(THRUSTER, 1.0, 0.0, "the braking torque follows G (law K or Jw), not a body axis"))
    if sc.control is not None:
        out.append(Condition("b / (G0 |w0|)", co.b / (co.G0 * w), SLOW_MAX,
                             "the brake slows the spin only a little per turn"))
    out.append(Condition("|A - B| / A", abs(sc.body.A - sc.body.B) / sc.body.A, ASYM_MAX, SYMMETRIC))
    return out


def closed_form_available(sc: Scenario) -> tuple[bool, str]:
    """The closed forms cover seed 004 (viscous mass, cavity, medium, control) and seed 000
    section 2 (quadratic friction alone)."""
    if thruster(sc):
        return False, "a thruster fixed in the body has no closed form (the closed forms brake along G)"
    if sc.mass is not None and sc.mass.lam_q > 0:
        others = (sc.mass.chi > 0, sc.cavity is not None, sc.medium is not None, sc.control is not None)
        if any(others):
            return False, "quadratic friction has a closed form (seed 000 (2.11)) only on its own"
    return True, "closed form exists"


# the averaged conditions the error estimate does not cover (the study varies eps and the coupling chi |w0| /
# Omega^2, so those are the estimate's to judge; these it never saw)
STRUCTURAL = (DECAY, "Re", "lambda", "b /", "|A - B|", "control.law")


def structural_conditions(sc: Scenario) -> list[Condition]:
    """The averaged conditions that rule a cheaper model out whatever its error estimate says, held or not, and
    for a mass with quadratic friction, that there is none (the estimate is not calibrated for it)."""
    out = [c for c in averaged_conditions(sc) if c.name.startswith(STRUCTURAL)]
    if forced_response.applies(sc):
        # its estimate runs the full model over a resting mass's start-up wobble (forced_response.transient_time):
        # a slow decay is measured there, not ruled out
        out = [c for c in out if not c.name.startswith(DECAY)]
    if sc.mass is not None and sc.mass.lam_q > 0:
        # the estimate covers quadratic friction alone (the closed form (2.11) it reads its path from)
        alone, _ = closed_form_available(sc)
        out.append(Condition("lam_q with other dissipation (no calibrated error estimate)", sc.mass.lam_q,
                             math.inf if alone else 0.0,
                             "quadratic friction acts alone (no chi, cavity, medium or brake beside it)"))
    return out


def structural_failures(sc: Scenario) -> list[Condition]:
    """The structural conditions that fail."""
    return [c for c in structural_conditions(sc) if not c.holds]
