"""Quasirigid physics: free rigid bodies with moving internal parts, at three fidelities.

Headless (numpy, scipy, numba); never imports the app or viser. The public API:

    sc = physics.Scenario.load("assets/scenarios/oblate_settling.toml")
    tr = physics.simulate(sc)            # Trajectory: t, theta, K, E, omega, quat, internal
    physics.derived(sc)                  # F, D, L, H, P, Gamma1, ..., T, eps, Re, auto's choice
    physics.sweep(sc, vary={"mass.chi": "1:20:5"}, metric="decay_time")   # SweepTable (docs/sweeps.md)
    physics.design(sc, vary={"pendulum.k": (20, 80)}, objective="decay_time")   # DesignResult (docs/guide.md)
"""

from physics.core import figure
from physics.core.errors import IntegrationFault, ScenarioError, ValidityWarning
from physics.core.rotation import IDENTITY, qconj, qmul, rotate, rotation_matrix
from physics.core.trajectory import Trajectory
from physics.kernels.build import BuildStatus
from physics.kernels.build import status as kernel_status
from physics.registry import (
    REGISTRY,
    SYSTEMS,
    Model,
    Param,
    RegistrationError,
    System,
    Table,
    get_model,
    get_system,
    load_builtin,
    register_system,
    unregister_system,
)
from physics.registry import register as register_model
from physics.scenario.defaults import default_scenario
from physics.scenario.edit import edit_dict
from physics.scenario.initial import initial_G
from physics.scenario.meta import BASE_FOLDERS, BASE_PARAMS, base_values
from physics.scenario.params import Body, Initial, Run
from physics.scenario.scenario import Scenario
from physics.stepping.live import LiveRun
from physics.stepping.simulate import simulate
from physics.stepping.stepper import brake_and_medium
from physics.stepping.warm import start as build_kernels
from physics.studies.design import OBJECTIVES, DesignResult, DesignStopped, Evaluation, design
from physics.studies.metrics import METRICS, Metric
from physics.studies.sweep import SweepTable, axis_values, check_point, numeric_keys, point_scenario, resolve_key, sweep
from physics.studies.work_precision import Row as WorkPrecisionRow
from physics.studies.work_precision import WorkPrecision, work_precision
from physics.systems.carry import CannotCarry, Carried, carry_state
from physics.systems.choice import DEFAULT_ACCURACY, choose_fidelity
from physics.systems.choice import conditions as validity_conditions
from physics.systems.derived import derived
from physics.systems.end_state import EndLocked, EndState, NoEndState, end_state
from physics.systems.moving_mass import closed
from physics.systems.moving_mass.coefficients import Coefficients, coefficients
from physics.systems.moving_mass.params import THRUSTERS, Cavity, Control, Mass, Medium, with_thruster
from physics.systems.moving_mass.validity import averaged_conditions
from physics.systems.pendulum.geometry import resolved_stiffness
from physics.systems.pendulum.params import PIVOTS

__all__ = [
    "Body", "BuildStatus", "figure", "CannotCarry", "Carried", "build_kernels", "kernel_status",
    "Cavity", "Coefficients", "Control", "IntegrationFault", "Initial", "LiveRun", "Mass", "Medium", "Model",
    "METRICS", "Metric", "REGISTRY", "Run", "Scenario", "ScenarioError", "SweepTable", "Trajectory", "ValidityWarning",
    "averaged_conditions", "axis_values", "check_point", "numeric_keys", "point_scenario", "resolve_key", "sweep",
    "OBJECTIVES", "DesignResult", "DesignStopped", "Evaluation", "design",
    "DEFAULT_ACCURACY", "PIVOTS", "carry_state", "choose_fidelity", "closed", "resolved_stiffness", "coefficients",
    "default_scenario", "derived", "end_state", "EndLocked", "EndState", "NoEndState",
    "get_model", "get_system", "initial_G", "load_builtin", "Param", "register_model", "register_system",
    "RegistrationError", "System", "SYSTEMS", "Table", "unregister_system",
    "BASE_FOLDERS", "BASE_PARAMS", "base_values", "brake_and_medium", "edit_dict", "IDENTITY", "qconj", "qmul",
    "rotate",
    "rotation_matrix",
    "simulate", "validity_conditions", "WorkPrecision", "WorkPrecisionRow", "work_precision",
    "THRUSTERS", "with_thruster",
]

load_builtin()  # every system folder registers its system and models
