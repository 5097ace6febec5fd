"""Parameters of the pendulum nutation dampers (seed 002, docs/models.md Part B), validated.

``[pendulum]`` is Alger's spherical pendulum: a bob of mass m (kg) on an arm of length l (m) from
a two-gimbal pivot on the spin axis at height h (m) above the system COM O (bob at rest at
(h + l) e3), a torsional spring k (N m/rad) and a pivot damper c_d (N m s/rad) on both gimbal
angles. ``[[plane_pendulum]]`` is one of Taylor's plane pendulums: a hinge point (m, from O), a
hinge axis, an arm direction at rest (perpendicular to the axis), l, m, k, c_d; or a named
``preset`` geometry of docs/models.md B.7 placed by ``R``, ``z_p`` and ``azimuth`` (rad).
``k`` may be "resonant" or "optimal" (spherical pendulum): tuned from the scenario (docs/models.md B.5).
``pivot`` (spherical pendulum) says what the spring and damper act on: "cardan" (the default, the paper's
model, docs/models.md B.1): the two gimbal angles, V = k (alpha^2 + beta^2)/2, singular where the arm is
perpendicular to both gimbal axes (|beta| = 90 deg), so the run stops there with a spring; "isotropic": the
arm's direction e, V = k (1 - e.e3), R = c_d |e'|^2/2, the same to second order in the angles and defined at
every position, so the run goes on through that pole (physics/compiled/pendulum.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from physics.core.errors import ScenarioError
from physics.scenario.params import _number, nonneg, positive

TUNINGS = ("resonant", "optimal")
PRESETS = ("in_plane", "meridian_out", "meridian_in", "meridian_axis")
PIVOTS = ("cardan", "isotropic")  # pendulum.pivot: spring and damper on the Cardan angles, or on the arm's direction


def _stiffness(key: str, value) -> float | str:
    if isinstance(value, str):
        if value not in TUNINGS:
            raise ScenarioError(key, value, 'must be a number >= 0, "resonant" or "optimal"')
        return value
    return nonneg(key, value)


def _vector(key: str, value, *, nonzero: bool) -> tuple[float, float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise ScenarioError(key, value, "must be a list of three numbers [x, y, z]")
    v = tuple(_number(f"{key}[{i}]", x) for i, x in enumerate(value))
    if nonzero and math.hypot(*v) == 0:
        raise ScenarioError(key, value, "must not be the zero vector")
    return v


@dataclass(frozen=True)
class Pendulum:
    """Spherical pendulum (seed 002, Alger's damper; docs/models.md B.1). ``pivot``: see the module docstring."""

    m: float
    l: float
    h: float
    k: float | str
    c_d: float = 0.0
    pivot: str = "cardan"

    def __post_init__(self):
        object.__setattr__(self, "m", positive("pendulum.m", self.m))
        object.__setattr__(self, "l", positive("pendulum.l", self.l))
        object.__setattr__(self, "h", _number("pendulum.h", self.h))
        object.__setattr__(self, "k", _stiffness("pendulum.k", self.k))
        object.__setattr__(self, "c_d", nonneg("pendulum.c_d", self.c_d))
        if not isinstance(self.pivot, str) or self.pivot not in PIVOTS:
            raise ScenarioError("pendulum.pivot", self.pivot, 'must be "cardan" (spring and damper on the gimbal '
                                'angles, the paper\'s model) or "isotropic" (on the arm\'s direction: goes on through '
                                "the gimbal pole)")


@dataclass(frozen=True)
class PlanePendulum:
    """One plane pendulum (seed 002, Taylor's damper; docs/models.md B.1, B.7). Give ``hinge``, ``axis`` and
    ``arm``, or a ``preset`` with ``R``, ``z_p`` and ``azimuth``."""

    m: float
    l: float
    k: float | str
    c_d: float = 0.0
    hinge: tuple[float, float, float] | None = None
    axis: tuple[float, float, float] | None = None
    arm: tuple[float, float, float] | None = None
    preset: str | None = None
    R: float | None = None
    z_p: float | None = None
    azimuth: float | None = None

    def __post_init__(self):
        where = "plane_pendulum"
        object.__setattr__(self, "m", positive(f"{where}.m", self.m))
        object.__setattr__(self, "l", positive(f"{where}.l", self.l))
        object.__setattr__(self, "k", _stiffness(f"{where}.k", self.k))
        if self.k == "optimal":
            raise ScenarioError(f"{where}.k", "optimal", 'is for the spherical pendulum; use a number or "resonant"')
        object.__setattr__(self, "c_d", nonneg(f"{where}.c_d", self.c_d))
        geometry = (self.hinge, self.axis, self.arm)
        placed = (self.R, self.z_p, self.azimuth)
        if self.preset is not None:
            if self.preset not in PRESETS:
                raise ScenarioError(f"{where}.preset", self.preset, "must be one of " + ", ".join(PRESETS))
            if any(g is not None for g in geometry):
                raise ScenarioError(f"{where}.preset", self.preset, "give either a preset or hinge/axis/arm, not both")
            object.__setattr__(self, "R", nonneg(f"{where}.R", 0.0 if self.R is None else self.R))
            object.__setattr__(self, "z_p", _number(f"{where}.z_p", 0.0 if self.z_p is None else self.z_p))
            object.__setattr__(self, "azimuth", _number(f"{where}.azimuth", 0.0 if self.azimuth is None else
                                                        self.azimuth))
            if self.preset == "meridian_axis" and self.R != 0:
                raise ScenarioError(f"{where}.R", self.R, "must be 0 for the meridian_axis preset (hinge on the axis)")
            return
        if any(v is not None for v in placed):
            raise ScenarioError(where, "R/z_p/azimuth", "place a pendulum by R, z_p, azimuth only with a preset")
        if any(g is None for g in geometry):
            raise ScenarioError(where, "(incomplete)", "give hinge, axis and arm (three vectors), or a preset")
        object.__setattr__(self, "hinge", _vector(f"{where}.hinge", self.hinge, nonzero=False))
        object.__setattr__(self, "axis", _vector(f"{where}.axis", self.axis, nonzero=True))
        object.__setattr__(self, "arm", _vector(f"{where}.arm", self.arm, nonzero=True))
        n, e = np.array(self.axis), np.array(self.arm)
        n, e = n / np.max(np.abs(n)), e / np.max(np.abs(e))  # scaled first: huge or tiny components stay finite
        cos = abs(n @ e) / (np.linalg.norm(n) * np.linalg.norm(e))
        if cos > 1e-9:
            raise ScenarioError(f"{where}.arm", self.arm, f"must be perpendicular to axis = {list(self.axis)} "
                                f"(|cos| = {cos:.3g})")

    def geometry(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(hinge point from O, unit hinge axis n, unit arm direction e0), body frame."""
        if self.preset is None:
            n, e = np.array(self.axis), np.array(self.arm)
            n, e = n / np.max(np.abs(n)), e / np.max(np.abs(e))  # scaled first: |[5e-324, 0, 0]| is 0 in floats
            return np.array(self.hinge, dtype=float), n / np.linalg.norm(n), e / np.linalg.norm(e)
        c, s = math.cos(self.azimuth), math.sin(self.azimuth)
        radial, tangential, z = np.array([c, s, 0.0]), np.array([-s, c, 0.0]), np.array([0.0, 0.0, 1.0])
        hinge = self.R * radial + self.z_p * z
        if self.preset == "in_plane":
            return hinge, z, radial
        if self.preset == "meridian_in":
            return hinge, tangential, -radial
        return hinge, tangential, radial  # meridian_out, meridian_axis
