"""The layers of pyproject.toml's import-linter contracts hold, and the check would catch a breach."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LINT = [sys.executable, "-c", "import sys; from importlinter.cli import lint_imports_command; "
        "sys.exit(lint_imports_command())", "--no-logo", "--no-cache"]


def _lint(cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(cwd))
    return subprocess.run(LINT, cwd=cwd, env=env, capture_output=True, text=True, timeout=300)


def test_every_contract_is_kept():
    """Every contract pyproject.toml lists is checked and kept: none skipped, none broken."""
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    out = _lint(ROOT)
    assert out.returncode == 0, out.stdout + out.stderr
    n = len(contracts)
    assert f"Contracts: {n} kept, 0 broken." in out.stdout, out.stdout
    assert out.stdout.count("KEPT") == n and "BROKEN" not in out.stdout


def test_the_app_reaching_into_physics_breaks_a_contract(tmp_path):
    """A copy of the tree where one app module imports a physics submodule fails the check, naming it."""
    for name in ("physics", "app", "bench"):
        shutil.copytree(ROOT / name, tmp_path / name, ignore=shutil.ignore_patterns("__pycache__", "results"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    (tmp_path / "app" / "reaching.py").write_text("from physics.systems import choice  # noqa: F401\n")
    out = _lint(tmp_path)
    assert out.returncode != 0
    assert "app.reaching -> physics.systems.choice" in out.stdout
