"""``python -m bench pendulum-ceiling`` on a few rows of the check study: its parts rebuild the product's estimate,
and the best pair of factors with no violation takes at least the product's share (SAFETY itself is a pair it
tries)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

import physics
from bench.pendulum_ceiling import ACCURACIES, main
from physics.systems.pendulum.accuracy import SAFETY, SAFETY_LINEAR

ROOT = Path(__file__).resolve().parent.parent
ROWS = 16


def pendulum_study(tmp: Path, n: int) -> tuple[list[dict], Path]:
    """The check study's first n averaged spherical-pendulum rows, written as a study CSV in tmp: (rows, path)."""
    with open(ROOT / "bench" / "results" / "fidelity.csv", newline="") as f:
        reader = csv.DictReader(f)
        rows = [r for r in reader if r["system"] == "spherical_pendulum" and r["fidelity"] == "averaged"][:n]
        fields = reader.fieldnames
    study = tmp / "study.csv"
    with open(study, "w", newline="") as f:
        w = csv.DictWriter(f, fields)
        w.writeheader()
        w.writerows(rows)
    return rows, study


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("ceiling")
    rows, study = pendulum_study(tmp, ROWS)
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


def test_the_hardening_form_is_third_order_in_the_nutation(run):
    """The swing-following detuning is SWING_SHIFT omega_0 |Ut|^2 with Ut proportional to theta0, and theta moves
    by it at first order: halving theta0 divides the hardening gap by 8 (to the integrator's 1e-9), where a gap
    that did not follow the swing (or followed it at the wrong power) would divide by 2 or 4."""
    from bench.pendulum_ceiling import hardening_gap

    rows, out, _, _ = run
    sc = physics.Scenario.from_dict(json.loads(rows[0]["scenario"]))
    th = sc.initial.theta0
    gaps = [hardening_gap(sc.with_values(**{"initial.theta0": th * f})) for f in (0.1, 0.05)]
    assert float(out[0]["hardening"]) > 0 and gaps[1] > 0
    assert gaps[0] / gaps[1] == pytest.approx(8.0, rel=0.03)


def test_the_following_form_keeps_the_products_resonance_read(run):
    """The resonance column is the part of the product's detuning gap read at sigma = 0, so it never exceeds that
    gap; and the following form's estimate at each factor is rebuilt from the columns: its violations are those of
    SAFETY_LINEAR linear + S max(following, rate, resonance)."""
    _, out, meta, _ = run
    col = {k: [float(o[k]) for o in out] for k in ("actual", "linear", "detuning", "rate", "following", "resonance")}
    assert all(r <= d for r, d in zip(col["resonance"], col["detuning"], strict=True))
    assert all(f > 0 for f in col["following"])
    for form in meta["summary"]["following_form"]:
        est = [SAFETY_LINEAR * lin + form["factor"] * max(f, r, res) for lin, f, r, res in zip(
            col["linear"], col["following"], col["rate"], col["resonance"], strict=True)]
        assert form["violations"] == sum(a > e for a, e in zip(col["actual"], est, strict=True))
