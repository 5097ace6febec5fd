"""Changing single keys of a scenario: the one place that knows how dotted keys map onto its tables.

``initial`` holds either ``omega`` or ``G0`` with ``theta0``. Setting G0 or theta0 on a scenario given by
omega first rewrites omega as the G0 and theta0 it means (``initial_G``), so the other one is kept;
setting omega drops G0 and theta0. A key of an array table (``plane_pendulum.k``) sets every item, or
item i with ``plane_pendulum[i].k``.
"""

from __future__ import annotations

import re

from physics.core.errors import ScenarioError
from physics.scenario.initial import initial_G

ITEM = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\[([0-9]+)\]$")


def edit_dict(data: dict, dotted: str, value, base=None) -> None:
    """Set ``dotted`` (``table.key``) to ``value`` in the scenario dict ``data`` (``Scenario.to_dict()``),
    in place. ``base`` is the Scenario ``data`` came from (needed to rewrite omega as G0, theta0)."""
    table, _, key = dotted.partition(".")
    if not key:
        raise ScenarioError(dotted, value, "must be a dotted key table.key, e.g. mass.m")
    item = ITEM.match(table)
    if item:
        table, index = item.group(1), int(item.group(2))
        blocks = data.get(table)
        if not isinstance(blocks, list) or index >= len(blocks):
            have = len(blocks) if isinstance(blocks, list) else 0
            raise ScenarioError(dotted, value, f"names no item: this scenario has {have} [[{table}]] tables")
        blocks[index][key] = value
        return
    if isinstance(data.get(table), list):  # an array table: every item
        for block in data[table]:
            block[key] = value
        return
    section = data.setdefault(table, {})
    if table == "initial" and key in ("G0", "theta0") and "omega" in section:
        if base is None:
            from physics.scenario.scenario import Scenario

            base = Scenario.from_dict(data)
        _, G0, theta0 = initial_G(base)
        section.pop("omega")
        section["G0"], section["theta0"] = G0, theta0
    if table == "initial" and key == "omega":
        section.pop("G0", None), section.pop("theta0", None)
    section[key] = value


def with_values(base, values: dict):
    """``base`` (a Scenario) with the dotted keys set, validated again (raises ScenarioError)."""
    from physics.scenario.scenario import Scenario

    data = base.to_dict()
    for dotted, value in values.items():
        edit_dict(data, dotted, value, base)
    return Scenario.from_dict(data)
