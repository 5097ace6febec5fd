"""Issue 24, point 3: the public API raises only its documented error types (ScenarioError for bad input,
IntegrationFault for a run that cannot go on) for any argument, bounds every point count it is given, and
names the key whose value causes a refusal."""

from __future__ import annotations

from physics import ScenarioError
from physics.core.errors import NumericalFault


class Unshowable:
    """A caller's object whose every text conversion raises: the error about it must still be made."""

    def __repr__(self):
        raise KeyError("repr")

    def __str__(self):
        raise KeyError("str")

    def __format__(self, spec):
        raise KeyError("format")

    def __float__(self):
        raise KeyError("float")


def test_an_error_about_a_value_whose_repr_raises_is_still_one_line_naming_the_key():
    err = ScenarioError("mass.chi", Unshowable(), "must be a number")
    assert str(err) == "mass.chi = (a Unshowable that cannot be shown): must be a number"
    err = ScenarioError(Unshowable(), 1.0, Unshowable())  # key and allowed text too
    assert "\n" not in str(err) and "Unshowable" in str(err)
    fault = NumericalFault("the run failed", Unshowable(), Unshowable())
    assert "cannot be shown" in str(fault)
