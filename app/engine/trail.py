"""The e3 trail stays a trail at any time warp.

The scene publishes a few samples per frame. Once those samples lie more than a small fraction of a turn
of the nutation cone apart (from about 20x on the default scene; at 10,000x they are tens of turns apart),
joining them draws chords across the cone, and the trail becomes a filled disc that hides the body. So at
such warps a frame's advance is split: the part before its last TRAIL_TURNS turns with the usual few samples
(for the plots), then the last turns densely sampled, and those dense samples alone are the trail. The trail
then always shows the cone's last few turns, joined by short chords. No viser here.
"""

from __future__ import annotations

import math

import numpy as np

import physics

SAMPLES_PER_TURN = 24  # a chord spans at most 15 degrees of the cone: drawn, it reads as the circle
TRAIL_TURNS = 3.0  # at high warp the trail shows this many turns of the cone, ending now


def turn_period(A: float, B: float, K: float, omega: float) -> float:
    """Seconds for the trail's point to go once round, at the fastest: e3 turns about K at |K|/A for an
    axisymmetric body (A = B); K turns about e3, seen from the body, at |C - A|/A omega3 <= |omega| (C <= 2A).
    Inf when nothing turns."""
    rate = max(abs(float(K)) / min(float(A), float(B)), abs(float(omega)))
    return 2 * math.pi / rate if rate > 0 else math.inf


def split_advance(dt: float, samples: int, period: float) -> tuple[float, float, int]:
    """(head, tail, tail_samples): integrate ``head`` seconds with ``samples`` samples, then ``tail``
    seconds with ``tail_samples`` for the trail. (dt, 0, 0) when ``samples`` over dt are already close
    enough for the trail."""
    if not dt > 0 or not math.isfinite(period) or period <= 0:
        return dt, 0.0, 0
    spacing = period / SAMPLES_PER_TURN
    if dt / max(int(samples), 1) <= spacing:
        return dt, 0.0, 0
    tail = min(dt, TRAIL_TURNS * period)
    return dt - tail, tail, max(int(math.ceil(tail / spacing)), 1)


def thinned(tr: physics.Trajectory, n: int) -> physics.Trajectory:
    """``n`` rows of ``tr`` evenly spread, its last row among them (the plots take these from a dense tail)."""
    m = len(tr)
    if m <= n:
        return tr
    idx = np.unique(np.round(np.linspace(m - 1, 0, n)[::-1]).astype(int))
    return physics.Trajectory(t=tr.t[idx], theta=tr.theta[idx], K=tr.K[idx], E=tr.E[idx], omega=tr.omega[idx],
                              quat=tr.quat[idx], internal={k: np.asarray(v)[idx] for k, v in tr.internal.items()},
                              info=tr.info)


def azimuths(points: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Azimuth (rad, unwrapped) of each point (n, 3) about ``axis``: how far round the cone it has gone."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    ref = np.cross(a, [1.0, 0.0, 0.0])
    if np.linalg.norm(ref) < 1e-6:
        ref = np.cross(a, [0.0, 1.0, 0.0])
    ref /= np.linalg.norm(ref)
    other = np.cross(a, ref)
    p = np.asarray(points, dtype=float)
    return np.unwrap(np.arctan2(p @ other, p @ ref))


def largest_step(points: np.ndarray, axis: np.ndarray) -> float:
    """The largest angle (rad) about ``axis`` between consecutive points: small for a trail, about a
    quarter turn and more for chords across a disc."""
    if len(points) < 2:
        return 0.0
    steps = np.abs(np.diff(azimuths(points, axis)))
    return float(steps.max())


def turns_covered(points: np.ndarray, axis: np.ndarray) -> float:
    """How many turns about ``axis`` the points (oldest first) go round."""
    if len(points) < 2:
        return 0.0
    az = azimuths(points, axis)
    return float(abs(az[-1] - az[0]) / (2 * math.pi))
