"""Fidelity ``auto`` against a requested accuracy: the cheapest model whose measured error bound
meets ``run.accuracy`` (rad, in theta) and whose structural validity conditions hold.

The averaged model's theta error is O(eps^2), eps = |w0|/Omega, uniformly over the slow time scale
(MODELS.md A.5). Its coefficient was measured against the full model (MODELS A.5 and A.7(a), prolate
C = 0.5, theta 0.3 -> 1.03, |w0| = 1.913 Omega eps_table): max error / eps^2 = 0.0101, 0.0216, 0.0656,
0.109 at m/M = 0, 0.1, 0.3, 0.5; oblate (C = 1.4, |w0| = 0.926 Omega eps_table) is 0.517 at m/M = 0.1.
``python -m bench stability`` maps it over theta0 too: at eps = 0.1 (prolate) theta0 = 1 gives 4x the
theta0 = 0.3 coefficient, hence SAFETY.
"""

from __future__ import annotations

import numpy as np

from physics.scenario.scenario import Scenario
from physics.systems.moving_mass.coefficients import coefficients

ETA_POINTS = (0.0, 0.1, 0.3, 0.5)  # m/M of the measured coefficients
PROLATE_COEFF = (0.0101, 0.0216, 0.0656, 0.109)  # max |theta_full - theta_avg| / eps^2, MODELS A.5
OBLATE_FACTOR = 0.517 / 0.0216  # oblate / prolate at m/M = 0.1, MODELS A.7(a)
SAFETY = 5.0  # theta0 and shape spread beyond the measured cases (bench validity map: 4x)


def averaged_error_bound(sc: Scenario) -> float:
    """Bound on max |theta_full - theta_averaged| (rad) for a moving-mass scenario."""
    eps = coefficients(sc).omega0 / sc.mass.Omega
    eta = sc.mass.m / sc.body.M
    c = float(np.interp(eta, ETA_POINTS, PROLATE_COEFF, right=PROLATE_COEFF[-1] * eta / ETA_POINTS[-1]))
    if sc.body.C > sc.body.A:
        c *= OBLATE_FACTOR
    return SAFETY * c * eps**2


def choose_for_accuracy(sc: Scenario) -> tuple[str, str] | None:
    """(fidelity, reason) for ``run.accuracy``, or None when this chooser does not cover the system."""
    from physics.systems.moving_mass.validity import averaged_conditions, closed_form_available

    tol = sc.run.accuracy
    if tol is None or sc.system != "moving_mass" or sc.mass is None:
        return None
    bound = averaged_error_bound(sc)
    # the eps condition is replaced by the measured error bound; the structural ones still apply
    failed = [c for c in averaged_conditions(sc) if not c.holds and not c.name.startswith("eps")]
    if failed:
        return "full", "averaged conditions fail: " + "; ".join(map(str, failed))
    if bound > tol:
        return "full", f"averaged error bound {bound:.2g} rad > requested accuracy {tol:g} rad"
    ok, why = closed_form_available(sc)
    fid = "closed" if ok else "averaged"
    return fid, f"averaged error bound {bound:.2g} rad <= requested accuracy {tol:g} rad; {why}"
