"""Compiled (numba, cache=True) right-hand sides and integrators. Nothing here imports models/."""
