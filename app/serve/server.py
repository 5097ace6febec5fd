"""The viser server: one Session (its own simulation, controls and scene: ``app.serve.session``) per browser tab,
and what happens when a tab connects or closes.
"""

from __future__ import annotations

import threading
import traceback
import warnings
import weakref
from collections import deque

import viser

import physics

from .address import listening_port
from .capacity import MAX_TABS, full_note
from .classroom import ClassRoom
from .closing import COLLECTOR, ClosedTabs
from .guard import configure, refuse_share_tunnel
from .page_scripts import install as install_page_scripts
from .session import Session

__all__ = ["App", "Session", "warm_up"]


class App:
    """The server and its sessions."""

    def __init__(self, host: str = "127.0.0.1", port: int = 8080, scenario: physics.Scenario | None = None,
                 mesh=None, server: viser.ViserServer | None = None, class_mode: bool = False):
        """``server``: one already serving (``python -m app`` starts it before loading the physics, so a
        browser fetches the page meanwhile); tabs that connected before are served now. ``class_mode``: one run
        for every tab, driven by the lecturer's (``self.classroom``, app.serve.classroom)."""
        self.scenario = scenario
        self.mesh = mesh
        # a tab's last frame can race its disconnection; viser then warns that the message is dropped
        warnings.filterwarnings("ignore", message="Queued a .* on a closed connection")
        if server is None:
            port = listening_port(host, port, dashes="")  # AddressError here, where viser would wait for ever
            configure(host)  # before the server starts: same-origin browsers and this host's name only
            install_page_scripts()
        self.server = server or viser.ViserServer(host=host, port=port, label="Quasirigid")
        refuse_share_tunnel(self.server)
        # The control panel docked at the right edge from the start, not floating over the view: the 3-D view is
        # what remains beside it, and a study window docks below it later without moving it (moving it from
        # floating to docked would remount it and close every folder the user had opened, the Sweep folder
        # holding the button they just pressed among them).
        self.server.gui.main_panel.dock_right()
        self.sessions: dict[int, Session] = {}
        # Tabs whose Session is being built (viser's connect callback), and the last tabs that closed: viser runs
        # the disconnect callback on another thread as soon as a tab goes, and a tab closed while its Session was
        # built kept a session running for no one (2 of 60 bench-load clients). A connect callback queued behind
        # others may even start after its tab has gone: it builds nothing then.
        self._connecting: set[int] = set()
        self._gone = ClosedTabs()
        self._lock = threading.Lock()
        self.stats: dict = {}
        # (client id, frames its session published) of the last closed tabs: bench/load.py compares them
        # with what each client received; bounded, so a server up for days keeps no record per tab
        self.closed_frames: deque[tuple[int, int]] = deque(maxlen=1000)
        self.classroom = None
        if class_mode:
            self.classroom = ClassRoom(self.server, scenario, mesh, self.stats)
        self.server.on_client_connect(self._connect)
        self.server.on_client_disconnect(self._disconnect)

    def _connect(self, client: viser.ClientHandle) -> None:
        if self.classroom is not None:
            self.classroom.connect(client)
            return
        cid = client.client_id
        with self._lock:
            if cid in self._gone:
                self.stats["gone_before_built"] = self.stats.get("gone_before_built", 0) + 1
                return
            full = len(self.sessions) + len(self._connecting) >= MAX_TABS
            if not full:
                self._connecting.add(cid)
        if full:
            self.stats["full"] = self.stats.get("full", 0) + 1
            full_note(client, "the explorer")
            return
        session = None
        try:
            session = Session(self.server, client, self.scenario, self.stats, self.mesh)
        except Exception:
            traceback.print_exc()
        with self._lock:
            self._connecting.discard(cid)
            gone = cid in self._gone
            if session is not None and not gone:
                self.sessions[cid] = session
                self.stats["sessions"] = len(self.sessions)
        if session is not None:
            self.stats["opened"] = self.stats.get("opened", 0) + 1
            if gone:
                self._closed(client, session)

    def _disconnect(self, client: viser.ClientHandle) -> None:
        if self.classroom is not None:
            self.classroom.disconnect(client)
            return
        with self._lock:
            s = self.sessions.pop(client.client_id, None)
            self._gone.add(client.client_id)  # a Session being built for it is closed when it is
            self.stats["sessions"] = len(self.sessions)
        if s is not None:
            self._closed(client, s)

    def _closed(self, client: viser.ClientHandle, s: Session) -> None:
        """End a closed tab's session and free it."""
        s.close()
        self.stats["closed"] = self.stats.get("closed", 0) + 1
        self.closed_frames.append((client.client_id, s.published))
        # cyclic garbage, and viser holds the client handle until this callback returns: freed on another
        # thread once the session's loop has ended and viser has let go (app.serve.closing)
        COLLECTOR.add(s.thread, weakref.ref(s))

    @property
    def port(self) -> int:
        return self.server.get_port()

    def close(self) -> None:
        if self.classroom is not None:
            self.classroom.close()
        for s in list(self.sessions.values()):
            s.close()
        self.server.stop()


def warm_up() -> None:
    """Load (or compile) the integrator and the kernels once, so the first tab is quick."""
    run = physics.LiveRun(physics.default_scenario())
    run.advance(0.01)
