"""Changing single keys of a scenario: the one place that knows how dotted keys map onto its tables.

``initial`` holds either ``omega`` or ``G0`` with ``theta0``. Setting G0 or theta0 on a scenario given by
omega first rewrites omega as the G0 and theta0 it means (``initial_G``), so the other one is kept;
setting omega drops G0 and theta0. A key of an array table (``plane_pendulum.k``) sets every item, or
item i with ``plane_pendulum[i].k``.
"""

from __future__ import annotations

import re
from types import SimpleNamespace

from physics.core.errors import ScenarioError
from physics.scenario.initial import initial_G
from physics.scenario.params import Body, Initial

ITEM = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\[([0-9]+)\]$")


def edit_dict(data: dict, dotted: str, value, base=None) -> None:
    """Set ``dotted`` (``table.key``) to ``value`` in the scenario dict ``data`` (``Scenario.to_dict()``),
    in place. ``base`` is the Scenario ``data`` came from (its body and initial rewrite omega as G0, theta0; without
    it they are read from ``data``)."""
    if not isinstance(data, dict):
        raise ScenarioError("data", type(data).__name__, "must be a scenario dict (Scenario.to_dict())")
    if not isinstance(dotted, str):
        raise ScenarioError("key", dotted, "must be a dotted key table.key, e.g. mass.m")
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
            base = _start(data, section)
        _, G0, theta0 = initial_G(base)
        section.pop("omega")
        section["G0"], section["theta0"] = G0, theta0
    if table == "initial" and key == "omega":
        section.pop("G0", None), section.pop("theta0", None)
    section[key] = value


def _start(data: dict, initial: dict) -> SimpleNamespace:
    """The body and initial tables of ``data``, validated: all that ``initial_G`` reads of a scenario."""
    body = data.get("body")
    if not isinstance(body, dict):
        raise ScenarioError("body", body, "the table [body] is required")
    try:
        return SimpleNamespace(body=Body(**body), initial=Initial(**initial))
    except TypeError as exc:  # a key the table does not have
        raise ScenarioError("initial", "(keys)", f"cannot be read: {exc}") from None
