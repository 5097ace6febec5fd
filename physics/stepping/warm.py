"""Warming the compiled kernels: what the explorer runs first (the default scene, a step of the live run).

``python -m physics.stepping.warm`` is the background build's child process (``physics.kernels.build``): it
runs ``exercise`` compiled, filling numba's cache; the parent then runs it once more to load the result.
``start`` is ``physics.build_kernels``.
"""

from __future__ import annotations

import sys

from physics.kernels import build
from physics.kernels.build import BuildStatus


def exercise() -> None:
    """Run what the explorer runs first: in the child this compiles and caches it, in the parent it loads it."""
    from physics.scenario.defaults import default_scenario
    from physics.stepping.live import LiveRun

    LiveRun(default_scenario()).advance(0.01)


def start(command: list[str] | None = None) -> BuildStatus:
    """Build the explorer's kernels in a child process unless they are built already; returns at once."""
    return build.start(command, exercise)


def build_here() -> None:
    """Compile (or load) the explorer's kernels in this process and stamp numba's cache as built."""
    build.build_here(exercise)


if __name__ == "__main__":
    sys.exit(build.main(exercise))
