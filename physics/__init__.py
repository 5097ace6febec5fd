"""Quasirigid physics: free rigid bodies with moving internal parts, at three fidelities.

Headless (numpy, scipy, numba); never imports the app or viser. The public API:

    sc = physics.Scenario.load("assets/scenarios/oblate_settling.toml")
    tr = physics.simulate(sc)            # Trajectory: t, theta, K, E, omega, quat, internal
    physics.derived(sc)                  # F, D, L, H, P, Gamma1, ..., T, eps, Re, auto's choice
"""

from . import closed
from .coefficients import Coefficients, coefficients, initial_G
from .defaults import default_scenario
from .derived import derived
from .errors import IntegrationFault, ScenarioError, ValidityWarning
from .live import LiveRun
from .models import REGISTRY, Model, get_model
from .params import Body, Cavity, Control, Initial, Mass, Medium, Run
from .scenario import Scenario
from .simulate import simulate
from .trajectory import Trajectory
from .validity import averaged_conditions, choose_fidelity

__all__ = [
    "Body", "Cavity", "Coefficients", "Control", "IntegrationFault", "Initial", "LiveRun", "Mass", "Medium", "Model",
    "REGISTRY", "Run", "Scenario", "ScenarioError", "Trajectory", "ValidityWarning", "averaged_conditions",
    "choose_fidelity", "closed", "coefficients", "default_scenario", "derived", "get_model", "initial_G",
    "simulate",
]
