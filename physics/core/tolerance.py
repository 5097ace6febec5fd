"""The absolute tolerance every adaptive run gets, from its relative one: one rule for the stepper and for the
studies that call a compiled integrator directly (the averaged model's slow reduction)."""

from __future__ import annotations

import numpy as np

ATOL_FACTOR = 1e-6  # atol = rtol * ATOL_FACTOR * max|y0|: keeps the small mass displacement resolved


def atol_for(rtol: float, y0: np.ndarray) -> float:
    """The absolute tolerance every run gets: rtol * ATOL_FACTOR * max(1, max|y0|)."""
    return rtol * ATOL_FACTOR * max(1.0, float(np.max(np.abs(y0))))
