"""The integrators for a model with a Python right-hand side (``Model.py_rhs``): the same source as the compiled
ones, interpreted, with the model's functions bound in.

physics/compiled/dop853.py and fixed.py call the dispatch functions ``rhs``, ``fault``, ``switch_chart`` and
``braking_norm`` (physics/compiled/dispatch.py) by name, with a kernel id. For a Python model those names are
rebound, in a copy of the integrator's globals (``physics.kernels.interpreted.rebuild``, the mechanism of the
interpreted twins), to functions that ignore the id: ``rhs`` calls ``model.py_rhs``; ``fault`` and
``switch_chart`` return 0 (a Python model has no chart to switch and no state it cannot continue from);
``braking_norm`` returns 1 (braking is refused for such a model: ``stepper.check_method``). The step-size
control, the error norm, the output stepping and the statuses are thus the compiled integrators' own, line
for line: a Python model and a compiled one with the same equations take the same steps.
"""

from __future__ import annotations

import threading

from physics.compiled import dop853, fixed
from physics.kernels.interpreted import rebuild

_CACHE: dict = {}  # (model name, its py_rhs) -> (integrate, run): re-registering a name with new equations rebuilds
_LOCK = threading.Lock()


def _no_event(model, y, p):
    return 0


def _no_braking(model, y, p):
    return 1.0


def integrators(model):
    """(dop853.integrate, fixed.run) for ``model``, with the same signatures as the compiled ones (the kernel
    id argument is ignored)."""
    key = (model.name, model.py_rhs)
    with _LOCK:
        if key not in _CACHE:
            py_rhs = model.py_rhs

            def rhs(kernel, t, y, p, out):
                py_rhs(t, y, p, out)

            bound = dict(rhs=rhs, fault=_no_event, switch_chart=_no_event, braking_norm=_no_braking)
            integrate = rebuild(dop853.integrate, {**dop853.integrate.py_func.__globals__, **bound})
            fixed_integrate = rebuild(fixed.integrate, {**fixed.integrate.py_func.__globals__, **bound})
            run = rebuild(fixed.run, {**fixed.run.__globals__, "integrate": fixed_integrate})
            _CACHE[key] = (integrate, run)
        return _CACHE[key]
