"""Which model runs a scenario: the validity conditions and ``auto``'s choice, asked of the scenario's system.

The one place a fidelity name becomes a Model (``resolve``), used by ``simulate``, ``LiveRun`` and the studies.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

from physics.core.budget import MAX_STEPS
from physics.core.errors import ScenarioError, ValidityWarning
from physics.registry import FIDELITY_ORDER, Condition, Model, get_model, get_system
from physics.scenario import arguments
from physics.systems.cost import estimated_steps


def conditions(sc) -> list[Condition]:
    """The validity conditions of the scenario's cheaper (averaged) model."""
    return get_system(sc.system).conditions(sc)


def choose_fidelity(sc) -> tuple[str, str]:
    """The cheapest model ``auto`` trusts for ``sc``, and why (the system's own rule; with ``run.accuracy``
    the cheapest whose error estimate meets it, where the system has estimates), within the step budget
    (``choose``)."""
    arguments.scenario(sc)
    choice = choose(sc)
    return choice.fidelity, choice.reason


@dataclass(frozen=True)
class Choice:
    """``auto``'s pick: the fidelity, why, and the estimated steps (physics/systems/cost.py) of the models it
    weighed: the one it picked and, when that would exceed the budget, the full model (None: no estimate)."""

    fidelity: str
    reason: str
    steps: dict[str, float | None]


def choose(sc) -> Choice:
    """The system's pick (``System.pick``), unless its estimated steps exceed MAX_STEPS. Then, among the other
    models available for ``sc``: the cheapest (``System.cheapest_first``) whose error estimate meets the accuracy
    and that fits the budget, else the most accurate (dearest first, FIDELITY_ORDER) that fits; the reason names
    its error estimate (or none) and the full model's steps. When no model fits, the pick stands and the run says
    why it cannot."""
    system = get_system(sc.system)
    fid, reason = system.pick(sc)
    steps = {fid: estimated_steps(sc, fid)}
    if _fits(steps[fid], unknown=True):
        return Choice(fid, reason, steps)
    steps.setdefault("full", estimated_steps(sc, "full"))
    over = f"{_steps_text(fid, steps[fid])}, more than the budget of {MAX_STEPS:.2g} per run"
    if fid != "full":
        over += f" ({_steps_text('the full model', steps['full'])})"
    others = [f for f in FIDELITY_ORDER if f != fid and f in system.models and system.available(sc, f)[0]]
    tol, asked = _accuracy(sc)
    fitting = []
    for f in others:
        steps[f] = estimated_steps(sc, f)
        if _fits(steps[f], unknown=False):
            fitting.append(f)
    for f in system.cheapest_first(sc):
        est = system.error_bounds(sc, f) if f in fitting else None
        if est is not None and est <= tol:
            return Choice(f, f"{over}: {f} runs, the cheapest model that fits with its error estimate "
                             f"{est:.2g} rad <= {asked}", steps)
    if fitting:
        f = fitting[0]
        est = system.error_bounds(sc, f)
        said = (f"its error estimate {est:.2g} rad > {asked}" if est is not None and math.isfinite(est) else
                f"no error estimate here, so no promise of {asked}")
        return Choice(f, f"{over}: {f} runs, the most accurate model that fits ({steps[f]:.2g} steps), with "
                         f"{said}; auto would otherwise run {fid}: {reason}", steps)
    return Choice(fid, f"{reason}; {over}, and no other model fits", steps)


def _steps_text(who: str, steps: float | None) -> str:
    who = "the full model" if who == "full" else who
    return f"{who} would need about {steps:.2g} steps" if steps is not None else f"{who}: no step estimate"


def _fits(steps: float | None, unknown: bool) -> bool:
    """Whether estimated ``steps`` are within MAX_STEPS; ``unknown`` is the answer when there is no estimate."""
    return unknown if steps is None else steps <= MAX_STEPS


def _accuracy(sc) -> tuple[float, str]:
    """auto's accuracy in theta (rad) for ``sc`` and how to say it."""
    tol = sc.run.accuracy if sc.run.accuracy is not None else DEFAULT_ACCURACY
    return tol, f"accuracy {tol:g} rad" + ("" if sc.run.accuracy is not None else " (the default; set run.accuracy)")


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
    steps: dict[str, float | None] | None = None  # auto's estimated steps (Choice.steps); None when requested


def resolve(sc, fidelity: str | None = None, *, warn: bool = False) -> Resolved:
    """The model that runs ``sc`` at ``fidelity`` (default: its ``run.fidelity``; ``auto`` resolved). Raises
    ScenarioError, naming run.fidelity, when the system has no such model or it does not cover ``sc``. With
    ``warn``, a cheaper model asked for outside its validity conditions runs with a ValidityWarning."""
    fid = fidelity or sc.run.fidelity
    reason, steps = "requested", None
    if fid == "auto":
        choice = choose(sc)
        fid, reason, steps = choice.fidelity, choice.reason, choice.steps
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
    return Resolved(get_model(sc.system, fid).for_scenario(sc), fid, reason, steps)


# auto's accuracy in theta (rad) when the scenario sets no run.accuracy: the 1e-3 rad the averaged model's
# validity limits promised before issue 15, and where auto's wall time over the fidelity studies stays within
# 1.7x of an oracle's (at 1e-2 it is 2.1x-3.5x: bench/results/fidelity.meta.json, docs/models.md A.5)
DEFAULT_ACCURACY = 1e-3


def cheapest_within(sc, failed) -> tuple[str, str]:
    """``auto``'s pick from error estimates: the cheapest available model (the system's ``cheapest_first``) whose
    estimate (its ``error_bounds``) is at most ``run.accuracy`` (DEFAULT_ACCURACY when unset), else the full model.
    ``failed``: the structural conditions that do not hold (their estimates do not cover them), which rule out
    every cheaper model."""
    system = get_system(sc.system)
    tol, asked = _accuracy(sc)
    if failed:
        return "full", "conditions fail: " + "; ".join(map(str, failed))
    worst = None
    for fid in system.cheapest_first(sc):
        if fid not in system.models or not system.available(sc, fid)[0]:
            continue
        est = system.error_bounds(sc, fid)
        if est is None:
            continue
        if est <= tol:
            return fid, f"{fid} error estimate {est:.2g} rad <= {asked}"
        worst = worst or f"{fid} error estimate {est:.2g} rad > {asked}"
    return "full", worst or "no cheaper model has an error estimate here"
