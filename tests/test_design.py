"""Damper design (issue 26): physics.design finds what a grid finds, in fewer runs; its value is a full run's; any
executor gives the same design; bad input is one message; a stopped design keeps what it found."""

from __future__ import annotations

import csv
import json
import math
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from watched_runs import watch

import physics
from physics.scenario.arguments import MAX_WORKERS
from physics.studies.design import OBJECTIVES, evaluate

ROOT = Path(__file__).resolve().parent.parent
PENDULUM_VARY = {"pendulum.k": (20.0, 80.0), "pendulum.c_d": (1.0, 40.0)}


def _pendulum() -> physics.Scenario:
    return physics.Scenario.load(ROOT / "assets" / "scenarios" / "pendulum_resonant.toml")


def _mass() -> physics.Scenario:
    """A moving-mass damper whose full runs take milliseconds: 400 s, a few e-folding times at the optimum."""
    return physics.Scenario.from_dict({
        "body": {"A": 1.0, "C": 1.4, "M": 1.0}, "mass": {"m": 0.1, "rho": 1.0, "Omega": 2.0, "chi": 1.0},
        "initial": {"G0": 1.0, "theta0": 0.3, "mass_state": "rest"}, "run": {"t_end": 400.0, "samples": 801}})


def _grid_best(sc: physics.Scenario, vary: dict, metric: str = "decay_time") -> float:
    table = physics.sweep(sc.with_values(**{"run.fidelity": "full"}), vary, metric, workers=2)
    values = table.column(metric)
    return float(np.min(np.where(values > 0, values, np.inf)))


def _full_value(result: physics.DesignResult) -> float:
    sc = result.scenario().with_values(**{"run.fidelity": "full"})
    return physics.METRICS[result.objective](physics.simulate(sc), sc)


# ---- what a design finds -------------------------------------------------------------------------------

def test_pendulum_design_beats_a_20_by_20_grid_in_at_most_120_runs():
    result = physics.design(_pendulum(), PENDULUM_VARY, "decay_time", workers=2)
    grid = _grid_best(_pendulum(), {"pendulum.k": "20:80:20", "pendulum.c_d": "log:1:40:20"})
    assert result.evaluations <= 120 and len(result.path) == result.evaluations
    assert 0 < result.value <= grid
    assert result.value == _full_value(result)  # the stated value is what a full run of the optimum gives
    assert result.path[-1].phase == "check" and result.path[-1].model.endswith("/full")
    # auto ran the full model at every start point (the estimate is above the design's accuracy here), so the
    # refinements ran it directly, without auto's cost probe and estimate per run
    assert "refinements ran it directly" in result.method
    # beside the papers' rules: both tunings ran on the full model, and the design does better than either
    refs = result.references
    assert set(refs) == {"resonance (Grobov 1968, eq. 14)", "linear optimum (fastest linear decay)"}
    for values, value in refs.values():
        assert math.isfinite(value) and result.value < value and "pendulum.k" in values
    assert all(20 <= e.values[0] <= 80 and 1 <= e.values[1] <= 40 for e in result.path)


def test_moving_mass_design_of_chi_and_m_at_fixed_omega():
    """The heaviest mass damps fastest, so m ends on its upper bound; chi has an inner optimum (too little
    damping dissipates little, too much locks the mass)."""
    vary = {"mass.chi": (0.5, 100.0), "mass.m": (0.02, 0.2)}
    result = physics.design(_mass(), vary, "decay_time", workers=2)
    grid = _grid_best(_mass(), {"mass.chi": "log:0.5:100:12", "mass.m": "0.02:0.2:12"})
    assert result.evaluations <= 120
    assert result.value <= grid and result.value == _full_value(result)
    assert result.best["mass.m"] == pytest.approx(0.2, rel=1e-3)
    assert 2.0 < result.best["mass.chi"] < 50.0


def test_braking_design_reaches_the_closed_form_time():
    """b against the braking time: the strongest brake wins, and the full model's time there is seed 000's
    T = |K(0)|/b (no medium, the mass at rest: |K|' = -b exactly)."""
    data = physics.Scenario.load(ROOT / "assets" / "scenarios" / "braking_cavity_medium.toml").to_dict()
    for table in ("cavity", "medium"):
        data.pop(table)
    data["initial"]["mass_state"] = "rest"
    data["run"]["t_end"] = 15000.0
    sc = physics.Scenario.from_dict(data)
    result = physics.design(sc, {"control.b": (1e-4, 1e-3)}, "braking_time", executor="serial")
    assert result.best["control.b"] == 1e-3
    _, G0, _ = physics.initial_G(sc)
    assert result.value == pytest.approx(physics.closed.braking_time(G0, 1e-3, 0.0), rel=1e-9)


def test_a_callable_objective_maximised():
    def swing(tr, sc):
        return physics.METRICS["max_displacement"](tr, sc)

    sc = _pendulum().with_values(**{"run.t_end": 12.0, "run.samples": 121})
    result = physics.design(sc, {"pendulum.c_d": (1.0, 40.0)}, swing, maximize=True, executor="serial")
    swings = result.column("objective")[:-1]
    assert result.goal == "max" and result.cheap_value == np.nanmax(swings)
    assert result.best["pendulum.c_d"] < 3.0  # the lightest damping lets the bob swing widest


# ---- the same design on every executor -------------------------------------------------------------------

def _same_design(a: physics.DesignResult, b: physics.DesignResult) -> bool:
    return (a.best == b.best and a.value == b.value and len(a.path) == len(b.path)
            and all(x.values == y.values and x.phase == y.phase and
                    (x.objective == y.objective or (math.isnan(x.objective) and math.isnan(y.objective)))
                    for x, y in zip(a.path, b.path, strict=True)))


def test_serial_processes_and_dask_give_the_same_design():
    pytest.importorskip("distributed")
    sc = _pendulum().with_values(**{"run.t_end": 20.0, "run.samples": 201})
    args = (sc, PENDULUM_VARY, "decay_time")
    serial = physics.design(*args, executor="serial", budget=60, references=False)
    processes = physics.design(*args, workers=2, budget=60, references=False)
    on_dask = physics.design(*args, dask="local", workers=2, budget=60, references=False)
    assert serial.evaluations <= 60
    assert _same_design(serial, processes) and _same_design(serial, on_dask)


# ---- bad input ----------------------------------------------------------------------------------------------

@pytest.mark.parametrize("vary, objective, message", [
    ({"pendulum.k": (80.0, 20.0)}, "decay_time", "these are reversed"),
    ({"pendulum.k": (20.0, 20.0)}, "decay_time", "the range is empty"),
    ({"pendulum.k": "20:nan"}, "decay_time", "finite LO < HI"),
    ({"pendulum.m": (-1.0, 5.0)}, "decay_time", "reaches outside what pendulum.m allows"),
    ({"pendulum.spring": (1.0, 5.0)}, "decay_time", "is not a scenario key"),
    ({"k": (1.0, 5.0)}, "speed", "must be one of decay_time"),
    ({}, "decay_time", "give one to four parameters"),
    ({"k": (1, 2), "c_d": (1, 2), "m": (1, 2), "l": (0.5, 1), "h": (-1, 0)}, "decay_time", "names 5 parameters"),
])
def test_bad_input_is_one_message_naming_it(vary, objective, message):
    with pytest.raises(physics.ScenarioError, match=message) as info:
        physics.design(_pendulum(), vary, objective, executor="serial")
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("kwargs, message", [
    # a pool forks all its processes at its first run: 100000 forked over a thousand in 30 s before this bound
    (dict(workers=100_000), f"workers = 100000: must be a whole number of processes from 1 to {MAX_WORKERS}"),
    (dict(workers=0), "workers = 0: must be a whole number of processes"),
    (dict(workers=2.0), "workers = 2.0: must be a whole number of processes"),
    # once let through to every point, whose runs then all failed on run.accuracy = inf
    (dict(accuracy=math.inf), "accuracy = inf: must be a finite number > 0 rad"),
])
def test_workers_and_accuracy_out_of_range_are_refused_before_any_run(kwargs, message, monkeypatch):
    monkeypatch.setattr("physics.studies.design.evaluate", lambda *a, **k: pytest.fail("a point ran"))
    with pytest.raises(physics.ScenarioError, match=re.escape(message)):
        physics.design(_pendulum(), PENDULUM_VARY, "decay_time", **kwargs)


def test_an_objective_nan_everywhere_is_refused_with_the_reason():
    sc = _pendulum().with_values(**{"run.t_end": 6.0, "run.samples": 61})
    with pytest.raises(physics.ScenarioError, match="is not finite at any point"):
        physics.design(sc, {"pendulum.c_d": (1.0, 40.0)}, lambda tr, sc: math.nan, executor="serial")


def test_a_bad_point_is_a_row_not_a_failure():
    row = evaluate(_pendulum(), ("pendulum.k",), (-5.0,), "decay_time", "auto", None)
    assert math.isnan(row["objective"]) and "pendulum.k" in row["error"]


def test_objectives_are_metrics():
    assert set(OBJECTIVES) <= set(physics.METRICS)


# ---- stopping keeps what was found ---------------------------------------------------------------------------

def test_a_stopped_design_keeps_its_best_point():
    stop = threading.Event()

    def progress(done, budget, e):
        if done >= 30:
            stop.set()

    result = physics.design(_pendulum(), PENDULUM_VARY, "decay_time", executor="serial", progress=progress, stop=stop)
    assert result.stopped and 30 <= result.evaluations < 40
    assert math.isnan(result.value)  # the full model's check did not run
    finite = [e.objective for e in result.path if e.objective > 0]
    assert result.cheap_value == min(finite)


def test_cli_design_prints_units_writes_csv_and_the_optimum(tmp_path):
    out, save = tmp_path / "design.csv", tmp_path / "best.toml"
    scenario = tmp_path / "pend.toml"
    scenario.write_text(_pendulum().with_values(**{"run.t_end": 20.0, "run.samples": 201}).to_toml())
    proc = subprocess.run([sys.executable, "-m", "physics", "design", str(scenario), "--vary", "k=20:80",
                           "--vary", "c_d=1:40", "--budget", "60", "--out", str(out), "--save", str(save),
                           "--workers", "1"], capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert "optimum: pendulum.k = " in proc.stdout and "N m/rad" in proc.stdout and "N m s/rad" in proc.stdout
    assert re.search(r"^design: \d+/60 runs, best decay_time ", proc.stderr, re.M)
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) <= 60 and rows[-1]["phase"] == "check"
    best = physics.Scenario.load(save)
    value = float(rows[-1]["decay_time"])
    assert physics.METRICS["decay_time"](physics.simulate(best, fidelity="full"), best) == value
    assert f"{value:.6g} s (full model" in proc.stdout


@pytest.mark.parametrize("argv, message", [
    (["--vary", "k"], "must be KEY=LO:HI"),
    (["--vary", "k=80:20"], "these are reversed"),
    (["--vary", "k=1:2", "--objective", "speed"], "invalid choice"),
    (["--vary", "k=1:2", "--budget", "3"], "is too small"),
])
def test_cli_bad_input_is_one_line_and_status_2(argv, message):
    proc = subprocess.run([sys.executable, "-m", "physics", "design", "assets/scenarios/pendulum_resonant.toml",
                           *argv], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert proc.returncode == 2 and message in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr


def test_ctrl_c_ends_the_design_with_what_it_found(tmp_path):
    out = tmp_path / "design.csv"
    scenario = tmp_path / "pend.toml"  # runs of about a second: the design is stopped within its start
    scenario.write_text(_pendulum().with_values(**{"run.t_end": 20000.0, "run.samples": 2001}).to_toml())
    proc = subprocess.Popen([sys.executable, "-m", "physics", "design", str(scenario), "--vary", "k=20:80",
                             "--vary", "c_d=1:40", "--out", str(out), "--workers", "2"], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    line = ""
    while "design: " not in line and time.monotonic() < deadline:
        line = proc.stderr.readline()
    assert "design: " in line, "no progress line"
    os.kill(proc.pid, signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 0, stderr
    assert "stopped: the best point so far follows" in stdout and "Traceback" not in stderr
    with open(out, newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert 1 <= len(rows) < 25 and all(r["phase"] == "start" for r in rows)
    assert "optimum: pendulum.k = " in stdout and "not checked on the full model" in stdout
    # the method says what ran: the start's share, no refinement (it said "from the best 2" before)
    method = next(line for line in stdout.splitlines() if line.startswith("method: "))
    assert f"= 25 points ({len(rows)} ran before the stop), on pendulum.k" in method, method
    assert "Nelder-Mead" not in method and "at every start point" not in method


def test_stop_during_the_first_point_ends_the_design_at_once():
    """The first point runs in the design's own process, before the pool. Its run here takes minutes (t_end about
    4e6 s on the full model): Stop (the Design window's button, a first Ctrl-C) did nothing until it ended. Now the
    run ends at its next progress callback, and with no point to keep the design says so."""
    sc = _pendulum().with_values(**{"run.samples": 201})
    stop, out = threading.Event(), {}

    def run():
        try:
            out["result"] = physics.design(sc, {"run.t_end": (3e6, 3e7)}, "decay_time", fidelity="full", stop=stop,
                                           workers=1, references=False)
        except Exception as exc:  # noqa: BLE001 - what the design raised is the test's subject
            out["error"] = exc

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    time.sleep(1.0)
    stop.set()
    worker.join(30)
    assert not worker.is_alive(), "the design went on after stop for 30 s"
    assert isinstance(out.get("error"), physics.DesignStopped), out
    assert "no run had ended when it was stopped" in str(out["error"])


def _stat(pid: int) -> tuple[str, int] | None:
    """(state, parent) of a live process from /proc (procps may not be installed); None once it has ended or is a
    zombie."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return None if fields[0] == "Z" else (fields[0], int(fields[1]))


def _children(pid: int) -> list[int]:
    """The live processes whose parent is pid."""
    return [int(p.name) for p in Path("/proc").glob("[0-9]*") if (_stat(int(p.name)) or ("", 0))[1] == pid]


def _gone(pids: list[int], within_s: float) -> bool:
    deadline = time.monotonic() + within_s
    while time.monotonic() < deadline:
        if all(_stat(p) is None for p in pids):
            return True
        time.sleep(0.1)
    return False


def _long_design(tmp_path) -> subprocess.Popen:
    """A design whose first point (run here) takes seconds and whose next points, in the two workers, a minute or
    more each (the run's own length is what varies), stopped at its first progress line."""
    scenario = tmp_path / "pend.toml"
    scenario.write_text(_pendulum().with_values(**{"run.t_end": 1000.0, "run.samples": 2001}).to_toml())
    proc = subprocess.Popen([sys.executable, "-m", "physics", "design", str(scenario), "--vary", "run.t_end=1000:1e15",
                             "--budget", "13", "--workers", "2"], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    line = ""
    while "design: " not in line and time.monotonic() < deadline:
        line = proc.stderr.readline()
    assert "design: 1/13 runs" in line, line
    deadline = time.monotonic() + 30
    while len(_children(proc.pid)) < 2 and time.monotonic() < deadline:  # the pool starts at its first point
        time.sleep(0.1)
    return proc


@pytest.mark.slow
def test_ctrl_c_ends_the_workers_runs_rather_than_waiting_for_them(tmp_path):
    """The workers' runs in flight take a minute or more; a stopped design keeps none of them, so it ends them
    (it waited for each to finish, and a second Ctrl-C left the workers running)."""
    proc = _long_design(tmp_path)
    workers = _children(proc.pid)
    assert len(workers) >= 2, workers  # the two workers (and a resource tracker, if one started)
    os.kill(proc.pid, signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=20)  # the run in flight alone takes a minute or more
    assert proc.returncode == 0 and "stopped: the best point so far follows" in stdout, stderr
    assert _gone(workers, 10)


@pytest.mark.slow
def test_a_second_ctrl_c_leaves_no_worker_behind(tmp_path):
    """The second Ctrl-C ends the design's process at once, without a word to the pool: its workers, idle or in a
    run, end by themselves (idle ones waited for work forever, holding the terminal's output)."""
    proc = _long_design(tmp_path)
    workers = _children(proc.pid)
    assert len(workers) >= 2, workers
    os.kill(proc.pid, signal.SIGINT)
    time.sleep(0.2)
    os.kill(proc.pid, signal.SIGINT)
    proc.wait(timeout=20)
    assert proc.returncode in (130, -signal.SIGINT)  # interrupted; or, had the first ended it, killed by the second
    assert _gone(workers, 10)
    proc.communicate(timeout=10)  # the output's pipes close: nobody holds them


def _blas_threads(tr, sc) -> float:
    from threadpoolctl import threadpool_info

    return float(max((i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"), default=1))


def test_worker_processes_run_one_blas_thread():
    """Two workers on two cores, each with BLAS's thread per core, made a design's runs 2.3x slower (issue 26)."""
    sc = _pendulum().with_values(**{"run.t_end": 6.0, "run.samples": 61})
    result = physics.design(sc, {"pendulum.c_d": (1.0, 40.0)}, _blas_threads, workers=2, budget=20, references=False)
    in_workers = [e.objective for e in result.path[1:] if e.phase != "check"]  # the first and the check run here
    assert in_workers and set(in_workers) == {1.0}


def test_cli_on_an_existing_scheduler_address(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    from physics.cli import main

    sc = _pendulum().with_values(**{"run.t_end": 12.0, "run.samples": 121})
    scenario = tmp_path / "pend.toml"
    scenario.write_text(sc.to_toml())
    with distributed.LocalCluster(n_workers=1, processes=False, dashboard_address=None) as cluster:
        assert main(["design", str(scenario), "--vary", "c_d=1:40", "--budget", "30", "--json",
                     "--dask", cluster.scheduler_address]) == 0
    out = json.loads(capsys.readouterr().out)
    local = physics.design(sc, {"c_d": (1.0, 40.0)}, "decay_time", budget=30, executor="serial")
    assert out["best"] == local.best and out["value"] == local.value and out["evaluations"] == local.evaluations


def test_a_fault_in_a_refinement_reaches_the_caller_not_a_thread_traceback():
    """A progress callback that raises inside a refinement's thread: the design raises it where it was called (the
    explorer shows it), rather than a thread printing a traceback and the design going on without it."""
    def progress(done, budget, e):
        if e.phase.startswith("refine"):
            raise ZeroDivisionError("float division by zero")

    sc = _pendulum().with_values(**{"run.t_end": 6.0, "run.samples": 61})
    with pytest.raises(ZeroDivisionError):
        physics.design(sc, {"pendulum.c_d": (1.0, 40.0)}, "decay_time", executor="serial", progress=progress)


def test_an_unreachable_scheduler_is_one_line_naming_it():
    pytest.importorskip("distributed")
    proc = subprocess.run([sys.executable, "-m", "physics", "design", "assets/scenarios/pendulum_resonant.toml",
                           "--vary", "k=20:80", "--budget", "20", "--dask", "tcp://127.0.0.1:1"],
                          capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert "dask = 'tcp://127.0.0.1:1': cannot be reached" in proc.stderr and "refused" in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def test_the_first_ctrl_c_asks_the_design_to_stop_and_a_second_one_interrupts():
    """The command line's handler raises nothing on the first Ctrl-C (a KeyboardInterrupt raised where the signal
    landed was lost in fork's hooks or escaped the design's handlers); the second is the way out of a long run."""
    from physics.studies.design_cli import _CtrlC

    stop = _CtrlC()
    assert not stop.is_set()
    stop(signal.SIGINT, None)
    assert stop.is_set()
    with pytest.raises(KeyboardInterrupt):
        stop(signal.SIGINT, None)


def test_a_stopped_design_ends_its_runs_on_a_cluster_it_does_not_own(monkeypatch):
    """As a sweep does (tests/test_sweep.py): a design on a shared scheduler, stopped while a long run (~5 s and
    more, 40 progress callbacks) goes on a worker's thread, halts it instead of leaving it to run to its end."""
    distributed = pytest.importorskip("distributed")
    from physics.studies import design as D

    stop = threading.Event()
    # Stop pressed while a long run goes on; the cluster's workers are threads of this process
    runs = watch(monkeypatch, D, on_start=lambda sc: sc.run.t_end > 1e5 and stop.set())
    sc = _pendulum().with_values(**{"run.t_end": 12.0, "run.samples": 121, "run.fidelity": "full"})
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        result = physics.design(sc, {"run.t_end": (12.0, 2e6)}, "theta_end", dask=client, stop=stop, budget=13,
                                references=False)
        runs.settle()
    outcomes = runs.outcomes
    assert result.stopped
    long = [o for t, o in outcomes if t > 1e5]
    assert long and set(long) == {"stopped"}, outcomes


@pytest.mark.parametrize("bounds", [(5e-324, 40.0), (1e-300, 1e300)])
def test_a_range_across_the_doubles_is_searched_on_its_log_scale(bounds):
    """hi/lo overflowed for a lower bound of 5e-324: every point of the coarse start was the upper bound, eight
    runs of one scenario reported as a search of the range."""
    from physics.studies.design import _Scale

    start = [_Scale([bounds]).values([(i + 0.5) / 8])[0] for i in range(8)]
    steps = np.diff(np.log(start))
    assert np.all(steps > 0) and np.allclose(steps, (math.log(bounds[1]) - math.log(bounds[0])) / 8, rtol=1e-9)


def test_a_line_across_the_doubles_stays_finite():
    from physics.studies.design import _Scale

    values = [_Scale([(-1e308, 1e308)]).values([x])[0] for x in (0.0, 0.25, 0.5, 1.0)]
    assert values == [-1e308, -5e307, 0.0, 1e308]


def test_a_design_from_the_smallest_double_runs_eight_different_points():
    sc = _pendulum().with_values(**{"run.t_end": 6.0, "run.samples": 61})
    result = physics.design(sc, {"pendulum.c_d": (5e-324, 40.0)}, lambda tr, s: s.pendulum.c_d, executor="serial",
                            budget=13, references=False)
    start = sorted(e.values[0] for e in result.path if e.phase == "start")
    assert len(set(start)) == 8 and start[0] < 1e-300 and start[-1] > 1e-20  # 10^(-323.3 + 325.2 (i + 0.5)/8)
