"""The Share folder of a tab, and the tab's memory of its last scene.

- "Share this scene" shows the scene as the engine has it now (slider changes included) as a share code
  (``app.share.code``) and as a link carrying it; "Load shared code" loads a pasted code or link, from t = 0.
- A tab opened with a link (``?scene=CODE``, copied into the browser's storage by ``app.share.link``) asks
  whether to load its scene, in a dialog: never silently.
- The browser keeps the tab's last scene under one key of its storage (viser 1.1 ``client.local_storage``),
  written at most once a second and only when the scene changed; a new tab, or a reload, restores it and
  says so in the status line. A stored value that does not decode is ignored, with a notice.

A code that cannot be read, or a scenario the live run refuses, leaves the scene as it is and says what was
wrong. Callbacks run on viser's threads and the storage is read on a thread of its own: the scene changes
only through ``Engine.request`` (its "scenario" action), applied on the session's loop.
"""

from __future__ import annotations

import re
import threading
import time

import physics

from ..engine import controls, presets
from ..engine.engine import Engine
from ..markup import plain
from .code import decode, encode, link
from .link import LINK_KEY, PAGE_KEY

SAVE_KEY = "quasirigid.last"  # the browser's last scene, as a share code
SAVE_INTERVAL = 1.0  # s: the storage is written at most this often (a slider dragged changes the scene per frame)
READ_TIMEOUT = 60.0  # s to wait for the browser's storage when the tab connects (a tab still building its 3-D
# scene in software WebGL on a busy machine answers after 10 s and more; a closed tab ends the wait at once)
NOTE_SECONDS = 30.0  # how long the status line says what happened to the tab's scene
SHARED = "shared scene"  # a loaded code's name, when it is no preset as shipped
RESTORED = "your last scene"  # a restored scene's name, when it is no preset as shipped


class SharePanel:
    """The Share folder (built into the panel being built) and the storage of the tab's last scene."""

    def __init__(self, gui, engine: Engine, client, restore: bool = True, read: bool = True):
        self.engine = engine
        self.client = client
        self.page_url: str | None = None  # the page's address, read from the browser's storage
        self.ready = threading.Event()  # set once the storage was read: the last scene may be written from then
        self._hold_seq = 0  # a restore requested as this change: nothing is written before it is applied
        self._saved: physics.Scenario | None = None
        self._saved_code: str | None = None
        self._saved_at = float("-inf")
        self._note, self._note_until = "", 0.0
        self._shown: physics.Scenario | None = None  # the scene whose code the Share folder shows
        self._shown_at = float("-inf")
        with gui.add_folder("Share", expand_by_default=False):
            self.share_btn = gui.add_button("Share this scene", hint="a short code, and a link carrying it, that "
                                            "reproduce this scene exactly (slider changes included), from t = 0")
            self.code = gui.add_text("share code", "", visible=False, multiline=True,  # the whole code in sight
                                     hint="select it all and copy it (Ctrl+A, Ctrl+C); paste it in another tab")
            self.link = gui.add_text("link", "", visible=False, hint="opened in a browser, this page offers the scene")
            self.shared_md = gui.add_markdown("")
            self.paste = gui.add_text("paste a code", "", hint="a share code (qr1:...) or a link carrying one")
            self.load_btn = gui.add_button("Load shared code", hint="replaces the scene with the code's, from t = 0")
            self.note_md = gui.add_markdown("")

        @self.share_btn.on_click
        def _(_event):
            self.share()

        @self.load_btn.on_click
        def _(_event):
            self.load_pasted(self.paste.value)

        self.restore = restore  # False when the server was started on a scene of its own: that scene is shown
        if read:  # (a test reads on its own thread)
            threading.Thread(target=self._read_storage, name="share-storage", daemon=True).start()
        else:
            self.ready.set()

    # ---- the Share folder ------------------------------------------------------------------------
    def share(self) -> str:
        """Show the code and the link of the scene as it is now; returns the code. Once shown, they follow the
        scene (``tick``): a preset chosen or a slider moved since gives a new code, as the words above it say."""
        self._shown, self._shown_at = self.engine.scenario, time.monotonic()
        code = encode(self._shown)
        self.code.value = code
        self.code.visible = True
        if self.page_url:
            self.link.value = link(self.page_url, code)
            where = "open the link"
        else:  # a page served without app.share.link's script: its address is not known here
            self.link.value = f"?scene={code}"
            where = "add the link's text to this page's address"
        self.link.visible = True
        self.shared_md.content = (f"Code of the scene as it is now ({len(code)} characters). In another tab, paste "
                                  f"it under *paste a code*, or {where}: the same scene starts there at t = 0.")
        return code

    def load_pasted(self, text: str) -> bool:
        """Load a pasted code or link; a code that cannot be read is said under the box, and the scene stays."""
        try:
            sc = checked(text)
        except Exception as exc:  # ScenarioError; anything else is said too, never a traceback
            self.note_md.content = _red(f"**Not loaded:** {plain(why(exc))}. The scene is unchanged.")
            return False
        name = scene_name(sc, SHARED)
        self.engine.request("scenario", (sc, name))
        self.note_md.content = f"Loaded **{plain(name)}** from the code; it starts at t = 0."
        self.say("loaded a shared scene")
        return True

    # ---- the status line ---------------------------------------------------------------------------
    def say(self, note: str) -> None:
        """A note the status line shows for NOTE_SECONDS."""
        self._note, self._note_until = note, time.monotonic() + NOTE_SECONDS

    def status(self) -> str:
        """The status line's note (" · restored your last scene"), or nothing once it is old."""
        return f" · {self._note}" if self._note and time.monotonic() < self._note_until else ""

    # ---- the browser's storage ---------------------------------------------------------------------
    def tick(self) -> None:
        """Called with every published frame: the code shown follows the scene, and the browser keeps the last
        scene, when the scene changed, at most once per SAVE_INTERVAL, and never before the stored one was read (it
        would be overwritten unread)."""
        eng = self.engine
        sc = eng.scenario
        now = time.monotonic()
        if self.code.visible and sc is not self._shown and now - self._shown_at >= SAVE_INTERVAL:
            self.share()  # the code shown is always the scene's as it is now (a drag: once a SAVE_INTERVAL)
        if not self.ready.is_set() or eng.applied_seq < self._hold_seq:
            return
        if sc is self._saved or now - self._saved_at < SAVE_INTERVAL:
            return
        self._saved, self._saved_at = sc, now
        code = encode(sc)
        if code != self._saved_code:  # a slider moved and back: nothing to write
            self._saved_code = code
            self.client.local_storage.set_item(SAVE_KEY, code)

    def _read_storage(self) -> None:
        """On connecting: the page's address, the link's scene and the last scene, from the browser's storage."""
        storage = getattr(self.client, "local_storage", None)
        if storage is None:  # a client without a browser behind it (a test's stand-in): nothing to read or keep
            return
        try:
            page = storage.get_item(PAGE_KEY, timeout=READ_TIMEOUT)
            linked = storage.get_item(LINK_KEY, timeout=READ_TIMEOUT)
            last = storage.get_item(SAVE_KEY, timeout=READ_TIMEOUT)
            if linked is not None:
                storage.remove_item(LINK_KEY)  # offered once; the address still carries it for a reload
        except TimeoutError:  # connected but silent for a minute: a link it carried would be lost unsaid
            self.say("this browser did not answer for its stored scenes; a link's scene was not read")
            self.ready.set()
            return
        except RuntimeError:  # storage blocked by the browser, or the tab closed: none of this
            self.ready.set()
            return
        try:
            if isinstance(page, str) and re.fullmatch(r"https?://[^\s?#]{1,2000}", page):
                self.page_url = page
            if last is not None and self.restore:
                self._restore(last)
            if linked is not None:
                self._offer(linked)
        finally:
            self.ready.set()

    def _restore(self, stored: str) -> None:
        try:
            sc = checked(stored)
        except Exception as exc:  # ScenarioError; anything else is said too, never a traceback
            self.say("your stored last scene could not be read; ignored")
            self.client.add_notification("Your last scene was not restored", f"The scene this browser kept cannot "
                                         f"be read ({why(exc)}); the page opened on its usual scene.", color="yellow",
                                         auto_close_seconds=20.0)
            return
        self._hold_seq = self.engine.request("scenario", (sc, scene_name(sc, RESTORED)))
        self.say("restored your last scene")

    def _offer(self, code: str) -> None:
        """A dialog asking whether to load the scene the page's link carries."""
        gui = self.client.gui
        try:
            sc = checked(code)
        except Exception as exc:  # ScenarioError; anything else is said too, never a traceback
            with gui.add_modal("The link's scene cannot be opened") as modal:
                gui.add_markdown(f"This page was opened with a link carrying a scene that cannot be read: "
                                 f"{plain(why(exc))}. The scene stays as it is.")
                gui.add_button("Close").on_click(lambda _e: modal.close())
            return
        name = scene_name(sc, SHARED)
        with gui.add_modal("Open the shared scene?") as modal:
            gui.add_markdown(f"This page was opened with a link that carries a scene: **{plain(name)}** "
                             f"({plain(system_label(sc.system))}, fidelity {plain(sc.run.fidelity)}). Load it? It "
                             "starts at t = 0 and replaces the scene shown now.")
            load = gui.add_button("Load the shared scene")
            keep = gui.add_button("Keep the current scene", color="gray")

        @load.on_click
        def _(_event):
            modal.close()
            self.engine.request("scenario", (sc, name))
            self.say("loaded the linked scene")

        @keep.on_click
        def _(_event):
            modal.close()


def why(exc: Exception) -> str:
    """A refusal in words: a ScenarioError's own message; any other error by its type too."""
    return str(exc) if isinstance(exc, physics.ScenarioError) else f"{type(exc).__name__}: {str(exc)[:160]}"


def checked(text: object) -> physics.Scenario:
    """The scenario of a code, once the live run accepts it too (a code can hold a valid scenario whose parts do
    not fit the body): ShareCodeError or ScenarioError otherwise."""
    sc = decode(text)
    physics.LiveRun(sc)
    return sc


_preset_scenes: list[tuple[str, physics.Scenario]] | None = None
_preset_lock = threading.Lock()


def scene_name(sc: physics.Scenario, fallback: str) -> str:
    """The preset a scenario is, exactly as shipped (the dropdown then names it), else ``fallback``."""
    global _preset_scenes
    with _preset_lock:
        if _preset_scenes is None:
            _preset_scenes = [(n, presets.load_preset(n)) for n in presets.preset_names()]
    return next((n for n, p in _preset_scenes if p == sc), fallback)


def system_label(system: str) -> str:
    """The System dropdown's name of a system (its registered name -> its label)."""
    return next((label for label, name in controls.SYSTEM_LABELS.items() if name == system), system)


def _red(markdown: str) -> str:
    return f"<span style='color:#c00'>{markdown}</span>"


__all__ = ["SAVE_KEY", "SharePanel", "checked", "scene_name"]
