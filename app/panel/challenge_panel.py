"""The Braking challenge folder of one tab's panel (issue 25, point 2): a level and a start number (a seed), Start,
six thruster buttons that fire while held, their keys, End, and the race in words. Callbacks only queue the engine's
"challenge" and "thrust" actions (app.engine.challenge); the optimal law's body is compare mode's second body.

A held key fires as a held button does: the page script below turns a key's press and release into the
button's pointer press and release, so that viser's client repeats the button's hold message (10 a second)
until the key is let go. Keys typed into a text box are left alone, and a page that loses focus lets go.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass

from ..engine import challenge

HOLD_HZ = 10.0  # viser's client repeats a held button's message this often; the engine's HOLD_S spans 5 of them
START, END, OFF = "Start the challenge", "End the challenge", "Thrusters off"
INTRO = ("Stop the spinning body with thrusters of torque b along its axes e1, e2, e3, faster than the time-optimal "
         "law -b K/|K| (Zinkevich et al.) whose body runs beside yours. Hold a button or its key; it stops when "
         "you let go. The score is T / T_you when your |K| falls below 1 % of its start; the same level "
         "and start number give everyone the same start.")


def button_label(thruster: str) -> str:
    return f"{thruster} · key {challenge.KEYS[thruster]}"


KEYS_LINE = ("keys during a race: " + " · ".join(f"**{challenge.KEYS[t]}** {t}" for t in challenge.THRUSTERS)
             + " (otherwise they move the camera, as in viser)")


@dataclass(frozen=True)
class ClassChallenge:
    """What a class shares with a tab's folder (app.serve.scoreboard): ``choice()`` the level and start number the
    lecturer last raced (None before), which a student's folder starts from; ``chose(level, start)``, the lecturer's
    Start; ``post(name, title, score, seconds)``, a student's attempt that stopped; ``board()``, the scores in words
    for the lecturer's tab."""

    choice: Callable[[], tuple[str, int] | None]
    chose: Callable[[str, int], None] | None = None
    post: Callable[..., None] | None = None
    board: Callable[[], str] | None = None


class ChallengePanel:
    """Widgets in a "Braking challenge" folder, for one tab's ``engine``; ``klass``: the class's side, in class
    mode."""

    def __init__(self, gui, engine, klass: ClassChallenge | None = None):
        self.engine = engine
        self.klass = klass
        self._posted = None  # the attempt whose score went to the class
        self.titles = {challenge.level_title(level): level for level in challenge.LEVELS}
        level, seed = (klass.choice() if klass is not None else None) or (challenge.LEVELS[0], 0)
        with gui.add_folder("Braking challenge", expand_by_default=False):
            gui.add_markdown(INTRO)
            self.level = gui.add_dropdown("level", list(self.titles), initial_value=challenge.level_title(level),
                                          hint="the rigid body; with the medium; with the moving mass (nutation "
                                               "makes aiming hard); a prolate body")
            self.seed = gui.add_number("start number", initial_value=seed, min=0, max=challenge.SEEDS - 1, step=1,
                                       hint="picks the start's nutation angle: the same number, the same start")
            self.name = None
            if klass is not None and klass.post is not None:
                self.name = gui.add_text("your name (optional)", initial_value="",
                                         hint="shown beside your score in the lecturer's list of the class's scores")
            self.start = gui.add_button(START, hint="loads the level's scene from t = 0, in real time")
            self.race_md = gui.add_markdown("")  # above the buttons: in sight while a student aims
            self.keys_md = gui.add_markdown(KEYS_LINE)
            self.thrusters = {}
            for t in challenge.THRUSTERS:
                button = gui.add_button(button_label(t), hint=f"fires a torque b along {t} of the body while held")
                button.on_hold(self._fire(t), callback_hz=HOLD_HZ)
                button.on_click(self._fire(t))  # Enter or Space on a focused button: one press
                self.thrusters[t] = button
            self.off = gui.add_button(OFF, hint="stops the thruster at once; letting go of a thruster's key or "
                                                 "button presses this too")
            self.off.on_click(lambda _event: engine.request("thrust", "off"))
            self.end = gui.add_button(END, hint="ends the attempt; the scene stays")
            self.board_md = gui.add_markdown("") if klass is not None and klass.board is not None else None

        @self.start.on_click
        def _(_event):
            level = self.titles.get(self.level.value)
            if level is None:
                engine.error = (f"level: {str(self.level.value)[:40]!r} refused; expected one of "
                                + ", ".join(self.titles))
                return
            try:
                challenge.start_angle(self.seed.value)  # refused here, before the class hears of it
            except ValueError as exc:
                engine.error = str(exc)
                return
            engine.request("challenge", (level, self.seed.value))
            if klass is not None and klass.chose is not None:  # the lecturer's race: the class's start
                klass.chose(level, int(self.seed.value))

        @self.end.on_click
        def _(_event):
            engine.request("challenge", "off")

    def _fire(self, thruster: str):
        def fire(_event):
            self.engine.request("thrust", thruster)
        return fire

    def update(self) -> None:
        """The race in words (empty without an attempt); in a class, a student's score posted once, the lecturer's
        list of scores."""
        md = challenge.readout_md(self.engine)
        if self.race_md.content != md:
            self.race_md.content = md
        ch, klass = self.engine.challenge, self.klass
        if klass is None:
            return
        if klass.post is not None and ch is not None and ch.score is not None and self._posted is not ch:
            self._posted = ch
            klass.post(self.name.value if self.name is not None else "", ch.title, ch.score, ch.finished_at)
        if self.board_md is not None:
            board = klass.board()
            if self.board_md.content != board:
                self.board_md.content = board


_KEYS_JS = json.dumps({challenge.KEYS[t].lower(): button_label(t) for t in challenge.THRUSTERS})
PAGE_SCRIPT = (b"""<script>/* Quasirigid (app/panel/challenge_panel.py): a held key holds its thruster's button */
(function () {
  var keys = KEYS_JS, held = {};
  function button(label) {
    var all = document.querySelectorAll("button");
    for (var i = 0; i < all.length; i++) if (all[i].textContent.trim() === label) return all[i];
    return null;
  }
  function typing(e) {
    var t = e.target, tag = t && t.tagName;
    return tag === "INPUT" || tag === "TEXTAREA" || tag === "SELECT" || (t && t.isContentEditable);
  }
  function send(b, type) {
    b.dispatchEvent(new PointerEvent(type, {bubbles: true, cancelable: true, button: 0, pointerId: 7,
                                            pointerType: "mouse", isPrimary: true}));
  }
  function racing() {  /* the race's words are on the page and it is not over: the keys are the thrusters' */
    var ps = document.querySelectorAll("p");
    for (var i = 0; i < ps.length; i++) {
      var t = ps[i].textContent;
      if (t.indexOf("Braking challenge \\u00b7") !== 0) continue;
      return t.indexOf("score T / T_you") < 0 && t.indexOf("out of time:") < 0;
    }
    return false;
  }
  function off() { var b = button("OFF_LABEL"); if (b) b.click(); }  /* "off" now, not after the hold's timeout */
  function release(k) { var b = held[k]; delete held[k]; if (b) { send(b, "pointerup"); off(); } }
  var labels = {};
  for (var k in keys) labels[keys[k]] = true;
  document.addEventListener("pointerup", function (e) {  /* a thruster's button let go by a mouse or a finger */
    var b = e.isTrusted && e.target && e.target.closest ? e.target.closest("button") : null;
    if (b && labels[b.textContent.trim()]) off();
  }, true);
  /* on the window, capturing: before viser's camera, which moves on the same keys (W A S D Q E) */
  window.addEventListener("keydown", function (e) {
    var k = (e.key || "").toLowerCase();
    if (!(k in keys) || e.ctrlKey || e.metaKey || e.altKey || typing(e)) return;
    if (!held[k] && !racing()) return;  /* no race: the camera's keys as usual */
    e.preventDefault();
    e.stopPropagation();
    if (e.repeat || held[k]) return;
    var b = button(keys[k]);
    if (!b || b.disabled) return;
    held[k] = b;
    send(b, "pointerdown");
  }, true);
  window.addEventListener("keyup", function (e) {
    var k = (e.key || "").toLowerCase();
    if (held[k]) { e.stopPropagation(); release(k); }
  }, true);
  window.addEventListener("blur", function () { for (var k in held) release(k); });
})();
</script>""").replace(b"KEYS_JS", _KEYS_JS.encode()).replace(b"OFF_LABEL", OFF.encode())
