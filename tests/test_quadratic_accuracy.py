"""Quadratic friction's error estimate (issue 23): the moving mass's estimate, judged by the viscous damping with
the same slow rate at the start, covers the mass against quadratic friction alone, where the closed form of seed
000 section 2 gives the path; with any other dissipation beside it there is no closed form and no claim."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import physics
from physics.systems.moving_mass.accuracy import domain, equivalent_chi
from physics.systems.moving_mass.closed000 import quadratic_friction_theta
from physics.systems.moving_mass.closed004 import nutation_rate_13

ROOT = Path(__file__).resolve().parents[1]
PRESET = ROOT / "assets" / "scenarios" / "quadratic_friction.toml"


def _scenario(C: float = 0.5, theta0: float = 0.3, lam_q: float = 16000.0, **extra) -> physics.Scenario:
    data = {"body": {"A": 1.0, "C": C, "M": 1.0},
            "mass": {"m": 0.1, "rho": 1.5, "Omega": 20.0, "lam_q": lam_q},
            "initial": {"G0": 1.0, "theta0": theta0, "mass_state": "quasistatic"},
            "run": {"t_end": 2e4, "samples": 201}}
    for key, value in extra.items():
        data.setdefault(key.split(".")[0], {})[key.split(".")[1]] = value
    return physics.Scenario.from_dict(data)


@pytest.mark.parametrize("C,theta0", [(0.5, 0.3), (1.4, 0.8), (0.8, 1.2), (1.1, 0.05)])
def test_the_equivalent_chi_gives_seed_004s_viscous_rate_the_quadratic_rate_of_seed_000(C, theta0):
    """Seed 004's (13) with chi = chi_eq against the slope of seed 000's (2.11) closed form at t = 0, taken by a
    finite difference of the inverted invariant: two papers' formulas, one rate."""
    sc = _scenario(C=C, theta0=theta0)
    co = physics.coefficients(sc)
    ms = sc.mass
    chi = equivalent_chi(sc)
    D = ms.m * ms.rho**2 * chi * co.C**3 * (co.A - co.C) / (ms.Omega**4 * co.A**4)
    viscous = float(nutation_rate_13(co.theta0, co.G0, co.A, co.C, 0.0, D))
    h = 1e-5 * co.theta0 / abs(viscous)  # theta moves by 1e-5 of itself: the difference is the slope to ~1e-5
    th = quadratic_friction_theta(np.array([0.0, h]), co.theta0, co.gamma)
    quadratic = (th[1] - th[0]) / h
    assert viscous != 0.0 and quadratic == pytest.approx(viscous, rel=1e-4)


def test_quadratic_friction_alone_gets_an_estimate_and_the_domain_reads_its_equivalent_chi():
    sc = physics.Scenario.load(PRESET)
    d = physics.derived(sc)
    assert math.isfinite(d["averaged_error_bound"]) and math.isfinite(d["closed_error_bound"])
    chi = next(c for c in domain(sc) if c.name == "chi / Omega")
    assert chi.value == pytest.approx(equivalent_chi(sc) / sc.mass.Omega)
    # far more friction: the equivalent damping leaves the calibrated range and the claim goes with it
    strong = sc.with_values(**{"mass.lam_q": 40 * sc.mass.lam_q})
    assert math.isinf(physics.derived(strong)["averaged_error_bound"])


@pytest.mark.parametrize("extra", [{"mass.chi": 5.0}, {"medium.lambda": 1e-6}, {"cavity.beta": 100.0,
                                                                                  "cavity.nu": 20.0,
                                                                                  "cavity.a0": 0.1}])
def test_quadratic_friction_beside_other_dissipation_has_no_estimate_and_says_which_condition(extra):
    sc = _scenario(**extra)
    d = physics.derived(sc)
    assert math.isinf(d["averaged_error_bound"])
    failed = [c for c in physics.validity_conditions(sc) if not c.holds]
    assert any(c.name.startswith("lam_q with other dissipation") for c in failed), failed


def test_the_damping_conditions_speak_of_the_friction_not_of_a_chi_the_slider_shows_as_0():
    """The explorer shows each condition's sentence beside the sliders, where chi reads 0 under quadratic friction
    alone: the sentence says the friction's viscous equivalent is what is judged. The viscous mass's say chi."""
    quad = {c.name: c.sentence for c in domain(_scenario())}
    viscous = {c.name: c.sentence for c in domain(_scenario(lam_q=0.0, **{"mass.chi": 5.0}))}
    for name in ("Omega / chi", "chi / Omega"):
        assert "friction" in quad[name] and "the viscous chi of its slow rate" in quad[name], quad[name]
        assert "damper" in viscous[name] and "(chi at" in viscous[name], viscous[name]
