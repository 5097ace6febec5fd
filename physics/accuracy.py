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

from .coefficients import coefficients
from .scenario import Scenario

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
    from .validity import averaged_conditions, closed_form_available

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


def _method_text(sc: Scenario, fidelity: str) -> str:
    """The integrator ``simulate`` runs for this fidelity and [run] method, with its setting."""
    run = sc.run
    if fidelity == "closed":
        return "closed form (no integrator)"
    if run.method == "auto":
        return f"DOP853 (compiled), rtol = {run.rtol:g}"
    if run.method in ("RK4", "RK8", "midpoint"):
        return f"{run.method} (compiled), dt = {run.dt:g} s"
    return f"scipy {run.method}, rtol = {run.rtol:g}"


def auto_choice(sc: Scenario) -> dict[str, float | str]:
    """What fidelity ``auto`` runs for ``sc`` and why, as the keys of ``physics.derived``:

    - auto_fidelity, auto_model (registry name), auto_method (integrator and its setting);
    - auto_accuracy: the requested theta accuracy ``run.accuracy`` (rad), or "not set";
    - averaged_error_bound: the averaged model's estimated max theta error against the full model
      (rad, ``averaged_error_bound``; moving-mass scenarios with a mass only);
    - auto_error_bound: that bound for the chosen model (0 when the full model is chosen: it is the
      reference, with only the integrator's error, set by rtol);
    - auto_reason: the chooser's sentence (conditions, or bound against the requested accuracy).
    """
    from .validity import choose_fidelity

    fid, reason = choose_fidelity(sc)
    out: dict[str, float | str] = dict(auto_fidelity=fid, auto_model=f"{sc.system}/{fid}",
                                       auto_method=_method_text(sc, fid))
    out["auto_accuracy"] = sc.run.accuracy if sc.run.accuracy is not None else "not set"
    if sc.system == "moving_mass" and sc.mass is not None:
        bound = averaged_error_bound(sc)
        out["averaged_error_bound"] = bound
        out["auto_error_bound"] = 0.0 if fid == "full" else bound
    out["auto_reason"] = reason
    return out
