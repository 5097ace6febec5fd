"""What a number typed into a slider's box is: read as people write it, or refused in words. No viser here.

The page sends the box's text as typed (``app.panel.typed_numbers``), so the server reads it, not the browser's
number input (which dropped what it did not expect: ``1e-3`` arrived as -13, ``1,5`` as 15). Read here:

- decimals with a point, an exponent in either case and either sign: ``0.001``, ``1e-3``, ``1.5E2``, ``-2e+1``;
- a decimal comma (``1,5`` is 1.5, ``2,25e-3`` is 0.00225) when it cannot be a thousands separator: a comma
  followed by exactly three digits (``1,500``) could be either, so it is refused, saying both readings;
- spaces around the number, a typographic minus sign (U+2212).

Refused, with the reason: an empty box, anything else (``abc``, ``1.2.3``, ``0x10``, ``1_000``), and what is not a
finite number (``inf``, ``nan``, ``1e999``).
"""

from __future__ import annotations

import math
import re

MAX_TEXT = 60  # characters of a typed text kept (and shown); a longer one is no number anyone typed

_PLAIN = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")
_COMMA = re.compile(r"[+-]?\d*,\d+([eE][+-]?\d+)?")
_THOUSANDS = re.compile(r"[+-]?\d{1,3},\d{3}")


class Unreadable(ValueError):
    """A typed text that is no number; ``str(exc)`` says why, in words for the page."""


def read_number(text: str) -> tuple[float, bool]:
    """(the number ``text`` stands for, whether it was read with a decimal comma); raises Unreadable."""
    if not isinstance(text, str):
        raise Unreadable("not text")
    s = text.strip().replace("\u2212", "-")
    if not s:
        raise Unreadable("the box was left empty")
    comma = False
    if _THOUSANDS.fullmatch(s):
        raise Unreadable(f"a comma before three digits may be a decimal comma or a thousands separator; write "
                         f"{float(s.replace(',', '.')):g} or {s.replace(',', '')}")
    if _COMMA.fullmatch(s):
        s, comma = s.replace(",", "."), True
    if not _PLAIN.fullmatch(s):
        raise Unreadable("not a number (write it like 0.001, 1e-3, 1.5E2 or 1,5)")
    value = float(s)
    if not math.isfinite(value):
        raise Unreadable("too large to be a number here (beyond 1.8e308)")
    return value, comma


def shown(text: str) -> str:
    """The typed text as the page quotes it: stripped, at most MAX_TEXT characters."""
    s = str(text).strip()
    return repr(s if len(s) <= MAX_TEXT else s[:MAX_TEXT] + "...")
