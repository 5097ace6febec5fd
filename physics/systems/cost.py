"""What a model costs on a scenario, in steps, before it runs: what ``auto`` weighs against the step budget.

A closed form costs no steps. A fixed step costs t_end / dt. The adaptive method (DOP853) is probed: PROBE_STEPS
steps from the scenario's initial state with the run's own tolerances, in two halves, and the second half's pace
(steps per second of model time, the step size having settled) is carried to t_end; the output times are added,
since the integrator lands a step on each. That pace is what the run's
own budget check reads (physics/stepping/simulate.py ``_check_pace``: steps so far over time covered), so a run
whose probe fits is one whose pace check passes as long as its step size stays what it was at the start: the
fast time scales of these models (the spring's Omega, the spin, the pendulum's swing) are set by the
parameters and |G|, which dissipation only lowers. A problem too stiff for DOP853 shows the same way: its step
is held at the stability limit from the first steps, and its estimate is the count it would never finish.

The probe calls the compiled integrator directly (as the studies do): a few hundred steps, milliseconds. While
the compiled kernels are being built (the explorer's first minute, ``physics.kernels.build``) only the
interpreted twin runs, at 1-2 s a probe: too slow for a slider, and a shorter probe reads the pace up to 3.4x low
(measured with 40 steps on the shipped scenarios), so there is no estimate then (None, not kept; auto's pick
stands, as it did before it knew costs; the command line never builds in the background, so it always has one).
Nor is there one for a model with a Python right-hand side (``Model.py_rhs``), which only the interpreted
integrator steps. Estimates are cached per (scenario, fidelity): the explorer asks on every slider change.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from physics.compiled import dispatch, dop853
from physics.core.tolerance import atol_for
from physics.kernels.build import compiled_ready
from physics.registry import get_model
from physics.scenario.params import FIXED_STEP_METHODS

PROBE_STEPS = 400  # two halves: the first lets the step-size control settle, the second's pace is carried on


def brake_and_medium(sc) -> tuple[float, float]:
    """(b, lambda): the braking torque and the medium's resistance (0 where the system has neither table)."""
    control, medium = getattr(sc, "control", None), getattr(sc, "medium", None)
    return (float(control.b) if control else 0.0), (float(medium.lambda_) if medium else 0.0)


def estimated_steps(sc, fidelity: str) -> float | None:
    """The steps the model of ``fidelity`` takes over [0, run.t_end] of ``sc`` (module docstring): 0 for a
    closed form, None where the probe cannot tell (it ended in a fault, which the run itself will report) or
    cannot run fast (the compiled kernels are being built; a Python right-hand side)."""
    if not compiled_ready():  # not kept: once the kernels are built, the probe answers
        return _estimate(sc, fidelity)
    try:
        return _cached(sc, fidelity)
    except TypeError:  # a scenario that cannot be hashed (an array in it): estimated afresh
        return _estimate(sc, fidelity)


@lru_cache(maxsize=256)
def _cached(sc, fidelity: str) -> float | None:
    return _estimate(sc, fidelity)


def _estimate(sc, fidelity: str) -> float | None:
    model = get_model(sc.system, fidelity).for_scenario(sc)
    if model.solve is not None:
        return 0.0
    t_end = float(sc.run.t_end)
    if sc.run.method in FIXED_STEP_METHODS and sc.run.dt is not None:
        return float(math.ceil(t_end / float(sc.run.dt)))
    if model.py_rhs is not None or not compiled_ready():
        return None
    try:
        steps = _probe(model, sc, t_end)
    except (ArithmeticError, ValueError):  # values the model cannot pack (Omega^2 overflows): the run says so
        return None
    outputs = len(sc.run.t_eval) if sc.run.t_eval is not None else sc.run.samples
    return None if steps is None else steps + outputs


def _probe(model, sc, t_end: float) -> float | None:
    p = np.ascontiguousarray(model.pack(sc), dtype=float)
    y0 = np.ascontiguousarray(model.initial_state(sc, p), dtype=float)
    rtol = float(sc.run.rtol)
    atol = atol_for(rtol, y0)
    b, lam = brake_and_medium(sc)
    G0 = float(dispatch.braking_norm(model.kernel, y0, p)) if b > 0 else 1.0
    half = PROBE_STEPS // 2
    t, y, h, steps = 0.0, y0, 0.0, 0
    for _ in range(2):
        t_from = t
        span = np.array([t, t_end])
        _, _, status, t, y, _, n, h = dop853.integrate(model.kernel, y, p, span, rtol, atol, b, lam, half, h, G0)
        t, steps = float(t), steps + int(n)
        if status in (dop853.OK, dop853.BRAKED):
            return float(steps)
        if status != dop853.MAX_STEPS or not t > t_from:
            return None
    return steps + n * (t_end - t) / (t - t_from)
