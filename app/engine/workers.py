"""The engine's background workers: the cheaper fidelity's prediction (the overlay) and auto's badge.
Each runs in a daemon thread, so a long computation never stalls the frames; a newer request makes an
older overlay give up, and the badge is worked out once per scenario. When the tab closes
(``cancel_workers``) both stop, so nothing of a closed tab keeps a core busy.

Each is a plain object the ``app.engine.engine.Engine`` holds (``prediction``, ``auto_badge``), given what it
reads (the scenario, how far the run has come) and told how to report (the engine's ``error`` and
``plots_changed``).
"""

from __future__ import annotations

import ctypes
import threading
import warnings
from collections.abc import Callable

import numpy as np

import physics

from . import words

OVERLAYS = ("none", "averaged", "closed")  # the overlay dropdown's choices: a cheaper prediction, or none
OVERLAY_SAMPLES = 2000  # from t = 0 to OVERLAY_WINDOWS times now: smooth models, interpolated linearly
OVERLAY_WINDOWS = 2.0  # a prediction reaches this many times as far as the run has come


def _envelope(sc: physics.Scenario, fid: str) -> bool:
    """Whether the "closed" overlay is linear theory's envelope (``physics.derived``'s decay_rate_linear): for a
    system with no closed-form model (the pendulums)."""
    return fid == "closed" and "closed" not in physics.get_system(sc.system).models


class Overlay:
    """The overlay: ``curve`` is (t, theta) or None; ``fidelity`` "none", "averaged" or "closed"; ``dirty``: a
    prediction is to be started (at the next tick). ``changed()`` says the plots must be drawn again and
    ``failed(message)`` reports an error (the engine's ``plots_changed`` and ``error``); both may be called
    from the worker thread."""

    def __init__(self, changed: Callable[[], None], failed: Callable[[str], None]) -> None:
        self._changed = changed
        self._failed = failed
        self.fidelity = "none"
        self.curve: tuple[np.ndarray, np.ndarray] | None = None
        self.dirty = True
        self.thread: threading.Thread | None = None
        self._gen = 0
        self._key = None  # (fidelity, start scenario) of the prediction shown

    def restart(self) -> None:
        """The run starts anew: no prediction shown until the next one is ready."""
        self.curve = None
        self.dirty = True

    def compute(self, start_scenario: physics.Scenario, t: float, window: float) -> None:
        """Start computing the cheaper fidelity's prediction in a background thread: a long prediction must
        not stall the frames. A newer request cancels an older one. ``t``: how far the run has come (s);
        ``window``: the plots' window (s).

        The prediction starts at t = 0 from the scenario the run began with (``start_scenario``), so it
        lies on the same axes as the run's whole history; ``title`` says so, and names the edits
        the run went on through since. It reaches OVERLAY_WINDOWS times as far as the run has come (at
        least a plot window ahead), so it is computed again only each time the run doubles its t.
        Moving mass and the spherical pendulum: the fidelity's own model; both pendulum systems,
        "closed": linear theory's envelope theta0 exp(-rate t) (docs/models.md B.4)."""
        if self.thread is not None and self.thread.is_alive():
            self._gen += 1  # cancel it; dirty stays set, so a later tick starts anew
            return
        self.dirty = False
        fid = self.fidelity
        key = (fid, start_scenario)
        if key != self._key:  # another prediction: the old one must not show meanwhile
            self.curve = None
            self._changed()
        elif self.curve is not None and self.curve[0][-1] >= t:
            return  # an edit that kept the run: the prediction from t = 0 is the same
        self._key = key
        self._gen += 1
        if fid == "none":
            return
        sc = start_scenario
        t_end = max(OVERLAY_WINDOWS * t, t + window, 1.0)
        envelope = _envelope(sc, fid)
        try:
            if not envelope:
                sc = sc.with_values(**{"run.t_end": t_end, "run.samples": OVERLAY_SAMPLES})
        except (physics.ScenarioError, ValueError) as exc:
            self._failed(f"overlay ({fid}): {exc}")
            return
        gen = self._gen

        def progress(_fraction):
            if gen != self._gen:  # chunks between compiled calls: the place to give up
                raise _Cancelled

        def work():
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", physics.ValidityWarning)
                    if envelope:  # the analysis is bounded but can take a second: never on the loop thread
                        d = physics.derived(sc)
                        t = np.linspace(0.0, t_end, OVERLAY_SAMPLES)
                        result = (t, d["theta0"] * np.exp(-float(d["decay_rate_linear"]) * t))
                    else:
                        tr = physics.simulate(sc, fidelity=fid, progress=progress)
                        result = (tr.t, tr.theta)
            except _Cancelled:
                return
            except (physics.ScenarioError, physics.IntegrationFault, ArithmeticError, ValueError) as exc:
                if gen == self._gen:
                    self._failed(f"overlay ({fid}): {exc}")
                return
            except Exception as exc:  # noqa: BLE001 - a worker thread must say what failed, never print a traceback
                if gen == self._gen:
                    self._failed(f"overlay ({fid}) failed: {type(exc).__name__}: {str(exc)[:200]}")
                return
            if gen == self._gen:
                self.curve = result
                self._changed()

        self.thread = threading.Thread(target=work, name="overlay", daemon=True)
        self.thread.start()

    def title(self, start_scenario: physics.Scenario, edits: list[tuple[float, str]], edit_count: int) -> str:
        """The prediction chart's title: which model, from when, and what the run did that it does not know
        (``edits``: the first (t, what) of the ``edit_count`` changes the run went on through)."""
        fid = self.fidelity
        if _envelope(start_scenario, fid):
            what = "linear theory's envelope"
        else:
            what = f"the {fid} model's prediction"
        title = f"theta and {what} from t = 0"
        if edit_count:
            t0, names = edits[0]
            more = f" and {edit_count - 1} more" if edit_count > 1 else ""
            title += f", for the scene at t = 0 (edited since: {names} at t = {t0:.4g} s{more})"
        return title

    def cancel(self) -> None:
        """The tab closed: a prediction being computed gives up at its next chunk."""
        self._gen += 1
        self.dirty = False

    def wait(self, timeout: float = 30.0) -> bool:
        """Block until the prediction being computed is done (for tests and scripts)."""
        if self.thread is not None:
            self.thread.join(timeout)
        return self.curve is not None


class Badge:
    """Auto's badge, cached per scenario: ``text()`` returns markdown at once (a placeholder until ready).
    ``scenario``: the engine's scenario now (the badge is for whichever scenario is current when asked)."""

    def __init__(self, scenario: Callable[[], physics.Scenario]) -> None:
        self._scenario = scenario
        self._lock = threading.Lock()
        self.done: tuple | None = None  # (scenario, markdown, details' markdown) of the last badge
        self.busy = False
        self.thread: threading.Thread | None = None
        self.stop: BadgeStop | None = None  # the running badge's cancellation

    def text(self, block: bool = False) -> str:
        """Auto's choice (model, method, error bound against the requested accuracy, and why) and the
        averaged model's validity conditions, as markdown. Computed once per scenario, in a background
        thread (up to 0.4 s for three plane pendulums: the frames go on meanwhile); until it is ready,
        a placeholder. ``block``: wait for it instead."""
        sc = self._scenario()
        done = self.done
        if done is not None and done[0] is sc:
            return done[1]
        if block:
            self.done = (sc, *_badge_text(sc))
            return self.done[1]
        with self._lock:
            start = not self.busy
            self.busy = True
        if start:
            self.stop = stop = BadgeStop()
            self.thread = threading.Thread(target=self._work, args=(sc, stop), name="badge", daemon=True)
            self.thread.start()
        return "_auto: working out its choice..._"

    def _work(self, sc: physics.Scenario, stop: BadgeStop) -> None:
        try:
            text = _badge_text(sc, stop)
            if not stop.is_set():  # a cancelled badge is for a closed tab: nothing to show it to
                self.done = (sc, *text)
        except BadgeCancelled:
            pass
        finally:
            self.busy = False  # the next call starts another if the scenario has changed since

    def cancel(self) -> None:
        """Stop the badge being worked out (its tab closed): the physics call in progress is interrupted and
        no further one starts, so a slow analysis (many plane pendulums) does not keep a core busy."""
        stop = self.stop
        if stop is not None:
            stop.set()

    def details(self) -> str:
        """The averaged model's conditions as formulas with their values (the Details folder), once the
        badge of the present scenario is ready; "" until then."""
        done = self.done
        return done[2] if done is not None and done[0] is self._scenario() else ""


class _Cancelled(Exception):
    """A newer overlay request replaced this one."""


def _badge_text(sc: physics.Scenario, stop: BadgeStop | None = None) -> tuple[str, str]:
    """(the badge in words, the conditions' formulas): app.engine.words.badge_parts. With ``stop``, each of its three
    units of work runs under it, so a cancel raises BadgeCancelled (not an Exception: it is not a failure to
    report as "unavailable")."""
    run = stop.run if stop is not None else (lambda fn, *args: fn(*args))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            d = run(physics.derived, sc)
            conds = run(physics.validity_conditions, sc)
    except Exception as exc:  # never let the badge break a frame
        return f"auto: unavailable ({exc})", ""
    return run(words.badge_parts, d, conds, sc.run.fidelity)


class BadgeCancelled(BaseException):
    """The badge's tab closed. A BaseException, so that neither physics' fault handling (``guarded``) nor the
    badge's own ``except Exception`` turns it into a message."""


class BadgeStop:
    """A badge's cancellation, checked before each unit of work (``run``) and interrupting the unit in progress.

    ``physics.derived`` has no progress or cancel hook, and on many plane pendulums its linear theory runs for a
    second or more in Python (1.1 s for 24 bobs). So ``set`` raises
    BadgeCancelled in the thread running a unit (CPython's PyThreadState_SetAsyncExc: it fires at that thread's
    next bytecode boundary, once a numpy call in progress returns). It is sent only while the thread is inside
    ``run`` (under the lock), and one still pending as the unit returns fires as ``run`` leaves (``_let_fire``),
    so it never fires outside the worker's handler."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._set = False
        self._inside: int | None = None  # the thread id running a unit, if any
        self.interrupts = 0  # how many units were interrupted in progress (for tests)

    def is_set(self) -> bool:
        return self._set

    def set(self) -> None:
        with self._lock:
            if self._set:  # one interrupt at most: a second could reach a later thread given the same id
                return
            self._set = True
            if self._inside is not None and _async_raise(self._inside, BadgeCancelled):
                self.interrupts += 1

    def run(self, fn, *args):
        """fn(*args), unless cancelled before or during it (BadgeCancelled)."""
        with self._lock:
            if self._set:
                raise BadgeCancelled
            self._inside = threading.get_ident()
        try:
            return fn(*args)
        finally:
            with self._lock:
                self._inside = None
                sent = self.interrupts > 0
            if sent:  # an interrupt sent as fn returned fires here, inside the worker's handler
                _let_fire()


def _let_fire() -> None:
    """Run a few bytecode boundaries, where an asynchronous exception still pending for this thread is raised.
    Clearing one instead (PyThreadState_SetAsyncExc with NULL) leaves CPython 3.11's eval breaker signalled for
    the whole interpreter, and then any profiler or tracer (sys.setprofile, cProfile) spins forever at the next
    function call of every thread: only raising it clears the signal."""
    for _ in range(64):
        pass


def _async_raise(thread_id: int, exc: type[BaseException] | None) -> bool:
    """Raise ``exc`` in thread ``thread_id`` at its next bytecode boundary (None: clear a pending one).
    True if a thread was found."""
    return ctypes.pythonapi.PyThreadState_SetAsyncExc(ctypes.c_ulong(thread_id),
                                                      ctypes.py_object(exc) if exc is not None else None) == 1
