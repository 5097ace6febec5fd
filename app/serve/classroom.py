"""Class mode (``python -m app --class``): one run, driven by the lecturer's tab, followed live by every student's.

The class has one engine and one loop thread (``ClassRoom._loop``): the run is integrated once per frame, however
many tabs follow it. The class's 3-D scene is drawn once a frame in viser's scene that every tab shares, and then
each tab's view (app.serve.class_view) shows the frame's numbers in its own panel, inside its ``client.atomic()``.
A following tab costs its share of this fan-out: viser's sending of the shared scene's messages and, at the plots'
rate, its panel's.

Who drives: the lecturer's link carries a key (``secrets.token_urlsafe``); the page's script puts the link's
``class`` parameter in the browser's storage (app.share.link), the server reads it when the tab connects and
compares it with the key (``hmac.compare_digest``). A tab with the key gets the explorer's whole panel over the class
engine; any other tab is a student's: a scene and a panel with no control of the class run (its only button,
"Explore from here", acts on the tab itself), so no message its client sends can reach the class engine (the
panel's callbacks are the only way in, and a student's tab has none bound to it).

"Explore from here" gives the student a normal ``Session`` whose engine is a copy of the class engine at that
frame (app.engine.branch); its "Follow the class" ends that session and follows again. Tabs that open before
the lecturer's see a note until the lecturer's tab opens the class.

Threads: viser's callbacks (connect, disconnect, buttons) only queue; the loop builds and drops views between
frames, so the class engine is read by one thread only.
"""

from __future__ import annotations

import hmac
import secrets
import threading
import time
import traceback
import weakref
from collections import deque

import viser

import physics

from ..engine.branch import branch
from ..engine.clock import PLOT_HZ
from ..engine.engine import Engine
from ..engine.frame import non_finite
from ..panel.challenge_panel import ClassChallenge
from ..share.link import CLASS_KEY
from .capacity import MAX_TABS, full_note
from .class_view import ClassDrawing, EngineView, FollowerView, LecturerView, Shared, show_class_scene, waiting_note
from .closing import COLLECTOR, ClosedTabs
from .pace import Pace
from .scoreboard import Scoreboard
from .session import CROWD_PLOT_HZ, Session

KEY_BYTES = 16  # of randomness in the lecturer's key (secrets.token_urlsafe: 22 characters)
ROLE_TIMEOUT = 5.0  # s to wait for a tab's storage to say whether it carries the key; then it is a student's
MAX_KEY_CHARS = 200  # of a class parameter compared with the key (the page's script cuts it there too)
JOINS_PER_FRAME = 1  # views built between two frames: a crowd joining at once slows the class's frames a little
PLOT_FRAMES = 4  # at most one frame in this many carries the plots: a slow machine's frames stay light
# a crowd of following tabs gets the plots this often: each tab's copy of the plots' arrays is encoded and sent
# on its own, and in a class of 30 that, not the shared scene, was most of the server's work (bench class)
FOLLOWER_PLOT_HZ = 2.0
FOLLOW = "Follow the class"


class ClassRoom:
    """The class run, its lecturer's and students' views, and the students' own runs."""

    def __init__(self, server: viser.ViserServer, scenario: physics.Scenario | None = None, mesh=None,
                 stats: dict | None = None, key: str | None = None):
        self.server = server
        self.scenario, self.mesh = scenario, mesh
        self.stats = stats if stats is not None else {}
        self.key = key or secrets.token_urlsafe(KEY_BYTES)
        self.engine: Engine | None = None  # made when the lecturer first opens the class (or ``open``)
        self.shared: Shared | None = None
        self.drawing: ClassDrawing | None = None  # the class's scene, in viser's scene every tab shares
        self.views: dict[int, object] = {}  # client id -> its view; the loop's alone
        self.explorers: dict[int, Session] = {}  # client id -> the student's own run
        self.waiting: dict[int, tuple] = {}  # client id -> (client, the note), before the class opens
        self._lock = threading.Lock()
        self._joins: deque = deque()  # (client, role) to give a view, in the loop
        self._gone = ClosedTabs()  # so a tab closing while it joins gets no view
        self._explores: deque = deque()  # clients whose student asked for a run of their own
        self._admitting = 0  # tabs whose role is being read (connect's threads)
        self.ticks = 0  # class engine ticks: one per frame, however many tabs follow
        self.frames = 0
        self.first_frame_after: dict[int, float] = {}  # lecturer's change seq -> s until every view had its frame
        self.pace = Pace()
        self._next_follower_plot = 0.0
        self.scoreboard = Scoreboard()  # the braking challenge: the lecturer's start, the students' scores
        self.stop = threading.Event()
        self.thread: threading.Thread | None = None

    # ---- links and roles ---------------------------------------------------------------------------
    def links(self, url: str) -> tuple[str, str]:
        """(lecturer's link, students' link) of the class served at ``url`` (``http://host:port``)."""
        return f"{url}/?class={self.key}", f"{url}/"

    def is_lecturer(self, value) -> bool:
        """Whether ``value`` (a tab's class parameter) is the key; compared in constant time."""
        if not isinstance(value, str) or not value or len(value) > MAX_KEY_CHARS:
            return False
        return hmac.compare_digest(value.encode(), self.key.encode())

    def _role(self, client: viser.ClientHandle) -> str:
        storage = getattr(client, "local_storage", None)
        if storage is None:
            return "student"
        try:
            value = storage.get_item(CLASS_KEY, timeout=ROLE_TIMEOUT)
            if value is not None:
                storage.remove_item(CLASS_KEY)  # read once: a later tab of this browser without it is a student's
        except (RuntimeError, TimeoutError):  # no answer (a raw client, storage blocked): a student
            return "student"
        return "lecturer" if self.is_lecturer(value) else "student"

    # ---- tabs connecting and leaving (viser's threads) ---------------------------------------------------
    def connect(self, client: viser.ClientHandle) -> None:
        # each tab's role is read on a thread of its own (up to ROLE_TIMEOUT): at most MAX_TABS at once
        with self._lock:
            full = self._admitting >= MAX_TABS
            self._admitting += not full
        if full:
            self._full(client)
            return
        threading.Thread(target=self._admit, args=(client,), name=f"class-admit-{client.client_id}",
                         daemon=True).start()

    def _tabs(self) -> int:
        """The students' tabs the class serves: following, waiting, joining or on a run of their own."""
        return len(self.views) + len(self.waiting) + len(self._joins) + len(self.explorers)

    def _full(self, client: viser.ClientHandle) -> None:
        self.stats["full"] = self.stats.get("full", 0) + 1
        full_note(client, "the class")

    def _admit(self, client: viser.ClientHandle) -> None:
        try:
            try:
                role = self._role(client)
            finally:
                with self._lock:
                    self._admitting -= 1
            if role == "lecturer":
                self.open()
            with self._lock:
                if client.client_id in self._gone:
                    return
                if role == "student" and self._tabs() >= MAX_TABS:  # the lecturer's tab is always let in
                    self._full(client)
                    return
                if self.engine is None:  # a student before the lecturer: a note until the class opens
                    self.waiting[client.client_id] = (client, waiting_note(client))
                    return
                self._joins.append((client, role))
        except Exception:
            traceback.print_exc()

    def disconnect(self, client: viser.ClientHandle) -> None:
        cid = client.client_id
        with self._lock:
            self._gone.add(cid)
            self.waiting.pop(cid, None)
            session = self.explorers.pop(cid, None)
        if session is not None:
            self._end_session(session)
        self._count()

    def open(self, scenario: physics.Scenario | None = None) -> Engine:
        """Start the class run (the lecturer's first tab does; a benchmark may without one): the engine and the
        loop; the students waiting follow it from its first frames."""
        with self._lock:
            if self.engine is None:
                self.engine = Engine(scenario or self.scenario, mesh=self.mesh)
                self.shared = Shared(self.engine)
                for client, note in self.waiting.values():
                    try:
                        note.remove()
                    except Exception:
                        pass
                    self._joins.append((client, "student"))
                self.waiting.clear()
                self.thread = threading.Thread(target=self._loop, name="class-run", daemon=True)
                self.thread.start()
        self._count()
        return self.engine

    # ---- a student's own run and back -----------------------------------------------------------------------
    def explore(self, client: viser.ClientHandle) -> None:
        """"Explore from here" (a button's thread): the loop copies the class engine at its next frame."""
        with self._lock:
            self._explores.append(client)

    def _start_exploring(self, client: viser.ClientHandle, engine: Engine) -> None:
        """A Session on the copied engine, in the tab the follower view left (off the loop thread)."""
        try:
            _clear(client)
            show_class_scene(client, False)
            board = self.scoreboard
            session = Session(self.server, client, None, self.stats, engine=engine,
                              klass=ClassChallenge(choice=board.choice, post=board.post))
            back = session.follow_button = client.gui.add_button(
                FOLLOW, hint="leave your own run and follow the class run again",
                order=session.panel.playbar.buttons.order - 1.0)  # first in the panel: the way back
            back.on_click(lambda _event: self.follow(client))
            with self._lock:
                if client.client_id in self._gone:
                    self._end_session(session)
                    return
                self.explorers[client.client_id] = session
            self._count()
        except Exception:
            traceback.print_exc()

    def follow(self, client: viser.ClientHandle) -> None:
        """"Follow the class" (a button's thread): the student's run ends and the tab follows again."""
        with self._lock:
            session = self.explorers.pop(client.client_id, None)
        if session is None:
            return
        self._end_session(session)
        _clear(client)
        show_class_scene(client, True)
        with self._lock:
            if client.client_id not in self._gone:
                self._joins.append((client, "student"))
        self._count()

    def _end_session(self, session: Session) -> None:
        session.close()
        if session.thread is not threading.current_thread():
            session.thread.join(timeout=5.0)
        COLLECTOR.add(session.thread, weakref.ref(session))  # cyclic garbage: app.serve.closing

    def _count(self) -> None:
        """Loops running (the class's and each student's own run): what each loop's Pace divides the server by."""
        self.stats["sessions"] = (self.engine is not None) + len(self.explorers)

    # ---- the loop (one thread: the class engine's owner) ---------------------------------------------------
    def _between_frames(self) -> None:
        with self._lock:
            joins = [self._joins.popleft() for _ in range(min(JOINS_PER_FRAME, len(self._joins)))]
            explores = list(self._explores)
            self._explores.clear()
            gone = [cid for cid in self.views if cid in self._gone]
            joins = [(c, role) for c, role in joins if c.client_id not in self._gone]
        for cid in gone:
            self.views.pop(cid, None)
        for client, role in joins:
            if role == "lecturer":
                board = self.scoreboard
                self.views[client.client_id] = LecturerView(
                    client, self.engine, self.shared, self.drawing,
                    ClassChallenge(choice=board.choice, chose=board.choose, board=board.markdown))
            else:
                self.views[client.client_id] = FollowerView(client, self.engine, self.shared, self.drawing,
                                                            lambda c=client: self.explore(c))
        for client in explores:
            if client.client_id not in self.views:
                continue  # gone, or asked twice
            try:
                engine = branch(self.engine)  # the class run's present, copied on the thread that owns it
            except Exception as exc:  # the tab follows on, and says why it could not branch
                self.engine_note(client, f"Explore from here failed: {type(exc).__name__}: {exc}")
                continue
            del self.views[client.client_id]
            threading.Thread(target=self._start_exploring, args=(client, engine),
                             name=f"class-explore-{client.client_id}", daemon=True).start()

    @staticmethod
    def engine_note(client: viser.ClientHandle, message: str) -> None:
        client.add_notification("Class mode", message, color="red", auto_close_seconds=20.0)

    def _loop(self) -> None:
        eng, shared = self.engine, self.shared
        self.drawing = ClassDrawing(self.server, EngineView(eng, shared))
        last = deadline = time.perf_counter()
        next_plot = 0.0
        since_plot = PLOT_FRAMES
        last_good = None
        while not self.stop.is_set():
            now = time.perf_counter()
            dt, last = now - last, now
            cpu = time.thread_time()
            try:
                self._between_frames()
                fr = eng.tick(dt)
                self.ticks += 1
                if non_finite(fr) is not None:
                    eng.error = f"the frame at t = {fr.t:.6g} s is not finite; the last finite drawing is kept"
                    fr = last_good
                else:
                    last_good = fr
                shared.take_flags()
                crowded = self.pace.crowded(len(self.views))
                since_plot += 1
                plots_now = now >= next_plot and since_plot >= PLOT_FRAMES
                if plots_now:
                    since_plot = 0
                    next_plot = now + 1.0 / (CROWD_PLOT_HZ if crowded else PLOT_HZ)
                if fr is not None:
                    self._publish(fr, plots_now)
                self.frames += 1
                self.pace.spent(time.thread_time() - cpu)
                done = time.perf_counter()
                for seq, t0 in list(eng.change_times.items()):
                    if fr is not None and seq <= fr.applied and seq not in self.first_frame_after:
                        self.first_frame_after[seq] = done - t0
                        del eng.change_times[seq]
            except Exception:  # never let one bad frame end the class
                if self.stop.is_set():
                    break
                eng.error = "internal error: " + traceback.format_exc(limit=1).strip().splitlines()[-1]
                traceback.print_exc()
                time.sleep(0.2)
            deadline += 1.0 / self.pace.hz(self.stats.get("sessions", 1))
            sleep = deadline - time.perf_counter()
            if sleep > 0:
                self.stop.wait(sleep)
            else:
                deadline = time.perf_counter()

    def _publish(self, fr, plots_now: bool) -> None:
        self.drawing.engine.raise_flags()
        with self.server.atomic():  # the class's scene, once for every tab
            self.drawing.update(fr, plots_now)
        views = list(self.views.items())
        lecturer_here = any(v.role == "lecturer" for _, v in views)
        now = time.perf_counter()
        followers_plot = plots_now and (not self.pace.crowded(len(views)) or now >= self._next_follower_plot)
        if followers_plot:
            self._next_follower_plot = now + 1.0 / FOLLOWER_PLOT_HZ
        for cid, view in views:
            try:  # a follower that skips a plots frame keeps its flags raised and draws them at its next one
                view.publish(fr, followers_plot if view.role == "student" else plots_now, lecturer_here)
            except Exception:  # one tab's failure (closed as it was drawn) is never the class's
                if cid not in self._gone:
                    traceback.print_exc()
                self.views.pop(cid, None)

    def close(self) -> None:
        self.stop.set()
        if self.thread is not None and self.thread is not threading.current_thread():
            self.thread.join(timeout=5.0)  # no frame is queued on the tabs once the server stops
        for session in list(self.explorers.values()):
            session.close()
        if self.engine is not None:
            self.engine.cancel_workers()


def _clear(client: viser.ClientHandle) -> None:
    """Everything a view or a session put in the tab: its panel and its scene."""
    client.gui.reset()
    client.scene.reset()


__all__ = ["FOLLOW", "ClassRoom"]
