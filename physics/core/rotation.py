"""Quaternion helpers; scalar first (w, x, y, z), rotating body components into inertial ones."""

from __future__ import annotations

import numpy as np

IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])  # no rotation; read-only so that no caller can change it for all
IDENTITY.flags.writeable = False


def qmul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product a (x) b, scalar first, broadcasting over leading axes."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    a0, a1, a2, a3 = a[..., 0], a[..., 1], a[..., 2], a[..., 3]  # indexing, not moveaxis: a third of the time
    b0, b1, b2, b3 = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return np.stack([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0], axis=-1)


def qconj(q: np.ndarray) -> np.ndarray:
    """The conjugate (the inverse of a unit quaternion), broadcasting over leading axes."""
    q = np.asarray(q, dtype=float)
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """R(q) (3, 3) of one quaternion (4,); q need not be exactly unit (it is normalised)."""
    w, x, y, z = (float(c) for c in q)
    s = 2.0 / (w * w + x * x + y * y + z * z)
    return np.array([[1 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y)],
                     [s * (x * y + w * z), 1 - s * (x * x + z * z), s * (y * z - w * x)],
                     [s * (x * z - w * y), s * (y * z + w * x), 1 - s * (x * x + y * y)]])


def normalize(q: np.ndarray) -> np.ndarray:
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """R(q) v for arrays q (..., 4) and v (..., 3); q need not be exactly unit (it is normalised).
    One quaternion turning a few vectors (the explorer, 60 frames a second) is a matrix product: about ten
    times cheaper than the cross products below, which pay off over many attitudes."""
    q = np.asarray(q, dtype=float)
    if q.ndim == 1:
        return np.asarray(v, dtype=float) @ rotation_matrix(q).T
    q = normalize(q)
    w, u = q[..., :1], q[..., 1:]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)


def nutation_angle(Kb: np.ndarray) -> np.ndarray:
    """Angle between a body-frame vector (..., 3) and e3, rad: docs/models.md conventions' theta."""
    return np.arctan2(np.hypot(Kb[..., 0], Kb[..., 1]), Kb[..., 2])

