"""A user's own body mesh (``python -m app --mesh FILE``): trimesh computes its inertia.

The mesh is taken as a uniform solid of the scenario's total mass M. It is moved to its centre of
mass and turned to its principal axes; the axis whose moment stands most apart becomes e3 (the
symmetry axis, MODELS conventions), and the scenario's A, B, C become the mesh's moments.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import physics

SYMMETRIC = 1e-6  # relative |A - B| below which a mesh counts as axisymmetric (facets break the symmetry)


@dataclass(frozen=True)
class BodyMesh:
    """Vertices (n, 3) in the body frame (principal axes, COM at the origin), m; faces (k, 3);
    principal moments (A, B, C) of a uniform solid of mass M, kg m^2."""

    vertices: np.ndarray
    faces: np.ndarray
    moments: np.ndarray
    name: str = "mesh"


def principal_order(moments: np.ndarray) -> np.ndarray:
    """Indices (e1, e2, e3) that put the two closest moments first: e3 is the most distinct axis."""
    m = np.asarray(moments, dtype=float)
    pairs = [(abs(m[i] - m[j]) / max(m[i], m[j]), i, j) for i, j in ((0, 1), (0, 2), (1, 2))]
    _, i, j = min(pairs)
    k = 3 - i - j
    return np.array([i, j, k])


def load_mesh(path: str | Path, M: float) -> BodyMesh:
    """Read a mesh file (any format trimesh reads) as a uniform solid of mass M (kg).
    Raises ScenarioError when it cannot be read or does not enclose a volume."""
    import trimesh

    try:
        mesh = trimesh.load(str(path), force="mesh")
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise physics.ScenarioError("--mesh", str(path), f"cannot be read as a mesh ({exc})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise physics.ScenarioError("--mesh", str(path), "holds no triangles")
    if not mesh.is_watertight or mesh.volume <= 0:
        raise physics.ScenarioError("--mesh", str(path), "must be a closed (watertight) surface enclosing a volume, "
                                    "so that its inertia is defined")
    mesh = mesh.copy()
    mesh.density = M / mesh.volume
    mesh.apply_transform(mesh.principal_inertia_transform)  # COM to the origin, principal axes along x, y, z
    I = np.asarray(mesh.moment_inertia, dtype=float)
    order = principal_order(np.diag(I))
    P = np.eye(3)[order]  # new coordinates = P @ old
    if np.linalg.det(P) < 0:
        P[0] *= -1.0  # keep the frame right-handed
    vertices = np.asarray(mesh.vertices, dtype=float) @ P.T
    moments = np.diag(P @ I @ P.T).copy()
    return BodyMesh(vertices=vertices, faces=np.asarray(mesh.faces), moments=moments, name=Path(path).name)


def with_mesh(sc: physics.Scenario, mesh: BodyMesh) -> physics.Scenario:
    """``sc`` with the body's principal moments taken from the mesh (validated by physics)."""
    A, B, C = (float(x) for x in mesh.moments)
    if abs(A - B) <= SYMMETRIC * A:  # a symmetric mesh, up to its facets: let the averaged models apply
        A = B = 0.5 * (A + B)
    return sc.with_values(**{"body.A": A, "body.B": B, "body.C": C})
