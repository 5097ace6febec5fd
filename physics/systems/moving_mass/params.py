"""The moving-mass system's tables: the mass, the cavity, the medium and the braking control, validated.

Names follow seed 004 and docs/models.md Part A section 1 (``rho``, ``Omega``, ``chi``, ``lambda_``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from physics.core.errors import ScenarioError
from physics.scenario.params import _choice, nonneg, positive

LAWS = ("K", "Jw")
# A thruster fixed in the body: the torque b along one body axis, whatever the motion (the braking challenge's
# hand control, which races the law above). The kernel's law code is the index in LAWS + THRUSTERS.
THRUSTERS = ("+e1", "-e1", "+e2", "-e2", "+e3", "-e3")
# initial.mass_state: "rest" puts the mass at O1 with no relative velocity (also when not given); "quasistatic" on
# its forced (slow-manifold) motion, docs/models.md Part A section 3. The key sits in the shared [initial] table (every
# shipped file and share link spells it so) but belongs to this system: System.initial_keys.
MASS_STATES = ("rest", "quasistatic")


def check_mass_state(sc) -> None:
    if sc.initial.mass_state is not None:
        _choice("initial.mass_state", sc.initial.mass_state, MASS_STATES)


@dataclass(frozen=True)
class Mass:
    """Point mass on an isotropic spring-damper at O1 = rho e3 (seed 004 eq. (4), seed 000 (1.1)).

    m: kg; rho: m; Omega = sqrt(c/m): rad/s; chi = delta/m: 1/s; lam_q = mu/m: 1/m (quadratic
    friction, force -mu |u'| u')."""

    m: float
    rho: float
    Omega: float
    chi: float = 0.0
    lam_q: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "m", positive("mass.m", self.m))
        object.__setattr__(self, "rho", nonneg("mass.rho", self.rho))
        object.__setattr__(self, "Omega", positive("mass.Omega", self.Omega))
        object.__setattr__(self, "chi", nonneg("mass.chi", self.chi))
        object.__setattr__(self, "lam_q", nonneg("mass.lam_q", self.lam_q))


@dataclass(frozen=True)
class Cavity:
    """Spherical cavity of radius a0 (m) filled with fluid of density beta (kg/m^3) and kinematic
    viscosity nu (m^2/s), in the Stokes (low Reynolds number) limit, seed 004 eq. (4), (6)."""

    beta: float
    nu: float
    a0: float

    def __post_init__(self):
        object.__setattr__(self, "beta", nonneg("cavity.beta", self.beta))
        object.__setattr__(self, "nu", positive("cavity.nu", self.nu))
        object.__setattr__(self, "a0", positive("cavity.a0", self.a0))
        if not math.isfinite(self.P):
            raise ScenarioError("cavity.a0", self.a0, f"must be at most {A0_MAX:.3g} m: the shape factor "
                                "8 pi a0^7 / 525 must stay finite")

    @property
    def P(self) -> float:
        """Shape factor P = 8 pi a0^7 / 525 of a spherical cavity (seed 004, after eq. (4))."""
        a0 = self.a0
        return 8.0 * math.pi * (a0 * a0 * a0 * a0 * a0 * a0 * a0) / 525.0  # a product: inf, not OverflowError

    @property
    def coupling(self) -> float:
        """beta P / nu, kg m^2 s: the cavity's relative momentum is -coupling * w' (docs/models.md A.3)."""
        return self.beta * self.P / self.nu


@dataclass(frozen=True)
class Medium:
    """Linear resistance of the medium, torque -lambda J* w, seed 004 eq. (2). lambda_: 1/s."""

    lambda_: float

    def __post_init__(self):
        object.__setattr__(self, "lambda_", nonneg("medium.lambda", self.lambda_))


def with_thruster(sc, thruster: str | None, b: float):
    """``sc`` with the thruster ``thruster`` (one of THRUSTERS) firing a torque ``b`` (N m), or none: the control's
    torque 0 under a brake's law (the scene's, else "K"), so that a b set later brakes as in any scene. The braking
    challenge's student switches with it (app.engine.challenge)."""
    if thruster is not None:
        _choice("control.law", thruster, THRUSTERS)
        return sc.replace(control=Control(b=b, law=thruster))
    law = sc.control.law if sc.control is not None and sc.control.law in LAWS else LAWS[0]
    return sc.replace(control=Control(b=0.0, law=law))


@dataclass(frozen=True)
class Control:
    """Time-optimal braking torque -b G/|G| (seed 004 eq. (8)); b in N m. ``law`` says which G:
    "K" the total angular momentum, "Jw" the fictitious body's J* w; or one of THRUSTERS, a torque b along
    that body axis (not a brake: it turns with the body, and only the full model runs it)."""

    b: float
    law: str = "K"

    def __post_init__(self):
        object.__setattr__(self, "b", nonneg("control.b", self.b))
        _choice("control.law", self.law, LAWS + THRUSTERS)


A0_MAX = 1.7e308 ** (1 / 7) * (525.0 / (8.0 * math.pi)) ** (1 / 7)  # m: where the cavity's shape factor P overflows
