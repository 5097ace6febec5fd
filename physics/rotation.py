"""Quaternion helpers; scalar first (w, x, y, z), rotating body components into inertial ones."""

from __future__ import annotations

import numpy as np


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
