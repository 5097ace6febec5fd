"""How the moving mass is drawn so that a viewer sees it belongs to the body: its displacement u from the
rest point O1 is exaggerated by a factor chosen from the scene (the drawn displacement stays a fraction of
the body's size) and capped while drawing, and the factor is shown beside it. No viser here.
"""

from __future__ import annotations

import math

import numpy as np

DRAWN_FRACTION = 0.15  # the default factor draws the expected largest |u| at most this fraction of the body
CAP_FRACTION = 0.3  # whatever the factor, the drawn displacement never exceeds this fraction of the body
NICE = (1.0, 2.0, 5.0)  # the default factor is 1, 2 or 5 times a power of ten: easy to read
EXAGGERATION_MIN, EXAGGERATION_MAX = 1.0, 1000.0  # the View slider's range


def expected_displacement(rho: float, Omega: float, omega: float) -> float:
    """The scale of the mass's displacement, m: the quasi-static answer to the largest centrifugal load on a
    point at distance rho from the centre spinning at |omega| (rad/s), held by a spring of natural frequency
    Omega (rad/s): |u| <~ |omega|^2 rho / Omega^2."""
    return float(omega) ** 2 * abs(float(rho)) / float(Omega) ** 2 if Omega > 0 else math.inf


def default_exaggeration(extent: float, rho: float, Omega: float, omega: float) -> float:
    """The factor the scene starts with: the largest 1-2-5 number that draws the expected displacement at
    most DRAWN_FRACTION of the body's size ``extent`` (m), within the slider's range."""
    u = expected_displacement(rho, Omega, omega)
    if not u > 0 or not math.isfinite(u):
        return EXAGGERATION_MIN
    want = DRAWN_FRACTION * extent / u
    if want <= EXAGGERATION_MIN:
        return EXAGGERATION_MIN
    p = 10.0 ** math.floor(math.log10(want))
    best = max(m * p for m in NICE if m * p <= want)
    return float(min(max(best, EXAGGERATION_MIN), EXAGGERATION_MAX))


def drawn_displacement(u: np.ndarray, factor: float, extent: float) -> tuple[np.ndarray, bool]:
    """(the displacement to draw, m; whether the cap cut it): factor * u, shortened to CAP_FRACTION * extent
    if longer, so a resonance or a large factor cannot throw the mass off the body."""
    d = float(factor) * np.asarray(u, dtype=float)
    n = float(np.linalg.norm(d))
    cap = CAP_FRACTION * extent
    if n > cap:
        return d * (cap / n), True
    return d, False


def factor_label(factor: float, capped: bool) -> str:
    """The text beside the mass: the factor its displacement is drawn with."""
    return f"u x {factor:g}" + (" (capped)" if capped else "")
