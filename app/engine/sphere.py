"""The momentum sphere, as plain numbers (no viser here, so it is testable headless).

In body axes the total angular momentum K of a free body keeps its length, so its tip stays on the sphere
|K| = const; the frozen body's energy 2E = K1^2/A + K2^2/B + K3^2/C keeps it on an ellipsoid too. Their
intersections, for a set of energy levels between K^2/max(A,B,C) and K^2/min(A,B,C), are the polhodes of
K (Landau & Lifshitz, Mechanics, section 37). The level 2E = K^2/I_mid is the separatrix: two great circles
through the intermediate axis (only when the three moments differ). As internal parts dissipate energy at
fixed |K|, K's tip crosses the polhodes towards the axis of largest moment (the energy-sink rule).

Everything here is on the unit sphere (K/|K|): the polhodes' shapes depend only on A, B, C, so the
drawing is rebuilt only when those change, whatever |K| does.
"""

from __future__ import annotations

import math

import numpy as np

from physics import qconj, rotate

from .geometry import SYMMETRY_TOL

LEVELS_PER_SIDE = 5  # polhodes drawn on each side of the separatrix (around the largest and the smallest axis)
CURVE_POINTS = 96  # points per closed polhode: a chord spans under 4 degrees
PATH_POINTS = 1500  # K's path on the sphere keeps at most this many points (the oldest go)
MIN_STEP = 0.02  # rad: a new point of the path is kept only this far from the last kept one (bounds the path
# by its length, not by the frame rate or the warp)
MAX_CHORD = 0.3  # rad: consecutive path points farther apart than this are not joined (samples a high warp
# spaces widely; a line across the sphere would be no path K took)


def _order(moments) -> tuple[np.ndarray, np.ndarray]:
    """(I, idx): the moments and the body axes' indices sorted from the smallest moment to the largest."""
    m = np.asarray(moments, dtype=float)
    if m.shape != (3,) or not np.all(np.isfinite(m)) or np.any(m <= 0):
        raise ValueError(f"moments (A, B, C) must be three finite positive numbers, got {tuple(m.ravel())}")
    idx = np.argsort(m, kind="stable")
    return m[idx], idx


def _equal(a: float, b: float) -> bool:
    return abs(a - b) <= SYMMETRY_TOL * max(a, b)


def has_separatrix(moments) -> bool:
    """Whether the three moments differ (app.engine.geometry.SYMMETRY_TOL): only then is there a separatrix."""
    I, _ = _order(moments)
    return not (_equal(I[0], I[1]) or _equal(I[1], I[2]))


def _ring(axis_a: np.ndarray, a: float, axis_b: np.ndarray, b: float, axis_c: np.ndarray, sign: float,
          n: int, height: float | None = None) -> np.ndarray:
    """Points (n + 1, 3), closed, of x_a = a cos(phi), x_b = b sin(phi), x_c = sign sqrt(1 - x_a^2 - x_b^2);
    ``height``: x_c itself when it is known to be constant (a circle of latitude, a = b: the square root of a
    difference near 0 would be off by 1e-8 at the equator)."""
    phi = np.linspace(0.0, 2 * math.pi, n + 1)
    xa, xb = a * np.cos(phi), b * np.sin(phi)
    if height is not None:
        xc = np.full_like(phi, sign * height)
    else:
        xc = sign * np.sqrt(np.maximum(1.0 - xa * xa - xb * xb, 0.0))
    return np.outer(xa, axis_a) + np.outer(xb, axis_b) + np.outer(xc, axis_c)


def polhodes(moments, levels: int = LEVELS_PER_SIDE, n: int = CURVE_POINTS) -> list[tuple[float, int, np.ndarray]]:
    """The polhodes of K on the unit sphere, as (h, axis, points (n + 1, 3) closed, body axes): h = 2E/|K|^2,
    ``axis`` the index (0, 1, 2 for e1, e2, e3) of the body axis the curve goes round.

    Levels are spaced evenly in the angle at which a polhode crosses the great circle through the largest and
    the smallest axis, so the curves are evenly spaced on the sphere: ``levels`` around the axis of largest
    moment and ``levels`` around the axis of smallest moment (one closed curve on each hemisphere of that
    axis). For an axisymmetric body the curves are circles of latitude about its symmetry axis, and the
    level of the other two moments (the equator, every point a steady spin) is drawn as one of them.
    A sphere (A = B = C) has none: every K is a steady spin.

    On the great circle x_mid = 0, at angle alpha from the largest axis, h = cos^2/I_l + sin^2/I_s; with
    h fixed, x_s^2 (1/I_s - 1/I_l) + x_m^2 (1/I_m - 1/I_l) = h - 1/I_l is an ellipse in (x_s, x_m), and
    x_l follows from |x| = 1 (and the same about the smallest axis).
    """
    I, idx = _order(moments)
    if _equal(I[0], I[2]):
        return []
    e = np.eye(3)[idx]  # e[0]: the smallest moment's body axis, e[1] the intermediate, e[2] the largest
    inv = 1.0 / I
    out: list[tuple[float, int, np.ndarray]] = []
    # angle from the largest axis at which the separatrix crosses x_mid = 0: tan^2 = (1/I_m - 1/I_l)/(1/I_s - 1/I_m)
    if _equal(I[1], I[2]):
        a_sep = 0.0  # prolate: only curves about the smallest axis
    elif _equal(I[0], I[1]):
        a_sep = math.pi / 2  # oblate: only curves about the largest axis, down to the equator
    else:
        a_sep = math.atan(math.sqrt((inv[1] - inv[2]) / (inv[0] - inv[1])))
    symmetric = not has_separatrix(moments)
    # about the largest axis: alpha in (0, a_sep); an oblate body's last level is its equator (alpha = a_sep)
    count = levels if a_sep > 0 else 0
    for k in range(1, count + 1):
        alpha = a_sep * k / (levels + (0 if symmetric else 1))
        h = math.cos(alpha) ** 2 * inv[2] + math.sin(alpha) ** 2 * inv[0]
        a = math.sqrt(max(h - inv[2], 0.0) / (inv[0] - inv[2]))
        b = math.sqrt(max(h - inv[2], 0.0) / (inv[1] - inv[2])) if not _equal(I[1], I[2]) else a
        for sign in ((1.0, -1.0) if alpha < math.pi / 2 - 1e-12 else (1.0,)):
            if symmetric:
                a, b = math.sin(alpha), math.sin(alpha)
            out.append((h, int(idx[2]), _ring(e[0], a, e[1], b, e[2], sign, n,
                                              math.cos(alpha) if symmetric else None)))
    # about the smallest axis: beta = pi/2 - alpha from the smallest axis, in (0, pi/2 - a_sep)
    b_sep = math.pi / 2 - a_sep
    count = levels if b_sep > 0 else 0
    for k in range(1, count + 1):
        beta = b_sep * k / (levels + (0 if symmetric else 1))
        h = math.cos(beta) ** 2 * inv[0] + math.sin(beta) ** 2 * inv[2]
        a = math.sqrt(max(inv[0] - h, 0.0) / (inv[0] - inv[2]))
        b = math.sqrt(max(inv[0] - h, 0.0) / (inv[0] - inv[1])) if not _equal(I[0], I[1]) else a
        for sign in ((1.0, -1.0) if beta < math.pi / 2 - 1e-12 else (1.0,)):
            if symmetric:
                a, b = math.sin(beta), math.sin(beta)
            out.append((h, int(idx[0]), _ring(e[2], a, e[1], b, e[0], sign, n,
                                              math.cos(beta) if symmetric else None)))
    return out


def separatrices(moments, n: int = CURVE_POINTS) -> list[np.ndarray]:
    """The separatrix (h = 1/I_mid) as two closed great circles (n + 1, 3) through the intermediate axis, or
    [] when two moments are equal. Its planes hold the intermediate axis and x_l = +-k x_s, with
    k^2 = (1/I_s - 1/I_m)/(1/I_m - 1/I_l)."""
    if not has_separatrix(moments):
        return []
    I, idx = _order(moments)
    e = np.eye(3)[idx]
    inv = 1.0 / I
    k = math.sqrt((inv[0] - inv[1]) / (inv[1] - inv[2]))
    phi = np.linspace(0.0, 2 * math.pi, n + 1)
    out = []
    for sign in (1.0, -1.0):
        u = (e[0] + sign * k * e[2]) / math.sqrt(1 + k * k)  # unit, in the plane of the smallest and largest axes
        out.append(np.outer(np.cos(phi), e[1]) + np.outer(np.sin(phi), u))
    return out


def level(points: np.ndarray, moments) -> np.ndarray:
    """h = x.J^-1 x / |x|^2 of points (n, 3): 2E/|K|^2 of the frozen body, whose polhode the point is on."""
    p = np.atleast_2d(np.asarray(points, dtype=float))
    inv = 1.0 / np.asarray(moments, dtype=float)
    return np.einsum("ij,j,ij->i", p, inv, p) / np.einsum("ij,ij->i", p, p)


def segments(curves: list[np.ndarray]) -> np.ndarray:
    """Closed curves (each (m, 3)) as one set of line segments (sum of m - 1, 2, 3), for one scene node."""
    if not curves:
        return np.zeros((1, 2, 3))
    return np.concatenate([np.stack([c[:-1], c[1:]], axis=1) for c in curves])


def pure_spin_energies(K, moments) -> np.ndarray:
    """Energies (3, ...) J of steady spin about e1, e2, e3 with |K| = K: K^2/(2A), K^2/(2B), K^2/(2C)."""
    K = np.asarray(K, dtype=float)
    return np.stack([K * K / (2.0 * float(m)) for m in moments])


class MomentumPath:
    """K's direction in body axes over the run, thinned by distance (MIN_STEP) and bounded (PATH_POINTS).

    ``extend(quats, K_inertial)``: the body's attitudes (n, 4) at the samples of a stretch of run and the
    inertial total K at its end (physics.LiveRun.momentum: the full model's true total K). Inertial K is
    fixed when no external torque acts; under braking or a medium it turns slowly, and a frame's samples
    share its value at the frame's end."""

    def __init__(self, capacity: int = PATH_POINTS):
        self.points = np.zeros((capacity, 3))
        self.size = 0
        self.version = 0  # bumped when the path changes: the view resends it only then
        self.now: np.ndarray | None = None  # K's direction at the latest sample, kept or not

    def clear(self) -> None:
        self.size = 0
        self.now = None
        self.version += 1

    def extend(self, quats: np.ndarray, K_inertial: np.ndarray) -> None:
        n = float(np.linalg.norm(K_inertial))
        q = np.atleast_2d(np.asarray(quats, dtype=float))
        if not len(q) or not n > 0 or not math.isfinite(n):
            return
        body = rotate(qconj(q), np.broadcast_to(np.asarray(K_inertial, dtype=float) / n, (len(q), 3)))
        body /= np.linalg.norm(body, axis=1, keepdims=True)
        cap = len(self.points)
        added = False
        last = tuple(self.points[self.size - 1]) if self.size else None
        step2 = MIN_STEP * MIN_STEP
        for p in body.tolist():  # a few to a few dozen samples a frame: plain floats, a microsecond each
            if last is not None and (p[0] - last[0]) ** 2 + (p[1] - last[1]) ** 2 + (p[2] - last[2]) ** 2 < step2:
                continue
            if self.size == cap:  # the oldest half goes at once: a shift per point would cost cap copies each
                keep = cap // 2
                self.points[:keep] = self.points[cap - keep:cap]
                self.size = keep
            self.points[self.size] = p
            self.size += 1
            last = p
            added = True
        self.now = body[-1].copy()
        if added:
            self.version += 1

    def values(self) -> np.ndarray:
        """The kept directions (size, 3), oldest first (a copy)."""
        return self.points[:self.size].copy()


def path_segments(points: np.ndarray) -> np.ndarray:
    """Consecutive path points (n, 3) joined as segments (m, 2, 3), leaving out joins longer than MAX_CHORD;
    one degenerate segment when nothing is left (a scene node needs one)."""
    p = np.asarray(points, dtype=float)
    if len(p) < 2:
        q = p[0] if len(p) else np.zeros(3)
        return np.array([[q, q]])
    seg = np.stack([p[:-1], p[1:]], axis=1)
    near = np.linalg.norm(p[1:] - p[:-1], axis=1) <= MAX_CHORD
    return seg[near] if near.any() else seg[:1, :1].repeat(2, axis=1)
