"""What one published frame shows (``Frame``), and how the engine makes it from the run's last state:
the body's attitude, K, omega and e3 as arrows, the internal parts (the system's own figure, physics.figure),
the e3 trail and the polhode, in the inertial view (K of t = 0 pointing up) or the body view. Mixed into
``app.engine.Engine``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

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


class FrameMixin:
    """Reads the engine's ``run``, ``scenario``, ``view``, ``world_wxyz``, ``K_ref``, ``w_ref``, ``shape``,
    ``trail``, ``polhode`` and ``view_values``."""

    def figure_view(self) -> physics.figure.View:
        """What the system's figure is drawn with: the body's drawn size and the view actions' values."""
        return physics.figure.View(extent=self.shape.extent, **self.view_values)

    def frame_figure(self) -> tuple:
        """The system's picture of the run's last state (physics.figure primitives, body frame, m)."""
        sc = self.scenario
        state = physics.figure.row_state(self.run.last.internal, 0)
        return tuple(physics.get_system(sc.system).figure(sc, state, self.figure_view()))

    def frame(self) -> Frame:
        run = self.run
        last = run.last
        q = last.quat[0]
        K = self.momentum()
        w_in = rotate(q, last.omega[0])
        axis = rotate(q, E3)
        torque = None
        if run.b > 0 and not run.ended:
            n = np.linalg.norm(K)
            torque = -run.b * K / n if n > 0 else None
        if self.view == "body":
            turn = np.array([q[0], -q[1], -q[2], -q[3]])  # inertial -> body components
            body_wxyz = np.array([1.0, 0, 0, 0])
            world = np.array([1.0, 0, 0, 0])
        else:
            turn = self.world_wxyz  # inertial -> the view with the initial K up
            body_wxyz = qmul(self.world_wxyz, q)
            world = self.world_wxyz

        def to_scene(v):
            return rotate(turn, v)
        size = self.shape.extent
        self.seq += 1
        fr = Frame(seq=self.seq, t=run.t, theta=float(last.theta[0]), K=float(last.K[0]), E=float(last.E[0]),
                   body_wxyz=body_wxyz, world_wxyz=world,
                   K_vec=to_scene(K) / self.K_ref * 1.0 * size,
                   omega_vec=to_scene(w_in) / self.w_ref * 0.9 * size,
                   axis_vec=to_scene(axis) * 0.9 * size,
                   torque_vec=None if torque is None else to_scene(torque) / (np.linalg.norm(torque)) * 0.6 * size,
                   status=run.status, message=run.message, applied=self.applied_seq)
        fr.figure = self.frame_figure()
        fr.trail = self.trail.values() * 0.9 * size  # the e3 arrow's tip draws it
        if self.show_polhode:
            fr.polhode = self.polhode.values()
        return fr

    def ellipsoid(self) -> np.ndarray:
        b = self.scenario.body
        return ellipsoid_axes(b.A, b.B, b.C, 0.6 * self.shape.extent)

    def _polhode_points(self, omega: np.ndarray) -> np.ndarray:
        """omega (n, 3, body components) scaled onto the drawn inertia ellipsoid w.J w = const: the
        polhode (Poinsot). The ellipsoid's semi-axes are size/sqrt(I_k) times sqrt(min I)."""
        b = self.scenario.body
        J = np.array([b.A, b.B, b.C])
        w = np.atleast_2d(omega)
        n = np.sqrt(np.maximum(np.einsum("ij,j,ij->i", w, J, w), 1e-300))[:, None]
        return w / n * (0.6 * self.shape.extent * math.sqrt(J.min()))

    def _trail_point(self, q: np.ndarray) -> np.ndarray:
        """Inertial view: the tip of the symmetry axis; body view: the direction of K in the body."""
        if self.view == "body":
            return rotate(np.array([q[0], -q[1], -q[2], -q[3]]), self.momentum_dir())
        return rotate(self.world_wxyz, rotate(q, E3))

    def momentum(self) -> np.ndarray:
        """Inertial total angular momentum now (kg m^2/s); a closed form's is fixed along its start's G, turned
        by where an edit restarted it (physics.LiveRun.momentum)."""
        return self.run.momentum()

    def momentum_dir(self) -> np.ndarray:
        K = self.momentum()
        n = np.linalg.norm(K)
        return K / n if n > 0 else E3
