"""physics/compiled/__init__.py drops numba's cache when any compiled source changes, wherever numba keeps it:
found when a NUMBA_CACHE_DIR filled before a kernel edit kept serving the old kernel (the pendulum's pivot flag
was ignored) because only the cache next to the sources was checked."""

from __future__ import annotations

from pathlib import Path

import physics.compiled as compiled


def test_a_stale_cache_under_numba_cache_dir_is_dropped(tmp_path, monkeypatch):
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    here = Path(compiled.__file__).parent
    dirs = compiled._cache_dirs(here)
    assert len(dirs) == 2 and dirs[1].parent == tmp_path
    dirs[1].mkdir(parents=True)
    stale = dirs[1] / "pendulum.rhs-1.py311.nbi"
    stale.write_text("old")
    (dirs[1] / "sources.sha256").write_text("a digest of other sources")
    compiled._drop_stale_cache()
    assert not stale.exists()
    stamp = (dirs[1] / "sources.sha256").read_text()
    assert stamp != "a digest of other sources"
    kept = dirs[1] / "dispatch.rhs-1.py311.nbi"  # written after the check, for these sources: kept next time
    kept.write_text("new")
    compiled._drop_stale_cache()
    assert kept.exists() and (dirs[1] / "sources.sha256").read_text() == stamp


def test_without_numba_cache_dir_only_the_folder_next_to_the_sources(monkeypatch):
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    here = Path(compiled.__file__).parent
    assert compiled._cache_dirs(here) == [here / "__pycache__"]
