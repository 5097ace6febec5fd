"""A user's own body mesh (``python -m app --mesh FILE``): trimesh computes its inertia.

The mesh is taken as a uniform solid of the scenario's total mass M. It is moved to its centre of
mass and turned to its principal axes; the axis whose moment stands most apart becomes e3 (the
symmetry axis, docs/models.md conventions), and the scenario's A, B, C become the mesh's moments.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

import physics

MESH_DIR = Path(__file__).resolve().parents[2] / "assets" / "meshes"
MESH_SUFFIXES = (".stl", ".obj", ".ply", ".glb", ".off")
INERTIA_SHAPE = "inertia shape"  # the GUI's name for "no mesh: the uniform solid of the body's inertia"
EXTENT_MIN, EXTENT_MAX = 1e-50, 1e50  # m: coordinates whose fifth powers (inertia integrals) stay finite
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

    path = Path(path)  # named whole in an error (physics.ScenarioError shows a path's file name)
    try:
        mesh = trimesh.load(str(path), force="mesh")
    except Exception as exc:  # trimesh raises many kinds for unreadable files
        raise physics.ScenarioError("--mesh", path, f"cannot be read as a mesh ({exc})") from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise physics.ScenarioError("--mesh", path, "holds no triangles")
    extent = float(np.max(np.abs(mesh.vertices))) if len(mesh.vertices) else 0.0
    if not EXTENT_MIN <= extent <= EXTENT_MAX:  # the inertia integrals are fifth powers of the coordinates
        raise physics.ScenarioError("--mesh", path, f"has coordinates up to {extent:.3g} in size; they must "
                                    f"reach between {EXTENT_MIN:g} and {EXTENT_MAX:g} (m) so that its inertia "
                                    "stays within floating point: rescale the mesh")
    if not mesh.is_watertight or not mesh.volume > 0:
        raise physics.ScenarioError("--mesh", path, "must be a closed (watertight) surface enclosing a volume, "
                                    "so that its inertia is defined")
    mesh = mesh.copy()
    mesh.density = M / mesh.volume
    try:
        with np.errstate(all="ignore"):
            mesh.apply_transform(mesh.principal_inertia_transform)  # COM to the origin, principal axes along x, y, z
            I = np.asarray(mesh.moment_inertia, dtype=float)
    except (np.linalg.LinAlgError, ValueError, ArithmeticError) as exc:
        raise physics.ScenarioError("--mesh", path, f"its inertia cannot be computed ({exc}); "
                                    "rescale the mesh") from None
    if not np.all(np.isfinite(I)) or not np.all(np.isfinite(mesh.vertices)):
        raise physics.ScenarioError("--mesh", path, "its inertia is not finite; rescale the mesh")
    order = principal_order(np.diag(I))
    P = np.eye(3)[order]  # new coordinates = P @ old
    if np.linalg.det(P) < 0:
        P[0] *= -1.0  # keep the frame right-handed
    vertices = np.asarray(mesh.vertices, dtype=float) @ P.T
    moments = np.diag(P @ I @ P.T).copy()
    return BodyMesh(vertices=vertices, faces=np.asarray(mesh.faces), moments=moments, name=path.name)


def with_mesh(sc: physics.Scenario, mesh: BodyMesh) -> physics.Scenario:
    """``sc`` with the body's principal moments taken from the mesh (validated by physics)."""
    A, B, C = (float(x) for x in mesh.moments)
    if abs(A - B) <= SYMMETRIC * A:  # a symmetric mesh, up to its facets: let the averaged models apply
        A = B = 0.5 * (A + B)
    return sc.with_values(**{"body.A": A, "body.B": B, "body.C": C})


def asset_names() -> list[str]:
    """The meshes shipped in assets/meshes (file names), for the GUI's body dropdown."""
    return sorted(p.name for p in MESH_DIR.iterdir() if p.suffix.lower() in MESH_SUFFIXES) if MESH_DIR.is_dir() else []


def asset_path(name: str) -> Path:
    """The path of a shipped mesh by its file name; anything else (a path, "..") is refused, so what a
    browser sends can never name a file outside assets/meshes."""
    if name not in asset_names():
        raise physics.ScenarioError("body mesh", name, f"is not a mesh in assets/meshes ({', '.join(asset_names())})")
    return MESH_DIR / name


def scaled_to(mesh: BodyMesh, body: physics.Body) -> BodyMesh:
    """``mesh`` scaled uniformly so that its moments sum to A + B + C of ``body`` (same mass): an asset's
    shape and inertia ratios, at the size of the scene it joins, so the internal parts still fit."""
    s = float(np.sqrt((body.A + body.B + body.C) / np.sum(mesh.moments)))
    return BodyMesh(vertices=mesh.vertices * s, faces=mesh.faces, moments=mesh.moments * s * s, name=mesh.name)
