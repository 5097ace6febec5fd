"""The compiled integrators release the GIL (``nogil=True``): a long run on a background thread must
not stall a Python thread, as the app's frame loop would be while a simulation runs."""

import threading
import time

import numpy as np
import pytest

import physics
from physics.compiled import dispatch, dop853, fixed, midpoint
from physics.reference.problems import p2

RUN_S = 0.6  # s: the background run is at least this long
# Turns a Python loop must get while a compiled run works on another thread. Holding the GIL, the run lets it
# turn about once in all (when the run returns); releasing it, the loop turns about as often as alone (199 of
# 199 on an idle machine, 39 of 199 with the 2 cores at load 20). The count tells the two apart on any load.
MIN_TURNS = 10


def _horizon_for(run, seconds):
    """Grow the horizon until ``run(t)`` takes ``seconds`` (the machine's speed varies)."""
    run(np.linspace(0.0, 0.1, 3))  # load the compiled code first: that is not the run
    t_end = 10.0
    while True:
        start = time.perf_counter()
        run(np.linspace(0.0, t_end, 3))
        if time.perf_counter() - start >= seconds:
            return np.linspace(0.0, t_end, 3)
        t_end *= 2


def _iterations(stop: threading.Event) -> int:
    """A frame loop's turns (sleep, wake, touch Python objects) until ``stop`` is set."""
    n = 0
    while not stop.is_set():
        time.sleep(0.002)
        n += 1
    return n


def _turns_while(run, t) -> tuple[int, int]:
    """Turns of a Python loop while ``run(t)`` works on another thread, and turns in as long a window with that
    thread asleep (the same loop, the same machine, the same minute): a ratio measured in one run."""
    done = threading.Event()
    worker = threading.Thread(target=lambda: (run(t), done.set()), daemon=True)
    start = time.perf_counter()
    worker.start()
    during = _iterations(done)
    worker.join()
    span = time.perf_counter() - start
    idle = threading.Event()
    sleeper = threading.Thread(target=lambda: (time.sleep(span), idle.set()), daemon=True)
    sleeper.start()
    alone = _iterations(idle)
    return during, alone


@pytest.mark.slow
@pytest.mark.parametrize("which", ["DOP853", "RK8"])
def test_background_integration_leaves_python_threads_running(which):
    sc = p2(1.0)
    model = physics.get_model("moving_mass", "full")
    p = model.pack(sc)
    y0 = model.initial_state(sc, p)

    def run(t):
        if which == "DOP853":
            dop853.integrate(dispatch.MASS_FULL, y0, p, t, 1e-10, 1e-16, 0.0, 0.0, 10**9, 0.0, 1.0)
        else:
            fixed.run(fixed.RK8, dispatch.MASS_FULL, y0, p, t, 0.01)

    t = _horizon_for(run, RUN_S)  # long enough that a held GIL would cost the loop most of its turns
    during, alone = _turns_while(run, t)
    assert alone >= 20  # the window was long enough to tell
    assert during >= MIN_TURNS, f"the Python loop got {during} turns during the run, {alone} without it"


@pytest.mark.parametrize("kernel", [dop853.integrate, fixed.integrate, midpoint.integrate])
def test_every_compiled_integrator_is_built_without_the_gil(kernel):
    assert kernel.targetoptions.get("nogil") is True, kernel
