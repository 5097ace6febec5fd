"""The benchmark commands run end to end in --quick mode (issue 5: so they cannot rot)."""

import csv
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("mujoco")
pytest.importorskip("matplotlib")

ROOT = Path(__file__).resolve().parent.parent
COLUMNS = ["problem", "method", "setting", "error", "wall_s", "nfev", "steps"]


def _run(command: str, tmp_path: Path) -> tuple[Path, Path]:
    out, img = tmp_path / "results", tmp_path / "img"
    subprocess.run([sys.executable, "-m", "bench", command, "--quick", "--out", str(out), "--img", str(img)],
                   cwd=ROOT, check=True, timeout=300, capture_output=True)
    return out, img


@pytest.mark.slow
def test_work_precision_quick(tmp_path):
    out, img = _run("work-precision", tmp_path)
    with open(out / "work_precision.csv") as fh:
        reader = csv.DictReader(fh)
        assert reader.fieldnames == COLUMNS
        rows = list(reader)
    assert {r["problem"] for r in rows} == {"P1", "P2", "P3", "P4"}
    methods = {r["method"] for r in rows}
    assert {"scipy DOP853 (numpy rhs)", "MuJoCo RK4", "RK4 (compiled)", "RK8 (compiled)"} <= methods
    # every row is a measured run: it evaluated the right-hand side and took a positive, finite wall time (a row
    # written without timing it would carry 0 or nan)
    assert all(int(r["nfev"]) > 0 and 0 < float(r["wall_s"]) < math.inf for r in rows)
    peers = {(r["problem"], r["method"]) for r in rows}
    assert {("P2", "scipy DOP853 (numpy rhs)"), ("P4", "scipy DOP853 (numpy rhs)")} <= peers
    meta = json.loads((out / "work_precision.meta.json").read_text())
    assert meta["machine"]["numba"] and meta["command"] and meta["targets"]
    for name in ("work_precision_wall.png", "work_precision_nfev.png"):
        assert (img / name).stat().st_size > 10_000


@pytest.mark.slow
def test_stability_quick(tmp_path):
    out, img = _run("stability", tmp_path)
    for name in ("stiffness", "drift", "validity", "braking"):
        assert (out / f"stability_{name}.csv").stat().st_size > 0
        assert (img / f"stability_{name}.png").stat().st_size > 10_000
    with open(out / "stability_drift.csv") as fh:
        drift = {r["method"]: r for r in csv.DictReader(fh)}
    midpoint = next(r for m, r in drift.items() if m.startswith("midpoint"))
    assert float(midpoint["max_rel_K_drift"]) < 1e-12
