"""``python -m bench commands`` runs each command with hostile option values as a user runs it (a subprocess)
and writes what came of each case; on this tree none prints a traceback, hangs or refuses without naming what.

The --quick sample, two cases at a time, takes 25 s to a minute: marked slow. The outcome rules are checked here
on their own."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from bench import commands


def test_every_option_is_given_every_value_in_both_forms(tmp_path):
    cases = commands.cases(tmp_path, commands.QUICK)
    options = {(c, o) for c, o, _v, _a in cases}
    assert {("physics design", "--vary"), ("physics design", "--accuracy"), ("physics design", "--budget"),
            ("physics design", "--workers"), ("app record", "--seconds"), ("app record", "--warp"), ("app", "--port"),
            ("app", "--host")} == options
    written = [a for c, o, v, argv in cases if o == "--seconds" for a in argv if a.startswith("--seconds")]
    assert "--seconds=-1e308" in written and "--seconds" in written  # attached, and apart
    records = [a[a.index("--out") + 1] for c, o, v, a in cases if c == "app record"]
    assert len(set(records)) == len(records)  # cases run at once write files of their own


@pytest.mark.parametrize("case, option, value, want", [
    (dict(traceback=True, hung=False, status=1, ready=False, last="x"), "--port", "-1", "traceback"),
    (dict(traceback=False, hung=True, status=None, ready=False, last=""), "--host", "192.0.2.1", "hung"),
    (dict(traceback=False, hung=False, status=0, ready=False, last="wrote"), "--seconds", "2.5", "ran"),
    (dict(traceback=False, hung=False, status=-9, ready=True, last="ready"), "--port", "0", "ran"),
    (dict(traceback=False, hung=False, status=2, ready=False, last="error: --port 70000: must be"), "--port", "7",
     "refused"),
    (dict(traceback=False, hung=False, status=2, ready=False, last="error: accuracy = -5e-324: must be > 0"),
     "--accuracy", "-5e-324", "refused"),
    (dict(traceback=False, hung=False, status=2, ready=False, last="error: expected one argument"), "--budget", "",
     "unnamed"),
    (dict(traceback=False, hung=False, status=2, ready=False, last="python -m app: error: argument --port: invalid"),
     "--port", "nan", "refused"),
    (dict(traceback=False, hung=False, status=2, ready=False, last="error: ... is mass.Omega = 8.5e-304: bring it"),
     "--vary", "5e-324", "refused"),
    (dict(traceback=False, hung=False, status=1, ready=False, last="error: numerical fault"), "--vary", "1", "other"),
])
def test_the_outcomes(case, option, value, want):
    assert commands.outcome(case, option, value) == want


@pytest.mark.slow
def test_no_command_prints_a_traceback_hangs_or_refuses_without_a_name(tmp_path, monkeypatch):
    # a fresh machine may compile the kernels in a design's first run: the bound is for hangs, not for that
    monkeypatch.setattr(commands, "TIME_BOUND_S", 600.0)
    out = tmp_path / "commands.json"
    assert commands.main(["--quick", "--jobs", "2", "--out", str(out), "--note", "test"]) == 0
    record = json.loads(Path(out).read_text())
    assert record["cases"] == len(commands.cases(tmp_path, commands.QUICK)) and record["machine"]["cpus"]
    assert record["jobs"] == 2
    assert record["bad"] == [] and set(record["counts"]) <= {"ran", "refused"}, record["bad"][:3]
    assert record["counts"]["ran"] > 0 and record["counts"]["refused"] > 0


def test_docs_quote_the_committed_run():
    root = Path(__file__).resolve().parents[1]
    record = json.loads((root / "bench" / "results" / "commands.json").read_text())
    c = record["counts"]
    text = " ".join((root / "docs" / "reliability.md").read_text().split())
    assert record["bad"] == [] and f"{record['cases']} cases, {c['ran']} ran, {c['refused']} refused" in text
    assert f"in {round(record['wall_s'])} s (`bench/results/commands.json`)" in text
