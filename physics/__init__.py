"""Quasirigid physics: free rigid bodies with moving internal parts, at three fidelities.

Headless (numpy, scipy, numba); never imports the app or viser. The public API:

    sc = physics.Scenario.load("assets/scenarios/oblate_settling.toml")
    tr = physics.simulate(sc)            # Trajectory: t, theta, K, E, omega, quat, internal
    physics.derived(sc)                  # F, D, L, H, P, Gamma1, ..., T, eps, Re, auto's choice
    physics.sweep(sc, vary={"mass.chi": "1:20:5"}, metric="decay_time")   # SweepTable (docs/sweeps.md)
"""

from . import closed
from .carry import CannotCarry, Carried, carry_state
from .coefficients import Coefficients, coefficients, initial_G
from .defaults import default_scenario
from .derived import derived
from .errors import IntegrationFault, ScenarioError, ValidityWarning
from .kernel_build import BuildStatus
from .kernel_build import start as build_kernels
from .kernel_build import status as kernel_status
from .live import LiveRun
from .metrics import METRICS, Metric
from .models import REGISTRY, Model, get_model
from .params import Body, Cavity, Control, Initial, Mass, Medium, Run
from .pendulum_system import resolved_stiffness
from .scenario import Scenario
from .simulate import simulate
from .sweep import SweepTable, axis_values, check_point, numeric_keys, point_scenario, resolve_key, sweep
from .trajectory import Trajectory
from .validity import averaged_conditions, choose_fidelity
from .validity import conditions as validity_conditions
from .work_precision import Row as WorkPrecisionRow
from .work_precision import WorkPrecision, work_precision

__all__ = [
    "Body", "BuildStatus", "CannotCarry", "Carried", "build_kernels", "kernel_status",
    "Cavity", "Coefficients", "Control", "IntegrationFault", "Initial", "LiveRun", "Mass", "Medium", "Model",
    "METRICS", "Metric", "REGISTRY", "Run", "Scenario", "ScenarioError", "SweepTable", "Trajectory", "ValidityWarning",
    "averaged_conditions", "axis_values", "check_point", "numeric_keys", "point_scenario", "resolve_key", "sweep",
    "carry_state", "choose_fidelity", "closed", "resolved_stiffness", "coefficients", "default_scenario", "derived",
    "get_model", "initial_G",
    "simulate", "validity_conditions", "WorkPrecision", "WorkPrecisionRow", "work_precision",
]
