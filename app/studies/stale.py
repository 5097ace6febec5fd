"""Whether a result computed on one scene still describes the scene shown now.

A panel keeps the scenario its result was computed on; the scene is "the same" when the two scenarios
agree apart from the keys the result itself varies (a sweep's keys, so loading one of its points does
not make the sweep stale; a run's method and step, so applying a recommended method does not either).
"""

from __future__ import annotations

import physics

RUN_SETTINGS = ("run.method", "run.rtol", "run.dt")
INITIAL_FORMS = ("initial.omega", "initial.G0", "initial.theta0")  # one state, written two ways


def _stripped(sc: physics.Scenario, keys) -> dict:
    data = sc.to_dict()
    for dotted in keys:
        table, _, key = dotted.partition(".")
        section = data.get(table)
        blocks = section if isinstance(section, list) else [section] if isinstance(section, dict) else []
        for block in blocks:
            block.pop(key, None)
        if isinstance(section, dict) and not section:
            data.pop(table)  # a table the varied key alone brought in (e.g. medium.lambda)
    return data


def same_scene(a: physics.Scenario | None, b: physics.Scenario | None, ignore=()) -> bool:
    """True when ``a`` and ``b`` differ at most in the dotted keys ``ignore``."""
    if a is None or b is None:
        return a is b
    if a is b:
        return True
    keys = set(ignore)
    if any(k in INITIAL_FORMS for k in keys):
        keys |= set(INITIAL_FORMS)
    return _stripped(a, keys) == _stripped(b, keys)
