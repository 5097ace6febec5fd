"""Every shipped scenario (assets/scenarios/**/*.toml) runs from ``python -m physics run FILE`` within the step
budget (issue 23). The model the file asks for (auto resolved) must have an estimate within MAX_STEPS; the CLI
then runs the file as shipped when that is cheap, and otherwise at its cheapest model (``--fidelity``), so the
whole set takes seconds. The CLI runs in this process (``physics.cli.main``, what ``python -m physics`` calls):
a subprocess per file would spend most of the time loading numba's cache."""

from __future__ import annotations

from pathlib import Path

import pytest

import physics
from physics import cli
from physics.core.budget import MAX_STEPS
from physics.registry import get_system
from physics.systems.choice import resolve
from physics.systems.cost import estimated_steps

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = sorted((ROOT / "assets" / "scenarios").rglob("*.toml"))
CHEAP_STEPS = 50_000  # a run the test does as shipped: a fraction of a second compiled


def test_every_kind_of_shipped_scenario_is_here():
    folders = {p.parent.name for p in SHIPPED}
    assert {"scenarios", "explorer", "figures"} <= folders and len(SHIPPED) >= 20


@pytest.mark.parametrize("path", SHIPPED, ids=[str(p.relative_to(ROOT / "assets" / "scenarios")) for p in SHIPPED])
def test_shipped_scenario_runs_from_the_cli_within_the_budget(path, capsys):
    sc = physics.Scenario.load(path)
    fid = resolve(sc).fidelity
    steps = estimated_steps(sc, fid)
    assert steps is not None and steps <= MAX_STEPS, f"{fid}: about {steps} steps"
    args = ["run", str(path)]
    if steps > CHEAP_STEPS:
        system = get_system(sc.system)
        costs = {f: estimated_steps(sc, f) for f in system.fidelities[1:] if system.available(sc, f)[0]}
        cheapest = min(costs, key=lambda f: costs[f])
        assert costs[cheapest] <= CHEAP_STEPS, costs
        args += ["--fidelity", cheapest]
    assert cli.main(args) == 0
    out = capsys.readouterr().out
    assert "ended: reached t_end" in out or "ended: braking brought |G| to zero" in out, out
