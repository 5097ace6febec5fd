"""What a sweep measures on one run: each metric is defined here once, as ``fn(trajectory, scenario) -> float``.

``METRICS`` maps a name to a Metric (unit, one-line meaning, function). docs/sweeps.md quotes these
definitions; a metric that does not apply to a run (no braking torque, no internal part) is NaN, never
an error, so one odd point cannot stop a sweep.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from physics.core.trajectory import Trajectory
from physics.registry import get_system
from physics.scenario.scenario import Scenario

FIT_BAND = 20.0  # the decay fit ends when theta first leaves [theta0/20, 20 theta0]: three e-folds either way
FIT_CEILING = 1.2  # rad; growth slows as theta nears a flat spin (pi/2), so the growth fit ends here
FIT_MIN_POINTS = 3  # fewer samples in the window give no fit (NaN)
BRAKED = "braking brought |G| to zero"  # Trajectory.info["stop_reason"] of a run ended by braking


@dataclass(frozen=True)
class Metric:
    """One number per run: ``name`` (the CSV column), ``unit``, ``meaning`` and ``fn(tr, sc) -> float``."""

    name: str
    unit: str
    meaning: str
    fn: Callable[[Trajectory, Scenario], float]

    def __call__(self, tr: Trajectory, sc: Scenario) -> float:
        return float(self.fn(tr, sc))


def decay_time(tr: Trajectory, sc: Scenario) -> float:
    """Fitted nutation e-folding time tau = -1/s, s (signed: > 0 decays, < 0 grows, inf if flat).

    s is the least-squares slope of ln theta(t) over the samples from t = 0 until theta first leaves
    [theta0/FIT_BAND, min(FIT_BAND theta0, FIT_CEILING)] (no ceiling when theta0 >= FIT_CEILING), so
    theta(t) ~ theta0 exp(-t/tau) early in the run. NaN with fewer than FIT_MIN_POINTS samples or theta0 = 0.
    """
    t, theta = np.asarray(tr.t, float), np.asarray(tr.theta, float)
    th0 = theta[0]
    if not th0 > 0:
        return math.nan
    hi = min(FIT_BAND * th0, FIT_CEILING) if th0 < FIT_CEILING else math.inf
    outside = (theta < th0 / FIT_BAND) | (theta > hi) | ~(theta > 0)
    inside = np.cumsum(outside) == 0
    if inside.sum() < FIT_MIN_POINTS:
        return math.nan
    slope = float(np.polyfit(t[inside], np.log(theta[inside]), 1)[0])
    return math.inf if slope == 0 else -1.0 / slope


def theta_end(tr: Trajectory, sc: Scenario) -> float:
    """Nutation angle theta at the last output time (the braking time when braking ends the run), rad."""
    return float(tr.theta[-1])


def braking_time(tr: Trajectory, sc: Scenario) -> float:
    """Time at which the braking torque brought |G| to zero (seed 004 eq. (8)-(9)), s; inf when the run
    reached t_end still turning, NaN when the scenario has no braking torque (no [control] or b = 0)."""
    if sc.control is None or sc.control.b == 0:
        return math.nan
    if tr.info.get("stop_reason") == BRAKED:
        return float(tr.info.get("t_stop", tr.t[-1]))
    return math.inf


def max_displacement(tr: Trajectory, sc: Scenario) -> float:
    """Largest excursion of the internal part over the run, as its system measures it (``System.amplitude``:
    the moving mass's max |u|, m; a pendulum's largest angle from rest, rad). NaN without an internal part."""
    amplitude = get_system(sc.system).amplitude
    return math.nan if amplitude is None else float(amplitude(tr, sc))


def energy_dissipated(tr: Trajectory, sc: Scenario) -> float:
    """E(0) - E(end), J: kinetic plus spring energy lost over the run, to internal damping and to the
    external torques (medium, braking) alike. Trajectory.E of the model that ran (the averaged and
    closed models' E is that of the fictitious rigid body, 0.5 w . J* w)."""
    return float(tr.E[0] - tr.E[-1])


METRICS: dict[str, Metric] = {m.name: m for m in (
    Metric("decay_time", "s", "fitted nutation e-folding time (signed: < 0 means the nutation grows)", decay_time),
    Metric("theta_end", "rad", "nutation angle at the end of the run", theta_end),
    Metric("braking_time", "s", "time at which braking stopped the rotation (inf: not by t_end)", braking_time),
    Metric("max_displacement", "m or rad", "largest displacement of the internal mass (m) or swing of the "
           "pendulum (rad)", max_displacement),
    Metric("energy_dissipated", "J", "E(0) - E(end): energy lost to damping and external torques", energy_dissipated),
)}
