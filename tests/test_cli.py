"""The command line, run as a user runs it: a subprocess."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import physics

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = sorted((ROOT / "assets" / "scenarios").glob("*.toml"))
INFO_NAMES = ("F", "D", "L", "H", "P", "Gamma1", "Gamma2", "k_star", "T", "eps", "Re", "auto_fidelity", "auto_reason")


def _cli(*args, cwd=ROOT):
    return subprocess.run([sys.executable, "-m", "physics", *args], capture_output=True, text=True, cwd=cwd,
                          timeout=300)


def test_run_default_writes_full_precision_csv(tmp_path):
    out = tmp_path / "traj.csv"
    res = _cli("run", "--out", str(out))
    assert res.returncode == 0, res.stderr
    header = out.read_text().splitlines()[0].split(",")
    assert header[:11] == ["t", "theta", "K", "E", "wx", "wy", "wz", "qw", "qx", "qy", "qz"]
    assert header[11:14] == ["ux", "uy", "uz"]
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    tr = physics.simulate(physics.default_scenario())
    assert np.array_equal(data, tr.table())  # 17 digits: nothing lost


def test_info_prints_every_derived_quantity():
    # the text is for people (units, meaning, 6 digits); --json carries the full precision (issue 17)
    res = _cli("info", "--json", str(ROOT / "assets/scenarios/braking_cavity_medium.toml"))
    assert res.returncode == 0, res.stderr
    values = {k: v["value"] for k, v in json.loads(res.stdout).items()}
    assert all(name in values for name in INFO_NAMES)
    sc = physics.Scenario.load(ROOT / "assets/scenarios/braking_cavity_medium.toml")
    assert float(values["T"]) == physics.derived(sc)["T"]  # round-trips through 17 digits


def test_info_text_gives_units_meanings_and_readable_digits():
    res = _cli("info", str(ROOT / "assets/scenarios/braking_cavity_medium.toml"))
    assert res.returncode == 0, res.stderr
    lines = {line.split(" = ", 1)[0].strip(): line.split(" = ", 1)[1] for line in res.stdout.splitlines()}
    assert all(name in lines for name in INFO_NAMES)
    T = physics.derived(physics.Scenario.load(ROOT / "assets/scenarios/braking_cavity_medium.toml"))["T"]
    value, unit, *meaning = lines["T"].split()
    assert value == f"{T:.6g}" and unit == "s" and "braking time" in " ".join(meaning)
    assert lines["F"].split()[1] == "s^2/(kg" and "D < 0" in lines["D"]
    assert max(len(v.split()[0]) for k, v in lines.items() if not k.startswith("auto")) <= 12  # no 17-digit floats


@pytest.mark.parametrize("args,needle", [
    (("run", "missing.toml"), "scenario = 'missing.toml': cannot be read (No such file or directory)"),
    (("run", "--fidelity", "fast"), "--fidelity"),
    (("info", "--bogus"), "--bogus"),
    (("frobnicate",), "frobnicate"),
    ((), "required"),
])
def test_bad_arguments_exit_2_with_one_line(args, needle):
    res = _cli(*args)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0] and "Traceback" not in res.stderr


@pytest.mark.parametrize("command, option, value, needle", [
    ("run", "--out", "{tmp}", "is a folder"),
    ("run", "--out", "{tmp}/no/such/folder/run.csv", "does not exist"),
    ("run", "--out", "", "names no file"),
    ("design", "--out", "{tmp}", "is a folder"),
    ("design", "--save", "{tmp}/none/best.toml", "does not exist"),
])
def test_a_file_that_cannot_be_written_is_refused_before_the_run(tmp_path, command, option, value, needle):
    """Before: a run (or a design) went to its end, then was lost to --out / (Is a directory)."""
    value = value.format(tmp=tmp_path)
    extra = ["--vary", "mass.Omega=1:3", "--budget", "13"] if command == "design" else []
    res = _cli(command, str(ROOT / "assets/scenarios/oblate_settling.toml"), *extra, option, value)
    assert res.returncode == 2 and res.stdout == ""  # nothing ran: not even the run's first line
    (line,) = res.stderr.strip().splitlines()
    assert line.startswith(f"error: {option} = {value[:60]!r}"[:-1])  # names the option and the value (a long one cut)
    assert needle in res.stderr and "Traceback" not in res.stderr and list(tmp_path.iterdir()) == []


def test_bad_scenario_file_exit_2_names_the_key(tmp_path):
    f = tmp_path / "bad.toml"
    f.write_text("[body]\nA = 1\nC = 1\nM = 1\n[mass]\nm = 2\nrho = 1\nOmega = 1\n[initial]\nG0 = 1\ntheta0 = 0.1\n"
                 "[run]\nt_end = 1\n")
    res = _cli("run", str(f))
    assert res.returncode == 2
    assert res.stderr.strip() == "error: mass.m = 2.0: must be less than body.M = 1 (M is the total mass)"


def test_validity_warning_is_printed_not_fatal(tmp_path):
    f = tmp_path / "wide.toml"
    f.write_text("[body]\nA = 1\nC = 1.4\nM = 1\n[mass]\nm = 0.1\nrho = 1\nOmega = 2\nchi = 2\n"
                 "[initial]\nG0 = 1\ntheta0 = 0.5\n[run]\nt_end = 5\nfidelity = \"averaged\"\n")
    res = _cli("run", str(f))
    assert res.returncode == 0
    # the conditions auto judges by, each with its value (eps is one of them here)
    assert res.stderr.startswith("warning: the averaged model is outside its validity conditions: ")
    assert "eps = |w0|/Omega = 0.395 > 0.2" in res.stderr


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_example_scenarios_load_and_run(path):
    sc = physics.Scenario.load(path)
    short = sc.replace(run=physics.Run(t_end=min(sc.run.t_end, 50.0), samples=11, fidelity=sc.run.fidelity))
    tr = physics.simulate(short)
    assert np.all(np.isfinite(tr.theta)) and tr.t[-1] > 0
    assert physics.Scenario.from_toml(sc.to_toml()) == sc
