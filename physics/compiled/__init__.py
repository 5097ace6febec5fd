"""Compiled (numba, cache=True) right-hand sides and integrators. Nothing here imports physics/systems.

numba invalidates a cached function only when its own file changes, not when a function it calls
changes: after an edit to a kernel or to dispatch.py, the cached integrator would keep calling the
old code. So the cache of this package is keyed on all of its sources together: when any file here
changes, every cached entry is dropped before numba loads it.

The entry points Python calls on whole runs (the integrators' ``integrate`` and the observers) are
compiled with ``nogil=True``: a simulation on a background thread then leaves the GIL to the
threads that serve the app.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path


def _cache_dirs(here: Path) -> list[Path]:
    """Where numba keeps this package's cache: next to the sources, and under NUMBA_CACHE_DIR when that is set
    (numba then uses it instead, in a subfolder named after this folder's path)."""
    dirs = [here / "__pycache__"]
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        from numba.core.caching import _CacheLocator

        dirs.append(Path(user) / _CacheLocator.get_suitable_cache_subpath(str(here / "dispatch.py")))
    return dirs


def _drop_stale_cache() -> None:
    here = Path(__file__).parent
    digest = hashlib.sha256()
    for src in sorted(here.glob("*.py")):
        digest.update(src.name.encode() + src.read_bytes())
    for cache in _cache_dirs(here):
        stamp = cache / "sources.sha256"
        try:
            if stamp.exists() and stamp.read_text() == digest.hexdigest():
                continue
            cache.mkdir(parents=True, exist_ok=True)
            for entry in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
                entry.unlink()
            stamp.write_text(digest.hexdigest())
        except OSError:
            pass  # a read-only install: numba then cannot write a cache either


_drop_stale_cache()
