"""Which model runs a scenario: the validity conditions and ``auto``'s choice, asked of the scenario's system.

The one place a fidelity name becomes a Model (``resolve``), used by ``simulate``, ``LiveRun`` and the studies.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

from physics.core.errors import ScenarioError, ValidityWarning
from physics.registry import Condition, Model, get_model, get_system


def conditions(sc) -> list[Condition]:
    """The validity conditions of the scenario's cheaper (averaged) model."""
    return get_system(sc.system).conditions(sc)


def choose_fidelity(sc) -> tuple[str, str]:
    """The cheapest model ``auto`` trusts for ``sc``, and why (the system's own rule; with ``run.accuracy``
    the cheapest whose error estimate meets it, where the system has estimates)."""
    return get_system(sc.system).pick(sc)


def available(sc, fidelity: str) -> tuple[bool, str]:
    """Whether the scenario's system has a model of ``fidelity`` that covers ``sc``, and why not."""
    system = get_system(sc.system)
    if fidelity not in system.models:
        return False, f"{system.name} has: " + ", ".join(system.fidelities[1:])
    return system.available(sc, fidelity)


@dataclass(frozen=True)
class Resolved:
    """Which model runs a scenario, and why."""

    model: Model
    fidelity: str
    reason: str


def resolve(sc, fidelity: str | None = None, *, warn: bool = False) -> Resolved:
    """The model that runs ``sc`` at ``fidelity`` (default: its ``run.fidelity``; ``auto`` resolved). Raises
    ScenarioError, naming run.fidelity, when the system has no such model or it does not cover ``sc``. With
    ``warn``, a cheaper model asked for outside its validity conditions runs with a ValidityWarning."""
    fid = fidelity or sc.run.fidelity
    reason = "requested"
    if fid == "auto":
        fid, reason = choose_fidelity(sc)
    ok, why = available(sc, fid)
    if not ok:
        if fid not in get_system(sc.system).models:
            raise ScenarioError("run.fidelity", fid, f"is not available for {sc.system}; it has: "
                                + ", ".join(get_system(sc.system).fidelities[1:]))
        raise ScenarioError("run.fidelity", fid, f"is not available for this scenario: {why}")
    if warn and reason == "requested" and fid != "full":
        failed = [str(c) for c in conditions(sc) if not c.holds]
        if failed:
            warnings.warn(f"the {fid} model is outside its validity conditions: " + "; ".join(failed),
                          ValidityWarning, stacklevel=3)
    return Resolved(get_model(sc.system, fid), fid, reason)


# auto's accuracy in theta (rad) when the scenario sets no run.accuracy: the 1e-3 rad the averaged model's
# validity limits promised before issue 15, and where auto's wall time over the calibration study stays within
# 2x of an oracle's (at 1e-2 it is 4x: bench/results/fidelity.meta.json)
DEFAULT_ACCURACY = 1e-3
CHEAPEST_FIRST = ("closed", "averaged")


def cheapest_within(sc, failed) -> tuple[str, str]:
    """``auto``'s pick from error estimates: the cheapest available model whose estimate (the system's
    ``error_bounds``) is at most ``run.accuracy`` (DEFAULT_ACCURACY when unset), else the full model. ``failed``:
    the structural conditions that do not hold (their estimates do not cover them), which rule out every
    cheaper model."""
    system = get_system(sc.system)
    tol = sc.run.accuracy if sc.run.accuracy is not None else DEFAULT_ACCURACY
    asked = f"accuracy {tol:g} rad" + ("" if sc.run.accuracy is not None else " (the default; set run.accuracy)")
    if failed:
        return "full", "conditions fail: " + "; ".join(map(str, failed))
    worst = None
    for fid in CHEAPEST_FIRST:
        if fid not in system.models or not system.available(sc, fid)[0]:
            continue
        est = system.error_bounds(sc, fid)
        if est is None:
            continue
        if est <= tol:
            return fid, f"{fid} error estimate {est:.2g} rad <= {asked}"
        worst = worst or f"{fid} error estimate {est:.2g} rad > {asked}"
    return "full", worst or "no cheaper model has an error estimate here"
