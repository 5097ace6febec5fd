"""physics/reference (the independent references the tests and benchmarks share) stays out of the product, and
the seed 004 curve helpers that the figures script now takes from closed004 keep their meaning (issue 14)."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from physics.systems.moving_mass import closed004


def _modules_after(code: str) -> set[str]:
    """The module names loaded by a fresh interpreter after running ``code``."""
    done = subprocess.run([sys.executable, "-c", code + "\nimport sys; print(' '.join(sys.modules))"],
                          capture_output=True, text=True, timeout=120, check=True)
    return set(done.stdout.split())


def test_import_physics_loads_neither_the_references_nor_mujoco():
    loaded = _modules_after("import physics")
    assert "physics" in loaded and "physics.systems.moving_mass.closed004" in loaded  # the probe sees imports
    assert not {m for m in loaded if m.startswith("physics.reference")}
    assert "mujoco" not in loaded


def test_only_the_mujoco_references_import_mujoco():
    plain = _modules_after("import physics.reference.problems, physics.reference.numpy_rhs, "
                           "physics.reference.averaged_equations")
    assert "physics.reference.problems" in plain and "mujoco" not in plain
    pytest.importorskip("mujoco")
    assert "mujoco" in _modules_after("import physics.reference.mujoco_moving_mass")


@pytest.mark.parametrize("G0, b, lam", [(1.0, 0.01, 0.005), (2.5, 0.3, 0.02), (1.0, 1.0, 1e-3)])
def test_braking_tau_24_is_the_braking_time_in_units_of_the_medium(G0, b, lam):
    k_star = b / (lam * G0)
    assert closed004.braking_tau_24(k_star) == pytest.approx(lam * closed004.braking_time(G0, b, lam), rel=1e-12)


def test_braking_tau_24_without_control_never_stops_and_rejects_negative_k():
    assert closed004.braking_tau_24(0.0) == math.inf
    with pytest.raises(ValueError, match=r"k_star must be >= 0, got -0\.5"):
        closed004.braking_tau_24(-0.5)
    with pytest.raises(ValueError, match="k_star must be >= 0, got nan"):
        closed004.braking_tau_24(float("nan"))


def test_nutation_curve_24_samples_eq24_up_to_the_stop():
    theta0, G1, G2, k = math.pi / 4, -1.0, 5.0, 0.5
    tau, theta = closed004.nutation_curve_24(theta0, G1, G2, k, n=41)
    assert tau.shape == theta.shape == (41,)
    assert tau[0] == 0.0 and tau[-1] == closed004.braking_tau_24(k)
    np.testing.assert_array_equal(theta, closed004.nutation_angle_24(tau, theta0, G1, G2, k))
    assert theta[0] == pytest.approx(theta0, abs=1e-15) and abs(theta[-1] - theta0) > 1e-3  # it moved


@pytest.mark.parametrize("k_star, n, word", [(0.0, 11, "k_star must be > 0"), (0.5, 1, "n must be >= 2")])
def test_nutation_curve_24_refuses_a_curve_that_cannot_end(k_star, n, word):
    with pytest.raises(ValueError, match=word):
        closed004.nutation_curve_24(math.pi / 4, 1.0, 1.0, k_star, n=n)
