"""``python -m bench``: one subcommand per study, each with its own options, and one machine record (issue 14).

In-process and cheap: help texts are parsed and the dispatch is checked with a study's ``main`` replaced by a
recorder, so no study runs."""

from __future__ import annotations

import json
import os
import platform
import re
import subprocess
import sys
from importlib import import_module, metadata
from pathlib import Path

import pytest

from bench.__main__ import STUDIES
from bench.__main__ import main as bench_main
from bench.machine import machine

ROOT = Path(__file__).resolve().parents[1]

# each study and options its --help must name (its own parser's, not the top level's)
OPTIONS = {
    "work-precision": ["--quick", "--out", "--img"],
    "stability": ["--quick", "--out", "--img"],
    "figures": ["--out", "--quick", "--presets"],
    "sweep": ["--vary", "--metric", "--workers", "--dask", "--scaling"],
    "soak": ["--minutes", "--clients", "--churn", "--reconnect", "--trim"],
    "load": ["--clients", "--minutes", "--warmup", "--out"],
    "hostile": ["--rounds", "--settle", "--seed", "--out"],
    "api-escapes": ["--root", "--out", "--note"],
    "commands": ["--quick", "--out", "--note"],
    "refusals": ["--wall", "--out"],
    "class": ["--tabs", "--minutes", "--warmup", "--edit-every", "--out"],
    "explorer-rates": ["seconds", "--out", "--img", "--chart-only", "--compare"],
    "fidelity": ["--quick", "--n", "--seed", "--out", "--img", "--workers", "--system"],
    "corrections": ["--out"],
    "challenge": ["--starts", "--reactions", "--out", "--img"],
    "design": ["--n", "--workers", "--out", "--img"],
    "pendulum-hardening": ["--study", "--limit", "--out", "--img"],
    "pendulum-ceiling": ["--study", "--out", "--img"],
    "pendulum-prediction": ["--study", "--workers", "--out", "--img"],
    "explorer-startup": ["repetitions", "--cold", "--inline", "--compare-env-map", "--fast-timeout"],
}


def _exit(argv, capsys) -> tuple[int, str, str]:
    with pytest.raises(SystemExit) as stop:
        bench_main(argv)
    out, err = capsys.readouterr()
    return stop.value.code, out, err


def test_every_study_module_with_a_main_is_a_subcommand():
    # a module of bench/ that defines main() is a study: it must be reachable as python -m bench NAME
    with_main = {p.stem for p in (ROOT / "bench").glob("*.py")
                 if p.stem != "__main__" and re.search(r"^def main\(", p.read_text(), re.M)}
    assert with_main == {module for module, _line in STUDIES.values()}
    assert set(STUDIES) == set(OPTIONS)


def test_top_level_help_lists_every_subcommand_with_its_line(capsys):
    code, out, _err = _exit(["--help"], capsys)
    assert code == 0
    text = re.sub(r"\s+", " ", out)
    for name, (_module, line) in STUDIES.items():
        assert f"{name} {line}" in text, f"python -m bench --help does not list {name} with its line"


@pytest.mark.parametrize("name", sorted(OPTIONS))
def test_study_help_shows_its_own_options(name, capsys):
    code, out, _err = _exit([name, "--help"], capsys)
    assert code == 0
    assert out.startswith(f"usage: python -m bench {name} "), out.splitlines()[0]
    for option in OPTIONS[name]:
        assert option in out, f"python -m bench {name} --help does not name {option}"


def test_the_rest_of_the_line_reaches_the_study_unchanged(monkeypatch):
    module = import_module("bench.explorer_startup")
    seen = []
    monkeypatch.setattr(module, "main", lambda argv: seen.append(argv) or 7)
    # a positional among options, an option=value, and options the top-level parser does not know
    argv = ["--cold", "3", "--out=x.csv", "--fast-timeout", "90", "--inline"]
    assert bench_main(["explorer-startup", *argv]) == 7  # the study's exit status is the command's
    assert seen == [argv]


def test_unknown_study_exits_2_naming_it(capsys):
    code, _out, err = _exit(["no-such-study", "--quick"], capsys)
    assert code == 2
    assert "'no-such-study'" in err and "work-precision" in err  # what was given, and what is allowed


def test_no_study_exits_2_saying_one_is_needed(capsys):
    code, _out, err = _exit([], capsys)
    assert code == 2
    assert "STUDY" in err


def test_the_older_script_form_still_runs():
    # README.md quoted `python bench/explorer_startup.py ...` before the subcommand existed
    done = subprocess.run([sys.executable, "bench/explorer_startup.py", "--help"], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("usage: python bench/explorer_startup.py ") and "--cold" in done.stdout


def test_machine_records_the_union_of_the_older_records():
    box = machine()
    assert set(box) == {"platform", "processor", "cpu", "cpus", "cores", "python", "numpy", "scipy", "numba",
                        "mujoco", "matplotlib", "dask", "distributed"}
    assert box["cpus"] == box["cores"] == os.cpu_count()
    assert box["python"] == platform.python_version()
    assert box["numpy"] == metadata.version("numpy") and box["numba"] == metadata.version("numba")
    assert box["cpu"] and box["platform"] == platform.platform()
    json.dumps(box)  # it goes into .meta.json files as is


def test_machine_keeps_the_key_names_of_the_results_already_written():
    # every machine key of the committed results is still recorded, so readers of old and new files agree
    boxes = {}
    for path in (ROOT / "bench" / "results").glob("*.json"):
        box = json.loads(path.read_text()).get("machine")
        if box:
            boxes[path.name] = box
    assert boxes, "no results file with a machine record"
    for name, box in boxes.items():
        assert set(box) <= set(machine()), f"{name}: {sorted(set(box) - set(machine()))} no longer recorded"


# a numeric option of each study and values it must refuse before anything runs: a minus (argparse took "-1e308"
# for an option and said only "expected one argument"), the ends of the doubles, inf and nan, and a count too big
REFUSED = [
    ("load", "--minutes", "-1e308"), ("load", "--clients", "1e9"), ("load", "--warmup", "-inf"),
    ("soak", "--minutes", "5e-324"), ("soak", "--churn", "1e308"), ("soak", "--clients", "-1"),
    ("class", "--tabs", "-5e-324"), ("class", "--edit-every", "nan"), ("design", "--n", "-1e308"),
    ("design", "--workers", "100000"), ("fidelity", "--seed", "-1"), ("fidelity", "--n", "1e308"),
    ("hostile", "--settle", "1e308"), ("hostile", "--rounds", "-2"), ("challenge", "--reactions", "0"),
    ("challenge", "--starts", "-1"), ("refusals", "--wall", "nan"), ("pendulum-hardening", "--limit", "-1"),
    ("pendulum-prediction", "--workers", "-1e3"), ("explorer-startup", "--fast-timeout", "-1e308"),
    ("explorer-rates", None, "-1"), ("sweep", "--workers", "-1e3"),
]


@pytest.mark.parametrize(("study", "option", "value"), REFUSED, ids=lambda v: str(v))
def test_a_numeric_option_out_of_range_is_refused_naming_it_its_value_and_what_is_allowed(study, option, value,
                                                                                          capsys):
    code, _, err = _exit([study, *([option] if option else ["--"]), value], capsys)
    line = err.strip().splitlines()[-1]
    assert code == 2 and f"'{value}'" in line and "allowed: " in line, line
    assert f"argument {option or 'seconds'}: " in line, line
    assert "Traceback" not in err and "expected one argument" not in err


def test_every_parser_of_the_benchmarks_reads_a_leading_minus_as_a_value():
    """A parser made anywhere in bench/ but bench/cli.py (and the top level's, which passes the rest on) would read
    ``--opt -1e308`` as two options again: each goes through study_parser or numbers_as_values."""
    for path in (ROOT / "bench").glob("*.py"):
        text = path.read_text()
        if path.name in ("cli.py", "__main__.py"):
            continue
        assert "argparse.ArgumentParser(" not in text, path.name
        for made in re.findall(r"\bap = (\w+)\(", text):
            assert made in ("study_parser", "quick_out_img_parser", "numbers_as_values"), (path.name, made)
