"""The compiled integrators release the GIL (``nogil=True``): a long run on a background thread must
not stall a Python thread, as the app's frame loop would be while a simulation runs."""

import threading
import time

import numpy as np
import pytest

import physics
from bench.problems import p2
from physics.compiled import dispatch, dop853, fixed

RUN_S = 0.6  # s: the background run is at least this long
GAP_FRACTION = 0.5  # the longest pause of the Python thread stays under this fraction of the run


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


def _longest_pause_while(run, t):
    done = threading.Event()
    worker = threading.Thread(target=lambda: (run(t), done.set()), daemon=True)
    stamps = [time.perf_counter()]
    worker.start()
    while not done.is_set():
        time.sleep(0.002)  # a frame loop: sleep, wake, touch Python objects
        stamps.append(time.perf_counter())
    worker.join()
    return float(np.max(np.diff(stamps))), time.perf_counter() - stamps[0]


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

    t = _horizon_for(run, RUN_S)
    pause, wall = _longest_pause_while(run, t)
    assert wall >= 0.5 * RUN_S  # the run did take long enough to tell
    assert pause < GAP_FRACTION * wall, f"the Python thread stalled for {pause:.3f} s of a {wall:.3f} s run"
