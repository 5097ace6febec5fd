"""The swing-following detuning study (``python -m bench pendulum-hardening``, issue 23): its integrator agrees with
the averaged model's closed form when nothing follows the swing, and its results file says what docs/models.md
quotes from it."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import physics
from bench.pendulum_hardening import VARIANTS, detuned_theta, summary
from physics.scenario.initial import initial_G
from physics.systems.pendulum.averaged import AveragedCoefficients, averaged_theta
from physics.systems.pendulum.geometry import pendulum_system
from physics.systems.pendulum.linear import spherical_linear

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "bench" / "results"


def test_with_nothing_following_the_swing_the_integration_is_the_closed_form():
    """The study's DOP853 integration of the averaged equations against their 2x2 matrix exponential: an outside
    check of its right-hand side (a sign or a factor wrong in it would show at the 1e-3 level or worse)."""
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml")
    p = spherical_linear(pendulum_system(sc))
    w0, _, _ = initial_G(sc)
    t = np.linspace(0.0, float(sc.run.t_end), 501)
    exact, _ = averaged_theta(AveragedCoefficients(p), np.array([w0[0] + 1j * w0[1], 0j]), float(w0[2]), t)
    assert np.max(np.abs(detuned_theta(sc, t, 0.0, 0.0) - exact)) < 1e-9 * exact[0]
    moved = detuned_theta(sc, t, 1.0, 1.0)  # and the detuning that follows does change theta
    assert np.max(np.abs(moved - exact)) > 1e-6 * exact[0]


@pytest.fixture(scope="module")
def study():
    with open(RESULTS / "pendulum_hardening.csv", newline="") as f:
        rows = [{k: (v if k in ("index", "pivot") else float(v)) for k, v in r.items()} for r in csv.DictReader(f)]
    return rows, json.loads((RESULTS / "pendulum_hardening.meta.json").read_text())


def test_the_results_file_s_summary_is_its_rows(study):
    rows, meta = study
    again = summary(rows)
    assert again["scenarios"] == meta["summary"]["scenarios"] == len(rows) > 0
    for name in VARIANTS:
        for key in ("nearer", "farther", "within_0.01", "within_0.001"):
            assert again[name][key] == meta["summary"][name][key], (name, key)
        assert again[name]["median_ratio"] == pytest.approx(meta["summary"][name]["median_ratio"], rel=1e-12)
    assert meta["machine"]["cpus"] and meta["command"].startswith("python -m bench pendulum-hardening")


def test_docs_quote_the_study_as_measured(study):
    _, meta = study
    s = meta["summary"]["both"]
    text = " ".join((ROOT / "docs" / "models.md").read_text().split())
    quoted = (f"nearer the full model in {s['nearer']} of {meta['summary']['scenarios']} scenarios and farther in "
              f"{s['farther']} (up to {s['worst']:.1f}x)")
    assert quoted in text, quoted
    within = s["within_0.01"]
    assert f"within 1e-2 rad in {within[1]} scenarios against {within[0]}" in text
