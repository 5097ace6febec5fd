"""Quadratic friction's error estimate read off its committed studies (issue 23), each
``python -m bench fidelity --system quadratic_friction --quick --n 40 --workers 2 --seed S`` and scored with today's
estimate (``--rescore``): seed 15 (bench/results/fidelity_quadratic_calibration.{csv,meta.json}), on which the rate
form the estimate had before was calibrated; seed 41, which found that form's first violation
(fidelity_quadratic_seed41); seed 505, its check (fidelity_quadratic); seed 8821, drawn for the forced response
(fidelity_quadratic_seed8821); and seed 9463, drawn after every change (fidelity_quadratic_seed9463). The forced
response's factors were fitted on none of them (the viscous sets, docs/models.md A.5). Every run in them is the full
model against the averaged and closed ones; nothing is simulated here."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from bench import fidelity as F

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "bench" / "results"
STUDIES = {"first set": "fidelity_quadratic_calibration", "second set": "fidelity_quadratic_seed41",
           "third set": "fidelity_quadratic", "fourth set": "fidelity_quadratic_seed8821",
           "check": "fidelity_quadratic_seed9463"}
SEEDS = {"first set": 15, "second set": 41, "third set": 505, "fourth set": 8821, "check": 9463}
GROUPS = ("moving_mass/averaged", "moving_mass/closed")


@pytest.fixture(scope="module", params=list(STUDIES))
def study(request):
    stem = STUDIES[request.param]
    meta = json.loads((RESULTS / f"{stem}.meta.json").read_text())
    return request.param, F.read_rows(RESULTS / f"{stem}.csv"), meta


def test_the_sets_are_quadratic_friction_alone_and_of_the_seeds_named(study):
    name, rows, meta = study
    assert meta["seed"] == SEEDS[name]
    assert meta["n"] >= 40 and len({r["index"] for r in rows}) == meta["n"]
    for r in rows:
        data = json.loads(r["scenario"])
        assert data["mass"]["lam_q"] > 0 and data["mass"].get("chi", 0.0) == 0.0
        assert not {"cavity", "medium", "control"} & set(data)
    assert sum(r["status"] == "ok" for r in rows) >= 0.9 * len(rows)


def test_no_stated_estimate_is_below_the_actual_error(study):
    name, rows, _meta = study
    stated = [r for r in rows if r["status"] == "ok" and math.isfinite(r["estimate"] or math.inf)]
    assert len(stated) >= 50
    over = [(name, r["index"], r["fidelity"], r["actual_error"], r["estimate"]) for r in stated
            if r["actual_error"] > r["estimate"]]
    assert not over, over


def test_median_over_estimate_coverage_and_autos_cheaper_picks_meet_issue_23(study):
    name, _rows, meta = study
    for group in GROUPS:
        g = meta["summary"]["groups"][group]
        assert g["median_estimate_over_actual"] <= 3.0, (name, group)
        assert g["coverage_inside"] >= 0.95, (name, group)
        assert g["over_1"] == 0
    for o in meta["summary"]["oracle"]:
        assert o["auto_cheaper_within_accuracy"] == o["auto_cheaper"], o


def test_the_sets_leave_the_margin_the_code_claims():
    """accuracy.py: fitted on none of these sets, the forced response's estimate left the worst error at 0.906 of
    it (SAFETY_FORCED's 1.1x beyond an exact prediction), and its median over-estimate is under 1.15 on each."""
    worst, medians = [], []
    for stem in STUDIES.values():
        g = json.loads((RESULTS / f"{stem}.meta.json").read_text())["summary"]["groups"]["moving_mass/averaged"]
        worst.append(g["worst_actual_over_estimate"])
        medians.append(g["median_estimate_over_actual"])
    assert max(worst) == pytest.approx(0.906, abs=5e-4) and max(medians) < 1.15


def test_the_meta_summary_is_the_csvs(study):
    _name, rows, meta = study
    again = F.summary(rows)
    for group in GROUPS:
        for key in ("worst_actual_over_estimate", "median_estimate_over_actual", "coverage_inside"):
            assert again["groups"][group][key] == pytest.approx(meta["summary"]["groups"][group][key], rel=1e-9)


def quoted_row(name: str, meta: dict) -> str:
    g = meta["summary"]["groups"]["moving_mass/averaged"]
    p = g["over_estimate_percentiles"]
    spread = " / ".join(f"{p[q]:.2g}" for q in ("25", "50", "75", "90"))
    return (f"| {name} (seed {meta['seed']}) | quadratic friction / averaged and closed | {g['n']} | {g['inside']} | "
            f"{g['finite_estimate']} ({g['coverage_inside']:.0%}) | {g['over_1']} | "
            f"{g['worst_actual_over_estimate']:.2f} | {spread} |")


def test_docs_quote_every_set_as_its_files_give_it(study):
    name, _rows, meta = study
    text = (ROOT / "docs" / "models.md").read_text()
    assert quoted_row(name, meta) in text, quoted_row(name, meta)
    for o in meta["summary"]["oracle"]:
        share = "-" if o["auto_share"] is None else f"{o['auto_share']:.0%}"
        row = (f"| {name} (seed {meta['seed']}) | {o['accuracy']:g} | quadratic friction | {o['auto_cheaper']} of "
               f"{o['scenarios']} | {o['oracle_cheaper']} | {share} | "
               f"{o['auto_cheaper'] - o['auto_cheaper_within_accuracy']} | {o['auto_over_oracle']:.2f} |")
        assert row in text, row
