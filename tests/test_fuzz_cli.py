"""Property-based fuzzing of the CLI's arguments (issue 7): ``python -m physics run|info ...`` called
in-process through ``physics.cli.main(argv)``. Bad arguments exit with status 2 and one line on stderr
starting "error: ", never a traceback; good ones get as far as the run (stubbed here: this fuzzes
the arguments, not the integrator) or print ``info``.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from physics import cli
from physics.scenario.params import FIDELITIES, METHODS

ROOT = Path(__file__).resolve().parent.parent
GOOD_FILE = str(ROOT / "assets" / "scenarios" / "oblate_settling.toml")
EXAMPLES = 1_000


class Reached(Exception):
    """The arguments were good: main() got as far as simulating."""


def _stub(*_args, **_kwargs):
    raise Reached


def run_main(argv: list[str]) -> tuple[int | str, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = cli.main(argv)
        except SystemExit as exc:  # argparse's exits
            code = exc.code
        except Reached:
            code = "reached"
    return code, out.getvalue(), err.getvalue()


tokens = st.one_of(
    st.sampled_from(["run", "info", "--out", "--fidelity", "--method", "--", "-x", "--fidelity=full",
                     "--method=RK4", "--out=", "--bogus", "-", "", " ", "run info", GOOD_FILE, "/dev/null",
                     "/dev/zero", "/", str(ROOT), "/nonexistent/x.toml", "x\x00y", "\n", "--out=/dev/null"]),
    st.sampled_from(list(FIDELITIES) + list(METHODS) + ["FULL", "rk4", "auto "]),
    st.text(min_size=0, max_size=12),
)


@pytest.mark.slow
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(st.lists(tokens, max_size=6))
def test_fuzzed_arguments_exit_2_with_one_line_or_run(monkeypatch, argv):
    monkeypatch.setattr(cli, "simulate", _stub)
    if "-h" in argv or "--help" in argv or any(a.startswith("--h") and "--help".startswith(a) for a in argv):
        return  # help is multi-line on purpose and exits 0
    code, out, err = run_main(argv)
    assert "Traceback" not in err + out
    if code == "reached":
        return
    if code == 0:  # info of a good file: "name = value" lines
        assert argv and argv[0] == "info" and all(" = " in line for line in out.splitlines() if line)
        return
    assert code == 2, (argv, code, err)
    lines = err.strip("\n").split("\n")
    assert len(lines) == 1 and lines[0].startswith("error: "), (argv, err)


@pytest.mark.parametrize("argv, needle", [
    ([], "required"),
    (["run", "--fidelity", "nope"], "invalid choice"),
    (["run", "/dev/zero"], "at most 1000000 bytes"),  # read without end before the fix
    (["info", str(ROOT)], "cannot be read"),
    (["run", "a\x00b"], "cannot be read"),  # a NUL in a path: ValueError from open()
    # a negative number after an option is its value, not an option: "expected one argument" named neither
    (["design", GOOD_FILE, "--vary", "mass.Omega=1:3", "--accuracy", "-5e-324"],
     "accuracy = -5e-324: must be a finite number > 0 rad"),
    (["design", GOOD_FILE, "--vary", "mass.Omega=1:3", "--accuracy", "-inf"], "accuracy = -inf: must be a finite"),
    # let through to every point's run before 73c53ad, each refusing it
    (["design", GOOD_FILE, "--vary", "mass.Omega=1:3", "--accuracy", "inf"], "accuracy = inf: must be a finite"),
    (["design", GOOD_FILE, "--vary", "mass.Omega=1:3", "--budget", "-1e308"], "--budget: invalid int value: '-1e308'"),
    (["design", GOOD_FILE, "--vary", "mass.Omega=1:3", "--budget", "3"], "is too small for 1 key:"),
])
def test_bad_arguments_name_the_problem(monkeypatch, argv, needle):
    monkeypatch.setattr(cli, "simulate", _stub)
    code, _, err = run_main(argv)
    assert code == 2 and needle in err and err.count("\n") == 1


def test_good_arguments_reach_the_run(monkeypatch):
    monkeypatch.setattr(cli, "simulate", _stub)
    assert run_main(["run", GOOD_FILE, "--fidelity", "averaged", "--method", "RK45"])[0] == "reached"


def test_numpys_floating_point_warnings_stay_quiet_from_any_thread(monkeypatch):
    """errstate holds in the calling thread only; a design's refinements run in threads of their own, and an
    extreme design printed 14 lines of "warning: invalid value encountered in divide". A warning of the
    product's own still prints."""
    import threading
    import warnings

    import numpy as np

    def noisy_design(_sc, _args):
        def work():
            np.divide(np.zeros(2), np.zeros(2))  # numpy warns: invalid value encountered in divide
            np.divide(np.ones(2), np.zeros(2))  # and: divide by zero encountered in divide

        t = threading.Thread(target=work)
        t.start()
        t.join()
        warnings.warn("the product's own words", UserWarning, stacklevel=1)
        return 0

    monkeypatch.setattr(cli, "run_design", noisy_design)
    code, _, err = run_main(["design", GOOD_FILE, "--vary", "mass.Omega=1:3"])
    assert code == 0 and err == "warning: the product's own words\n", err
