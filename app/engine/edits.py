"""What a typed slider value becomes, where its message goes, and the way back from a change. No viser here.

viser 1.1.1's slider number box (client/src/components/Slider.tsx, a Mantine NumberInput) dropped the characters
it did not expect before sending (``1e-3`` arrived as -13, ``1,5`` as 15) and clamped to the slider's range when
it lost focus. The page's script (``app.panel.typed_numbers``) keeps the box from sending anything: it sends the
text as typed, read here (``app.engine.typed``). Hence:

- a value physics rejects (m = -1, m = 1e308) is not applied: the message goes beside the slider, under it,
  quoting what was typed, and the slider shows the last good value (at once for a typed value, once the user
  has stopped dragging for a slider's own moves);
- a text that is no number (``abc``, an empty box) is refused the same way;
- a value physics accepts is applied, even outside the slider's usual span: nothing is clamped. The slider's
  span widens to show it (``controls.slider_range``), and a note says the span was widened;
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

from . import controls, typed

# A slider set back while the user still drags it fights the hand; viser tells the server nothing about the
# mouse, so a slider's own rejected value is set back once it has sent nothing for a while. A typed value comes
# once, when the box is left or Enter is pressed: it is set back at once.
TYPING_PAUSE_S = 3.0  # s without a new value from a slider before it is set back
UNDO_DEPTH = 20  # changes that can be undone one after another
FAULT = "fault"  # a LiveRun's status when the integration stopped on an error (physics/stepping/live.py, not exported)


@dataclass(frozen=True)
class Note:
    """A message beside the slider ``key``: ``kind`` is "rejected", "widened", "read" or "fault"; ``reason`` is
    physics's own text of a rejection (the engine's ``error``, which the top of the panel then omits)."""

    key: str | None
    kind: str
    text: str
    reason: str = ""


def _name(key: str) -> str:
    return controls.BY_KEY[key].label


def _with_unit(key: str, value: float, text: str | None = None) -> str:
    """``value`` with the slider's unit; ``text``: as the user typed it, quoted instead of the number."""
    if text is not None:  # a number as typed (app.engine.typed read it): 1e308, 1,5
        return f"{text.strip()} {controls.BY_KEY[key].unit}".strip()
    if not is_number(value):  # a raw client's string, list or None: as it came, with no unit
        return repr(value)[:40]
    unit = controls.BY_KEY[key].unit
    return f"{controls.fmt(value)} {unit}".strip()


def rejected_text(key: str, value: float, reason: str, kept: float | None, text: str | None = None) -> str:
    """``reason``: physics's ScenarioError text ("mass.m = -1.0: must be > 0"). Its own key and value are
    dropped when they repeat the slider's; a reason about another parameter is kept whole."""
    head = f"{key} = "
    if reason.startswith(f"{head}{value!r}: "):  # the value as physics shows it, whatever its ": " inside
        reason = reason[len(f"{head}{value!r}: "):]
    elif reason.startswith(head) and ": " in reason:
        reason = reason.partition(": ")[2]
    p = controls.BY_KEY.get(key)
    if p is not None and is_number(value) and value < 0 and re.search(r"\b0 = no", p.hint):
        reason += f" (0 removes the {key.partition('.')[0]})"  # a switch: the Param says that 0 means none
    stays = "" if kept is None else f" {_name(key)} stays {_with_unit(key, kept)}."
    return f"Rejected: {_name(key)} = {_with_unit(key, value, text)}: {reason.rstrip('.')}.{stays}"


def widened_text(key: str, value: float, text: str | None = None) -> str:
    """A value beyond the slider's usual span, applied: the span now reaches it."""
    p = controls.BY_KEY[key]
    lo, hi = controls.slider_range(p, value)
    read = "" if text is None else f" (typed {typed.shown(text)})"
    return (f"{_name(key)} = {_with_unit(key, value)}{read} is outside the slider's usual span ({controls.fmt(p.lo)} "
            f"to {controls.fmt(p.hi)}): applied, and the slider now spans {controls.fmt(lo)} to {controls.fmt(hi)}. "
            "Far outside it a run may need many more steps.")


def read_text(key: str, value: float, text: str) -> str:
    """A value typed with a decimal comma, applied: how it was read."""
    return f"{_name(key)}: {typed.shown(text)} read as {_with_unit(key, value)} (a decimal comma)."


def unreadable_text(key: str, text: str, why: str, kept: float | None) -> str:
    """A typed text that is no number (``app.engine.typed``)."""
    stays = "" if kept is None else f" {_name(key)} stays {_with_unit(key, kept)}."
    if not str(text).strip():
        return f"{_name(key)}: {why}; nothing changed.{stays}"
    return f"Rejected: {_name(key)} = {typed.shown(text)}: {why}.{stays}"


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


def is_number(value) -> bool:
    """A number a slider can take and show (not a word such as "resonant", None, a bool, a list or a table)."""
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class Guard:
    """Per tab: the typed texts of the values received, the note beside a slider, the sliders to set back and the
    undo stack. ``received`` and ``unreadable`` run on GUI threads under the engine's lock; the rest on the loop
    thread."""

    def __init__(self):
        self._lock = threading.Lock()  # received() runs on GUI threads; take_revert() on the loop thread
        self._typed_at: dict[str, float] = {}  # slider key -> when it last sent a value (perf_counter s)
        self._texts: dict[str, str] = {}  # slider key -> the text its pending value was typed as
        self.epoch = 0  # bumped by every fresh start of the buffers (engine._restarted)
        self.loaded: tuple | None = None  # (scenario, name) as loaded: what "reset the scene" reloads
        self.note: Note | None = None
        self.rejections: list[str] = []  # physics's reasons for the values the last screen rejected
        self.screened: physics.Scenario | None = None  # what the last screen built with the values it accepted
        self.revert: dict[str, float] = {}  # slider -> the value it must show: the last good, or a typed one
        self.undo: list[Snapshot] = []
        self._chain: str | None = None  # key of the change in progress (a drag): later values extend it
        self._chain_at = -math.inf  # when it last moved: after TYPING_PAUSE_S, the same slider starts a new one
        self.last_key: str | None = None  # the slider of the last applied change: a fault's note goes there

    # ---- GUI threads ---------------------------------------------------------------------------------
    def received(self, key: str, value, text: str | None = None) -> None:
        """A slider's value arrived; ``text``: what the user typed into its box (its value is then set back at
        once if refused), None for the slider's own move. ``key``: the slider's (no bob suffix)."""
        with self._lock:
            self._typed_at[key] = -math.inf if text is not None else time.perf_counter()
            if text is not None:
                self._texts[key] = text
            else:
                self._texts.pop(key, None)

    def unreadable(self, key: str, text: str, why: str, kept: float | None) -> None:
        """A text typed into ``key``'s box that is no number: refused, with ``why``; nothing is applied."""
        self.note = Note(key, "rejected", unreadable_text(key, text, why, kept), why)

    def take_revert(self, now: float | None = None) -> dict[str, float]:
        """Sliders to set back now (loop thread), to their last good value: those that have sent nothing for
        TYPING_PAUSE_S, and typed ones at once."""
        now = time.perf_counter() if now is None else now
        with self._lock:
            ready = {k: v for k, v in self.revert.items() if now - self._typed_at.get(k, -math.inf) >= TYPING_PAUSE_S}
            for key in ready:
                del self.revert[key]
            return ready

    # ---- loop thread ---------------------------------------------------------------------------------
    def screen(self, base: physics.Scenario, changes: dict, pending: dict, values: dict) -> dict:
        """``pending`` without the values physics rejects. Sets ``note`` (the last one wins), ``revert`` (sliders
        to push back) and the rejections' text (``rejections``), and ``screened``: the scenario ``base`` becomes
        with the accepted values, built while judging the last of them (None when a value was let through
        unjudged), so that applying them need not build it again. A value outside its slider's usual span is
        applied (the panel widens the span), with a note."""
        accepted: dict = {}
        self.rejections = []
        self.screened = None
        fresh = False
        with self._lock:
            texts = {k: self._texts.pop(k) for k in list(self._texts) if any(f.partition("#")[0] == k for f in pending)}
        for full_key, value in pending.items():
            key = full_key.partition("#")[0]
            if key not in controls.BY_KEY or not is_number(value):
                accepted[full_key] = value  # not a slider value: apply_changes judges it
                self.screened = None
                continue
            text = texts.get(key)
            reason, built = _judged(base, changes, accepted, full_key, value)
            if reason is not None:
                kept = values.get(key)
                self.note = Note(key, "rejected", rejected_text(key, value, reason, kept, text), reason)
                fresh = True
                self.rejections.append(reason)
                if kept is not None:
                    self.revert[key] = kept
                continue
            accepted[full_key] = value
            self.screened = built  # with every value accepted so far
            self.revert.pop(key, None)  # a good value typed since: nothing to set back
            if text is not None:
                self.revert[key] = value  # the slider (moved by no one) shows the value typed, now running
            p = controls.BY_KEY[key]
            if not p.lo <= value <= p.hi:
                self.note, fresh = Note(key, "widened", widened_text(key, value, text)), True
            elif text is not None and "," in text:  # read with a decimal comma (app.engine.typed)
                self.note, fresh = Note(key, "read", read_text(key, value, text)), True
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
