"""The plain numpy right-hand sides of the benchmark's scipy peers (physics/reference/numpy_rhs.py) are the
same equations as the compiled kernels."""

import numpy as np
import pytest

import physics
from physics.reference.numpy_rhs import spherical_pendulum_rhs
from physics.reference.problems import p4

RATE_TOL = 1e-12  # relative: the same equations, assembled and solved differently


@pytest.mark.parametrize("seed", range(4))
def test_spherical_pendulum_rhs_matches_the_compiled_kernel(seed):
    sc = p4(1.0)
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    rng = np.random.default_rng(seed)
    y = model.initial_state(sc, p)
    y[:12] += 0.4 * rng.standard_normal(12)  # not the chart (last): it stays 0, the Cardan angles
    y[7:11] /= np.linalg.norm(y[7:11])
    compiled = model.rhs(0.0, y, p)
    assert np.max(np.abs(spherical_pendulum_rhs(p)(0.0, y) - compiled)) <= RATE_TOL * np.max(np.abs(compiled))


def test_spherical_pendulum_rhs_refuses_plane_pendulums():
    p = np.zeros(12 + 16)
    p[0], p[1] = 1, 1
    with pytest.raises(ValueError, match="spherical"):
        spherical_pendulum_rhs(p)
