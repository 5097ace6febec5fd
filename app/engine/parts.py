"""The internal part's items as the explorer draws them, without naming a system: the items of the scene's
array tables (several of one part, e.g. plane pendulums) and the number of pendulum bobs."""

from __future__ import annotations

import physics


def array_items(sc: physics.Scenario) -> tuple:
    """The items of the scene's array tables (``[[table]]``), in order."""
    items: list = []
    for table in physics.get_system(sc.system).tables:
        if table.array:
            items += list(getattr(sc, table.attribute))
    return tuple(items)


def bob_count(sc: physics.Scenario) -> int:
    """Pendulum bobs drawn for the scene: the array tables' items, plus a single ``[pendulum]``."""
    return len(array_items(sc)) + (sc.pendulum is not None)
