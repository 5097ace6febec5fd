"""What a typed slider value becomes, where its message goes, and the way back from a change. No viser here.

viser 1.1.1's slider number box (client/src/components/Slider.tsx, a Mantine NumberInput) sends every
keystroke that parses as a number whatever the slider's range, and clamps to the range only when it loses
focus, sending the clamped value then. Measured in chromium: typing -1 into m (range 0..1) sent -1, and
the next click elsewhere sent 0; typing 1000000 into Omega (0.5..60) sent 1, 10, ..., 1e6, then 60 on Tab.
viser's server passes both on unclamped. Hence:

- a value physics rejects (m = -1) is not applied: the message goes beside the slider, under it, and the
  slider goes back to the last good value once the user has stopped typing in its box;
- a value physics accepts but outside the slider's range (Omega = 1e6) is clamped to the range's end,
  with a note, rather than accepted with a warning: the browser clamps it anyway at the next click (so an
  accepted 1e6 would silently become 60 then), the knob cannot show it, and the range is what the explorer
  integrates at interactive speed (Omega = 1e6 gave E = 8.5e12 J, then a step size underflow). A scenario
  file takes any valid value;
- the browser's clamp-on-blur of an out-of-range value (the range's end, arriving just after it) is not
  the user's choice and is dropped, so a rejected m = -1 never becomes m = 0;
- a change (the updates one slider sends in a row: a drag, the keystrokes of one number) can be undone:
  the parameters and the run's state of just before it come back.
"""

from __future__ import annotations

import math
import re
import threading
import time
from dataclasses import dataclass

import numpy as np

import physics

from . import controls

# A slider set back while the user is still typing in its box mixes the typed digits with the value set
# back (typing 1000000 into Omega became "600": 100 was clamped to 60, then "0" was typed after it). viser
# tells the server nothing about focus, so a slider is set back once it has sent nothing for a while, or at
# once when the browser's clamp-on-blur says the user has left the box. On this 2-core machine under load
# (software WebGL), keys typed 80 ms apart in headless chromium reached the server 0.4 to 2.1 s apart.
TYPING_PAUSE_S = 3.0  # s without a new value from a slider before it is set back
ECHO_WINDOW_S = 0.3  # s after a slider is set back: a clamp-on-blur sent before it arrived is still dropped
UNDO_DEPTH = 20  # changes that can be undone one after another
FAULT = "fault"  # a LiveRun's status when the integration stopped on an error (physics/stepping/live.py, not exported)


@dataclass(frozen=True)
class Note:
    """A message beside the slider ``key``: ``kind`` is "rejected", "clamped" or "fault"; ``reason`` is
    physics's own text of a rejection (the engine's ``error``, which the top of the panel then omits)."""

    key: str | None
    kind: str
    text: str
    reason: str = ""


def _name(key: str) -> str:
    return controls.BY_KEY[key].label


def _with_unit(key: str, value: float) -> str:
    if not _number(value):  # a raw client's string, list or None: as it came, with no unit
        return repr(value)[:40]
    unit = controls.BY_KEY[key].unit
    return f"{controls.fmt(value)} {unit}".strip()


def rejected_text(key: str, value: float, reason: str, kept: float | None) -> str:
    """``reason``: physics's ScenarioError text ("mass.m = -1.0: must be > 0"). Its own key and value are
    dropped when they repeat the slider's; a reason about another parameter is kept whole."""
    head = f"{key} = "
    if reason.startswith(f"{head}{value!r}: "):  # the value as physics shows it, whatever its ": " inside
        reason = reason[len(f"{head}{value!r}: "):]
    elif reason.startswith(head) and ": " in reason:
        reason = reason.partition(": ")[2]
    p = controls.BY_KEY.get(key)
    if p is not None and _number(value) and value < 0 and re.search(r"\b0 = no", p.hint):
        reason += f" (0 removes the {key.partition('.')[0]})"  # a switch: the Param says that 0 means none
    stays = "" if kept is None else f" {_name(key)} stays {_with_unit(key, kept)}."
    return f"Rejected: {_name(key)} = {_with_unit(key, value)}: {reason.rstrip('.')}.{stays}"


def clamped_text(key: str, value: float, lo: float, hi: float, used: float) -> str:
    return (f"{_name(key)} = {_with_unit(key, value)} is outside this slider's range ({controls.fmt(lo)} to "
            f"{controls.fmt(hi)}): set to {_with_unit(key, used)}, the range the explorer runs at interactive "
            "speed. A scenario file (File, Load scenario) takes any valid value.")


def shown_note(guard: Guard, status: str, message: str) -> Note | None:
    """The note the panel shows now: a fault's (with its way out) while the run is stopped by one, else the
    guard's last note about a typed value."""
    if status == FAULT:
        return Note(guard.last_key, "fault", fault_text(message, guard.last_key))
    return guard.note


def fault_text(message: str, key: str | None) -> str:
    after = f" after {_name(key)} was changed" if key else ""
    return (f"The run stopped{after}: {message.rstrip('.')}. Undo the last change (its parameters and the state "
            "of just before it come back) or reset the scene (its parameters as loaded, from t = 0).")


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Guard:
    """Per tab: the limits each slider had when it sent a value, the browser's clamp echoes to drop, the
    note beside a slider, and the undo stack. ``received`` runs on GUI threads under the engine's lock;
    the rest on the loop thread."""

    def __init__(self):
        self._lock = threading.Lock()  # received() runs on GUI threads; take_dropped() on the loop thread
        self._dropped: set[str] = set()  # sliders whose browser echo was dropped: the browser shows it
        self._typed_at: dict[str, float] = {}  # slider key -> when it last sent a value (perf_counter s)
        self.epoch = 0  # bumped by every fresh start of the buffers (engine._restarted)
        self.loaded: tuple | None = None  # (scenario, name) as loaded: what "reset the scene" reloads
        self.limits: dict[str, tuple[float, float]] = {}  # slider key -> (min, max) it showed
        self._echo: dict[str, tuple[float, float | None]] = {}  # key -> (value to drop, applied at)
        self.note: Note | None = None
        self.rejections: list[str] = []  # physics's reasons for the values the last screen rejected
        self.screened: physics.Scenario | None = None  # what the last screen built with the values it accepted
        self.revert: dict[str, float] = {}  # sliders the session pushes back to these (last good) values
        self.undo: list[Snapshot] = []
        self._chain: str | None = None  # key of the change in progress (a drag): later values extend it
        self._chain_at = -math.inf  # when it last moved: after TYPING_PAUSE_S, the same slider starts a new one
        self.last_key: str | None = None  # the slider of the last applied change: a fault's note goes there

    # ---- GUI threads ---------------------------------------------------------------------------------
    def received(self, key: str, value, limits: tuple[float, float] | None) -> bool:
        """Record a slider's ``limits`` with its value; False for the browser's clamp of a value out of range
        (drop it), sent before the slider was set back or just after. ``key``: the slider's (no bob suffix)."""
        with self._lock:
            now = time.perf_counter()
            echo = self._echo.pop(key, None)
            if echo is not None and _number(value) and value == echo[0]:
                if echo[1] is None or now - echo[1] < ECHO_WINDOW_S:
                    self._dropped.add(key)  # the browser now shows the echo: the slider must be set back
                    self._typed_at.pop(key, None)  # and the user has left the box: at once
                    return False
            self._typed_at[key] = now
            if limits is not None:
                self.limits[key] = (float(limits[0]), float(limits[1]))
                lo, hi = self.limits[key]
                if _number(value) and not lo <= value <= hi and math.isfinite(value):
                    self._echo[key] = (min(max(value, lo), hi), None)
            return True

    def take_revert(self, now: float | None = None) -> dict[str, float]:
        """Sliders to set back now (loop thread), to their last good value or a clamped one: those that have
        sent nothing for TYPING_PAUSE_S. From then on, their echo window runs."""
        now = time.perf_counter() if now is None else now
        with self._lock:
            ready = {k: v for k, v in self.revert.items() if now - self._typed_at.get(k, -math.inf) >= TYPING_PAUSE_S}
            for key in ready:
                del self.revert[key]
                if key in self._echo:
                    self._echo[key] = (self._echo[key][0], now)
            return ready

    def take_dropped(self) -> set[str]:
        with self._lock:
            dropped, self._dropped = self._dropped, set()
            return dropped

    # ---- loop thread ---------------------------------------------------------------------------------
    def screen(self, base: physics.Scenario, changes: dict, pending: dict, values: dict) -> dict:
        """``pending`` without the values physics rejects, out-of-range values clamped. Sets ``note`` (the
        last one wins), ``revert`` (sliders to push back) and the rejections' text (``rejections``), and
        ``screened``: the scenario ``base`` becomes with the accepted values, built while judging the last of
        them (None when a value was let through unjudged), so that applying them need not build it again."""
        accepted: dict = {}
        self.rejections = []
        self.screened = None
        fresh = False
        for full_key, value in pending.items():
            key = full_key.partition("#")[0]
            if key not in controls.BY_KEY or not _number(value):
                accepted[full_key] = value  # not a slider value: apply_changes judges it
                self.screened = None
                continue
            reason, built = _judged(base, changes, accepted, full_key, value)
            lo, hi = self.limits.get(key, (-math.inf, math.inf))
            if reason is None and not lo <= value <= hi:
                used = min(max(value, lo), hi)
                reason, built = _judged(base, changes, accepted, full_key, used)
                if reason is None:
                    self.note, fresh = Note(key, "clamped", clamped_text(key, value, lo, hi, used)), True
                    self.revert[key] = used
                    accepted[full_key] = used
                    self.screened = built  # with every value accepted so far
                    continue
            if reason is not None:
                kept = values.get(key)
                self.note, fresh = Note(key, "rejected", rejected_text(key, value, reason, kept), reason), True
                self.rejections.append(reason)
                if kept is not None:
                    self.revert[key] = kept
                continue
            accepted[full_key] = value
            self.screened = built  # with every value accepted so far
            self.revert.pop(key, None)  # a good value typed since: nothing to set back
        if accepted and not fresh:
            self.note = None  # an accepted edit: an older note no longer describes the panel
        return accepted

    def failed(self, accepted: dict, pushed: bool, values: dict, exc: Exception) -> None:
        """``accepted`` passed the screen but applying them raised ``exc``: nothing changed, so no undo
        step, and their sliders go back, with the reason beside the last one."""
        if pushed:
            self.undo.pop()
            self._chain = None
        for full_key, value in accepted.items():
            key = full_key.partition("#")[0]
            if key in values:
                self.revert[key] = values[key]
                self.note = Note(key, "rejected", rejected_text(key, value, str(exc), values[key]), str(exc))

    def before_change(self, accepted: dict, engine) -> bool:
        """Called before ``accepted`` values are applied: a new change starts (and is saved for undo) unless
        they continue the change in progress (one slider's drag or typing). True when one was saved."""
        keys = {k.partition("#")[0] for k in accepted}
        key = next(iter(keys)) if len(keys) == 1 else None
        self.last_key = key or next(reversed(accepted)).partition("#")[0]
        now, before = time.perf_counter(), self._chain_at
        self._chain_at = now
        if key is not None and self._chain == key and now - before < TYPING_PAUSE_S:
            return False  # the same drag or number: one change
        self._chain = key
        self.undo.append(Snapshot.of(engine, self.last_key, self.epoch))
        del self.undo[:-UNDO_DEPTH]
        return True

    def take_undo(self) -> Snapshot | None:
        """The last change's snapshot (None when nothing can be undone); the next value starts a new change."""
        self._chain = self.last_key = None  # which slider came before is not known: a fault's note goes on top
        self.note = None
        return self.undo.pop() if self.undo else None

    def interrupt(self) -> None:
        """An action came between: the next value starts a new change."""
        self._chain = None

    def forget(self, scenario: physics.Scenario, name: str) -> None:
        """A new scene (``scenario`` loaded as ``name``): nothing before it can be undone, no note describes it."""
        self.loaded = (scenario, name)
        self.undo.clear()
        self._chain = self.last_key = self.note = None
        self.revert.clear()


@dataclass
class Snapshot:
    """What undoing a change restores: the scene's parameters and the run (parameters and state)."""

    key: str
    base: physics.Scenario
    changes: dict
    values: dict
    item: int | None  # the array table's item the sliders edit
    fidelity: str
    accuracy: float | None  # auto's
    choices: dict  # the systems' choice actions' options
    run_state: dict
    epoch: int  # the buffers' start it belongs to: a change that restarted the run started new ones
    n_edits: int  # the engine's list of edits the run went through, up to this change
    edit_count: int | None  # and their count
    retunes: list | None = None  # the engine's log of changes for a replay (app.replay.record), up to this change

    @classmethod
    def of(cls, engine, key: str, epoch: int) -> Snapshot:
        state = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in vars(engine.run).items()}
        return cls(key, engine.base, dict(engine.changes), dict(engine.values), engine.item, engine.fidelity_choice,
                   engine.accuracy_choice, dict(engine.choices), state, epoch, len(getattr(engine, "edits", ())),
                   getattr(engine, "edit_count", None), getattr(engine, "retunes", None))

    def restore(self, engine) -> float:
        """Put the parameters and the run back (the run object stays the same: whoever holds it sees the
        restored one). Everything the engine set after this snapshot goes, a later fidelity choice too.
        Returns the restored t."""
        run = engine.run
        vars(run).clear()
        vars(run).update({k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in self.run_state.items()})
        engine.base, engine.changes, engine.values = self.base, dict(self.changes), dict(self.values)
        engine.item, engine.fidelity_choice, engine.accuracy_choice = self.item, self.fidelity, self.accuracy
        engine.choices = dict(self.choices)
        if isinstance(getattr(engine, "edits", None), list):
            del engine.edits[self.n_edits:]
        if hasattr(engine, "retunes"):
            engine.retunes = self.retunes  # the log is replaced on each change, never changed in place
        if self.edit_count is not None:
            engine.edit_count = self.edit_count
        return float(run.t)


def _judged(base, changes, accepted, full_key, value) -> tuple[str | None, physics.Scenario | None]:
    """(why physics rejects ``value``, None) or (None, the scenario with it and the values accepted before)."""
    try:
        return None, controls.apply_changes(base, controls.merge_changes(changes, {**accepted, full_key: value}))
    except physics.ScenarioError as exc:
        return str(exc), None


def rewind(buffer, t: float) -> None:
    """Drop a buffer's rows (time in column 0) from ``t`` on: undo turns the clock back to ``t`` and records
    the restored state's row again (the change may have added a row at ``t`` itself). Any buffer with
    ``values``, ``clear`` and ``extend`` (a Ring, a DecimatingStore)."""
    rows = buffer.values()
    if len(rows) and rows[-1, 0] >= t:
        buffer.clear()
        buffer.extend(rows[rows[:, 0] < t])
