"""Headless checks of the scene geometry (app/engine/geometry.py): shapes with matching moments, the inertia
ellipsoid, quaternions, parts' positions and the bounded ring buffers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.engine.geometry import (
    E3,
    Ring,
    align,
    body_shape,
    ellipsoid_axes,
    qconj,
    qmul,
    rotate,
    shape_moments,
    trail_segments,
)
from physics.systems.moving_mass.figure import mass_points
from physics.systems.pendulum.figure import plane_bob, spherical_bob

MOMENT_TOL = 1e-12  # relative


@pytest.mark.parametrize("A, B, C, kind", [(1.0, 1.0, 1.4, "disk"), (1.0, 1.0, 0.5, "rod"),
                                           (1.0, 1.0, 1.0, "cylinder"), (1.5, 1.0, 2.0, "box"),
                                           (2.0, 3.0, 4.0, "box")])
def test_body_shape_has_the_given_moments(A, B, C, kind):
    M = 2.5
    shape = body_shape(A, B, C, M)
    assert shape.kind == kind
    np.testing.assert_allclose(shape_moments(shape, M), [A, B, C], rtol=MOMENT_TOL)


def test_an_oblate_disk_is_flatter_than_a_prolate_rod():
    disk, rod = body_shape(1.0, 1.0, 1.9, 1.0), body_shape(1.0, 1.0, 0.2, 1.0)
    assert disk.height < 2 * disk.radius and rod.height > 2 * rod.radius


def test_ellipsoid_semi_axes_go_as_one_over_sqrt_moment():
    ax = ellipsoid_axes(1.0, 2.0, 4.0, size=3.0)
    assert ax.max() == pytest.approx(3.0)
    np.testing.assert_allclose(ax * np.sqrt([1.0, 2.0, 4.0]), ax[0] * 1.0, rtol=1e-14)


def test_quaternion_helpers():
    q = np.array([math.cos(0.3), math.sin(0.3), 0.0, 0.0])  # 0.6 rad about x
    v = rotate(q, E3)
    np.testing.assert_allclose(v, [0.0, -math.sin(0.6), math.cos(0.6)], atol=1e-15)
    np.testing.assert_allclose(rotate(qmul(qconj(q), q), E3), E3, atol=1e-15)
    for a in ([1.0, 2.0, 3.0], [0.0, 0.0, -1.0], [0.0, 0.0, 1.0]):
        np.testing.assert_allclose(rotate(align(a, E3), np.array(a) / np.linalg.norm(a)), E3, atol=1e-12)


def test_parts_positions():
    rest, pos = mass_points(1.5, np.array([0.01, 0.0, 0.0]), 10.0)
    np.testing.assert_allclose(rest, [0, 0, 1.5])
    np.testing.assert_allclose(pos, [0.1, 0, 1.5])
    pivot, bob = spherical_bob(0.5, 0.3, 0.0, 0.0)
    np.testing.assert_allclose(bob, [0, 0, 0.8])
    hinge, bob = plane_bob([0.5, 0, 0], [0, 0, 1], [1, 0, 0], 0.2, math.pi / 2)
    np.testing.assert_allclose(bob, [0.5, 0.2, 0.0], atol=1e-15)


def test_ring_buffer_is_bounded_and_ordered():
    r = Ring(5, 2)
    r.extend(np.arange(16).reshape(8, 2))
    assert len(r) == 5
    np.testing.assert_array_equal(r.values()[:, 0], [6, 8, 10, 12, 14])
    r.extend(np.arange(100).reshape(50, 2))
    np.testing.assert_array_equal(r.values()[-1], [98, 99])
    assert r.data.shape == (5, 2)
    r.clear()
    assert len(r) == 0 and r.values().shape == (0, 2)


def test_trail_segments():
    pts = np.arange(12.0).reshape(4, 3)
    seg = trail_segments(pts)
    assert seg.shape == (3, 2, 3)
    np.testing.assert_array_equal(seg[1], pts[1:3])
    assert trail_segments(np.zeros((0, 3))).shape == (1, 2, 3)
