"""The one name of the integrator a run uses and of how its right-hand side runs.

Stepper.label (a trajectory's ``info["method"]``) and ``physics.derived``'s ``auto_method`` (``physics info``, the
explorer's auto line) both come from ``method_label``, and it decides "compiled" the way the stepper does: by
asking the stepper's kernel picker whether it hands out the compiled integrator (physics/kernels/build.py
``pick`` gives the interpreted twin while the compiled kernels are being built) and whether the model has a
Python right-hand side. So the two cannot disagree.
"""

from __future__ import annotations

from physics.compiled import dop853
from physics.scenario.params import FIXED_STEP_METHODS

COMPILED = "compiled"
TWIN = "interpreted twin while the compiled kernels are built"
PYTHON = "interpreted, Python right-hand side"


def _identity(function):
    return function


def execution(model, kernels=None) -> str:
    """How ``model``'s right-hand side runs under the kernel picker ``kernels`` (None: compiled, as ``simulate``
    calls it): COMPILED, TWIN or PYTHON."""
    if model.py_rhs is not None:
        return PYTHON
    pick = kernels or _identity
    return COMPILED if pick(dop853.integrate) is dop853.integrate else TWIN


def method_label(model, method: str, kernels=None) -> str:
    """The integrator that steps ``model`` with the [run] ``method`` ("auto": DOP853), and how it runs."""
    how = execution(model, kernels)
    if method == "auto":
        return f"DOP853 ({how})"
    if method == "midpoint":
        return f"implicit midpoint ({how}, structure-preserving)"
    if method in FIXED_STEP_METHODS:
        return f"{method} ({how})"
    return f"scipy {method}" + ("" if how == COMPILED else f" ({how})")
