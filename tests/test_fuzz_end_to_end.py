"""End-to-end fuzz (issue 17): generated scenarios go through the whole path a user's file takes, with
nothing stubbed: parse, ``derived``, ``simulate`` (with small budgets, so that every example ends soon),
and, for a sample, ``python -m physics info|run FILE`` in a subprocess with the real budgets.

Every numeric key gets magnitudes from 5e-324 to 1e308 (tests/fuzz_scenarios.py); dotted keys nest up to
20,000 deep; sample counts go up to 10,000,000. Allowed outcomes: a result, a ScenarioError (exit 2, one
line naming the key), an IntegrationFault (exit 1, one line). Anything else is a bug: no other exception,
no traceback, no run past its step or output budget, no subprocess past its time or memory bound.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

from physics import IntegrationFault, Scenario, ScenarioError, derived, simulate
from tests.fuzz_scenarios import generate

SIM = importlib.import_module("physics.stepping.simulate")
AVERAGED = importlib.import_module("physics.systems.pendulum.averaged")
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SMALL = dict(MAX_STEPS=20_000, STEPS_PER_CALL=2_000, MAX_OUTPUT_BYTES=2_000_000, MAX_SCIPY_EVALS=20_000)
MAX_MESSAGE = 600  # characters: one readable line
CLI_TIMEOUT = 180  # s: a bound on a subprocess, far above what any budget allows on a loaded machine
CLI_RSS_KB = 1_500_000  # peak resident memory of one CLI process (numba and scipy loaded: ~200 MB)
EXAMPLES = generate()


def _one_line(exc: Exception) -> str:
    text = str(exc)
    assert "\n" not in text and 0 < len(text) <= MAX_MESSAGE, text[:1000]
    return text


def _outcome(text: str) -> tuple[str, object]:
    """("refused" | "fault" | "ok", detail) of one scenario text through parse, derived and simulate."""
    try:
        sc = Scenario.from_toml(text)
    except ScenarioError as exc:
        return "refused", _one_line(exc)
    try:
        derived(sc)
        tr = simulate(sc)
    except ScenarioError as exc:
        return "refused", _one_line(exc)
    except IntegrationFault as exc:
        return "fault", _one_line(exc)
    return "ok", tr


@pytest.fixture
def small_budget(monkeypatch):
    for name, value in SMALL.items():
        monkeypatch.setattr(SIM, name, value)
    monkeypatch.setattr(AVERAGED, "MAX_SUBSTEPS", 50_000)


def test_the_generator_covers_extremes_deep_keys_and_huge_samples():
    texts = [t for _, t in EXAMPLES]
    assert any("5e-324" in t for t in texts) and any("1.7976931348623157e+308" in t for t in texts)
    assert any("a." * 1000 in t for t in texts) and any("samples = 10000000" in t for t in texts)
    assert len(EXAMPLES) >= 150


@pytest.mark.parametrize("label, text", EXAMPLES, ids=[label[:60] for label, _ in EXAMPLES])
def test_every_generated_scenario_ends_in_a_result_or_one_line(small_budget, label, text):
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        kind, detail = _outcome(text)
    if kind == "ok":
        tr = detail
        steps = tr.info.get("steps") or 0
        assert steps <= SMALL["MAX_STEPS"], tr.info  # the budget holds
        assert len(tr) * 8 * (tr.table().shape[1]) <= SMALL["MAX_OUTPUT_BYTES"]
        assert np.all(np.isfinite(tr.t))


# ``python -m physics`` that reports its own peak resident memory on its last stderr line
MEASURED = ("import resource, runpy, sys\n"
            "sys.argv = ['physics'] + sys.argv[1:]\n"
            "try:\n"
            "    runpy.run_module('physics', run_name='__main__', alter_sys=True)\n"
            "finally:\n"
            "    sys.stderr.write(f'peak_rss_kb={resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}\\n')\n")
ADDRESS_SPACE = 4 * 1024**3  # bytes: a safety net so a failure here cannot exhaust the machine


def _limit_memory():
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (ADDRESS_SPACE, ADDRESS_SPACE))


def _cli_sample() -> list[tuple[str, str]]:
    """A few of each kind: moderate values (runs that end in a result), extremes (refusals and faults),
    and mixtures with huge sample counts or deep dotted keys."""
    moderate = [e for e in EXAMPLES if e[0].endswith(("=1.0", "=1000.0"))][:3:2]
    extreme = [e for e in EXAMPLES if e[0].endswith(("=1e+200", "=1.7976931348623157e+308"))][:3:2]
    mixed = [e for e in EXAMPLES if "samples = 10000000" in e[1] or "a.a.a.a.a.a.a.a.a" in e[1]][:2]
    return moderate + extreme + mixed


CLI_SAMPLE = _cli_sample()


@pytest.mark.parametrize("command", ["info", "run"])
@pytest.mark.parametrize("label, text", CLI_SAMPLE, ids=[label[:40] for label, _ in CLI_SAMPLE])
def test_the_command_line_exits_0_1_or_2_with_one_line(tmp_path, command, label, text):
    path = tmp_path / "fuzzed.toml"
    path.write_text(text)
    proc = subprocess.Popen([sys.executable, "-c", MEASURED, command, str(path)], cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, preexec_fn=_limit_memory)
    try:
        out, err = proc.communicate(timeout=CLI_TIMEOUT)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.communicate()
        pytest.fail(f"python -m physics {command} ran past {CLI_TIMEOUT} s on {label}")
    *lines, peak = err.splitlines()
    assert peak.startswith("peak_rss_kb=") and int(peak.split("=")[1]) <= CLI_RSS_KB, (label, peak)
    err = "\n".join(lines)
    assert "Traceback" not in out + err and "out of memory" not in err
    errors = [line for line in err.splitlines() if line.startswith("error: ")]
    assert proc.returncode in (0, 1, 2), (label, proc.returncode, err[-2000:])
    if proc.returncode == 0:
        assert not errors and out.strip()
    else:
        assert len(errors) == 1 and len(errors[0]) <= MAX_MESSAGE + 40, err
        assert all(line.startswith(("error: ", "warning: ", "integrating: ")) for line in err.splitlines()), err
