"""A user's mesh (--mesh): trimesh's inertia, the axis convention (e3 the most distinct moment), and
the engine drawing it."""

from __future__ import annotations

import numpy as np
import pytest
import trimesh

import physics
from app.engine.geometry import shape_moments
from app.engine.mesh import load_mesh, principal_order, with_mesh
from app.state import Engine

MOMENT_TOL = 1e-6  # relative: trimesh integrates a box exactly, but STL stores float32 vertices


def test_a_box_mesh_has_the_box_moments_with_e3_the_distinct_axis(tmp_path):
    path = tmp_path / "plate.stl"
    trimesh.creation.box(extents=(1.0, 0.2, 1.0)).export(path)  # a square plate: its normal (y) is distinct
    M = 2.0
    mesh = load_mesh(path, M)
    a, b, c = 1.0, 1.0, 0.2  # after the turn the plate's normal is e3
    from app.engine.geometry import Shape

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


def test_own_box_and_cylinder_meshes_are_closed_with_the_exact_volume():
    from app.engine.geometry import box_mesh, cylinder_mesh

    v, f = box_mesh((1.0, 2.0, 3.0))
    box = trimesh.Trimesh(v, f, process=False)
    assert box.is_watertight and box.is_winding_consistent and box.volume == pytest.approx(6.0, rel=1e-12)
    n = 48
    v, f = cylinder_mesh(0.5, 0.2, n)
    cyl = trimesh.Trimesh(v, f)  # merging the caps' copies of the rim vertices closes it
    polygon = 0.5 * n * 0.5**2 * np.sin(2 * np.pi / n)  # the inscribed n-gon's area
    assert cyl.is_watertight and cyl.volume == pytest.approx(polygon * 0.2, rel=1e-12)  # positive: wound outward


def test_the_satellite_asset_is_a_closed_prolate_body():
    from app.engine.mesh import asset_names, asset_path

    assert "satellite.stl" in asset_names()
    mesh = load_mesh(asset_path("satellite.stl"), 500.0)
    A, B, C = mesh.moments
    assert C < min(A, B)  # the wings' axis is e3, the smallest moment: it ends in a flat spin
    assert A + B > C and B + C > A and A + C > B


def test_the_engine_draws_an_asset_mesh_and_refuses_anything_else():
    from app.engine.mesh import scaled_to

    e = Engine()
    before = e.scenario.body
    e.request("mesh", "satellite.stl")
    e.tick(1 / 60)
    b = e.scenario.body
    assert e.error == "" and e.mesh is not None and e.shape.kind == "mesh"
    assert b.A + b.B + b.C == pytest.approx(before.A + before.B + before.C, rel=1e-12)  # scaled_to keeps the sum
    assert b.C < min(b.A, b.B)
    assert scaled_to(e.mesh, b).moments == pytest.approx(e.mesh.moments, rel=1e-12)
    for bad in ("../pyproject.toml", "/etc/passwd", "satellite.stl/.."):
        e.request("mesh", bad)
        e.tick(1 / 60)
        assert "is not a mesh in assets/meshes" in e.error and e.scenario.body == b  # the last good state stays
    e.request("mesh", "inertia shape")
    e.tick(1 / 60)
    assert e.mesh is None and e.shape.kind != "mesh"
