"""What one published frame shows (``Frame``), and how the engine makes it from the run's last state:
the body's attitude, K, omega and e3 as arrows, the internal parts (the system's own figure, physics.figure),
the e3 trail and the polhode, in the inertial view (K of t = 0 pointing up) or the body view. Functions of what
they read, called by ``app.engine.Engine`` and ``app.engine.compare.Comparison`` (each makes its own frames).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

import physics
from physics import qmul, rotate

from .geometry import E3, ellipsoid_axes


@dataclass
class Frame:
    """Everything one published frame shows. Vectors are in scene coordinates (inertial frame turned so
    the initial K points up, or the body frame), metres; quaternions scalar first."""

    seq: int
    t: float
    theta: float
    K: float
    E: float
    body_wxyz: np.ndarray
    world_wxyz: np.ndarray
    K_vec: np.ndarray
    omega_vec: np.ndarray
    axis_vec: np.ndarray
    torque_vec: np.ndarray | None
    figure: tuple = ()  # the system's picture: physics.figure primitives, body frame, m
    trail: np.ndarray | None = None  # (n, 3) scene coordinates, on a sphere of radius trail_radius
    polhode: np.ndarray | None = None  # (n, 3) body frame, m: omega's tip on the drawn inertia ellipsoid
    status: str = "running"
    message: str = ""
    applied: int = 0  # sequence number of the last GUI change reflected in this frame

    def part(self, name: str):
        """The figure's primitive named ``name``, or None."""
        return next((p for p in self.figure if p.name == name), None)

    def parts(self, role: str) -> tuple:
        """The figure's primitives of legend role ``role``."""
        return tuple(p for p in self.figure if p.role == role)


def figure_view(extent: float, view_values: dict[str, float]) -> physics.figure.View:
    """What the system's figure is drawn with: the body's drawn size (m) and the view actions' values."""
    return physics.figure.View(extent=extent, **view_values)


def figure(run: physics.LiveRun, extent: float, view_values: dict[str, float]) -> tuple:
    """The system's picture of the run's last state (physics.figure primitives, body frame, m)."""
    sc = run.scenario
    state = physics.figure.row_state(run.last.internal, 0)
    return tuple(physics.get_system(sc.system).figure(sc, state, figure_view(extent, view_values)))


def make_frame(run: physics.LiveRun, *, seq: int, applied: int, view: str, world_wxyz: np.ndarray, K_ref: float,
               w_ref: float, extent: float, view_values: dict[str, float], trail: np.ndarray,
               polhode: np.ndarray | None) -> Frame:
    """The frame of the run's last state: in the ``view`` "body" or the inertial one turned by ``world_wxyz``
    (K of t = 0 up), K and omega scaled by ``K_ref`` and ``w_ref``, arrows and parts sized by the body's drawn
    ``extent`` (m); ``trail``: the e3 trail's unit points; ``polhode``: shown, or None."""
    last = run.last
    q = last.quat[0]
    K = run.momentum()
    w_in = rotate(q, last.omega[0])
    axis = rotate(q, E3)
    # the control torque (the brake's -b K/|K|, a thruster's body axis), drawn at a fixed length: its direction
    torque = run.torque_direction()
    if view == "body":
        turn = np.array([q[0], -q[1], -q[2], -q[3]])  # inertial -> body components
        body_wxyz = np.array([1.0, 0, 0, 0])
        world = np.array([1.0, 0, 0, 0])
    else:
        turn = world_wxyz  # inertial -> the view with the initial K up
        body_wxyz = qmul(world_wxyz, q)
        world = world_wxyz

    def to_scene(v):
        return rotate(turn, v)
    size = extent
    fr = Frame(seq=seq, t=run.t, theta=float(last.theta[0]), K=float(last.K[0]), E=float(last.E[0]),
               body_wxyz=body_wxyz, world_wxyz=world,
               K_vec=to_scene(K) / K_ref * 1.0 * size,
               omega_vec=to_scene(w_in) / w_ref * 0.9 * size,
               axis_vec=to_scene(axis) * 0.9 * size,
               torque_vec=None if torque is None else to_scene(torque) * 0.6 * size,
               status=run.status, message=run.message, applied=applied)
    fr.figure = figure(run, extent, view_values)
    fr.trail = trail * 0.9 * size  # the e3 arrow's tip draws it
    fr.polhode = polhode
    return fr


def non_finite(fr: Frame) -> str | None:
    """The name of the first part of ``fr`` a tab would be sent as NaN or infinity (a number, an array, a
    figure primitive's field), or None when every number in it is finite."""
    for name in ("t", "theta", "K", "E", "body_wxyz", "world_wxyz", "K_vec", "omega_vec", "axis_vec", "torque_vec",
                 "trail", "polhode"):
        v = getattr(fr, name)
        if v is not None and not np.all(np.isfinite(v)):
            return name
    for p in fr.figure:
        for field in fields(p):
            v = getattr(p, field.name)
            if not isinstance(v, (float, tuple, np.ndarray)):
                continue
            try:
                finite = np.all(np.isfinite(np.asarray(v, dtype=float)))
            except (TypeError, ValueError):
                continue  # not numbers (a label's words)
            if not finite:
                return f"{p.name}.{field.name}"
    return None


def ellipsoid(body, extent: float) -> np.ndarray:
    """The drawn inertia ellipsoid's semi-axes (m) for ``body`` (A, B, C) drawn ``extent`` across."""
    return ellipsoid_axes(body.A, body.B, body.C, 0.6 * extent)


def polhode_points(body, extent: float, omega: np.ndarray) -> np.ndarray:
    """omega (n, 3, body components) scaled onto the drawn inertia ellipsoid w.J w = const: the
    polhode (Poinsot). The ellipsoid's semi-axes are size/sqrt(I_k) times sqrt(min I)."""
    J = np.array([body.A, body.B, body.C])
    w = np.atleast_2d(omega)
    n = np.sqrt(np.maximum(np.einsum("ij,j,ij->i", w, J, w), 1e-300))[:, None]
    return w / n * (0.6 * extent * math.sqrt(J.min()))


def trail_points(quats: np.ndarray, view: str, world_wxyz: np.ndarray, K: np.ndarray) -> np.ndarray:
    """(n, 3) for attitudes (n, 4): inertial view, the tip of the symmetry axis; body view, the direction of K
    (inertial, the same for every sample of a frame) in the body. One array operation for a frame's samples."""
    q = np.atleast_2d(quats)
    if view == "body":
        return rotate(q * np.array([1.0, -1.0, -1.0, -1.0]), np.broadcast_to(direction(K), (len(q), 3)))
    return rotate(world_wxyz, rotate(q, np.broadcast_to(E3, (len(q), 3))))


def trail_point(q: np.ndarray, view: str, world_wxyz: np.ndarray, K: np.ndarray) -> np.ndarray:
    """``trail_points`` of one attitude (4,): (3,)."""
    return trail_points(np.asarray(q)[None], view, world_wxyz, K)[0]


def direction(K: np.ndarray) -> np.ndarray:
    """K's unit vector (E3 for K = 0)."""
    n = np.linalg.norm(K)
    return K / n if n > 0 else E3
