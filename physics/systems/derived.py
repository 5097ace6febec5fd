"""Derived quantities for ``python -m physics info`` and ``physics.derived``: the scenario's system gives its
own (the papers' coefficients, T, eps, Re; a pendulum's linear theory), and every scenario gets ``auto``'s
choice with its reason and error estimates."""

from __future__ import annotations

from physics.core.blame import guarded
from physics.registry import get_system
from physics.scenario.scenario import Scenario
from physics.systems.choice import choose_fidelity


def derived(sc: Scenario) -> dict[str, float | str]:
    """Derived quantities by name; the ``auto_*`` keys (``auto_choice``) say which model and method fidelity
    ``auto`` runs, the requested accuracy, the estimated error bound and the reason. Arithmetic that fails on
    extreme input raises NumericalFault naming a key."""
    with guarded(sc, "computing the derived quantities"):
        out = dict(get_system(sc.system).derived(sc))
        out.update(auto_choice(sc))
        return out


def _method_text(sc: Scenario, fidelity: str) -> str:
    """The integrator ``simulate`` runs for this fidelity and [run] method, with its setting."""
    run = sc.run
    if get_system(sc.system).models[fidelity].solve is not None:
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
    - averaged_error_bound: the averaged model's estimated max theta error against the full model (rad),
      where the system gives one;
    - auto_error_bound: that estimate for the chosen model (0 when the full model is chosen: it is the
      reference, with only the integrator's error, set by rtol);
    - auto_reason: the chooser's sentence (conditions, or bound against the requested accuracy).
    """
    system = get_system(sc.system)
    fid, reason = choose_fidelity(sc)
    out: dict[str, float | str] = dict(auto_fidelity=fid, auto_model=f"{sc.system}/{fid}",
                                       auto_method=_method_text(sc, fid))
    out["auto_accuracy"] = sc.run.accuracy if sc.run.accuracy is not None else "not set"
    bound = system.error_bounds(sc, "averaged")
    if bound is not None:
        out["averaged_error_bound"] = bound
        out["auto_error_bound"] = 0.0 if fid == "full" else bound
    out["auto_reason"] = reason
    return out
