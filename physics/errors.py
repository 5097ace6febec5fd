"""Errors and warnings that the project raises on purpose.

Every message names the parameter, the value it got and what is allowed, so a user can fix the
input without reading code (the CLI prints ``str(error)`` and exits with status 2).
"""

from __future__ import annotations


class ScenarioError(ValueError):
    """Bad input: a key, its value and the allowed range or set."""

    def __init__(self, key: str, value: object, allowed: str):
        self.key = key
        self.value = value
        self.allowed = allowed
        super().__init__(f"{key} = {_show(value)}: {allowed}")


class ValidityWarning(UserWarning):
    """A model was asked for outside the conditions under which it is accurate (not an error)."""


class IntegrationFault(RuntimeError):
    """The integrator could not go on (non-finite state, step-size underflow)."""

    def __init__(self, what: str, t: float):
        self.what = what
        self.t = t
        super().__init__(f"{what} at t = {t:.17g}")


def _show(value: object) -> str:
    if isinstance(value, str) and value.startswith("("):
        return value  # a placeholder such as "(missing)", not a value the user typed
    if isinstance(value, int) and value.bit_length() > 256:  # repr() refuses ints of more than 4300 digits
        return f"(an integer of about {int(value.bit_length() * 0.30103) + 1} digits)"
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."
