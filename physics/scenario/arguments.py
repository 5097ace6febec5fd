"""Checks of the arguments an API caller passes beside a scenario (a callback, a choice, a mapping).

The public functions raise only their documented types (ScenarioError for bad input, IntegrationFault for
a run that cannot go on); an argument of the wrong type must not reach the code as an AttributeError or
TypeError from deep inside. Each check names the argument as the caller wrote it.
"""

from __future__ import annotations

import os
from collections.abc import Mapping

from physics.core.errors import ScenarioError
from physics.scenario.scenario import Scenario


def scenario(value: object, name: str = "scenario") -> Scenario:
    """``value`` if it is a physics.Scenario."""
    if not isinstance(value, Scenario):
        raise ScenarioError(name, type(value).__name__, "must be a physics.Scenario")
    return value


def callback(value: object, name: str):
    """``value`` if it is None or callable (a progress callback)."""
    if value is not None and not callable(value):
        raise ScenarioError(name, value, "must be a function (or None)")
    return value


def choice(value: object, name: str, allowed: tuple[str, ...]) -> str:
    """``value`` if it is one of the strings ``allowed`` (a dict or list is refused, not hashed)."""
    if not isinstance(value, str) or value not in allowed:
        raise ScenarioError(name, value, "must be one of " + ", ".join(f'"{a}"' for a in allowed))
    return value


def mapping(value: object, name: str, example: str) -> Mapping:
    """``value`` if it is a mapping whose keys are strings."""
    if not isinstance(value, Mapping) or not all(isinstance(k, str) for k in value):
        raise ScenarioError(name, value, f"must be a dict of names to values, e.g. {example}")
    return value


def number(value: object, name: str) -> float:
    """``float(value)``, refused in words when float() refuses it (a caller's object may raise anything)."""
    if isinstance(value, bool):
        raise ScenarioError(name, value, "must be a number")
    try:
        return float(value)
    except Exception:  # noqa: BLE001 - float() of a caller's object may raise any type
        raise ScenarioError(name, value, "must be a number") from None


# The most local processes a sweep or design may start. A pool forks all of its processes at its first run (a
# ProcessPoolExecutor on fork), so ``workers=100000`` forked over a thousand processes within 30 s, climbing with no
# end; past the cores they only share them, and 256 is more than any machine we run on has.
MAX_WORKERS = 256


def workers(value: object, name: str = "workers") -> int:
    """``value`` (a whole number from 1 to MAX_WORKERS) or, when None, the machine's cores."""
    if value is None:
        return min(os.cpu_count() or 1, MAX_WORKERS)
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= MAX_WORKERS:
        raise ScenarioError(name, value, f"must be a whole number of processes from 1 to {MAX_WORKERS} (or None: all "
                                         f"cores, {os.cpu_count() or 1} here); more than the cores only share them")
    return value
