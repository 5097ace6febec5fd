"""States of a linear system y' = S y at many times, with few matrix exponentials.

The pendulum dampers' linear theory samples its nutation angle on long, even grids (up to 200,001
times, to find the e-folding time): one ``expm`` per sample took 112 s for two plane pendulums. On an
even grid one exponential E = e^{S dt} serves every step, and the states of a block of B steps come
from the powers E^1..E^B at once, so the Python loop runs n/B times. Exact exponentials, never
eigenvectors: they stay accurate at the double root of an optimally tuned damper.
"""

from __future__ import annotations

import numpy as np

BLOCK = 256  # steps per block of powers: B matrix products once, then one (B x n) product per block
EVEN_RTOL = 1e-9  # relative spread of the steps below which a grid counts as even


def propagate(S: np.ndarray, y0, t) -> np.ndarray:
    """States (len(t), n) of y' = S y at times t (increasing, s) from y0 at t = 0."""
    from scipy.linalg import expm  # here, not at the top: scipy.linalg adds 0.2 s to the app's start

    S = np.asarray(S)
    t = np.asarray(t, dtype=float)
    y = np.asarray(y0, dtype=S.dtype if np.iscomplexobj(S) else float)
    Y = np.empty((t.size, y.size), dtype=np.result_type(S, y))
    if t.size == 0:
        return Y
    y = expm(S * t[0]) @ y if t[0] != 0 else y
    Y[0] = y
    if t.size == 1:
        return Y
    dt = np.diff(t)
    step = (t[-1] - t[0]) / (t.size - 1)
    if np.all(np.abs(dt - step) <= EVEN_RTOL * abs(step)):
        E = expm(S * step)
        powers = [E]
        for _ in range(min(BLOCK, t.size - 1) - 1):
            powers.append(powers[-1] @ E)
        P = np.stack(powers)  # P[j] = E^(j+1)
        i = 1
        while i < t.size:
            k = min(BLOCK, t.size - i)
            Y[i:i + k] = P[:k] @ Y[i - 1]
            i += k
        return Y
    cached, E = None, None
    for i in range(1, t.size):  # an uneven grid: one exponential per distinct step
        if cached is None or abs(dt[i - 1] - cached) > EVEN_RTOL * max(abs(cached), 1e-300):
            cached, E = dt[i - 1], expm(S * dt[i - 1])
        Y[i] = E @ Y[i - 1]
    return Y
