"""Errors and warnings that the project raises on purpose.

Every message names the parameter, the value it got and what is allowed, so a user can fix the
input without reading code (the CLI prints ``str(error)`` and exits with status 2).
"""

from __future__ import annotations

import os


class ScenarioError(ValueError):
    """Bad input: a key, its value and the allowed range or set."""

    def __init__(self, key: str, value: object, allowed: str):
        # a key or text of a hundred thousand characters (a fuzzed file) is cut, so the message stays one line
        self.key = _cut(_text(key))
        self.value = value
        self.allowed = _cut(_text(allowed), MAX_ALLOWED)
        super().__init__(f"{self.key} = {_show(value)}: {self.allowed}")


class ValidityWarning(UserWarning):
    """A model was asked for outside the conditions under which it is accurate (not an error)."""


class IntegrationFault(RuntimeError):
    """The integrator could not go on (non-finite state, step-size underflow)."""

    def __init__(self, what: str, t: float):
        self.what = what
        self.t = t
        super().__init__(f"{what} at t = {t:.17g}")


class NumericalFault(IntegrationFault):
    """Arithmetic or linear algebra failed on accepted input (an overflow, a singular matrix...): reported
    as a fault like an integration's, naming the key most likely to blame (physics/core/blame.py)."""

    def __init__(self, what: str, key: str, value: object, ordinary: bool = False):
        shown = f"{_cut(_text(key))} = {_show(value)}"
        # ordinary: no value lies outside the size its key usually takes, so none is to blame, and saying "bring it
        # nearer" would send the user after a value that is fine (run.samples = 1001 was named so)
        tail = (f"no value is far from its usual size (the furthest is {shown}): please report this scenario"
                if ordinary else f"the most extreme value is {shown}: bring it nearer the scenario's other scales")
        RuntimeError.__init__(self, f"{what}; {tail}")
        self.what, self.t, self.key, self.value = what, 0.0, key, value


def _show(value: object) -> str:
    if isinstance(value, os.PathLike):  # a file's path is shown whole: its name, at the end, is what a user looks for
        return _cut_middle(repr(os.fspath(value)), MAX_PATH)
    if isinstance(value, str) and value.startswith("("):
        return value  # a placeholder such as "(missing)", not a value the user typed
    if isinstance(value, int) and value.bit_length() > 256:  # repr() refuses ints of more than 4300 digits
        return f"(an integer of about {int(value.bit_length() * 0.30103) + 1} digits)"
    try:
        text = repr(value)
    except RecursionError:  # a table nested thousands deep (a long dotted key): say what it is
        return f"(a {type(value).__name__} nested too deeply to show)"
    except ValueError:  # repr() refuses an integer of more than 4300 digits inside a list or table
        return f"(a {type(value).__name__} holding a number too long to show)"
    except Exception:  # noqa: BLE001 - an API caller's object whose __repr__ raises: the message must still be made
        return f"(a {type(value).__name__} that cannot be shown)"
    return _cut(text)


def _text(thing: object) -> str:
    """``str(thing)``, or what it is when its __str__ raises (a caller's own object)."""
    if isinstance(thing, str):
        return thing
    try:
        return str(thing)
    except Exception:  # noqa: BLE001 - the error being built must not be replaced by another
        return _show(thing)


MAX_SHOWN = 80  # characters of a key or value echoed back: a message stays one readable line
MAX_ALLOWED = 400  # characters of the "allowed" part (it may list keys, or quote a parser's message)
MAX_PATH = 1000  # characters of a file's path: longer ones (the system allows 4096) lose their middle, not their name


def _cut(text: str, limit: int = MAX_SHOWN) -> str:
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _cut_middle(text: str, limit: int) -> str:
    keep = limit - 3
    return text if len(text) <= limit else text[:keep // 2] + "..." + text[len(text) - (keep - keep // 2):]
