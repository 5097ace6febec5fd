"""A user's mesh (--mesh): trimesh's inertia, the axis convention (e3 the most distinct moment), and
the engine drawing it."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import physics
from app.mesh import load_mesh, principal_order, with_mesh
from app.scene import shape_moments
from app.state import Engine

MOMENT_TOL = 1e-6  # relative: trimesh integrates a box exactly, but STL stores float32 vertices


def test_a_box_mesh_has_the_box_moments_with_e3_the_distinct_axis(tmp_path):
    path = tmp_path / "plate.stl"
    trimesh.creation.box(extents=(1.0, 0.2, 1.0)).export(path)  # a square plate: its normal (y) is distinct
    M = 2.0
    mesh = load_mesh(path, M)
    a, b, c = 1.0, 1.0, 0.2  # after the turn the plate's normal is e3
    from app.scene import Shape

    np.testing.assert_allclose(mesh.moments, shape_moments(Shape("box", dims=(a, b, c)), M), rtol=MOMENT_TOL)
    ext = mesh.vertices.max(axis=0) - mesh.vertices.min(axis=0)
    np.testing.assert_allclose(ext, [1.0, 1.0, 0.2], atol=1e-12)
    sc = with_mesh(physics.default_scenario(), mesh)
    assert sc.body.A == sc.body.B and sc.body.C == pytest.approx(mesh.moments[2])


def test_principal_order():
    assert list(principal_order(np.array([2.0, 1.0, 1.0]))) == [1, 2, 0]
    assert list(principal_order(np.array([1.0, 1.0, 2.0]))) == [0, 1, 2]


def test_an_open_or_unreadable_mesh_is_rejected(tmp_path):
    box = trimesh.creation.box()
    open_mesh = trimesh.Trimesh(box.vertices, box.faces[:-2])  # two triangles missing: not closed
    path = tmp_path / "open.stl"
    open_mesh.export(path)
    with pytest.raises(physics.ScenarioError, match="watertight"):
        load_mesh(path, 1.0)
    bad = tmp_path / "bad.stl"
    bad.write_text("not a mesh")
    with pytest.raises(physics.ScenarioError):
        load_mesh(bad, 1.0)


def test_the_engine_draws_a_mesh_until_a_preset_is_loaded(tmp_path):
    path = tmp_path / "cyl.stl"
    # wide enough that the default moving mass fits inside its inertia (m rho^2/(1 - m/M) < A)
    trimesh.creation.cylinder(radius=2.0, height=0.6, sections=64).export(path)
    mesh = load_mesh(path, 1.0)
    e = Engine(with_mesh(physics.default_scenario(), mesh), mesh=mesh)
    assert e.shape.kind == "mesh" and e.preset.startswith("mesh")
    fr = e.tick(1 / 60)
    assert fr.t > 0 and np.isfinite(fr.theta)
    e.request("preset", "Explorer 1's flat spin")
    e.tick(1 / 60)
    assert e.mesh is None and e.shape.kind == "rod"
