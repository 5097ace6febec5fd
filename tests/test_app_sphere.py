"""The momentum sphere's numbers (app.engine.sphere): polhodes on both the sphere and the energy ellipsoid, the
separatrix only for three different moments, K's path in body axes, the pure spins' energies."""

from __future__ import annotations

import math

import numpy as np
import pytest

import physics
from app.engine import sphere

ON_SURFACE_TOL = 1e-9  # |x|^2 - 1 and h(x) - h, dimensionless (unit sphere, h in 1/(kg m^2))
ASYMMETRIC = (1.5, 1.0, 2.0)  # the flip preset's A, B, C
OBLATE, PROLATE = (1.0, 1.0, 1.4), (1.0, 1.0, 0.5)


@pytest.mark.parametrize("moments", [ASYMMETRIC, OBLATE, PROLATE, (3.0, 2.0, 1.0), (2.0, 1.0, 1.0)])
def test_every_polhode_lies_on_the_sphere_and_on_its_energy_ellipsoid(moments):
    curves = sphere.polhodes(moments)
    assert len(curves) >= sphere.LEVELS_PER_SIDE
    inv = 1.0 / np.array(moments)
    for h, _, pts in curves:
        assert 1 / max(moments) - ON_SURFACE_TOL <= h <= 1 / min(moments) + ON_SURFACE_TOL
        np.testing.assert_allclose(np.einsum("ij,ij->i", pts, pts), 1.0, rtol=0, atol=ON_SURFACE_TOL)
        np.testing.assert_allclose(pts ** 2 @ inv, h, rtol=0, atol=ON_SURFACE_TOL)
        np.testing.assert_allclose(pts[0], pts[-1], atol=ON_SURFACE_TOL)  # closed


def test_levels_are_distinct_and_lie_between_the_pure_spins():
    hs = sorted({round(h, 12) for h, _, _ in sphere.polhodes(ASYMMETRIC)})
    assert len(hs) == 2 * sphere.LEVELS_PER_SIDE
    A, B, C = ASYMMETRIC
    assert 1 / C < hs[0] and hs[-1] < 1 / B
    assert 1 / A not in hs  # the separatrix's level is drawn apart


def test_separatrix_present_for_three_different_moments_and_on_both_surfaces():
    seps = sphere.separatrices(ASYMMETRIC)
    assert len(seps) == 2
    assert sphere.has_separatrix(ASYMMETRIC)
    A = ASYMMETRIC[0]  # the intermediate moment
    for pts in seps:
        np.testing.assert_allclose(np.einsum("ij,ij->i", pts, pts), 1.0, rtol=0, atol=ON_SURFACE_TOL)
        np.testing.assert_allclose(sphere.level(pts, ASYMMETRIC), 1 / A, rtol=0, atol=ON_SURFACE_TOL)
        assert np.max(np.abs(pts[:, 0])) == pytest.approx(1.0)  # it passes through the intermediate axis e1


@pytest.mark.parametrize("moments", [OBLATE, PROLATE, (2.0, 1.0, 1.0), (1.2, 1.2, 1.2)])
def test_no_separatrix_when_two_moments_are_equal(moments):
    assert sphere.separatrices(moments) == []
    assert not sphere.has_separatrix(moments)


def test_a_symmetric_body_has_circles_of_latitude_about_its_axis():
    for _, axis, pts in sphere.polhodes(OBLATE):
        assert axis == 2
        assert np.ptp(pts[:, 2]) < ON_SURFACE_TOL  # e3 component fixed along the curve: a circle of latitude
    assert sphere.polhodes((1.2, 1.2, 1.2)) == []  # a sphere: every K is a steady spin


@pytest.mark.parametrize("bad", [(1.0, 0.0, 2.0), (1.0, -1.0, 1.0), (1.0, math.nan, 1.0), (1.0, 2.0)])
def test_bad_moments_are_refused_naming_them(bad):
    with pytest.raises(ValueError, match="moments"):
        sphere.polhodes(bad)


def test_the_path_is_K_in_body_axes_thinned_and_bounded():
    K = np.array([0.3, -0.2, 2.0])
    angles = np.linspace(0.0, 2.0, 400)
    quats = np.column_stack([np.cos(angles / 2), np.zeros_like(angles), np.sin(angles / 2), np.zeros_like(angles)])
    path = sphere.MomentumPath(capacity=50)
    path.extend(quats, K)
    pts = path.values()
    assert len(pts) <= 50
    expected = physics.rotate(physics.qconj(quats[-1]), K / np.linalg.norm(K))
    np.testing.assert_allclose(path.now, expected, atol=1e-12)  # K now, even when not kept
    np.testing.assert_allclose(np.linalg.norm(pts, axis=1), 1.0, atol=1e-12)
    steps = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert steps.min() >= sphere.MIN_STEP  # thinned by distance
    v = path.version
    path.extend(quats[-1:], K)  # the same point again: too close to be kept, nothing to resend
    assert path.version == v


def test_path_segments_leave_out_long_chords():
    p = np.array([[1.0, 0, 0], [0.99, 0.1, 0], [-1.0, 0, 0], [-0.99, 0.1, 0]])
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    seg = sphere.path_segments(p)
    assert seg.shape == (2, 2, 3)  # the jump across the sphere is not drawn


def test_pure_spin_energies():
    e = sphere.pure_spin_energies(np.array([2.0, 3.0]), ASYMMETRIC)
    np.testing.assert_allclose(e[:, 0], [4 / 3.0, 4 / 2.0, 4 / 4.0])
    assert e.shape == (3, 2)


def test_the_engine_traces_K_in_body_axes_and_it_crosses_the_curves_towards_the_largest_axis():
    """The default scene (oblate, a dissipating mass): the path's frozen-body level h = 2E/|K|^2 falls towards
    1/C, the spin about e3; the path's last point is K now in body axes; hiding the sphere keeps tracing."""
    from app.engine.engine import Engine

    eng = Engine()
    eng.warp = 10.0
    for _ in range(120):
        eng.tick(1 / 60)
    eng.request("sphere", False)
    for _ in range(120):
        eng.tick(1 / 60)
    assert eng.show_sphere is False
    path = eng.sphere_path.values()
    assert len(path) > 50
    K = eng.momentum()
    now = physics.rotate(physics.qconj(eng.run.last.quat[0]), K / np.linalg.norm(K))
    np.testing.assert_allclose(eng.sphere_path.now, now, atol=1e-12)
    b = eng.scenario.body
    h = sphere.level(path, (b.A, b.B, b.C))
    assert eng.run.t > 30.0
    assert h[-1] < h[0] - 0.3 * (h[0] - 1 / b.C)  # a third of the way or more down to the steady spin's level
    eng.request("reset")
    eng.tick(1 / 60)
    assert eng.sphere_path.size <= 2  # a new run starts a new path
