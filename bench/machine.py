"""What a benchmark ran on: one record for every study's results (``machine`` in each .meta.json, the
machine columns of bench/results/explorer_startup_cold.csv).

The keys are the union of what the studies recorded before they shared this function, under the same names,
so results files written earlier read the same way: ``cpus`` (work-precision, stability, sweep, soak, load)
and ``cores`` (the explorer benchmarks) are the same count under the two names those files use.
"""

from __future__ import annotations

import os
import platform
from importlib import metadata
from pathlib import Path

# the libraries whose versions move the figures; read from the installed metadata, so recording them imports
# none of them (dask and distributed alone take seconds to import)
LIBRARIES = ("numpy", "scipy", "numba", "mujoco", "matplotlib", "dask", "distributed")


def _version(name: str) -> str | None:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:  # an optional peer (mujoco, dask) not installed here: say so, as None
        return None


def _cpu_model() -> str:
    """The CPU's model name ("AMD EPYC ..."), which platform.processor() does not give on Linux."""
    try:
        return next(line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                    if line.startswith("model name"))
    except (OSError, StopIteration):  # not Linux, or a cpuinfo without model names (some ARM boards)
        return platform.processor() or platform.machine()


def machine() -> dict:
    """The CPU, its count, the OS and Python, and the versions of the libraries in ``LIBRARIES`` (None when one
    is not installed)."""
    cpus = os.cpu_count()
    return dict(platform=platform.platform(), processor=platform.processor() or platform.machine(),
                cpu=_cpu_model(), cpus=cpus, cores=cpus, python=platform.python_version(),
                **{name: _version(name) for name in LIBRARIES})
