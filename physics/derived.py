"""Derived quantities for ``python -m physics info``: the papers' coefficients, T, eps, Re, and
the fidelity ``auto`` would choose, with its reason. Pendulum scenarios get their linear theory
instead (frequencies, tuning, decay rate and e-folding time; ``pendulum_linear_general``)."""

from __future__ import annotations

import math

from .accuracy import auto_choice
from .blame import guarded
from .coefficients import coefficients
from .scenario import Scenario


def derived(sc: Scenario) -> dict[str, float | str]:
    """Derived quantities by name; the ``auto_*`` keys (physics/accuracy.py ``auto_choice``) say
    which model and method fidelity ``auto`` runs, the requested accuracy, the estimated error
    bound and the reason. Arithmetic that fails on extreme input raises NumericalFault naming a key."""
    with guarded(sc, "computing the derived quantities"):
        return _derived(sc)


def _derived(sc: Scenario) -> dict[str, float | str]:
    if sc.system != "moving_mass":  # the pendulum dampers of seed 002: their linear theory
        from .pendulum_linear_general import pendulum_derived

        out = pendulum_derived(sc)
        out.update(auto_choice(sc))
        return out
    from .closed import braking_time

    co = coefficients(sc)
    out: dict[str, float | str] = dict(F=co.F, D=co.D, L=co.L, H=co.H, P=co.P)
    out.update(Gamma1=co.Gamma1, Gamma2=co.Gamma2, k_star=co.k_star)
    out["T"] = braking_time(co.G0, co.b, co.lam) if co.b > 0 else math.inf
    out["G0"] = co.G0
    out["theta0"] = co.theta0
    out["eps"] = co.omega0 / sc.mass.Omega if sc.mass else 0.0
    out["Re"] = sc.cavity.a0 * sc.cavity.a0 * co.omega0 / sc.cavity.nu if sc.cavity else 0.0
    out.update(auto_choice(sc))
    return out
