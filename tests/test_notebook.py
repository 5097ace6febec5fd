"""docs/explorer.ipynb runs top to bottom in a Jupyter kernel (nbclient, in-process), as CI runs it: it simulates
the default scene, plots it with Trajectory.plot(), and serves the explorer with app.show, which must return at
once (no browser connects here) and stop when asked."""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOK = ROOT / "docs" / "explorer.ipynb"
CELL_TIMEOUT = 300  # s: a cold numba cache compiles the integrator in the first cell


def _outputs(cell) -> tuple[str, set[str]]:
    """A code cell's printed and displayed text, and the MIME types it displayed."""
    text, kinds = [], set()
    for out in cell.get("outputs", []):
        if out.output_type == "stream":
            text.append(out.text)
        for kind, value in out.get("data", {}).items():
            kinds.add(kind)
            if kind in ("text/plain", "text/html"):
                text.append(value)
    return "".join(text), kinds


def test_the_notebook_runs_plots_and_shows_the_explorer(tmp_path):
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(nb, timeout=CELL_TIMEOUT, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})  # writes nothing in the repo
    # the kernel imports physics and app from this checkout, whatever is installed (as tests/test_docs.py does)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    client.execute(env=env)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(not any(o.output_type == "error" for o in c.outputs) for c in code)
    by_source = {c.source.split("\n")[0]: _outputs(c) for c in code}
    summary = next(text for src, (text, _) in by_source.items() if src.startswith("%matplotlib"))
    m = re.search(r"theta from ([\d.]+) to ([\d.]+) rad", summary)
    assert m and float(m.group(2)) < float(m.group(1)), summary  # the default scene settles
    plot_text, plot_kinds = next(v for src, v in by_source.items() if src.startswith("fig = trajectory.plot"))
    assert "image/png" in plot_kinds, plot_text  # the Figure is drawn inline
    shown, kinds = next(v for src, v in by_source.items() if src.startswith("import app"))
    url = re.search(r"http://127\.0\.0\.1:(\d+)", shown)
    assert url and int(url.group(1)) > 0, shown
    assert "text/html" in kinds and "<iframe" in shown and url.group(0) in shown.split("<iframe", 1)[1], shown
    assert "running at" in shown, shown
    stopped, _ = next(v for src, v in by_source.items() if src.startswith("explorer.stop()"))
    assert "stopped at" in stopped, stopped
