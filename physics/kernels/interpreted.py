"""Pure-Python twins of the compiled kernels, built from the kernels' own source.

numba keeps the Python function it compiles as ``dispatcher.py_func``. Calling that function as it is
would still call the other kernels through their dispatchers (and so compile them); ``twin`` rebuilds it
with its globals rebound: every compiled function it names, directly or through a module of
``physics.compiled``, is replaced by that function's twin. The twin runs the same equations, line for
line, in the interpreter: no compilation, but slower: measured, a DOP853 step of the default scene's
moving-mass model 0.47 ms against 0.03 ms compiled (35 steps per simulated second: real time costs 2% of a
core), the pendulum kernels (loops over small arrays) 250-3000 times slower. It is what the live
run steps with while the compiled kernels are still being built (``physics.kernels.build``): one source
of the equations, so the two paths cannot drift apart.
"""

from __future__ import annotations

import threading
import types

from numba.core.dispatcher import Dispatcher

COMPILED_PACKAGE = "physics.compiled"


class _ModuleTwin:
    """A module of physics.compiled whose compiled functions read as their twins."""

    def __init__(self, module: types.ModuleType):
        self._module = module

    def __getattr__(self, name: str):
        value = getattr(self._module, name)
        return twin(value) if isinstance(value, Dispatcher) else value


def _rebind(value):
    if isinstance(value, Dispatcher):
        return twin(value)
    if isinstance(value, types.ModuleType) and value.__name__.startswith(COMPILED_PACKAGE):
        return _ModuleTwin(value)
    return value


def rebuild(function, namespace: dict):
    """``function``'s code (a numba dispatcher's Python function, or a plain function) as a new function that
    reads its globals from ``namespace``: the interpreted twin's mechanism, also used to bind a model's Python
    right-hand side into the integrators (physics/kernels/py_kernels.py)."""
    f = function.py_func if isinstance(function, Dispatcher) else function
    g = types.FunctionType(f.__code__, namespace, f.__name__, f.__defaults__, f.__closure__)
    g.__kwdefaults__, g.__doc__, g.__qualname__ = f.__kwdefaults__, f.__doc__, f.__qualname__
    return g


_TWINS: dict = {}
_LOCK = threading.RLock()  # sessions' threads may ask at once; a half-rebound twin must not escape


def twin(function):
    """The interpreted twin of a compiled kernel (a numba dispatcher) or of a Python function that calls
    compiled kernels (e.g. a model's ``observe``): same code, globals rebound to twins."""
    with _LOCK:
        if function in _TWINS:
            return _TWINS[function]
        f = function.py_func if isinstance(function, Dispatcher) else function
        namespace = dict(f.__globals__)
        g = rebuild(function, namespace)
        _TWINS[function] = g  # before rebinding: a kernel may name itself (co_names holds attribute names too)
        for name in set(f.__code__.co_names) & namespace.keys():
            namespace[name] = _rebind(namespace[name])
        return g
