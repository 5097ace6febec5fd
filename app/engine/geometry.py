"""What the 3-D scene shows, as plain numbers (no viser here, so it is testable headless).

Conventions (docs/models.md): body axes e1, e2, e3 are principal, e3 the symmetry axis; quaternions are
scalar first (w, x, y, z) and rotate body components into inertial ones, which is viser's ``wxyz``.
Lengths are metres; the server scales the whole scene so the body is about 1.5 units across.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from physics import qconj, qmul, rotate  # noqa: F401  (physics' quaternions, named here for the scene's tests)

E3 = np.array([0.0, 0.0, 1.0])


# ---- quaternions (the products and rotations are physics') -----------------------------------------

def align(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The shortest rotation (quaternion) taking direction a to direction b."""
    a = np.asarray(a, dtype=float) / np.linalg.norm(a)
    b = np.asarray(b, dtype=float) / np.linalg.norm(b)
    c = float(a @ b)
    if c < -1 + 1e-12:  # opposite: half a turn about any axis normal to a
        axis = np.cross(a, [1.0, 0.0, 0.0])
        if np.linalg.norm(axis) < 1e-6:
            axis = np.cross(a, [0.0, 1.0, 0.0])
        axis /= np.linalg.norm(axis)
        return np.array([0.0, *axis])
    q = np.array([1.0 + c, *np.cross(a, b)])
    return q / np.linalg.norm(q)


# ---- the body --------------------------------------------------------------------------------

@dataclass(frozen=True)
class Shape:
    """A uniform solid with the given principal moments: ``kind`` "disk", "rod" or "cylinder" (a
    circular cylinder along e3 of ``radius`` and ``height``), or "box" (side lengths ``dims``); "mesh"
    is a user's mesh, ``dims`` its bounding box."""

    kind: str
    radius: float = 0.0
    height: float = 0.0
    dims: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def extent(self) -> float:
        """Largest size, m."""
        if self.kind in ("box", "mesh"):
            return float(max(self.dims))
        return float(max(2 * self.radius, self.height))


SYMMETRY_TOL = 1e-9  # relative |A - B| below which the body is axisymmetric
THIN = 0.04  # a limiting flat plate or thin rod is drawn this fraction of its size thick
SIZE_RANGE = (1e-150, 1e150)  # m: a body's drawn size is kept within (its pixels are the same at any size)


def body_shape(A: float, B: float, C: float, M: float) -> Shape:
    """Uniform solid of mass M (kg) with principal moments A, B, C (kg m^2).

    Axisymmetric (A = B): a cylinder along e3 with C = M R^2/2, A = M(3R^2 + h^2)/12, so
    R = sqrt(2C/M), h = sqrt(12A/M - 6C/M): a disk when C > A (oblate), a rod when C < A (prolate).
    Otherwise a box with A = M(b^2 + c^2)/12 and so on: a = sqrt(6(B + C - A)/M), ...
    Sizes scale as sqrt(I/M), computed without forming I/M (A = 1 with M = 5e-324 overflows it) and kept within
    SIZE_RANGE m, so that a drawing, which shows every body at one size, always has a finite scale.
    """
    r = max(A, B, C)
    scale = min(max(math.sqrt(r) / math.sqrt(M), SIZE_RANGE[0]), SIZE_RANGE[1])
    A, B, C = A / r, B / r, C / r  # the shape of a body with M = 1 and moments of order 1, scaled below
    if abs(A - B) <= SYMMETRY_TOL * A:
        R = math.sqrt(2 * C)
        h = math.sqrt(max(12 * A - 6 * C, 0.0))
        h = max(h, THIN * 2 * R)
        kind = "disk" if C > A * (1 + SYMMETRY_TOL) else "rod" if C < A * (1 - SYMMETRY_TOL) else "cylinder"
        return Shape(kind, radius=R * scale, height=h * scale)
    sides = np.sqrt(np.maximum(6.0 * np.array([B + C - A, A + C - B, A + B - C]), 0.0))
    sides = np.maximum(sides, THIN * sides.max())
    return Shape("box", dims=tuple(float(s * scale) for s in sides))


def box_mesh(dims) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (8, 3), faces (12, 3)) of a box with side lengths ``dims`` centred at the origin,
    faces wound outward."""
    half = 0.5 * np.asarray(dims, dtype=float)
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * half
    quads = ((0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3))
    faces = np.array([tri for a, b, c, d in quads for tri in ((a, b, c), (a, c, d))])
    return corners, faces


def cylinder_mesh(radius: float, height: float, sections: int = 48) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, faces) of a closed circular cylinder along e3 centred at the origin, wound outward.
    The caps have their own copies of the rim vertices, so smooth shading keeps the rims sharp. Built
    here rather than with trimesh so the server starts without importing it (about 0.7 s)."""
    a = np.linspace(0.0, 2 * np.pi, sections, endpoint=False)
    ring = np.column_stack([radius * np.cos(a), radius * np.sin(a), np.zeros(sections)])
    lo, hi = ring - [0, 0, height / 2], ring + [0, 0, height / 2]
    n = sections
    vertices = np.vstack([lo, hi, lo, hi, [[0, 0, -height / 2], [0, 0, height / 2]]])  # side rims, cap rims, centres
    i = np.arange(n)
    j = (i + 1) % n
    bottom, top = 4 * n, 4 * n + 1
    side = np.concatenate([np.column_stack([i, j, j + n]), np.column_stack([i, j + n, i + n])])
    caps = np.concatenate([np.column_stack([np.full(n, bottom), j + 2 * n, i + 2 * n]),
                           np.column_stack([np.full(n, top), i + 3 * n, j + 3 * n])])
    return vertices, np.concatenate([side, caps]).astype(np.int64)


def shape_moments(shape: Shape, M: float) -> np.ndarray:
    """Principal moments (3,) of a uniform ``shape`` of mass M: the inverse of body_shape."""
    if shape.kind == "box":
        a, b, c = shape.dims
        return M / 12 * np.array([b * b + c * c, a * a + c * c, a * a + b * b])
    R, h = shape.radius, shape.height
    A = M * (3 * R * R + h * h) / 12
    return np.array([A, A, M * R * R / 2])


def ellipsoid_axes(A: float, B: float, C: float, size: float) -> np.ndarray:
    """Semi-axes (3,) of the inertia ellipsoid, proportional to 1/sqrt(moment), largest = size."""
    s = 1.0 / np.sqrt(np.array([A, B, C]))
    return size * s / s.max()


# ---- ring buffers ----------------------------------------------------------------------------

class Ring:
    """A fixed-capacity buffer of rows (capacity, width): memory stays bounded however long it runs."""

    def __init__(self, capacity: int, width: int):
        self.data = np.full((capacity, width), 0.0)  # written now: its pages count from the start, not as it fills
        self.start = 0
        self.size = 0

    @property
    def capacity(self) -> int:
        return self.data.shape[0]

    def clear(self) -> None:
        self.start = self.size = 0

    def extend(self, rows: np.ndarray) -> None:
        rows = np.atleast_2d(np.asarray(rows, dtype=float))[-self.capacity:]
        for row in rows:  # a few rows per frame: a loop is simplest and cheap
            i = (self.start + self.size) % self.capacity
            self.data[i] = row
            if self.size < self.capacity:
                self.size += 1
            else:
                self.start = (self.start + 1) % self.capacity

    def values(self) -> np.ndarray:
        """Rows oldest first, a copy (size, width)."""
        idx = (self.start + np.arange(self.size)) % self.capacity
        return self.data[idx].copy()

    def __len__(self) -> int:
        return self.size


def trail_segments(points: np.ndarray) -> np.ndarray:
    """Consecutive points (n, 3) as line segments (max(n - 1, 1), 2, 3) for viser's line segments."""
    if len(points) < 2:
        p = points[0] if len(points) else np.zeros(3)
        return np.array([[p, p]])
    return np.stack([points[:-1], points[1:]], axis=1)
