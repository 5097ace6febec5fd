"""A system registered in this file alone is picked up everywhere: simulate, LiveRun, sweep, the model battery,
``physics info``'s derived quantities and the explorer's system list and sliders (issue 14).

The toy is a gyrostat: a body with a rotor spinning about e3 with a fixed relative angular momentum h
(Volterra). Its body-frame momentum K = J w + h e3 obeys K' = K x w, so |K| and the inertial K are
conserved; with h = 0 it is the free rigid body, which the moving-mass system runs with no mass.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass

import numpy as np
import pytest
import test_model_battery as battery

import physics
import physics.compiled.dispatch
from physics.core.rotation import nutation_angle, rotate
from physics.registry import Condition

NAME = "rotor"


@dataclass(frozen=True)
class Rotor:
    """A rotor about e3 with relative angular momentum h (kg m^2/s)."""

    h: float

    def __post_init__(self):
        if isinstance(self.h, bool) or not isinstance(self.h, (int, float)) or not math.isfinite(self.h):
            raise physics.ScenarioError("rotor.h", self.h, "must be a finite number")
        object.__setattr__(self, "h", float(self.h))


def pack(sc):
    return np.array([sc.body.A, sc.body.B, sc.body.C, sc.rotor.h])


def rhs(t, y, p, out):
    J, h = p[:3], p[3]
    w, q = y[:3], y[3:7]
    K = J * w
    K[2] += h
    out[:3] = np.cross(K, w) / J  # J w' = K x w (the rotor's h is constant relative to the body)
    out[3] = -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2])
    out[4] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1])
    out[5] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2])
    out[6] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0])


def initial_state(sc, p):
    w0, _, _ = physics.initial_G(sc)
    return np.concatenate([w0, [1.0, 0.0, 0.0, 0.0]])


def _momentum(Y, p):
    K = Y[:, :3] * p[:3]
    K[:, 2] += p[3]
    return K, 0.5 * np.sum(Y[:, :3] * Y[:, :3] * p[:3], axis=1)


def observe(t, Y, p, sc):
    K, E = _momentum(Y, p)
    q = Y[:, 3:7] / np.linalg.norm(Y[:, 3:7], axis=1)[:, None]
    return physics.Trajectory(t=t, theta=nutation_angle(K), K=np.linalg.norm(K, axis=1), E=E,
                              omega=Y[:, :3].copy(), quat=q)


def invariants(Y, p):
    K, E = _momentum(Y, p)
    return rotate(Y[:, 3:7], K), E


EXAMPLE = """
[body]
A = 1.0
B = 1.2
C = 1.5
M = 1.0

[rotor]
h = 0.3

[initial]
G0 = 2.0
theta0 = 0.4

[run]
fidelity = "auto"
t_end = 20.0
samples = 201
"""


@pytest.fixture(scope="module", autouse=True)
def toy():
    physics.register_model(physics.Model(
        name=f"{NAME}/full", system=NAME, fidelity="full", summary="a gyrostat (test toy)",
        state=("wx", "wy", "wz", "qw", "qx", "qy", "qz"), py_rhs=rhs, pack=pack, initial_state=initial_state,
        observe=observe, invariants=invariants))
    system = physics.register_system(physics.System(
        name=NAME, label="body with a rotor", summary="a gyrostat: a rotor of fixed relative momentum h about e3",
        tables=(physics.Table("rotor", Rotor),), example=EXAMPLE,
        params=(physics.Param("rotor.h", "h", "kg m^2/s", "the rotor's angular momentum relative to the body",
                              -2.0, 2.0, 0.01, folder="Rotor"),),
        folders=("Rotor",), derived=lambda sc: {"h": sc.rotor.h}))
    yield system
    physics.unregister_system(NAME)


def test_a_scenario_with_its_table_runs_its_system():
    sc = physics.Scenario.from_toml(EXAMPLE)
    assert sc.system == NAME and sc.rotor == Rotor(0.3)
    assert physics.Scenario.from_toml(sc.to_toml()) == sc  # the table round-trips
    with pytest.raises(physics.ScenarioError, match="rotor.h"):
        physics.Scenario.from_toml(EXAMPLE.replace("h = 0.3", 'h = "fast"'))
    with pytest.raises(physics.ScenarioError, match="one internal part at a time"):
        physics.Scenario.from_toml(EXAMPLE + "\n[mass]\nm = 0.1\nrho = 1.0\nOmega = 5.0\n")


def test_simulate_conserves_the_gyrostats_momentum():
    sc = physics.Scenario.from_toml(EXAMPLE)
    tr = physics.simulate(sc)
    assert tr.info["model"] == f"{NAME}/full" and tr.info["fidelity"] == "full"
    assert len(tr.t) == 201 and np.all(np.isfinite(tr.theta))
    model = physics.get_model(NAME, "full")
    p = model.pack(sc)
    Y = np.column_stack([tr.omega, tr.quat])
    K_inertial, E = model.invariants(Y, p)
    assert np.max(np.abs(K_inertial - K_inertial[0])) < 1e-8 * np.linalg.norm(K_inertial[0])
    assert np.max(np.abs(E - E[0])) < 1e-8 * E[0]  # torque-free, no dissipation
    assert np.ptp(tr.theta) > 1e-3  # it does nutate: the check above is not of a body at rest


def test_with_no_rotor_it_is_the_free_body_the_moving_mass_system_runs():
    toy = physics.Scenario.from_toml(EXAMPLE.replace("h = 0.3", "h = 0.0"))
    bare = physics.Scenario.from_dict({k: v for k, v in toy.to_dict().items() if k != "rotor"})
    assert bare.system != NAME
    a = physics.simulate(toy)
    b = physics.simulate(bare, fidelity="full")
    assert np.max(np.abs(a.theta - b.theta)) < 1e-7
    assert np.max(np.abs(a.quat - b.quat)) < 1e-7


def test_live_run_steps_it_like_simulate():
    sc = physics.Scenario.from_toml(EXAMPLE)
    run = physics.LiveRun(sc)
    rows = [run.advance(0.5, samples=5) for _ in range(40)]
    theta = np.concatenate([r.theta for r in rows])
    t = np.concatenate([r.t for r in rows])
    ref = physics.simulate(sc)
    assert run.status == "running" and abs(t[-1] - 20.0) < 1e-9
    assert np.max(np.abs(np.interp(ref.t[1:], t, theta) - ref.theta[1:])) < 1e-6


def test_sweep_varies_its_parameter():
    sc = physics.Scenario.from_toml(EXAMPLE)
    assert "rotor.h" in physics.numeric_keys(sc)
    table = physics.sweep(sc, vary={"rotor.h": "0:0.6:3"}, metric="theta_end", executor="serial")
    rows = table.rows
    assert [r["rotor.h"] for r in rows] == [0.0, 0.3, 0.6]
    assert all(r["error"] == "" and math.isfinite(r["theta_end"]) for r in rows)
    assert len({round(r["theta_end"], 9) for r in rows}) == 3  # h changes the motion


def test_the_model_battery_runs_it():
    name = f"{NAME}/full"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a toy the battery runs must not need a warning filter
        battery.test_model_is_deterministic_finite_and_well_shaped(name)
        battery.test_models_start_from_the_same_rotation(name)


def test_the_explorer_lists_it_with_its_slider():
    from app.engine import controls

    assert controls.SYSTEM_LABELS["body with a rotor"] == NAME
    assert "rotor.h" in controls.BY_KEY and NAME in controls.BY_KEY["rotor.h"].systems
    sc = physics.Scenario.from_toml(EXAMPLE)
    assert controls.apply_changes(sc, {"rotor.h": 0.5}).rotor == Rotor(0.5)


def test_derived_and_info_report_it():
    sc = physics.Scenario.from_toml(EXAMPLE)
    d = physics.derived(sc)
    assert d["h"] == 0.3 and d["auto_fidelity"] == "full" and d["auto_model"] == f"{NAME}/full"
    # its Python right-hand side is named as the run names it (physics info said "compiled")
    method = physics.simulate(sc.with_values(**{"run.t_end": 0.5})).info["method"]
    assert method == "DOP853 (interpreted, Python right-hand side)"
    assert d["auto_method"] == f"{method}, rtol = {sc.run.rtol:g}"


def test_a_change_keeps_its_momentum_and_its_readouts_work_with_no_hooks_given():
    """The carry, the braking readout and ``physics info`` serve a system that declares none of their hooks (no
    ``parts``, ``start_part``, ``braking_time``, ``quantities``): the defaults, not a missing-hook error."""
    from physics.info_text import COMMON, describe

    sc = physics.Scenario.from_toml(EXAMPLE)
    run = physics.LiveRun(sc)
    run.advance(1.0, samples=2)
    K, t = run.momentum(), run.t
    assert run.retune(sc.with_values(**{"rotor.h": 0.6}))  # True: the state was carried, not restarted
    assert run.t == t and run.scenario.rotor.h == 0.6
    assert np.linalg.norm(run.momentum() - K) <= 1e-12 * np.linalg.norm(K)
    assert run.edit.iterations > 0  # h changed K at the same omega: omega was solved for, not just copied
    assert run.remaining_braking_time() == math.inf
    assert describe("h", NAME) == ("", "")
    assert describe("auto_model", NAME) == COMMON["auto_model"]


# ---- registration is checked: each rule broken by a toy of its own ----------------------------------------------

def _toy_system(name: str, table: str, params=()):
    return physics.System(name=name, label=name, summary="a toy breaking a registration rule",
                          tables=(physics.Table(table, Rotor),), example=EXAMPLE.replace("[rotor]", f"[{table}]"),
                          params=params)


def _toy_model(system: str, fidelity: str = "full"):
    return physics.Model(name=f"{system}/{fidelity}", system=system, fidelity=fidelity, summary="toy",
                         state=("wx", "wy", "wz", "qw", "qx", "qy", "qz"), py_rhs=rhs, pack=pack,
                         initial_state=initial_state, observe=observe, invariants=invariants)


def test_a_system_without_a_full_model_is_not_runnable_and_is_named_until_its_full_model_comes():
    name = "toy_no_full"
    try:
        physics.register_system(_toy_system(name, "wheel0"))
        physics.register_model(_toy_model(name, "averaged"))  # a cheaper model is not enough
        assert name not in physics.SYSTEMS
        with pytest.raises(physics.RegistrationError, match=f"system '{name}' has no full model .registered: averaged"):
            physics.registry.systems()
        with pytest.raises(physics.RegistrationError, match=name):
            physics.Scenario.from_toml(EXAMPLE)  # any use of the registry says so
        physics.register_model(_toy_model(name))  # registered in the other order: now it is complete
        assert physics.registry.systems()[name].fidelities == ("auto", "full", "averaged")
    finally:
        physics.unregister_system(name)
    physics.registry.systems()  # removed: the registry is whole again


def test_a_model_whose_system_never_registers_is_named():
    name = "toy_orphan"
    try:
        physics.register_model(_toy_model(name))
        with pytest.raises(physics.RegistrationError, match=f"model '{name}/full' belongs to the system '{name}', "
                                                            "which is not registered"):
            physics.registry.get_system(NAME)
    finally:
        physics.unregister_system(name)
    assert physics.registry.get_system(NAME).name == NAME


def test_a_param_of_a_table_the_system_does_not_have_is_refused_at_registration():
    stray = physics.Param("mass.m", "m", "kg", "a key of the moving mass's table", 0.0, 1.0, 0.1)
    with pytest.raises(physics.RegistrationError, match=r"system 'toy_stray': Param 'mass.m' names the table \[mass\]"):
        physics.register_system(_toy_system("toy_stray", "wheel1", params=(stray,)))
    assert "toy_stray" not in physics.SYSTEMS and "toy_stray" not in physics.registry._WAITING
    shared = physics.Param("initial.G0", "G0", "kg m^2/s", "a shared table's key", 0.1, 5.0, 0.1)
    own = physics.Param("wheel1.h", "h", "kg m^2/s", "its own table's key", -1.0, 1.0, 0.1)
    try:  # its own table and a shared one are accepted
        physics.register_model(_toy_model("toy_stray"))
        physics.register_system(_toy_system("toy_stray", "wheel1", params=(shared, own)))
        assert "toy_stray" in physics.registry.systems()
    finally:
        physics.unregister_system("toy_stray")


def test_a_borrowed_table_must_belong_to_a_system_registered_before():
    with pytest.raises(physics.RegistrationError, match=r"'toy_borrow' borrows the table \[nowhere\]"):
        physics.register_system(dataclasses.replace(_toy_system("toy_borrow", "wheel2"), borrows=("nowhere",)))
    # the plane pendulums borrow the spherical pendulum's sliders: pendulum.k sets every [[plane_pendulum]]
    assert physics.get_system("plane_pendulums").borrows == ("pendulum",)


def test_a_kernel_id_dispatch_does_not_know_is_refused_at_registration():
    unknown = max(physics.compiled.dispatch.KERNELS) + 1
    model = dataclasses.replace(_toy_model("toy_kernel"), py_rhs=None, kernel=unknown)
    with pytest.raises(physics.RegistrationError, match=f"'toy_kernel/full' of the system 'toy_kernel': kernel id "
                                                        f"{unknown} is not one physics/compiled/dispatch.py knows"):
        physics.register_model(model)
    assert "toy_kernel/full" not in physics.REGISTRY


def test_the_scenarios_view_of_the_tables_follows_registration():
    """The scenario keeps its table maps per registry version: a table registered after a scenario was read is
    known at once, and gone once its system is removed."""
    physics.Scenario.from_toml(EXAMPLE)  # the maps are built
    toml = EXAMPLE.replace("[rotor]", "[wheel4]")
    try:
        physics.register_model(_toy_model("toy_late"))
        physics.register_system(_toy_system("toy_late", "wheel4"))
        assert physics.Scenario.from_toml(toml).system == "toy_late"
    finally:
        physics.unregister_system("toy_late")
    with pytest.raises(physics.ScenarioError, match="wheel4 = .*unknown table"):
        physics.Scenario.from_toml(toml)


def test_auto_without_a_chooser_tries_the_cheaper_models_in_the_system_s_own_order():
    """A system with no chooser of its own: auto takes the first available cheaper model in its ``cheapest_first``
    (not the registry's dearest-first order reversed), the full model when a condition fails or none is available."""
    models = {f: _toy_model("toy_order", f) for f in ("full", "averaged", "closed")}
    holds, free = [Condition("x", 1.0, 2.0)], {"averaged", "closed"}
    system = dataclasses.replace(_toy_system("toy_order", "wheel0"), models=models,
                                 conditions=lambda sc: holds,
                                 available=lambda sc, f: (f in free, "" if f in free else "not here"),
                                 cheapest_first=lambda sc: ("averaged", "closed"))
    assert system.pick(None) == ("averaged", "conditions hold")
    free.discard("averaged")
    assert system.pick(None) == ("closed", "conditions hold")
    free.discard("closed")
    assert system.pick(None) == ("full", "no cheaper model")
    free.update({"averaged", "closed"})
    holds[0] = Condition("x", 3.0, 2.0)
    fid, why = system.pick(None)
    assert fid == "full" and why.startswith("conditions fail: ")
