"""The page's "Download replay (HTML)" button: the tab's run, recorded from t = 0 with the changes made on the
way (Engine.retunes) into one HTML file (app.replay.record) that the browser downloads. It records in a thread of its
own, on a copy of the scene, so the tab's run goes on; a line under the button says what it is doing and where
the file went.
"""

from __future__ import annotations

import re
import threading
import traceback

from ..engine.engine import Engine

MIN_SECONDS = 5.0  # a replay shorter than this shows little
MAX_SECONDS = 60.0  # played seconds the button records at most: the default scene: 1.4 MB, 3-5 s of work
FILE_NAME = "quasirigid-replay.html"


def replay_seconds(eng: Engine) -> float:
    """Played seconds to record: as long as the tab has played (its simulated time over its warp), within
    [MIN_SECONDS, MAX_SECONDS]."""
    played = eng.run.t / max(eng.warp, 1e-9)
    return float(min(MAX_SECONDS, max(MIN_SECONDS, played)))


def file_name(title: str) -> str:
    """quasirigid-replay-<the scene's name, as letters, digits and dashes>.html"""
    slug = re.sub(r"[^A-Za-z0-9]+", "-", title).strip("-").lower()[:40]
    return f"quasirigid-replay-{slug}.html" if slug else FILE_NAME


class ReplayButton:
    """A button and its status line, in the folder being built (the panel's File folder)."""

    def __init__(self, gui, engine: Engine, client):
        self.engine = engine
        self.client = client
        self.busy = threading.Lock()
        self.button = gui.add_button("Download replay (HTML)", hint="this run from t = 0, changes included, with its "
                                     "plots and scenario, in one HTML file any browser plays offline")
        self.status = gui.add_markdown("")

        @self.button.on_click
        def _(event):
            self.start(event.client or self.client)

    def start(self, client) -> None:
        if not self.busy.acquire(blocking=False):
            self.status.content = "A replay is being recorded already; it downloads when done."
            return
        threading.Thread(target=self._run, args=(client,), name="replay-export", daemon=True).start()

    def _run(self, client) -> None:
        from .record import copy_of_tab, record

        try:
            eng = self.engine
            seconds = replay_seconds(eng)
            title = eng.preset + (" (edited)" if eng.edited else "")
            self.status.content = f"Recording a replay: {seconds:.0f} s of {title} from t = 0..."

            def progress(fraction: float) -> None:
                self.status.content = f"Recording a replay: {seconds:.0f} s of {title} from t = 0... " \
                                      f"{100 * fraction:.0f}%"

            replay = record(None, seconds, title=title, engine=copy_of_tab(eng), progress=progress,
                            changes=eng.retunes or [])  # the changes the run went on through, at their t
            name = file_name(title)
            client.send_file_download(name, replay.html.encode(), save_immediately=True)
            size = replay.size / 2**20
            self.status.content = (f"Replay downloaded as **{name}** ({size:.1f} MB, {replay.seconds:.0f} s at "
                                   f"{replay.warp:.3g}x): your browser saved it in its downloads folder; open it in "
                                   "any browser, offline.")
        except Exception as exc:  # a replay that cannot be made says why; the tab runs on
            traceback.print_exc()
            self.status.content = f"<span style='color:#c00'>The replay could not be made: {type(exc).__name__}: " \
                                  f"{str(exc)[:160]}</span>"
        finally:
            self.busy.release()
