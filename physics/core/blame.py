"""Arithmetic and linear-algebra failures on accepted input, turned into faults that name a key.

Validation refuses what is meaningless; a scenario it accepts can still hold values so far apart in
size that a product overflows, a quotient divides by an underflowed zero or a matrix turns singular.
``guarded(sc)`` wraps a computation (``derived``, ``simulate``) so that such a failure reaches the
user as one NumericalFault naming the most extreme value, never as a traceback.
"""

from __future__ import annotations

import math
import re
from contextlib import contextmanager

import numpy as np

from physics.core.errors import IntegrationFault, NumericalFault, ScenarioError
from physics.core.guarded import RightSideError

# what numpy, scipy and Python raise when the numbers, not the code, are at fault
NUMERICAL = (ArithmeticError, np.linalg.LinAlgError, ValueError, RuntimeError)
# The sizes [run] keys usually take (they have no slider): without them a default rtol = 1e-10, ten decades
# from 1, was blamed for a fault that mass.chi = 1e12 caused.
RUN_SPANS = {"run.t_end": (1e-3, 1e6), "run.rtol": (1e-14, 1e-2), "run.dt": (1e-7, 1.0), "run.accuracy": (1e-12, 1.0),
             "run.samples": (2, 1e6)}


def _decades(x: float, span: tuple[float, float] | None) -> float:
    """How many decades |x| lies outside ``span`` (lo, hi), or from 1 when there is none; with lo <= 0 only
    the top counts (a tiny value of a key that may be 0 is ordinary)."""
    if span is None:
        return abs(math.log10(abs(x)))
    lo, hi = span
    top = max(abs(lo), abs(hi))
    # differences of logarithms, not logarithms of quotients: 5e-324 / 1e6 underflows to 0, whose log10 raised
    # ValueError here, out of the very handler that turns failures into a fault naming a key
    size = math.log10(abs(x))
    over = size - math.log10(top) if top > 0 else 0.0
    under = math.log10(lo) - size if lo > 0 else 0.0
    return max(0.0, over, under)


def most_extreme(sc, spans: dict[str, tuple[float, float]] | None = None) -> tuple[str, object]:
    """(dotted key, value) of the scenario's nonzero number furthest in size from the span its key usually
    takes (``spans``: key -> (lo, hi), the explorer's slider ranges, and RUN_SPANS), or from 1 (|log10|x||)
    for a key with no span."""
    spans = {**RUN_SPANS, **(spans or {})}
    best, worst = ("scenario", "(no number)"), -1.0
    for table, items in sc.to_dict().items():
        blocks = items if isinstance(items, list) else [items]
        for i, block in enumerate(blocks):
            where = f"{table}[{i}]" if isinstance(items, list) else table
            for key, value in block.items():
                for x in value if isinstance(value, list) else [value]:
                    if isinstance(x, bool) or not isinstance(x, (int, float)) or x == 0 or not math.isfinite(x):
                        continue
                    size = _decades(x, spans.get(f"{table}.{key}"))
                    if size > worst:
                        best, worst = (f"{where}.{key}", value), size
    return best


def outlier(sc, spans: dict[str, tuple[float, float]] | None = None) -> tuple[str, object] | None:
    """``most_extreme`` when that value lies outside the span its key usually takes (for a key with no span, more
    than OUTLIER_DECADES from 1); None when every value is ordinary."""
    key, value = most_extreme(sc, spans)
    numbers = [x for x in (value if isinstance(value, list) else [value])  # initial.omega is a list
               if isinstance(x, (int, float)) and not isinstance(x, bool) and x != 0 and math.isfinite(x)]
    if not numbers:
        return None
    span = {**RUN_SPANS, **(spans or {})}.get(re.sub(r"\[\d+\]", "", key))  # plane_pendulum[0].k: plane_pendulum.k
    size = max(_decades(float(x), span) for x in numbers)
    return (key, value) if size > (0.0 if span else OUTLIER_DECADES) else None


# a value of a key with no usual span is an outlier this many decades from 1
OUTLIER_DECADES = 6.0
# A fault this early in the run (a fraction of run.t_end) is one of the input: the integrator had barely started
# (pendulum.k = 1e30: a step-size underflow at t = 8e-13 of 120 s), so it is blamed as a fault at t = 0 is.
EARLY_FRACTION = 1e-9


@contextmanager
def guarded(sc, what: str, spans: dict[str, tuple[float, float]] | None = None):
    """Re-raise an arithmetic or linear-algebra failure inside the block as NumericalFault naming the
    most extreme value of ``sc`` (most_extreme, with ``spans``); so too an integration fault at t = 0 (a
    step-size underflow or a non-finite state before the first step, or within EARLY_FRACTION of run.t_end, is a
    fault of the input, and the user must learn which key); ScenarioError and other IntegrationFaults pass unchanged."""
    try:
        yield
    except NumericalFault:
        raise
    except IntegrationFault as exc:
        blamed = input_fault(sc, exc, spans)
        if blamed is None:
            raise
        raise blamed from exc
    except ScenarioError:
        raise
    except NUMERICAL as exc:
        key, value = most_extreme(sc, spans)
        raise NumericalFault(f"{what} failed: {plain_words(exc)}", key, value, outlier(sc, spans) is None) from exc


def input_fault(sc, exc: IntegrationFault, spans: dict[str, tuple[float, float]] | None = None
                ) -> NumericalFault | None:
    """An integration fault at the run's start (t <= EARLY_FRACTION run.t_end) as one of the input: a
    NumericalFault naming the most extreme value of ``sc``; None for a later fault, or one of another kind."""
    if type(exc) is not IntegrationFault or not exc.t <= EARLY_FRACTION * _t_end(sc):
        return None
    key, value = most_extreme(sc, spans)
    return NumericalFault(str(exc), key, value, outlier(sc, spans) is None)


def plain_words(exc: BaseException) -> str:
    """What went wrong in a numerical failure, in a user's words where the library's are its own ("(34,
    'Numerical result out of range')", "`y0` must be finite"); otherwise its type and first line, so nothing is
    hidden."""
    if isinstance(exc, (RightSideError, ScenarioError, IntegrationFault)):  # already in the project's words
        return str(exc)
    text = str(exc).splitlines()[0][:120] if str(exc) else ""
    low = text.lower()
    if isinstance(exc, OverflowError) or "overflow" in low or "out of range" in low:
        return "a number grew past the largest a float can hold (about 1.8e308)"
    if isinstance(exc, ZeroDivisionError) or "divide by zero" in low or "division by zero" in low:
        return "a quotient divided by zero (a value too small to tell from 0 next to the others)"
    if "spacing between numbers" in low:  # scipy's step-size underflow, as the compiled steppers name it
        return text.split(":")[0] + ": step size underflow" if ":" in text else "step size underflow"
    if "finite" in low or re.search(r"\b(nan|nans|inf|infs|infinity)\b", low):
        return "a number it needed was not finite (NaN or infinity)"
    if isinstance(exc, np.linalg.LinAlgError) or "singular" in low:
        return "a matrix it had to solve was singular (its values too far apart in size)"
    return f"{type(exc).__name__}{': ' + text if text else ''}"


def _t_end(sc) -> float:
    try:
        return float(sc.run.t_end)
    except (AttributeError, TypeError, ValueError):
        return 0.0
