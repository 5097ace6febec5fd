"""The one place where compiled right-hand sides are dispatched by model id.

numba caches a compiled function only when every function it calls is a module-level global, so
the integrators call ``rhs(model, ...)`` below rather than taking the right-hand side as an
argument. Adding a compiled model means the next id (and N_KERNELS raised), its branch in ``rhs`` (and in the
other functions only where it has a fault, a chart or a braking law), and the id on its Model
(physics/systems/<system>/models.py). An id outside KERNELS (which registration refuses: physics.registry
checks a Model's kernel against it) gets NaN or a fault, never another model's value.
"""

from __future__ import annotations

import math

from numba import njit

from . import averaged as averaged_kernel
from . import mass_full as mass_full_kernel
from . import pendulum as pendulum_kernel
from . import wheel as wheel_kernel

MASS_FULL = 0
MASS_AVERAGED = 1
SPHERICAL_FULL = 2
PLANE_FULL = 3
MASS_AVERAGED_AXISYMMETRIC = 4  # the averaged model's slow (w_perp, w3) reduction, J*1 = J*2 only
WHEEL_FULL = 5
N_KERNELS = 6  # the ids above are 0 .. N_KERNELS - 1: a new kernel takes the next id and raises this
KERNELS = tuple(range(N_KERNELS))  # every id known here (registration refuses any other)
UNKNOWN_KERNEL_FAULT = 99  # fault()'s code for an id not in KERNELS


@njit(cache=True)
def rhs(model, t, y, p, out):
    if model == MASS_FULL:
        mass_full_kernel.rhs(t, y, p, out)
    elif model == MASS_AVERAGED:
        averaged_kernel.rhs(t, y, p, out)
    elif model == SPHERICAL_FULL or model == PLANE_FULL:
        pendulum_kernel.rhs(t, y, p, out)
    elif model == MASS_AVERAGED_AXISYMMETRIC:
        averaged_kernel.rhs_axisymmetric(t, y, p, out)
    elif model == WHEEL_FULL:
        wheel_kernel.rhs(t, y, p, out)
    else:  # unknown: a non-finite rate stops the run (status NONFINITE)
        for i in range(out.size):
            out[i] = math.nan


@njit(cache=True)
def fault(model, y, p):
    """0 while the state is valid; a positive code when the model has reached a state it cannot
    continue from (the gimbal singularity with a spring on the Cardan angles): the integrator stops there
    with status MODEL_FAULT."""
    if model == SPHERICAL_FULL:
        return pendulum_kernel.fault(y, p)
    if 0 <= model < N_KERNELS:
        return 0  # the other known models are defined everywhere
    return UNKNOWN_KERNEL_FAULT


@njit(cache=True)
def switch_chart(model, y, p):
    """Called after each accepted step: a model whose coordinates have a chart in use may re-express ``y``
    in another chart in place (the spherical pendulum near its gimbal pole). 1 when ``y`` changed (the
    integrator must then evaluate the right-hand side afresh), else 0."""
    if model == SPHERICAL_FULL:
        return pendulum_kernel.switch_chart(y, p)
    return 0  # one chart (an unknown id too: its rhs is NaN and fault() stops it)


@njit(cache=True)
def braking_norm(model, y, p):
    """|G| for the braking law: the run ends when it reaches zero (seed 004 eq. (11))."""
    if model == MASS_FULL:
        return mass_full_kernel.braking_norm(y, p)
    if model == MASS_AVERAGED_AXISYMMETRIC:
        return averaged_kernel.braking_norm_axisymmetric(y, p)
    if model == MASS_AVERAGED:
        return averaged_kernel.braking_norm(y, p)
    if 0 <= model < N_KERNELS:
        return 1.0  # a known model with no braking law (the pendulums, the wheel)
    return math.nan  # unknown
