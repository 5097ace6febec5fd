"""The one place where compiled right-hand sides are dispatched by model id.

numba caches a compiled function only when every function it calls is a module-level global, so
the integrators call ``rhs(model, ...)`` below rather than taking the right-hand side as an
argument. Registering a compiled model means adding a branch here and its id in models/.
"""

from __future__ import annotations

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


@njit(cache=True)
def fault(model, y, p):
    """0 while the state is valid; a positive code when the model has reached a state it cannot
    continue from (the gimbal singularity with a spring on the Cardan angles): the integrator stops there
    with status MODEL_FAULT."""
    if model == SPHERICAL_FULL:
        return pendulum_kernel.fault(y, p)
    return 0


@njit(cache=True)
def switch_chart(model, y, p):
    """Called after each accepted step: a model whose coordinates have a chart in use may re-express ``y``
    in another chart in place (the spherical pendulum near its gimbal pole). 1 when ``y`` changed (the
    integrator must then evaluate the right-hand side afresh), else 0."""
    if model == SPHERICAL_FULL:
        return pendulum_kernel.switch_chart(y, p)
    return 0


@njit(cache=True)
def braking_norm(model, y, p):
    """|G| for the braking law: the run ends when it reaches zero (seed 004 eq. (11))."""
    if model == MASS_FULL:
        return mass_full_kernel.braking_norm(y, p)
    if model == SPHERICAL_FULL or model == PLANE_FULL or model == WHEEL_FULL:
        return 1.0  # no braking law for the pendulum systems and the wheel
    if model == MASS_AVERAGED_AXISYMMETRIC:
        return averaged_kernel.braking_norm_axisymmetric(y, p)
    return averaged_kernel.braking_norm(y, p)
