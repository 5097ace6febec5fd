"""Frequencies of the free pendulum and of the free carrier (seed 002 (4)-(7), (10), (14); docs/models.md
Part B sections 4, 5 and corrections B.9.1, B.9.2, B.9.4, B.9.6).

Pure functions on floats: moments in kg m^2, rates in rad/s, masses in kg, lengths in m. A body-frame
exponent s means the motion goes as e^{s t}; Im s > 0 turns with the spin.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# ---- (6), (7): the free pendulum -----------------------------------------------------------------

def reduced_mass(m: float, M0: float) -> float:
    """mu = m M0/(M0 + m), kg: the bob's mass in every pendulum equation (docs/models.md B.2, B.9.1)."""
    return m * M0 / (M0 + m)


def natural_frequency(k: float, mu: float, l: float) -> float:
    """omega_0 = sqrt(k/(mu l^2)), rad/s: the pendulum's frequency in inertial terms (B.4)."""
    return math.sqrt(k / (mu * l**2))


def frequencies_eq6(omega_n2: float, W: float) -> tuple[float, float]:
    """The positive roots lambda_1 < lambda_2 of seed 002 (6) as printed,
    lambda^4 - 2(omega_n^2 + 2W^2) lambda^2 + omega_n^4 = 0 (rad/s)."""
    b = omega_n2 + 2 * W**2
    disc = math.sqrt(max(b * b - omega_n2**2, 0.0))
    lo, hi = b - disc, b + disc
    return math.sqrt(max(lo, 0.0)), math.sqrt(hi)


def pendulum_frequencies(omega0: float, W: float) -> tuple[float, float]:
    """(6) solved: lambda_{1,2} = |omega_0 -/+ W| (docs/models.md B.4, B.9.2), rad/s."""
    return abs(omega0 - W), omega0 + W


def distribution_coefficients(lambdas, omega_n2: float, W: float) -> tuple[float, ...]:
    """Seed 002 (7): c_j = -(omega_n^2 - lambda_j^2)/(2 W lambda_j). For omega_0 > W they are exactly
    c_1 = -1, c_2 = +1 (B.9.2); for omega_0 < W both are +1 (B.4)."""
    return tuple(-(omega_n2 - lam**2) / (2 * W * lam) for lam in lambdas)


@dataclass(frozen=True)
class PendulumMode:
    """One circular mode of the free pendulum in the body frame: frequency lambda (rad/s, > 0),
    distribution coefficient c of (7), its sense ("co-rotating" with the spin or "counter-rotating")
    and its body-frame exponent s = +/- i lambda (z = alpha + i beta goes as e^{s t})."""

    name: str
    frequency: float
    c: float
    sense: str
    exponent: complex


def pendulum_modes(omega0: float, W: float) -> tuple[PendulumMode, PendulumMode]:
    """Modes 1 and 2 of (5)-(7) with their sense of rotation in the body frame (B.4).

    z = alpha + i beta obeys z'' + 2iW z' + omega_n^2 z = 0, so z ~ e^{i nu t} with
    nu = -W +/- omega_0. With (5), z = -i c-weighted circles: c = -1 is co-rotating (nu > 0).
    omega_0 > W: mode 1 co-rotates at omega_0 - W, mode 2 counter-rotates at omega_0 + W.
    omega_0 < W: both counter-rotate (at W - omega_0 and W + omega_0), and c = +1 for both."""
    lam = pendulum_frequencies(omega0, W)
    c = distribution_coefficients(lam, omega0**2 - W**2, W) if min(lam) > 0 else (math.nan, 1.0)
    out = []
    for name, nu, lam_j, c_j in zip(("pendulum 1", "pendulum 2"), (-W + omega0, -W - omega0), lam, c, strict=True):
        sense = "co-rotating" if nu > 0 else "counter-rotating"
        out.append(PendulumMode(name, lam_j, c_j, sense, 1j * nu))
    return tuple(out)


# ---- free nutation (4), (10) ---------------------------------------------------------------------

def nutation_frequency(A: float, C: float, W: float) -> float:
    """Omega = (C - A) W / A of seed 002 (4), rad/s; > 0 turns with the spin in the body frame."""
    return (C - A) * W / A


def precession_coefficients(A: float, B: float, C: float) -> tuple[float, float]:
    """s1 = (C - B)/A, s2 = (C - A)/B of seed 002 (1)."""
    return (C - B) / A, (C - A) / B


def free_precession_frequency(A: float, B: float, C: float, W: float) -> float:
    """rho = sqrt(s1 s2) W of seed 002 (10), signed like Omega (negative for a prolate carrier), rad/s."""
    s1, s2 = precession_coefficients(A, B, C)
    if s1 * s2 <= 0:
        raise ValueError("s1 s2 <= 0: C is the intermediate moment, there is no free precession")
    return math.copysign(math.sqrt(s1 * s2), s1) * W


def precession_amplitude_ratio(A: float, B: float, C: float) -> float:
    """|omega_y|/|omega_x| of free precession: sqrt(s2/s1) (corrected (10), docs/models.md B.6, B.9.4)."""
    s1, s2 = precession_coefficients(A, B, C)
    return math.sqrt(s2 / s1)


def precession_amplitude_ratio_printed(A: float, B: float, C: float) -> float:
    """The ratio seed 002 (10) prints, sqrt(s1 s2)/s2 = sqrt(s1/s2): wrong unless s1 = s2 (B.9.4)."""
    s1, s2 = precession_coefficients(A, B, C)
    return math.sqrt(s1 * s2) / s2


def resonant_omega0(A: float, B: float, C: float, W: float) -> float:
    """omega_0 that puts mode 1 on the free nutation, lambda_1 = Omega (or rho), seed 002 (14) with
    B.9.6: omega_0 = W + rho, i.e. C W/A for a symmetric carrier (docs/models.md B.5), rad/s."""
    s1, s2 = precession_coefficients(A, B, C)
    return W * (1.0 + math.copysign(math.sqrt(s1 * s2), s1))
