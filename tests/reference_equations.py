"""Averaged equations written out in plain numpy, independently of physics/, for the closed-form tests."""

from __future__ import annotations

import math


def rhs_004(t, w, A, C, F, D, L, H, lam, b):
    """Seed 004 eq. (1) with the control (8) M = -b J* w/|J* w| and the medium torque -lam J* w."""
    p, q, r = w
    G = math.sqrt(A * A * (p * p + q * q) + C * C * r * r)
    wp2 = p * p + q * q
    k = b / G if b else 0.0
    dp = (-(C - A) * q * r - k * A * p + L * p * r * r + F * G * G * q * r + D * r**4 * p - lam * A * p) / A
    dq = (-(A - C) * p * r - k * A * q + L * q * r * r - F * G * G * p * r + D * r**4 * q - lam * A * q) / A
    dr = (-k * C * r + H * wp2 * r - (A / C) * D * r**3 * wp2 - lam * C * r) / C
    return [dp, dq, dr]
