"""The badge's worker stops when its tab closes (issue 17: "the badge thread runs on after the tab closes").

``Engine.cancel_workers`` is what ``Session.close`` calls. These tests replace ``physics.derived`` (the badge's
first unit of work) with stand-ins that hold or spin, so they count what ran instead of timing it; every join
is bounded, and a stand-in that is not stopped ends by itself when its test gives up, so no thread outlives
the test.
"""

from __future__ import annotations

import threading

import pytest

import physics
from app.engine import workers
from app.state import Engine

pytestmark = pytest.mark.filterwarnings("ignore::physics.ValidityWarning")
JOIN_S = 20.0  # bound on every join: far above the milliseconds a stop takes, so it fails only on a real hang


@pytest.fixture
def counted(monkeypatch):
    """Count the badge's second unit (the validity conditions): a cancelled badge must never reach it."""
    calls = []
    real = physics.validity_conditions
    monkeypatch.setattr(physics, "validity_conditions", lambda sc: calls.append(sc) or real(sc))
    return calls


def start_badge(engine: Engine) -> threading.Thread:
    assert "working out" in engine.badge()
    return engine.auto_badge.thread


def test_a_badge_cancelled_during_its_analysis_stops_and_shows_nothing(monkeypatch, counted):
    entered, release = threading.Event(), threading.Event()

    def held(sc):  # blocks like a long analysis until the test lets it go
        entered.set()
        release.wait(JOIN_S)
        return {}

    monkeypatch.setattr(physics, "derived", held)
    e = Engine()
    thread = start_badge(e)
    assert entered.wait(JOIN_S)
    e.cancel_workers()  # the tab closed
    release.set()
    thread.join(JOIN_S)
    assert not thread.is_alive()
    assert counted == []  # no unit of work after the cancel
    assert e.auto_badge.done is None and not e.auto_badge.busy  # nothing published; a later badge could start anew
    assert e.auto_badge.stop.interrupts == 1  # the unit in progress was interrupted, not left to finish


def test_cancel_interrupts_a_physics_call_that_would_run_on(monkeypatch, counted):
    """A pure-Python loop stands for physics.derived on 200 plane pendulums (one expm per sample, many seconds):
    it has no hook to check, and would spin until the test gives up if the cancel did not interrupt it."""
    entered, give_up = threading.Event(), threading.Event()
    turns = [0]

    def spinning(sc):
        entered.set()
        while not give_up.is_set():
            turns[0] += 1
        return {}

    monkeypatch.setattr(physics, "derived", spinning)
    e = Engine()
    thread = start_badge(e)
    try:
        assert entered.wait(JOIN_S)
        e.cancel_workers()
        thread.join(JOIN_S)
        stopped_by_cancel = not thread.is_alive()
    finally:
        give_up.set()  # end the loop whatever happened, so no thread outlives the test
        thread.join(JOIN_S)
    assert stopped_by_cancel, "the badge thread ran on after cancel_workers"
    assert turns[0] > 0 and counted == [] and e.auto_badge.done is None


def test_a_badge_cancelled_before_it_starts_runs_no_unit(monkeypatch, counted):
    derived_calls = []
    monkeypatch.setattr(physics, "derived", lambda sc: derived_calls.append(sc) or {})
    stop = workers.BadgeStop()
    stop.set()
    with pytest.raises(workers.BadgeCancelled):
        workers._badge_text(physics.default_scenario(), stop)
    assert derived_calls == [] and counted == [] and stop.interrupts == 0


def test_an_uncancelled_badge_is_unchanged_by_its_stop():
    sc = physics.default_scenario()
    assert workers._badge_text(sc, workers.BadgeStop()) == workers._badge_text(sc)


def run_rounds(monkeypatch, units: int | None, rounds: int = 200) -> tuple[list, list, int]:
    """``rounds`` workers, each running ``units`` tiny units under a BadgeStop (None: until cancelled), each
    cancelled right after its first unit. Returns (exception types that escaped a thread, caught cancels,
    workers that finished their units uncancelled)."""
    escaped, caught, finished = [], [], []
    monkeypatch.setattr(threading, "excepthook", lambda args: escaped.append(args.exc_type))

    def worker(stop: workers.BadgeStop, ready: threading.Event):
        try:
            n = 0
            while units is None or n < units:
                stop.run(sum, range(2000))
                n += 1
                ready.set()
            finished.append(1)
        except workers.BadgeCancelled:
            caught.append(1)
        for _ in range(2000):  # bytecode boundaries where a leaked interrupt would fire
            pass

    for _ in range(rounds):
        stop, ready = workers.BadgeStop(), threading.Event()
        thread = threading.Thread(target=worker, args=(stop, ready), daemon=True)
        thread.start()
        assert ready.wait(JOIN_S)
        stop.set()
        thread.join(JOIN_S)
        assert not thread.is_alive()
    return escaped, caught, len(finished)


def test_an_interrupt_during_the_units_is_caught_by_the_worker(monkeypatch):
    """A cancel at an arbitrary point of a tight loop of units fires inside the worker's handler, once."""
    escaped, caught, finished = run_rounds(monkeypatch, units=None)
    assert escaped == [] and len(caught) == 200 and finished == 0


def test_an_interrupt_never_escapes_the_worker(monkeypatch):
    """A cancel that lands as the last unit returns, or after the worker left its handler, is dropped: it must
    never fire later (an exception escaping a thread prints a traceback to the server's console)."""
    escaped, caught, finished = run_rounds(monkeypatch, units=3)
    assert escaped == [] and len(caught) + finished == 200
