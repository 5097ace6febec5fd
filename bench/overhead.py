"""The bare right-hand side in a tight compiled loop: the floor that an integrator's cost per
evaluation is measured against (issue 5: within 3x).

Where the rest goes, for the 15-state moving-mass model (~150 flops per rhs call):
- the stage combinations y + h sum_j a_sj k_j: DOP853's 12 stages need 66 multiply-adds per state
  component per step, i.e. ~80 per component per evaluation, comparable to the rhs itself;
- DOP853's error estimate (two 13-term sums per component, a square root) and step control; the
  fixed-step RK8 has the same stages without them, and RK4 has only 4 stages with 6 coefficients;
- the dispatch branch on the model id and the braking/fault checks per step (a few ns).
Measured ratios vary between runs by up to ~2x on shared cores (both sides are timed in one run).
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit

from physics.compiled.dispatch import rhs


@njit(cache=True)
def _loop(model, y, p, n):
    out = np.empty_like(y)
    ys = y.copy()
    acc = 0.0
    for k in range(n):
        # feed the result back in (scaled to nothing), so the calls cannot be hoisted or elided
        ys[0] = y[0] + 1e-300 * acc
        rhs(model, 1e-9 * k, ys, p, out)
        acc += out[0]
    return acc


def bare_rhs_seconds(model: int, y, p, n: int = 1_000_000) -> float:
    """Seconds per call of the compiled rhs of ``model`` (fastest of three timed loops)."""
    y = np.ascontiguousarray(y, dtype=float)
    _loop(model, y, p, 10)
    best = np.inf
    for _ in range(3):
        start = time.perf_counter()
        _loop(model, y, p, n)
        best = min(best, (time.perf_counter() - start) / n)
    return best
