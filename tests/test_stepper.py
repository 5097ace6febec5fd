"""The one stepper (physics/stepping/stepper.py) under simulate and LiveRun, and a model whose right-hand side is
Python (``Model.py_rhs``) stepped by the same integrator source as the compiled kernels (issue 14).

The toy system is the torque-free rigid body, registered in this file only: state w (3) and the attitude
quaternion (4), J w' = J w x w. The moving-mass system with no mass is the same body; its compiled model
carries the mass's (zero) coordinates along, 15 states in all.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import physics
from physics.compiled import mass_full
from physics.core.rotation import nutation_angle, rotate
from physics.stepping.stepper import STIFF, Stepper, spectral_radius, supports
from physics.systems.moving_mass import models as mm

ROOT = Path(__file__).resolve().parents[1]
NAME = "free_body_test"
AGREE = 1e-9  # rad, and relative in |K|: two runs at rtol 1e-12 whose error norms differ (7 against 15 states)
RTOL = 1e-12


@dataclasses.dataclass(frozen=True)
class FreeBody:
    """The table that selects the toy system: a body with no internal part (no keys of its own)."""


def rhs(t, y, p, out):
    J, w, q = p[:3], y[:3], y[3:7]
    out[:3] = np.cross(J * w, w) / J
    out[3] = -0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2])
    out[4] = 0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1])
    out[5] = 0.5 * (q[0] * w[1] + q[3] * w[0] - q[1] * w[2])
    out[6] = 0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0])


def pack(sc):
    return np.array([sc.body.A, sc.body.B, sc.body.C])


def initial_state(sc, p):
    w0, _, _ = physics.initial_G(sc)
    return np.concatenate([w0, [1.0, 0.0, 0.0, 0.0]])


def invariants(Y, p):
    K = Y[:, :3] * p[:3]
    return rotate(Y[:, 3:7], K), 0.5 * np.sum(Y[:, :3] * K, axis=1)


def observe(t, Y, p, sc):
    K = Y[:, :3] * p[:3]
    q = Y[:, 3:7] / np.linalg.norm(Y[:, 3:7], axis=1)[:, None]
    return physics.Trajectory(t=t, theta=nutation_angle(K), K=np.linalg.norm(K, axis=1),
                              E=0.5 * np.sum(Y[:, :3] * K, axis=1), omega=Y[:, :3].copy(), quat=q)


def mirror_rhs(t, y, p, out):
    """The compiled moving-mass kernel called from Python: a Python model with the compiled model's equations."""
    mass_full.rhs(t, y, p, out)


BODY = {"A": 1.0, "B": 1.3, "C": 1.7, "M": 1.0}
INITIAL = {"G0": 2.0, "theta0": 0.5}


def _scenario(t_end=12.0, samples=121, **run):
    return physics.Scenario.from_dict({"body": BODY, "free_body": {}, "initial": INITIAL,
                                       "run": {"t_end": t_end, "samples": samples, "rtol": RTOL, **run}})


def _bare(sc):
    """The same body and initial state, run by the moving-mass system with no mass."""
    return physics.Scenario.from_dict({k: v for k, v in sc.to_dict().items() if k != "free_body"})


@pytest.fixture(scope="module", autouse=True)
def toy():
    physics.register_model(physics.Model(
        name=f"{NAME}/full", system=NAME, fidelity="full", summary="the torque-free rigid body (test toy)",
        state=("wx", "wy", "wz", "qw", "qx", "qy", "qz"), py_rhs=rhs, pack=pack, initial_state=initial_state,
        observe=observe, invariants=invariants))
    physics.register_model(dataclasses.replace(
        mm.FULL, name=f"{NAME}/mirror", system=NAME, fidelity="mirror", kernel=None, py_rhs=mirror_rhs))
    system = physics.register_system(physics.System(
        name=NAME, label="free body (test)", summary="a rigid body with no internal part",
        tables=(physics.Table("free_body", FreeBody),), example="", choose=lambda sc: ("full", "the toy's model")))
    yield system
    physics.unregister_system(NAME)


def test_the_toy_scenario_runs_the_toy_system():
    sc = _scenario()
    assert sc.system == NAME and _bare(sc).system == "moving_mass"


def test_a_python_model_matches_the_compiled_bare_body_through_simulate_and_live_run():
    sc = _scenario()
    ref = physics.simulate(_bare(sc), fidelity="full")
    py = physics.simulate(sc)
    assert py.info["model"] == f"{NAME}/full" and "Python right-hand side" in py.info["method"]
    assert np.ptp(ref.theta) > 1e-2  # it nutates: the comparison is not of a body at rest
    assert np.max(np.abs(py.theta - ref.theta)) < AGREE
    assert np.max(np.abs(py.K - ref.K)) < AGREE * ref.K[0]
    run = physics.LiveRun(sc)
    pieces = [run.advance(0.5, samples=5) for _ in range(24)]
    t = np.concatenate([p.t for p in pieces])
    theta = np.concatenate([p.theta for p in pieces])
    K = np.concatenate([p.K for p in pieces])
    assert run.status == "running" and t[-1] == pytest.approx(12.0, abs=1e-12)
    at = np.searchsorted(t, ref.t[1:] - 1e-9)  # the live rows at simulate's times (both every 0.1 s)
    assert np.max(np.abs(t[at] - ref.t[1:])) < 1e-12
    assert np.max(np.abs(theta[at] - ref.theta[1:])) < AGREE
    assert np.max(np.abs(K[at] - ref.K[1:])) < AGREE * ref.K[0]


def test_the_python_model_conserves_the_inertial_momentum_and_energy():
    sc = _scenario()
    tr = physics.simulate(sc)
    model = physics.get_model(NAME, "full")
    K, E = model.invariants(np.column_stack([tr.omega, tr.quat]), model.pack(sc))
    assert np.max(np.abs(K - K[0])) < 1e-9 * np.linalg.norm(K[0])
    assert np.max(np.abs(E - E[0])) < 1e-9 * E[0]


def test_a_python_rhs_takes_exactly_the_compiled_models_steps():
    """The same equations as a Python function and as the compiled kernel: the same integrator source takes the
    same steps (counts equal) to the same states."""
    sc = _scenario(t_end=5.0, samples=51)
    compiled = physics.simulate(_bare(sc), fidelity="full")
    python = physics.simulate(sc, fidelity="mirror")
    assert python.info["steps"] == compiled.info["steps"] > 10
    assert python.info["nfev"] == compiled.info["nfev"]
    assert np.max(np.abs(python.theta - compiled.theta)) < 1e-13


def test_simulate_and_live_run_take_the_same_steps_through_the_shared_stepper():
    sc = _scenario(t_end=5.0, samples=11)
    whole = physics.simulate(sc)
    run = physics.LiveRun(sc)
    tr = run.advance(5.0, samples=10)  # one call onto simulate's output times
    assert run.nsteps == whole.info["steps"] and run.nfev == whole.info["nfev"]
    assert np.max(np.abs(tr.t - whole.t[1:])) < 1e-12
    assert np.max(np.abs(tr.theta - whole.theta[1:])) < 1e-12
    pieces = physics.LiveRun(sc)
    for _ in range(50):  # the step size carries over: pieces cost about what one call costs
        pieces.advance(0.1)
    assert pieces.nsteps <= 1.5 * whole.info["steps"] + 50  # at most one extra step per piece (its end)


def test_spectral_radius_works_for_a_python_model():
    sc = _scenario()
    mirror = physics.get_model(NAME, "mirror")
    p = mirror.pack(sc)
    y = mirror.initial_state(sc, p)
    python = spectral_radius(Stepper(mirror, sc, y, p=p).rhs, 0.0, y, p)
    bare = _bare(sc)
    full = physics.get_model("moving_mass", "full")
    compiled = spectral_radius(Stepper(full, bare, y, p=p).rhs, 0.0, y, p)
    assert python > 0 and python == pytest.approx(compiled, rel=1e-12)


def test_the_stiffness_check_runs_for_a_python_model_too(monkeypatch):
    import physics.stepping.stepper as stepper_module

    monkeypatch.setattr(stepper_module, "STIFFNESS_CHECK_STEPS", 300)  # a check within a short interpreted run
    calm = _scenario()
    model = physics.get_model(NAME, "full")
    p = model.pack(calm)
    y = model.initial_state(calm, p)
    piece = Stepper(model, calm, y, p=p).step(y, np.array([0.0, 100.0]), 10_000)
    assert piece.checked and piece.status == stepper_module.OK and piece.nsteps >= 300  # checked: not stiff
    # a mass on a stiff spring: the Python mirror of the compiled kernel is found stiff as the kernel is
    stiff = physics.default_scenario().with_values(**{"mass.Omega": 1e4, "mass.chi": 1e4, "run.fidelity": "full"})
    pieces = []
    for model in (physics.get_model(NAME, "mirror"), physics.get_model("moving_mass", "full")):
        p = model.pack(stiff)
        y = model.initial_state(stiff, p)
        pieces.append(Stepper(model, stiff, y, p=p).step(y, np.array([0.0, 0.05]), 10_000))
    python, compiled = pieces
    assert python.status == compiled.status == stepper_module.STIFF and python.ended
    assert python.nsteps == compiled.nsteps >= 300 and python.t_last == compiled.t_last > 0
    assert "too stiff for the explicit integrator" in str(python.fault())


def test_the_midpoint_is_a_method_for_the_full_moving_mass_kernel_only():
    sc = _scenario()
    bare = _bare(sc)
    full = physics.get_model("moving_mass", "full")
    assert supports(full, bare, "midpoint")[0]
    assert not supports(physics.get_model(NAME, "mirror"), sc, "midpoint")[0]  # same equations, not its kernel
    assert not supports(physics.get_model("moving_mass", "averaged"), bare, "midpoint")[0]
    cavity = physics.Scenario.from_dict({**bare.to_dict(), "cavity": {"beta": 1000.0, "nu": 1e-3, "a0": 0.1}})
    assert supports(full, cavity, "midpoint") == (False, "the full moving-mass model without a cavity")
    with pytest.raises(physics.ScenarioError, match="run.method = 'midpoint': covers only the full moving-mass"):
        physics.simulate(_scenario(method="midpoint", dt=0.01))
    stepped = physics.simulate(bare.with_values(**{"run.dt": 0.01}), fidelity="full", method="midpoint")
    assert "midpoint" in stepped.info["method"] and len(stepped.t) == len(bare.run.times())


def test_braking_is_refused_for_a_python_model_naming_control_b():
    model = physics.get_model(NAME, "mirror")  # the mirror packs the moving mass's tables, so it can be asked
    braked = physics.Scenario.from_dict({**_bare(_scenario()).to_dict(), "control": {"b": 0.1}})
    p = model.pack(braked)
    with pytest.raises(physics.ScenarioError, match=r"control.b = 0.1: braking needs the braking law's \|G\|"):
        Stepper(model, braked, model.initial_state(braked, p), p=p)


@pytest.mark.parametrize("toml, edits, named", [
    ("quadratic_friction.toml", {"mass.Omega": 1e4, "mass.rho": 1e-6},
     ("mass.Omega", "mass.chi", "mass.lam_q", "mass.rho", "initial.G0", "initial.theta0")),
    ("pendulum_resonant.toml", {"pendulum.c_d": 1e5}, ("pendulum.k", "pendulum.c_d", "pendulum.m", "pendulum.l")),
    ("wheel_damper.toml", {"wheel.c": 1e5, "wheel.J": 0.005}, ("wheel.c / wheel.J = 2e+07 1/s", "wheel.J")),
], ids=["moving mass", "spherical pendulum", "wheel"])
def test_a_stiff_run_is_refused_in_its_own_system_s_keys(toml, edits, named, monkeypatch):
    """The stiffness refusal's advice is the system's (Model.stiff_advice), naming the keys that set the fast
    rate and the motion: a moving mass whose rho was made tiny is told about rho, not only about Omega and chi
    (it said "lower Omega or chi" for every system, the wheel and the pendulums too). Short enough that the
    note under the slider leaves Undo and Reset in sight (tests/test_app_browser_reject.py)."""
    from physics.stepping import stepper as stepper_module

    monkeypatch.setattr(stepper_module, "STIFFNESS_CHECK_STEPS", 300)  # checked within a short run
    base = physics.Scenario.from_toml((ROOT / "assets" / "scenarios" / toml).read_text())
    sc = base.with_values(**edits, **{"run.fidelity": "full"})
    model = physics.get_model(sc.system, "full").for_scenario(sc)
    p = model.pack(sc)
    y = model.initial_state(sc, p)
    piece = Stepper(model, sc, y, p=p).step(y, np.array([0.0, 1.0]), 10_000)
    assert piece.status == STIFF, (piece.status, piece.t_last)
    message = str(piece.fault())
    assert "too stiff for the explicit integrator" in message, message
    assert toml.startswith("quadratic") or "Omega" not in message, message  # no moving mass's words elsewhere
    for words in named:
        assert words in message, (words, message)


def test_scipy_stops_at_a_right_hand_side_that_is_not_finite_not_at_its_evaluation_budget():
    """A right-hand side that turns NaN past t = 1 s: scipy's RK45 rejects every step with a NaN error norm and
    ended in "Required step size is less than spacing between numbers" at t = 0.975, the last accepted time,
    which names neither the cause nor where it arose (and a NaN step size can pass the minimum-step test: the
    closed forms' solve_ivp looped for good that way, physics/core/guarded.py). The stepper stops at the first
    such value, saying so at its time."""
    calls = []

    def spoiled(t, y, p, out):
        calls.append(t)
        rhs(t, y, p, out)
        if t > 1.0:
            out[0] = np.nan

    physics.register_model(physics.Model(
        name=f"{NAME}/spoiled", system=NAME, fidelity="spoiled", summary="a right side that is NaN past 1 s",
        state=("wx", "wy", "wz", "qw", "qx", "qy", "qz"), py_rhs=spoiled, pack=pack, initial_state=initial_state,
        observe=observe, invariants=invariants))
    with pytest.raises(physics.IntegrationFault) as info:
        physics.simulate(_scenario(t_end=3.0), fidelity="spoiled", method="RK45")
    assert "the right-hand side became non-finite (NaN or infinity)" in str(info.value)
    assert 1.0 < info.value.t <= 3.0 and len(calls) < 1000
