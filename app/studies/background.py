"""One study at a time in the background, for the sweep and design panels: Run starts it on a daemon thread unless
one is running, bad input is said before anything starts, Stop asks it to end, and whatever ends it is said in the
panel (its status line, and its results window while that shows no result), never raised into viser."""

from __future__ import annotations

import threading

from . import results_window


class BackgroundStudy:
    """A panel's study lifecycle. The panel makes ``status``, ``result_md``, ``bar``, ``run_btn`` and ``stop_btn``,
    and says what its study is: ``NOUN`` (the buttons' word), ``has_result()``, ``prepare()`` and ``work(*args)``."""

    NOUN = "study"

    def __init__(self):
        self.thread: threading.Thread | None = None
        self.stop = threading.Event()

    def has_result(self) -> bool:
        """Whether the results window shows a result (which news then leaves alone)."""
        raise NotImplementedError

    def prepare(self) -> tuple[tuple, str]:
        """The study's arguments for ``work`` and the words that announce it; raises on bad input."""
        raise NotImplementedError

    def work(self, *args) -> None:
        """Run the study and show what it found (on the study's thread)."""
        raise NotImplementedError

    def _say(self, text: str) -> None:
        self.status.content = text

    def start(self) -> threading.Thread | None:
        """Start the study on a daemon thread (not while one runs); returns the thread, or None."""
        if self.thread is not None and self.thread.is_alive():
            self._say(f"A {self.NOUN} is running; **Stop {self.NOUN}** ends it.")
            return None
        try:
            args, announce = self.prepare()
        except Exception as exc:  # noqa: BLE001 - shown, never raised into viser
            results_window.say(self.status, self.result_md, f"**Cannot start:** {results_window.failure(exc)}",
                               self.has_result())
            return None
        self.stop.clear()
        self.bar.value = 0.0
        self.run_btn.disabled, self.stop_btn.disabled = True, False
        results_window.say(self.status, self.result_md, announce, self.has_result())
        self.thread = threading.Thread(target=self._run, args=args, name=self.NOUN, daemon=True)
        self.thread.start()
        return self.thread

    def _run(self, *args) -> None:
        try:
            self.work(*args)
        except Exception as exc:  # noqa: BLE001 - the panel reports, the server goes on
            results_window.say(self.status, self.result_md,
                               f"**{self.NOUN.capitalize()} failed:** {results_window.failure(exc)}",
                               self.has_result())
        finally:
            self.run_btn.disabled, self.stop_btn.disabled = False, True
