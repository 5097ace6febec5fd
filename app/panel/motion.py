"""A browser that asks for reduced motion (``prefers-reduced-motion: reduce``, an operating system setting) gets
a tab that starts paused at t = 0 and says why in the status line until the user presses Play (WCAG 2.2.2: the
moving 3-D view can be paused, and here it does not start moving by itself).

The page's script (app.share.link) writes the browser's answer into its storage under MOTION_KEY before viser's
client starts; this reads it when the tab connects, on a thread of its own, as the Share folder reads the last
scene. The run plays for the moment that takes and is then put back to t = 0, so what the user first sees
playing is what they started.
"""

from __future__ import annotations

import threading

from ..share.link import MOTION_KEY
from ..share.panel import READ_TIMEOUT  # the same wait as for the stored scenes: a busy tab answers late

REDUCE = "reduce"  # the value the page's script writes when the browser asks for reduced motion
NOTE = "paused because this browser asks for reduced motion: press Play (or Space) to start"


class ReducedMotion:
    """Reads the browser's motion preference once; pauses and resets the tab's run if it asks for less."""

    def __init__(self, client, engine, read: bool = True):
        self.client, self.engine = client, engine
        self.asked = False  # the browser asked for reduced motion and the run was paused for it
        self._played = False  # the user has pressed Play since: the note has done its job
        self._seq = 0  # the engine's change that paused the run (playing until it is applied is not the user's)
        if read:
            threading.Thread(target=self.read, name="motion-preference", daemon=True).start()

    def read(self) -> None:
        storage = getattr(self.client, "local_storage", None)
        if storage is None:  # a client without a browser behind it (a test's stand-in)
            return
        try:
            answer = storage.get_item(MOTION_KEY, timeout=READ_TIMEOUT)
        except (RuntimeError, TimeoutError):  # storage blocked, the tab closed, or silent: the run plays on
            return
        if answer == REDUCE:
            self.engine.request("pause")
            self._seq = self.engine.request("reset")
            self.asked = True

    def status(self) -> str:
        """The status line's note while the run waits for the user's Play, else nothing."""
        if not self.asked or self._played:
            return ""
        if self.engine.playing and self.engine.applied_seq >= self._seq:
            self._played = True
            return ""
        return f" · {NOTE}"
