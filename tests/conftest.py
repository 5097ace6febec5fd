"""Shared scenario builders for the physics tests (docs/models.md A.7(a) reference setup)."""

from __future__ import annotations

import functools
import re
from pathlib import Path

import numpy as np
import pytest

import physics


def reference(eps: float, C: float, theta0: float, t_end: float, *, samples: int = 401, rtol: float = 1e-11,
              chi: float | None = None, lam_q: float = 0.0, extra: dict | None = None,
              mass_state: str = "quasistatic") -> physics.Scenario:
    """docs/models.md A.7(a): A = 1, m = 0.1, m/M = 0.1, rho = 1.5, Omega = 1/eps, chi = Omega, G0 = 1."""
    Om = 1.0 / eps
    data = {
        "body": {"A": 1.0, "C": C, "M": 1.0},
        "mass": {"m": 0.1, "rho": 1.5, "Omega": Om, "chi": Om if chi is None else chi, "lam_q": lam_q},
        "initial": {"G0": 1.0, "theta0": theta0, "mass_state": mass_state},
        "run": {"t_end": t_end, "samples": samples, "rtol": rtol},
    }
    data.update(extra or {})
    return physics.Scenario.from_dict(data)


def state_matrix(tr: physics.Trajectory) -> np.ndarray:
    """The full model's state rows rebuilt from a trajectory (for the invariants)."""
    cols = [tr.omega] + [tr.internal[k][:, None] for k in ("ux", "uy", "uz", "vx", "vy", "vz")]
    cols += [tr.quat, tr.internal["W_int"][:, None], tr.internal["W_ext"][:, None]]
    return np.hstack(cols)


@pytest.fixture
def full_model():
    return physics.get_model("moving_mass", "full")


# The README's test command runs the suite on two pytest-xdist workers. The tests that serve the explorer, drive
# chromium or talk to a server through a websocket run one after another, on one worker (the "live" group), so
# two browsers or two servers never share the machine's cores with each other; the physics tests run beside them
# on the other worker. A test module is live when its source starts the server (App, ViserServer, ``python -m
# app``, tests/explorer_process.py), a raw websocket client (tests/raw_client.py) or chromium.
LIVE = re.compile(r"\bApp\(|ViserServer|chromium|explorer_process|raw_client|raw_session|serve_and_watch|"
                  r"explorer_startup|\"-m\", \"app\"|python -m app|\"(?:load|soak)\"")


@functools.cache
def _live(path: Path) -> bool:
    return bool(LIVE.search(path.read_text(encoding="utf-8")))


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook reads the groups
def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.get_closest_marker("browser") is not None or _live(Path(item.path)):
            item.add_marker(pytest.mark.xdist_group("live"))
