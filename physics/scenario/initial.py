"""The initial rotation every system starts from: ``omega`` as given, or G0 and theta0 turned into it."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # read only for its body and initial tables; the scenario module imports the edits built on this
    from physics.scenario.scenario import Scenario


def initial_G(scenario: Scenario) -> tuple[np.ndarray, float, float]:
    """Initial angular velocity w0 (body frame), G0 = |J* w0| and theta0 (angle of J* w0 to e3)."""
    body, ini = scenario.body, scenario.initial
    J = np.array([body.A, body.B, body.C])
    if ini.omega is not None:
        w = np.array(ini.omega, dtype=float)
        G = J * w
        return w, float(np.linalg.norm(G)), float(math.atan2(math.hypot(G[0], G[1]), G[2]))
    G = ini.G0 * np.array([math.sin(ini.theta0), 0.0, math.cos(ini.theta0)])
    return G / J, float(ini.G0), float(ini.theta0)
