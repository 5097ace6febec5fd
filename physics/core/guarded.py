"""A bound on the small scipy integrations inside closed forms and error estimates.

scipy's ``solve_ivp`` has no step budget, and a right side that turns NaN or infinite does not end it: the error
norm is NaN, every step is rejected and the step size becomes NaN, which no ``h < min_step`` test catches, so it
loops for good (found by fuzzing: ``initial.G0 = 1e300`` or ``body.C = 1e-300`` in a closed-form run of seed 004
eq. (13)). ``guarded`` wraps a right side so that either ends the integration with ``RightSideError``, a
RuntimeError that names what was being integrated.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np


class RightSideError(RuntimeError):
    """A guarded integration's right side was evaluated too often (``over_budget``) or was not finite, at ``t``."""

    def __init__(self, message: str, t: float = 0.0, over_budget: bool = False):
        super().__init__(message)
        self.t, self.over_budget = float(t), over_budget


def guarded(fun: Callable, max_calls: int, what: str) -> Callable:
    """``fun(t, y)`` that raises RightSideError after ``max_calls`` evaluations or on a value that is not finite."""
    calls = 0

    def g(t, y):
        nonlocal calls
        calls += 1
        if calls > max_calls:
            raise RightSideError(f"{what}: more than {max_calls} evaluations of its right side", t, True)
        out = fun(t, y)
        if not np.all(np.isfinite(out)):
            raise RightSideError(f"{what}: its right side is not finite (NaN or infinity) at t = {float(t):.6g}", t)
        return out

    return g
