"""physics.LiveRun under edits a viewer may make at any magnitude: each shipped scene started at a random fidelity,
then retuned one to three keys at a time to values from 5e-324 to 1e308 (NaN and inf too, negatives), with and
without the state kept, and advanced between. Every call ends in a result, a ScenarioError naming the key, or a
fault recorded in status and message; nothing else leaves the API, a refusal keeps the run as it was, and no
message is in Python's or numpy's own words. An ad hoc run of this (seeds 11-16) found retune raising
OverflowError, ValueError and LinAlgError, and advance raising RuntimeError, out of the API."""

from __future__ import annotations

import math
import random
import re
from pathlib import Path

import pytest

import physics
from physics.stepping.live import FAULT, LiveRun

pytestmark = [pytest.mark.filterwarnings("ignore::physics.ValidityWarning"),
              pytest.mark.filterwarnings("ignore::RuntimeWarning")]
ROOT = Path(__file__).resolve().parents[1]
SCENES = sorted((ROOT / "assets" / "scenarios").glob("**/*.toml"))
MAGNITUDES = (5e-324, 1e-308, 1e-300, 1e-200, 1e-100, 1e-30, 1e-10, 1e-3, 0.5, 3.0, 1e3, 1e10, 1e30, 1e100, 1e200,
              1e300, 1e308, -1.0, -1e300, 0.0, math.nan, math.inf)
FIDELITIES = ("full", "averaged", "closed", "auto", None)
SEQUENCES = 100
PYTHONS_WORDS = re.compile(r"[A-Z][A-Za-z]*Error\b|could not convert|invalid literal|unhashable|not supported between"
                           r"|\(34, 'Numerical result|spacing between numbers|`y0`")


def _edit(rng: random.Random, sc: physics.Scenario) -> dict:
    keys = physics.numeric_keys(sc)
    return {k: rng.choice(MAGNITUDES) * rng.choice((1.0, 1.7))
            for k in rng.sample(keys, rng.randint(1, min(3, len(keys))))}


@pytest.mark.slow
@pytest.mark.parametrize("seed", [11, 12, 13, 14])
def test_a_live_run_takes_any_edit_as_a_result_a_refusal_or_a_fault(seed):
    rng = random.Random(seed)
    for _ in range(SEQUENCES):
        sc0 = physics.Scenario.from_toml(rng.choice(SCENES).read_text())
        try:
            run = LiveRun(sc0, rng.choice(FIDELITIES))
        except physics.ScenarioError as exc:  # a fidelity the scene has not: refused in words
            assert not PYTHONS_WORDS.search(str(exc)), str(exc)
            continue
        for _ in range(4):
            changes = _edit(rng, sc0)
            try:
                sc = sc0.with_values(**changes)
            except physics.ScenarioError:
                continue  # validation's own refusals are tests/test_fuzz_scenario.py's
            before = dict(vars(run))
            try:
                run.retune(sc, rng.choice(FIDELITIES), keep_state=rng.random() < 0.7)
            except physics.ScenarioError as exc:
                assert not PYTHONS_WORDS.search(str(exc)), (changes, str(exc))
                assert all(vars(run)[k] is v for k, v in before.items()), changes  # the run as it was
            run.advance(rng.choice((1e-3, 0.1, 1.0)), rng.choice((1, 5)))
            if run.status == FAULT:
                assert run.message and not PYTHONS_WORDS.search(run.message), (changes, run.message)
                break
