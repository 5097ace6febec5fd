"""Choosing between a compiled kernel and its interpreted twin: the background build's state (``build``),
the twins (``interpreted``) and the integrators rebound to a Python right-hand side (``py_kernels``).

Below the models and the drivers: they call ``build.pick(kernel)`` to get whichever can run now.
"""
