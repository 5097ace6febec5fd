"""Play, Pause, Step and Reset where a lecturer reaches them: one row of buttons at the top of the panel, above
the status line, whose length changes as the run plays, so the row never moves under the pointer (visible
without scrolling at 1024x768), and the keys of MuJoCo's viewer, listed on the page: Space plays or pauses,
R resets, the right arrow steps.

The keys are viser commands (``gui.add_command``, also in its command palette, Ctrl+K). The page ignores
them while a text box has focus; a focused slider takes the arrow keys itself, and the page sends the
step as well, so a keyed step waits STEP_DEFER_S and is dropped when a slider value came within
STEP_DEFER_S of it, before or after.
"""

from __future__ import annotations

import threading
import time

BUTTONS = {"Play": "play", "Pause": "pause", "Step": "step", "Reset": "reset"}
# viser hotkey -> (what the page lists, the engine's action)
KEYS = {"space": ("Space", "toggle"), "R": ("R", "reset"), "arrowright": ("→", "step")}
KEYS_LINE = "keys: **Space** play/pause · **R** reset · **→** step"
STEP_DEFER_S = 0.25  # s: the browser sends a slider's value within 50 ms of the key (one message per 50 ms)


class Playbar:
    """The row of buttons, the keys and the line that lists them, for one tab's ``engine``."""

    def __init__(self, gui, engine):
        self.engine = engine
        self.buttons = gui.add_button_group("Run", tuple(BUTTONS), hint="or the keys listed below")
        self.keys_md = gui.add_markdown(KEYS_LINE)
        self.commands = []

        @self.buttons.on_click
        def _(_event):
            engine.request(BUTTONS[self.buttons.value])

        for key, (shown, action) in KEYS.items():
            cmd = gui.add_command(f"{action.capitalize()} ({shown})", hotkey=key,
                                  description=f"the {shown} key: {'play or pause' if action == 'toggle' else action}")
            cmd.on_trigger(self._keyed(action))
            self.commands.append(cmd)

    def _keyed(self, action: str):
        def trigger(_event):
            if action != "step":
                self.engine.request(action)
                return
            timer = threading.Timer(STEP_DEFER_S, self._step_unless_slider, args=(time.monotonic(),))
            timer.daemon = True
            timer.start()
        return trigger

    def _step_unless_slider(self, pressed: float) -> None:
        # the slider's value and the key's command reach the server in either order, within milliseconds
        if abs(self.engine.value_requested_at - pressed) > STEP_DEFER_S:  # no slider took this key
            self.engine.request("step")
