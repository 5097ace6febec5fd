"""The viscous wheel damper's table ``[wheel]``, validated (docs/models.md Part C).

``J`` (kg m^2) is the wheel's moment about its own axis, ``c`` (N m s) the bearing's viscous coefficient (torque
-c Omega_w on the wheel, Omega_w its rate relative to the body), ``axis`` the wheel's axis in body axes, stored as
a unit vector. The body's A, B, C are the frozen system's moments (the wheel locked), so they include the wheel;
that J fits inside them is a check on the whole scenario (``physics.systems.wheel.system.check``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from physics.core.errors import ScenarioError
from physics.scenario.params import _number, nonneg, positive

UNIT_TOL = 1e-15  # |1 - |a||: a vector this close to unit length is kept as given, so loading is idempotent


def unit_axis(key: str, value) -> tuple[float, float, float]:
    """``value`` (three finite numbers, not all zero) as a unit vector; refused with ScenarioError naming ``key``."""
    if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple)) or len(value) != 3:
        raise ScenarioError(key, value, "must be a list of three numbers [x, y, z] (the wheel's axis, body frame)")
    v = np.array([_number(f"{key}[{i}]", x) for i, x in enumerate(value)])
    big = float(np.max(np.abs(v)))
    if big == 0.0:
        raise ScenarioError(key, value, "must not be the zero vector: it gives the wheel's axis direction")
    with np.errstate(over="ignore"):
        if abs(float(np.linalg.norm(v)) - 1.0) <= UNIT_TOL:
            return (float(v[0]), float(v[1]), float(v[2]))  # already unit: a written scenario reads back as it was
    v = v / big  # scaled first: [1e-320, 0, 0] and [1e300, 1e300, 0] have a finite, nonzero length
    v = v / float(np.linalg.norm(v))
    return (float(v[0]), float(v[1]), float(v[2]))


@dataclass(frozen=True)
class Wheel:
    """A wheel of axial moment ``J`` (kg m^2) about the unit body axis ``axis`` in a bearing of viscous
    coefficient ``c`` (N m s)."""

    J: float
    c: float
    axis: tuple[float, float, float]

    def __post_init__(self):
        object.__setattr__(self, "J", positive("wheel.J", self.J))
        object.__setattr__(self, "c", nonneg("wheel.c", self.c))
        object.__setattr__(self, "axis", unit_axis("wheel.axis", self.axis))
        if not math.isfinite(self.c / self.J):
            raise ScenarioError("wheel.c", self.c, f"is too large for J = {self.J:g}: the wheel's relaxation rate "
                                "c/J must stay finite")
