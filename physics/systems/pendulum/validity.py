"""Where the spherical pendulum's averaged model may run, its error estimate, and ``auto``'s choice (issue 15).

Since issue 15 the averaged model's error is estimated (``accuracy.averaged_error_bound``: the detuning, the
coupling, the damping, the amplitude nonlinearity and the horizon are all in it), so the old limits of docs/models.md
B.10 on those no longer block it: ``auto`` runs it when the estimate meets run.accuracy. What remains are the
structural conditions the estimate cannot cover: a spring (the model averages about omega_0), a nearly
symmetric carrier (its equations are for A = B; the estimate was calibrated for |A - B|/A up to 0.1), and the
domain the estimate was calibrated on, stated in the pendulum's
own swing amplitude from linear theory (not theta0: in weakly coupled cases the bob swings ~6 times theta0):
the swing itself, and the amplitude-dependent detuning it causes against the resonance's width; and the
coupling mu D^2/A.
"""

from __future__ import annotations

import math

import numpy as np

from physics.registry import Condition
from physics.scenario.scenario import Scenario
from physics.systems.choice import cheapest_within
from physics.systems.pendulum.accuracy import (
    SAFETY,
    SAFETY_LINEAR,
    SAFETY_PREDICTED,
    SWING_MAX,
    averaged_error_bound,
    scenario_parts,
)
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.pendulum.linear import spherical_linear

# |A - B| / A: the averaged equations are for a symmetric carrier (they take A as the mean of A and B), and the
# estimate's linear part is the exact linear theory of the asymmetric one; over the 133 scenarios with B/A in
# 1.01-1.1 of eight studies (docs/models.md B.10) the estimate held (worst actual / unscaled estimate 0.96, against
# 1.51 for symmetric carriers), so the limit is the studies' range, where it was 1e-9
ASYM_MAX = 0.1
# the amplitude-dependent detuning (from the bob's swing in linear theory and theta0) over the resonance's width:
# the calibration studies' range (their largest 56.5, seeds 15, 101, 202, 303). Beyond 1 the nonlinearity can pull
# the pendulum across the resonance; since the detuning gap reads the resonance too (accuracy.parts), the unscaled
# estimate held there in all 138 such scenarios of six seeds (worst 0.98; read at the ends only it missed by up to
# 2.4x, and this limit was 1). Most are off by more than 1e-2 rad: the estimate says so instead of nothing
NONLINEAR_MAX = 60.0
COUPLING_MAX = 0.02  # mu D^2 / A: the calibration study's range (its largest were 0.014-0.018)

# derived's ``error_bound_method`` and the explorer's badge: how the estimate is obtained, in one sentence
METHOD = ("the averaged model's distance from the exact linear theory plus its change under the amplitude-"
          "dependent detuning (spin-up W theta0^2/2, the bob's swing from linear theory or at resonance, where "
          "it can jump there) and, on an asymmetric carrier, its free nutation's departure from the linear one, "
          "over [0, t_end], "
          f"each times a safety factor ({SAFETY_LINEAR:g} on the linear part, {SAFETY:g} on the nonlinear), or, "
          "where smaller and the bob has one steady swing, its distance from the full equations averaged "
          f"numerically times {SAFETY_PREDICTED:g}; the factors calibrated against the full model (python -m bench "
          "fidelity, docs/models.md)")


def averaged_conditions(sc: Scenario) -> list[Condition]:
    """The averaged model's structural conditions (module docstring); the swing is computed only when the
    others hold (it needs the spring)."""
    system = pendulum_system(sc)
    A, B, _ = np.diag(system.I_c)
    p = spherical_linear(system)
    if not p.omega0 > 0:  # no spring: no resonance to average about
        return [Condition("1/omega_0 (k = 0: no spring frequency)", math.inf, 0.0, "the pendulum has a spring")]
    out = [Condition("|A - B| / A", abs(A - B) / A, ASYM_MAX,
                     "the body's transverse moments differ by at most the calibrated 10 %"),
           Condition("mu D^2 / A", p.coupling, COUPLING_MAX, "the pendulum is light next to the body")]
    if all(c.holds for c in out):
        q = scenario_parts(sc, predict=False)  # the swing and the detuning: no prediction needed to judge them
        if not math.isfinite(q.a):  # far from resonance the averaged model may even grow, and overflow over t_end
            return out + [Condition("error estimate finite over t_end (a model's mode grows)", math.inf, 0.0,
                                    "the motion stays bounded over the run")]
        out += [Condition("pendulum swing (linear theory, rad)", q.a, SWING_MAX,
                          "the pendulum's own swing stays moderate"),
                Condition("amplitude detuning / resonance width", q.shift / q.width if q.width > 0 else math.inf,
                          NONLINEAR_MAX, "the swing detunes the pendulum no further than the calibrated range")]
    return out


def error_bounds(sc: Scenario, fidelity: str) -> float | None:
    """The averaged model's estimated max |theta - theta_full| over [0, t_end] (rad), None for any other
    fidelity or where a structural condition fails (the estimate was not calibrated there)."""
    if fidelity != "averaged" or not all(c.holds for c in averaged_conditions(sc)):
        return None
    return averaged_error_bound(sc)


def choose(sc: Scenario) -> tuple[str, str]:
    """``auto``'s pick: the averaged model when its structural conditions hold and its estimate meets
    run.accuracy (physics.systems.choice.DEFAULT_ACCURACY when unset), else the full model, and why."""

    return cheapest_within(sc, [c for c in averaged_conditions(sc) if not c.holds])
