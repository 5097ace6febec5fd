"""The built-in default scenario: an oblate body whose nutation visibly decays within seconds."""

from __future__ import annotations

from importlib import resources

from physics.scenario.scenario import Scenario


def default_scenario() -> Scenario:
    text = resources.files("physics").joinpath("data/default.toml").read_text(encoding="utf-8")
    return Scenario.from_toml(text)
