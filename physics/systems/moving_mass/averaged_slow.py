"""The averaged model's slow (w_perp, w3) reduction, integrated: theta(t) of an axisymmetric body without
following the free-body revolutions.

For J*1 = J*2 the phase of w and the attitude do not feed back on theta, so the averaged model reduces to
two states (physics/compiled/averaged.py ``rhs_axisymmetric``). The work-precision study of issue 5 runs it
as the cheapest way to cover the averaged model's slow horizon (``python -m bench work-precision``). It lives
with the moving mass because it is that system's reduction; the atol rule is every run's (physics/core/tolerance.py).
"""

from __future__ import annotations

import math
import time

import numpy as np

from physics.compiled import dispatch, dop853
from physics.core.tolerance import atol_for
from physics.scenario.scenario import Scenario
from physics.systems.moving_mass.models import AVERAGED


def averaged_slow_theta(sc: Scenario, rtol: float) -> tuple[np.ndarray, int, int, float]:
    """Theta (rad) at ``sc.run.times()`` from the slow reduction, by the compiled DOP853 with the project's
    atol rule (as ``simulate``). Returns (theta, nfev, steps, wall_s); the wall time covers packing, the
    initial state, the integration and theta, as simulate's does."""
    start = time.perf_counter()
    model = AVERAGED
    p = model.pack(sc)
    if p[0] != p[1]:
        raise ValueError(f"the slow reduction needs an axisymmetric body (A = B), got frozen moments "
                         f"J*1 = {p[0]!r}, J*2 = {p[1]!r}")
    w0 = model.initial_state(sc, p)[0:3]
    y0 = np.array([math.hypot(w0[0], w0[1]), w0[2]])
    t = sc.run.times()
    atol = atol_for(rtol, y0)
    Y, n, status, *_, nfev, steps, _h = dop853.integrate(
        dispatch.MASS_AVERAGED_AXISYMMETRIC, y0, p, t, rtol, atol, 0.0, 0.0, 10**9, 0.0, 1.0)
    if status != dop853.OK:
        raise RuntimeError(dop853.STATUS_TEXT[status])
    theta = np.arctan2(p[0] * Y[:, 0], p[2] * Y[:, 1])  # angle between G = J* w and e3
    return theta, int(nfev), int(steps), time.perf_counter() - start
