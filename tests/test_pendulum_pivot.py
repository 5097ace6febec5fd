"""``pendulum.pivot`` (issue 17, "A fault that should not be one"): the spherical pendulum's spring and damper on
the Cardan angles ("cardan", the paper's model, docs/models.md B.1) or on the arm's direction ("isotropic",
V = k (1 - e.e3), R = c_d |e'|^2/2). The isotropic pivot goes on through the gimbal pole with a spring, where
the Cardan one stops with a fault that names the key; at small amplitude the two agree to third order."""

from __future__ import annotations

import dataclasses
import math
import subprocess
import sys

import numpy as np
import pytest

import physics
from physics import IntegrationFault, LiveRun, Scenario, ScenarioError
from physics.compiled import pendulum as kernel
from physics.stepping.live import FAULT, RUNNING

INVARIANT_TOL = 1e-9  # relative drift of the inertial K and of E + W (tests/test_pendulum_full.py's)
RHS_TOL = 1e-12  # relative: the same equations written twice (tests/test_speed_numpy_rhs.py's)
T_END = 30.0


def pole(pivot: str, *, rtol: float | None = None, samples: int = 3001) -> Scenario:
    """The spherical example (system.py's SPHERICAL_EXAMPLE) with a badly tuned spring, 1/13 of the resonant one
    (k = 0.001, c_d = 0.001): the bob falls over, swings past 90 deg from its rest direction, through the
    Cardan angles' pole (the Cardan pivot stops there at t = 1.8 s), then whirls at a large angle."""
    run = {"fidelity": "full", "t_end": T_END, "samples": samples} | ({"rtol": rtol} if rtol else {})
    return Scenario.from_dict({"body": {"A": 1.0, "C": 1.4, "M": 1.0},
                               "pendulum": {"m": 0.05, "l": 0.3, "h": 0.5, "k": 0.001, "c_d": 0.001, "pivot": pivot},
                               "initial": {"G0": 2.0, "theta0": 0.3}, "run": run})


def small(pivot: str, theta0: float) -> Scenario:
    """The spherical example (resonant spring, c_d = 0.01) at a small nutation angle."""
    return Scenario.from_dict({"body": {"A": 1.0, "C": 1.4, "M": 1.0},
                               "pendulum": {"m": 0.05, "l": 0.3, "h": 0.5, "k": "resonant", "c_d": 0.01,
                                            "pivot": pivot},
                               "initial": {"G0": 2.0, "theta0": theta0},
                               "run": {"fidelity": "full", "t_end": T_END, "samples": 601, "rtol": 1e-12}})


def states(tr) -> np.ndarray:
    return np.hstack([tr.omega] + [tr.internal[k][:, None] for k in ("alpha", "beta", "alpha_dot", "beta_dot")]
                     + [tr.quat, tr.internal["W_diss"][:, None], tr.internal["chart"][:, None]])


def arm_z(tr) -> np.ndarray:
    """e.e3 = cos a cos b, the same in both charts."""
    return np.cos(tr.internal["alpha"]) * np.cos(tr.internal["beta"])


# ---- through the pole ---------------------------------------------------------------------------------------

def test_isotropic_pivot_goes_through_the_pole_with_a_spring_and_keeps_the_invariants():
    sc = pole("isotropic")
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    assert p[kernel.HEADER + 2] > 0 and p[kernel.HEADER + 3] > 0 and p[kernel.HEADER + kernel.PIVOT] == 1
    tr = physics.simulate(sc)
    assert tr.t[-1] == T_END and tr.info["stop_reason"] == "reached t_end"
    chart = tr.internal["chart"]
    assert int(np.sum(chart[1:] != chart[:-1])) >= 2 and set(np.unique(chart)) == {0.0, 1.0}
    over = np.arccos(np.clip(arm_z(tr), -1.0, 1.0)) > math.pi / 2  # the bob beyond the pole's great circle
    assert int(np.sum(over[1:] & ~over[:-1])) >= 2  # it swings past the pole more than once
    assert np.max(np.abs(np.sin(tr.internal["beta"]))) < 1.0 - 1e-3  # neither chart comes near its own pole
    K, E = model.invariants(states(tr), p)
    W = tr.internal["W_diss"]
    assert np.max(np.linalg.norm(K - K[0], axis=1)) <= INVARIANT_TOL * np.linalg.norm(K[0])  # size and direction
    assert np.max(np.abs(E[0] - E - W)) <= INVARIANT_TOL * E[0]
    assert W[-1] > 1e-3 * E[0]  # the damper really worked
    # the spring's energy is part of E: k (1 - e_z) of the isotropic pivot, not k (a^2 + b^2)/2
    U = p[kernel.HEADER + 2] * (1.0 - arm_z(tr))
    y = states(tr)[np.argmin(arm_z(tr))]
    zero_k = p.copy()
    zero_k[kernel.HEADER + 2] = 0.0
    assert kernel.energy(y, p) - kernel.energy(y, zero_k) == pytest.approx(U.max(), rel=1e-9)


def test_cardan_pivot_stops_at_the_pole_and_names_the_key():
    with pytest.raises(IntegrationFault, match=r"gimbal singularity") as info:
        physics.simulate(pole("cardan"))
    assert 'pendulum.pivot = "isotropic"' in str(info.value) and 1.0 < info.value.t < T_END
    run = LiveRun(pole("cardan", samples=31))
    for _ in range(60):
        run.advance(1.0, samples=4)
        if run.ended:
            break
    assert run.status == FAULT and 'pendulum.pivot = "isotropic"' in run.message


def test_the_cli_run_goes_through_the_pole_and_the_cardan_fault_says_what_to_set(tmp_path):
    iso = tmp_path / "iso.toml"
    iso.write_text(pole("isotropic", samples=301).to_toml())
    out = tmp_path / "out.csv"
    done = subprocess.run([sys.executable, "-m", "physics", "run", str(iso), "--out", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    header = out.read_text().splitlines()[0]
    assert "chart" in header
    cardan = tmp_path / "cardan.toml"
    cardan.write_text(pole("cardan", samples=301).to_toml())
    done = subprocess.run([sys.executable, "-m", "physics", "run", str(cardan), "--out", str(tmp_path / "c.csv")],
                          capture_output=True, text=True, timeout=300)
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 1 and len(lines) == 1 and 'pendulum.pivot = "isotropic"' in lines[0], done.stderr


# ---- agreement and convergence -------------------------------------------------------------------------------

def test_small_swings_agree_with_the_cardan_pivot_to_third_order():
    diffs = []
    for theta0 in (0.01, 0.02):
        iso, card = physics.simulate(small("isotropic", theta0)), physics.simulate(small("cardan", theta0))
        assert np.max(np.abs(card.internal["alpha"])) > 2 * theta0  # the pendulum really swings
        assert np.all(card.internal["chart"] == 0) and np.all(iso.internal["chart"] == 0)
        diffs.append(np.max(np.abs(iso.theta - card.theta)))
    order = math.log2(diffs[1] / diffs[0])
    assert diffs[0] > 0 and order > 2.5, (diffs, order)


def test_the_isotropic_run_through_the_pole_converges_with_rtol():
    ref, coarse, fine = (physics.simulate(pole("isotropic", rtol=r, samples=61)) for r in (1e-12, 1e-8, 1e-10))
    assert int(np.sum(np.diff(ref.internal["chart"]) != 0)) >= 2
    err_coarse = np.max(np.abs(coarse.theta - ref.theta))
    err_fine = np.max(np.abs(fine.theta - ref.theta))
    assert err_fine <= 1e-9 and err_fine * 10 <= err_coarse  # 100x tighter rtol: at least 10x closer
    # the arm direction (chart-free) agrees too, whatever chart each run was in at a sample
    assert np.max(np.abs(arm_z(fine) - arm_z(ref))) <= 1e-8


# ---- the kernel's equations -----------------------------------------------------------------------------------

def _random_states(sc: Scenario, chart: int, n: int = 4) -> tuple[np.ndarray, list[np.ndarray]]:
    model = physics.get_model(sc.system, "full")
    p = model.pack(sc)
    rng = np.random.default_rng(17 + chart)
    ys = []
    for _ in range(n):
        y = model.initial_state(sc, p)
        y[:kernel.CHART] += 0.6 * rng.standard_normal(kernel.CHART)
        y[7:11] /= np.linalg.norm(y[7:11])
        y[kernel.CHART] = chart
        ys.append(y)
    return p, ys


@pytest.mark.parametrize("chart", [0, 1])
def test_the_spring_and_damper_forces_are_those_of_the_energy_and_the_dissipation(chart):
    """Along the flow, dE/dt = -W' in both charts: the isotropic forces are -grad U and the damper's power is
    what W_diss integrates (a wrong sign or chart would break it at first order)."""
    sc = pole("isotropic")
    p, ys = _random_states(sc, chart)
    assert p[kernel.HEADER + 2] > 0
    p = p.copy()
    p[kernel.HEADER + 2] = 0.5  # a spring as strong as the motion: its force must balance its energy
    for y in ys:
        f = np.empty_like(y)
        kernel.rhs(0.0, y, p, f)
        h = 1e-6
        dE = (kernel.energy(y + h * f, p) - kernel.energy(y - h * f, p)) / (2 * h)
        assert f[11] > 0 and dE == pytest.approx(-f[11], rel=1e-7, abs=1e-9 * kernel.energy(y, p))


def test_the_numpy_reference_and_the_interpreted_twin_match_the_kernel():
    from physics.kernels.interpreted import twin
    from physics.reference.numpy_rhs import spherical_pendulum_rhs

    for pivot in ("isotropic", "cardan"):
        p, ys = _random_states(pole(pivot), 0)
        assert p[19] == (pivot == "isotropic")
        for y in ys:
            compiled = np.empty_like(y)
            kernel.rhs(0.0, y, p, compiled)
            reference = spherical_pendulum_rhs(p)(0.0, y)
            assert np.max(np.abs(reference - compiled)) <= RHS_TOL * np.max(np.abs(compiled))
            interpreted = np.empty_like(y)
            twin(kernel.rhs)(0.0, y, p, interpreted)
            assert np.max(np.abs(interpreted - compiled)) <= RHS_TOL * np.max(np.abs(compiled))
    # the two pivots differ where the angles are large: the test above compares different equations
    p_iso, ys = _random_states(pole("isotropic"), 0)
    p_card = p_iso.copy()
    p_card[kernel.HEADER + kernel.PIVOT] = kernel.CARDAN
    a, b = np.empty_like(ys[0]), np.empty_like(ys[0])
    kernel.rhs(0.0, ys[0], p_iso, a)
    kernel.rhs(0.0, ys[0], p_card, b)
    assert np.max(np.abs(a - b)) > 1e-6 * np.max(np.abs(b))


def test_the_fault_fires_only_for_the_cardan_pivot_with_a_spring():
    for pivot, k, fires in (("cardan", 1e-4, 1), ("isotropic", 1e-4, 0), ("cardan", 0.0, 0)):
        d = pole(pivot).to_dict()
        d["pendulum"]["k"] = k
        sc = Scenario.from_dict(d)
        p = physics.get_model(sc.system, "full").pack(sc)
        y = physics.get_model(sc.system, "full").initial_state(sc, p)
        y[4] = math.pi / 2 - 1e-4  # at the pole of chart 0
        assert kernel.fault(y, p) == fires
        z = y.copy()
        assert kernel.switch_chart(z, p) == 1 - fires and z[kernel.CHART] == 1 - fires


# ---- the key --------------------------------------------------------------------------------------------------

def test_pivot_round_trips_through_toml_and_defaults_to_cardan(tmp_path):
    sc = pole("isotropic")
    path = tmp_path / "s.toml"
    path.write_text(sc.to_toml())
    assert 'pivot = "isotropic"' in path.read_text()
    assert Scenario.load(path).pendulum.pivot == "isotropic" and Scenario.load(path) == sc
    assert Scenario.from_dict(sc.to_dict()) == sc
    d = sc.to_dict()
    del d["pendulum"]["pivot"]
    plain = Scenario.from_dict(d)
    assert plain.pendulum.pivot == "cardan" and physics.get_model(plain.system, "full").pack(plain)[19] == 0


@pytest.mark.parametrize("value", ["gimbal", 1, "Isotropic", ["isotropic"]])
def test_a_bad_pivot_names_the_key_its_value_and_the_choices(value):
    d = pole("isotropic").to_dict()
    d["pendulum"]["pivot"] = value
    with pytest.raises(ScenarioError) as err:
        Scenario.from_dict(d)
    assert err.value.key == "pendulum.pivot" and err.value.value == value
    assert '"cardan"' in str(err.value) and '"isotropic"' in str(err.value)


def test_plane_pendulums_have_no_pivot_key():
    d = {"body": {"A": 1.0, "C": 1.4, "M": 1.0}, "initial": {"G0": 2.0, "theta0": 0.3}, "run": {"t_end": 1.0},
         "plane_pendulum": [{"m": 0.03, "l": 0.2, "k": 0.5, "preset": "in_plane", "R": 0.5, "pivot": "isotropic"}]}
    with pytest.raises(ScenarioError, match=r"plane_pendulum\[0\]\.pivot .*unknown key"):
        Scenario.from_dict(d)


def test_cli_info_refuses_a_bad_pivot_with_one_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(pole("isotropic").to_toml().replace('pivot = "isotropic"', 'pivot = "gimbal"'))
    done = subprocess.run([sys.executable, "-m", "physics", "info", str(path)], capture_output=True, text=True,
                          timeout=120)
    lines = (done.stdout + done.stderr).strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1, done.stdout + done.stderr
    assert "pendulum.pivot" in lines[0] and "'gimbal'" in lines[0] and '"isotropic"' in lines[0]


def test_the_app_loads_an_uploaded_isotropic_scene_and_runs_it_past_the_pole():
    from app.engine.engine import Engine
    from app.engine.upload import parse_upload

    sc = parse_upload("pivot.toml", pole("isotropic", samples=31).to_toml().encode())
    assert sc.pendulum.pivot == "isotropic"
    eng = Engine(sc)
    eng.request_value("pendulum.c_d", 0.002)  # a slider edit rebuilds the scenario from its dict
    eng.warp = 10.0
    for _ in range(400):
        fr = eng.tick(0.1)
        if fr.status != RUNNING or fr.t >= T_END:
            break
    assert not eng.error and eng.scenario.pendulum.pivot == "isotropic" and eng.scenario.pendulum.c_d == 0.002
    assert fr.status == RUNNING and not fr.message and fr.t >= T_END


# ---- a spring switched on while the bob is in chart 1 ----------------------------------------------------------

def _arm(y) -> np.ndarray:
    """The arm direction e of a state, from its chart's angles (the formulas of physics/compiled/pendulum.py)."""
    a, b = y[3], y[4]
    if y[kernel.CHART] < 0.5:
        return np.array([math.sin(b), -math.sin(a) * math.cos(b), math.cos(a) * math.cos(b)])
    return np.array([math.sin(a) * math.cos(b), -math.sin(b), math.cos(a) * math.cos(b)])


def _in_chart_0(y) -> np.ndarray:
    """``y`` with the bob's angles and rates written in chart 0 (the gimbal angles), from e and e' (central
    differences of e along the state's own angles), independently of the kernel's ``to_chart``."""
    z = y.copy()
    e = _arm(y)
    d = 1e-6
    de = sum(((_arm(_shift(y, i, d)) - _arm(_shift(y, i, -d))) / (2 * d)) * y[i + 2] for i in (3, 4))
    b, a = math.asin(e[0]), math.atan2(-e[1], e[2])
    ea = np.array([0.0, -math.cos(a) * math.cos(b), -math.sin(a) * math.cos(b)])
    eb = np.array([math.cos(b), math.sin(a) * math.sin(b), -math.cos(a) * math.sin(b)])
    z[3], z[4] = a, b
    z[5], z[6] = de @ ea / (math.cos(b) ** 2), de @ eb
    z[kernel.CHART] = 0.0
    return z


def _shift(y, i, d):
    z = y.copy()
    z[i] += d
    return z


def test_a_spring_switched_on_in_chart_1_acts_on_the_gimbal_angles():
    """The app's k slider raised from 0 while the bob is past 60 deg (chart 1): the Cardan spring must act on the
    gimbal angles, so the run goes on as one from the same state written in them. Before the fix the kernel kept
    chart 1's angles under the spring and the arm direction 0.5 s on was 0.20 off."""
    free = pole("cardan").replace(pendulum=dataclasses.replace(pole("cardan").pendulum, k=0.0))
    runs = [LiveRun(free), LiveRun(free)]
    for run in runs:
        while run.y[kernel.CHART] < 0.5:
            run.advance(0.01)
    carried, written = runs
    assert abs(_arm(carried.y)[0]) > math.sin(math.pi / 3)  # past 60 deg: the state is in chart 1
    written.y = _in_chart_0(written.y)
    assert np.max(np.abs(_arm(written.y) - _arm(carried.y))) < 1e-12
    for run in runs:
        run.retune(pole("cardan"), keep_state=True)
        run.advance(0.5)
    assert carried.status == RUNNING and carried.y[kernel.CHART] == 0.0
    assert np.max(np.abs(_arm(carried.y) - _arm(written.y))) < 1e-6  # the two rates' 1e-10 differences, grown
    assert np.allclose(carried.y[:3], written.y[:3], rtol=0, atol=1e-6)


def test_a_spring_switched_on_at_the_gimbal_pole_stops_at_once_naming_the_key():
    free = pole("cardan").replace(pendulum=dataclasses.replace(pole("cardan").pendulum, k=0.0))
    run = LiveRun(free)
    while run.y[kernel.CHART] < 0.5:
        run.advance(0.01)
    y = run.y.copy()
    y[3], y[4] = math.pi / 2, 0.0  # chart 1: e = e1, chart 0's pole
    run.y = y
    run.retune(pole("cardan"), keep_state=True)
    t = run.t
    run.advance(0.1)
    assert run.status == FAULT and 'pendulum.pivot = "isotropic"' in run.message and run.t == t
