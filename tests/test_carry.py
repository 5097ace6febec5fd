"""A parameter or fidelity change keeps the inertial angular momentum K, the attitude and the internal
displacement (physics/systems/carry.py through LiveRun.retune; issue 13 point 1)."""

from __future__ import annotations

import numpy as np
import pytest

import physics
from physics.stepping.live import LiveRun
from physics.systems.carry import CannotCarry, carried_layout, carry_state, state_names

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")

K_TOL = 1e-12  # relative: the carry solves K to rounding (Newton, K_RTOL = 1e-14)
RUN_RTOL = 1e-11  # integrator tolerance of the run after the edit
# the averaged moving mass rebuilds its attitude from K's fixed frame (a product of four rotations): the attitude
# it is given comes back to rounding, not bit for bit (every other model keeps it bit for bit)
REBUILT_ATTITUDE_TOL = 4 * np.finfo(float).eps
DRIFT_TOL = 1e-8  # relative drift of K over the short run after the edit, at RUN_RTOL
SETTLE = 1.5  # s run before the edit, so the internal parts are displaced and moving
AFTER = 2.0  # s run after the edit

MASS = {"body": {"A": 1.0, "C": 1.4, "M": 1.0}, "mass": {"m": 0.2, "rho": 1.5, "Omega": 5.0, "chi": 5.0},
        "initial": {"G0": 3.0, "theta0": 0.8, "mass_state": "quasistatic"}}
MASS_REST_ASYM = {"body": {"A": 1.0, "B": 1.2, "C": 1.5, "M": 2.0}, "mass": {"m": 0.2, "rho": 0.8, "Omega": 12.0,
                                                                             "chi": 3.0},
                  "initial": {"omega": [0.6, 0.3, 1.2], "mass_state": "rest"}}
CAVITY = MASS | {"cavity": {"beta": 1000.0, "nu": 1.0, "a0": 0.3}}
MEDIUM = MASS | {"medium": {"lambda": 0.002}}
SPHERICAL = {"body": {"A": 1.0, "C": 1.4, "M": 1.0},
             "pendulum": {"m": 0.05, "l": 0.3, "h": 0.5, "k": 0.5, "c_d": 0.01},
             "initial": {"G0": 2.0, "theta0": 0.3}}
PLANE = {"body": {"A": 1.0, "C": 1.4, "M": 1.0},
         "plane_pendulum": [{"preset": "in_plane", "m": 0.03, "l": 0.2, "k": 0.5, "c_d": 0.01, "R": 0.5,
                             "azimuth": a} for a in (0.0, 2.0943951023931953, 4.1887902047863905)],
         "initial": {"G0": 2.0, "theta0": 0.3}}

# (key, low, high) of the random edits per scene; "mass.m" may also go to 0 and back (removing the mass)
CAVITY_KEYS = [("cavity.beta", 0.0, 1500.0), ("cavity.nu", 0.5, 5.0), ("cavity.a0", 0.1, 0.4),
               ("mass.lam_q", 0.0, 50.0)]
MASS_KEYS = [("mass.m", 0.05, 0.4), ("mass.rho", 0.5, 1.8), ("mass.Omega", 3.0, 20.0), ("mass.chi", 0.0, 10.0),
             ("body.A", 0.8, 1.3), ("body.B", 0.8, 1.3), ("body.C", 1.0, 1.6), ("body.M", 1.0, 3.0)]
PENDULUM_KEYS = [("pendulum.m", 0.01, 0.1), ("pendulum.l", 0.1, 0.4), ("pendulum.k", 0.1, 2.0),
                 ("pendulum.c_d", 0.0, 0.05), ("body.A", 0.8, 1.2), ("body.C", 1.2, 1.6), ("body.M", 0.8, 2.0)]


def scenario(tables: dict, fidelity: str = "full") -> physics.Scenario:
    return physics.Scenario.from_dict(tables | {"run": {"fidelity": fidelity, "t_end": 10.0, "rtol": RUN_RTOL}})


def edit(sc: physics.Scenario, key: str, value: float) -> physics.Scenario:
    """``sc`` with one slider-like change: mass.m = 0 removes the mass, a positive m puts it back."""
    data = sc.to_dict()
    table, _, name = key.partition(".")
    if key == "mass.m" and value == 0:
        data.pop("mass")
    elif key == "cavity.beta" and value < 100.0:  # a slider at 0 removes the cavity
        data.pop("cavity", None)
    elif table == "cavity" and "cavity" not in data:
        data["cavity"] = dict(CAVITY["cavity"]) | {name: value}
    elif table == "mass" and "mass" not in data:
        data["mass"] = dict(MASS["mass"]) | {name: value}
    elif table == "pendulum" and "plane_pendulum" in data:
        for bob in data["plane_pendulum"]:
            bob[name] = value
    else:
        data[table][name] = value
    return physics.Scenario.from_dict(data)


def K_of(run: LiveRun) -> np.ndarray:
    return run.model.invariants(run.y[None, :], run.p)[0][0]


CLOSED_OK = MASS | {"mass": MASS["mass"] | {"Omega": 40.0}}  # eps small enough for the averaged theory


def internal_of(run: LiveRun) -> dict[str, float]:
    y = carried_layout(run.model, run.y, run.p)
    names = state_names(run.model, y.size)
    return {n: v for n, v in zip(names, y, strict=True) if not n.startswith(("w", "q"))}


def mass_coordinates_absent(sc: physics.Scenario) -> set[str]:
    return {"ux", "uy", "uz", "vx", "vy", "vz"} if sc.system == "moving_mass" and sc.mass is None else set()


def check_edit(run: LiveRun, new: physics.Scenario, fidelity: str | None = None) -> None:
    """Retune ``run`` to ``new`` and assert that K (vector), the attitude and every surviving internal
    coordinate are kept, and that the reported energy change is the model's."""
    K0, q0, t0 = K_of(run), run.last.quat[0].copy(), run.t
    E0 = float(run.last.E[0])
    before = internal_of(run)
    was_absent = mass_coordinates_absent(run.scenario)
    assert run.retune(new, fidelity), run.edit_note
    assert run.t == t0
    K1 = K_of(run)
    assert np.linalg.norm(K1 - K0) <= K_TOL * np.linalg.norm(K0), (K0, K1)
    if run.model.chart is None:
        np.testing.assert_array_equal(run.last.quat[0], q0)
    else:
        assert np.max(np.abs(run.last.quat[0] - q0)) <= REBUILT_ATTITUDE_TOL, (run.last.quat[0], q0)
    now_absent = mass_coordinates_absent(new)
    for name, value in internal_of(run).items():
        if name in now_absent:
            assert value == 0.0, name  # a part switched off leaves nothing behind
        elif name in before and name not in was_absent:
            assert value == before[name], name  # a part that stays keeps its displacement and rate
    assert run.energy_change == pytest.approx(float(run.last.E[0]) - E0, rel=1e-12, abs=1e-15)


def check_conserved_after(run: LiveRun) -> None:
    """No torque: K stays what the edit kept while the run goes on."""
    K1 = K_of(run)
    run.advance(AFTER, samples=4)
    assert run.status == "running", run.message
    assert np.linalg.norm(K_of(run) - K1) <= DRIFT_TOL * np.linalg.norm(K1)


def started(tables: dict, fidelity: str = "full") -> LiveRun:
    run = LiveRun(scenario(tables, fidelity))
    run.advance(SETTLE)
    return run


@pytest.mark.parametrize("tables,keys", [(MASS, MASS_KEYS), (MASS_REST_ASYM, MASS_KEYS),
                                         (CAVITY, MASS_KEYS + CAVITY_KEYS), (MEDIUM, MASS_KEYS),
                                         (SPHERICAL, PENDULUM_KEYS + [("pendulum.h", -0.5, 0.8)]),
                                         (PLANE, PENDULUM_KEYS)],
                         ids=["mass", "mass-asymmetric-rest", "mass+cavity", "mass+medium", "spherical", "plane"])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_random_edits_keep_K_attitude_and_displacement(tables, keys, seed):
    rng = np.random.default_rng(seed)
    run = started(tables)
    for _ in range(6):
        key, lo, hi = keys[rng.integers(len(keys))]
        value = float(rng.uniform(lo, hi))
        if key == "body.B" and run.scenario.system != "moving_mass":
            continue
        try:
            sc = edit(run.scenario, key, value)
            physics.get_model(sc.system, "full").pack(sc)
        except physics.ScenarioError:  # an invalid combination (a mass too far out for A): not an edit
            continue
        check_edit(run, sc)
        if run.scenario.medium is None:
            check_conserved_after(run)
        else:
            run.advance(0.2)


def test_mass_off_and_on_keeps_K_and_attitude():
    """The issue's sequence on the default scene: m 0.2 -> 0 -> 0.2 with the state kept."""
    run = started(MASS)
    K0, q0 = K_of(run), run.last.quat[0].copy()
    E0 = float(run.last.E[0])
    off = edit(run.scenario, "mass.m", 0.0)
    check_edit(run, off)
    assert run.scenario.mass is None and np.all(run.y[3:9] == 0.0)
    # without the mass the body is rigid with the frozen moments A, B, C: E = 1/2 K J*^-1 K in body axes
    Kb = run.model.observe(np.array([run.t]), run.y[None, :], run.p, run.scenario).omega[0] * [1.0, 1.0, 1.4]
    assert float(run.last.E[0]) == pytest.approx(0.5 * np.sum(Kb**2 / [1.0, 1.0, 1.4]), rel=1e-12)
    assert run.energy_change != 0.0
    check_conserved_after(run)
    K1 = K_of(run)
    q1 = run.last.quat[0].copy()
    check_edit(run, edit(run.scenario, "mass.m", 0.2))
    assert np.linalg.norm(K_of(run) - K0) <= DRIFT_TOL * np.linalg.norm(K0)  # the same K all along
    assert np.linalg.norm(K_of(run) - K1) <= K_TOL * np.linalg.norm(K1)
    np.testing.assert_array_equal(run.last.quat[0], q1)
    assert not np.array_equal(q1, q0)  # the body moved meanwhile: the attitude kept is the present one
    # the mass comes back quasi-static (the scene's mass_state): displaced, not at its rest point
    assert np.linalg.norm(run.y[3:6]) > 1e-3
    assert abs(float(run.last.E[0]) - E0) > 1e-3  # E is not what is kept; the app reports the change
    check_conserved_after(run)


def test_cavity_off_and_on_keeps_K():
    """The cavity's fluid carries momentum (-kc f(omega), quadratic in omega): K still kept, by Newton."""
    run = started(CAVITY)
    K0 = K_of(run)
    check_edit(run, edit(run.scenario, "cavity.beta", 0.0))
    assert run.scenario.cavity is None and run.edit.iterations >= 1
    check_edit(run, edit(run.scenario, "cavity.beta", 1000.0))
    assert run.scenario.cavity is not None
    assert np.linalg.norm(K_of(run) - K0) <= DRIFT_TOL * np.linalg.norm(K0)
    check_conserved_after(run)


@pytest.mark.parametrize("tables", [MASS, MASS_REST_ASYM, CAVITY], ids=["mass", "mass-asymmetric-rest", "cavity"])
def test_full_to_averaged_and_back_keeps_K_and_attitude(tables):
    run = started(tables)
    check_edit(run, run.scenario, "averaged")
    assert run.fidelity == "averaged" and run.y.size == 8  # (w, psi, K's frame) or its axisymmetric form
    run.advance(0.5)
    check_edit(run, run.scenario, "full")
    assert run.fidelity == "full" and run.y.size == 15
    u = run.y[3:9]
    if run.scenario.initial.mass_state == "rest":
        assert np.all(u == 0.0)
    else:
        from physics.systems.moving_mass.models import quasi_static_displacement

        u_qs, v_qs = quasi_static_displacement(run.scenario, run.y[:3])
        np.testing.assert_allclose(u, np.concatenate([u_qs, v_qs]), atol=1e-9)
    check_conserved_after(run)


def test_from_the_closed_form_keeps_its_K_and_attitude():
    """Closed -> full: the closed form's G is |J* omega|; the full model starts from it."""
    run = LiveRun(scenario(CLOSED_OK, "closed"))
    run.advance(SETTLE)
    G, q = float(run.last.K[0]), run.last.quat[0].copy()
    assert run.retune(run.scenario, "full"), run.edit_note
    assert run.fidelity == "full" and run.t == pytest.approx(SETTLE)
    assert np.linalg.norm(K_of(run)) == pytest.approx(G, rel=K_TOL)
    np.testing.assert_allclose(run.last.quat[0], q / np.linalg.norm(q), rtol=0, atol=1e-15)
    check_conserved_after(run)


def test_to_the_closed_form_it_restarts_at_t_with_K_and_attitude_kept():
    """Full -> closed: the closed form goes on from the present K and attitude (physics/systems/moving_mass/
    closed_restart.py);
    its theta then follows the averaged model carried from the same state, its K stays fixed in space."""
    run = started(CLOSED_OK)
    K0, q0, t0 = run.momentum(), run.last.quat[0].copy(), run.t
    assert run.retune(run.scenario, "closed"), run.edit_note
    assert run.fidelity == "closed" and run.t == t0
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    np.testing.assert_allclose(run.last.quat[0], q0, rtol=0, atol=1e-15)
    averaged = started(CLOSED_OK)
    assert averaged.retune(averaged.scenario, "averaged")
    np.testing.assert_allclose(run.last.omega[0], averaged.last.omega[0], rtol=1e-13)  # A = B: the same omega
    assert run.energy_change == pytest.approx(float(run.last.E[0]) - float(averaged.last.E[0]) + averaged.energy_change,
                                              rel=1e-9)
    for _ in range(3):
        run.advance(1.0)
        averaged.advance(1.0)
        assert run.t == pytest.approx(averaged.t, abs=1e-12)
        assert run.last.theta[0] == pytest.approx(averaged.last.theta[0], abs=1e-9)
        # the closed form's attitude is first order in the mass's coupling (closed_state.py): 2.5e-3 rad measured
        assert 2 * np.arccos(min(1.0, abs(run.last.quat[0] @ averaged.last.quat[0]))) < 1e-2
        assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)


def test_from_the_closed_form_after_a_restart_and_back():
    run = started(CLOSED_OK)
    K0 = run.momentum()
    assert run.retune(run.scenario, "closed")
    run.advance(1.0)
    assert run.retune(edit(run.scenario, "mass.m", 0.1), "closed")  # a slider while closed: restarted again
    assert run.fidelity == "closed" and np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    run.advance(1.0)
    q = run.last.quat[0].copy()
    assert run.retune(run.scenario, "full")
    assert np.linalg.norm(run.momentum() - K0) <= 1e-12 * np.linalg.norm(K0)
    np.testing.assert_allclose(run.last.quat[0], q / np.linalg.norm(q), rtol=0, atol=1e-15)
    check_conserved_after(run)


def test_from_the_pendulum_averaged_solution_its_row_is_carried():
    """Spherical pendulum, averaged (a closed form) -> full: the row's attitude, bob angles and rates go on;
    K is the one the solution shows (its |H(0)|, fixed in space), omega solved for it."""
    run = LiveRun(scenario(SPHERICAL | {"pendulum": SPHERICAL["pendulum"] | {"k": "resonant"}}, "averaged"))
    run.advance(SETTLE)
    row, K0 = run.last, run.momentum()
    assert run.retune(run.scenario, "full"), run.edit_note
    assert run.fidelity == "full" and run.t == pytest.approx(SETTLE)
    np.testing.assert_allclose(run.last.quat[0], row.quat[0], rtol=0, atol=1e-15)
    for name in ("alpha", "beta", "alpha_dot", "beta_dot"):
        assert run.last.internal[name][0] == row.internal[name][0], name
    assert abs(row.internal["alpha"][0]) > 0.1  # at resonance the bob swings: there is something to carry
    # the K the solution shows is kept (omega solved for it), not the full model's K at its row (0.3 % off)
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    assert np.linalg.norm(K0) == pytest.approx(float(row.K[0]), rel=K_TOL)
    check_conserved_after(run)


def test_to_the_pendulum_averaged_solution_it_goes_on_at_t():
    """Full -> averaged: restarted at t with K and the attitude kept (more in tests/test_restart_pendulum.py)."""
    run = started(SPHERICAL)
    K0, t0 = run.momentum(), run.t
    assert run.retune(run.scenario, "averaged"), run.edit_note
    assert run.t == t0 and run.edit_note == "" and run.energy_change is not None
    assert np.linalg.norm(run.momentum() - K0) <= K_TOL * np.linalg.norm(K0)
    with pytest.raises(CannotCarry, match="closed form"):
        carry_state(physics.get_model("moving_mass", "full"), np.zeros(15), run.scenario, np.zeros(15),
                    physics.get_model("moving_mass", "closed"), run.scenario)


def test_a_damping_change_keeps_the_state_bit_for_bit():
    run = started(MASS)
    y = run.y.copy()
    assert run.retune(edit(run.scenario, "mass.chi", 2.0))
    np.testing.assert_array_equal(run.y, y)
    assert run.energy_change == 0.0
