"""The moving mass's and the pendulums' pictures against their geometry: the mass at O1 plus its exaggerated,
capped displacement; each bob on a sphere of radius l about its pivot, a plane bob in the plane normal to its
hinge axis."""

from __future__ import annotations

import math

import numpy as np
import pytest

import physics
from physics.core.figure import View
from physics.systems.moving_mass import figure as mass_figure
from physics.systems.pendulum import figure as pendulum_figure

LENGTH_TOL = 1e-12  # m, on lengths of order 1 m
MASS_SCENE = physics.Scenario.from_toml(physics.SYSTEMS["moving_mass"].example)


def _by_name(parts) -> dict:
    return {p.name: p for p in parts}


def test_the_mass_is_drawn_at_its_rest_point_plus_the_exaggerated_displacement():
    rho, u = MASS_SCENE.mass.rho, np.array([1e-3, -2e-3, 5e-4])
    parts = _by_name(mass_figure.figure(MASS_SCENE, dict(ux=u[0], uy=u[1], uz=u[2]), View(extent=3.0,
                                                                                          exaggeration=20.0)))
    rest = np.array([0.0, 0.0, rho])
    assert np.allclose(parts["rest"].centre, rest, atol=LENGTH_TOL)
    assert np.allclose(parts["mass"].centre, rest + 20.0 * u, atol=LENGTH_TOL)
    assert np.allclose(parts["spring"].points(), [rest, rest + 20.0 * u], atol=LENGTH_TOL)
    assert np.allclose(parts["mount"].points(), [np.zeros(3), rest], atol=LENGTH_TOL)
    assert parts["factor"].text == "u x 20" and "x 20" in parts["mass"].label


def test_a_large_factor_is_capped_at_a_fraction_of_the_body_and_says_so():
    extent = 2.0
    parts = _by_name(mass_figure.figure(MASS_SCENE, dict(ux=0.1, uy=0.0, uz=0.0), View(extent=extent,
                                                                                       exaggeration=1000.0)))
    drawn = np.array(parts["mass"].centre) - np.array(parts["rest"].centre)
    assert np.linalg.norm(drawn) == pytest.approx(mass_figure.CAP_FRACTION * extent, rel=1e-12)
    assert drawn[0] > 0 and parts["factor"].text == "u x 1000 (capped)"


def test_without_a_displacement_the_mass_rests_at_o1_and_no_spring_is_drawn():
    parts = _by_name(mass_figure.figure(MASS_SCENE, {}, View(extent=3.0)))
    assert np.allclose(parts["mass"].centre, parts["rest"].centre) and "spring" not in parts
    assert "at rest" in parts["mass"].label


def test_the_default_factor_is_a_readable_number_within_the_slider():
    assert mass_figure.default_exaggeration(1.0, 1.5, 10.0, 1.0) == 10.0  # |u| ~ 0.015 m: 0.15 / 0.015 = 10
    assert mass_figure.default_exaggeration(1.0, 1.5, 10.0, 1.2) == 5.0  # |u| ~ 0.0216 m: 6.9 -> 5
    assert mass_figure.default_exaggeration(1.0, 1e-9, 10.0, 1.0) == mass_figure.EXAGGERATION_MAX
    assert mass_figure.default_exaggeration(1.0, 1.5, 10.0, 0.0) == mass_figure.EXAGGERATION_MIN


@pytest.mark.parametrize("chart", [0.0, 1.0])
def test_the_spherical_bob_hangs_at_its_arm_length_from_the_pivot(chart):
    sc = physics.Scenario.from_toml(physics.SYSTEMS["spherical_pendulum"].example)
    p = sc.pendulum
    for alpha, beta in [(0.0, 0.0), (0.3, -0.2), (1.2, 0.9), (-2.5, 0.4)]:
        parts = _by_name(pendulum_figure.spherical_figure(sc, dict(alpha=alpha, beta=beta, chart=chart), View()))
        bob, (pivot, end) = np.array(parts["bob0"].centre), parts["arm0"].points()
        assert np.allclose(pivot, [0.0, 0.0, p.h]) and np.allclose(end, bob)
        assert np.linalg.norm(bob - pivot) == pytest.approx(p.l, abs=LENGTH_TOL)
        if alpha == beta == 0.0:
            assert np.allclose(bob, [0.0, 0.0, p.h + p.l], atol=LENGTH_TOL)  # both charts: along e3 at rest


def test_a_plane_bob_swings_in_the_plane_normal_to_its_hinge():
    sc = physics.Scenario.from_toml(physics.SYSTEMS["plane_pendulums"].example)
    angles = {f"a{i + 1}": 0.4 * (i + 1) for i in range(len(sc.plane_pendulums))}
    parts = _by_name(pendulum_figure.plane_figure(sc, angles, View()))
    for i, pp in enumerate(sc.plane_pendulums):
        hinge, n, e0 = pp.geometry()
        r = np.array(parts[f"bob{i}"].centre) - hinge
        assert np.linalg.norm(r) == pytest.approx(pp.l, abs=LENGTH_TOL)
        assert abs(r @ n) < LENGTH_TOL
        assert math.acos(np.clip(r @ e0 / pp.l, -1, 1)) == pytest.approx(0.4 * (i + 1), abs=1e-9)
    assert "bobs (3)" in parts["bob0"].label


def test_a_disk_is_drawn_with_its_face_rim_and_spokes_turning_with_its_angle():
    """app.scene.figure_view draws a physics Disk: the rim on its circle, SPOKES radii from its angle (so a
    turning wheel is seen to turn), and a face that covers the circle; all in the disk's plane."""
    from app.scene.figure_view import DISK_SIDES, SPOKES, disk_face, disk_segments

    n = np.array([1.0, 2.0, 2.0]) / 3.0
    ref = np.cross(n, [0.0, 0.0, 1.0])
    ref /= np.linalg.norm(ref)
    disk = physics.figure.Disk(name="w", role="w", label="w", colour="wheel", centre=(0.1, 0.0, 0.2), normal=n,
                               ref=ref, radius=0.5, angle=0.7)
    k, size = 2.0, 1.5
    c = k * np.array(disk.centre)
    segs = disk_segments(disk, k, size)
    assert segs.shape == (DISK_SIDES + SPOKES, 2, 3)
    np.testing.assert_allclose(np.linalg.norm(segs[:DISK_SIDES, 0] - c, axis=1), k * 0.5, rtol=1e-12)
    np.testing.assert_allclose((segs.reshape(-1, 3) - c) @ n, 0.0, atol=1e-12)  # all in the disk's plane
    first = segs[DISK_SIDES, 1] - c
    f = np.cross(n, ref)
    np.testing.assert_allclose(first, k * 0.5 * (np.cos(0.7) * ref + np.sin(0.7) * f), atol=1e-12)
    turned = disk_segments(physics.figure.Disk(**{**disk.__dict__, "angle": 0.7 + 0.3}), k, size)
    assert not np.allclose(turned[DISK_SIDES:], segs[DISK_SIDES:])  # the spokes turn
    np.testing.assert_allclose(turned[:DISK_SIDES], segs[:DISK_SIDES], atol=1e-12)  # the rim stays
    vertices, faces = disk_face(disk, k, size)
    assert faces.min() == 0 and faces.max() == len(vertices) - 1
    area = sum(0.5 * np.linalg.norm(np.cross(vertices[b] - vertices[a], vertices[c_] - vertices[a]))
               for a, b, c_ in faces)
    polygon = 0.5 * DISK_SIDES * (k * 0.5) ** 2 * np.sin(2 * np.pi / DISK_SIDES)  # the inscribed polygon's area
    assert area == pytest.approx(polygon, rel=1e-12)
