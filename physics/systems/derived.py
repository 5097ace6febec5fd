"""Derived quantities for ``python -m physics info`` and ``physics.derived``: the scenario's system gives its
own (the papers' coefficients, T, eps, Re; a pendulum's linear theory), and every scenario gets ``auto``'s
choice with its reason and error estimates."""

from __future__ import annotations

import math

from physics.core.blame import guarded
from physics.kernels.build import pick
from physics.registry import get_system
from physics.scenario import arguments
from physics.scenario.params import FIXED_STEP_METHODS
from physics.scenario.scenario import Scenario
from physics.systems.choice import choose_fidelity
from physics.systems.method import method_label


def derived(sc: Scenario) -> dict[str, float | str]:
    """Derived quantities by name; the ``auto_*`` keys (``auto_choice``) say which model and method fidelity
    ``auto`` runs, the requested accuracy, the estimated error bound and the reason. Arithmetic that fails on
    extreme input raises NumericalFault naming a key."""
    arguments.scenario(sc)
    with guarded(sc, "computing the derived quantities"):
        out = dict(get_system(sc.system).derived(sc))
        out.update(auto_choice(sc))
        return out


def _method_text(sc: Scenario, fidelity: str) -> str:
    """The integrator a run of this fidelity and [run] method uses, as its Stepper names it (with the live run's
    kernel picker: the interpreted twin while the compiled kernels are built), and its setting."""
    run = sc.run
    model = get_system(sc.system).models[fidelity]
    if model.solve is not None:
        return "closed form (no integrator)"
    setting = f"dt = {run.dt:g} s" if run.method in FIXED_STEP_METHODS else f"rtol = {run.rtol:g}"
    return f"{method_label(model, run.method, pick)}, {setting}"


def auto_choice(sc: Scenario) -> dict[str, float | str]:
    """What fidelity ``auto`` runs for ``sc`` and why, as the keys of ``physics.derived``:

    - auto_fidelity, auto_model (registry name), auto_method (integrator and its setting);
    - auto_accuracy: the requested theta accuracy ``run.accuracy`` (rad), or "not set" (auto then uses
      physics.systems.choice.DEFAULT_ACCURACY);
    - averaged_error_bound, closed_error_bound: each cheaper model's estimated max |theta - theta_full| over
      [0, t_end] (rad), for every cheaper fidelity the system has (inf where it states no estimate: outside the
      conditions its estimate was calibrated on);
    - auto_error_bound: that estimate for the chosen model (0 when the full model is chosen: it is the
      reference, with only the integrator's error, set by rtol);
    - error_bound_method: how the estimates were obtained (the system's ``error_method``);
    - auto_reason: the chooser's sentence (conditions, or estimate against the accuracy).
    """
    system = get_system(sc.system)
    fid, reason = choose_fidelity(sc)
    out: dict[str, float | str] = dict(auto_fidelity=fid, auto_model=f"{sc.system}/{fid}",
                                       auto_method=_method_text(sc, fid))
    out["auto_accuracy"] = sc.run.accuracy if sc.run.accuracy is not None else "not set"
    for cheaper in system.fidelities[1:]:
        if cheaper == "full":
            continue
        bound = system.error_bounds(sc, cheaper)
        out[f"{cheaper}_error_bound"] = math.inf if bound is None else bound
    if len(system.fidelities) > 2:
        out["auto_error_bound"] = 0.0 if fid == "full" else out[f"{fid}_error_bound"]
        out["error_bound_method"] = system.error_method or "none stated"
    out["auto_reason"] = reason
    return out
