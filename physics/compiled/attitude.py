"""The attitude's kinematics, shared by every compiled right-hand side: q' = q (0, w) / 2.

q is the unit quaternion (scalar first) taking body coordinates to inertial ones, w the body-frame angular
velocity (docs/models.md conventions). Written once here so the kernels cannot disagree on a sign; the interpreted
twins (physics/kernels/interpreted.py) get the same source rebound, so they use it too.
"""

from __future__ import annotations

from numba import njit


@njit(cache=True)
def quaternion_rate(y, o, w1, w2, w3, out):
    """out[o:o + 4] = q' = q (0, w) / 2 for the quaternion q = y[o:o + 4] and body rates w (rad/s)."""
    qw, qx, qy, qz = y[o], y[o + 1], y[o + 2], y[o + 3]
    out[o] = -0.5 * (qx * w1 + qy * w2 + qz * w3)
    out[o + 1] = 0.5 * (qw * w1 + qy * w3 - qz * w2)
    out[o + 2] = 0.5 * (qw * w2 + qz * w1 - qx * w3)
    out[o + 3] = 0.5 * (qw * w3 + qx * w2 - qy * w1)
