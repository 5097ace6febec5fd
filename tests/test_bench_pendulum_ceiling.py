"""``python -m bench pendulum-ceiling`` on a few rows of the check study: its parts rebuild the product's estimate,
and the best pair of factors with no violation takes at least the product's share (SAFETY itself is a pair it
tries)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from bench.pendulum_ceiling import ACCURACIES, main
from physics.systems.pendulum.accuracy import SAFETY, SAFETY_LINEAR

ROOT = Path(__file__).resolve().parent.parent
ROWS = 16


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ceiling")
    with open(ROOT / "bench" / "results" / "fidelity.csv", newline="") as f:
        reader = csv.DictReader(f)
        rows = [r for r in reader if r["system"] == "spherical_pendulum" and r["fidelity"] == "averaged"][:ROWS]
        fields = reader.fieldnames
    study = tmp / "study.csv"
    with open(study, "w", newline="") as f:
        w = csv.DictWriter(f, fields)
        w.writeheader()
        w.writerows(rows)
    assert main(["--study", str(study), "--out", str(tmp), "--img", str(tmp)]) == 0
    with open(tmp / "pendulum_ceiling.csv", newline="") as f:
        out = list(csv.DictReader(f))
    return rows, out, json.loads((tmp / "pendulum_ceiling.meta.json").read_text()), tmp


def test_the_parts_rebuild_the_products_estimate(run):
    rows, out, _, _ = run
    assert len(out) == ROWS
    for r, o in zip(rows, out, strict=True):
        assert float(o["actual"]) == float(r["actual_error"])
        rebuilt = SAFETY_LINEAR * float(o["linear"]) + SAFETY * max(float(o["detuning"]), float(o["rate"]))
        assert rebuilt == pytest.approx(float(o["estimate"]), rel=1e-12)


def test_the_ceiling_takes_at_least_the_products_share_with_no_violation(run):
    _, out, meta, tmp = run
    s = meta["summary"]
    assert s["scenarios"] == ROWS and s["product"]["violations"] == 0
    c = s["ceiling"]
    assert c["worst"] <= 1.0
    assert sum(c[f"{a:g}"]["share"] for a in ACCURACIES) >= sum(s["product"][f"{a:g}"]["share"] for a in ACCURACIES)
    for a in ACCURACIES:  # the oracle is the same for every estimate
        assert c[f"{a:g}"]["oracle"] == s["product"][f"{a:g}"]["oracle"] == sum(
            float(o["actual"]) <= a for o in out)
    assert (tmp / "pendulum_ceiling.png").stat().st_size > 0 and "machine" in meta
