"""Parameter sweeps (issue 8): the grid, the metrics, the executors agree bit for bit, resuming
recomputes nothing, the CLI and the explorer's panel."""

from __future__ import annotations

import csv
import math
import sys
import threading
import time

import numpy as np
import pytest
from watched_runs import watch

import physics
from physics.scenario.arguments import MAX_WORKERS
from physics.studies.metrics import FIT_BAND, decay_time, energy_dissipated, max_displacement

sweep_module = sys.modules["physics.studies.sweep"]  # the name physics.sweep is the function

REL_FIT = 1e-9  # relative error of the decay fit on an exact exponential (rounding only)
ROOT = __import__("pathlib").Path(__file__).resolve().parent.parent
METRICS = tuple(physics.METRICS)


def _short_pendulum() -> physics.Scenario:
    """The resonant spherical pendulum over 12 s: a few milliseconds a run."""
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml")
    return sc.with_values(**{"run.t_end": 12.0, "run.samples": 121})


VARY = {"k": "log:20:60:3", "c_d": "4,12"}  # 6 points, one of them (k = 34.6) near resonance


def _same(a: float, b: float) -> bool:
    """Bit for bit, NaN equal to NaN."""
    return (math.isnan(a) and math.isnan(b)) or a == b


def _rows_equal(t1: physics.SweepTable, t2: physics.SweepTable) -> bool:
    return len(t1.rows) == len(t2.rows) and all(
        all(_same(r1[c], r2[c]) for c in (*t1.keys, *t1.metrics)) and r1["error"] == r2["error"]
        for r1, r2 in zip(t1.rows, t2.rows, strict=True))


# ---- the grid ------------------------------------------------------------------------------------------

def test_axis_values_linear_log_and_lists():
    assert physics.axis_values("10:100:4") == ([10.0, 40.0, 70.0, 100.0], "linear")
    v, how = physics.axis_values("log:1:100:3")
    assert how == "log" and v[0] == 1.0 and v[-1] == 100.0 and v[1] == pytest.approx(10.0, rel=1e-15)
    assert physics.axis_values((0.0, 1.0, 3)) == ([0.0, 0.5, 1.0], "linear")
    assert physics.axis_values(("log", 2.0, 8.0, 3))[0] == pytest.approx([2.0, 4.0, 8.0], rel=1e-15)
    assert physics.axis_values("1,2.5") == ([1.0, 2.5], "list")
    assert physics.axis_values([3, 1]) == ([3.0, 1.0], "list")
    for bad in ("1:2", "log:0:10:3", "1:2:0", "a:b:c", "1:2:2.5", (1.0, 2.0), "log:1:2"):
        with pytest.raises(physics.ScenarioError):
            physics.axis_values(bad)


def test_axis_values_across_the_doubles_are_finite_and_even():
    """linspace's step (hi - lo)/(n - 1) overflows for -1e308:1e308: its points were nan, inf, inf, inf, 1e308."""
    assert physics.axis_values("-1e308:1e308:5") == ([-1e308, -5e307, 0.0, 5e307, 1e308], "linear")
    big = 1.7976931348623157e308
    assert physics.axis_values((-big, big, 3)) == ([-big, 0.0, big], "linear")
    v, _ = physics.axis_values("log:5e-324:1e308:4")
    assert v[0] == 5e-324 and v[-1] == 1e308 and all(0 < a < b for a, b in zip(v[:-1], v[1:], strict=True))


def test_short_names_resolve_per_system_with_clear_errors():
    pend = _short_pendulum()
    assert physics.resolve_key(pend, "k") == "pendulum.k"
    assert physics.resolve_key(pend, "c_d") == "pendulum.c_d"
    assert physics.resolve_key(pend, "m") == "pendulum.m"
    plane = physics.Scenario.load(ROOT / "assets" / "scenarios" / "plane_pendulums_three.toml")
    assert physics.resolve_key(plane, "k") == "plane_pendulum.k"
    mass = physics.Scenario.load(ROOT / "assets" / "scenarios" / "oblate_settling.toml")
    assert physics.resolve_key(mass, "m") == "mass.m"
    assert physics.resolve_key(mass, "lambda") == "medium.lambda"  # a medium the file leaves out may be swept in
    with pytest.raises(physics.ScenarioError, match="k.*not a key of this moving_mass scenario.*allowed: body.A"):
        physics.resolve_key(mass, "k")
    with pytest.raises(physics.ScenarioError, match="not a number"):
        physics.resolve_key(mass, "control.law")
    with pytest.raises(physics.ScenarioError, match="does not have"):
        physics.resolve_key(pend, "mass.chi")


def test_plane_pendulum_key_sets_every_pendulum():
    plane = physics.Scenario.load(ROOT / "assets" / "scenarios" / "plane_pendulums_three.toml")
    sc = physics.point_scenario(plane, {"plane_pendulum.c_d": 3.5})
    assert [p.c_d for p in sc.plane_pendulums] == [3.5, 3.5, 3.5]


# ---- the metrics ---------------------------------------------------------------------------------------

def _trajectory(t, theta, E=None, internal=None, info=None) -> physics.Trajectory:
    n = len(t)
    return physics.Trajectory(t=t, theta=theta, K=np.ones(n), E=np.ones(n) if E is None else E,
                              omega=np.zeros((n, 3)), quat=np.tile([1.0, 0, 0, 0], (n, 1)),
                              internal=internal or {}, info=info or {})


def test_decay_time_recovers_an_exponential_and_signs_growth():
    t = np.linspace(0.0, 100.0, 1001)
    sc = _short_pendulum()
    assert decay_time(_trajectory(t, 0.2 * np.exp(-t / 7.0)), sc) == pytest.approx(7.0, rel=REL_FIT)
    assert decay_time(_trajectory(t, 0.01 * np.exp(t / 40.0)), sc) == pytest.approx(-40.0, rel=REL_FIT)
    # the fit stops at the band: a decay that later stalls does not bend the fit
    theta = np.maximum(0.2 * np.exp(-t / 5.0), 0.2 / FIT_BAND / 2)
    assert decay_time(_trajectory(t, theta), sc) == pytest.approx(5.0, rel=1e-6)
    assert abs(decay_time(_trajectory(t, np.full_like(t, 0.3)), sc)) > 1e12  # s: no decay at all


def test_swing_energy_and_braking_metrics():
    t = np.linspace(0.0, 1.0, 5)
    sc = _short_pendulum()
    alpha = np.array([0.0, 0.1, 0.3, -0.2, 0.0])
    beta = np.array([0.0, 0.2, 0.0, 0.1, 0.0])
    tr = _trajectory(t, np.full(5, 0.1), E=np.array([5.0, 4.0, 3.5, 3.2, 3.0]),
                     internal={"alpha": alpha, "beta": beta})
    expect = max(math.acos(math.cos(a) * math.cos(b)) for a, b in zip(alpha, beta, strict=True))
    assert max_displacement(tr, sc) == pytest.approx(expect, rel=1e-14)
    assert energy_dissipated(tr, sc) == 2.0
    assert math.isnan(physics.METRICS["braking_time"](tr, sc))  # no braking torque


def test_braking_time_is_the_closed_form_time():
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "braking_cavity_medium.toml")
    tr = physics.simulate(sc, fidelity="closed")  # the metric read off a closed-form run gives seed 004's T
    _, G0, _ = physics.initial_G(sc)
    T = physics.closed.braking_time(G0, sc.control.b, sc.medium.lambda_)
    assert physics.METRICS["braking_time"](tr, sc) == pytest.approx(T, rel=1e-6)


# ---- a sweep is the individual runs, whichever executor ------------------------------------------------

def test_small_sweep_equals_individual_simulate_calls():
    base = _short_pendulum()
    table = physics.sweep(base, VARY, list(METRICS), workers=2)
    assert table.keys == ("pendulum.k", "pendulum.c_d") and table.shape == (3, 2) and table.computed == 6
    for row in table.rows:
        sc = base.with_values(**{"pendulum.k": row["pendulum.k"], "pendulum.c_d": row["pendulum.c_d"]})
        tr = physics.simulate(sc)
        assert row["model"] == tr.info["model"] and row["error"] == ""
        for m in METRICS:
            assert _same(row[m], physics.METRICS[m](tr, sc)), (m, row)
    grid = table.grid("decay_time")
    assert np.argmin(grid[:, 0]) == 1  # the tuning near resonance damps fastest, at either damping


def test_dask_local_cluster_equals_local_run():
    pytest.importorskip("distributed")
    base = _short_pendulum()
    local = physics.sweep(base, VARY, list(METRICS), executor="serial")
    on_dask = physics.sweep(base, VARY, list(METRICS), dask="local", workers=2)
    assert on_dask.info["executor"] == "dask" and on_dask.computed == 6
    assert _rows_equal(local, on_dask)


def test_cli_on_an_existing_scheduler_address(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    from bench.sweep import main

    scenario = tmp_path / "pend.toml"
    scenario.write_text(_short_pendulum().to_toml())
    out = tmp_path / "sweep.csv"
    with distributed.LocalCluster(n_workers=1, processes=False, dashboard_address=None) as cluster:
        assert main([str(scenario), "--vary", "c_d=4,12", "--metric", "theta_end", "--out", str(out),
                     "--dask", cluster.scheduler_address, "--no-chart"]) == 0
    assert "2 computed now" in capsys.readouterr().out
    local = physics.sweep(_short_pendulum(), {"c_d": "4,12"}, "theta_end", executor="serial")
    with open(out, newline="") as fh:
        rows = sorted(csv.DictReader(fh), key=lambda r: float(r["pendulum.c_d"]))
    assert [float(r["theta_end"]) for r in rows] == [r["theta_end"] for r in local.rows]


def test_an_unreachable_scheduler_is_refused_naming_it():
    """No scheduler at the address: a ScenarioError naming ``dask`` and the refusal, from the first try (dask's own
    client retried a refused connection for 30 s and then raised a bare OSError "Timed out trying to connect")."""
    pytest.importorskip("distributed")
    with pytest.raises(physics.ScenarioError) as refused:
        physics.sweep(_short_pendulum(), VARY, "theta_end", dask="tcp://127.0.0.1:1")
    assert refused.value.key == "dask" and "cannot be reached" in str(refused.value)
    assert "refused" in str(refused.value) and "Timed out" not in str(refused.value)


@pytest.mark.parametrize("study", ["sweep", "design"])
def test_dask_without_distributed_installed_is_said_with_the_install_command(study, monkeypatch):
    """dask is in the test extra only: on a plain install a sweep raised a bare ModuleNotFoundError."""
    monkeypatch.setitem(sys.modules, "distributed", None)  # what ``import distributed`` meets when it is missing
    with pytest.raises(physics.ScenarioError) as refused:
        if study == "sweep":
            physics.sweep(_short_pendulum(), VARY, "theta_end", dask="local")
        else:
            physics.design(_short_pendulum(), {"pendulum.c_d": (4.0, 16.0)}, dask="local")
    assert refused.value.key == "dask" and "pip install 'dask[distributed]'" in str(refused.value)


@pytest.mark.parametrize("address", ["inproc://x", "ucx://10.0.0.1:8786", "tcp://127.0.0.1:99999", "tcp://127.0.0.1:0",
                                     "tcp://127.0.0.1:-5", "tcp://:8786", "", "x" * 100_000, "foo://1.2.3.4:5"])
def test_an_address_that_is_no_scheduler_address_is_refused_in_words(address):
    """Each of these raised dask's own error (an AssertionError, a TypeError) or waited out its timeout."""
    pytest.importorskip("distributed")
    with pytest.raises(physics.ScenarioError) as refused:
        physics.sweep(_short_pendulum(), VARY, "theta_end", dask=address)
    said = str(refused.value)
    assert refused.value.key == "dask"
    assert "tcp://host:port with a port from 1 to 65535" in said or "cannot be reached" in said
    assert len(said) < 1000 and "Timed out" not in said


@pytest.mark.parametrize("workers", [100_000, 0, -1, True, 2.5])
def test_a_number_of_workers_out_of_range_is_refused_before_any_run(workers, monkeypatch):
    """A pool forks all its processes at its first run: 100000 workers forked over a thousand within 30 s."""
    monkeypatch.setattr("physics.studies.sweep._run_processes", lambda *a, **k: pytest.fail("the sweep started"))
    with pytest.raises(physics.ScenarioError, match=f"workers = {workers}: must be a whole number of processes "
                                                    f"from 1 to {MAX_WORKERS}"):
        physics.sweep(_short_pendulum(), VARY, ["decay_time"], workers=workers)


def test_bad_points_are_rows_not_failures():
    base = physics.Scenario.load(ROOT / "assets" / "scenarios" / "prolate_flat_spin.toml").with_values(
        **{"run.t_end": 50.0, "run.samples": 51})
    table = physics.sweep(base, {"m": [0.15, 2.0]}, "theta_end", executor="serial")
    ok, bad = table.rows
    assert ok["error"] == "" and math.isfinite(ok["theta_end"])
    assert bad["error"].startswith("ScenarioError: mass.m = 2.0") and math.isnan(bad["theta_end"])


# ---- resuming ------------------------------------------------------------------------------------------

def test_interrupted_sweep_resumes_without_recomputing(tmp_path, monkeypatch):
    base = _short_pendulum()
    out = tmp_path / "sweep.csv"
    calls = []
    real = sweep_module.run_point

    def counting(b, keys, values, metrics, stop=None):
        calls.append(tuple(values))
        return real(b, keys, values, metrics, stop)

    monkeypatch.setattr(sweep_module, "run_point", counting)
    stop = threading.Event()

    def interrupt(done, total):
        if done >= 2:
            stop.set()  # as if the run were killed after two points

    first = physics.sweep(base, VARY, "decay_time", out=out, executor="serial", progress=interrupt, stop=stop)
    assert first.stopped and first.computed == 2 and len(calls) == 2
    with open(out, newline="") as fh:
        assert len(list(csv.reader(fh))) == 1 + 2  # header and the two finished points
    done_before = set(calls)

    calls.clear()
    second = physics.sweep(base, VARY, "decay_time", out=out, executor="serial")
    assert second.skipped == 2 and second.computed == 4 and len(calls) == 4
    assert not done_before & set(calls)  # no point ran twice

    calls.clear()
    third = physics.sweep(base, VARY, "decay_time", out=out, executor="serial")
    assert calls == [] and third.computed == 0 and third.skipped == 6
    fresh = physics.sweep(base, VARY, "decay_time", executor="serial")
    assert _rows_equal(third, fresh)  # what came back from the CSV is the same, bit for bit


def test_resume_with_processes_and_a_cut_line(tmp_path):
    base = _short_pendulum()
    out = tmp_path / "sweep.csv"
    full = physics.sweep(base, VARY, ["decay_time", "theta_end"], out=out, workers=2)
    lines = out.read_text().splitlines(keepends=True)
    out.write_text("".join(lines[:-1]) + lines[-1][: len(lines[-1]) // 3])  # a write cut by a crash
    again = physics.sweep(base, VARY, ["decay_time", "theta_end"], out=out, workers=2)
    assert again.computed == 1 and again.skipped == 5
    assert _rows_equal(full, again)
    out.write_text(out.read_text()[:-3])  # cut inside the last column this time
    assert physics.sweep(base, VARY, ["decay_time", "theta_end"], out=out, workers=2).computed == 1
    last = physics.sweep(base, VARY, ["decay_time", "theta_end"], out=out, workers=2)
    assert last.computed == 0 and _rows_equal(full, last)  # the rows after a cut line are read back


def test_csv_of_another_sweep_is_refused(tmp_path):
    out = tmp_path / "sweep.csv"
    physics.sweep(_short_pendulum(), {"c_d": "4,12"}, "theta_end", out=out, executor="serial")
    other = _short_pendulum().with_values(**{"pendulum.h": -0.6})
    with pytest.raises(physics.ScenarioError, match="another scenario"):
        physics.sweep(other, {"c_d": "4,12"}, "theta_end", out=out, executor="serial")
    with pytest.raises(physics.ScenarioError, match="columns"):
        physics.sweep(_short_pendulum(), {"c_d": "4,12"}, "decay_time", out=out, executor="serial")


# ---- the command line ----------------------------------------------------------------------------------

def test_cli_writes_csv_and_heat_map_then_resumes(tmp_path, capsys):
    from bench.sweep import main

    scenario = tmp_path / "pend.toml"
    scenario.write_text(_short_pendulum().to_toml())
    out = tmp_path / "sweep.csv"
    argv = [str(scenario), "--vary", "k=20:60:2", "--vary", "c_d=log:4:12:2", "--metric", "decay_time",
            "--out", str(out), "--workers", "1"]
    assert main(argv) == 0
    text = capsys.readouterr()
    assert "4 computed now, 0 already there" in text.out and "sweep [" in text.err
    assert out.with_suffix(".png").stat().st_size > 1000
    header = out.read_text().splitlines()[0]
    assert header == "pendulum.k,pendulum.c_d,decay_time,error_bound,model,error,scenario"
    assert main(argv) == 0
    assert "0 computed now, 4 already there" in capsys.readouterr().out


@pytest.mark.parametrize("vary, message", [
    ("lambda=1:2:3", "lambda"), ("k=1:2", "LO:HI:N"), ("k", "KEY=SPEC")])
def test_cli_bad_input_is_one_line_and_status_2(tmp_path, capsys, vary, message):
    from bench.__main__ import main as bench_main

    def main(argv):
        return bench_main(["sweep", *argv])  # through `python -m bench sweep`

    scenario = ROOT / "assets" / "scenarios" / "pendulum_resonant.toml"
    assert main([str(scenario), "--vary", vary, "--out", str(tmp_path / "x.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: ") and message in err[0]


def _long_point_scene() -> physics.Scenario:
    """Points of 12-34 s each here: t_end 4e5 s is too long for the averaged model's attitude budget, so auto runs
    the full model."""
    sc = physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml")
    return sc.with_values(**{"run.t_end": 4e5, "run.samples": 201})


@pytest.mark.parametrize("how", [dict(executor="processes", workers=2, start_method="forkserver"),
                                 dict(executor="processes", workers=2, start_method="fork"),
                                 dict(executor="serial")], ids=["forkserver", "fork", "serial"])
def test_a_stopped_sweep_ends_the_runs_in_flight(how):
    """The explorer's sweeps run in forkserver workers (its server has threads); a stopped sweep waited for the
    runs in flight, whose results it does not keep: 78-82 s after Stop on these points. Under fork the first point
    runs in the sweep's own process, and serially every point does: those ignored stop too."""

    stop = threading.Event()
    timer = threading.Timer(2.0, stop.set)
    timer.start()
    start = time.monotonic()
    table = physics.sweep(_long_point_scene(), {"pendulum.k": [20.0, 30.0, 40.0, 50.0]}, "decay_time", stop=stop,
                          **how)
    after_stop = time.monotonic() - start - 2.0
    assert table.stopped and all(r["error"] == "(not run: the sweep was stopped)" for r in table.rows), table.rows
    assert after_stop < 10.0, after_stop  # a point alone takes 12 s or more


def test_a_stopped_sweep_ends_its_runs_on_a_cluster_it_does_not_own(monkeypatch):
    """A sweep on a shared scheduler is stopped after its first point: the long run already going on a worker's
    thread ends at its next look at the sweep's halt (a cancelled future would have run it to its end, ~10 s).
    The point queued behind the short one may start before the stop reaches the scheduler: it is halted too."""
    distributed = pytest.importorskip("distributed")
    from physics.studies import sweep as S

    runs = watch(monkeypatch, S)  # the cluster's workers are threads of this process
    base = _short_pendulum().with_values(**{"run.fidelity": "full"})
    stop = threading.Event()
    short, long = 12.0, 4e5  # a few ms; about 10 s, 40 progress callbacks
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        table = physics.sweep(base, {"run.t_end": f"{short:g},{long:g},{long:g}"}, "theta_end", dask=client,
                              progress=lambda done, total: stop.set(), stop=stop)
        runs.settle()
    outcomes = runs.outcomes
    assert table.computed == 1 and table.rows[0]["run.t_end"] == short
    assert (short, "ended") in outcomes
    halted = [o for t, o in outcomes if t == long]
    assert halted and set(halted) == {"stopped"}, outcomes  # each long run that started ended at the halt
