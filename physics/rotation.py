"""Quaternion helpers; scalar first (w, x, y, z), rotating body components into inertial ones."""

from __future__ import annotations

import numpy as np


def qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a (x) b, scalar first, broadcasting over leading axes."""
    a0, a1, a2, a3 = np.moveaxis(np.asarray(a, dtype=float), -1, 0)
    b0, b1, b2, b3 = np.moveaxis(np.asarray(b, dtype=float), -1, 0)
    return np.stack([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0], axis=-1)


def normalize(q: np.ndarray) -> np.ndarray:
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """R(q) v for arrays q (..., 4) and v (..., 3); q need not be exactly unit (it is normalised)."""
    q = normalize(np.asarray(q, dtype=float))
    w, u = q[..., :1], q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def nutation_angle(Kb: np.ndarray) -> np.ndarray:
    """Angle between a body-frame vector (..., 3) and e3, rad: MODELS conventions' theta."""
    return np.arctan2(np.hypot(Kb[..., 0], Kb[..., 1]), Kb[..., 2])
