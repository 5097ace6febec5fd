"""Issue 15's goals, read off the committed calibration study (``python -m bench fidelity --workers 2``, seed 15,
300 scenarios; bench/results/fidelity.csv and .meta.json), and the study's own arithmetic on hand-made rows.

The estimates were fitted on other seeds (moving mass: 7; pendulum: 101, 202, 303): seed 15 is the check."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest

from bench import fidelity as F

RESULTS = Path(__file__).resolve().parents[1] / "bench" / "results"
NUMBERS = ("actual_error", "estimate", "wall_s", "wall_full_s", "choose_s_0.01", "choose_s_0.001")


def _rows() -> list[dict]:
    with (RESULTS / "fidelity.csv").open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    for r in rows:
        for k in NUMBERS:
            if r.get(k, "") != "":
                r[k] = float(r[k])  # "inf" reads as inf: a cheaper model that claims nothing
        r["index"] = int(r["index"])
    return rows


@pytest.fixture(scope="module")
def rows():
    return _rows()


@pytest.fixture(scope="module")
def meta():
    return json.loads((RESULTS / "fidelity.meta.json").read_text())


def test_the_committed_study_is_the_full_one(rows, meta):
    assert meta["n"] >= 300 and meta["seed"] == 15 and not meta["quick"]
    assert len({r["index"] for r in rows}) == meta["n"]
    assert {r["system"] for r in rows} == {"moving_mass", "spherical_pendulum"}


def test_every_stated_estimate_holds(rows):
    stated = [r for r in rows if r["status"] == "ok" and r["estimate"] != "" and math.isfinite(r["estimate"])]
    assert len(stated) >= 150
    over = [(r["index"], r["fidelity"], r["actual_error"], r["estimate"]) for r in stated
            if r["actual_error"] > r["estimate"]]
    assert not over, over


def test_the_estimates_are_useful(rows):
    """Median estimate/actual at most 10 for every system and fidelity with estimates."""
    for system, fid in {(r["system"], r["fidelity"]) for r in rows if r["status"] == "ok"}:
        g = [r for r in rows if (r["system"], r["fidelity"]) == (system, fid) and r["status"] == "ok"
             and r["estimate"] != "" and math.isfinite(r["estimate"]) and r["actual_error"] > 0]
        assert g, (system, fid)
        assert np.median([r["estimate"] / r["actual_error"] for r in g]) <= 10, (system, fid)


def test_auto_is_within_twice_the_oracle_at_the_default_accuracy(meta):
    """At physics.DEFAULT_ACCURACY (1e-3 rad); the study reports 1e-2 too, where it is ~4x (docs/models.md)."""
    import physics

    default = [o for o in meta["summary"]["oracle"] if o["accuracy"] == physics.DEFAULT_ACCURACY]
    assert len(default) == 1 and default[0]["auto_over_oracle"] <= 2.0, default
    for o in meta["summary"]["oracle"]:
        assert o["auto_cheaper_within_accuracy"] == o["auto_cheaper"], o  # every cheaper pick met its accuracy


def test_the_meta_summary_is_the_csvs(rows, meta):
    again = F.summary(rows)
    for name, group in meta["summary"]["groups"].items():
        assert again["groups"][name]["worst_actual_over_estimate"] == pytest.approx(
            group["worst_actual_over_estimate"], rel=1e-9)
        assert again["groups"][name]["finite_estimate"] == group["finite_estimate"]


# ---- the study's arithmetic on hand-made rows -----------------------------------------------------------

def _row(index, fid, actual, wall, full_s, pick, est=1.0):
    return {"index": index, "system": "moving_mass", "fidelity": fid, "status": "ok", "actual_error": actual,
            "auto_fidelity": pick, "note": "",
            "estimate": est, "wall_s": wall, "wall_full_s": full_s, "auto_0.01": pick, "auto_0.001": pick,
            "choose_s_0.01": 0.01, "choose_s_0.001": 0.01}


def test_the_oracle_runs_the_cheapest_model_that_meets_the_accuracy():
    rows = [_row(0, "averaged", 5e-3, 0.1, 10.0, "full"), _row(0, "closed", 5e-3, 0.01, 10.0, "full"),
            _row(1, "averaged", 5e-2, 0.1, 20.0, "averaged"), _row(1, "closed", 5e-2, 0.01, 20.0, "averaged")]
    o = F.oracle(rows, 1e-2)
    assert o["oracle_wall_s"] == pytest.approx(0.01 + 20.0)  # scenario 0: closed; scenario 1: nothing meets it
    assert o["auto_wall_s"] == pytest.approx(0.02 + 10.0 + 0.1)  # choosing twice, full, then averaged
    assert o["auto_cheaper"] == 1 and o["auto_cheaper_within_accuracy"] == 0 and o["oracle_cheaper"] == 1


def test_the_summary_splits_claims_from_no_claims():
    rows = [_row(0, "closed", 1e-3, 0.01, 1.0, "full", est=2e-3), _row(1, "closed", 1e-3, 0.01, 1.0, "full",
                                                                         est=math.inf)]
    g = F.summary(rows)["groups"]["moving_mass/closed"]
    assert g["finite_estimate"] == 1 and g["no_claim"] == 1
    assert g["worst_actual_over_estimate"] == pytest.approx(0.5)
    assert g["median_estimate_over_actual"] == pytest.approx(2.0)


def test_docs_quote_the_study_as_its_files_give_it(meta):
    """docs/models.md's tables of the study, made from the meta file at the shown precision."""
    text = (RESULTS.parents[1] / "docs" / "models.md").read_text()
    groups = meta["summary"]["groups"]
    for name, label in (("moving_mass/averaged", "moving mass / averaged and closed"),
                        ("spherical_pendulum/averaged", "spherical pendulum / averaged")):
        g = groups[name]
        row = (f"| {label} | {g['n']} | {g['finite_estimate']} | {g['worst_actual_over_estimate']:.2f} | "
               f"{g['median_estimate_over_actual']:.1f} |")
        assert row in text, row
    for o in meta["summary"]["oracle"]:
        assert f"| {o['auto_cheaper']} of {o['scenarios']}, all within it | {o['oracle_cheaper']} | " \
               f"{o['auto_over_oracle']:.2f} |" in text, o
    before = json.loads((RESULTS / "fidelity_before.json").read_text())
    off = before["old_auto_cheaper_off_by_more_than_1e_3"]
    assert f"a cheaper model in {before['old_auto_cheaper']} of them, {off} of which" in text


def test_the_summary_reports_the_over_estimate_spread_and_the_coverage_inside_the_conditions():
    rows = [_row(0, "closed", 1e-3, 0.01, 1.0, "full", est=2e-3), _row(1, "closed", 1e-3, 0.01, 1.0, "full", est=4e-3),
            _row(2, "closed", 1e-3, 0.01, 1.0, "full", est=math.inf), _row(3, "closed", 1e-3, 0.01, 1.0, "full",
                                                                          est=math.inf)]
    for r, inside in zip(rows, (True, "True", "True", "False"), strict=True):  # a CSV's flags are strings
        r["inside"] = inside
    g = F.summary(rows)["groups"]["moving_mass/closed"]
    assert g["inside"] == 3 and g["coverage_inside"] == pytest.approx(2 / 3)  # the fourth is outside: not counted
    p = g["over_estimate_percentiles"]
    assert p["50"] == pytest.approx(3.0) and p["100"] == pytest.approx(4.0) and p["10"] == pytest.approx(2.2)


def test_auto_share_counts_the_oracles_cheaper_runs_auto_takes_too():
    rows = [_row(0, "closed", 5e-3, 0.01, 10.0, "closed"), _row(1, "closed", 5e-3, 0.01, 10.0, "full"),
            _row(2, "closed", 5e-2, 0.01, 10.0, "full")]
    o = F.oracle(rows, 1e-2)
    assert o["oracle_cheaper"] == 2 and o["auto_cheaper"] == 1 and o["auto_share"] == pytest.approx(0.5)
    assert F.oracle(rows, 1e-2, "spherical_pendulum")["scenarios"] == 0


def test_rescore_states_todays_estimate_and_keeps_the_measurement():
    import physics
    from physics.reference.problems import moving_mass

    sc = moving_mass(0.05, t_end=200.0)
    row = dict(_row(0, "closed", 1e-4, 0.01, 1.0, "full", est=123.0), scenario=json.dumps(sc.to_dict()))
    again = F.rescore([row])[0]
    assert again["estimate"] == physics.derived(sc)["closed_error_bound"] != 123.0
    assert again["actual_error"] == 1e-4 and again["wall_s"] == 0.01  # the run's own figures stay
    assert again["ratio"] == pytest.approx(1e-4 / again["estimate"]) and again["inside"] is True
    assert again["auto_0.001"] in ("full", "averaged", "closed") and row["estimate"] == 123.0  # a copy
