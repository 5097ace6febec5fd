"""The first start on a machine (issue 13 point 9): while the compiled kernels are built in a child process,
the live run steps with their interpreted twins, which must step exactly as the compiled ones do; the switch
to the compiled kernels mid-run keeps the state continuous; the build reports its state."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import physics
from physics.compiled import dispatch, dop853
from physics.kernels import build as kernel_build
from physics.kernels.interpreted import twin
from physics.stepping.live import RUNNING

FRAME = 1 / 60  # what the explorer asks for per frame at 1x
SAMPLES = 8


@pytest.fixture
def pending(monkeypatch):
    """The build pretends to be running: compiled_ready() is False, nothing compiled is called."""
    monkeypatch.setattr(kernel_build._BUILD, "state", kernel_build.PENDING)
    assert not kernel_build.compiled_ready()
    return kernel_build._BUILD


@pytest.fixture
def fresh_build(monkeypatch):
    """A build state of the test's own, so a started child cannot leak into other tests."""
    b = kernel_build._Build()
    monkeypatch.setattr(kernel_build, "_BUILD", b)
    yield b
    if b.proc is not None and b.proc.poll() is None:
        b.proc.kill()
        b.proc.wait(timeout=10)


ROOT = Path(__file__).resolve().parent.parent


def scenario(name: str) -> physics.Scenario:
    """A few systems and fidelities the explorer runs: each a different kernel and state layout; "default RK4"
    and "default midpoint" step the default scene with a fixed-step method."""
    if not name.startswith("default"):
        return physics.Scenario.load(ROOT / "assets" / "scenarios" / f"{name}.toml")
    sc = physics.default_scenario()
    if name == "default":
        return sc
    d = sc.to_dict()
    d["run"].update(method=name.split()[1], dt=0.002)
    return physics.Scenario.from_dict(d)


def run_frames(run: physics.LiveRun, frames: int) -> tuple[np.ndarray, np.ndarray]:
    ts, ys = [], []
    for _ in range(frames):
        tr = run.advance(FRAME, samples=SAMPLES)
        ts.append(tr.t)
        ys.append(np.column_stack([tr.theta, tr.K, tr.E, tr.omega, tr.quat]))
    return np.concatenate(ts), np.concatenate(ys)


def test_the_twin_of_a_kernel_is_its_own_source_run_by_the_interpreter():
    rhs = twin(dispatch.rhs)
    assert not hasattr(rhs, "py_func")  # a plain function: calling it compiles nothing
    run = physics.LiveRun(physics.default_scenario())
    y = run.y + 0.01 * np.random.default_rng(1).standard_normal(run.y.size)
    a, b = np.empty_like(y), np.empty_like(y)
    rhs(run.model.kernel, 0.3, y, run.p, a)
    dispatch.rhs(run.model.kernel, 0.3, y, run.p, b)
    np.testing.assert_allclose(a, b, rtol=1e-13, atol=1e-13 * np.max(np.abs(b)))
    # the integrator's twin calls the twin of the right-hand side, not the dispatcher
    assert twin(dop853.integrate).__globals__["rhs"] is rhs


@pytest.mark.parametrize("name, fidelity", [("default", None), ("braking_cavity_medium", "full"),
                                            ("braking_cavity_medium", "averaged"), ("pendulum_resonant", None),
                                            ("plane_pendulums_three", None), ("default RK4", None),
                                            ("default midpoint", None)])
def test_interpreted_stepping_agrees_with_the_compiled_one(name, fidelity, monkeypatch):
    sc = scenario(name)
    compiled = physics.LiveRun(sc, fidelity)
    t_c, rows_c = run_frames(compiled, 30)
    monkeypatch.setattr(kernel_build._BUILD, "state", kernel_build.PENDING)
    interpreted = physics.LiveRun(sc, fidelity)
    t_i, rows_i = run_frames(interpreted, 30)
    assert interpreted.nsteps == compiled.nsteps > 0  # the same method takes the same steps
    np.testing.assert_array_equal(t_i, t_c)
    scale = np.maximum(1.0, np.max(np.abs(rows_c), axis=0))
    assert np.max(np.abs(rows_i - rows_c) / scale) <= sc.run.rtol  # agree to the integrator's tolerance


def test_a_switch_to_the_compiled_kernels_mid_run_keeps_the_state_continuous(pending, monkeypatch):
    sc = physics.default_scenario()
    mixed = physics.LiveRun(sc)  # starts interpreted (pending)
    t_a, rows_a = run_frames(mixed, 20)
    monkeypatch.setattr(kernel_build._BUILD, "state", kernel_build.READY)  # the build finished
    t_b, rows_b = run_frames(mixed, 20)
    reference = physics.LiveRun(sc)  # compiled from the start
    t_r, rows_r = run_frames(reference, 40)
    np.testing.assert_array_equal(np.concatenate([t_a, t_b]), t_r)
    scale = np.maximum(1.0, np.max(np.abs(rows_r), axis=0))
    assert np.max(np.abs(np.concatenate([rows_a, rows_b]) - rows_r) / scale) <= sc.run.rtol
    assert mixed.nsteps == reference.nsteps and mixed.status == RUNNING


def test_the_method_is_named_as_the_stepper_runs_it(pending, monkeypatch):
    """physics.derived's auto_method and the live run's stepper give one name: interpreted while the build is
    pending (they said "compiled" while the run stepped the twin), compiled once it is ready."""
    sc = physics.default_scenario().with_values(**{"run.fidelity": "full"})
    run = physics.LiveRun(sc)
    assert run.stepper.label == "DOP853 (interpreted twin while the compiled kernels are built)"
    assert physics.derived(sc)["auto_method"] == run.stepper.label + f", rtol = {sc.run.rtol:g}"
    monkeypatch.setattr(kernel_build._BUILD, "state", kernel_build.READY)
    assert run.stepper.label == "DOP853 (compiled)"
    assert physics.derived(sc)["auto_method"] == f"DOP853 (compiled), rtol = {sc.run.rtol:g}"
    assert physics.simulate(sc).info["method"] == run.stepper.label


def test_a_build_runs_in_a_child_and_the_run_steps_meanwhile(fresh_build, tmp_path):
    gate = tmp_path / "gate"
    child = [sys.executable, "-c", f"import pathlib, time\nwhile not pathlib.Path({str(gate)!r}).exists(): "
             "time.sleep(0.02)"]
    st = kernel_build.start(command=child)
    assert st.state == kernel_build.PENDING and not kernel_build.compiled_ready()
    assert kernel_build.start(command=child).state == kernel_build.PENDING  # a second start joins the first
    run = physics.LiveRun(physics.default_scenario())
    run_frames(run, 10)
    assert run.t > 0 and run.nsteps > 0 and kernel_build.status().state == kernel_build.PENDING
    gate.write_text("go")
    assert kernel_build.wait(timeout=600).state == kernel_build.READY
    assert kernel_build.compiled_ready() and kernel_build.status().elapsed > 0
    t_before = run.t
    run_frames(run, 5)
    assert run.t > t_before and run.status == RUNNING


def test_a_failed_build_says_why_and_leaves_the_compiled_path_on(fresh_build):
    st = kernel_build.start(command=[sys.executable, "-c", "raise SystemExit('no compiler here')"])
    assert st.state == kernel_build.PENDING
    st = kernel_build.wait(timeout=120)
    assert st.state == kernel_build.FAILED and "no compiler here" in st.message
    assert kernel_build.compiled_ready()  # compiles on first use, as it did before background builds


PENDING_SESSION = """
import sys
from physics.kernels import build as kernel_build
kernel_build._BUILD.state = kernel_build.PENDING  # as while the child builds
from app.engine.engine import Engine
e = Engine()
for _ in range(30):
    fr = e.tick(1 / 60)
e.request_value("mass.chi", 2.0)  # a slider edit carries the state over (K kept): no compiled call either
for _ in range(30):
    fr = e.tick(1 / 60)
e.readouts()
assert e.run.scenario.mass.chi == 2.0
assert e.run.t > 0 and e.run.status == "running", (e.run.t, e.run.status, e.run.message)
print(e.run.t, e.run.nsteps)
"""


def test_a_session_runs_without_compiling_anything_while_the_build_is_pending(tmp_path):
    """An empty numba cache of its own: a compiled kernel called in this process would write one there."""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "numba"))
    done = subprocess.run([sys.executable, "-c", PENDING_SESSION], cwd=ROOT, env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    t, nsteps = done.stdout.split()
    assert float(t) > 0 and int(nsteps) > 0
    assert not list((tmp_path / "numba").rglob("*.nbi"))  # nothing was compiled (or cached) on the way


def test_inline_mode_starts_no_build(fresh_build, monkeypatch):
    monkeypatch.setenv(kernel_build.MODE_ENV, "inline")
    st = kernel_build.start(command=[sys.executable, "-c", "raise SystemExit(1)"])
    assert st.state == kernel_build.READY and fresh_build.proc is None and kernel_build.compiled_ready()


QUAT_RATE_TOL = 1e-15  # 1/s: a few roundings of products of order one


def test_every_kernel_takes_its_attitude_rate_from_the_one_helper():
    """q' = q (0, w) / 2 is written once (physics/compiled/attitude.py) and agrees with the Hamilton product;
    each compiled right-hand side calls it (its twin with it), none spells the product out again."""
    from physics.compiled import attitude
    from physics.core.rotation import qmul

    rng = np.random.default_rng(3)
    q, w = rng.normal(size=4), rng.normal(size=3)
    y, out = np.concatenate([[9.0], q]), np.zeros(5)
    attitude.quaternion_rate(y, 1, *w, out)
    expected = 0.5 * qmul(q, np.concatenate([[0.0], w]))
    np.testing.assert_allclose(out[1:], expected, rtol=0, atol=QUAT_RATE_TOL)
    assert out[0] == 0.0  # only the quaternion's four entries are written
    compiled = Path(dispatch.__file__).parent
    spelled = [p.name for p in compiled.glob("*.py") if "0.5 * (qw * w1" in p.read_text()]
    assert spelled == ["attitude.py"]
    for name in ("mass_full", "pendulum"):  # the averaged kernels integrate no quaternion: the attitude follows
        assert "quaternion_rate(" in (compiled / f"{name}.py").read_text(), name  # from K (docs/models.md A.3)
