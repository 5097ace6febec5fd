"""Derived quantities of a scenario: the papers' coefficients and the validity numbers.

F, D, L, H, P: seed 004 eq. (4); Gamma1, Gamma2, k*: eq. (24) as corrected in docs/models.md A.6
(seed 004 item 7); T: eq. (10)-(11); A_c, N, B, Lambda, gamma, sigma: seed 000 (2.6), (2.10),
(3.2), (3.8) as corrected. For an asymmetric body (A != B) the averaged theory does not apply;
the perturbation coefficients then use the mean equatorial moment (A + B)/2 and the validity
check says so.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from physics.scenario.initial import initial_G
from physics.scenario.scenario import Scenario


def _ieee(f):
    """Run ``f`` on numpy floats with IEEE results: an overflow gives inf and 1/0 gives inf, where Python's
    own floats raise (a scenario may hold Omega = 1e200: F is then 0, not a crash)."""
    @functools.wraps(f)
    def wrapper(*args, **kwargs):
        with np.errstate(all="ignore"):
            return f(*args, **kwargs)
    return wrapper


@dataclass(frozen=True)
class Coefficients:
    A: float  # equatorial moment used by the averaged theory, (A + B)/2
    C: float
    F: float
    D: float
    L: float
    H: float
    P: float
    lam: float
    b: float
    Lambda: float  # lam_q / Omega^3, seed 000 (1.2)
    Bq0: float  # seed 000 (2.6) B without its factor w_perp: m rho^3 Lambda C^4 d|d| / (Omega^3 A^5)
    G0: float
    theta0: float
    omega0: float  # |w(0)|, rad/s: the "typical rotation rate" of the validity conditions

    @property
    @_ieee
    def d(self) -> float:
        """Seed 000 asymmetry parameter d = (A - C)/A."""
        return (self.A - self.C) / self.A

    @property
    @_ieee
    def N(self) -> float:
        """Seed 000 (3.2): N = D/A."""
        return self.D / self.A

    # Gamma1, Gamma2 and k* measure time in tau = lambda t: without a medium they are undefined (nan)
    @property
    @_ieee
    def Gamma1(self) -> float:
        """Seed 004 (24), corrected: Gamma1 = H G0^2 / (lambda A^2 C)."""
        return self.H * self.G0**2 / (self.lam * self.A**2 * self.C) if self.lam > 0 else math.nan

    @property
    @_ieee
    def Gamma2(self) -> float:
        """Seed 004 (24), corrected: Gamma2 = D G0^4 / (lambda A C^4)."""
        return self.D * self.G0**4 / (self.lam * self.A * self.C**4) if self.lam > 0 else math.nan

    @property
    @_ieee
    def k_star(self) -> float:
        """Seed 004 (24): k* = b / (lambda G0)."""
        if self.lam > 0:
            return self.b / (self.lam * self.G0)
        return math.inf if self.b > 0 else math.nan

    @property
    @_ieee
    def gamma(self) -> float:
        """Seed 000 (2.10), corrected: gamma = m rho^3 Lambda d|d| K^7 / (Omega^3 A^6 C^2)."""
        return self.Bq0 * self.G0**7 / (self.A * self.C**6)

    @property
    @_ieee
    def sigma(self) -> float:
        """Seed 000 (3.8): sigma = 5 b C^4 / (2 N K0^5)."""
        return 5.0 * self.b * self.C**4 / (2.0 * self.N * self.G0**5) if self.N != 0 else math.inf


@_ieee
def coefficients(scenario: Scenario) -> Coefficients:
    body = scenario.body
    A = np.float64(0.5) * (body.A + body.B)
    C = np.float64(body.C)
    w0, G0, theta0 = initial_G(scenario)
    F = D = L = H = Lam = Bq0 = 0.0
    if scenario.mass is not None:
        ms = _floats(scenario.mass)
        F = ms.m * ms.rho**2 * C / (ms.Omega**2 * A**3)
        D = ms.m * ms.rho**2 * ms.chi * C**3 * (A - C) / (ms.Omega**4 * A**4)
        Lam = ms.lam_q / ms.Omega**3
        d = (A - C) / A
        Bq0 = ms.m * ms.rho**3 * Lam * C**4 * d * abs(d) / (ms.Omega**3 * A**5)
    P = 0.0
    if scenario.cavity is not None:
        cav = scenario.cavity
        P = np.float64(cav.P)
        L = np.float64(cav.coupling) * C * (A - C) / A**2
        H = np.float64(cav.coupling) * (C - A) / A
    lam = np.float64(scenario.medium.lambda_ if scenario.medium is not None else 0.0)
    b = np.float64(scenario.control.b if scenario.control is not None else 0.0)
    return Coefficients(A=A, C=C, F=F, D=D, L=L, H=H, P=P, lam=lam, b=b, Lambda=Lam, Bq0=Bq0,
                        G0=np.float64(G0), theta0=theta0, omega0=np.float64(np.linalg.norm(w0)))


class _floats:
    """A parameter set's numbers as numpy floats (attribute access as on the original)."""

    def __init__(self, params):
        self._p = params

    def __getattr__(self, name):
        return np.float64(getattr(self._p, name))
