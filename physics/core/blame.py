"""Arithmetic and linear-algebra failures on accepted input, turned into faults that name a key.

Validation refuses what is meaningless; a scenario it accepts can still hold values so far apart in
size that a product overflows, a quotient divides by an underflowed zero or a matrix turns singular.
``guarded(sc)`` wraps a computation (``derived``, ``simulate``) so that such a failure reaches the
user as one NumericalFault naming the most extreme value, never as a traceback.
"""

from __future__ import annotations

import math
from contextlib import contextmanager

import numpy as np

from physics.core.errors import IntegrationFault, NumericalFault, ScenarioError

# what numpy, scipy and Python raise when the numbers, not the code, are at fault
NUMERICAL = (ArithmeticError, np.linalg.LinAlgError, ValueError, RuntimeError)


def most_extreme(sc) -> tuple[str, object]:
    """(dotted key, value) of the scenario's nonzero number furthest from 1 in size (|log10|x||)."""
    best, worst = ("scenario", "(no number)"), -1.0
    for table, items in sc.to_dict().items():
        blocks = items if isinstance(items, list) else [items]
        for i, block in enumerate(blocks):
            where = f"{table}[{i}]" if isinstance(items, list) else table
            for key, value in block.items():
                for x in value if isinstance(value, list) else [value]:
                    if isinstance(x, bool) or not isinstance(x, (int, float)) or x == 0 or not math.isfinite(x):
                        continue
                    size = abs(math.log10(abs(x)))
                    if size > worst:
                        best, worst = (f"{where}.{key}", value), size
    return best


@contextmanager
def guarded(sc, what: str):
    """Re-raise an arithmetic or linear-algebra failure inside the block as NumericalFault naming the
    most extreme value of ``sc``; ScenarioError and IntegrationFault pass unchanged."""
    try:
        yield
    except (ScenarioError, IntegrationFault):
        raise
    except NUMERICAL as exc:
        key, value = most_extreme(sc)
        detail = str(exc).splitlines()[0][:120] if str(exc) else ""
        raise NumericalFault(f"{what} failed ({type(exc).__name__}{': ' + detail if detail else ''})",
                             key, value) from exc
